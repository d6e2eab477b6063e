//! Angle units (`math::units`): the promises its module doc makes.

use std::f32::consts::{FRAC_PI_2 as FRAC_PI_2_F32, PI as PI_F32};

use touch_arm::math::units::{centideg_to_rad, deg_per_rad, rad_to_centideg, rad_to_deg, round_i32};

#[test]
fn typed_round_angles_land_on_the_codes_constants() {
    assert_eq!(centideg_to_rad::<f32>(9000), FRAC_PI_2_F32);
    assert_eq!(centideg_to_rad::<f32>(-9000), -FRAC_PI_2_F32);
    assert_eq!(centideg_to_rad::<f32>(18_000), PI_F32);
    assert_eq!(centideg_to_rad::<f32>(36_000), 2.0 * PI_F32);
    assert_eq!(centideg_to_rad::<f32>(0), 0.0);
    // In f64 the product is within an ulp (the promise is the chip's f32).
    assert!((centideg_to_rad::<f64>(18_000) - std::f64::consts::PI).abs() <= 4.5e-16);
}

#[test]
fn hundredths_read_back_as_typed() {
    for v in -2_000_000..=2_000_000 {
        assert_eq!(rad_to_centideg(centideg_to_rad::<f32>(v)), v);
    }
}

#[test]
fn factors() {
    assert_eq!(deg_per_rad::<f32>(), 180.0 / PI_F32);
    assert_eq!(deg_per_rad::<f64>(), 180.0 / std::f64::consts::PI);
    // 180/π rounded once into f32 (57.29578), not 180 over f32's π (57.295776).
    assert_eq!(rad_to_deg(1.0f32), (180.0 / std::f64::consts::PI) as f32);
    assert_ne!(rad_to_deg(1.0f32), deg_per_rad::<f32>());
    for x in [0.1, 1.0, -2.5, 3.0] {
        let d = rad_to_deg(x);
        assert!((d - f64::to_degrees(x)).abs() <= f64::EPSILON * d.abs(), "{x}");
    }
    assert_eq!(rad_to_centideg(FRAC_PI_2_F32), 9000);
    assert_eq!(rad_to_centideg(-2.0), -11_459);
    assert_eq!(rad_to_centideg(f32::NAN), 0);
    assert_eq!(rad_to_centideg(f32::INFINITY), i32::MAX);
}

#[test]
fn rounding_is_half_away_from_zero_and_saturates() {
    assert_eq!(round_i32(2.5), 3);
    assert_eq!(round_i32(-2.5), -3);
    assert_eq!(round_i32(2.49), 2);
    assert_eq!(round_i32(-0.4), 0);
    assert_eq!(round_i32(f32::NAN), 0);
    assert_eq!(round_i32(1e10), i32::MAX);
    assert_eq!(round_i32(-1e10), i32::MIN);
}
