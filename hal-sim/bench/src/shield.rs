//! The simulated shield a run asks for, by the names the command lines take:
//! the display controller (`--lcd`) and the touch panel's wiring
//! (`--wiring`), shared by the main job and the live bench so both accept the
//! same words and set the firmware up the same way.

use touch_arm::touch::map::Calibration;
use touch_arm_rig::lcd_bus::Chip;
use touch_arm_rig::panel::PanelWiring;

/// `--lcd`: a supported controller by name.
pub fn lcd_chip(s: &str) -> Result<Chip, String> {
    Chip::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Chip::SUPPORTED.iter().map(|c| c.name()).collect();
        format!("unknown controller {s:?} ({})", names.join(", "))
    })
}

/// The wirings `--wiring` names, by their letters.
const WIRINGS: [(&str, PanelWiring); 3] = [("a", PanelWiring::A), ("b", PanelWiring::B), ("c", PanelWiring::C)];

/// `--wiring`: a preset of the pin map by its letter.
pub fn panel_wiring(s: &str) -> Result<PanelWiring, String> {
    WIRINGS.iter().find(|(n, _)| *n == s).map(|(_, w)| *w).ok_or_else(|| format!("unknown wiring {s:?} (a, b or c)"))
}

/// A wiring's `--wiring` letter (`?` for a pin map that is none of the
/// presets).
pub fn wiring_name(w: PanelWiring) -> &'static str {
    WIRINGS.iter().find(|(_, p)| *p == w).map_or("?", |(n, _)| n)
}

/// The touch calibration the firmware runs with on `wiring`: the default,
/// or on wiring c what its calibration screen would find. Wiring c is b's
/// two pins mirrored: a c reading (x, y) arrives as (1023 − y, 1023 − x), so
/// the axes swap, both run backwards, and each span is the default one
/// mirrored.
pub fn touch_calibration(wiring: PanelWiring) -> Calibration {
    let d = Calibration::DEFAULT;
    if wiring != PanelWiring::C {
        return d;
    }
    let m = |v: u16| 1023 - v;
    Calibration {
        x_min: m(d.x_max),
        x_max: m(d.x_min),
        y_min: m(d.y_max),
        y_max: m(d.y_min),
        swap_xy: true,
        invert_x: true,
        invert_y: true,
    }
}

/// The `cal set touch …` lines that give the firmware
/// [`touch_calibration`]'s values (none when they are its defaults).
pub fn calibration_lines(wiring: PanelWiring) -> Vec<String> {
    if wiring != PanelWiring::C {
        return Vec::new();
    }
    let c = touch_calibration(wiring);
    [
        ("x_min", c.x_min),
        ("x_max", c.x_max),
        ("y_min", c.y_min),
        ("y_max", c.y_max),
        ("swap", u16::from(c.swap_xy)),
        ("invert_x", u16::from(c.invert_x)),
        ("invert_y", u16::from(c.invert_y)),
    ]
    .iter()
    .map(|(f, v)| format!("cal set touch {f} {v}"))
    .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_the_mirrored_calibration() {
        assert_eq!(lcd_chip("ili9486"), Ok(Chip::Ili9486));
        assert!(lcd_chip("ssd1306").unwrap_err().contains("ili9341"));
        assert_eq!(panel_wiring("c"), Ok(PanelWiring::C));
        assert_eq!(["a", "b", "c"].map(|n| wiring_name(panel_wiring(n).unwrap())), ["a", "b", "c"]);
        assert!(panel_wiring("d").is_err());
        assert!(calibration_lines(PanelWiring::A).is_empty() && calibration_lines(PanelWiring::B).is_empty());
        // A c reading (x, y) arrives as (1023 − y, 1023 − x): through the
        // mirrored calibration it lands where (x, y) lands through the default.
        let (d, c) = (Calibration::DEFAULT, touch_calibration(PanelWiring::C));
        for (x, y) in [(200u16, 300u16), (512, 512), (850, 190)] {
            let a = d.map::<f32>(x, y).unwrap();
            let b = c.map::<f32>(1023 - y, 1023 - x).unwrap();
            assert!((a.x_p - b.x_p).abs() < 1e-5 && (a.y_p - b.y_p).abs() < 1e-5, "({x}, {y}): {a:?} vs {b:?}");
        }
        assert_eq!(calibration_lines(PanelWiring::C).len(), 7);
    }
}
