//! Issue #24, F4: the path rates' bound over a stretch (`jet_bound`) holds
//! against dense f64 sampling of `ik_jet` (10⁴ points a stretch) on random
//! lines and circles, near the rim and the base axis too; it closes in on
//! the sampled values as the stretch shrinks; and a planned move's peaks
//! (now bounds over the whole move) are at or above a dense sampling of the
//! move's own joint speeds and accelerations.

use core::f64::consts::PI;

use proptest::prelude::*;
use touch_arm::app::{CHECK_REFINE, CHECK_SAMPLES};
use touch_arm::geometry::ik::{Branch, Links};
use touch_arm::geometry::jet_bound::jet_bound;
use touch_arm::geometry::path::{ik_jet, Path, Vec3};
use touch_arm::motion::path::{law_jerk, Pace, PathArm, PathCheck, PathLimits, PathRequest, HALVING_BUDGET};
use touch_arm::motion::plan::{JointLaw, LawKind};
use touch_arm::motion::zat::ShapeParams;

fn cfg() -> ProptestConfig {
    ProptestConfig::with_cases(256)
}

/// A point at distance `r` from the shoulder, `rho` of it off the base axis
/// (as a share), at base angle `a`.
fn at(r: f64, share: f64, a: f64, up: bool) -> Vec3<f64> {
    let rho = r * share;
    let z = (r * r - rho * rho).max(0.0).sqrt();
    [rho * a.cos(), rho * a.sin(), if up { z } else { -z }]
}

/// Points anywhere in the shell, biased to the rim (r → l2 + l3 = 2) and
/// the base axis (share → 0).
fn point() -> impl Strategy<Value = Vec3<f64>> {
    (prop_oneof![0.3f64..1.95, 1.95f64..1.9999], prop_oneof![0.05f64..1.0, 0.001f64..0.05], -PI..PI, any::<bool>())
        .prop_map(|(r, sh, a, up)| at(r, sh, a, up))
}

fn path() -> impl Strategy<Value = Path<f64>> {
    prop_oneof![
        (point(), point()).prop_filter_map("degenerate", |(a, b)| Path::line(&a, &b).ok()),
        (point(), 0.01f64..0.6).prop_filter_map("crosses", |(c, r)| Path::circle(&c, r).ok()),
    ]
}

/// Max |θ′|, |θ″| per joint at n + 1 points of [sa, sb]; `None` if one is
/// unreachable or singular.
fn sampled(links: &Links<f64>, b: Branch, p: &Path<f64>, sa: f64, sb: f64, n: u32) -> Option<[(f64, f64); 3]> {
    let mut m = [(0.0f64, 0.0f64); 3];
    for k in 0..=n {
        let s = sa + (sb - sa) * f64::from(k) / f64::from(n);
        let jj = ik_jet(links, b, &p.jet(s)).ok()?;
        for (j, mj) in m.iter_mut().enumerate() {
            mj.0 = mj.0.max(jj.dq[j].abs());
            mj.1 = mj.1.max(jj.ddq[j].abs());
        }
    }
    Some(m)
}

fn links() -> impl Strategy<Value = (Links<f64>, Branch)> {
    (prop_oneof![Just(1.0f64), 0.5f64..1.5], any::<bool>()).prop_map(|(l3, minus)| {
        // Scaled so that the rim of the point strategy (r = 2) stays the rim.
        let l2 = 2.0 / (1.0 + l3);
        (Links::new(l2, l3 * l2).unwrap(), if minus { Branch::Minus } else { Branch::Plus })
    })
}

/// The soundness property of one stretch: [sa, sa + 10^w] of `p`.
fn holds_between_samples(p: &Path<f64>, l: &Links<f64>, b: Branch, sa: f64, w: f64) -> Result<(), TestCaseError> {
    let sb = (sa + 10f64.powf(w)).min(1.0);
    let Some(m) = sampled(l, b, p, sa, sb, 10_000) else { return Ok(()) };
    if let Some(bd) = jet_bound(l, b, p, sa, sb).map(|bd| bd.map(|(v, a)| (v.mag(), a.mag()))) {
        for j in 0..3 {
            // 1e-6: ik_jet's own rounding (a circle's base rate, 0, comes
            // out up to 3e-9 next to the axis).
            prop_assert!(
                bd[j].0 >= m[j].0 * (1.0 - 1e-9) - 1e-6 && bd[j].1 >= m[j].1 * (1.0 - 1e-9) - 1e-6,
                "joint {j}: bound {:?} below sampled {:?} on [{sa}, {sb}] of {p:?}",
                bd[j],
                m[j]
            );
        }
    }
    let p32 = match *p {
        Path::Line { from, to, .. } => Path::line(&from.map(|v| v as f32), &to.map(|v| v as f32)).ok(),
        Path::Circle { center, radius, .. } => Path::circle(&center.map(|v| v as f32), radius as f32).ok(),
    };
    let l32 = Links::new(l.l2() as f32, l.l3() as f32).unwrap();
    // The f32 inputs move the path by ~1e-7, which next to the base axis
    // moves the base's rate (K/ρ²) by more than any tolerance: sample the
    // path the chip is given (its f32 ends, in f64), so the comparison
    // measures the f32 arithmetic alone.
    let given = match *p {
        Path::Line { from, to, .. } => {
            Path::line(&from.map(|v| f64::from(v as f32)), &to.map(|v| f64::from(v as f32))).ok()
        }
        Path::Circle { center, radius, .. } => {
            Path::circle(&center.map(|v| f64::from(v as f32)), f64::from(radius as f32)).ok()
        }
    };
    let Some(m) = given.and_then(|g| sampled(l, b, &g, f64::from(sa as f32), f64::from(sb as f32), 10_000)) else {
        return Ok(());
    };
    if let Some(bd) =
        p32.and_then(|p32| jet_bound(&l32, b, &p32, sa as f32, sb as f32)).map(|bd| bd.map(|(v, a)| (v.mag(), a.mag())))
    {
        for j in 0..3 {
            // f32 rounding of the bound's own arithmetic (no directed
            // rounding, docs/method.md §8.1). With ρ² taken from the stretch's
            // ends (jet_bound.rs) 2·10⁴ cases stayed within 0.1 % of the
            // sampled rates (before, ρ² as a quadratic lost its digits next to
            // the axis: 31 % low, the test below); 0.2 % is allowed, which the
            // app's planning at 98 % of every limit (`speed_margin`) covers ten
            // times.
            let tol = 2e-3 * m[j].0.max(1.0);
            let tol2 = 2e-3 * m[j].1.max(1.0);
            prop_assert!(
                f64::from(bd[j].0) >= m[j].0 - tol && f64::from(bd[j].1) >= m[j].1 - tol2,
                "f32 joint {j}: bound {:?} below sampled {:?}",
                bd[j],
                m[j]
            );
        }
    }
    Ok(())
}

/// The case CI found (a line ending 6.3e-4 from the base axis): in f32
/// the quadratic form of ρ² lost all its digits there and the base's rate
/// bound came out 31 % below the sampled rate; ρ² from the stretch's ends
/// keeps it sound.
#[test]
fn the_f32_bound_holds_next_to_the_axis() {
    let from = [-0.7063786317333147, 1.5426529063897072, -0.9842696180615204];
    let to = [0.0006292529898424474, 0.0, -0.6292526752158738];
    let p = Path::line(&from, &to).unwrap();
    holds_between_samples(&p, &Links::new(1.0, 1.0).unwrap(), Branch::Plus, 0.976918644197445, -0.5).unwrap();
}

proptest! {
    #![proptest_config(cfg())]

    /// Sound: at or above every one of 10⁴ points of the stretch (f64 and
    /// the chip's f32, the latter within its rounding).
    #[test]
    fn the_bound_holds_between_samples(p in path(), (l, b) in links(), sa in 0.0f64..1.0, w in -4.0f64..-0.5) {
        holds_between_samples(&p, &l, b, sa, w)?;
    }

    /// Tight: the bound's excess over the sampled maximum shrinks with the
    /// stretch (first order: a tenth of the stretch, at most half the
    /// excess), which is what lets the scan halve a loose stretch.
    #[test]
    fn the_bound_closes_in_on_short_stretches(
        a in (0.6f64..1.8, 0.3f64..1.0, -PI..PI, any::<bool>()).prop_map(|(r, sh, a, up)| at(r, sh, a, up)),
        b in (0.6f64..1.8, 0.3f64..1.0, -PI..PI, any::<bool>()).prop_map(|(r, sh, a, up)| at(r, sh, a, up)),
        (l, br) in links(),
        sa in 0.0f64..0.999,
    ) {
        let Ok(p) = Path::line(&a, &b) else { return Ok(()) };
        let excess = |h: f64| -> Option<[(f64, f64); 3]> {
            let m = sampled(&l, br, &p, sa, sa + h, 200)?;
            let bd = jet_bound(&l, br, &p, sa, sa + h)?.map(|(v, a)| (v.mag(), a.mag()));
            Some([0, 1, 2].map(|j| (bd[j].0 - m[j].0, bd[j].1 - m[j].1)))
        };
        let (Some(e4), Some(e5)) = (excess(1e-4), excess(1e-5)) else { return Ok(()) };
        for j in 0..3 {
            prop_assert!(e5[j].0 <= 0.5 * e4[j].0 + 1e-7 && e5[j].1 <= 0.5 * e4[j].1 + 1e-7,
                "joint {j}: excess {:?} on 1e-4, {:?} on 1e-5", e4[j], e5[j]);
        }
    }
}

fn rim_line() -> impl Strategy<Value = Path<f64>> {
    // Lines from or to the nearly stretched arm, like the issue's.
    (
        (1.99f64..1.9999, 0.05f64..1.0, 0.2f64..2.9, any::<bool>()),
        (0.5f64..1.9, 0.05f64..1.0, 0.2f64..2.9, any::<bool>()),
        any::<bool>(),
    )
        .prop_filter_map("degenerate", |((r, sh, a, up), (r2, sh2, a2, up2), rev)| {
            let (p, q) = (at(r, sh, a, up), at(r2, sh2, a2, up2));
            if rev {
                Path::line(&q, &p).ok()
            } else {
                Path::line(&p, &q).ok()
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A plan's peaks are bounds: no instant of 2·10⁴ over the move is
    /// faster or accelerates more, with the chip's 24 scan intervals.
    #[test]
    fn a_plans_peaks_bound_the_whole_move(p in prop_oneof![rim_line(), path()], minus in any::<bool>(),
        law in prop_oneof![Just(LawKind::Zat), Just(LawKind::Quintic), Just(LawKind::Cubic), Just(LawKind::Trapezoid)]) {
        let arm = PathArm { links: Links::new(1.0, 1.0).unwrap(), branch: if minus { Branch::Minus } else { Branch::Plus } };
        let lim = PathLimits { min: [-10.0; 3], max: [10.0; 3], speed: [1.0; 3], accel: [1.0; 3], ts_max: 1e9 };
        let req = PathRequest { path: p, law, ts: 1.0, pace: Pace::SlowDown, samples: CHECK_SAMPLES, refine: CHECK_REFINE };
        let Ok(mut check) = PathCheck::new(&req, &arm, &lim) else { return Ok(()) };
        let Some(Ok(plan)) = check.step(u16::MAX) else { return Ok(()) };
        let (pk, ts) = (*plan.peaks(), plan.ts());
        let n = 20_000;
        let mut worst = 0.0f64;
        for k in 0..=n {
            let st = plan.state(ts * f64::from(k) / f64::from(n)).unwrap();
            for j in 0..3 {
                worst = worst.max(st.dq[j].abs().powi(2)).max(st.ddq[j].abs());
                // 1e-9: the rounding of a rate that is 0 (a circle's base).
                prop_assert!(st.dq[j].abs() <= pk.speed[j] * (1.0 + 1e-9) + 1e-9 && st.ddq[j].abs() <= pk.accel[j] * (1.0 + 1e-9) + 1e-9,
                    "joint {j} at t = {}: {} {} over {} {}", st.s, st.dq[j], st.ddq[j], pk.speed[j], pk.accel[j]);
                prop_assert!(st.dq[j].abs() <= 1.0 + 1e-6 && st.ddq[j].abs() <= 1.0 + 1e-6);
            }
        }
        // Not needlessly slow: a slowed-down move is at most 5 % longer than
        // the dense sampling's own shortest (the halving's 3 %, and the
        // deepest halving's reach next to the rim and the axis).
        // The trapezoid's g̈ is a step, bounded by its sign only: 8 %.
        let slack = if law == LawKind::Trapezoid { 1.08 } else { 1.05 };
        // A scan that spent its whole halving budget keeps the rest of its
        // bounds as they were: sound (above), looser.
        if ts > 1.0 && check.halvings() < HALVING_BUDGET {
            prop_assert!(ts <= slack * ts * worst.sqrt(), "ts {ts}, dense shortest {}", ts * worst.sqrt());
        }
    }

    /// The laws' largest |f‴| (`law_jerk`) at or above a 10⁶-point finite
    /// difference of their own f64 g̈, and within 1 % of it.
    #[test]
    fn the_laws_jerk_bounds_hold(k in prop_oneof![Just(LawKind::Zat), Just(LawKind::Quintic), Just(LawKind::Cubic)]) {
        let law = JointLaw::<f64>::from_kind(k, &ShapeParams { ts: 1.0, a: 0.0, n: 2.0 }).unwrap();
        let n = 1_000_000;
        let (mut prev, mut m) = (law.g_derivs(0.0).acc, 0.0f64);
        for i in 1..=n {
            let a = law.g_derivs(f64::from(i) / f64::from(n)).acc;
            m = m.max((a - prev).abs() * f64::from(n));
            prev = a;
        }
        let j = law_jerk(k).unwrap();
        prop_assert!(m <= j * (1.0 + 1e-9) && j <= 1.01 * m, "{k:?}: {m} vs {j}");
    }
}
