//! Issue #20 §3, the carer lock on the screen: an exhaustive sweep of the
//! hit test over every pixel of every page, on both panels, STOP and RESUME,
//! for every lock profile (carer mode; each item hidden alone; all hidden):
//! a hidden button's place never yields its action (nor any other: it does
//! nothing), it is drawn blank, and every other pixel means exactly what it
//! means in carer mode, so the guard bands, STOP's band and the map are
//! untouched. The carer's gesture places are the same on every page and
//! overlap nothing else.

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::RgbColor;
use hal_sim::display::Framebuffer;
use touch_arm::config::access::item;
use touch_arm::config::settings::SpeedPreset;
use touch_arm::ui::layout::{Layout, SLOTS};
use touch_arm::ui::screen::page_button;
use touch_arm::ui::{hides, theme, Hit, Page, Ui, UiConfig, UiModel, UiState};

const CONFIG: UiConfig = UiConfig { reach_min: 0.2, reach_max: 1.0 };
const PAGES: [Page; 3] = [Page::Main, Page::More, Page::Setup];
/// Carer mode, each item hidden alone, and everything hidden.
const PROFILES: [u8; 7] = [0, item::CAL, item::LINE, item::LIFT, item::FAST, item::TOUCH, item::ALL];

/// A UI on `lay` showing `page` under the hidden items `hide`, drawn.
fn shown(lay: Layout, page: Page, hide: u8, stopped: bool) -> (Ui, Framebuffer) {
    let mut ui = Ui::with_layout(&CONFIG, lay);
    let mut m = UiModel::new(SpeedPreset::Normal);
    m.state = if stopped { UiState::Stopped } else { UiState::Idle };
    m.page = page;
    m.hide = hide;
    let mut fb = Framebuffer::new(lay.width().into(), lay.height().into(), Rgb565::BLACK);
    ui.draw(&m, &mut fb).unwrap();
    (ui, fb)
}

/// Which buttons each item hides (the table is `ui::hides`; this is the
/// issue's list, written out independently).
fn hidden_by(hide: u8) -> Vec<Hit> {
    let mut v = Vec::new();
    if hide & (item::CAL | item::TOUCH) != 0 {
        v.push(Hit::Calibrate);
    }
    if hide & item::LINE != 0 {
        v.push(Hit::Line);
    }
    if hide & item::LIFT != 0 {
        v.push(Hit::Lift);
    }
    if hide & item::FAST != 0 {
        v.push(Hit::Speed(SpeedPreset::Fast));
    }
    v
}

#[test]
fn hidden_regions_do_nothing_and_everything_else_is_unchanged_on_every_pixel() {
    let mut swept = 0u64;
    let mut blank = 0u64;
    for lay in [Layout::QVGA, Layout::HVGA] {
        for page in PAGES {
            for stopped in [false, true] {
                let (carer, _) = shown(lay, page, 0, stopped);
                for hide in PROFILES {
                    let gone = hidden_by(hide);
                    for h in [Hit::Calibrate, Hit::Line, Hit::Lift, Hit::Speed(SpeedPreset::Fast)] {
                        assert_eq!(hides(hide, &h), gone.contains(&h), "ui::hides({hide:#07b}, {h:?})");
                    }
                    let (ui, fb) = shown(lay, page, hide, stopped);
                    // The slots whose button is hidden on this page.
                    let hidden_slots: Vec<_> =
                        (0..SLOTS - 1).filter(|&i| gone.contains(&page_button(page, i))).map(|i| lay.slot(i)).collect();
                    for y in 0..lay.height() as i16 {
                        for x in 0..lay.width() as i16 {
                            let hit = ui.hit(x, y);
                            let ctx = format!(
                                "{}x{} {page:?} hide {hide:#07b} stopped {stopped} ({x},{y})",
                                lay.width(),
                                lay.height()
                            );
                            if let Some(h) = hit {
                                assert!(!gone.contains(&h), "{ctx}: a hidden button hit: {h:?}");
                            }
                            if hidden_slots.iter().any(|a| a.contains(x, y)) {
                                assert_eq!(hit, None, "{ctx}: a hidden place acts");
                                assert_eq!(
                                    fb.pixel(x.into(), y.into()),
                                    Some(theme::BG),
                                    "{ctx}: a hidden button drawn"
                                );
                                blank += 1;
                            } else {
                                assert_eq!(hit, carer.hit(x, y), "{ctx}: differs from carer mode");
                            }
                            swept += 1;
                        }
                    }
                }
            }
        }
    }
    eprintln!("{swept} pixels swept, {blank} of them on hidden buttons");
    // (320·240 + 480·320) · 3 pages · 2 STOP states · 7 profiles.
    assert_eq!(swept, (320 * 240 + 480 * 320) * 3 * 2 * 7);
    assert!(blank > 0);
}

#[test]
fn the_carer_gesture_places_are_the_same_on_every_page_and_panel_and_touch_no_button() {
    for lay in [Layout::QVGA, Layout::HVGA] {
        for page in PAGES {
            let (ui, _) = shown(lay, page, 0, false);
            for i in 0..2 {
                let a = lay.carer_corner(i);
                assert!(
                    a.w >= lay.button_h() && a.h == 2 * lay.headline().h,
                    "{a:?}: a button wide, two status lines tall"
                );
                for y in a.y..a.bottom() {
                    for x in a.x..a.right() {
                        assert_eq!(ui.hit(x, y), Some(Hit::Carer(i)), "{page:?} ({x},{y})");
                    }
                }
            }
            assert!(lay.carer_corner(0).right() < lay.carer_corner(1).x, "the two places apart");
            // Below the guard band, and two status lines (a button's
            // height on neither panel) above the buttons.
            for i in 0..2 {
                let a = lay.carer_corner(i);
                assert!(a.y >= lay.headline().y && a.bottom() <= lay.detail().bottom());
                assert!(lay.slot(0).y - a.bottom() >= 24, "{a:?}");
            }
        }
    }
}
