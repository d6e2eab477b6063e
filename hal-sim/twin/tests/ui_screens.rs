//! The touch-screen UI (`touch_arm::ui`) rendered into the host framebuffer
//! (`hal_sim::display`): every screen state is written as a PNG to
//! `target/ui-snapshots/`, and the pictures are checked for real properties:
//! the colours of the four triangles against `workspace::condition` and the
//! reach circles, markers on the pixels the mapping predicts, text compared
//! with text drawn on its own, STOP red and large, partial redraws that
//! write only inside the regions that changed and leave the same picture as
//! a full redraw, hit-testing, and the calibration flow recovering known
//! panel calibrations (swap and inversions included).

use std::path::PathBuf;

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use hal_sim::display::{Counting, Framebuffer};
use hal_sim::rng::Rng;
use touch_arm::config::settings::{PressSettings, SpeedPreset};
use touch_arm::geometry::workspace::{condition, Condition};
use touch_arm::touch::map::{Calibration, CalibrationError};
use touch_arm::ui::calibration::{
    cal_pixel, cal_point, cancel_area, cross_r, save_area, setting_area, Setting, CAL_COUNT,
};
use touch_arm::ui::draw::{text, Area, TextStyle};
use touch_arm::ui::font::{glyph_row, CELL_H, CELL_W, DEGREE};
use touch_arm::ui::layout::{Layout, GUARD, SLOTS};
use touch_arm::ui::scan::ScanShow;
use touch_arm::ui::ws_view::{base_area, marker_r};
use touch_arm::ui::{
    theme, warn, CalFailure, CalPhase, CalibrationEvent, CalibrationFlow, Hit, Page, Preview, Redrawn, Refusal, Ui,
    UiConfig, UiModel, UiState,
};

fn snapshot(fb: &Framebuffer, name: &str) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/ui-snapshots");
    fb.save_png(dir.join(format!("{name}.png"))).unwrap();
}

/// The 320×240 screen: the layout every test below checks pixel by pixel.
const L: Layout = Layout::QVGA;
const WS: Area = L.ws();
/// Pixels per workspace unit on the 320×240 map.
const S: i16 = L.scale() as i16;
const BASE_AREA: Area = base_area(&L);
const MARKER_R: u16 = marker_r(&L);
const CROSS_R: u16 = cross_r(&L);
const SAVE_AREA: Area = save_area(&L);
const CAL_PIXELS: [(i16, i16); CAL_COUNT] = {
    let mut p = [(0, 0); CAL_COUNT];
    let mut i = 0;
    while i < CAL_COUNT {
        p[i] = match cal_pixel(&L, i) {
            Some(xy) => xy,
            None => panic!(),
        };
        i += 1;
    }
    p
};

fn pixel_center_to_panel(x: i16, y: i16) -> (f32, f32) {
    L.pixel_center_to_panel(x, y)
}

fn ws_pixel_to_point(x: i16, y: i16) -> Option<(f32, f32)> {
    L.ws_pixel_to_point(x, y)
}

fn ws_point_to_pixel(x: f32, y: f32) -> Option<(i16, i16)> {
    L.ws_point_to_pixel(x, y)
}

const REACH_MIN: f32 = 0.3;
const REACH_MAX: f32 = 0.9;
const CONFIG: UiConfig = UiConfig { reach_min: REACH_MIN, reach_max: REACH_MAX };

fn rect(a: Area) -> Rectangle {
    a.to_rect()
}

fn moving_model() -> UiModel {
    let (x, y) = (0.4f32, 0.5f32);
    UiModel {
        state: UiState::Moving { progress: 0.63 },
        preview: None,
        resume: None,
        touch: Some((x, y)),
        target: Some((x, y)),
        condition: Some(condition(x, y).unwrap()),
        alpha: y.atan2(x),
        joints: [0.896, 0.7, 1.4],
        speed: SpeedPreset::Normal,
        warnings: 0,
        page: Page::Main,
        grip_closed: false,
        path_line: false,
        lift: false,
        scan: None,
        hide: 0,
        confirm: 0,
    }
}

fn full(model: &UiModel) -> Framebuffer {
    let mut fb = Framebuffer::landscape();
    Ui::new(&CONFIG).draw_full(model, &mut fb).unwrap();
    fb
}

/// Sub-image of `fb` inside `a`, row-major.
fn crop(fb: &Framebuffer, a: Area) -> Vec<Rgb565> {
    rect(a).points().map(|p| fb.pixel(p.x, p.y).unwrap()).collect()
}

/// `s` drawn on its own at `(x, y)` in `style`, cropped to its cells.
fn text_alone(s: &[u8], x: i16, y: i16, style: &TextStyle) -> (Vec<Rgb565>, Area) {
    // Black, as `Framebuffer::landscape`, and large enough for 480×320.
    let mut fb = Framebuffer::new(480, 320, Rgb565::BLACK);
    text(&mut fb, x, y, s, style).unwrap();
    let (w, h) = style.extent(s.len());
    let a = Area::new(x, y, w, h);
    (crop(&fb, a), a)
}

// ---- font -------------------------------------------------------------------

fn ink_bits(ch: u8) -> u32 {
    (0..8).map(|r| glyph_row(ch, r).count_ones()).sum()
}

#[test]
fn font_glyphs_are_distinct_and_scale_to_the_expected_pixel_counts() {
    // Hand-counted: 'T' = 5 + 6, 'L' = 6 + 5, 'H' = 6·2 + 5, 'I' = 3 + 5 + 3.
    assert_eq!(ink_bits(b'T'), 11);
    assert_eq!(ink_bits(b'L'), 11);
    assert_eq!(ink_bits(b'H'), 17);
    assert_eq!(ink_bits(b'I'), 11);
    assert_eq!(ink_bits(b' '), 0);
    // Only the descender glyphs and '_' use the row below the baseline.
    for ch in 32u8..=127 {
        let below = glyph_row(ch, 7) != 0;
        assert_eq!(below, b",_gjpqy".contains(&ch), "row 7 of {:?}", ch as char);
        if ch != b' ' {
            assert!(ink_bits(ch) > 0, "{:?} has no ink", ch as char);
        }
        for r in 0..8 {
            assert_eq!(glyph_row(ch, r) & !0x1f, 0, "glyph rows are 5 bits wide");
        }
    }
    // Every glyph differs from every other.
    for a in 32u8..=127 {
        for b in (a + 1)..=127 {
            let same = (0..8).all(|r| glyph_row(a, r) == glyph_row(b, r));
            assert!(!same, "{:?} and {:?} look the same", a as char, b as char);
        }
    }
    // Bytes outside the table draw as '?'.
    for r in 0..8 {
        assert_eq!(glyph_row(0x80, r), glyph_row(b'?', r));
        assert_eq!(glyph_row(10, r), glyph_row(b'?', r));
    }
    // Scaled ink: every set bit becomes an s×s block; opaque text writes each
    // cell pixel exactly once, transparent text only the ink.
    for s in 1u8..=3 {
        let word: &[u8] = b"Hi 42\x7f";
        let expected_ink: u32 = word.iter().map(|&c| ink_bits(c)).sum::<u32>() * u32::from(s) * u32::from(s);
        let fg = Rgb565::new(31, 0, 0);
        let bg = Rgb565::new(0, 0, 31);
        let mut fb = Framebuffer::new(320, 240, Rgb565::BLACK);
        let mut c = Counting::new(&mut fb);
        let end = text(&mut c, 3, 5, word, &TextStyle::opaque(s, fg, bg)).unwrap();
        let cell = (CELL_W * u16::from(s), CELL_H * u16::from(s));
        assert_eq!(end, 3 + (cell.0 * word.len() as u16) as i16);
        let cells = u64::from(cell.0) * u64::from(cell.1) * word.len() as u64;
        assert_eq!(c.total_writes(), cells);
        assert_eq!(c.touched() as u64, cells);
        assert_eq!(c.fill_contiguous_calls, word.len(), "one window per glyph");
        let area =
            Rectangle::new(Point::new(3, 5), Size::new(u32::from(cell.0) * word.len() as u32, u32::from(cell.1)));
        assert_eq!(fb.count_in(&area, fg) as u32, expected_ink);
        assert_eq!(fb.count_in(&area, bg) as u64, cells - u64::from(expected_ink));

        let mut fb = Framebuffer::new(320, 240, Rgb565::BLACK);
        let mut c = Counting::new(&mut fb);
        text(&mut c, 3, 5, word, &TextStyle::ink(s, fg)).unwrap();
        assert_eq!(c.total_writes(), u64::from(expected_ink));
        assert_eq!(fb.count_in(&area, fg) as u32, expected_ink);
    }
    // The pixel at row r, column c of a scaled glyph is the font bit.
    let mut fb = Framebuffer::new(40, 40, Rgb565::BLACK);
    text(&mut fb, 0, 0, &[DEGREE][..], &TextStyle::ink(2, Rgb565::WHITE)).unwrap();
    for r in 0..8 {
        for col in 0..5 {
            let bit = glyph_row(DEGREE, r as u8) >> (4 - col) & 1 == 1;
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let px = fb.pixel(col * 2 + dx, r * 2 + dy).unwrap();
                assert_eq!(px == Rgb565::WHITE, bit, "degree sign r{r} c{col}");
            }
        }
    }
}

// ---- layout and mappings ----------------------------------------------------------

/// Every pixel's panel point maps back to it, every map pixel's workspace
/// point is its exact half-unit centre and maps back to it, and the regions
/// tile the screen exactly (each pixel belongs to one region or gap).
fn check_mappings_and_tiling(lay: &Layout) {
    let (w, h) = (lay.width() as i16, lay.height() as i16);
    for y in 0..h {
        for x in 0..w {
            let (x_p, y_p) = lay.pixel_center_to_panel(x, y);
            assert_eq!(lay.panel_to_pixel(x_p, y_p), Some((x, y)));
        }
    }
    let ws = lay.ws();
    let two_s = f32::from(2 * lay.scale());
    for y in ws.y..ws.bottom() {
        for x in ws.x..ws.right() {
            let (x_p, y_p) = lay.ws_pixel_to_point(x, y).unwrap();
            assert_eq!(x_p, (2.0 * f32::from(x) + 1.0 - two_s) / two_s);
            assert_eq!(y_p, (two_s - 1.0 - 2.0 * f32::from(y)) / two_s);
            assert_eq!(lay.ws_point_to_pixel(x_p, y_p), Some((x, y)));
        }
    }
    assert_eq!(lay.ws_pixel_to_point(ws.right(), 10), None);
    assert_eq!(lay.ws_pixel_to_point(10, ws.bottom()), None);
    // Corners and edges of both coordinate systems.
    assert_eq!(lay.panel_to_pixel(-1.0, 1.0), Some((0, 0)));
    assert_eq!(lay.panel_to_pixel(1.0, 0.0), Some((w - 1, h - 1)));
    assert_eq!(lay.panel_to_pixel(0.0, 0.5), Some((w / 2, h / 2)));
    let s = lay.scale() as i16;
    assert_eq!(lay.ws_point_to_pixel(-1.0, 0.0), Some((0, s - 1)));
    assert_eq!(lay.ws_point_to_pixel(1.0, 1.0), Some((2 * s - 1, 0)));
    assert_eq!(lay.ws_point_to_pixel(0.0, 0.0), Some((s, s - 1)));
    assert_eq!(lay.ws_point_to_pixel(-1e-6, 0.0), Some((s - 1, s - 1)));
    for bad in [f32::NAN, f32::INFINITY, 1.01, -1.01] {
        assert_eq!(lay.panel_to_pixel(bad, 0.5), None);
        assert_eq!(lay.ws_point_to_pixel(bad, 0.5), None);
    }
    assert_eq!(lay.ws_point_to_pixel(0.0, -0.01), None);
    assert_eq!(lay.ws_point_to_pixel(0.0, 1.01), None);
    // The map keeps one scale on both axes.
    assert_eq!((ws.w, ws.h), (2 * lay.scale(), lay.scale()));
    // The regions, buttons and gaps tile the screen (the same on every
    // page: only what the buttons do changes): every pixel is painted by
    // exactly one of them in a full redraw.
    let mut owner = vec![0u8; usize::from(lay.width()) * usize::from(lay.height())];
    let mut regions = vec![ws, lay.stop(), lay.headline(), lay.detail(), lay.info(), lay.warn(), lay.joints()];
    regions.extend((0..SLOTS).map(|i| lay.slot(i)));
    regions.extend(lay.gaps());
    for a in regions {
        for p in rect(a).points() {
            owner[p.y as usize * usize::from(lay.width()) + p.x as usize] += 1;
        }
    }
    assert!(owner.iter().all(|&n| n == 1), "regions must tile the screen exactly");
    // The guard bands right of and below the map.
    assert_eq!((lay.gaps()[0].w, lay.gaps()[1].h), (GUARD, GUARD));
    // The buttons: at least 15 px apart (the gap of 320×240), none beside
    // the map or STOP, all below the status lines.
    let buttons: Vec<Area> = (0..SLOTS).map(|i| lay.slot(i)).collect();
    for (i, a) in buttons.iter().enumerate() {
        assert!(a.y >= lay.joints().bottom(), "{a:?} is below the status lines, away from the map and STOP");
        for b in &buttons[i + 1..] {
            assert!(a.inflate(14).intersect(b).is_none(), "{a:?} and {b:?} are 15 px apart");
        }
    }
    // The named buttons are the slots of their pages.
    assert_eq!(
        [lay.slow(), lay.normal(), lay.fast(), lay.undo(), lay.page_key()],
        [0, 1, 2, 3, 4].map(|i| lay.slot(i))
    );
    assert_eq!([lay.grip(), lay.calibrate(), lay.line_toggle(), lay.lift_toggle()], [0, 1, 2, 3].map(|i| lay.slot(i)));
    assert_eq!((0..4).map(|n| lay.pose(n)).collect::<Vec<_>>(), buttons[..4]);
}

#[test]
fn pixel_and_coordinate_mappings_round_trip() {
    check_mappings_and_tiling(&L);
    // 320×240: 120 px per unit, the map at the top left.
    assert_eq!(WS, Area::new(0, 0, 224, 112));
    assert_eq!(L.panel_to_pixel(1.0, 0.0), Some((319, 239)));
    assert_eq!(ws_point_to_pixel(0.0, 0.0), Some((112, 111)));
}

/// A screen turned by 180° (`cal set lcd rotate 180`): the two panel
/// mappings still round-trip on every pixel (the regions are the unturned
/// layout's: `check_mappings_and_tiling`), and a pixel's panel point is
/// the unturned screen's at the opposite corner (where the controller draws
/// it on the glass), on both sizes.
#[test]
fn the_turned_layouts_map_each_pixel_to_the_opposite_corner_of_the_glass() {
    for lay in [L, Layout::HVGA] {
        let t = lay.turned(true);
        assert_eq!(t.turned(false), lay);
        let (w, h) = (lay.width() as i16, lay.height() as i16);
        for y in 0..h {
            for x in 0..w {
                let (x_p, y_p) = t.pixel_center_to_panel(x, y);
                assert_eq!(t.panel_to_pixel(x_p, y_p), Some((x, y)));
            }
        }
        for (x, y) in [(0, 0), (w - 1, h - 1), (17, 200), (w / 2, h / 2), (w - 3, 5)] {
            let (tx, ty) = t.pixel_center_to_panel(x, y);
            assert_eq!((tx, ty), lay.pixel_center_to_panel(w - 1 - x, h - 1 - y), "{x},{y}");
            // The unturned screen reads that point as the opposite pixel.
            assert_eq!(lay.panel_to_pixel(tx, ty), Some((w - 1 - x, h - 1 - y)), "{x},{y}");
        }
        // The glass's far corner is the turned screen's first pixel.
        assert_eq!(t.panel_to_pixel(1.0, 0.0), Some((0, 0)));
    }
}

#[test]
fn the_480x320_layout_is_the_same_arrangement_with_larger_targets() {
    let big = Layout::HVGA;
    check_mappings_and_tiling(&big);
    // Same map proportions (2:1, the arm base mid-bottom), 160 px per unit.
    assert_eq!(big.ws(), Area::new(0, 0, 320, 160));
    assert_eq!(big.ws_origin_x(), 160);
    // Every touch target is larger, and the guard bands stay 8 px.
    for (a, b) in [(L.stop(), big.stop())].into_iter().chain((0..SLOTS).map(|i| (L.slot(i), big.slot(i)))) {
        assert!(b.w > a.w && b.h > a.h, "{a:?} -> {b:?}");
    }
    assert_eq!((big.stop().w, big.stop().h), (152, 160));
    assert_eq!(big.gaps()[0].w, 8);
    assert_eq!(big.gaps()[1].h, 8);
    // The buttons: 52×52 15 px apart at 320×240, 83×80 16 px apart at
    // 480×320 (the last takes the rounding: 84).
    assert_eq!(L.slot(0), Area::new(0, 188, 52, 52));
    assert_eq!(L.slot(4), Area::new(268, 188, 52, 52));
    assert_eq!(big.slot(0), Area::new(0, 240, 83, 80));
    assert_eq!(big.slot(3), Area::new(297, 240, 83, 80));
    assert_eq!(big.slot(4), Area::new(396, 240, 84, 80));
    // STOP's guard band: beside and below STOP, not beside the map.
    assert_eq!(big.stop_hit(), Area::new(320, 0, 160, 168));
    // The labels fit their buttons (3× text: 18 px per character).
    for lay in [L, big] {
        let (cw, gap) = (6 * u16::from(lay.text_scale()), u16::from(lay.text_scale()));
        for (a, label) in [
            (lay.slow(), "Slow"),
            (lay.normal(), "Mid"),
            (lay.fast(), "Fast"),
            (lay.undo(), "Undo"),
            (lay.calibrate(), "Cal"),
            (lay.page_key(), "More"),
            (lay.page_key(), "Back"),
            (lay.grip(), "Grab"),
            (lay.grip(), "Open"),
            (lay.pose(0), "1"),
            (lay.line_toggle(), "Line"),
            (lay.lift_toggle(), "Lift"),
        ] {
            let ink = cw * label.len() as u16 - gap;
            assert!(ink <= a.w, "{label}: {ink} px in {}", a.w);
        }
    }
    // The hit test follows the layout.
    let mut ui = Ui::with_layout(&CONFIG, big);
    let mut fb = Framebuffer::new(480, 320, Rgb565::BLACK);
    ui.draw(&moving_model(), &mut fb).unwrap();
    snapshot(&fb, "hvga_moving");
    let centre = |a: Area| (a.x + a.w as i16 / 2, a.y + a.h as i16 / 2);
    for (a, hit) in [
        (big.stop(), Hit::Stop),
        (big.slow(), Hit::Speed(SpeedPreset::Slow)),
        (big.normal(), Hit::Speed(SpeedPreset::Normal)),
        (big.fast(), Hit::Speed(SpeedPreset::Fast)),
        (big.page_key(), Hit::Page),
    ] {
        let (x, y) = centre(a);
        assert_eq!(ui.hit(x, y), Some(hit));
        let (x_p, y_p) = big.pixel_center_to_panel(x, y);
        assert_eq!(ui.hit_panel(x_p, y_p), Some(hit));
    }
    assert_eq!(ui.hit(319, 0), Some(Hit::Map { x_p: 319.0 / 320.0, y_p: 319.0 / 320.0 }));
    assert_eq!(ui.hit(100, 164), None, "the guard band below the map");
    let (cx, cy) = big.ws_point_to_pixel(0.4, 0.5).unwrap();
    assert_eq!(fb.pixel(cx.into(), cy.into()), Some(theme::TOUCH_MARK));
    // The map's colours follow the conditions and the reach, pixel by pixel
    // (the diagonals, the vertical, the base and the zone numbers' ink
    // aside).
    let mut idle = UiModel::new(SpeedPreset::Slow);
    idle.state = UiState::Idle;
    let mut fb = Framebuffer::new(480, 320, Rgb565::BLACK);
    Ui::with_layout(&CONFIG, big).draw_full(&idle, &mut fb).unwrap();
    snapshot(&fb, "hvga_idle");
    let mut checked = 0;
    for y in 0..160i16 {
        for x in 0..320i16 {
            let px = fb.pixel(x.into(), y.into()).unwrap();
            let on_line = x == y || x == 319 - y || x == 159 || x == 160;
            if on_line || base_area(&big).contains(x, y) || px == theme::TEXT {
                continue;
            }
            let (x_p, y_p) = big.ws_pixel_to_point(x, y).unwrap();
            let zone = condition(x_p, y_p).unwrap().number() as usize - 1;
            let r = f64::from(x_p).hypot(f64::from(y_p));
            let reach = r >= f64::from(REACH_MIN) && r <= f64::from(REACH_MAX);
            let want = if reach { theme::ZONE[zone] } else { theme::ZONE_OUT[zone] };
            assert_eq!(px, want, "pixel ({x},{y}) = ({x_p},{y_p})");
            checked += 1;
        }
    }
    assert!(checked > 48_000, "checked {checked} map pixels");
}

// ---- the map ------------------------------------------------------------------------

#[test]
fn map_colours_follow_workspace_conditions_and_reach() {
    let mut model = UiModel::new(SpeedPreset::Slow);
    model.state = UiState::Idle;
    let fb = full(&model);
    snapshot(&fb, "idle");
    let labels: Vec<Area> =
        [(S + 2 * S / 3, 2 * S / 3), (S + S / 3, S / 3), (S - S / 3, S / 3), (S - 2 * S / 3, 2 * S / 3)]
            .iter()
            .map(|&(x, y)| Area::new(x - 7, y - 10, 18, 24))
            .collect();
    let mut checked = 0;
    for y in WS.y..WS.bottom() {
        for x in WS.x..WS.right() {
            let (col, row) = (x - WS.x, y - WS.y);
            let on_line = col == row || col == 2 * S - 1 - row || col == S - 1 || col == S;
            let px = fb.pixel(x.into(), y.into()).unwrap();
            if BASE_AREA.contains(x, y) {
                assert_eq!(px, theme::BASE);
                continue;
            }
            if on_line {
                assert_eq!(px, theme::ZONE_LINE, "line at ({x},{y})");
                continue;
            }
            if labels.iter().any(|l| l.contains(x, y)) {
                continue;
            }
            let (x_p, y_p) = ws_pixel_to_point(x, y).unwrap();
            let zone = condition(x_p, y_p).unwrap().number() as usize - 1;
            let r = f64::from(x_p).hypot(f64::from(y_p));
            let reach = r >= f64::from(REACH_MIN) && r <= f64::from(REACH_MAX);
            let want = if reach { theme::ZONE[zone] } else { theme::ZONE_OUT[zone] };
            assert_eq!(px, want, "pixel ({x},{y}) = ({x_p},{y_p}), zone {}, reach {reach}", zone + 1);
            checked += 1;
        }
    }
    assert!(checked > 22_000, "checked {checked} map pixels");
    // Each zone number is drawn in its own triangle, in text colour.
    for (i, l) in labels.iter().enumerate() {
        assert!(fb.count_in(&rect(*l), theme::TEXT) > 50, "label {} missing", i + 1);
        let (x_p, y_p) = ws_pixel_to_point(l.x + 7, l.y + 10).unwrap();
        assert_eq!(condition(x_p, y_p).unwrap().number() as usize, i + 1);
    }
}

/// The background painted row by row (a large area) and column by column
/// (a scan line's box, up to 3 pixels wide, anywhere across the map and
/// past its edges) gives every pixel `background_at`'s colour, and paints
/// nothing outside the map and the box, on both layouts, for reaches
/// from everything to a thin ring.
#[test]
fn the_map_background_is_exact_by_rows_and_by_columns() {
    use touch_arm::ui::ws_view::{background_at, draw_background, Reach};
    const NONE: Rgb565 = Rgb565::new(1, 2, 3);
    let mut checked = 0usize;
    for lay in [Layout::QVGA, Layout::HVGA] {
        let ws = lay.ws();
        for (min, max) in [(0.0, 2.0), (0.2, 1.0), (0.4, 0.9), (0.05, 0.6), (0.7, 0.72)] {
            let reach = Reach::new(min, max, lay.scale());
            let mut boxes = vec![Area::new(ws.x - 5, ws.y - 5, ws.w + 10, ws.h + 10)];
            for w in 1..=3u16 {
                boxes.extend((ws.x - 2..ws.right() + 1).map(|x| Area::new(x, ws.y, w, ws.h)));
            }
            for a in boxes {
                let mut fb = Framebuffer::new(lay.width().into(), lay.height().into(), NONE);
                draw_background(&mut fb, &lay, &reach, a).unwrap();
                // The box, a margin round it and the map's edges.
                let seen = a.inflate(4).intersect(&lay.screen()).unwrap();
                for y in seen.y..seen.bottom() {
                    for x in seen.x..seen.right() {
                        let want = if a.contains(x, y) && ws.contains(x, y) {
                            background_at(&lay, &reach, x, y)
                        } else {
                            NONE
                        };
                        assert_eq!(fb.pixel(x.into(), y.into()), Some(want), "({x}, {y}) of {a:?}, reach {min}..{max}");
                        checked += 1;
                    }
                }
            }
        }
    }
    // Per reach: both maps with margins (26 136 + 53 700 pixels), and
    // 229 + 325 column boxes of each width with their margins.
    assert!(checked > 5 * (26_136 + 53_700 + 3 * 229 * 9 * 120), "checked {checked} pixels");
}

#[test]
fn markers_sit_on_the_pixels_the_mapping_predicts() {
    let m = moving_model();
    let fb = full(&m);
    snapshot(&fb, "moving");
    let (cx, cy) = ws_point_to_pixel(0.4, 0.5).unwrap();
    assert_eq!((cx, cy), (156, 55));
    let (cx, cy) = (i32::from(cx), i32::from(cy));
    let r = i32::from(MARKER_R);
    // The plus: black arms through the centre, a white halo at their tips,
    // the map beyond.
    for d in -(r - 1)..=(r - 1) {
        assert_eq!(fb.pixel(cx + d, cy), Some(theme::TOUCH_MARK));
        assert_eq!(fb.pixel(cx, cy + d), Some(theme::TOUCH_MARK));
    }
    assert_eq!(fb.pixel(cx + r, cy), Some(theme::WHITE));
    assert_eq!(fb.pixel(cx, cy - r), Some(theme::WHITE));
    assert_eq!(fb.pixel(cx + r + 1, cy), Some(theme::ZONE[1]));
    // The ring around it (3 px, between the white outer and inner lines).
    for k in 1..=3 {
        assert_eq!(fb.pixel(cx - r + k, cy - 5), Some(theme::TARGET_MARK), "ring k={k}");
        assert_eq!(fb.pixel(cx + 5, cy + r - k), Some(theme::TARGET_MARK), "ring k={k}");
    }
    assert_eq!(fb.pixel(cx - 4, cy - 4), Some(theme::WHITE));
    assert_eq!(fb.pixel(cx - r, cy - r), Some(theme::WHITE));
    // A refused touch draws red; a target alone draws only the ring.
    let mut refused = m;
    refused.state = UiState::Refused(Refusal::TooFar);
    refused.touch = Some((-0.95, 0.9));
    refused.target = None;
    let fb = full(&refused);
    snapshot(&fb, "refused_far");
    let (rx, ry) = ws_point_to_pixel(-0.95, 0.9).unwrap();
    assert_eq!((rx, ry), (5, 11));
    assert_eq!(fb.pixel(5, 11), Some(theme::REFUSED));
    // Near the corner the marker is cut at the map's edge, never drawn
    // outside it: the gap right of the map stays background.
    let mut edge = m;
    edge.touch = Some((1.0, 1.0));
    let fb = full(&edge);
    assert_eq!(fb.pixel(223, 0), Some(theme::TOUCH_MARK));
    for y in 0..10 {
        assert_eq!(fb.pixel(224, y), Some(theme::BG));
    }
}

// ---- words --------------------------------------------------------------------

fn assert_text_at(fb: &Framebuffer, s: &[u8], x: i16, y: i16, style: &TextStyle) {
    let (want, a) = text_alone(s, x, y, style);
    assert_eq!(crop(fb, a), want, "text {:?} at ({x},{y})", String::from_utf8_lossy(s));
}

#[test]
fn status_lines_say_what_happens_in_words() {
    let head = |c: Rgb565| TextStyle::opaque(2, c, theme::BG);
    let small = TextStyle::opaque(1, theme::TEXT, theme::BG);
    type Case<'a> = (UiState, &'a [u8], Rgb565, Option<&'a [u8]>);
    let cases: [Case; 11] = [
        (UiState::PowerUp, b"Starting up", theme::TEXT, Some(b"Please wait")),
        (UiState::Idle, b"Ready", theme::TEXT, Some(b"Touch the map to move")),
        (UiState::Checking, b"Checking the way", theme::TEXT, Some(b"The arm starts soon")),
        (UiState::Moving { progress: 0.25 }, b"Moving to target", theme::TEXT, None),
        (UiState::Holding, b"Holding", theme::TEXT, Some(b"Touch the map to move")),
        (UiState::Paused, b"Paused", theme::TEXT, Some(b"Hold the map to go on")),
        (UiState::Stopped, b"Stopped - hold RESUME", theme::REFUSED, Some(b"The arm holds still")),
        (UiState::Refused(Refusal::TooFar), b"Out of reach", theme::REFUSED, Some(b"Try closer to the base")),
        (UiState::Refused(Refusal::TooClose), b"Out of reach", theme::REFUSED, Some(b"Try further from base")),
        (UiState::Refused(Refusal::OffMap), b"Not on the map", theme::REFUSED, Some(b"Touch inside the map")),
        (UiState::Refused(Refusal::Busy), b"Still moving", theme::TEXT, Some(b"Wait, or tap STOP")),
    ];
    for (state, headline, color, hint) in cases {
        let mut m = moving_model();
        m.state = state;
        let fb = full(&m);
        assert_text_at(&fb, headline, 4, 122, &head(color));
        if let Some(h) = hint {
            assert_text_at(&fb, h, 4, 142, &head(theme::TEXT));
        }
        assert_text_at(&fb, b"Zone 2  Direction 51\x7f", 4, 163, &small);
        assert_text_at(&fb, b"Base 51\x7f   Shoulder 40\x7f   Elbow 80\x7f", 4, 177, &small);
        let name = match state {
            UiState::Refused(r) => format!("refused_{r:?}").to_lowercase(),
            UiState::Moving { .. } => "moving_25".into(),
            s => format!("{s:?}").to_lowercase(),
        };
        snapshot(&fb, &name);
    }
    // Progress: bar filled to round(p·214) pixels and the percentage.
    let mut m = moving_model();
    m.state = UiState::Moving { progress: 0.25 };
    let fb = full(&m);
    let fill = L.bar_fill();
    let filled = fb.count_in(&rect(fill), theme::PROGRESS);
    assert_eq!(filled, 54 * 12, "0.25·214 = 53.5 → 54 columns");
    assert_text_at(&fb, b" 25%", 232, 142, &head(theme::TEXT));
    // Unknown angles show dashes; the top warning is shown in words.
    let mut m = UiModel::new(SpeedPreset::Fast);
    m.warnings = warn::DEFAULT_SETTINGS | warn::SERVOS_OFF;
    let fb = full(&m);
    snapshot(&fb, "powerup_warning");
    assert_text_at(&fb, b"Base --   Shoulder --   Elbow --", 4, 177, &small);
    assert_text_at(&fb, b"! servos are off", 164, 163, &TextStyle::opaque(1, theme::WARN_TEXT, theme::BG));
}

// ---- buttons --------------------------------------------------------------------

#[test]
fn stop_is_large_red_and_becomes_a_green_resume() {
    const { assert!(L.stop().w >= 60 && L.stop().h >= 60) };
    let mut ui = Ui::new(&CONFIG);
    // STOP works before anything is drawn.
    assert_eq!(ui.hit(280, 60), Some(Hit::Stop));
    assert_eq!(ui.hit(100, 60), None);
    let mut fb = Framebuffer::landscape();
    let mut m = moving_model();
    ui.draw(&m, &mut fb).unwrap();
    let stop = rect(L.stop());
    let red = fb.count_in(&stop, theme::STOP_RED);
    let white = fb.count_in(&stop, theme::WHITE);
    assert_eq!(red + white, 88 * 112, "STOP is red with white letters only");
    assert!(red > 88 * 112 * 3 / 4);
    assert_text_at(&fb, b"STOP", 244, 44, &TextStyle::opaque(3, theme::WHITE, theme::STOP_RED).tight());
    // The guard band beside STOP counts as STOP (the safe reading).
    assert_eq!(ui.hit(228, 60), Some(Hit::Stop));
    assert_eq!(ui.hit(300, 116), Some(Hit::Stop));
    assert_eq!(ui.hit(224, 0), Some(Hit::Stop));

    m.state = UiState::Stopped;
    let mut c = Counting::new(&mut fb);
    let r = ui.draw(&m, &mut c).unwrap();
    assert!(r.contains(Redrawn::STOP | Redrawn::HEADLINE));
    let fb_after = fb.clone();
    snapshot(&fb_after, "stopped");
    let green = fb_after.count_in(&stop, theme::RESUME_GREEN);
    assert!(green > 88 * 112 * 3 / 4);
    assert_text_at(&fb_after, b"RESUME", 243, 48, &TextStyle::opaque(2, theme::WHITE, theme::RESUME_GREEN).tight());
    // RESUME starts motion: only its own box counts, never the guard band.
    assert_eq!(ui.hit(280, 60), Some(Hit::Resume));
    assert_eq!(ui.hit(228, 60), None);
    assert_eq!(ui.hit(300, 116), None);

    // Held, RESUME counts down as a white band closing in from its edge:
    // 2 px (the text scale) a step inside a 1-px margin; each step paints
    // its new band only, and the label stays whole.
    let mut fb = fb_after.clone();
    for k in 1..=4u8 {
        m.resume = Some(k);
        let mut c = Counting::new(&mut fb);
        let r = ui.draw(&m, &mut c).unwrap();
        assert!(r.contains(Redrawn::STOP));
        let (outer, inner) = (L.stop().shrink(1 + 2 * (u16::from(k) - 1)), L.stop().shrink(1 + 2 * u16::from(k)));
        let in_stop = (stop.top_left.x..stop.top_left.x + 88)
            .flat_map(|x| (0..112).map(move |y| (x, y)))
            .filter(|&(x, y)| c.writes_at(x, y) > 0)
            .count();
        let area = |a: Area| a.w as usize * a.h as usize;
        assert_eq!(in_stop, area(outer) - area(inner), "step {k}: its new band only");
        let band = fb.count_in(&stop, theme::WHITE) - fb_after.count_in(&stop, theme::WHITE);
        assert_eq!(band, area(L.stop().shrink(1)) - area(inner), "step {k}");
        assert_text_at(&fb, b"RESUME", 243, 48, &TextStyle::opaque(2, theme::WHITE, theme::RESUME_GREEN).tight());
    }
    snapshot(&fb, "resume_held");
    // A dropout starts a new contact from 0: the button is drawn afresh.
    m.resume = Some(1);
    ui.draw(&m, &mut fb).unwrap();
    m.resume = None;
    ui.draw(&m, &mut fb).unwrap();
    assert_eq!(fb, fb_after);
}

#[test]
fn hits_map_to_buttons_and_workspace_points() {
    let mut ui = Ui::new(&CONFIG);
    let mut fb = Framebuffer::landscape();
    ui.draw(&moving_model(), &mut fb).unwrap();
    assert_eq!(ui.hit(30, 220), Some(Hit::Speed(SpeedPreset::Slow)));
    assert_eq!(ui.hit(93, 214), Some(Hit::Speed(SpeedPreset::Normal)));
    assert_eq!(ui.hit(160, 214), Some(Hit::Speed(SpeedPreset::Fast)));
    assert_eq!(ui.hit(227, 214), Some(Hit::Undo));
    assert_eq!(ui.hit(294, 214), Some(Hit::Page));
    // Gaps, guard band and status area do nothing.
    for (x, y) in [(59, 214), (126, 214), (193, 214), (260, 214), (100, 116), (100, 150), (100, 186), (-1, 5), (320, 5)]
    {
        assert_eq!(ui.hit(x, y), None, "({x},{y})");
    }
    // Every map pixel is a workspace point whose condition is the zone drawn
    // under it.
    for y in (WS.y..WS.bottom()).step_by(3) {
        for x in (WS.x..WS.right()).step_by(3) {
            let Some(Hit::Map { x_p, y_p }) = ui.hit(x, y) else { panic!("({x},{y}) is on the map") };
            assert_eq!(ws_point_to_pixel(x_p, y_p), Some((x, y)));
            let zone = condition(x_p, y_p).unwrap().number() as usize - 1;
            let px = fb.pixel(x.into(), y.into()).unwrap();
            let (col, row) = (x, y);
            let decorated =
                col == row || col == 2 * S - 1 - row || col == S - 1 || col == S || BASE_AREA.contains(x, y);
            if !decorated
                && (px == theme::ZONE[0]
                    || px == theme::ZONE_OUT[0]
                    || px == theme::ZONE[1]
                    || px == theme::ZONE[2]
                    || px == theme::ZONE[3]
                    || px == theme::ZONE_OUT[1]
                    || px == theme::ZONE_OUT[2]
                    || px == theme::ZONE_OUT[3])
            {
                assert!(px == theme::ZONE[zone] || px == theme::ZONE_OUT[zone], "zone colour at ({x},{y})");
            }
        }
    }
    // The panel mapping goes through the same pixels.
    let (x_p, y_p) = pixel_center_to_panel(280, 60);
    assert_eq!(ui.hit_panel(x_p, y_p), Some(Hit::Stop));
    assert_eq!(ui.hit_panel(2.0, 0.5), None);
    // The workspace point of the map's top-right pixel.
    assert_eq!(ui.hit(223, 0), Some(Hit::Map { x_p: 223.0 / 224.0, y_p: 223.0 / 224.0 }));
    assert_eq!(ui.hit(112, 111), Some(Hit::Map { x_p: 1.0 / 224.0, y_p: 1.0 / 224.0 }));
    assert_eq!(condition(1.0f32 / 224.0, 1.0 / 224.0), Ok(Condition::C1));
}

// ---- redraws ---------------------------------------------------------------------

#[test]
fn full_redraw_paints_every_pixel_and_reports_its_bus_cost() {
    let mut fb = Framebuffer::new(320, 240, Rgb565::new(31, 0, 31));
    let mut c = Counting::new(&mut fb);
    let mut ui = Ui::new(&CONFIG);
    let r = ui.draw_full(&moving_model(), &mut c).unwrap();
    assert_eq!(r, Redrawn(Redrawn::ALL_MAIN));
    assert_eq!(c.touched(), 320 * 240, "a full redraw paints every pixel");
    assert_eq!(c.outside, 0);
    let calls = c.fill_solid_calls + c.fill_contiguous_calls;
    // On the ILI9341 bus each call costs a window (CASET 5 + PASET 5 + RAMWR
    // 1 = 11 bytes) and every pixel 2 bytes.
    let bytes = 11 * calls as u64 + 2 * c.total_writes();
    eprintln!(
        "full redraw: {} pixel writes ({:.2} per pixel), {} fill_solid + {} fill_contiguous calls, {} bus bytes",
        c.total_writes(),
        c.total_writes() as f64 / 76_800.0,
        c.fill_solid_calls,
        c.fill_contiguous_calls,
        bytes
    );
    assert_eq!(c.draw_iter_calls, 0, "no per-pixel drawing");
    assert!(c.total_writes() < 80_000, "overdraw stays small: {}", c.total_writes());
    assert!(calls < 1_800, "{calls} windows");
    // Whatever was on the glass before, the picture is the same.
    assert_eq!(fb, full(&moving_model()));
}

fn assert_only_in(c: &Counting<'_, Framebuffer>, allowed: &[Area], what: &str) {
    let allowed: Vec<Rectangle> = allowed.iter().map(|a| rect(*a)).collect();
    let outside = c.touched_outside(&allowed);
    assert!(outside.is_empty(), "{what}: {} pixels written outside, first {:?}", outside.len(), outside.first());
}

#[test]
fn partial_redraws_write_only_the_changed_regions() {
    let mut ui = Ui::new(&CONFIG);
    let mut fb = Framebuffer::landscape();
    let mut m = moving_model();
    m.state = UiState::Moving { progress: 0.30 };
    ui.draw(&m, &mut fb).unwrap();

    // Nothing changed: nothing drawn.
    let mut c = Counting::new(&mut fb);
    assert!(ui.draw(&m, &mut c).unwrap().is_empty());
    assert_eq!(c.total_writes(), 0);
    // A change below display resolution draws nothing either.
    m.joints[0] += 0.001;
    let mut c = Counting::new(&mut fb);
    assert!(ui.draw(&m, &mut c).unwrap().is_empty());
    assert_eq!(c.total_writes(), 0);

    // Joint angles: only their line.
    m.joints[1] = 0.2;
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&m, &mut c).unwrap(), Redrawn(Redrawn::JOINTS));
    assert_only_in(&c, &[L.joints()], "joints");
    assert_eq!(c.touched(), 320 * 14);

    // Progress 0.30 → 0.31: the bar columns between (64 → 66) and the percent.
    m.state = UiState::Moving { progress: 0.31 };
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&m, &mut c).unwrap(), Redrawn(Redrawn::DETAIL));
    let bar_delta = Area::new(L.bar_fill().x + 64, L.bar_fill().y, 2, 12);
    assert_only_in(&c, &[bar_delta, L.bar_text()], "progress");
    assert_eq!(c.touched(), 2 * 12 + 52 * 16);

    // A new touch: only the boxes of the old and new plus.
    let old = ws_point_to_pixel(0.4, 0.5).unwrap();
    m.touch = Some((-0.5, 0.2));
    let new = ws_point_to_pixel(-0.5, 0.2).unwrap();
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&m, &mut c).unwrap(), Redrawn(Redrawn::MARKERS));
    assert_only_in(&c, &[Area::around(old.0, old.1, MARKER_R), Area::around(new.0, new.1, MARKER_R)], "markers");
    // The unchanged target ring is restored where the old plus was.
    assert_eq!(fb, full(&m), "partial result equals a full redraw");

    // Speed preset: only the three preset buttons.
    m.speed = SpeedPreset::Fast;
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&m, &mut c).unwrap(), Redrawn(Redrawn::SPEED));
    assert_only_in(&c, &[L.slow(), L.normal(), L.fast()], "speed");
    assert_eq!(fb, full(&m));
}

/// The pages on `lay`: the page key turns Main → More → Setup → Main;
/// each turn repaints only the row of buttons (the map, STOP, the headline
/// and the status lines stay) and leaves the same picture as a full draw;
/// the buttons hit as drawn; the Grip label follows the gripper and each
/// toggle's highlight its setting, repainting only that button.
fn more_page(lay: Layout, name: &str) {
    let mut ui = Ui::with_layout(&CONFIG, lay);
    let (w, h) = (lay.width().into(), lay.height().into());
    let mut fb = Framebuffer::new(w, h, Rgb565::BLACK);
    let full_of = |m: &UiModel| {
        let mut fb = Framebuffer::new(w, h, Rgb565::BLACK);
        Ui::with_layout(&CONFIG, lay).draw_full(m, &mut fb).unwrap();
        fb
    };
    let centre = |a: Area| (a.x + a.w as i16 / 2, a.y + a.h as i16 / 2);
    let row = Area::new(0, lay.slot(0).y, lay.width(), lay.slot(0).h);
    let main = moving_model();
    ui.draw(&main, &mut fb).unwrap();
    // The main page: the speed presets, Undo, More.
    for (a, hit) in [
        (lay.slow(), Hit::Speed(SpeedPreset::Slow)),
        (lay.normal(), Hit::Speed(SpeedPreset::Normal)),
        (lay.fast(), Hit::Speed(SpeedPreset::Fast)),
        (lay.undo(), Hit::Undo),
        (lay.page_key(), Hit::Page),
    ] {
        let (x, y) = centre(a);
        assert_eq!(ui.hit(x, y), Some(hit), "{name}: main {a:?}");
    }
    let mut more = main;
    more.page = Page::More;
    // `path line` set: the Line toggle shows on, Lift off.
    more.path_line = true;
    let mut c = Counting::new(&mut fb);
    let r = ui.draw(&more, &mut c).unwrap();
    assert_eq!(r, Redrawn(Redrawn::PAGE_KEY | Redrawn::ROW2));
    assert_only_in(&c, &[row], "page change to More");
    assert!(fb == full_of(&more), "{name}: the page change equals a full draw of the More page");
    snapshot(&fb, name);
    let mut scratch = Framebuffer::new(w, h, Rgb565::BLACK);
    assert_eq!(Ui::with_layout(&CONFIG, lay).draw_full(&more, &mut scratch).unwrap(), Redrawn(Redrawn::ALL_MORE));
    let style = TextStyle::opaque(lay.text_scale(), theme::WHITE, theme::BUTTON_ON);
    let key_style = TextStyle::opaque(lay.text_scale(), theme::TEXT, theme::BUTTON);
    let ink = |a: Area, s: &str, style: &TextStyle| {
        let (tw, th) = style.extent(s.len());
        let x = a.x + (a.w - (tw - u16::from(style.gap))) as i16 / 2;
        let y = a.y + (a.h - th) as i16 / 2;
        (x, y)
    };
    for (n, label) in [(0u8, "1"), (3, "4")] {
        let (x, y) = ink(lay.pose(n), label, &key_style);
        assert_text_at(&fb, label.as_bytes(), x, y, &key_style);
    }
    let (kx, ky) = ink(lay.page_key(), "More", &key_style);
    assert_text_at(&fb, b"More", kx, ky, &key_style);
    for (a, hit) in [
        (lay.pose(0), Hit::Pose(1)),
        (lay.pose(1), Hit::Pose(2)),
        (lay.pose(2), Hit::Pose(3)),
        (lay.pose(3), Hit::Pose(4)),
        (lay.page_key(), Hit::Page),
        (lay.stop(), Hit::Stop),
    ] {
        let (x, y) = centre(a);
        assert_eq!(ui.hit(x, y), Some(hit), "{name}: more {a:?}");
    }
    // The Setup page.
    let mut setup = more;
    setup.page = Page::Setup;
    let mut c = Counting::new(&mut fb);
    let r = ui.draw(&setup, &mut c).unwrap();
    assert_eq!(r, Redrawn(Redrawn::PAGE_KEY | Redrawn::ROW2 | Redrawn::TOGGLES));
    assert_only_in(&c, &[row], "page change to Setup");
    assert!(fb == full_of(&setup), "{name}: the page change equals a full draw of the Setup page");
    snapshot(&fb, &format!("{name}_setup"));
    let mut scratch = Framebuffer::new(w, h, Rgb565::BLACK);
    assert_eq!(Ui::with_layout(&CONFIG, lay).draw_full(&setup, &mut scratch).unwrap(), Redrawn(Redrawn::ALL_SETUP));
    // Labels: Grab while the gripper is open, the page key says Back.
    let (gx, gy) = ink(lay.grip(), "Grab", &style);
    assert_text_at(&fb, b"Grab", gx, gy, &style);
    let (kx, ky) = ink(lay.page_key(), "Back", &key_style);
    assert_text_at(&fb, b"Back", kx, ky, &key_style);
    let (x, y) = ink(lay.calibrate(), "Cal", &key_style);
    assert_text_at(&fb, b"Cal", x, y, &key_style);
    // Line highlighted (on), Lift plain (off).
    let (x, y) = ink(lay.line_toggle(), "Line", &style);
    assert_text_at(&fb, b"Line", x, y, &style);
    let (x, y) = ink(lay.lift_toggle(), "Lift", &key_style);
    assert_text_at(&fb, b"Lift", x, y, &key_style);
    for (a, hit) in [
        (lay.grip(), Hit::Grip),
        (lay.calibrate(), Hit::Calibrate),
        (lay.line_toggle(), Hit::Line),
        (lay.lift_toggle(), Hit::Lift),
        (lay.page_key(), Hit::Page),
        (lay.stop(), Hit::Stop),
    ] {
        let (x, y) = centre(a);
        assert_eq!(ui.hit(x, y), Some(hit), "{name}: setup {a:?}");
    }
    // The gaps between the buttons and the guard bands: nothing.
    for g in lay.gaps().iter().skip(2) {
        let (x, y) = centre(*g);
        assert_eq!(ui.hit(x, y), None, "{name}: gap {g:?}");
    }
    // The gripper closes: only Grip is repainted, and now says Open.
    let mut closed = setup;
    closed.grip_closed = true;
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&closed, &mut c).unwrap(), Redrawn(Redrawn::ROW2));
    assert_only_in(&c, &[lay.grip()], "grip label");
    let (gx, gy) = ink(lay.grip(), "Open", &style);
    assert_text_at(&fb, b"Open", gx, gy, &style);
    assert!(fb == full_of(&closed));
    // Line off: only Line is repainted, plain; then Lift on: only Lift,
    // highlighted.
    let mut joint = closed;
    joint.path_line = false;
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&joint, &mut c).unwrap(), Redrawn(Redrawn::TOGGLES));
    assert_only_in(&c, &[lay.line_toggle()], "line toggle");
    let (x, y) = ink(lay.line_toggle(), "Line", &key_style);
    assert_text_at(&fb, b"Line", x, y, &key_style);
    assert!(fb == full_of(&joint), "{name}: line off");
    let mut lifted = joint;
    lifted.lift = true;
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&lifted, &mut c).unwrap(), Redrawn(Redrawn::TOGGLES));
    assert_only_in(&c, &[lay.lift_toggle()], "lift toggle");
    let (x, y) = ink(lay.lift_toggle(), "Lift", &style);
    assert_text_at(&fb, b"Lift", x, y, &style);
    assert!(fb == full_of(&lifted), "{name}: lift on");
    // The status lines are on every page: progress and joints repaint
    // only their lines.
    let mut later = lifted;
    later.state = UiState::Moving { progress: 0.9 };
    later.joints[1] = 0.1;
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&later, &mut c).unwrap(), Redrawn(Redrawn::DETAIL | Redrawn::JOINTS));
    assert_only_in(&c, &[lay.detail(), lay.joints()], "status lines on Setup");
    assert!(fb == full_of(&later), "{name}: status lines on Setup");
    // Back: the main page again, as a full draw would paint it.
    let mut back = later;
    back.page = Page::Main;
    let mut c = Counting::new(&mut fb);
    assert_eq!(ui.draw(&back, &mut c).unwrap(), Redrawn(Redrawn::SPEED | Redrawn::PAGE_KEY | Redrawn::ROW2));
    assert_only_in(&c, &[row], "back to Main");
    assert!(fb == full_of(&back), "{name}: back on the main page");
    let (x, y) = centre(lay.slow());
    assert_eq!(ui.hit(x, y), Some(Hit::Speed(SpeedPreset::Slow)));
}

#[test]
fn the_pages_hold_the_speeds_undo_poses_grip_calib_and_toggles_on_both_sizes() {
    more_page(Layout::QVGA, "more_page");
    more_page(Layout::HVGA, "hvga_more_page");
}

/// Uniform in [0, 1), for model fields.
fn unit(rng: &mut Rng) -> f32 {
    rng.uniform() as f32
}

/// A model point: none, an edge or corner, or anywhere in the workspace.
fn point(rng: &mut Rng) -> Option<(f32, f32)> {
    match rng.below(4) {
        0 => None,
        // Edges and corners too.
        1 => Some(([-1.0, 1.0, 0.0][rng.below(3) as usize], [0.0, 1.0][rng.below(2) as usize])),
        _ => Some((unit(rng) * 2.0 - 1.0, unit(rng))),
    }
}

/// Random model changes on `lay`: after each, the partially redrawn
/// picture equals a full redraw.
fn random_redraws(lay: Layout, steps: usize) {
    let mut rng = Rng::new(7);
    let mut ui = Ui::with_layout(&CONFIG, lay);
    let mut fb = Framebuffer::new(lay.width().into(), lay.height().into(), Rgb565::BLACK);
    let mut m = UiModel::new(SpeedPreset::Normal);
    let full = |m: &UiModel| {
        let mut fb = Framebuffer::new(lay.width().into(), lay.height().into(), Rgb565::BLACK);
        Ui::with_layout(&CONFIG, lay).draw_full(m, &mut fb).unwrap();
        fb
    };
    let ws = lay.ws();
    for step in 0..steps {
        match rng.below(10) {
            // The switch scan (issue #20 §4): a column or row line anywhere
            // on the map, a target, a lit button or STOP's place, or none.
            8 => {
                let x = ws.x + rng.below(u64::from(ws.w)) as i16;
                let y = ws.y + rng.below(u64::from(ws.h)) as i16;
                m.scan = match rng.below(5) {
                    0 => None,
                    1 => Some(ScanShow::Column(x)),
                    2 => Some(ScanShow::Row(y)),
                    3 => Some(ScanShow::Target { x, y, go: rng.below(2) == 0 }),
                    _ => Some(ScanShow::Item(rng.below(6) as u8)),
                };
            }
            // The candidate under a finger, its ring filling.
            9 => {
                m.preview = point(&mut rng).map(|(x_p, y_p)| Preview {
                    x_p,
                    y_p,
                    ok: rng.below(2) == 0,
                    ring: rng.below(5) as u8,
                });
            }
            0 => m.touch = point(&mut rng),
            1 => m.target = point(&mut rng),
            2 => {
                m.state = match rng.below(7) {
                    0 => UiState::Idle,
                    1 | 2 => UiState::Moving { progress: unit(&mut rng) },
                    3 => UiState::Holding,
                    4 => UiState::Stopped,
                    5 => UiState::Refused(Refusal::TooClose),
                    _ => UiState::Refused(Refusal::JointLimit),
                }
            }
            3 => m.joints[rng.below(3) as usize] = unit(&mut rng) * 3.0 - 1.0,
            4 => m.speed = SpeedPreset::ALL[rng.below(3) as usize],
            5 => m.warnings = rng.below(32) as u8,
            7 if rng.below(3) == 0 => {
                m.page = m.page.next();
                m.grip_closed = rng.below(2) == 0;
            }
            7 => {
                // Line and Lift, on either page (the main page ignores them).
                m.path_line = rng.below(2) == 0;
                m.lift = !m.path_line && rng.below(2) == 0;
            }
            6 => {
                m.condition = [None, Some(Condition::C1), Some(Condition::C4)][rng.below(3) as usize];
                m.alpha = unit(&mut rng) * 3.0;
            }
            _ => {
                m.touch = point(&mut rng);
                m.target = m.touch;
            }
        }
        ui.draw(&m, &mut fb).unwrap();
        assert!(fb == full(&m), "{lay:?} step {step}: partial redraws diverged from a full redraw of {m:?}");
    }
}

#[test]
fn any_sequence_of_partial_redraws_leaves_the_full_redraw_picture() {
    random_redraws(Layout::QVGA, 300);
    random_redraws(Layout::HVGA, 150);
}

// ---- calibration -------------------------------------------------------------

/// What an ideal panel wired as `cal` reads at crosshair `i` (320×240).
fn raw_at(cal: &Calibration, i: usize) -> (u16, u16) {
    raw_at_on(&L, cal, i)
}

/// ... on the screen laid out as `lay`.
fn raw_at_on(lay: &Layout, cal: &Calibration, i: usize) -> (u16, u16) {
    let (x_p, y_p) = cal_point(lay, i).unwrap();
    let raw = cal.unmap::<f64>(f64::from(x_p), f64::from(y_p)).unwrap();
    (raw.x, raw.y)
}

/// The raw reading of a touch at the centre of screen area `a` (320×240).
fn raw_on(cal: &Calibration, a: Area) -> (u16, u16) {
    raw_on_screen(&L, cal, a)
}

/// ... on the screen laid out as `lay`.
fn raw_on_screen(lay: &Layout, cal: &Calibration, a: Area) -> (u16, u16) {
    let (x_p, y_p) = lay.pixel_center_to_panel(a.x + a.w as i16 / 2, a.y + a.h as i16 / 2);
    let raw = cal.unmap::<f64>(f64::from(x_p), f64::from(y_p)).unwrap();
    (raw.x, raw.y)
}

/// Five readings with both channels equal.
const DIAGONAL: [(u16, u16); 5] = [(300, 300), (700, 700), (650, 650), (250, 250), (480, 480)];

fn panels() -> Vec<Calibration> {
    let d = Calibration::DEFAULT;
    vec![
        d,
        Calibration { swap_xy: true, ..d },
        Calibration { invert_x: true, ..d },
        Calibration { invert_y: true, x_min: 90, x_max: 960, ..d },
        Calibration { swap_xy: true, invert_x: true, invert_y: true, x_min: 150, x_max: 880, y_min: 200, y_max: 850 },
    ]
}

#[test]
fn calibration_flow_recovers_the_panel_and_saves_only_on_save() {
    for lay in [Layout::QVGA, Layout::HVGA] {
        for truth in panels() {
            let mut flow = CalibrationFlow::new(Calibration::DEFAULT, &lay);
            for i in 0..CAL_COUNT {
                assert_eq!(flow.phase(), CalPhase::Touch { index: i as u8 });
                assert_eq!(flow.crosshair_pixel(), cal_pixel(&lay, i));
                let (x, y) = raw_at_on(&lay, &truth, i);
                assert_eq!(flow.feed(x, y, 0), None);
            }
            let CalPhase::Review { result: Ok(fit) } = flow.phase() else {
                panic!("fit failed for {truth:?}: {:?}", flow.phase())
            };
            assert_eq!((fit.swap_xy, fit.invert_x, fit.invert_y), (truth.swap_xy, truth.invert_x, truth.invert_y));
            for (a, b) in
                [(fit.x_min, truth.x_min), (fit.x_max, truth.x_max), (fit.y_min, truth.y_min), (fit.y_max, truth.y_max)]
            {
                assert!(a.abs_diff(b) <= 1, "{lay:?}: fit {fit:?} vs truth {truth:?}");
            }
            // Touches outside the buttons do nothing; Save (mapped with the
            // new calibration) hands the fit over.
            let (x, y) = raw_on_screen(&lay, &truth, Area::new(lay.sx(150), lay.sy(40), 20, 20));
            assert_eq!(flow.feed(x, y, 0), None);
            let (x, y) = raw_on_screen(&lay, &truth, save_area(&lay));
            assert_eq!(flow.feed(x, y, 0), Some(CalibrationEvent::Done(fit)));
            // Cancel keeps the old one.
            let mut flow = CalibrationFlow::new(Calibration::DEFAULT, &lay);
            for i in 0..CAL_COUNT {
                let (x, y) = raw_at_on(&lay, &truth, i);
                flow.feed(x, y, 0);
            }
            let (x, y) = raw_on_screen(&lay, &truth, cancel_area(&lay));
            assert_eq!(flow.feed(x, y, 0), Some(CalibrationEvent::Cancelled));
        }
    }
    // The 480×320 crosshairs: the same 10 % insets and the centre.
    let big: Vec<_> = (0..CAL_COUNT).filter_map(|i| cal_pixel(&Layout::HVGA, i)).collect();
    assert_eq!(big, [(48, 32), (432, 32), (432, 288), (48, 288), (240, 160)]);
}

/// The touch settings' page (issue #19 §3): after Save on a good fit, its
/// − and + walk each setting's ladder and stop at its ends, which are the
/// ranges `cal set touch` takes; Save hands the fit over with the edited
/// values, Cancel keeps both; the values repaint alone.
#[test]
fn the_touch_settings_page_steps_each_setting_within_its_range() {
    let truth = panels()[4];
    for lay in [Layout::QVGA, Layout::HVGA] {
        let start = PressSettings { hold_cs: 13, ..PressSettings::DEFAULT };
        let fitted = || {
            let mut flow = CalibrationFlow::new(Calibration::DEFAULT, &lay).with_settings(start);
            for i in 0..CAL_COUNT {
                let (x, y) = raw_at_on(&lay, &truth, i);
                flow.feed(x, y, 0);
            }
            let CalPhase::Review { result: Ok(fit) } = flow.phase() else { panic!("{:?}", flow.phase()) };
            let (x, y) = raw_on_screen(&lay, &truth, save_area(&lay));
            assert_eq!(flow.feed(x, y, 0), None, "Save leads to the settings' page");
            assert_eq!(flow.phase(), CalPhase::Settings { cal: fit });
            (flow, fit)
        };
        let (mut flow, fit) = fitted();
        let press = |flow: &mut CalibrationFlow, field, up| {
            let (x, y) = raw_on_screen(&lay, &truth, setting_area(&lay, field, up));
            assert_eq!(flow.feed(x, y, 0), None);
            field.value(&flow.settings().unwrap())
        };
        // 0.13 s (set over serial) is between steps: + goes to the next one.
        assert_eq!(press(&mut flow, Setting::Hold, true), 15);
        assert_eq!(press(&mut flow, Setting::Hold, false), 12);
        let mut seen = vec![];
        for _ in 0..20 {
            seen.push(press(&mut flow, Setting::Hold, false));
        }
        assert_eq!(seen[..4], [10, 8, 6, 4]);
        assert!(seen[3..].iter().all(|&v| v == 4), "stops at 0.04 s: {seen:?}");
        for (field, top, bottom) in [(Setting::Hold, 200, 4), (Setting::Repeat, 200, 0), (Setting::Radius, 255, 20)] {
            let ups: Vec<u8> = (0..20).map(|_| press(&mut flow, field, true)).collect();
            assert!(ups.windows(2).all(|w| w[0] <= w[1]) && ups[19] == top, "{field:?} {ups:?}");
            let downs: Vec<u8> = (0..20).map(|_| press(&mut flow, field, false)).collect();
            assert!(downs.windows(2).all(|w| w[0] >= w[1]) && downs[19] == bottom, "{field:?} {downs:?}");
            // Every step is a value the settings store takes.
            for v in ups.iter().chain(&downs) {
                let mut p = PressSettings::DEFAULT;
                match field {
                    Setting::Hold => p.hold_cs = *v,
                    Setting::Repeat => p.repeat_cs = *v,
                    Setting::Radius => p.radius = *v,
                }
                assert!(p.is_valid(), "{field:?} {v}");
            }
        }
        assert_eq!(flow.settings().unwrap(), PressSettings { hold_cs: 4, repeat_cs: 0, radius: 20, ..start });
        let (x, y) = raw_on_screen(&lay, &truth, save_area(&lay));
        assert_eq!(flow.feed(x, y, 0), Some(CalibrationEvent::Done(fit)));
        // Cancel on the page keeps the old calibration (and so the old
        // settings: the app stores nothing).
        let (mut flow, _) = fitted();
        press(&mut flow, Setting::Radius, false);
        let (x, y) = raw_on_screen(&lay, &truth, cancel_area(&lay));
        assert_eq!(flow.feed(x, y, 0), Some(CalibrationEvent::Cancelled));
        // No two of the page's buttons overlap, and all lie on the screen.
        let mut areas = vec![save_area(&lay), cancel_area(&lay)];
        areas.extend(Setting::ALL.iter().flat_map(|&f| [setting_area(&lay, f, false), setting_area(&lay, f, true)]));
        for (i, a) in areas.iter().enumerate() {
            assert!(a.x >= 0 && a.y >= 0 && a.x as u16 + a.w <= lay.width() && a.y as u16 + a.h <= lay.height());
            for b in &areas[i + 1..] {
                let apart = a.x + a.w as i16 <= b.x
                    || b.x + b.w as i16 <= a.x
                    || a.y + a.h as i16 <= b.y
                    || b.y + b.h as i16 <= a.y;
                assert!(apart, "{a:?} {b:?}");
            }
        }
    }
    // Drawn: the page, then only a changed value.
    let mut ui = Ui::new(&CONFIG);
    let mut fb = Framebuffer::landscape();
    let (mut flow, fit) = {
        let mut flow = CalibrationFlow::new(Calibration::DEFAULT, &L).with_settings(PressSettings::DEFAULT);
        for i in 0..CAL_COUNT {
            let (x, y) = raw_at(&truth, i);
            flow.feed(x, y, 0);
        }
        let CalPhase::Review { result: Ok(fit) } = flow.phase() else { panic!() };
        let (x, y) = raw_on(&truth, SAVE_AREA);
        flow.feed(x, y, 0);
        (flow, fit)
    };
    ui.draw_calibration(&flow, &mut fb).unwrap();
    snapshot(&fb, "calibration_settings");
    let style = TextStyle::opaque(2, theme::TEXT, theme::WHITE);
    let centred = |s: &[u8]| (320 - 12 * s.len() as i16 + 2) / 2;
    // Row 0 (y 4..54): the name and the value, each 16 high, 6 apart.
    assert_text_at(&fb, b"Hold", centred(b"Hold"), 4 + 6, &style);
    assert_text_at(&fb, b"0.10 s", centred(b"0.10 s"), 4 + 6 + 16 + 6, &style);
    assert_text_at(&fb, b"0.30 s", centred(b"0.30 s"), 58 + 6 + 16 + 6, &style);
    // 240 counts over the fit's span, on the axis with fewer pixels per
    // count: 240·320/(x span) across, 240·240/(y span) up.
    let px = (240 * 320 / u32::from(fit.x_max - fit.x_min)).min(240 * 240 / u32::from(fit.y_max - fit.y_min));
    let radius = format!("240 = {px} px");
    assert_text_at(&fb, radius.as_bytes(), centred(radius.as_bytes()), 112 + 6 + 16 + 6, &style);
    let (x, y) = raw_on(&truth, setting_area(&L, Setting::Repeat, true));
    flow.feed(x, y, 0);
    let mut c = Counting::new(&mut fb);
    ui.draw_calibration(&flow, &mut c).unwrap();
    let row = setting_area(&L, Setting::Repeat, true);
    assert_only_in(&c, &[Area::new(72, row.y, 176, row.h)], "the repeat value");
    assert_text_at(&fb, b"0.40 s", centred(b"0.40 s"), 58 + 6 + 16 + 6, &style);
}

#[test]
fn calibration_ignores_repeats_and_offers_retry_after_a_bad_fit() {
    let truth = Calibration::DEFAULT;
    let mut flow = CalibrationFlow::new(truth, &L);
    let (x0, y0) = raw_at(&truth, 0);
    flow.feed(x0, y0, 0);
    // The same spot again (a bounce, or the finger still on the first cross).
    flow.feed(x0 + 10, y0 - 5, 0);
    assert_eq!(flow.phase(), CalPhase::Touch { index: 1 });
    assert!(flow.last_rejected());
    let (x1, y1) = raw_at(&truth, 1);
    flow.feed(x1, y1, 0);
    assert!(!flow.last_rejected());
    assert_eq!(flow.phase(), CalPhase::Touch { index: 2 });
    // Readings where both channels say the same: neither assignment of
    // channels to axes explains them.
    let mut flow = CalibrationFlow::new(truth, &L);
    for (x, y) in DIAGONAL {
        flow.feed(x, y, 0);
    }
    let CalPhase::Review { result: Err(e) } = flow.phase() else { panic!("{:?}", flow.phase()) };
    assert_eq!(e, CalFailure::Fit(CalibrationError::AmbiguousAxes));
    // On failure the old calibration maps the buttons: Retry starts over.
    let (x, y) = raw_on(&truth, SAVE_AREA);
    assert_eq!(flow.feed(x, y, 0), None);
    assert_eq!(flow.phase(), CalPhase::Touch { index: 0 });
    assert_eq!(flow.cancel(), CalibrationEvent::Cancelled);
}

#[test]
fn calibration_screens_show_each_cross_and_repaint_only_what_changed() {
    let truth = panels()[4];
    let mut ui = Ui::new(&CONFIG);
    let mut fb = Framebuffer::landscape();
    ui.draw(&moving_model(), &mut fb).unwrap();
    let mut flow = CalibrationFlow::new(Calibration::DEFAULT, &L);
    ui.draw_calibration(&flow, &mut fb).unwrap();
    assert_eq!(ui.hit(280, 60), None, "main-screen buttons are off during calibration");
    for i in 0..CAL_COUNT {
        let (cx, cy) = CAL_PIXELS[i];
        snapshot(&fb, &format!("calibration_{}", i + 1));
        assert_eq!(fb.pixel(cx.into(), (cy - 10).into()), Some(theme::CROSSHAIR));
        assert_eq!(fb.pixel((cx + 10).into(), cy.into()), Some(theme::CROSSHAIR));
        assert_eq!(fb.pixel(cx.into(), cy.into()), Some(theme::TEXT));
        let mut l = b"Point ".to_vec();
        l.extend(format!("{} of 5", i + 1).bytes());
        let style = TextStyle::opaque(2, theme::TEXT, theme::WHITE);
        assert_text_at(&fb, &l, (320 - 12 * l.len() as i16 + 2) / 2, 146, &style);
        // Only the previous cross is on the glass.
        for (j, &(ox, oy)) in CAL_PIXELS.iter().enumerate() {
            if j != i {
                assert_eq!(fb.pixel(ox.into(), (oy - 10).into()), Some(theme::WHITE));
            }
        }
        let (x, y) = raw_at(&truth, i);
        flow.feed(x, y, 0);
        let mut c = Counting::new(&mut fb);
        ui.draw_calibration(&flow, &mut c).unwrap();
        if i + 1 < CAL_COUNT {
            let (nx, ny) = CAL_PIXELS[i + 1];
            let allowed = [Area::around(cx, cy, CROSS_R), Area::around(nx, ny, CROSS_R), Area::new(0, 146, 320, 16)];
            assert_only_in(&c, &allowed, "next cross");
        }
    }
    snapshot(&fb, "calibration_review");
    let CalPhase::Review { result: Ok(fit) } = flow.phase() else { panic!() };
    let style = TextStyle::opaque(2, theme::TEXT, theme::WHITE);
    let l = format!("X {} - {}", fit.x_min, fit.x_max);
    assert_text_at(&fb, l.as_bytes(), (320 - 12 * l.len() as i16 + 2) / 2, 48, &style);
    let green = fb.count_in(&rect(SAVE_AREA), theme::RESUME_GREEN);
    assert!(green > 5000, "{green} green pixels");
    // A failed fit shows Retry.
    let mut bad = CalibrationFlow::new(Calibration::DEFAULT, &L);
    for (x, y) in DIAGONAL {
        bad.feed(x, y, 0);
    }
    assert!(matches!(bad.phase(), CalPhase::Review { result: Err(_) }));
    let mut fb2 = fb.clone();
    let mut ui2 = Ui::new(&CONFIG);
    ui2.draw_calibration(&flow, &mut fb2).unwrap();
    // Another result on the same glass is drawn anew.
    let mut c = Counting::new(&mut fb2);
    ui2.draw_calibration(&bad, &mut c).unwrap();
    assert_eq!(c.touched(), 320 * 240);
    snapshot(&fb2, "calibration_failed");
    assert_text_at(
        &fb2,
        b"Calibration failed",
        (320 - 12 * 18 + 2) / 2,
        16,
        &TextStyle::opaque(2, theme::REFUSED, theme::WHITE),
    );
    assert_text_at(&fb2, b"Touches did not line up", (320 - 12 * 23 + 2) / 2, 64, &style);
    // Back to the main screen: a full redraw.
    let mut c = Counting::new(&mut fb);
    let r = ui.draw(&moving_model(), &mut c).unwrap();
    assert_eq!(r, Redrawn(Redrawn::ALL_MAIN));
    assert_eq!(fb, full(&moving_model()));
}

// ---- the touch's preview (issue #19) ----------------------------------------

/// The candidate under a finger: a white frame, four rings inside it that
/// take the verdict's colour from the outside in as the hold fills (ring k
/// is the frame `k` pixels in), and a dot of that colour in the middle.
/// Only the marker's box changes between fills.
#[test]
fn the_candidate_marker_fills_its_rings_over_the_hold() {
    use touch_arm::ui::Preview;
    let lay = Layout::QVGA;
    let (x_p, y_p) = (0.25f32, 0.5f32);
    let (cx, cy) = lay.ws_point_to_pixel(x_p, y_p).unwrap();
    let r = marker_r(&lay) as i32;
    let (cx, cy) = (i32::from(cx), i32::from(cy));
    let base = UiModel { state: UiState::Holding, ..moving_model() };
    let mut last: Option<Framebuffer> = None;
    for ring in 0..=4u8 {
        for ok in [true, false] {
            let m = UiModel { preview: Some(Preview { x_p, y_p, ok, ring }), ..base };
            let fb = full(&m);
            let ink = if ok { theme::RESUME_GREEN } else { theme::REFUSED };
            assert_eq!(fb.pixel(cx, cy), Some(ink), "dot, ring {ring} ok {ok}");
            // The outer frame is white; ring k (1..=4) along the top edge.
            assert_eq!(fb.pixel(cx, cy - r), Some(theme::WHITE));
            for k in 1..=4 {
                let want = if k <= i32::from(ring) { ink } else { theme::WHITE };
                assert_eq!(fb.pixel(cx, cy - r + k), Some(want), "ring {k} of fill {ring}, ok {ok}");
            }
            if ok {
                if let Some(prev) = &last {
                    // Everything outside the marker's box is as before.
                    let bx = (cx - r)..=(cx + r);
                    let by = (cy - r)..=(cy + r);
                    for y in 0..240 {
                        for x in 0..320 {
                            if !(bx.contains(&x) && by.contains(&y)) {
                                assert_eq!(fb.pixel(x, y), prev.pixel(x, y), "({x}, {y}) outside the box");
                            }
                        }
                    }
                }
                last = Some(fb);
            }
        }
    }
}

/// The map's reach shading follows `cal set arm` (issue #21 §4): with the
/// default equal links every map point is reachable (radius ≤ √2 < 2); links
/// of 120 and 80 mm (1.2 and 0.8 arm units) cannot reach inside radius 0.4,
/// so the map pixels there turn to the unreachable shade while those
/// farther out keep the reachable one. Drawn by the app in the twin.
#[test]
fn the_reach_shading_follows_the_arms_links() {
    use hal_sim::sim::{Sim, SimSetup};
    let mut setup = SimSetup::default();
    setup.params.screen = true;
    let mut sim = Sim::new(&setup).unwrap();
    sim.run_frames(100);
    // Points off the zone lines (the diagonals and the vertical): radius
    // 0.27 (either side of the vertical) and 0.67.
    let probe = |sim: &Sim, x_p: f32, y_p: f32| {
        let (x, y) = L.ws_point_to_pixel(x_p, y_p).unwrap();
        let zone = condition(x_p, y_p).unwrap().number() as usize - 1;
        let px = sim.display.as_ref().unwrap().pixel(x.into(), y.into()).unwrap();
        (px, zone)
    };
    let points = [(0.1f32, 0.25f32), (0.6, 0.35), (-0.1, 0.25)];
    for (x_p, y_p) in points {
        let (px, zone) = probe(&sim, x_p, y_p);
        assert_eq!(px, theme::ZONE[zone], "equal links, ({x_p}, {y_p})");
    }
    sim.send_line("cal set arm l2 120");
    sim.run_frames(5);
    sim.send_line("cal set arm l3 80");
    sim.run_frames(50);
    for (x_p, y_p) in points {
        let (px, zone) = probe(&sim, x_p, y_p);
        let r = x_p.hypot(y_p);
        let want = if r < 0.4 { theme::ZONE_OUT[zone] } else { theme::ZONE[zone] };
        assert_eq!(px, want, "links 120/80, ({x_p}, {y_p}) at radius {r}");
    }
}
