//! Issue #24, F5: `ServoMap::angle_to_pulse` judges a clamp by how far the
//! pulse moves in total from the unclamped pulse, the angle clamp and the
//! pulse clamp together, so two allowances of less than 0.5 µs each cannot
//! add up to a pose held a whole microsecond outside its window.

use touch_arm::servo::map::{JointCal, Limit, ServoMap};

fn rad(deg: f64) -> f32 {
    deg.to_radians() as f32
}

/// The base's default slope (10 µs per degree) with 0° at 599.8 µs: 90° is
/// 1499.8 µs, 89.96° is 1499.4 µs.
fn cal(max_deg: f64, max_us: u16) -> ServoMap {
    let c = JointCal { offset_us: 599.8, max_rad: rad(max_deg), max_us, ..JointCal::BASE_DEFAULT };
    ServoMap::new(&c).expect("valid calibration")
}

#[test]
fn an_angle_clamp_and_a_pulse_clamp_are_judged_together() {
    // The angle clamp alone: 90° → 89.96°, 0.4 µs: no clamp reported.
    let p = cal(89.96, 2400).angle_to_pulse(rad(90.0)).unwrap();
    assert_eq!((p.ticks, p.clamped), (2999, None));
    // The pulse clamp alone: 1499.4 µs → 1499 µs, 0.4 µs: none either.
    let p = cal(180.0, 1499).angle_to_pulse(rad(89.96)).unwrap();
    assert_eq!((p.ticks, p.clamped), (2998, None));
    // Both: 1499.8 µs → 1499 µs, 0.8 µs in all: a clamp, the pulse limit's
    // (applied last).
    let p = cal(89.96, 1499).angle_to_pulse(rad(90.0)).unwrap();
    assert_eq!((p.ticks, p.clamped), (2998, Some(Limit::PulseMax)));
    // Far past the angle limit alone: the angle limit's.
    let p = cal(89.96, 2400).angle_to_pulse(rad(91.0)).unwrap();
    assert_eq!((p.ticks, p.clamped), (2999, Some(Limit::AngleMax)));
}
