//! The electrical panel model the simavr tests rely on: each measurement the
//! firmware makes (SPEC §8) reads the value circuit theory predicts.

use hal_sim::panel::{terminal_fraction, Contact, Drive, Sheets, Terminal};

const SHEETS: Sheets = Sheets { r_x: 400.0, r_y: 600.0 };

fn touch(u: f64, v: f64, r: f64) -> Contact {
    Contact { u, v, r_touch: r }
}

#[test]
fn x_read_is_the_x_fraction_on_the_floating_y_sheet() {
    use Drive::*;
    let c = touch(0.3, 0.8, 500.0);
    // XP high, XM low, YP/YM floating; read YP (SPEC §8).
    let f = terminal_fraction(&SHEETS, Some(&c), [High, Low, Float, Float], Terminal::Yp).unwrap();
    assert!((f - 0.3).abs() < 1e-15);
    // Any contact resistance: no current flows into the floating sheet.
    let f2 = terminal_fraction(&SHEETS, Some(&touch(0.3, 0.8, 5000.0)), [High, Low, Float, Float], Terminal::Ym).unwrap();
    assert!((f2 - 0.3).abs() < 1e-15);
}

#[test]
fn y_read_is_the_y_fraction_on_the_floating_x_sheet() {
    use Drive::*;
    let c = touch(0.3, 0.8, 500.0);
    let f = terminal_fraction(&SHEETS, Some(&c), [Float, Float, High, Low], Terminal::Xm).unwrap();
    assert!((f - 0.8).abs() < 1e-15);
}

#[test]
fn pressure_reads_follow_the_series_circuit() {
    use Drive::*;
    let (u, v, rt) = (0.25, 0.6, 300.0);
    let c = touch(u, v, rt);
    // XP low, YM high: current YM → Y sheet (r_y·v) → contact → X sheet (r_x·(1−u)) → XP.
    let drive = [Low, Float, Float, High];
    let z1 = terminal_fraction(&SHEETS, Some(&c), drive, Terminal::Xm).unwrap();
    let z2 = terminal_fraction(&SHEETS, Some(&c), drive, Terminal::Yp).unwrap();
    let (rx, ry) = (400.0 * (1.0 - u), 600.0 * v);
    let total = rx + rt + ry;
    assert!((z1 - rx / total).abs() < 1e-15);
    assert!((z2 - (rx + rt) / total).abs() < 1e-15);
    // The firmware's measure 1023 + z1 − z2 = 1023·(1 − r_t/total): harder press, larger.
    let p = |rt: f64| {
        let c = touch(u, v, rt);
        1023.0 * (1.0 + terminal_fraction(&SHEETS, Some(&c), drive, Terminal::Xm).unwrap()
            - terminal_fraction(&SHEETS, Some(&c), drive, Terminal::Yp).unwrap())
    };
    assert!((p(rt) - 1023.0 * (1.0 - rt / total)).abs() < 1e-9);
    assert!(p(100.0) > p(300.0) && p(300.0) > p(3000.0));
}

#[test]
fn untouched_panel_reads_rails_or_nothing() {
    use Drive::*;
    // Nothing connects the sheets: a floating terminal has no defined voltage.
    assert_eq!(terminal_fraction(&SHEETS, None, [High, Low, Float, Float], Terminal::Yp), None);
    // A sheet driven at one end sits at that level: the pressure reads of an
    // untouched panel give z1 = 0, z2 = full scale, so 1023 + z1 − z2 = 0.
    assert_eq!(terminal_fraction(&SHEETS, None, [Low, Float, Float, High], Terminal::Xm), Some(0.0));
    assert_eq!(terminal_fraction(&SHEETS, None, [Low, Float, Float, High], Terminal::Yp), Some(1.0));
    // Driven terminals read their own level.
    assert_eq!(terminal_fraction(&SHEETS, None, [High, Low, Float, Float], Terminal::Xp), Some(1.0));
    assert_eq!(terminal_fraction(&SHEETS, None, [Low, Float, Float, High], Terminal::Xp), Some(0.0));
}
