//! Trajectory math: the ζ-a-tₛ shape (method.md §7), via points (§6), classic laws
//! (§7) and the synchronized multi-joint plan.

use proptest::prelude::*;
use reference::zat::Zat;
use touch_arm::motion::laws::{eval, Law, LawParams, LawPlan};
use touch_arm::motion::plan::{JointLaw, LawKind, MultiPlan, JOINTS};
use touch_arm::motion::via::{
    c1_max_base, c2_ln_base, c2_via_jerk, iterate_paper, smooth_via_a, via_condition, via_shape_for, Continuity,
    ContinuityError, ViaCondition, ViaParams, ViaPlan,
};
use touch_arm::motion::zat::{pole_margin, smooth_stop_a, u_min, zeta, Shape, ShapeParams, ZatParams, ZatPlan};
use touch_arm::motion::{Sample, TrajError};

// ---------------------------------------------------------------- references

/// Independent f64 reference for G (the `reference` crate: the printed form
/// normalized at tₛ, in log space, no shared code with the crate's recipe).
fn g_ref(t: f64, ts: f64, a: f64, n: f64) -> f64 {
    Zat::new(ts, a, n).g(t)
}

/// The printed eq. 8/13 form with its own ζ (`reference`: the powers formed
/// directly).
fn printed(t: f64, q0: f64, sf: f64, ts: f64, a: f64, n: f64) -> f64 {
    Zat::new(ts, a, n).printed(q0, sf, t)
}

fn shape64(ts: f64, a: f64, n: f64) -> Shape<f64> {
    Shape::new(&ShapeParams { ts, a, n }).unwrap()
}

/// Dense scan of G on (0, tₛ]: (is non-decreasing and ≤ 1, max).
/// Uniform points plus a geometric cluster at tₛ, where a decreasing tail can
/// be very short.
fn scan_monotone(s: &Shape<f64>) -> (bool, f64) {
    let ts = s.ts();
    let mut ts_pts: Vec<f64> = (1..=20_000).map(|k| ts * k as f64 / 20_000.0).collect();
    ts_pts.extend((1..=120).rev().map(|k| ts - ts * 10f64.powf(-(k as f64) / 10.0)));
    ts_pts.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut prev: f64 = 0.0;
    let mut mono = true;
    let mut peak: f64 = 0.0;
    for &t in &ts_pts {
        let g = s.g(t);
        peak = peak.max(g);
        if g < prev - 1e-12 * prev.max(1.0) || g > 1.0 + 1e-12 {
            mono = false;
        }
        prev = g;
    }
    (mono, peak)
}

/// Admissible shape parameters with a below u_min by at least `min_margin`.
fn admissible(min_margin: f64) -> impl Strategy<Value = (f64, f64, f64)> {
    (0.2f64..10.0, 1.1f64..100.0, min_margin..3.0).prop_map(|(ts, n, m)| (ts, u_min(ts) - m, n))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

// ---------------------------------------------------------------- ζ-a-tₛ shape

#[test]
fn endpoints_exact_f32_and_f64() {
    for &(ts, a, n) in &[(3.0, 1.0, 2.0), (0.5, 0.2, 10.0), (1.0, 0.3, 1.5), (7.3, 2.0, 57.0)] {
        let s64 = shape64(ts, a, n);
        assert_eq!(s64.g(ts), 1.0);
        assert_eq!(s64.g_derivs(ts).s, 1.0);
        assert_eq!(s64.g(0.0), 0.0);
        let s32 = Shape::<f32>::new(&ShapeParams { ts: ts as f32, a: a as f32, n: n as f32 }).unwrap();
        assert_eq!(s32.g(ts as f32), 1.0f32);
        // The formula just before tₛ joins continuously.
        assert!((s64.g(ts * (1.0 - 1e-12)) - 1.0).abs() < 1e-9);

        // Awkward decimals: q0 + (S_f − q0) would not round back to S_f.
        for &(q0, sf) in &[(0.1, 0.7), (0.7, 0.1), (-0.3, 2.9), (0.25, 0.25)] {
            let p = ZatPlan::new(&ZatParams { q0, sf, ts, a, n }).unwrap();
            assert_eq!(p.position(ts), sf);
            assert_eq!(p.sample(ts).s, sf);
            assert_eq!(p.position(0.0), q0);
            let after = p.sample(ts + 0.01);
            assert_eq!(after, Sample { s: sf, v: 0.0, acc: 0.0, jerk: 0.0 });
            assert_eq!(p.sample(-1.0), Sample { s: q0, v: 0.0, acc: 0.0, jerk: 0.0 });
            assert_eq!(p.sample(0.0), Sample { s: q0, v: 0.0, acc: 0.0, jerk: 0.0 });
            let p32 = ZatPlan::<f32>::new(&ZatParams {
                q0: q0 as f32,
                sf: sf as f32,
                ts: ts as f32,
                a: a as f32,
                n: n as f32,
            })
            .unwrap();
            assert_eq!(p32.position(ts as f32), sf as f32);
            assert_eq!(p32.position(0.0), q0 as f32);
        }
    }
}

#[test]
fn cheap_paths_agree_with_full_derivatives() {
    for &(ts, a, n) in &[(3.0f32, 1.0, 2.0), (0.5, 0.2, 10.0), (8.0, 4.0, 1.2)] {
        let s = Shape::<f32>::new(&ShapeParams { ts, a, n }).unwrap();
        for k in -2..=44 {
            let t = ts * k as f32 / 40.0;
            let d = s.g_derivs(t);
            assert_eq!(s.g(t), d.s, "{t}");
            assert_eq!(s.g_rate(t), (d.s, d.v), "{t}");
        }
        assert_eq!(s.g_derivs(ts).v, s.end_rate());
    }
}

#[test]
fn zero_displacement_is_constant() {
    let p = ZatPlan::new(&ZatParams { q0: 0.4, sf: 0.4, ts: 2.0, a: 0.5, n: 3.0 }).unwrap();
    assert_eq!(p.zeta(), None);
    for k in 0..=50 {
        let s = p.sample(2.0 * k as f64 / 40.0);
        assert_eq!(s, Sample { s: 0.4, v: 0.0, acc: 0.0, jerk: 0.0 });
    }
    assert_eq!(p.end_velocity(), 0.0);
}

#[test]
fn f32_recipe_matches_reference_over_spec_sweep() {
    // ts ∈ [0.2, 10], n ∈ [1.1, 100] (log spaced), a from 0.01 to ~12 below u_min.
    let margins = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 12.0];
    let (mut worst_mono, mut worst_rel) = (0.0f64, 0.0f64);
    let mut checked_mono = 0;
    for its in 0..=30 {
        let ts = 0.2f32 + 9.8 * its as f32 / 30.0;
        for inn in 0..=24 {
            let n = (1.1f64.ln() + (100f64.ln() - 1.1f64.ln()) * inn as f64 / 24.0).exp() as f32;
            for &m in &margins {
                let a = (u_min(ts as f64) - m) as f32;
                let s32 = Shape::<f32>::new(&ShapeParams { ts, a, n }).unwrap();
                let (ts64, a64, n64) = (ts as f64, a as f64, n as f64);
                let mono = shape64(ts64, a64, n64).is_monotone();
                checked_mono += mono as usize;
                for k in 1..=400 {
                    let t = ts * k as f32 / 400.0;
                    let r = g_ref(t as f64, ts64, a64, n64);
                    let e = (s32.g(t) as f64 - r).abs();
                    if mono {
                        worst_mono = worst_mono.max(e);
                    }
                    worst_rel = worst_rel.max(e / r.max(1.0));
                }
            }
        }
    }
    assert!(checked_mono > 2000, "{checked_mono}");
    // method.md §7.9: within 4e-7 in normalized units for the plans a servo may run.
    assert!(worst_mono <= 4e-7, "monotone worst {worst_mono:e}");
    // Overshooting shapes near the pole (G up to hundreds): relative accuracy;
    // the limit there is exp() of an argument up to ~4 carrying f32 rounding.
    assert!(worst_rel <= 2e-6, "relative worst {worst_rel:e}");
}

#[test]
fn f64_recipe_matches_independent_reference() {
    let mut worst = 0.0f64;
    for its in 0..=20 {
        let ts = 0.2 + 9.8 * its as f64 / 20.0;
        for &n in &[1.1, 1.7, 2.0, 5.0, 20.0, 100.0] {
            for &m in &[0.05, 0.5, 2.0] {
                let a = u_min(ts) - m;
                let s = shape64(ts, a, n);
                for k in 1..=200 {
                    let t = ts * k as f64 / 200.0;
                    let r = g_ref(t, ts, a, n);
                    worst = worst.max((s.g(t) - r).abs() / r.max(1.0));
                }
            }
        }
    }
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn normalized_equals_printed_zeta_form() {
    for &(q0, sf) in &[(0.1, 0.8), (0.9, 0.2), (-1.0, 2.5)] {
        for &(ts, n, m) in &[(1.0, 2.0, 0.5), (3.0, 2.0, 0.3), (0.4, 7.0, 0.1), (5.0, 1.5, 1.0), (2.0, 20.0, 0.2)] {
            let a = u_min(ts) - m;
            let p = ZatPlan::new(&ZatParams { q0, sf, ts, a, n }).unwrap();
            for k in 4..=100 {
                let t = ts * k as f64 / 100.0;
                let want = printed(t, q0, sf, ts, a, n);
                let got = p.position(t);
                assert!(close(got, want, 1e-11 * (1.0 + want.abs())), "{t}: {got} vs {want}");
            }
        }
    }
    // ζ itself against its printed definition.
    let z = zeta(&ZatParams { q0: 0.2, sf: 0.9, ts: 3.0, a: 1.5, n: 2.0 }).unwrap();
    let want = 3.0 - (0.7f64 * (2f64.powf(3.0) - 2f64.powf(1.5))).ln() / 2f64.ln();
    assert!(close(z, want, 1e-13), "{z} {want}");
    assert_eq!(zeta(&ZatParams { q0: 0.5, sf: 0.5, ts: 3.0, a: 1.5, n: 2.0 }), None);
}

#[test]
fn negative_displacement_negates_derivatives() {
    let up = ZatPlan::new(&ZatParams { q0: 0.0, sf: 0.6, ts: 2.0, a: 0.4, n: 3.0 }).unwrap();
    let down = ZatPlan::new(&ZatParams { q0: 0.6, sf: 0.0, ts: 2.0, a: 0.4, n: 3.0 }).unwrap();
    for k in 1..=20 {
        let t = 0.1 * k as f64;
        let (u, d) = (up.sample(t), down.sample(t));
        assert!(close(u.s + d.s, 0.6, 1e-15));
        assert!(close(u.v, -d.v, 1e-15) && close(u.acc, -d.acc, 1e-14) && close(u.jerk, -d.jerk, 1e-13));
        assert!(u.v > 0.0);
    }
}

#[test]
fn u_min_matches_dense_scan() {
    for k in 0..60 {
        let ts = 0.1 + 0.2 * k as f64;
        let mut m = f64::INFINITY;
        for j in 1..=200_000 {
            let t = ts * j as f64 / 200_000.0;
            m = m.min(t + ts / t - 1.0);
        }
        assert!(close(u_min(ts), m, 1e-8), "ts {ts}: {} vs {m}", u_min(ts));
        assert!(close(pole_margin(ts, 0.25), m - 0.25, 1e-8));
    }
}

#[test]
fn admissibility_errors() {
    let ts = 3.0;
    let um = 2.0 * 3f64.sqrt() - 1.0;
    let err = Shape::new(&ShapeParams { ts, a: um, n: 2.0 }).unwrap_err();
    assert_eq!(err, TrajError::ShapeNotAdmissible { a: um, u_min: um });
    let msg = format!("{err}");
    assert!(msg.contains("a must be < u_min = 2.464"), "{msg}");
    assert!(matches!(
        Shape::new(&ShapeParams { ts, a: 2.9, n: 2.0 }), // a < tₛ: the papers' condition, still a pole
        Err(TrajError::ShapeNotAdmissible { .. })
    ));
    assert!(Shape::new(&ShapeParams { ts, a: um - 1e-9, n: 2.0 }).is_ok());
    // tₛ < 1: the bound is tₛ itself.
    assert!(Shape::new(&ShapeParams { ts: 0.5, a: 0.5, n: 2.0 }).is_err());
    assert!(Shape::new(&ShapeParams { ts: 0.5, a: 0.4999, n: 2.0 }).is_ok());
    let s = Shape::<f32>::new(&ShapeParams { ts: 3.0, a: 2.45, n: 2.0 }).unwrap();
    assert!((s.u_min() - 2.4641016).abs() < 1e-6);

    let e = |ts: f64, a: f64, n: f64| Shape::new(&ShapeParams { ts, a, n }).unwrap_err();
    assert_eq!(e(0.0, -1.0, 2.0), TrajError::NonPositiveDuration);
    assert_eq!(e(-2.0, -1.0, 2.0), TrajError::NonPositiveDuration);
    assert_eq!(e(2.0, 0.0, 1.0), TrajError::BaseNotAboveOne);
    assert_eq!(e(2.0, 0.0, 0.5), TrajError::BaseNotAboveOne);
    assert_eq!(e(f64::NAN, 0.0, 2.0), TrajError::NotFinite);
    assert_eq!(e(2.0, f64::NEG_INFINITY, 2.0), TrajError::NotFinite);
    assert_eq!(e(2.0, 0.0, f64::INFINITY), TrajError::NotFinite);
    assert_eq!(ZatPlan::new(&ZatParams { q0: f64::NAN, sf: 1.0, ts: 2.0, a: 0.0, n: 2.0 }), Err(TrajError::NotFinite));
}

#[test]
fn spec_overshoot_example() {
    let s = shape64(3.0, 2.45, 2.0);
    assert!(!s.is_monotone());
    assert!(s.monotone_margin().unwrap() < -0.5);
    let (mono, scan_peak) = scan_monotone(&s);
    assert!(!mono);
    // method.md §7 quotes a peak of 9.6; the function actually peaks at
    // 19.67727105153175 at t = 1.740561590602 (30-digit mpmath root of G′;
    // G(1.7) alone is 18.4 = method.md §8's r), confirmed by the scan and by the
    // independent reference.
    let peak = s.peak();
    assert!(close(peak, 19.67727105153175, 1e-11), "{peak}");
    assert!(close(peak, scan_peak, 1e-5 * peak));
    assert!(close(g_ref(1.7405, 3.0, 2.45, 2.0), s.g(1.7405), 1e-10));
    match s.check_monotone() {
        Err(TrajError::Overshoot { peak: p }) => assert_eq!(p, peak),
        other => panic!("{other:?}"),
    }
    let s32 = Shape::<f32>::new(&ShapeParams { ts: 3.0, a: 2.45, n: 2.0 }).unwrap();
    assert!(!s32.is_monotone());
    assert!((s32.peak() - 19.677268).abs() < 1e-3);
}

#[test]
fn backtracking_inside_unit_interval_is_not_monotone() {
    // G rises to 0.7869 at t ≈ 2.75, falls to 0.7803 near t ≈ 3.14, then rises
    // to 1 (checked with 30-digit mpmath): never above 1, still not monotone.
    let s = shape64(4.832658314206215, 3.218816282384634, 4.713029014726548);
    assert!(!s.is_monotone());
    let (mono, scan_peak) = scan_monotone(&s);
    assert!(!mono && scan_peak <= 1.0);
    assert_eq!(s.peak(), 1.0);
    assert!(close(s.g(2.7486), 0.786851, 1e-5) && s.g(3.0) < s.g(2.75));
    assert_eq!(s.check_monotone(), Err(TrajError::Overshoot { peak: 1.0 }));
}

#[test]
fn end_velocity_and_smooth_stop() {
    for &(ts, a, n) in &[(3.0, 1.0, 2.0), (0.5, 0.1, 4.0), (6.0, 2.0, 1.5), (1.0, 0.5, 30.0)] {
        let s = shape64(ts, a, n);
        // Second-order one-sided difference at tₛ⁻.
        let h = 1e-5;
        let fd = (3.0 * s.g(ts) - 4.0 * s.g(ts - h) + s.g(ts - 2.0 * h)) / (2.0 * h);
        assert!(close(s.end_rate(), fd, 1e-7 * (1.0 + fd.abs())), "{} {fd}", s.end_rate());
        assert_eq!(s.g_derivs(ts).v, s.end_rate());
        let p = ZatPlan::new(&ZatParams { q0: 0.2, sf: -0.5, ts, a, n }).unwrap();
        assert!(close(p.end_velocity(), -0.7 * s.end_rate(), 1e-15));
        if ts <= 1.0 {
            // tₛ ≤ 1: the motion always ends with a velocity step ≥ ln n.
            assert!(s.end_rate() >= n.ln());
        }
    }
    // a* = tₛ − log_n tₛ stops smoothly.
    for &(ts, n) in &[(3.0, 2.0), (4.0, 1.5), (9.0, 1.3), (2.0, 4.0)] {
        let a = smooth_stop_a(ts, n).unwrap();
        assert!(close(a, ts - ts.ln() / n.ln(), 1e-15));
        let s = shape64(ts, a, n);
        assert!(s.end_rate().abs() < 1e-12, "{}", s.end_rate());
        let a32 = smooth_stop_a(ts as f32, n as f32).unwrap();
        let s32 = Shape::<f32>::new(&ShapeParams { ts: ts as f32, a: a32, n: n as f32 }).unwrap();
        assert!(s32.end_rate().abs() < 1e-5);
    }
    // method.md's admissibility condition is not enough for a usable a*: at tₛ, φ = 0
    // and φ′(tₛ) ≤ 0 ⇔ L·(tₛ − 1) ≤ 2 decides whether G dips before the end.
    for &(ts, n, mono) in
        &[(3.0, 2.6, true), (3.0, 2.8, false), (3.0, 7.7, false), (9.0, 1.3, false), (9.0, 1.28, true)]
    {
        let s = shape64(ts, smooth_stop_a(ts, n).unwrap(), n);
        assert_eq!(s.is_monotone(), mono, "{ts} {n}");
        assert_eq!(scan_monotone(&s).0, mono, "{ts} {n}");
        assert_eq!(n.ln() * (ts - 1.0) <= 2.0, mono);
    }
    assert!(shape64(3.0, smooth_stop_a(3.0, 7.7).unwrap(), 7.7).peak() > 30.0);
    assert_eq!(smooth_stop_a(1.0, 2.0), None);
    assert_eq!(smooth_stop_a(0.7, 2.0), None);
    // tₛ = 3: needs ln n < ln 3/(√3 − 1)² = 2.0494 → n < 7.76.
    assert!(smooth_stop_a(3.0, 7.7).is_some());
    assert_eq!(smooth_stop_a(3.0, 7.8), None);
}

#[test]
fn start_decays_faster_than_any_power() {
    for &(ts, a, n) in &[(1.0f64, 0.2, 2.0), (3.0, 1.0, 1.5), (0.5, 0.3, 10.0)] {
        let p = ZatPlan::new(&ZatParams { q0: 0.3, sf: 0.9, ts, a, n }).unwrap();
        let mut prev_ratio = f64::INFINITY;
        let mut prev_d = Sample { s: 0.0, v: f64::INFINITY, acc: f64::INFINITY, jerk: f64::INFINITY };
        for &t in &[0.05 * ts, 0.02 * ts, 0.01 * ts, 0.005 * ts] {
            let off = p.position(t) - 0.3;
            let ratio = off / t.powi(10);
            assert!(off >= 0.0 && ratio <= prev_ratio, "{t} {off}");
            prev_ratio = ratio;
            // Past L·tₛ/t ≈ 6 every derivative shrinks as t → 0.
            let d = p.sample(t);
            assert!(d.v >= 0.0 && d.v <= prev_d.v && d.acc <= prev_d.acc && d.jerk <= prev_d.jerk, "{d:?}");
            prev_d = d;
        }
        assert!(p.position(0.005 * ts) - 0.3 < 1e-20);
        // The decay is e^(−L·tₛ/t) up to a bounded factor: check against the
        // reference where it is still representable.
        let s = shape64(ts, a, n);
        for &t in &[0.05 * ts, 0.03 * ts] {
            let want = g_ref(t, ts, a, n);
            assert!(want > 0.0 && close(s.g(t), want, 1e-12 * want), "{t}");
            assert!(want <= (-(n.ln()) * (ts / t - 1.0)).exp() * 1.0001);
        }
        assert!(p.sample(0.005 * ts).jerk.abs() < 1e-10);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Each analytic derivative against a central difference of the one below.
    #[test]
    fn derivatives_match_finite_differences((ts, a, n) in admissible(0.05), frac in 0.05f64..0.98) {
        let s = shape64(ts, a, n);
        let t = frac * ts;
        let h = 1e-5 * ts;
        let (lo, mid, hi) = (s.g_derivs(t - h), s.g_derivs(t), s.g_derivs(t + h));
        let fd = [(hi.s - lo.s) / (2.0 * h), (hi.v - lo.v) / (2.0 * h), (hi.acc - lo.acc) / (2.0 * h)];
        let an = [mid.v, mid.acc, mid.jerk];
        // Scale: the size of the next derivative the difference truncates.
        let scale = 1.0 + mid.v.abs() + mid.acc.abs() + mid.jerk.abs();
        // Observed worst over 20 000 random cases: 1e-9, 1.8e-8, 1.6e-7.
        let tol = [1e-8, 2e-7, 2e-6];
        for k in 0..3 {
            prop_assert!((fd[k] - an[k]).abs() <= tol[k] * scale,
                "k={} fd={} an={} t={}", k, fd[k], an[k], t);
        }
        prop_assert!((mid.s - g_ref(t, ts, a, n)).abs() < 1e-12 * mid.s.max(1.0));
    }

    /// The convex-φ criterion agrees with a dense scan of G.
    #[test]
    fn monotone_check_matches_dense_scan((ts, n) in (1.01f64..10.0, 1.1f64..100.0), lm in -2.7f64..0.5) {
        // Log-spaced distance to the pole: most non-monotone shapes sit close to it.
        let a = u_min(ts) - 10f64.powf(lm);
        let s = shape64(ts, a, n);
        let margin = s.monotone_margin().unwrap();
        prop_assume!(margin.abs() > 1e-3);
        let (mono, peak) = scan_monotone(&s);
        prop_assert_eq!(s.is_monotone(), mono, "margin {}", margin);
        prop_assert_eq!(s.is_monotone(), margin > 0.0);
        if !mono && peak > 1.0 + 1e-9 {
            // The grid can only miss the top of a sharp peak, never exceed it.
            prop_assert!(s.peak() >= peak * (1.0 - 1e-12) && s.peak() <= peak * (1.0 + 1e-3),
                "{} vs {}", s.peak(), peak);
        } else {
            prop_assert!(s.peak() >= 1.0 && s.peak() <= peak.max(1.0) + 1e-9);
        }
    }

    #[test]
    fn short_motions_are_always_monotone(ts in 0.05f64..1.0, n in 1.1f64..100.0, m in 1e-6f64..3.0) {
        let s = shape64(ts, ts - m, n);
        prop_assert!(s.is_monotone());
        prop_assert_eq!(s.monotone_margin(), None);
        prop_assert!(scan_monotone(&s).0);
    }

    /// a* exists exactly under method.md's condition and always zeroes the end rate.
    #[test]
    fn smooth_stop_condition(ts in 0.3f64..10.0, n in 1.05f64..50.0) {
        let cond = ts > 1.0 && n.ln() < ts.ln() / (ts.sqrt() - 1.0).powi(2);
        let bound = ts.ln() / (ts.sqrt() - 1.0).powi(2);
        prop_assume!(ts <= 1.0 || (n.ln() - bound).abs() > 1e-9);
        // Just above tₛ = 1 the margin of Shape's test a < u_min(tₛ) shrinks
        // like (tₛ − 1)² and falls below f64's resolution (tₛ = 1 + 1.16e-6,
        // n = 48.1 failed once): the condition holds, the check rounds it
        // away. The product never plans ζ-a-tₛ under 1.2 s (`zat_ts_min`).
        prop_assume!(ts <= 1.0 || ts > 1.0 + 1e-4);
        match smooth_stop_a(ts, n) {
            Some(a) => {
                prop_assert!(cond);
                prop_assert!(shape64(ts, a, n).end_rate().abs() < 1e-10);
            }
            None => prop_assert!(!cond),
        }
    }
}

/// Edge values for the f32 checks: signed zeros, subnormals, 1 ± ulp, the
/// extremes, ±∞ and NaN.
const F32_EDGES: [f32; 20] = [
    0.0,
    -0.0,
    1e-45,
    -1e-45,
    1e-39,
    0.5,
    0.999_999_94,
    1.0,
    1.000_000_1,
    2.0,
    3.0,
    10.0,
    -2.0,
    1e30,
    -1e30,
    f32::MAX,
    f32::MIN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
];

/// `Shape::new`'s refusals written with plain float comparisons, in its order.
fn shape_refusal_ref(ts: f32, a: f32, n: f32) -> Result<(), TrajError<f32>> {
    if !(ts.is_finite() && a.is_finite() && n.is_finite()) {
        return Err(TrajError::NotFinite);
    }
    if ts <= 0.0 {
        return Err(TrajError::NonPositiveDuration);
    }
    if n <= 1.0 {
        return Err(TrajError::BaseNotAboveOne);
    }
    let um = u_min(ts);
    let delta = pole_margin(ts, a);
    if !(a < um && delta > 0.0) {
        return Err(TrajError::ShapeNotAdmissible { a, u_min: um });
    }
    let l = touch_arm::math::exp::ln(n);
    let l_delta = l * delta;
    let e_s = touch_arm::math::exp::expm1(l * (ts - a));
    let on_pole = l_delta < f32::EPSILON && !((1.0 / l_delta).is_finite() && (1.0 / e_s).is_finite());
    if on_pole || !l_delta.is_finite() {
        return Err(TrajError::NotFinite);
    }
    Ok(())
}

/// On f32 the shape's checks compare bit patterns (a float comparison is a
/// library call on the AVR): the same refusals, in the same order, as float
/// comparisons give, over edge values and around the u_min boundary.
#[test]
fn f32_shape_checks_match_float_comparisons() {
    let mut checked = [0usize; 2];
    for &ts in F32_EDGES.iter() {
        let um = if ts.is_finite() && ts > 0.0 { u_min(ts) } else { 1.0 };
        let up = |x: f32| f32::from_bits(x.to_bits().wrapping_add(1));
        let down = |x: f32| f32::from_bits(x.to_bits().wrapping_sub(1));
        let mut avals = F32_EDGES.to_vec();
        avals.extend([um, up(um), down(um), down(down(um)), um - 0.01, ts, down(ts)]);
        for &a in avals.iter() {
            for &n in F32_EDGES.iter().chain([1.1f32, 7.0, 100.0].iter()) {
                let got = Shape::<f32>::new(&ShapeParams { ts, a, n });
                let want = shape_refusal_ref(ts, a, n);
                assert_eq!(got.as_ref().err(), want.as_ref().err(), "tₛ {ts:e} a {a:e} n {n:e}");
                checked[usize::from(got.is_ok())] += 1;
            }
        }
    }
    assert!(checked[0] > 1000 && checked[1] > 100, "{checked:?}");
    // G at the edges of time: 0 for t ≤ 0 and NaN, 1 from tₛ on.
    let s = Shape::<f32>::new(&ShapeParams { ts: 3.0, a: 1.0, n: 2.0 }).unwrap();
    for t in [0.0, -0.0, -1.0, f32::NEG_INFINITY, f32::NAN, 1e-45] {
        assert_eq!(s.g(t), 0.0, "{t:e}");
        assert_eq!(s.g_rate(t), (0.0, 0.0), "{t:e}");
    }
    for t in [3.0, 3.000_000_2, 1e30, f32::INFINITY] {
        assert_eq!(s.g(t), 1.0, "{t:e}");
        assert_eq!(s.g_rate(t).0, 1.0, "{t:e}");
    }
    assert_eq!(s.g_rate(3.000_000_2), (1.0, 0.0));
    assert_eq!(s.g_rate(3.0), (1.0, s.end_rate()));
    assert!(s.g(2.999_999_8) < 1.0 && s.g(2.999_999_8) > 0.999);
}

/// n = 2 (the app's base) skips the logarithm on f32: the constant is the
/// chip's ln 2 to the bit, so shapes, a* and ζ are unchanged.
#[test]
fn f32_base_two_uses_the_chips_ln2() {
    let ln2 = touch_arm::math::exp::ln(2.0);
    assert_eq!(ln2.to_bits(), core::f32::consts::LN_2.to_bits());
    let s = Shape::<f32>::new(&ShapeParams { ts: 3.0, a: 1.0, n: 2.0 }).unwrap();
    assert_eq!(s.ln_n().to_bits(), ln2.to_bits());
    let a = smooth_stop_a(3.0f32, 2.0).unwrap();
    assert_eq!(a.to_bits(), (3.0f32 - touch_arm::math::exp::ln(3.0) / ln2).to_bits());
    let z = zeta(&ZatParams { q0: 0.1f32, sf: 0.9, ts: 3.0, a: 1.0, n: 2.0 }).unwrap();
    assert_eq!(Some(z), s.zeta(0.9f32 - 0.1));
}

// ---------------------------------------------------------------- via points

fn via_params(theta_v: f64, tv: f64, av: f64) -> ViaParams<f64> {
    ViaParams { q0: 0.1, theta_v, sf: 0.8, tv, ts: 3.0, a: 1.0, n: 2.0, av, nv: 3.0 }
}

#[test]
fn via_closed_form_hits_the_via_value() {
    for &theta in &[0.5, 0.95, 0.0, -0.3, 0.8] {
        for &(tv, av) in &[(1.5, 0.5), (0.6, 0.2), (2.5, 1.0)] {
            let p = via_params(theta, tv, av);
            let plan = ViaPlan::new(&p).unwrap();
            let r = plan.r();
            assert!(close(r, shape64(3.0, 1.0, 2.0).g(tv), 0.0));
            assert!(close(plan.sv(), (theta - r * 0.8) / (1.0 - r), 1e-15));
            assert!(close(plan.position(tv), theta, 1e-14), "{} vs {theta}", plan.position(tv));
            assert_eq!(plan.position(3.0), 0.8);
            assert_eq!(plan.position(0.0), 0.1);
            assert_eq!(plan.sample(3.5), Sample { s: 0.8, v: 0.0, acc: 0.0, jerk: 0.0 });
            // The signed form matches its two terms.
            let (gv, g) = (shape64(tv, av, 3.0), shape64(3.0, 1.0, 2.0));
            for k in 1..30 {
                let t = 0.1 * k as f64;
                let want = 0.1 + (plan.sv() - 0.1) * gv.g(t) + (0.8 - plan.sv()) * g.g(t);
                assert!(close(plan.position(t), want, 1e-15));
            }
            // ζ, ζ_v as method.md §8 restates eq. 10.
            assert_eq!(plan.zeta(), zeta(&ZatParams { q0: plan.sv(), sf: 0.8, ts: 3.0, a: 1.0, n: 2.0 }));
            assert_eq!(plan.zeta_v(), zeta(&ZatParams { q0: 0.1, sf: plan.sv(), ts: tv, a: av, n: 3.0 }));
        }
    }
}

#[test]
fn via_jumps_are_left_right_differences() {
    let p = via_params(0.5, 1.5, 0.5);
    let plan = ViaPlan::new(&p).unwrap();
    let at = plan.sample(1.5);
    let left = plan.sample(1.5 - 1e-9);
    let right = plan.sample(1.5 + 1e-9);
    assert!(close(at.v, left.v, 1e-6) && close(at.acc, left.acc, 1e-5));
    let j = plan.jumps();
    assert!(close(j.v, right.v - at.v, 1e-6), "{} {}", j.v, right.v - at.v);
    assert!(close(j.acc, right.acc - at.acc, 1e-5));
    assert_eq!(j.v, plan.velocity_jump());
    assert_eq!(j.acc, plan.acc_jump());
    assert!(j.v.abs() > 1e-3);
    assert!(close(plan.end_velocity(), (0.8 - plan.sv()) * shape64(3.0, 1.0, 2.0).end_rate(), 1e-15));
}

#[test]
fn smooth_via_shape_removes_velocity_jump() {
    for &(tv, nv) in &[(1.5, 3.0), (2.0, 2.0), (2.5, 1.5)] {
        let av = smooth_via_a(tv, nv).unwrap();
        assert!(close(av, tv - tv.ln() / nv.ln(), 1e-14), "tv {tv}: a_v {av} vs {}", tv - tv.ln() / nv.ln());
        let p = ViaParams { q0: 0.1, theta_v: 0.6, sf: 0.8, tv, ts: 3.0, a: 1.0, n: 2.0, av, nv };
        let plan = ViaPlan::new(&p).unwrap();
        assert!(plan.velocity_jump().abs() < 1e-12, "{}", plan.velocity_jump());
        // Acceleration still jumps (Gv″(t_v) ≠ 0 in general).
        assert!(plan.acc_jump().abs() > 1e-6);
        let (l, r) = (plan.sample(tv - 1e-7), plan.sample(tv + 1e-7));
        assert!(close(l.v, r.v, 1e-5));
    }
    assert_eq!(smooth_via_a(0.8, 2.0), None);
}

/// Left derivatives of Gv at its end from one-sided finite differences of
/// the independent reference's G (second order, step h): (G′, G″).
fn fd_end_derivs(tv: f64, av: f64, nv: f64, h: f64) -> (f64, f64) {
    let z = Zat::new(tv, av, nv);
    let g = |k: f64| z.g(tv - k * h);
    let v = (3.0 * g(0.0) - 4.0 * g(1.0) + g(2.0)) / (2.0 * h);
    let acc = (2.0 * g(0.0) - 5.0 * g(1.0) + 4.0 * g(2.0) - g(3.0)) / (h * h);
    (v, acc)
}

#[test]
fn via_continuity_c2_zeroes_velocity_and_acceleration_jumps() {
    for &tv in &[1.1f64, 1.3, 1.5, 2.0, 3.0, 5.0, 9.0] {
        let (av, nv) = via_shape_for(tv, f64::NAN, f64::NAN, Continuity::C2).unwrap();
        // n_v = e^(2/(t_v − 1)), a_v its smooth stop.
        assert!(close(nv.ln(), 2.0 / (tv - 1.0), 1e-14), "tv {tv}: n_v {nv}");
        assert!(close(av, tv - tv.ln() / nv.ln(), 1e-14), "tv {tv}: a_v {av} vs {}", tv - tv.ln() / nv.ln());
        assert_eq!(c2_ln_base(tv), Some(2.0 / (tv - 1.0)));
        let p = ViaParams { q0: 0.1, theta_v: 0.6, sf: 0.8, tv, ts: tv + 1.5, a: 1.0, n: 2.0, av, nv };
        let plan = ViaPlan::new(&p).unwrap();
        assert!(plan.via_shape().is_monotone(), "tv {tv}");
        let j = plan.jumps();
        let k = plan.sv() - 0.1;
        // Rounding level, relative to the scale of the via term's derivatives.
        let scale = k.abs() * c2_via_jerk(tv).max(1.0);
        assert!(j.v.abs() < 1e-12 * scale, "tv {tv}: velocity jump {}", j.v);
        assert!(j.acc.abs() < 1e-10 * scale, "tv {tv}: acceleration jump {}", j.acc);
        // The jerk cannot be continuous as well: −(S_v − q0)·4(t_v + 1)/(t_v²(t_v − 1)³).
        assert!(close(j.jerk, -k * c2_via_jerk(tv), 1e-8), "tv {tv}: {} vs {}", j.jerk, -k * c2_via_jerk(tv));
        // Against finite differences of the independent reference shape.
        let h = 1e-4 * (tv - 1.0);
        let (v, acc) = fd_end_derivs(tv, av, nv, h);
        let gv3 = c2_via_jerk(tv);
        assert!(v.abs() < 1e-6 * gv3, "tv {tv}: fd G′ {v}");
        assert!(acc.abs() < 1e-3 * gv3 * (tv - 1.0), "tv {tv}: fd G″ {acc}");
    }
}

#[test]
fn via_continuity_c1_keeps_the_base_and_steps_the_acceleration() {
    for &tv in &[1.2f64, 1.5, 2.5, 6.0] {
        let max = c1_max_base(tv);
        // ln n_v < ln t_v/(√t_v − 1)²: the bound is where a* reaches u_min.
        assert!(close(max.ln(), tv.ln() / (tv.sqrt() - 1.0).powi(2), 1e-14));
        for frac in [0.05, 0.5, 0.95] {
            let nv = (frac * max.ln()).exp();
            let (av, nv2) = via_shape_for(tv, 123.0, nv, Continuity::C1).unwrap();
            assert_eq!(nv2, nv);
            let p = ViaParams { q0: 0.0, theta_v: 0.7, sf: 1.0, tv, ts: tv + 1.0, a: 1.0, n: 2.0, av, nv };
            let plan = ViaPlan::new(&p).unwrap();
            let k = plan.sv();
            let l = nv.ln();
            assert!(plan.velocity_jump().abs() < 1e-11 * k.abs() * (1.0 + l * tv), "tv {tv} nv {nv}");
            // Gv″(t_v⁻) = (L/t_v)·(L − 2/(t_v − 1)): zero only at C2's base.
            let want = -k * (l / tv) * (l - 2.0 / (tv - 1.0));
            assert!(close(plan.acc_jump(), want, 1e-8), "tv {tv} nv {nv}: {} vs {want}", plan.acc_jump());
            let (v, acc) = fd_end_derivs(tv, av, nv, 1e-5);
            assert!(v.abs() < 1e-4 * (1.0 + l), "fd G′ {v}");
            assert!(close(-k * acc, want, 1e-3 * (1.0 + l * l)), "fd {} vs {want}", -k * acc);
        }
        match via_shape_for(tv, 0.0, max * 1.01, Continuity::C1) {
            Err(ContinuityError::BaseTooLarge { max: m, .. }) => assert!(close(m, max, 1e-14)),
            other => panic!("tv {tv}: {other:?}"),
        }
    }
}

#[test]
fn via_continuity_refusals() {
    for c in [Continuity::C1, Continuity::C2] {
        for tv in [0.3, 1.0] {
            assert_eq!(via_shape_for(tv, 0.5, 2.0, c), Err(ContinuityError::ViaTooEarly { tv }));
        }
        assert_eq!(via_shape_for(f64::NAN, 0.5, 2.0, c), Err(ContinuityError::NotFinite));
    }
    // e^(2/(t_v − 1)) overflows: f32 past L = 88, f64 past 709.
    assert_eq!(via_shape_for(1.01f32, 0.0, 0.0, Continuity::C2), Err(ContinuityError::NotFinite));
    assert!(via_shape_for(1.05f32, 0.0, 0.0, Continuity::C2).is_ok());
    assert_eq!(via_shape_for(1.001f64, 0.0, 0.0, Continuity::C2), Err(ContinuityError::NotFinite));
    // C0 passes the given shape through.
    assert_eq!(via_shape_for(0.5, 0.2, 3.0, Continuity::C0), Ok((0.2, 3.0)));
}

#[test]
fn via_paper_iteration_converges_to_closed_form() {
    for &theta in &[0.5, 0.95, -0.3] {
        let p = via_params(theta, 1.5, 0.5);
        let closed = ViaPlan::new(&p).unwrap();
        let r = closed.r();
        assert!(r < 1.0);
        let tol = 1e-10;
        let it = iterate_paper(&p, tol, 500).unwrap();
        assert!(close(it.sv, closed.sv(), 1e-9), "{} vs {}", it.sv, closed.sv());
        assert!(it.error.abs() < tol);
        // The iteration is linear: e_i = r^(i+1)·(S_f − θ_v), so the count is known.
        let e0 = (0.8 - theta).abs() * r;
        let expect = (0..).find(|&i| e0 * r.powi(i) < tol).unwrap() as u16;
        assert_eq!(it.iterations, expect);
        let trial = ViaPlan::with_sv(&p, it.sv).unwrap();
        assert_eq!(it.zeta, trial.zeta());
        assert_eq!(it.zeta_v, trial.zeta_v());
        assert!(close(trial.position(1.5), theta, 1e-9));
        assert_eq!(iterate_paper(&p, tol, 2), Err(TrajError::NoConvergence));
    }
    // θ_v = S_f: already exact at i = 0, where ζ_0 = ∞.
    let it = iterate_paper(&via_params(0.8, 1.5, 0.5), 1e-12, 10).unwrap();
    assert_eq!((it.iterations, it.sv, it.zeta), (0, 0.8, None));
}

#[test]
fn via_paper_iteration_diverges_for_spec_example() {
    let p = ViaParams { q0: 0.0, theta_v: 0.5, sf: 1.0, tv: 1.7, ts: 3.0, a: 2.45, n: 2.0, av: 0.5, nv: 2.0 };
    match iterate_paper(&p, 1e-6, 100) {
        Err(TrajError::ViaDiverges { r }) => assert!(close(r, 18.396165331078896, 1e-9), "{r}"),
        other => panic!("{other:?}"),
    }
    // The closed form still solves it (S_v = (θ_v − r·S_f)/(1 − r)).
    let plan = ViaPlan::new(&p).unwrap();
    assert!(close(plan.position(1.7), 0.5, 1e-12));
    let msg = format!("{}", TrajError::ViaDiverges { r: 18.4f64 });
    assert!(msg.contains("18.4"));
}

#[test]
fn via_validation_and_conditions() {
    for &tv in &[0.0, 3.0, 3.5, -1.0] {
        assert_eq!(ViaPlan::new(&via_params(0.5, tv, 0.0)), Err(TrajError::ViaTimeOutOfRange));
    }
    assert!(matches!(
        ViaPlan::new(&via_params(0.5, 1.5, 1.5)), // a_v ≥ u_min(1.5) = 1.449
        Err(TrajError::ShapeNotAdmissible { .. })
    ));
    assert_eq!(ViaPlan::new(&via_params(f64::NAN, 1.5, 0.5)), Err(TrajError::NotFinite));

    assert_eq!(via_condition(0.1, 0.5, 0.8), ViaCondition::Between);
    assert_eq!(via_condition(0.1, 0.9, 0.8), ViaCondition::Above);
    assert_eq!(via_condition(0.1, 0.0, 0.8), ViaCondition::Below);
    assert_eq!(via_condition(0.8, 0.5, 0.1), ViaCondition::BetweenFalling);
    assert_eq!(via_condition(0.8, 0.9, 0.1), ViaCondition::Above);
    assert_eq!(via_condition(0.8, 0.0, 0.1), ViaCondition::Below);
    assert_eq!(via_condition(0.1, 0.1, 0.8), ViaCondition::Between);
    assert_eq!(ViaCondition::BetweenFalling.number(), 4);
    let plan = ViaPlan::new(&via_params(0.95, 1.5, 0.5)).unwrap();
    assert!(plan.sv() > 0.95);
    assert_eq!(plan.condition().number(), 2);
}

/// The via plan's shapes are `Shape::new`'s, to the bit, whether or not the
/// segments share a base (then ln n is taken once); on f32 the via-time
/// check on bit patterns refuses as the float comparison does.
#[test]
fn via_shapes_are_shape_new_and_f32_checks_match() {
    for nv in [3.0, 2.0] {
        let p = ViaParams { nv, ..via_params(0.5, 1.5, 0.5) };
        let plan = ViaPlan::new(&p).unwrap();
        assert_eq!(*plan.via_shape(), shape64(1.5, 0.5, nv));
        assert_eq!(*plan.main_shape(), shape64(3.0, 1.0, 2.0));
        let p32 = ViaParams::<f32> {
            q0: 0.1,
            theta_v: 0.5,
            sf: 0.8,
            tv: 1.5,
            ts: 3.0,
            a: 1.0,
            n: 2.0,
            av: 0.5,
            nv: nv as f32,
        };
        let plan = ViaPlan::new(&p32).unwrap();
        let shape = |ts, a, n| Shape::<f32>::new(&ShapeParams { ts, a, n }).unwrap();
        assert_eq!(*plan.via_shape(), shape(1.5, 0.5, nv as f32));
        assert_eq!(plan.via_shape().ln_n().to_bits(), shape(1.5, 0.5, nv as f32).ln_n().to_bits());
        assert_eq!(*plan.main_shape(), shape(3.0, 1.0, 2.0));
        assert_eq!(plan.r().to_bits(), shape(3.0, 1.0, 2.0).g(1.5).to_bits());
    }
    let base = ViaParams::<f32> { q0: 0.1, theta_v: 0.5, sf: 0.8, tv: 1.5, ts: 3.0, a: 1.0, n: 2.0, av: 0.2, nv: 3.0 };
    let below_ts = f32::from_bits(3.0f32.to_bits() - 1);
    for tv in [0.0, -0.0, -1.0, 3.0, 3.5, f32::MAX, f32::MIN] {
        assert_eq!(ViaPlan::new(&ViaParams { tv, ..base }), Err(TrajError::ViaTimeOutOfRange), "{tv:e}");
    }
    for tv in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(ViaPlan::new(&ViaParams { tv, ..base }), Err(TrajError::NotFinite), "{tv:e}");
    }
    // Inside (0, tₛ): admitted as far as the via time goes (tiny t_v still
    // has its own shape to pass).
    assert!(ViaPlan::new(&ViaParams { tv: below_ts, av: 1.0, ..base }).is_ok());
    assert!(matches!(ViaPlan::new(&ViaParams { tv: 1e-45, ..base }), Err(TrajError::ShapeNotAdmissible { .. })));
}

// ---------------------------------------------------------------- classic laws

const LAWS: [Law; 4] = [Law::Linear, Law::Cubic, Law::Quintic, Law::Trapezoid];

#[test]
fn laws_endpoints_and_outside() {
    for law in LAWS {
        for &(t0, tf, s0, sf) in &[(0.0, 1.0, 0.0, std::f64::consts::PI), (0.3, 1.7, 0.1, 0.7), (1.0, 2.1, 0.9, -0.2)] {
            let p = LawParams { t0, tf, s0, sf };
            assert_eq!(eval(law, &p, tf).unwrap().s, sf);
            assert_eq!(eval(law, &p, t0).unwrap().s, s0);
            assert_eq!(eval(law, &p, tf + 0.5).unwrap(), Sample { s: sf, v: 0.0, acc: 0.0, jerk: 0.0 });
            assert_eq!(eval(law, &p, t0 - 0.5).unwrap(), Sample { s: s0, v: 0.0, acc: 0.0, jerk: 0.0 });
            let f32p = LawParams { t0: t0 as f32, tf: tf as f32, s0: s0 as f32, sf: sf as f32 };
            assert_eq!(eval(law, &f32p, tf as f32).unwrap().s, sf as f32);
        }
    }
    let p = LawParams { t0: 0.0, tf: 2.0, s0: 0.0, sf: 1.0 };
    // Boundary derivatives follow the formulas.
    assert_eq!(eval(Law::Linear, &p, 2.0).unwrap().v, 0.5);
    assert_eq!(eval(Law::Linear, &p, 0.0).unwrap().v, 0.5);
    assert_eq!(eval(Law::Cubic, &p, 2.0).unwrap().v, 0.0);
    assert_eq!(eval(Law::Cubic, &p, 2.0).unwrap().acc, -6.0 / 4.0);
    assert_eq!(eval(Law::Quintic, &p, 2.0).unwrap().acc, 0.0);
    assert_eq!(eval(Law::Trapezoid, &p, 0.0).unwrap().acc, 4.5 / 4.0);
}

#[test]
fn cubic_reaches_pi_exactly_at_tf() {
    // method.md §9: the paper's "3.053 rad" came from reading the cubic at 0.9 s.
    let p = LawParams { t0: 0.0, tf: 1.0, s0: 0.0, sf: core::f64::consts::PI };
    assert_eq!(eval(Law::Cubic, &p, 1.0).unwrap().s, core::f64::consts::PI);
    let at_09 = eval(Law::Cubic, &p, 0.9).unwrap().s;
    assert!(close(at_09, 0.972 * core::f64::consts::PI, 1e-12) && close(at_09, 3.0536, 1e-4));
}

#[test]
fn quintic_and_trapezoid_closed_forms() {
    let (t0, tf, s0, sf) = (0.5, 2.5, 0.2, 1.4);
    let (tt, d) = (tf - t0, sf - s0);
    let p = LawParams { t0, tf, s0, sf };
    for k in 0..=40 {
        let tau = k as f64 / 40.0;
        let t = t0 + tau * tt;
        let q = eval(Law::Quintic, &p, t).unwrap();
        // method.md's corrected acceleration (the note prints τ³ in place of 2τ³).
        let acc = 60.0 * d * (tau - 3.0 * tau * tau + 2.0 * tau.powi(3)) / (tt * tt);
        assert!(close(q.acc, acc, 1e-12), "{tau}");
        assert!(close(q.v, 30.0 * d * (tau * tau - 2.0 * tau.powi(3) + tau.powi(4)) / tt, 1e-12));
        assert!(close(q.s, s0 + d * (10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5)), 1e-12));
        let c = eval(Law::Cubic, &p, t).unwrap();
        assert!(close(c.v, 6.0 * d * (tau - tau * tau) / tt, 1e-12));
        assert!(close(c.acc, 6.0 * d * (1.0 - 2.0 * tau) / (tt * tt), 1e-12));
    }
    // Trapezoid: cruise velocity, acceleration, and continuity at T/3, 2T/3.
    let vc = 1.5 * d / tt;
    let tr = LawPlan::new(Law::Trapezoid, &p).unwrap();
    assert!(close(tr.sample(t0 + 0.5 * tt).v, vc, 1e-14));
    assert!(close(tr.sample(t0 + 0.1 * tt).acc, 4.5 * d / (tt * tt), 1e-14));
    assert!(close(tr.sample(t0 + 0.9 * tt).acc, -4.5 * d / (tt * tt), 1e-14));
    for &b in &[1.0 / 3.0, 2.0 / 3.0] {
        let tb = t0 + b * tt;
        let (l, r) = (tr.sample(tb - 1e-9), tr.sample(tb + 1e-9));
        assert!(close(l.s, r.s, 1e-8) && close(l.v, r.v, 1e-8), "{b}");
        assert!(close(tr.position(tb), s0 + d * if b < 0.5 { 0.25 } else { 0.75 }, 1e-14));
    }
    // At the boundary itself the later phase applies.
    let pu = LawParams { t0: 0.0, tf: 3.0, s0: 0.0, sf: 1.0 };
    assert_eq!(eval(Law::Trapezoid, &pu, 1.0).unwrap().acc, 0.0);
    assert_eq!(eval(Law::Trapezoid, &pu, 2.0).unwrap().acc, -0.5);
    assert!(close(eval(Law::Trapezoid, &pu, 1.0).unwrap().v, 0.5, 1e-15));
}

#[test]
fn law_errors() {
    let bad = LawParams { t0: 1.0, tf: 1.0, s0: 0.0, sf: 1.0 };
    assert_eq!(eval(Law::Cubic, &bad, 0.5), Err(TrajError::EmptyInterval));
    let bad = LawParams { t0: 2.0, tf: 1.0, s0: 0.0, sf: 1.0 };
    assert_eq!(LawPlan::new(Law::Linear, &bad), Err(TrajError::EmptyInterval));
    let bad = LawParams { t0: 0.0, tf: f64::INFINITY, s0: 0.0, sf: 1.0 };
    assert_eq!(LawPlan::new(Law::Linear, &bad), Err(TrajError::NotFinite));
    let ok = LawParams { t0: 0.0, tf: 1.0, s0: 0.0, sf: 1.0 };
    assert_eq!(eval(Law::Linear, &ok, f64::NAN), Err(TrajError::NotFinite));
    assert!(format!("{}", TrajError::<f64>::EmptyInterval).contains("tf must be > t0"));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn law_derivatives_match_finite_differences(
        li in 0usize..4, t0 in -2.0f64..2.0, tt in 0.2f64..5.0, s0 in -2.0f64..2.0, d in -3.0f64..3.0,
        frac in 0.01f64..0.99,
    ) {
        let law = LAWS[li];
        let plan = LawPlan::new(law, &LawParams { t0, tf: t0 + tt, s0, sf: s0 + d }).unwrap();
        let t = t0 + frac * tt;
        let h = 1e-6 * tt;
        // Stay off the trapezoid's phase boundaries, where acc steps.
        let tau = frac;
        prop_assume!(law != Law::Trapezoid || ((3.0 * tau - 1.0).abs() > 1e-4 && (3.0 * tau - 2.0).abs() > 1e-4));
        let (lo, mid, hi) = (plan.sample(t - h), plan.sample(t), plan.sample(t + h));
        let scale = 1.0 + (d / tt).abs() * (1.0 + 1.0 / tt).powi(3);
        prop_assert!(((hi.s - lo.s) / (2.0 * h) - mid.v).abs() < 1e-5 * scale);
        prop_assert!(((hi.v - lo.v) / (2.0 * h) - mid.acc).abs() < 1e-4 * scale);
        prop_assert!(((hi.acc - lo.acc) / (2.0 * h) - mid.jerk).abs() < 1e-3 * scale);
        prop_assert_eq!(plan.position(t), mid.s);
    }
}

// ---------------------------------------------------------------- multi-joint plan

#[test]
fn multiplan_joints_arrive_together() {
    let start = [0.1, 0.7, -0.4];
    let target = [0.9, 0.2, 0.3];
    let sp = ShapeParams { ts: 2.5, a: 1.0, n: 3.0 };
    let plan = MultiPlan::new(&start, &target, &sp).unwrap();
    let g = shape64(2.5, 1.0, 3.0);
    assert_eq!(plan.duration(), 2.5);
    assert_eq!(plan.positions(2.5), target);
    assert_eq!(plan.positions(9.0), target);
    assert_eq!(plan.positions(0.0), start);
    assert_eq!(plan.positions(-1.0), start);
    for k in 1..50 {
        let t = 2.5 * k as f64 / 50.0;
        let pos = plan.positions(t);
        let st = plan.sample(t);
        let full = plan.sample_full(t);
        let gd = g.g_derivs(t);
        for j in 0..JOINTS {
            let d = target[j] - start[j];
            assert_eq!(pos[j], start[j] + d * g.g(t));
            assert_eq!(st[j].pos, pos[j]);
            assert!(close(st[j].vel, d * gd.v, 1e-14));
            assert!(close(full[j].acc, d * gd.acc, 1e-14) && close(full[j].jerk, d * gd.jerk, 1e-12));
        }
        // All joints sit at the same fraction of their move.
        let fr: Vec<f64> = (0..JOINTS).map(|j| (pos[j] - start[j]) / (target[j] - start[j])).collect();
        assert!(close(fr[0], fr[1], 1e-14) && close(fr[1], fr[2], 1e-14));
    }
    let ev = plan.end_velocities();
    for j in 0..JOINTS {
        assert!(close(ev[j], (target[j] - start[j]) * g.end_rate(), 1e-15));
    }
    let after = plan.sample(3.0);
    assert!(after.iter().zip(target.iter()).all(|(s, t)| s.pos == *t && s.vel == 0.0));

    // f32, as the chip runs it.
    let p32 =
        MultiPlan::<f32>::new(&[0.1, 0.7, -0.4], &[0.9, 0.2, 0.3], &ShapeParams { ts: 2.5, a: 1.0, n: 3.0 }).unwrap();
    assert_eq!(p32.positions(2.5), [0.9f32, 0.2, 0.3]);
    let mid = p32.positions(1.25);
    for (m, p) in mid.iter().zip(plan.positions(1.25)) {
        assert!((*m as f64 - p).abs() < 1e-6);
    }
}

#[test]
fn multiplan_rejects_overshoot_and_bad_input() {
    let start = [0.0; 3];
    let target = [1.0, 0.5, 0.2];
    match MultiPlan::new(&start, &target, &ShapeParams { ts: 3.0, a: 2.45, n: 2.0 }) {
        Err(TrajError::Overshoot { peak }) => assert!(peak > 19.0),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        MultiPlan::new(&start, &target, &ShapeParams { ts: 3.0, a: 2.5, n: 2.0 }),
        Err(TrajError::ShapeNotAdmissible { .. })
    ));
    assert_eq!(
        MultiPlan::new(&[0.0, f64::NAN, 0.0], &target, &ShapeParams { ts: 3.0, a: 1.0, n: 2.0 }),
        Err(TrajError::NotFinite)
    );
    // Refusal order: non-finite joints, then the profile, then a travel that
    // overflows.
    let bad = JointLaw::zat(&ShapeParams { ts: 3.0, a: 2.45, n: 2.0 }).unwrap();
    let good = JointLaw::zat(&ShapeParams { ts: 3.0, a: 1.0, n: 2.0 }).unwrap();
    assert_eq!(MultiPlan::with_law(&start, &[1.0, f64::INFINITY, 0.0], &bad), Err(TrajError::NotFinite));
    assert!(matches!(MultiPlan::with_law(&[-1e308; 3], &[1e308; 3], &bad), Err(TrajError::Overshoot { .. })));
    assert_eq!(MultiPlan::with_law(&[0.0, -1e308, 0.0], &[1.0, 1e308, 0.0], &good), Err(TrajError::NotFinite));
    let plan = MultiPlan::with_law(&start, &target, &good).unwrap();
    assert_eq!((*plan.start(), *plan.target(), *plan.law()), (start, target, good));
    // The smooth-stop shape is monotone for tₛ = 3, n = 2 (L·(tₛ − 1) ≤ 2) and ends at rest.
    let a = smooth_stop_a(3.0, 2.0).unwrap();
    let plan = MultiPlan::new(&start, &target, &ShapeParams { ts: 3.0, a, n: 2.0 }).unwrap();
    assert!(plan.end_velocities().iter().all(|v| v.abs() < 1e-12));
}

#[test]
fn multiplan_classic_laws() {
    let start = [0.1, 0.7, -0.4];
    let target = [0.9, 0.2, 0.3];
    let sp = ShapeParams { ts: 2.0, a: 0.5, n: 2.0 };
    for (kind, law) in [
        (LawKind::Quintic, Law::Quintic),
        (LawKind::Cubic, Law::Cubic),
        (LawKind::Trapezoid, Law::Trapezoid),
        (LawKind::Linear, Law::Linear),
    ] {
        let jl = JointLaw::from_kind(kind, &sp).unwrap();
        let plan = MultiPlan::with_law(&start, &target, &jl).unwrap();
        assert_eq!(plan.duration(), 2.0);
        assert_eq!(plan.positions(2.0), target);
        for k in 1..20 {
            let t = 0.1 * k as f64;
            let pos = plan.positions(t);
            let st = plan.sample(t);
            for j in 0..JOINTS {
                let want = eval(law, &LawParams { t0: 0.0, tf: 2.0, s0: start[j], sf: target[j] }, t).unwrap();
                assert!(close(pos[j], want.s, 1e-14), "{kind:?} {t} {j}");
                assert!(close(st[j].vel, want.v, 1e-14));
            }
        }
        let ev = plan.end_velocities();
        let lin = law == Law::Linear;
        for j in 0..JOINTS {
            let want = if lin { (target[j] - start[j]) / 2.0 } else { 0.0 };
            assert!(close(ev[j], want, 1e-15));
        }
    }
    let z = JointLaw::from_kind(LawKind::ZatPaper, &sp).unwrap();
    assert_eq!(z, JointLaw::Zat(shape64(2.0, 0.5, 2.0)));
    // The default law is the time-scaled reference shape, whatever (a, n).
    let z = JointLaw::from_kind(LawKind::Zat, &sp).unwrap();
    assert_eq!(z, JointLaw::Scaled(touch_arm::motion::scaled::ScaledZat::new(2.0).unwrap()));
    assert_eq!(JointLaw::<f64>::classic(Law::Cubic, 0.0), Err(TrajError::NonPositiveDuration));
}

// ------------------------------------------------- time-scaled ζ-a-tₛ (§10)

use touch_arm::motion::scaled::{ScaledZat, ACC_RATIO, JERK_RATIO, REF_N, REF_T0, VEL_RATIO};

/// The reference shape's a* = T₀ − log_n T₀, formed here.
fn ref_a() -> f64 {
    REF_T0 - REF_T0.ln() / REF_N.ln()
}

/// max over s ∈ [0, 1] of |d^k/ds^k G(s·T₀)| for k = 1, 2, 3, from a dense
/// grid refined by golden section around the best point (f64 shape).
fn ref_ratio(k: usize) -> f64 {
    let s = shape64(REF_T0, ref_a(), REF_N);
    let f = |x: f64| {
        let d = s.g_derivs(x * REF_T0);
        [d.v * REF_T0, d.acc * REF_T0 * REF_T0, d.jerk * REF_T0.powi(3)][k - 1].abs()
    };
    let n = 20_000;
    let best = (1..=n).map(|i| i as f64 / n as f64).max_by(|a, b| f(*a).total_cmp(&f(*b))).unwrap();
    let (mut lo, mut hi) = ((best - 1.0 / n as f64).max(0.0), (best + 1.0 / n as f64).min(1.0));
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (a, b) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if f(a) > f(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    f(0.5 * (lo + hi)).max(f(best))
}

#[test]
fn scaled_zat_ratios_are_the_reference_peaks() {
    // Rounded up, and within 1e-6 of the peaks.
    for (k, c) in [(1, VEL_RATIO), (2, ACC_RATIO), (3, JERK_RATIO)] {
        let peak = ref_ratio(k);
        assert!(c >= peak && c <= peak * (1.0 + 2e-6), "k={k}: constant {c} vs peak {peak}");
    }
    // The figures of docs/method.md §10 against the quintic (1.875, 10/√3, 60).
    assert!((VEL_RATIO / 1.875 - 1.077).abs() < 1e-3);
    assert!(((ACC_RATIO / (10.0 / 3f64.sqrt())).sqrt() - 1.072).abs() < 1e-3);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// g(t) is method.md's G of the reference shape at τ = t·T₀/tₛ (the
    /// independent printed-form reference), and each derivative is the
    /// reference's scaled by (T₀/tₛ)^k.
    #[test]
    fn scaled_zat_is_the_spec_shape_in_normalized_time(ts in 0.05f64..40.0, frac in -0.2f64..1.2) {
        let z = ScaledZat::new(ts).unwrap();
        let t = frac * ts;
        let k = REF_T0 / ts;
        let g = z.g(t);
        let want = g_ref(t * k, REF_T0, ref_a(), REF_N);
        prop_assert!((g - want).abs() <= 1e-13, "t={t} ts={ts}: {g} vs {want}");
        let d = z.g_derivs(t);
        prop_assert_eq!(d.s, g);
        prop_assert_eq!(z.g_rate(t), (d.s, d.v));
        if frac > 0.0 && frac < 1.0 {
            let r = shape64(REF_T0, ref_a(), REF_N).g_derivs(t * k);
            prop_assert!((d.v - r.v * k).abs() <= 1e-12 * (1.0 + d.v.abs()));
            prop_assert!((d.acc - r.acc * k * k).abs() <= 1e-12 * (1.0 + d.acc.abs()));
            prop_assert!((d.jerk - r.jerk * k * k * k).abs() <= 1e-12 * (1.0 + d.jerk.abs()));
            // Every rate within the ratios.
            prop_assert!(d.v >= 0.0 && d.v * ts <= VEL_RATIO);
            prop_assert!(d.acc.abs() * ts * ts <= ACC_RATIO);
            prop_assert!(d.jerk.abs() * ts.powi(3) <= JERK_RATIO);
        } else if frac <= 0.0 {
            prop_assert_eq!(d, Sample::at_rest(0.0));
        } else if frac > 1.0 {
            prop_assert_eq!(d, Sample::at_rest(1.0));
        }
    }

    /// Every move ends exactly on 1 at rest, in f64 and in f32 as the chip
    /// evaluates it, and starts flat.
    #[test]
    fn scaled_zat_ends_exactly_and_at_rest(ts in 0.05f64..40.0) {
        let z = ScaledZat::new(ts).unwrap();
        prop_assert_eq!(z.g(ts), 1.0);
        prop_assert!(z.end_rate().abs() * ts < 1e-12, "end rate {}", z.end_rate());
        prop_assert_eq!(z.g_rate(ts * 1.0001), (1.0, 0.0));
        let z32 = ScaledZat::new(ts as f32).unwrap();
        prop_assert_eq!(z32.g(ts as f32), 1.0f32);
        prop_assert!((z32.end_rate() * ts as f32).abs() < 2e-6, "f32 end rate {}", z32.end_rate());
        let near = z32.g_rate(ts as f32 * (1.0 - 1e-6));
        prop_assert!(near.0 <= 1.0 && (near.1 * ts as f32).abs() < 1e-4);
        let start = z.g_derivs(ts * 1e-3);
        prop_assert!(start.s < 1e-200 && start.v.abs() < 1e-200 && start.acc.abs() < 1e-200);
    }
}

#[test]
fn scaled_zat_refuses_bad_durations() {
    assert_eq!(ScaledZat::<f64>::new(0.0), Err(TrajError::NonPositiveDuration));
    assert_eq!(ScaledZat::<f64>::new(-1.0), Err(TrajError::NonPositiveDuration));
    assert_eq!(ScaledZat::<f64>::new(f64::NAN), Err(TrajError::NotFinite));
    assert_eq!(ScaledZat::<f32>::new(f32::INFINITY), Err(TrajError::NotFinite));
}
