//! End-effector paths (the lab note): the path geometry, FK(IK(P(t))) = P(t),
//! the joint rates of `ik_jet` against finite differences of the IK, and the
//! plan-time checks refusing or slowing down what they must.

use core::f64::consts::PI;

use proptest::prelude::*;
use touch_arm::app::{CHECK_REFINE, CHECK_SAMPLES};
use touch_arm::geometry::ik::{fk3, ik3, Branch, Links};
use touch_arm::geometry::path::{ik_jet, JetError, Path, PathShapeError, Vec3};
use touch_arm::motion::path::{Pace, PathArm, PathCheck, PathError, PathLimits, PathPlan, PathRequest, REFINE_FULL};
use touch_arm::motion::plan::LawKind;

fn cfg() -> ProptestConfig {
    ProptestConfig::with_cases(128)
}

/// The app's arm: l2 = l3 = 1, elbow up, the servo defaults' angle ranges.
fn arm() -> PathArm<f64> {
    PathArm { links: Links::new(1.0, 1.0).unwrap(), branch: Branch::Minus }
}

fn limits(speed: f64, accel: f64) -> PathLimits<f64> {
    PathLimits { min: [0.0, 0.0, -PI], max: [PI, PI, 0.0], speed: [speed; 3], accel: [accel; 3], ts_max: 60.0 }
}

fn req(path: Path<f64>, law: LawKind, ts: f64, pace: Pace) -> PathRequest<f64> {
    PathRequest { path, law, ts, pace, samples: 400, refine: REFINE_FULL }
}

fn dist(a: &Vec3<f64>, b: &Vec3<f64>) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// A point in front of the arm, well inside the reachable shell.
fn point() -> impl Strategy<Value = Vec3<f64>> {
    (0.5f64..1.6, 0.35f64..2.8, 0.0f64..0.9).prop_map(|(r, a, z)| {
        let rho = (r * r - z * z).max(0.04).sqrt();
        [rho * a.cos(), rho * a.sin(), z]
    })
}

#[test]
fn line_and_circle_points_are_the_formulas() {
    let l = Path::line(&[0.5, 0.2, 0.1], &[-0.3, 0.9, 0.6]).unwrap();
    for k in 0..=10 {
        let s = k as f64 / 10.0;
        let p = l.point(s);
        let want = [0.5 - 0.8 * s, 0.2 + 0.7 * s, 0.1 + 0.5 * s];
        assert!(dist(&p, &want) < 1e-15, "{p:?} vs {want:?}");
        let j = l.jet(s);
        assert_eq!((j.dp, j.ddp), ([-0.8, 0.7, 0.5], [0.0; 3]));
    }
    // Circle in the vertical plane through the base axis and C = (0.6, 0.8, 0.5):
    // e_ρ = (0.6, 0.8, 0); start at C + r·e_ρ, rising first, back at the start.
    let c = Path::circle(&[0.6, 0.8, 0.5], 0.2).unwrap();
    assert!(dist(&c.start(), &[0.72, 0.96, 0.5]) < 1e-15);
    assert!(dist(&c.point(0.25), &[0.6, 0.8, 0.7]) < 1e-15);
    assert!(dist(&c.point(0.5), &[0.48, 0.64, 0.5]) < 1e-15);
    assert!(dist(&c.end(), &c.start()) < 1e-15);
    for k in 0..40 {
        let s = k as f64 / 40.0;
        let p = c.point(s);
        // On the sphere of radius r around C, and in the plane (0.8·x − 0.6·y = 0).
        assert!((dist(&p, &[0.6, 0.8, 0.5]) - 0.2).abs() < 1e-15);
        assert!((0.8 * p[0] - 0.6 * p[1]).abs() < 1e-15);
        // dP/ds and d²P/ds² against central differences.
        let (h, j) = (1e-5, c.jet(s));
        let (pm, pp) = (c.point(s - h), c.point(s + h));
        for i in 0..3 {
            assert!(((pp[i] - pm[i]) / (2.0 * h) - j.dp[i]).abs() < 1e-8);
            assert!(((pp[i] - 2.0 * p[i] + pm[i]) / (h * h) - j.ddp[i]).abs() < 1e-3);
        }
    }
}

#[test]
fn path_shapes_refuse_what_no_arm_can_follow() {
    assert_eq!(Path::line(&[0.5, 0.5, 0.2], &[0.5, 0.5, 0.2]), Err(PathShapeError::Degenerate));
    // Through the base axis in the top view (at any height).
    assert_eq!(Path::line(&[0.5, 0.5, 0.2], &[-0.5, -0.5, 0.9]), Err(PathShapeError::CrossesBaseAxis));
    assert_eq!(Path::line(&[0.0, 0.0, 0.5], &[0.5, 0.5, 0.5]), Err(PathShapeError::CrossesBaseAxis));
    // Vertical segments off the axis are fine.
    assert!(Path::line(&[0.5, 0.5, 0.2], &[0.5, 0.5, 0.9]).is_ok());
    assert_eq!(Path::line(&[f64::NAN, 0.5, 0.2], &[0.5, 0.5, 0.9]), Err(PathShapeError::NotFinite));
    assert_eq!(Path::circle(&[0.0, 0.0, 0.5], 0.1), Err(PathShapeError::CrossesBaseAxis));
    assert_eq!(Path::circle(&[0.3, 0.4, 0.5], 0.5), Err(PathShapeError::CrossesBaseAxis));
    assert_eq!(Path::circle(&[0.3, 0.4, 0.5], 0.0), Err(PathShapeError::Degenerate));
    assert_eq!(Path::circle(&[0.3, 0.4, 0.5], f64::INFINITY), Err(PathShapeError::NotFinite));
}

/// One-sided-free central differences of the IK along the path.
fn fd_joint_rates(path: &Path<f64>, s: f64, h: f64) -> ([f64; 3], [f64; 3]) {
    let a = arm();
    let q = |s: f64| {
        let p = path.point(s);
        let q = ik3(&a.links, p[0], p[1], p[2], a.branch).unwrap();
        [q.th1, q.th2, q.th3]
    };
    let (m, c, p) = (q(s - h), q(s), q(s + h));
    let d = [0, 1, 2].map(|i| (p[i] - m[i]) / (2.0 * h));
    let dd = [0, 1, 2].map(|i| (p[i] - 2.0 * c[i] + m[i]) / (h * h));
    (d, dd)
}

proptest! {
    #![proptest_config(cfg())]

    #[test]
    fn fk_of_ik_is_the_path_point(a in point(), b in point(), s in 0.0f64..=1.0) {
        let Ok(line) = Path::line(&a, &b) else { return Ok(()) };
        let p = line.point(s);
        let ar = arm();
        // Every point of a segment between two points in the shell: the
        // shoulder-distance is ≤ the larger end's and ≥ its closest approach.
        if let Ok(q) = ik3(&ar.links, p[0], p[1], p[2], ar.branch) {
            let f = fk3(&ar.links, q.th1, q.th2, q.th3);
            prop_assert!(dist(&[f.0, f.1, f.2], &p) < 1e-12, "{p:?} -> {f:?}");
        }
        let Ok(circle) = Path::circle(&a, 0.1) else { return Ok(()) };
        let p = circle.point(s);
        if let Ok(q) = ik3(&ar.links, p[0], p[1], p[2], ar.branch) {
            let f = fk3(&ar.links, q.th1, q.th2, q.th3);
            prop_assert!(dist(&[f.0, f.1, f.2], &p) < 1e-12, "{p:?} -> {f:?}");
        }
    }

    #[test]
    fn joint_rates_match_finite_differences(a in point(), b in point(), s in 0.05f64..0.95) {
        let Ok(line) = Path::line(&a, &b) else { return Ok(()) };
        let ar = arm();
        for path in [line, Path::circle(&a, 0.15).unwrap_or(line)] {
            let Ok(j) = ik_jet(&ar.links, ar.branch, &path.jet(s)) else { continue };
            // Keep away from the singular poses, where differences are meaningless.
            if j.q[2].sin().abs() < 0.2 || j.dq.iter().chain(j.ddq.iter()).any(|v| v.abs() > 50.0) {
                continue;
            }
            let (d, dd) = fd_joint_rates(&path, s, 1e-4);
            for i in 0..3 {
                prop_assert!((d[i] - j.dq[i]).abs() < 1e-5 * (1.0 + j.dq[i].abs()), "joint {i}: {d:?} vs {:?}", j.dq);
                prop_assert!((dd[i] - j.ddq[i]).abs() < 1e-3 * (1.0 + j.ddq[i].abs()), "joint {i}: {dd:?} vs {:?}", j.ddq);
            }
        }
    }

    /// An accepted move keeps every joint within its angle, speed and
    /// acceleration limits on a scan four times as dense as the plan's, and
    /// the effector on the path; a slowed-down move is as short as it may be
    /// (within 1 %).
    #[test]
    fn accepted_moves_keep_the_limits(a in point(), b in point(), ts in 0.5f64..4.0, law in 0usize..4) {
        let law = [LawKind::Zat, LawKind::Quintic, LawKind::Cubic, LawKind::Trapezoid][law];
        let Ok(line) = Path::line(&a, &b) else { return Ok(()) };
        // Slow servos: most moves must be slowed down.
        let lim = limits(1.5, 6.0);
        let plan = match PathPlan::new(&req(line, law, ts, Pace::SlowDown), &arm(), &lim) {
            Ok(p) => p,
            // Refusals must name a geometric reason: slowing down covers the rates.
            Err(e) => {
                prop_assert!(matches!(e, PathError::Unreachable { .. } | PathError::JointLimit { .. } | PathError::Singular { .. } | PathError::TooSlow { .. }), "{e}");
                return Ok(());
            }
        };
        prop_assert!(plan.ts() >= ts);
        let n = 1600;
        for i in 0..=n {
            let t = plan.ts() * i as f64 / n as f64;
            let st = plan.state(t).unwrap();
            for j in 0..3 {
                prop_assert!(lim.min[j] <= st.q[j] && st.q[j] <= lim.max[j]);
                prop_assert!(st.dq[j].abs() <= lim.speed[j] * 1.02, "joint {j} speed {} at t {t}", st.dq[j]);
                prop_assert!(st.ddq[j].abs() <= lim.accel[j] * 1.05, "joint {j} accel {} at t {t}", st.ddq[j]);
            }
            let f = fk3(&arm().links, st.q[0], st.q[1], st.q[2]);
            prop_assert!(dist(&[f.0, f.1, f.2], &line.point(st.s)) < 1e-12);
        }
        if plan.ts() > ts {
            // Slowed down: 1 % shorter is refused by the same scan. Not
            // 0.1 %: the scan halves a stretch while its bound is over 1/16
            // above the rates visited, in (speed/limit)² or accel/limit,
            // and which of the two binds changes with tₛ, so a move slowed
            // from another tₛ can end a little above the shortest a check
            // at fixed tₛ accepts (the saved case: 1.6910 s slowed from
            // 1.288 s, 1.6891 s from 0.5 s, 1.6890 s the shortest accepted).
            let shorter = PathPlan::new(&req(line, law, plan.ts() * 0.99, Pace::Refuse), &arm(), &lim);
            prop_assert!(matches!(shorter, Err(PathError::Speed { .. } | PathError::Accel { .. })), "{shorter:?}");
        }
    }
}

#[test]
fn the_move_starts_and_ends_at_rest_on_the_path_ends() {
    let line = Path::line(&[1.0, 0.3, 0.2], &[-0.4, 0.9, 0.7]).unwrap();
    let plan = PathPlan::new(&req(line, LawKind::Zat, 3.0, Pace::Refuse), &arm(), &limits(3.0, 17.45)).unwrap();
    let (s0, s1) = (plan.state(0.0).unwrap(), plan.state(3.0).unwrap());
    assert_eq!(s0.p, [1.0, 0.3, 0.2]);
    assert!(dist(&s1.p, &[-0.4, 0.9, 0.7]) < 1e-15);
    assert!(s0.dq.iter().all(|v| v.abs() < 1e-12), "{:?}", s0.dq);
    // The time-scaled ζ-a-tₛ stops smoothly (its end rate is 0 up to rounding).
    assert!(s1.dq.iter().all(|v| v.abs() < 1e-9), "{:?}", s1.dq);
    // Joint speeds are dq/ds·ġ: against central differences in time.
    for &t in &[0.7, 1.5, 2.2] {
        let h = 1e-5;
        let (m, c, p) = (plan.state(t - h).unwrap(), plan.state(t).unwrap(), plan.state(t + h).unwrap());
        for j in 0..3 {
            assert!(((p.q[j] - m.q[j]) / (2.0 * h) - c.dq[j]).abs() < 1e-6, "joint {j} at {t}");
            assert!(((p.q[j] - 2.0 * c.q[j] + m.q[j]) / (h * h) - c.ddq[j]).abs() < 1e-3, "joint {j} at {t}");
        }
    }
    // A circle ends where it started.
    let circle = Path::circle(&[0.8, 0.6, 0.4], 0.2).unwrap();
    let plan = PathPlan::new(&req(circle, LawKind::Quintic, 4.0, Pace::SlowDown), &arm(), &limits(3.0, 17.45)).unwrap();
    let (a, b) = (plan.state(0.0).unwrap(), plan.state(plan.ts()).unwrap());
    assert!(dist(&a.p, &b.p) < 1e-15 && (0..3).all(|j| (a.q[j] - b.q[j]).abs() < 1e-12));
    assert!(b.dq.iter().all(|v| v.abs() < 1e-12));
}

#[test]
fn plan_checks_refuse_with_the_reason() {
    let (a, lim) = (arm(), limits(3.0, 17.45));
    let plan = |p: Path<f64>, ts: f64, pace: Pace| PathPlan::new(&req(p, LawKind::Zat, ts, pace), &a, &lim);
    // Beyond the reach of l2 + l3 = 2.
    let far = Path::line(&[1.0, 0.5, 0.2], &[1.0, 2.0, 0.2]).unwrap();
    match plan(far, 3.0, Pace::SlowDown) {
        // Leaves the shell where ρ² + z² = 4: ρ = √3.96 at y = √(3.96 − 1).
        Err(PathError::Unreachable { s }) => assert!((0.5 + 1.5 * s - (3.96f64 - 1.0).sqrt()).abs() < 0.01, "{s}"),
        other => panic!("{other:?}"),
    }
    // Behind the arm: the base would have to go below 0.
    let behind = Path::line(&[1.0, 0.5, 0.2], &[1.0, -0.5, 0.2]).unwrap();
    assert!(matches!(plan(behind, 3.0, Pace::SlowDown), Err(PathError::JointLimit { joint: 0, .. })));
    // Below the shoulder: the elbow-up arm's shoulder leaves [0, π] first.
    let low = Path::line(&[1.0, 0.5, 0.2], &[1.0, 0.5, -1.3]).unwrap();
    assert!(matches!(plan(low, 3.0, Pace::SlowDown), Err(PathError::JointLimit { joint: 1, .. })));
    // Passing close by the base axis: the base's rate grows like 1/ρ.
    let near_axis = Path::line(&[0.6, 0.02, 0.5], &[-0.6, 0.02, 0.5]).unwrap();
    let refused = plan(near_axis, 2.0, Pace::Refuse);
    let ts_min = match refused {
        Err(PathError::Speed { joint: 0, ts_min }) | Err(PathError::Accel { joint: 0, ts_min }) => ts_min,
        other => panic!("{other:?}"),
    };
    assert!(ts_min > 2.0);
    let slowed = plan(near_axis, 2.0, Pace::SlowDown).unwrap();
    assert!(slowed.ts() >= ts_min && slowed.ts() < ts_min * 1.001, "{} vs {ts_min}", slowed.ts());
    let p = slowed.peaks();
    assert!(p.speed[0] <= 3.0 && p.accel[0] <= 17.45);
    assert!(p.speed[0] > 2.9 || p.accel[0] > 17.0, "one limit binds: {p:?}");
    // So close to the axis that even ts_max is too short.
    let closer = Path::line(&[0.6, 1e-4, 0.5], &[-0.6, 1e-4, 0.5]).unwrap();
    assert!(matches!(plan(closer, 2.0, Pace::SlowDown), Err(PathError::TooSlow { .. } | PathError::Singular { .. })));
    // Onto the rim (|P| = l2 + l3): the elbow ends straight, where the rates
    // are unbounded (1/sin θ3), and the move is refused, not clamped.
    let to_rim = Path::line(&[1.0, 0.5, 0.3], &[1.6, 1.2, 0.0]).unwrap();
    let r = plan(to_rim, 3.0, Pace::SlowDown);
    assert!(matches!(r, Err(PathError::Singular { .. } | PathError::TooSlow { .. })), "{r:?}");
    // Just inside it the law's stop at rest keeps the rates finite: slowed down, not refused.
    let near_rim = Path::line(&[1.0, 0.5, 0.3], &[1.6 * 0.995, 1.2 * 0.995, 0.0]).unwrap();
    let slowed = plan(near_rim, 1.0, Pace::SlowDown).unwrap();
    assert!(slowed.ts() > 1.0);
    // The papers' own form is not scalable: refused, not silently replaced.
    let ok = Path::line(&[1.0, 0.5, 0.2], &[0.5, 1.0, 0.6]).unwrap();
    assert_eq!(
        PathPlan::new(&req(ok, LawKind::ZatPaper, 3.0, Pace::SlowDown), &a, &lim),
        Err(PathError::LawNotScalable)
    );
    assert!(PathPlan::new(&req(ok, LawKind::Zat, 3.0, Pace::Refuse), &a, &lim).is_ok());
    let bad = PathLimits { speed: [3.0, 0.0, 3.0], ..lim };
    assert_eq!(PathPlan::new(&req(ok, LawKind::Zat, 3.0, Pace::Refuse), &a, &bad), Err(PathError::BadLimits));
    // A singular point itself has no rates.
    let straight = Path::line(&[2.0, 0.0, 0.0], &[1.0, 0.5, 0.0]).unwrap();
    assert_eq!(ik_jet(&a.links, a.branch, &straight.jet(0.0)), Err(JetError::Singular));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The check spread over many small steps (as the chip would over
    /// frames) decides exactly what the one-shot plan decides, in a number of
    /// units known in advance: the grid, then per critical point (the path's
    /// two and its two ends) one search,
    /// its instant, two sides per refinement step and the move to the next
    /// point, then the bounds between the points (issue #24, F4: the instant
    /// 0 and one unit per stretch, a stretch halved at most 12 times deep:
    /// at most 2¹³ − 1 stretches per grid interval), and the end (one scan, slowed
    /// down or not).
    #[test]
    fn stepped_check_equals_the_one_shot_plan(a in point(), b in point(), ts in 0.3f64..4.0, chunk in 1u16..40) {
        let Ok(line) = Path::line(&a, &b) else { return Ok(()) };
        for (pace, refine) in [(Pace::SlowDown, 24), (Pace::Refuse, 24), (Pace::SlowDown, REFINE_FULL)] {
            let r = PathRequest { path: line, law: LawKind::Zat, ts, pace, samples: 48, refine };
            let (arm, lim) = (arm(), limits(1.5, 6.0));
            let want = PathPlan::new(&r, &arm, &lim);
            let mut check = PathCheck::new(&r, &arm, &lim).unwrap();
            let mut calls = 0u32;
            let got = loop {
                calls += 1;
                if let Some(g) = check.step(chunk) {
                    break g;
                }
            };
            prop_assert_eq!(got, want);
            // Asked again, the same answer, no more work.
            prop_assert_eq!(check.step(chunk), Some(want));
            let per_scan = 49 + 4 * (3 + 2 * (u32::from(refine) - 3)) + 1 + 48 * 8191 + 1;
            prop_assert!(calls <= per_scan.div_ceil(u32::from(chunk)) + 1, "{calls} calls of {chunk}");
        }
    }
}

/// A check decides within a known number of units whatever the path
/// (`HALVING_BUDGET`): the app's check (its 24 samples and the critical
/// instants, f32) of the trapezoid on links of 69 and 100 mm (0.81657 and
/// 1.18343 arm units), a line folding the elbow from −127.42° to −169.9°,
/// halved its bounds for 18 195 units before the budget (minutes on the
/// chip); now its 256 halvings end it in 575 units (25 grid visits, 3 per
/// critical point and end, the step to the bounds, the instant 0, 24
/// stretches and 2 per halving: the most any path takes), and the plan it
/// accepts, 1.33 s, slower than the unbudgeted 1.081 s, keeps every limit
/// on a scan 50 times as dense (the bounds stay sound, only looser). The
/// smooth laws on the same line spend 43–49 halvings.
#[test]
fn the_scan_decides_within_its_halving_budget() {
    use touch_arm::geometry::ik::fk3_pose;
    use touch_arm::motion::path::HALVING_BUDGET;
    let links = Links::new(69.0f32 / 84.5, 100.0f32 / 84.5).unwrap();
    let d = |v: f32| v.to_radians();
    let (a, b) = ([d(91.65), d(127.78), d(-127.42)], [d(88.1), d(115.8), d(-169.9)]);
    let line = Path::line(&fk3_pose(&links, &a), &fk3_pose(&links, &b)).unwrap();
    let lim = PathLimits {
        min: [0.0, 0.0, -core::f32::consts::PI],
        max: [core::f32::consts::PI, core::f32::consts::PI, 0.0],
        speed: [3.0 * 0.98; 3],
        accel: [17.453_292 * 0.98; 3],
        ts_max: 30.0,
    };
    let arm = PathArm { links, branch: Branch::Minus };
    for law in [LawKind::Trapezoid, LawKind::Zat, LawKind::Quintic] {
        let r = PathRequest {
            path: line,
            law,
            ts: 0.5,
            pace: Pace::SlowDown,
            samples: CHECK_SAMPLES,
            refine: CHECK_REFINE,
        };
        let mut c = PathCheck::new(&r, &arm, &lim).unwrap();
        let mut units = 0u32;
        let plan = loop {
            units += 1;
            if let Some(p) = c.step(1) {
                break p.unwrap();
            }
            assert!(units < 800, "{law:?}: no verdict after {units} units");
        };
        assert!(c.halvings() <= HALVING_BUDGET);
        if law == LawKind::Trapezoid {
            assert_eq!(c.halvings(), HALVING_BUDGET, "the case spends the whole budget");
            assert_eq!(units, 25 + 4 * 3 + 1 + 1 + 24 + 2 * u32::from(HALVING_BUDGET), "{units} units");
            assert!(plan.ts() > 1.08, "{}", plan.ts());
        } else {
            assert!(c.halvings() < 64, "{law:?}: {}", c.halvings());
        }
        let n = 1200;
        for i in 0..=n {
            let st = plan.state(plan.ts() * i as f32 / n as f32).unwrap();
            for j in 0..3 {
                assert!(st.dq[j].abs() <= lim.speed[j] * 1.0001, "{law:?} joint {j} speed {}", st.dq[j]);
                assert!(st.ddq[j].abs() <= lim.accel[j] * 1.0001, "{law:?} joint {j} accel {}", st.ddq[j]);
            }
        }
    }
}
