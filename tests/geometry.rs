//! Touch mapping, workspace conditions/transforms and arm kinematics (method.md §3–6).

use core::f64::consts::{FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, PI};

use proptest::prelude::*;
use touch_arm::geometry::ik::{fk2, fk3, ik2, ik3, Branch, IkError, Links, LinksError};
use touch_arm::geometry::workspace::{
    alpha, alpha_deg, condition, ik_target, Condition, WorkspaceError, WorkspacePoint,
};
use touch_arm::touch::map::{Axis, Calibration, CalibrationError, Crosshair, MappedPoint, RawPoint, SwapMode, ADC_MAX};

const D: Calibration = Calibration::DEFAULT;

fn cfg() -> ProptestConfig {
    ProptestConfig::with_cases(256)
}

fn map64(cal: &Calibration, x: u16, y: u16) -> MappedPoint<f64> {
    cal.map::<f64>(x, y).expect("valid calibration")
}

// ---------------------------------------------------------------- touch map

#[test]
fn default_calibration_hits_spec_endpoints_exactly() {
    assert_eq!(D.validate(), Ok(()));
    let lo = map64(&D, 123, 128);
    assert_eq!((lo.x_p, lo.y_p, lo.clamped), (-1.0, 0.0, false));
    let hi = map64(&D, 932, 897);
    assert_eq!((hi.x_p, hi.y_p, hi.clamped), (1.0, 1.0, false));
    let lo32 = D.map::<f32>(123, 128).unwrap();
    assert_eq!((lo32.x_p, lo32.y_p), (-1.0, 0.0));
    let hi32 = D.map::<f32>(932, 897).unwrap();
    assert_eq!((hi32.x_p, hi32.y_p), (1.0, 1.0));
    // 527.5 is the midpoint: its neighbours are symmetric.
    let a = map64(&D, 527, 512).x_p;
    let b = map64(&D, 528, 513).x_p;
    assert_eq!(a, -b);
    assert_eq!(b, 1.0 / 809.0);
    assert_eq!(D.unmap_exact(0.0f64, 0.5).unwrap(), (527.5, 512.5));
    assert_eq!(D.unmap_exact(0.0f32, 0.5).unwrap(), (527.5, 512.5));
}

#[test]
fn default_mapping_equals_spec_formula_bit_for_bit() {
    // (raw − 527.5)/404.5 and (raw − 128)/769 have the same exact value as the
    // integer form used; both round once, so they must agree to the bit.
    for raw in 123u16..=932 {
        let p = map64(&D, raw, 500);
        assert_eq!(p.x_p, (raw as f64 - 527.5) / 404.5, "raw x {raw}");
        let p32 = D.map::<f32>(raw, 500).unwrap();
        assert_eq!(p32.x_p, (raw as f32 - 527.5) / 404.5, "raw x {raw} f32");
    }
    for raw in 128u16..=897 {
        let p = map64(&D, 500, raw);
        assert_eq!(p.y_p, (raw as f64 - 128.0) / 769.0, "raw y {raw}");
        let p32 = D.map::<f32>(500, raw).unwrap();
        assert_eq!(p32.y_p, (raw as f32 - 128.0) / 769.0, "raw y {raw} f32");
        assert!(!p.clamped);
    }
}

#[test]
fn out_of_range_raw_gives_clamped_point_and_flag() {
    for (rx, ry, x, y) in [
        (0u16, 500u16, -1.0, (500.0 - 128.0) / 769.0),
        (122, 500, -1.0, (500.0 - 128.0) / 769.0),
        (933, 500, 1.0, (500.0 - 128.0) / 769.0),
        (1023, 500, 1.0, (500.0 - 128.0) / 769.0),
        (u16::MAX, 500, 1.0, (500.0 - 128.0) / 769.0),
        (500, 127, (500.0 - 527.5) / 404.5, 0.0),
        (500, 0, (500.0 - 527.5) / 404.5, 0.0),
        (500, 898, (500.0 - 527.5) / 404.5, 1.0),
        (0, 1023, -1.0, 1.0),
    ] {
        let p = map64(&D, rx, ry);
        assert_eq!((p.x_p, p.y_p, p.clamped), (x, y, true), "raw ({rx}, {ry})");
    }
    assert!(!map64(&D, 123, 897).clamped);
    assert!(!map64(&D, 932, 128).clamped);
}

#[test]
fn swap_exchanges_panel_channels_before_mapping() {
    let plain = Calibration { x_min: 100, x_max: 900, y_min: 200, y_max: 800, ..D };
    let swapped = Calibration { swap_xy: true, ..plain };
    for (a, b) in [(100u16, 200u16), (900, 800), (300, 700), (50, 1000), (640, 333)] {
        assert_eq!(map64(&swapped, a, b), map64(&plain, b, a));
    }
    // Panel channel raw_y = 100 is the left edge of the swapped panel.
    let p = map64(&swapped, 200, 100);
    assert_eq!((p.x_p, p.y_p), (-1.0, 0.0));
}

#[test]
fn inversion_flips_axes() {
    let inv = Calibration { invert_x: true, invert_y: true, ..D };
    // Ends swap roles exactly.
    let p = map64(&inv, 123, 128);
    assert_eq!((p.x_p, p.y_p), (1.0, 1.0));
    let p = map64(&inv, 932, 897);
    assert_eq!((p.x_p, p.y_p), (-1.0, 0.0));
    for (rx, ry) in [(200u16, 300u16), (527, 512), (800, 890), (123, 600)] {
        let n = map64(&D, rx, ry);
        let i = map64(&inv, rx, ry);
        assert_eq!(i.x_p, -n.x_p);
        assert!((i.y_p - (1.0 - n.y_p)).abs() <= 1e-15, "{rx},{ry}");
        // y inversion is computed from the top edge, so it is exact.
        assert_eq!(i.y_p, (897.0 - ry as f64) / 769.0);
    }
}

#[test]
fn invalid_calibrations_are_rejected() {
    let c = Calibration { x_min: 500, x_max: 500, ..D };
    assert_eq!(c.validate(), Err(CalibrationError::EmptyRange { axis: Axis::X }));
    let c = Calibration { x_min: 600, x_max: 500, ..D };
    assert_eq!(c.validate(), Err(CalibrationError::EmptyRange { axis: Axis::X }));
    let c = Calibration { y_min: 900, y_max: 128, ..D };
    assert_eq!(c.validate(), Err(CalibrationError::EmptyRange { axis: Axis::Y }));
    let c = Calibration { y_max: 1024, ..D };
    assert_eq!(c.validate(), Err(CalibrationError::AboveAdcRange { axis: Axis::Y }));
    let c = Calibration { x_min: 2000, x_max: 3000, ..D };
    assert_eq!(c.validate(), Err(CalibrationError::AboveAdcRange { axis: Axis::X }));
    assert_eq!(c.map::<f32>(500, 500), Err(CalibrationError::AboveAdcRange { axis: Axis::X }));
    assert!(c.unmap(0.0f32, 0.5).is_err());
    let ok = Calibration { x_min: 0, x_max: ADC_MAX, y_min: 0, y_max: ADC_MAX, ..D };
    assert_eq!(ok.validate(), Ok(()));
}

#[test]
fn unmap_rejects_points_outside_the_workspace() {
    for (x, y) in [(1.0000001, 0.5), (-1.5, 0.5), (0.0, -1e-9), (0.0, 1.0000001), (f64::NAN, 0.5), (0.0, f64::INFINITY)]
    {
        assert_eq!(D.unmap(x, y), Err(CalibrationError::PointOutOfRange), "({x}, {y})");
    }
    assert_eq!(D.unmap(-1.0f64, 0.0), Ok(RawPoint { x: 123, y: 128 }));
    assert_eq!(D.unmap(1.0f64, 1.0), Ok(RawPoint { x: 932, y: 897 }));
    // 527.5 rounds half up.
    assert_eq!(D.unmap(0.0f64, 0.5), Ok(RawPoint { x: 528, y: 513 }));
}

prop_compose! {
    fn any_calibration()(x_min in 0u16..=1000, y_min in 0u16..=1000, flags in 0u8..8)
        (x_max in (x_min + 1)..=ADC_MAX, y_max in (y_min + 1)..=ADC_MAX,
         x_min in Just(x_min), y_min in Just(y_min), flags in Just(flags)) -> Calibration {
        Calibration {
            x_min, x_max, y_min, y_max,
            swap_xy: flags & 1 != 0, invert_x: flags & 2 != 0, invert_y: flags & 4 != 0,
        }
    }
}

proptest! {
    #![proptest_config(cfg())]

    #[test]
    fn raw_round_trips_through_map_and_unmap(cal in any_calibration(), u in 0.0f64..=1.0, v in 0.0f64..=1.0) {
        // A raw reading inside the span, in panel channel order.
        let sx = cal.x_min + ((cal.x_max - cal.x_min) as f64 * u).round() as u16;
        let sy = cal.y_min + ((cal.y_max - cal.y_min) as f64 * v).round() as u16;
        let (rx, ry) = if cal.swap_xy { (sy, sx) } else { (sx, sy) };
        let p = map64(&cal, rx, ry);
        prop_assert!(!p.clamped);
        prop_assert!((-1.0..=1.0).contains(&p.x_p) && (0.0..=1.0).contains(&p.y_p));
        prop_assert_eq!(cal.unmap(p.x_p, p.y_p), Ok(RawPoint { x: rx, y: ry }));
        let p32 = cal.map::<f32>(rx, ry).unwrap();
        prop_assert_eq!(cal.unmap(p32.x_p, p32.y_p), Ok(RawPoint { x: rx, y: ry }));
    }

    #[test]
    fn point_round_trips_within_half_a_raw_step(cal in any_calibration(), x in -1.0f64..=1.0, y in 0.0f64..=1.0) {
        let (ex, ey) = cal.unmap_exact(x, y).unwrap();
        let raw = cal.unmap(x, y).unwrap();
        prop_assert!((raw.x as f64 - ex).abs() <= 0.5 && (raw.y as f64 - ey).abs() <= 0.5);
        let p = map64(&cal, raw.x, raw.y);
        prop_assert!(!p.clamped);
        // One raw count is 2/(x span) in x and 1/(y span) in y.
        let hx = 1.0 / (cal.x_max - cal.x_min) as f64;
        let hy = 0.5 / (cal.y_max - cal.y_min) as f64;
        prop_assert!((p.x_p - x).abs() <= hx * (1.0 + 1e-9), "x {} -> {}", x, p.x_p);
        prop_assert!((p.y_p - y).abs() <= hy * (1.0 + 1e-9), "y {} -> {}", y, p.y_p);
    }
}

// ------------------------------------------------------------ crosshair fit

fn crosshairs(cal: &Calibration, at: &[(f64, f64)], noise: &[(i32, i32)]) -> Vec<Crosshair<f64>> {
    at.iter()
        .zip(noise.iter().chain(core::iter::repeat(&(0, 0))))
        .map(|(&(x, y), &(nx, ny))| {
            // Ideal (unrounded) reading, then noise, then the ADC's rounding.
            let (rx, ry) = unmap_any(cal, x, y);
            Crosshair { x_p: x, y_p: y, raw_x: (rx + nx as f64).round() as u16, raw_y: (ry + ny as f64).round() as u16 }
        })
        .collect()
}

/// The calibration's affine model, also outside the workspace.
fn unmap_any(cal: &Calibration, x: f64, y: f64) -> (f64, f64) {
    let x = if cal.invert_x { -x } else { x };
    let y = if cal.invert_y { 1.0 - y } else { y };
    let sx = (cal.x_min + cal.x_max) as f64 / 2.0 + x * (cal.x_max - cal.x_min) as f64 / 2.0;
    let sy = cal.y_min as f64 + y * (cal.y_max - cal.y_min) as f64;
    if cal.swap_xy {
        (sy, sx)
    } else {
        (sx, sy)
    }
}

const CORNERS: [(f64, f64); 4] = [(-1.0, 0.0), (1.0, 0.0), (1.0, 1.0), (-1.0, 1.0)];
const INSET: [(f64, f64); 5] = [(-0.8, 0.1), (0.8, 0.1), (0.8, 0.9), (-0.8, 0.9), (0.0, 0.5)];

prop_compose! {
    /// Spans large enough that the inset crosshairs plus noise stay inside the ADC.
    fn panel_calibration()(x_min in 20u16..=300, x_max in 600u16..=1000,
                           y_min in 20u16..=300, y_max in 600u16..=1000, flags in 0u8..8) -> Calibration {
        Calibration {
            x_min, x_max, y_min, y_max,
            swap_xy: flags & 1 != 0, invert_x: flags & 2 != 0, invert_y: flags & 4 != 0,
        }
    }
}

proptest! {
    #![proptest_config(cfg())]

    #[test]
    fn exact_corner_readings_recover_the_calibration(cal in panel_calibration()) {
        let pts = crosshairs(&cal, &CORNERS, &[]);
        prop_assert_eq!(Calibration::from_crosshairs(&pts, SwapMode::Detect), Ok(cal));
        let pts32: Vec<Crosshair<f32>> = pts.iter().map(|p| Crosshair {
            x_p: p.x_p as f32, y_p: p.y_p as f32, raw_x: p.raw_x, raw_y: p.raw_y }).collect();
        prop_assert_eq!(Calibration::from_crosshairs(&pts32, SwapMode::Detect), Ok(cal));
    }

    #[test]
    fn noisy_inset_readings_recover_the_calibration(
        cal in panel_calibration(),
        noise in proptest::collection::vec((-2i32..=2, -2i32..=2), 5),
    ) {
        let pts = crosshairs(&cal, &INSET, &noise);
        // Reading error ≤ 2.5 counts; mean error ≤ 2.5 plus slope error ×
        // extrapolation ≤ 3.2 bounds the fitted ends within 6 counts (after rounding).
        for fit in [
            Calibration::from_crosshairs(&pts, SwapMode::Detect).unwrap(),
            Calibration::from_crosshairs(&pts, SwapMode::Known(cal.swap_xy)).unwrap(),
        ] {
            prop_assert_eq!((fit.swap_xy, fit.invert_x, fit.invert_y),
                            (cal.swap_xy, cal.invert_x, cal.invert_y));
            for (got, want) in [(fit.x_min, cal.x_min), (fit.x_max, cal.x_max),
                                (fit.y_min, cal.y_min), (fit.y_max, cal.y_max)] {
                prop_assert!((got as i32 - want as i32).abs() <= 6, "{:?} vs {:?}", fit, cal);
            }
        }
    }

    #[test]
    fn two_diagonal_crosshairs_suffice_with_known_swap(cal in panel_calibration()) {
        let at = [(-1.0, 0.0), (1.0, 1.0)];
        let pts = crosshairs(&cal, &at, &[]);
        prop_assert_eq!(Calibration::from_crosshairs(&pts, SwapMode::Known(cal.swap_xy)), Ok(cal));
        // Detection needs a third, off-line crosshair.
        prop_assert_eq!(Calibration::from_crosshairs(&pts, SwapMode::Detect),
                        Err(CalibrationError::TooFewPoints));
        let at3 = [(-1.0, 0.0), (1.0, 1.0), (1.0, 0.0)];
        let pts = crosshairs(&cal, &at3, &[]);
        prop_assert_eq!(Calibration::from_crosshairs(&pts, SwapMode::Detect), Ok(cal));
    }
}

#[test]
fn crosshair_fit_rejects_degenerate_readings() {
    use CalibrationError::*;
    let cal = D;
    let fit = |at: &[(f64, f64)], mode| Calibration::from_crosshairs(&crosshairs(&cal, at, &[]), mode);
    assert_eq!(fit(&[], SwapMode::Known(false)), Err(TooFewPoints));
    assert_eq!(fit(&[(0.0, 0.5)], SwapMode::Known(false)), Err(TooFewPoints));
    // Same x everywhere: x cannot be fitted.
    assert_eq!(fit(&[(0.5, 0.0), (0.5, 1.0)], SwapMode::Known(false)), Err(DegeneratePositions));
    // Same point twice.
    assert_eq!(fit(&[(0.5, 0.5), (0.5, 0.5)], SwapMode::Known(false)), Err(DegeneratePositions));
    // Three crosshairs on one diagonal cannot tell the channels apart.
    assert_eq!(fit(&[(-1.0, 0.0), (0.0, 0.5), (1.0, 1.0)], SwapMode::Detect), Err(DegeneratePositions));
    // Non-finite position.
    let mut pts = crosshairs(&cal, &CORNERS, &[]);
    pts[2].x_p = f64::NAN;
    assert_eq!(Calibration::from_crosshairs(&pts, SwapMode::Detect), Err(DegeneratePositions));
    // Reading beyond the ADC.
    let mut pts = crosshairs(&cal, &CORNERS, &[]);
    pts[1].raw_y = 1024;
    assert_eq!(Calibration::from_crosshairs(&pts, SwapMode::Detect), Err(RawReadingOutOfRange));
    // A panel rotated by 45°: each channel follows x and y equally.
    let rotated: Vec<Crosshair<f64>> = CORNERS
        .iter()
        .map(|&(x, y)| Crosshair {
            x_p: x,
            y_p: y,
            raw_x: (500.0 + 200.0 * (x + 2.0 * y - 1.0)) as u16,
            raw_y: (500.0 + 200.0 * (x - 2.0 * y + 1.0)) as u16,
        })
        .collect();
    assert_eq!(Calibration::from_crosshairs(&rotated, SwapMode::Detect), Err(AmbiguousAxes));
    // A dead channel.
    let mut dead = crosshairs(&cal, &CORNERS, &[]);
    for p in &mut dead {
        p.raw_y = 400;
    }
    assert_eq!(Calibration::from_crosshairs(&dead, SwapMode::Detect), Err(AmbiguousAxes));
    assert_eq!(Calibration::from_crosshairs(&dead, SwapMode::Known(false)), Err(EmptyRange { axis: Axis::Y }));
    // Readings that extrapolate past the ADC at the screen edges.
    let steep: Vec<Crosshair<f64>> = [(-0.1, 0.4), (0.1, 0.4), (0.1, 0.6), (-0.1, 0.6)]
        .iter()
        .map(|&(x, y)| Crosshair {
            x_p: x,
            y_p: y,
            raw_x: (512.0 + 3000.0 * x) as u16,
            raw_y: (300.0 + 500.0 * y) as u16,
        })
        .collect();
    assert_eq!(Calibration::from_crosshairs(&steep, SwapMode::Detect), Err(FitOutOfAdcRange { axis: Axis::X }));
}

// ---------------------------------------------------------------- workspace

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn alpha_at_known_points() {
    for (x, y, rad) in [
        (1.0, 0.0, 0.0),
        (0.5, 0.0, 0.0),
        (0.0, 0.0, 0.0),
        (-0.0, 0.0, 0.0),
        (0.0, -0.0, 0.0),
        (-0.5, -0.0, PI),
        (-1.0, 0.0, PI),
        (0.5, 0.5, FRAC_PI_4),
        (0.0, 1.0, FRAC_PI_2),
        (-0.0, 0.3, FRAC_PI_2),
        (-1.0, 1.0, 3.0 * FRAC_PI_4),
    ] {
        let a = alpha(x, y).unwrap();
        assert_eq!(a, rad, "alpha({x}, {y})");
        let d = alpha_deg(x, y).unwrap();
        assert!(close(d, rad.to_degrees(), 1e-12), "alpha_deg({x}, {y}) = {d}");
    }
    // Printed eq. 1 gives atan(0.5/−0.25) = −63.43°; the right value is 180° − 63.43°.
    assert!(close(alpha_deg(-0.25, 0.5).unwrap(), 116.56505117707799, 1e-12));
    assert!(close(alpha_deg(-0.25f32, 0.5).unwrap() as f64, 116.56505117707799, 1e-5));
    assert!(close(alpha_deg(1.0f32, 1.0).unwrap() as f64, 45.0, 1e-5));
}

proptest! {
    #![proptest_config(cfg())]

    #[test]
    fn alpha_is_atan2_in_0_to_pi(x in -1.0f64..=1.0, y in 0.0f64..=1.0) {
        let a = alpha(x, y).unwrap();
        prop_assert!((0.0..=PI).contains(&a));
        // std's atan2 (the system libm) and the core's (libm crate) may differ by an ulp.
        if y > 0.0 {
            prop_assert!(close(a, y.atan2(x), 1e-15));
        } else {
            prop_assert_eq!(a, if x < 0.0 { PI } else { 0.0 });
        }
        prop_assert!(close(alpha_deg(x, y).unwrap(), a.to_degrees(), 1e-12));
        let a32 = alpha(x as f32, y as f32).unwrap() as f64;
        prop_assert!(close(a32, (y as f32 as f64).atan2(x as f32 as f64), 1e-6));
    }
}

fn cond(x: f64, y: f64) -> u8 {
    condition(x, y).unwrap().number()
}

#[test]
fn condition_boundaries_are_exact() {
    let tiny = f64::from_bits(1); // smallest subnormal
    let h = 0.5f64;
    // Origin and the x axis.
    assert_eq!(cond(0.0, 0.0), 1);
    assert_eq!(cond(-0.0, -0.0), 1);
    assert_eq!(cond(1.0, 0.0), 1);
    assert_eq!(cond(-1.0, 0.0), 4);
    assert_eq!(cond(-tiny, 0.0), 4);
    // 45°: on it → 1; a hair above → 2.
    assert_eq!(cond(h, h), 1);
    assert_eq!(cond(1.0, 1.0), 1);
    assert_eq!(cond(h, h.next_up()), 2);
    assert_eq!(cond(h, h.next_down()), 1);
    assert_eq!(cond(h.next_down(), h), 2);
    assert_eq!(cond(tiny, tiny), 1);
    // 90°: on it → 2; a hair left → 3.
    assert_eq!(cond(0.0, h), 2);
    assert_eq!(cond(-0.0, h), 2);
    assert_eq!(cond(0.0, 1.0), 2);
    assert_eq!(cond(tiny, h), 2);
    assert_eq!(cond(-tiny, h), 3);
    // 135°: on it → 3; a hair below → 4.
    assert_eq!(cond(-h, h), 3);
    assert_eq!(cond(-1.0, 1.0), 3);
    assert_eq!(cond(-h, h.next_up()), 3);
    assert_eq!(cond(-h, h.next_down()), 4);
    assert_eq!(cond(-(h.next_down()), h), 3);
    assert_eq!(cond(-(h.next_up()), h), 4);
    // Same in f32.
    let hf = 0.5f32;
    let c32 = |x: f32, y: f32| condition(x, y).unwrap().number();
    assert_eq!(c32(hf, hf), 1);
    assert_eq!(c32(hf, hf.next_up()), 2);
    assert_eq!(c32(0.0, hf), 2);
    assert_eq!(c32(-f32::from_bits(1), hf), 3);
    assert_eq!(c32(-hf, hf), 3);
    assert_eq!(c32(-hf, hf.next_down()), 4);
    // The perturbed points' α is within an ulp or two of the boundary angle, yet
    // the classification flips: it compares coordinates, not α.
    let a = alpha(h, h.next_up()).unwrap();
    assert!(a > FRAC_PI_4 && a - FRAC_PI_4 < 3e-16);
}

#[test]
fn grid_points_classify_by_angle_and_fill_equal_triangles() {
    // Irrational-ish spacing keeps grid points off the diagonals.
    let (nx, ny) = (401u32, 199u32);
    let mut count = [0u32; 4];
    for i in 0..nx {
        for j in 0..ny {
            let x = -1.0 + 2.0 * (i as f64 + 0.5) / nx as f64;
            let y = (j as f64 + 0.5) / ny as f64;
            let c = cond(x, y);
            let deg = y.atan2(x).to_degrees();
            let by_angle = if deg <= 45.0 {
                1
            } else if deg <= 90.0 {
                2
            } else if deg <= 135.0 {
                3
            } else {
                4
            };
            if (deg - 45.0).abs() > 1e-9 && (deg - 90.0).abs() > 1e-9 && (deg - 135.0).abs() > 1e-9 {
                assert_eq!(c, by_angle, "({x}, {y}) at {deg}°");
            }
            count[usize::from(c - 1)] += 1;
        }
    }
    let quarter = (nx * ny) as f64 / 4.0;
    for (k, &n) in count.iter().enumerate() {
        // Lattice error along a diagonal is O(grid size): ≤ 1 %.
        assert!(((n as f64) - quarter).abs() < 0.01 * quarter, "condition {}: {n} vs {quarter}", k + 1);
    }
}

#[test]
fn condition_numbers_and_mirror() {
    use Condition::*;
    assert_eq!([C1, C2, C3, C4].map(Condition::number), [1, 2, 3, 4]);
    assert_eq!([C1, C2, C3, C4].map(Condition::mirrored), [C4, C3, C2, C1]);
    for c in [C1, C2, C3, C4] {
        assert_eq!(c.mirrored().mirrored(), c);
    }
}

fn on_boundary(x: f64, y: f64) -> bool {
    x == y || x == 0.0 || y == -x
}

proptest! {
    #![proptest_config(cfg())]

    #[test]
    fn transform2_mirrors_point_angle_and_condition(x in -1.0f64..=1.0, y in 0.0f64..=1.0, k in 0.1f64..10.0) {
        let p = WorkspacePoint::new(x, y).unwrap();
        let t = p.transform2(k).unwrap();
        prop_assert_eq!((t.x, t.y), (-(k * x), k * y));
        prop_assert_eq!(t.condition, p.condition().mirrored());
        prop_assert!(close(t.alpha, PI - p.alpha(), 1e-15));
        // The mirrored point's own angle is π − α.
        let m = WorkspacePoint::new(-x, y).unwrap();
        prop_assert!(close(m.alpha(), t.alpha, 1e-15));
        if !on_boundary(x, y) {
            // Off the boundaries the label swap is the geometric mirror: 1↔4, 2↔3.
            prop_assert_eq!(m.condition(), p.condition().mirrored());
            prop_assert_eq!(m.condition().number(), 5 - p.condition().number());
        }
        let t1 = p.transform1(k).unwrap();
        prop_assert_eq!((t1.x, t1.y, t1.alpha, t1.condition), (k * x, k * y, p.alpha(), p.condition()));
    }

    #[test]
    fn ik_target_is_reach_height_and_base_angle(x in -1.0f64..=1.0, y in 0.0f64..=1.0, k in 0.1f64..10.0) {
        let p = WorkspacePoint::new(x, y).unwrap();
        let t = ik_target(x, y, k).unwrap();
        prop_assert_eq!((t.reach, t.height, t.alpha, t.condition), (k * x.abs(), k * y, p.alpha(), p.condition()));
        // Conditions 1–2 go through transform 1, 3–4 through transform 2.
        let via = if p.condition().number() <= 2 { p.transform1(k) } else { p.transform2(k) }.unwrap();
        prop_assert_eq!((via.x.abs(), via.y), (t.reach, t.height));
        prop_assert!(via.x >= 0.0);
    }
}

#[test]
fn boundary_points_are_not_mirror_symmetric() {
    // Lower-number rule: 45° → 1 but its mirror at 135° → 3 (not 4); the 90°
    // line → 2 either way; the origin → 1 either way.
    assert_eq!((cond(0.5, 0.5), cond(-0.5, 0.5)), (1, 3));
    assert_eq!((cond(0.0, 0.5), cond(-0.0, 0.5)), (2, 2));
    assert_eq!((cond(0.0, 0.0), cond(-0.0, 0.0)), (1, 1));
    // Transform 2 still labels by the mirror of the source.
    let t = WorkspacePoint::new(0.5, 0.5).unwrap().transform2(1.0).unwrap();
    assert_eq!(t.condition, Condition::C4);
}

#[test]
fn workspace_errors() {
    use WorkspaceError::*;
    assert_eq!(WorkspacePoint::new(1.0 + 1e-12, 0.5), Err(OutOfWorkspace));
    assert_eq!(WorkspacePoint::new(-1.5, 0.5), Err(OutOfWorkspace));
    assert_eq!(WorkspacePoint::new(0.0, -1e-300), Err(OutOfWorkspace));
    assert_eq!(WorkspacePoint::new(0.0, 1.0 + 1e-12), Err(OutOfWorkspace));
    assert_eq!(WorkspacePoint::new(f64::NAN, 0.5), Err(NotFinite));
    assert_eq!(WorkspacePoint::new(0.0, f32::INFINITY), Err(NotFinite));
    assert_eq!(alpha(2.0, 0.0), Err(OutOfWorkspace));
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(ik_target(0.5, 0.5, k), Err(BadScale), "k = {k}");
        let p = WorkspacePoint::new(0.5, 0.5).unwrap();
        assert_eq!(p.transform1(k), Err(BadScale));
        assert_eq!(p.transform2(k), Err(BadScale));
    }
    assert_eq!(ik_target(0.5, 1.5, 1.0), Err(OutOfWorkspace));
}

/// f32 (the chip) validates, labels and scales exactly as f64 does on the
/// same values: the edges of the workspace, signed zeros, subnormals and
/// non-finite values included.
#[test]
fn workspace_f32_agrees_with_f64() {
    let tiny = f32::from_bits(1);
    let mut vals = vec![0.0f32, -0.0, 1.0, -1.0, tiny, -tiny, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.5, -0.5];
    for v in [1.0f32, -1.0, 0.5, -0.5, 0.0] {
        vals.push(v.next_up());
        vals.push(v.next_down());
    }
    for i in 0..=40 {
        vals.push(-1.0 + i as f32 / 20.0);
    }
    for &x in &vals {
        for &y in &vals {
            let (p32, p64) = (WorkspacePoint::new(x, y), WorkspacePoint::new(x as f64, y as f64));
            match (p32, p64) {
                (Ok(a), Ok(b)) => {
                    assert_eq!((a.x_p() as f64).to_bits(), b.x_p().to_bits(), "({x:e}, {y:e})");
                    assert_eq!((a.y_p() as f64).to_bits(), b.y_p().to_bits(), "({x:e}, {y:e})");
                    assert_eq!(a.condition(), b.condition(), "({x:e}, {y:e})");
                    let (a32, a64) = (a.alpha() as f64, b.alpha());
                    assert!((a32 - a64).abs() <= 1.5 * 2.4e-7 * a64.max(0.5), "({x:e}, {y:e}): {a32} vs {a64}");
                }
                (a, b) => assert_eq!(a.err(), b.err(), "({x:e}, {y:e})"),
            }
        }
    }
    let p = WorkspacePoint::new(-0.25f32, 0.5).unwrap();
    for k in [0.0f32, -0.0, -1.0, -tiny, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(p.target(k), Err(WorkspaceError::BadScale), "k = {k:e}");
    }
    let t = p.target(tiny).unwrap();
    assert_eq!((t.reach, t.height), (tiny * 0.25, tiny * 0.5));
}

// ---------------------------------------------------------------------- IK

fn unit() -> Links<f64> {
    Links::new(1.0, 1.0).unwrap()
}

fn assert_angles(links: &Links<f64>, x: f64, y: f64, branch: Branch, q2: f64, q3: f64) {
    let q = ik2(links, x, y, branch).unwrap();
    assert!(close(q.q2, q2, 1e-14) && close(q.q3, q3, 1e-14), "({x}, {y}) {branch:?}: {q:?} vs ({q2}, {q3})");
}

#[test]
fn ik_known_values_unit_links() {
    let l = unit();
    // (1, 1): c = 0. Plus: upper link along x, forearm up. Minus: up, then right.
    assert_angles(&l, 1.0, 1.0, Branch::Plus, 0.0, FRAC_PI_2);
    assert_angles(&l, 1.0, 1.0, Branch::Minus, FRAC_PI_2, -FRAC_PI_2);
    // (1, 0): c = −1/2, q3 = ±2π/3, q2 = ∓π/3 (equilateral triangle).
    assert_angles(&l, 1.0, 0.0, Branch::Plus, -FRAC_PI_3, 2.0 * FRAC_PI_3);
    assert_angles(&l, 1.0, 0.0, Branch::Minus, FRAC_PI_3, -2.0 * FRAC_PI_3);
    // (0.5, 0.5): c = −3/4, q3 = acos(−3/4), β = atan2(√(7/16), 1/4), q2 = π/4 ∓ β.
    assert_angles(&l, 0.5, 0.5, Branch::Plus, -0.4240310394907405, 2.4188584057763776);
    assert_angles(&l, 0.5, 0.5, Branch::Minus, 1.994827366285637, -2.4188584057763776);
    // Fully stretched: both branches coincide.
    for b in [Branch::Plus, Branch::Minus] {
        assert_angles(&l, 2.0, 0.0, b, 0.0, 0.0);
        assert_angles(&l, 0.0, 2.0, b, FRAC_PI_2, 0.0);
    }
}

#[test]
fn touched_corner_through_the_whole_chain() {
    // Raw (123, 128) is the bottom-left corner: x_p = −1, y_p = 0.
    let p = map64(&D, 123, 128);
    let t = ik_target(p.x_p, p.y_p, 1.0).unwrap();
    assert_eq!((t.reach, t.height, t.alpha, t.condition), (1.0, 0.0, PI, Condition::C4));
    assert!(close(t.alpha_deg(), 180.0, 1e-12));
    assert_angles(&unit(), t.reach, t.height, Branch::Plus, -FRAC_PI_3, 2.0 * FRAC_PI_3);
    // Top centre: raw (527.5 → 528, 897) ≈ (0.0012, 1): nearly straight up at 90°.
    let p = map64(&D, 528, 897);
    let t = ik_target(p.x_p, p.y_p, 1.0).unwrap();
    assert_eq!(t.condition, Condition::C2);
    let q = ik2(&unit(), t.reach, t.height, Branch::Minus).unwrap();
    let (x, y) = fk2(&unit(), q.q2, q.q3);
    assert!(close(x, t.reach, 1e-15) && close(y, 1.0, 1e-15));
}

/// Link lengths (equal ones often: the paper's arm, with the hole closed) and a
/// point of the annulus, its rims and their close neighbourhood included.
fn links_and_reachable_point() -> impl Strategy<Value = (f64, f64, f64, f64)> {
    let l3 = prop_oneof![Just(None), (0.1f64..10.0).prop_map(Some)];
    let u = prop_oneof![Just(0.0), Just(1.0), 0.0f64..1e-4, (1.0 - 1e-4)..=1.0f64, 0.0f64..=1.0, 0.0f64..=1.0,];
    (0.1f64..10.0, l3, u, -PI..=PI).prop_map(|(l2, l3, u, th)| {
        let l3 = l3.unwrap_or(l2);
        let (rmin, rmax) = ((l2 - l3).abs(), l2 + l3);
        // Keep off the shoulder itself (the singular point when l2 = l3).
        let r = (rmin + u * (rmax - rmin)).max(1e-6 * rmax);
        (l2, l3, r * th.cos(), r * th.sin())
    })
}

fn branches() -> [Branch; 2] {
    [Branch::Plus, Branch::Minus]
}

proptest! {
    #![proptest_config(cfg())]

    #[test]
    fn fk_inverts_ik_on_both_branches((l2, l3, x, y) in links_and_reachable_point()) {
        let links = Links::new(l2, l3).unwrap();
        let mut q3s = [0.0; 2];
        for (i, b) in branches().into_iter().enumerate() {
            let q = ik2(&links, x, y, b).unwrap();
            prop_assert!(q.q2 > -PI && q.q2 <= PI);
            match b {
                Branch::Plus => prop_assert!(q.q3 >= 0.0),
                Branch::Minus => prop_assert!(q.q3 <= 0.0),
            }
            q3s[i] = q.q3;
            let (fx, fy) = fk2(&links, q.q2, q.q3);
            let tol = 1e-9 * (l2 + l3);
            prop_assert!(close(fx, x, tol) && close(fy, y, tol),
                "{:?}: ({}, {}) -> {:?} -> ({}, {})", b, x, y, q, fx, fy);
        }
        prop_assert_eq!(q3s[0], -q3s[1]);
    }

    /// f32 (the chip's width): |FK(IK(p)) − p| ≤ 1.5e-6·(l2 + l3), about 12 ulps of
    /// the arm's span (largest seen over 3·10⁵ cases: 8e-7), uniformly over the
    /// annulus including its rims, from rounding in r², atan2, sin and cos.
    #[test]
    fn fk_inverts_ik_in_f32((l2, l3, x, y) in links_and_reachable_point()) {
        let (l2, l3, x, y) = (l2 as f32, l3 as f32, x as f32, y as f32);
        let links = Links::new(l2, l3).unwrap();
        for b in branches() {
            // Rounding x, y to f32 may leave the annulus by a few ulps: within the slack.
            let q = ik2(&links, x, y, b).unwrap();
            let (fx, fy) = fk2(&links, q.q2, q.q3);
            let tol = 1.5e-6 * (l2 + l3);
            prop_assert!((fx - x).abs() <= tol && (fy - y).abs() <= tol,
                "{:?}: ({}, {}) -> ({}, {}), err {:e}", b, x, y, fx, fy, ((fx - x).abs().max((fy - y).abs())) / (l2 + l3));
        }
    }

    #[test]
    fn points_outside_the_annulus_are_unreachable(l2 in 0.1f64..10.0, l3 in 0.1f64..10.0,
                                                  out in 1e-6f64..1.0, th in -PI..=PI, inner in any::<bool>()) {
        let links = Links::new(l2, l3).unwrap();
        let (rmin, rmax) = (links.r_min(), links.r_max());
        let r = if inner { rmin * (1.0 - out) } else { rmax * (1.0 + out) };
        prop_assume!(r > 0.0 && (!inner || rmin > 1e-3));
        for b in branches() {
            match ik2(&links, r * th.cos(), r * th.sin(), b) {
                Err(IkError::Unreachable { c }) => {
                    prop_assert!(c.abs() > 1.0);
                    prop_assert_eq!(c > 1.0, !inner);
                }
                other => prop_assert!(false, "r = {} in [{}, {}]: {:?}", r, rmin, rmax, other),
            }
        }
    }

    #[test]
    fn points_on_the_boundary_circles_are_reachable(l2 in 0.1f64..10.0, l3 in 0.1f64..10.0, th in -PI..=PI) {
        let links = Links::new(l2, l3).unwrap();
        let links32 = Links::new(l2 as f32, l3 as f32).unwrap();
        let mut radii = vec![links.r_max()];
        if links.r_min() > 1e-3 {
            radii.push(links.r_min());
        }
        for r in radii {
            let (x, y) = (r * th.cos(), r * th.sin());
            for b in branches() {
                let q = ik2(&links, x, y, b).unwrap();
                let (fx, fy) = fk2(&links, q.q2, q.q3);
                prop_assert!(close(fx, x, 1e-9 * r.max(1.0)) && close(fy, y, 1e-9 * r.max(1.0)));
                let r32 = r as f32;
                let th32 = th as f32;
                prop_assert!(ik2(&links32, r32 * th32.cos(), r32 * th32.sin(), b).is_ok());
            }
        }
    }

    #[test]
    fn ik3_agrees_with_fk3((l2, l3, rho, z) in links_and_reachable_point(), th1 in -PI..=PI) {
        // (rho, z) is reachable in the arm's plane; keep rho ≥ 0 as ik3 produces.
        let rho = rho.abs();
        prop_assume!(rho > 1e-9);
        let links = Links::new(l2, l3).unwrap();
        let (xe, ye, ze) = (rho * th1.cos(), rho * th1.sin(), z);
        for b in branches() {
            let q = ik3(&links, xe, ye, ze, b).unwrap();
            prop_assert!(close(q.th1, ye.atan2(xe), 1e-15));
            let (fx, fy, fz) = fk3(&links, q.th1, q.th2, q.th3);
            let tol = 1e-9 * (l2 + l3);
            prop_assert!(close(fx, xe, tol) && close(fy, ye, tol) && close(fz, ze, tol));
            // d² = x² + y² + z² = l2² + l3² + 2·l2·l3·cos θ3 (lab note).
            let d2 = xe * xe + ye * ye + ze * ze;
            prop_assert!(close(d2, l2 * l2 + l3 * l3 + 2.0 * l2 * l3 * q.th3.cos(), 1e-9 * (l2 + l3).powi(2)));
        }
    }
}

#[test]
fn ik3_known_values() {
    let l = unit();
    // Above the y axis at (0, 1, 1): base at 90°, planar (1, 1).
    let q = ik3(&l, 0.0, 1.0, 1.0, Branch::Plus).unwrap();
    assert!(close(q.th1, FRAC_PI_2, 1e-15) && close(q.th2, 0.0, 1e-15) && close(q.th3, FRAC_PI_2, 1e-15));
    // Straight above the base: θ1 is free and set to 0.
    let q = ik3(&l, 0.0, -0.0, 1.5, Branch::Minus).unwrap();
    assert_eq!(q.th1, 0.0);
    let (x, y, z) = fk3(&l, q.th1, q.th2, q.th3);
    assert!(close(x, 0.0, 1e-15) && close(y, 0.0, 1e-15) && close(z, 1.5, 1e-15));
    // Behind the base: θ1 = π, planar reach stays positive.
    let q = ik3(&l, -1.0, 0.0, 1.0, Branch::Plus).unwrap();
    assert!(close(q.th1, PI, 1e-15) && close(q.th2, 0.0, 1e-15));
    assert_eq!(ik3(&l, 0.0, 0.0, 0.0, Branch::Plus), Err(IkError::Singular));
    assert!(matches!(ik3(&l, 3.0, 0.0, 0.0, Branch::Plus), Err(IkError::Unreachable { .. })));
    assert!(matches!(ik3(&l, 1e200, 1e200, 0.0, Branch::Plus), Err(IkError::Unreachable { .. })));
    assert_eq!(ik3(&l, f64::NAN, 0.0, 0.0, Branch::Plus), Err(IkError::NotFinite));
}

#[test]
fn ik_errors() {
    let l = unit();
    assert_eq!(ik2(&l, 0.0, 0.0, Branch::Plus), Err(IkError::Singular));
    assert_eq!(ik2(&l, -0.0, 0.0, Branch::Minus), Err(IkError::Singular));
    assert_eq!(ik2(&unit(), f64::NAN, 0.5, Branch::Plus), Err(IkError::NotFinite));
    assert_eq!(ik2(&unit(), 0.5, f64::NEG_INFINITY, Branch::Plus), Err(IkError::NotFinite));
    assert_eq!(ik2(&l, 3.0, 0.0, Branch::Plus), Err(IkError::Unreachable { c: 3.5 }));
    assert!(matches!(ik2(&l, 1e300, 0.0, Branch::Plus), Err(IkError::Unreachable { c }) if c == f64::INFINITY));
    // Unequal links: the shoulder is inside the hole, so unreachable, not singular.
    let l = Links::new(1.0, 0.5).unwrap();
    assert!(matches!(ik2(&l, 0.0, 0.0, Branch::Plus), Err(IkError::Unreachable { c }) if c < -1.0));
    assert!(matches!(ik2(&l, 0.4999, 0.0, Branch::Plus), Err(IkError::Unreachable { c }) if c < -1.0));
    // The inner circle itself is reachable: elbow folded back, q3 = ±π.
    let q = ik2(&l, 0.5, 0.0, Branch::Plus).unwrap();
    assert!(close(q.q3, PI, 1e-7) && close(q.q2, 0.0, 1e-7), "{q:?}");
    let l = Links::new(0.5, 1.0).unwrap();
    let q = ik2(&l, 0.5, 0.0, Branch::Plus).unwrap();
    let (x, y) = fk2(&l, q.q2, q.q3);
    assert!(close(x, 0.5, 1e-12) && close(y, 0.0, 1e-12), "{q:?}");

    assert_eq!(Links::new(0.0, 1.0), Err(LinksError::NotPositive));
    assert_eq!(Links::new(1.0, -2.0), Err(LinksError::NotPositive));
    assert_eq!(Links::new(f64::NAN, 1.0), Err(LinksError::NotFinite));
    assert_eq!(Links::new(1.0, f64::INFINITY), Err(LinksError::NotFinite));
    assert_eq!(Links::new(1e30f32, 1.0), Err(LinksError::NotFinite));
    let l = Links::new(0.3f64, 0.7).unwrap();
    assert_eq!((l.l2(), l.l3(), l.r_max()), (0.3, 0.7, 1.0));
    assert!(close(l.r_min(), 0.4, 1e-16));
}

#[test]
fn ik_f32_accurate_near_the_shoulder() {
    // l2 = l3 and the target close to the shoulder (bottom centre of the screen):
    // the elbow folds almost completely, π − |q3| = 2·asin(r/2).
    let l = Links::new(1.0f32, 1.0).unwrap();
    for (x, y) in [(0.01f32, 0.0f32), (0.001, 0.001), (-0.0003, 0.0002), (1e-5, 0.0)] {
        let r = ((x as f64).powi(2) + (y as f64).powi(2)).sqrt();
        let fold = 2.0 * (r / 2.0).asin();
        for b in branches() {
            let q = ik2(&l, x, y, b).unwrap();
            assert!(close(q.q3.abs() as f64, PI - fold, 5e-7), "({x}, {y}) {b:?}: {q:?}");
            let (fx, fy) = fk2(&l, q.q2, q.q3);
            assert!((fx - x).abs() <= 5e-7 && (fy - y).abs() <= 5e-7, "({x}, {y}) {b:?}: ({fx}, {fy})");
        }
    }
}

// ------------------------------------------------ IK in f32 against f64

/// Links (equal ones often) and a point of the annulus in f32, biased to the
/// hard places: both rims and their close neighbourhood, the shoulder side of
/// the hole (r → 0 with l2 = l3), and the axes (x ≈ 0 or y ≈ 0, either sign).
fn f32_links_and_point() -> impl Strategy<Value = (f32, f32, f32, f32)> {
    let l3 = prop_oneof![Just(None), (0.1f32..10.0).prop_map(Some), (-1e-3f32..1e-3).prop_map(|d| Some(1.0 + d))];
    let u = prop_oneof![
        Just(0.0),
        Just(1.0),
        0.0f64..1e-6,
        0.0f64..1e-3,
        (1.0 - 1e-6)..=1.0f64,
        (1.0 - 1e-3)..=1.0f64,
        0.0f64..=1.0,
    ];
    let th = prop_oneof![
        -PI..=PI,
        Just(0.0),
        Just(FRAC_PI_2),
        Just(PI),
        Just(-FRAC_PI_2),
        (-1e-4f64..1e-4),
        (-1e-4f64..1e-4).prop_map(|d| FRAC_PI_2 + d),
        (-1e-4f64..1e-4).prop_map(|d| PI - d.abs()),
        (-1e-7f64..1e-7).prop_map(|d| -PI + d.abs()),
    ];
    (0.1f32..10.0, l3, u, th).prop_map(|(l2, l3, u, th)| {
        let l3 = l3.map_or(l2, |f| if !(0.5..=2.0).contains(&f) { f } else { l2 * f });
        let (l2d, l3d) = (l2 as f64, l3 as f64);
        let (rmin, rmax) = ((l2d - l3d).abs(), l2d + l3d);
        let r = (rmin + u * (rmax - rmin)).max(1e-5 * rmax);
        (l2, l3, (r * th.cos()) as f32, (r * th.sin()) as f32)
    })
}

/// The f64 IK of (x, y) moved radially by the factor `f`, kept inside the annulus.
fn ik64_radial(links: &Links<f64>, x: f64, y: f64, f: f64, b: Branch) -> (f64, f64) {
    let r = x.hypot(y);
    let to = (r * f).clamp(links.r_min(), links.r_max());
    let q = ik2(links, x * (to / r), y * (to / r), b).unwrap();
    (q.q2, q.q3)
}

/// |a − b| as angles (q2 wraps at ±π).
fn angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(2.0 * PI - d)
}

/// f32 rounding of the target's radius (forming r² and the rim constants
/// from f32 values): a few ε relative.
const RADIAL_F32: f64 = 4.0 * f32::EPSILON as f64;
/// What f32 adds on top: the arctangents φ and β (≤ 1.5 ulp each, of up to
/// π) and the rounding of φ ∓ β (up to 2π) before it is wrapped: at most
/// 3¼ ulps of π (3 seen in 2·10⁵ cases).
const ANGLE_F32: f64 = 4.0 * 2.4e-7;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    /// The chip's f32 IK is the f64 IK of the same point to within what f32
    /// rounding of the radius does to the angles (which near the rims is
    /// much more than an ulp: q3 ∝ √(r_max − r) there) plus a few ulps of π,
    /// and FK brings both angles back to the point.
    #[test]
    fn ik_in_f32_tracks_f64((l2, l3, x, y) in f32_links_and_point()) {
        let links32 = Links::new(l2, l3).unwrap();
        let links = Links::new(l2 as f64, l3 as f64).unwrap();
        let (xd, yd) = (x as f64, y as f64);
        for b in branches() {
            let q = ik2(&links32, x, y, b).unwrap();
            prop_assert!(q.q2 > -core::f32::consts::PI && q.q2 <= core::f32::consts::PI);
            let (q2, q3) = ik64_radial(&links, xd, yd, 1.0, b);
            let (lo2, lo3) = ik64_radial(&links, xd, yd, 1.0 - RADIAL_F32, b);
            let (hi2, hi3) = ik64_radial(&links, xd, yd, 1.0 + RADIAL_F32, b);
            let tol2 = angle_gap(lo2, q2).max(angle_gap(hi2, q2)) + ANGLE_F32;
            let tol3 = (lo3 - q3).abs().max((hi3 - q3).abs()) + ANGLE_F32;
            prop_assert!(angle_gap(q.q2 as f64, q2) <= tol2,
                "{:?} l=({}, {}) p=({:e}, {:e}): q2 {} vs {} (tol {:e})", b, l2, l3, x, y, q.q2, q2, tol2);
            prop_assert!((q.q3 as f64 - q3).abs() <= tol3,
                "{:?} l=({}, {}) p=({:e}, {:e}): q3 {} vs {} (tol {:e})", b, l2, l3, x, y, q.q3, q3, tol3);
            // The position, computed in f64 from the f32 angles.
            let (fx, fy) = fk2(&links, q.q2 as f64, q.q3 as f64);
            let tol = 1.5e-6 * (links.r_max());
            prop_assert!((fx - xd).abs() <= tol && (fy - yd).abs() <= tol,
                "{:?} l=({}, {}) p=({:e}, {:e}): fk ({:e}, {:e})", b, l2, l3, x, y, fx, fy);
        }
    }
}

#[test]
fn ik_f32_known_values_and_errors() {
    let l = Links::new(1.0f32, 1.0).unwrap();
    let q = ik2(&l, 1.0, 1.0, Branch::Minus).unwrap();
    assert!(
        (q.q2 - core::f32::consts::FRAC_PI_2).abs() <= 2.4e-7 && (q.q3 + core::f32::consts::FRAC_PI_2).abs() <= 2.4e-7,
        "{q:?}"
    );
    // Straight out along either axis: both branches agree, q2 on the axis.
    for b in branches() {
        assert_eq!(ik2(&l, 2.0, 0.0, b).unwrap(), touch_arm::geometry::ik::JointAngles2 { q2: 0.0, q3: 0.0 });
        let q = ik2(&l, -2.0, 0.0, b).unwrap();
        assert_eq!((q.q2, q.q3), (core::f32::consts::PI, 0.0), "{b:?}");
        let q = ik2(&l, -2.0, -0.0, b).unwrap();
        assert_eq!((q.q2, q.q3), (core::f32::consts::PI, 0.0), "−0 height, {b:?}");
        let q = ik2(&l, 0.0, -2.0, b).unwrap();
        assert_eq!((q.q2, q.q3), (-core::f32::consts::FRAC_PI_2, 0.0), "{b:?}");
    }
    // Stretched out just below the negative x axis: the direction rounds to
    // −π, which is +π in (−π, π] (β = 0 leaves nothing to wrap it).
    for b in branches() {
        let q = ik2(&l, -2.0, -1e-30, b).unwrap();
        assert_eq!((q.q2, q.q3), (core::f32::consts::PI, 0.0), "{b:?}");
        let q = ik2(&unit(), -2.0, -1e-300, b).unwrap();
        assert_eq!((q.q2, q.q3), (PI, 0.0), "{b:?}");
    }
    // Folded back: q2 stays in (−π, π] on the negative x axis.
    let q = ik2(&l, -1e-3, 0.0, Branch::Minus).unwrap();
    assert!(q.q2 > -core::f32::consts::PI && q.q2 <= core::f32::consts::PI, "{q:?}");
    assert_eq!(ik2(&l, 0.0, 0.0, Branch::Plus), Err(IkError::Singular));
    assert_eq!(ik2(&l, -0.0, -0.0, Branch::Minus), Err(IkError::Singular));
    assert_eq!(ik2(&l, f32::NAN, 0.5, Branch::Plus), Err(IkError::NotFinite));
    assert_eq!(ik2(&l, 0.5, f32::INFINITY, Branch::Plus), Err(IkError::NotFinite));
    assert_eq!(ik2(&l, 3.0, 0.0, Branch::Plus), Err(IkError::Unreachable { c: 3.5 }));
    assert!(matches!(ik2(&l, 1e30, 1e30, Branch::Plus), Err(IkError::Unreachable { c }) if c == f32::INFINITY));
    // Just outside the outer rim (by far more than the rounding slack).
    assert!(matches!(ik2(&l, 2.0 * (1.0 + 1e-5), 0.0, Branch::Minus), Err(IkError::Unreachable { c }) if c > 1.0));
    // Nearly equal links: the origin is within the slack of the (tiny) hole,
    // but still the shoulder itself.
    let l = Links::new(1.0f32, 1.0 + 1e-6).unwrap();
    assert_eq!(ik2(&l, 0.0, 0.0, Branch::Plus), Err(IkError::Singular));
    let l = Links::new(1.0f32, 0.5).unwrap();
    assert!(matches!(ik2(&l, 0.0, 0.0, Branch::Plus), Err(IkError::Unreachable { c }) if c < -1.0));
    assert!(matches!(ik2(&l, 0.0, 0.4999, Branch::Plus), Err(IkError::Unreachable { c }) if c < -1.0));
    let q = ik2(&l, 0.0, 0.5, Branch::Minus).unwrap();
    assert!(
        (q.q3 + core::f32::consts::PI).abs() <= 2.4e-7 && (q.q2 - core::f32::consts::FRAC_PI_2).abs() <= 2.4e-7,
        "{q:?}"
    );
}

// ------------------------------------ f32 bit tests the geometry relies on

/// Sign, zero and order tests and the doubling that the geometry runs on the
/// bits of an f32 (a float comparison is a library call on the AVR) agree
/// with the float operations, on special values and random bit patterns.
#[test]
fn f32_bit_tests_agree_with_float_operations() {
    use touch_arm::math::real::Real;
    let mut vals = vec![
        0.0f32,
        -0.0,
        1.0,
        -1.0,
        f32::MIN_POSITIVE,
        -f32::MIN_POSITIVE,
        1e-45,
        -1e-45,
        f32::MAX,
        -f32::MAX,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -f32::NAN,
        core::f32::consts::PI,
        -core::f32::consts::PI,
        1.0 + f32::EPSILON,
        1.0 - f32::EPSILON / 2.0,
        3.4e38,
        1.7e38,
        8.5e37,
    ];
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    for _ in 0..20_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        vals.push(f32::from_bits(state as u32));
    }
    for &a in &vals {
        assert_eq!(a.is_zero(), a == 0.0, "{a:e}");
        assert_eq!(a.is_negative(), a < 0.0, "{a:e}");
        assert_eq!(a.barrier().to_bits(), a.to_bits());
        let t = a.twice();
        assert!(t.to_bits() == (a + a).to_bits() || (a.is_nan() && t.is_nan()), "{a:e}: {t:e}");
        if a.is_nan() {
            continue;
        }
        for &b in vals.iter().take(40) {
            if !b.is_nan() {
                assert_eq!(a.le_num(b), a <= b, "{a:e} <= {b:e}");
                assert_eq!(b.le_num(a), b <= a, "{b:e} <= {a:e}");
            }
        }
    }
}

// ------------------------------------------------- the arm's lengths (#21 §4)

proptest! {
    #![proptest_config(cfg())]
    /// `cal set arm`'s lengths in the map's arm unit (their mean): the sum
    /// is 2, the ratio kept, and a pose depends on the ratio only, so the
    /// same arm in other units gives the same angles; the FK of the solved
    /// pose in those links lands on the transformed point.
    #[test]
    fn arm_lengths_enter_as_their_ratio(l2 in 10.0f64..650.0, l3 in 10.0f64..650.0, scale in 0.01f64..100.0,
                                        x_p in -1.0f64..1.0, y_p in 0.0f64..1.0) {
        use touch_arm::geometry::pose::{pose_for_point, ArmGeometry};
        let g = ArmGeometry::from_lengths(1.0, l2, l3, Branch::Minus).unwrap();
        let (a, b) = (g.links.l2(), g.links.l3());
        prop_assert!(close(a + b, 2.0, 1e-15) && close(a / b, l2 / l3, 1e-13), "{a} {b}");
        let s = ArmGeometry::from_lengths(1.0, l2 * scale, l3 * scale, Branch::Minus).unwrap();
        prop_assert!(close(s.links.l2(), a, 1e-14) && close(s.links.l3(), b, 1e-14));
        if let (Ok(p), Ok(q)) = (pose_for_point(&g, x_p, y_p), pose_for_point(&s, x_p, y_p)) {
            prop_assert!(close(p.q2, q.q2, 1e-9) && close(p.q3, q.q3, 1e-9), "{p:?} {q:?}");
            let (x, y) = fk2(&g.links, p.q2, p.q3);
            prop_assert!(close(x, x_p.abs(), 1e-9) && close(y, y_p, 1e-9), "({x}, {y}) for ({x_p}, {y_p})");
        }
    }
}

#[test]
fn arm_lengths_are_checked_as_given() {
    use touch_arm::geometry::pose::ArmGeometry;
    let g = |l2: f64, l3: f64| ArmGeometry::from_lengths(1.0, l2, l3, Branch::Minus).map(|g| g.links);
    assert_eq!(g(-1.0, -1.0), Err(LinksError::NotPositive), "two negative lengths have a positive ratio");
    assert_eq!(g(0.0, 0.0), Err(LinksError::NotPositive));
    assert_eq!(g(f64::NAN, 1.0), Err(LinksError::NotFinite));
    assert_eq!(g(1.0, f64::INFINITY), Err(LinksError::NotFinite));
    // The paper's equal links, whatever their length.
    let l = g(250.0, 250.0).unwrap();
    assert_eq!((l.l2(), l.l3()), (1.0, 1.0));
    let l = g(120.0, 80.0).unwrap();
    assert!(close(l.l2(), 1.2, 1e-15) && close(l.l3(), 0.8, 1e-15) && close(l.r_min(), 0.4, 1e-15));
}
