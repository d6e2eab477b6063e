//! Lift over a via pose (issue #13 §1): the via pose's geometry, the move
//! through it at t_v with continuous velocity and acceleration, the limits on
//! a dense scan, the closed-form duration, and the refusals.

use core::f64::consts::{FRAC_PI_2, PI};

use reference::zat::Zat;
use touch_arm::geometry::ik::{fk3, Branch, Links};
use touch_arm::motion::lift::{LiftError, LiftPlan, LiftRequest, MAIN_REF_T, VIA_REF_T};
use touch_arm::motion::path::PathLimits;
use touch_arm::motion::via::c2_via_jerk;

const HOME: [f64; 3] = [FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2];

fn limits(speed: f64, accel: f64) -> PathLimits<f64> {
    PathLimits { min: [0.0, 0.0, -PI], max: [PI, PI, 0.0], speed: [speed; 3], accel: [accel; 3], ts_max: 30.0 }
}

fn request(target: [f64; 3], h: f64) -> LiftRequest<f64> {
    LiftRequest { start: HOME, target, h, links: Links::new(1.0, 1.0).unwrap(), branch: Branch::Minus, ts_min: 0.5 }
}

fn point(q: &[f64; 3]) -> [f64; 3] {
    let l = Links::new(1.0, 1.0).unwrap();
    let (x, y, z) = fk3(&l, q[0], q[1], q[2]);
    [x, y, z]
}

const TARGETS: [([f64; 3], f64); 3] = [([0.6, 0.9, -1.9], 0.2), ([2.4, 1.2, -1.2], 0.5), ([1.2, 0.3, -0.8], 0.05)];

#[test]
fn lift_passes_the_via_pose_h_above_the_higher_end() {
    // r = G(T/2) of the main reference, from the independent f64 reference.
    let (t0, n) = (MAIN_REF_T, (2.0 / (MAIN_REF_T - 1.0)).exp());
    let r_ref = Zat::new(t0, t0 - t0.ln() / n.ln(), n).g(t0 / 2.0);
    for (target, h) in TARGETS {
        let plan = LiftPlan::new(&request(target, h), &limits(2.94, 17.1)).unwrap();
        assert!((plan.r() - r_ref).abs() < 1e-14, "{} vs {r_ref}", plan.r());
        let (a, b) = (point(&HOME), point(&target));
        let via = plan.via_point();
        // Height h above the higher end; halfway in base rotation and in reach.
        assert!((via[2] - (a[2].max(b[2]) + h)).abs() < 1e-15, "{via:?}");
        let reach = |p: &[f64; 3]| p[0].hypot(p[1]);
        assert!((reach(via) - (reach(&a) + reach(&b)) / 2.0).abs() < 1e-15);
        assert!((via[1].atan2(via[0]) - (HOME[0] + target[0]) / 2.0).abs() < 1e-12);
        // S_v* = (θ_v − r·S_f)/(1 − r).
        for ((sv, v), f) in plan.sv().iter().zip(plan.via()).zip(&target) {
            assert!((sv - (v - r_ref * f) / (1.0 - r_ref)).abs() < 1e-13);
        }
        // The joints pass the via pose at t_v = tₛ/2, whose effector is that point.
        let (ts, tv) = (plan.ts(), plan.tv());
        assert_eq!(tv, ts / 2.0);
        let q = plan.positions(tv);
        assert!((0..3).all(|j| (q[j] - plan.via()[j]).abs() < 1e-12), "{q:?} vs {:?}", plan.via());
        let p = point(&q);
        assert!((0..3).all(|i| (p[i] - via[i]).abs() < 1e-12));
        // Exactly the start and the target at the ends, at rest.
        assert_eq!(plan.positions(0.0), HOME);
        assert_eq!(plan.positions(ts), target);
        let end = plan.samples(ts * (1.0 - 1e-9));
        assert!(end.iter().all(|s| s.v.abs() < 1e-6 && s.acc.abs() < 1e-3), "{end:?}");
        // Velocity and acceleration continuous at t_v; the jerk steps by
        // −(S_v − q0)·Gv‴ of the via reference (docs/method.md §8), scaled.
        let e = 1e-7 * ts;
        let (l, r) = (plan.samples(tv - e), plan.samples(tv + e));
        let kv = 2.0 * VIA_REF_T / ts;
        for j in 0..3 {
            assert!((l[j].v - r[j].v).abs() < 1e-6, "joint {j}: {} vs {}", l[j].v, r[j].v);
            assert!((l[j].acc - r[j].acc).abs() < 1e-4, "joint {j}: {} vs {}", l[j].acc, r[j].acc);
            let jump = -(plan.sv()[j] - HOME[j]) * c2_via_jerk(VIA_REF_T) * kv.powi(3);
            assert!((r[j].jerk - l[j].jerk - jump).abs() < 1e-3 * (1.0 + jump.abs()), "joint {j}: {jump}");
        }
    }
}

#[test]
fn lift_keeps_every_limit_and_is_as_short_as_they_allow() {
    for (speed, accel) in [(2.94, 17.1), (1.0, 4.0), (0.5, 40.0)] {
        let lim = limits(speed, accel);
        for (target, h) in TARGETS {
            let plan = LiftPlan::new(&request(target, h), &lim).unwrap();
            let ts = plan.ts();
            let n = 4000;
            let (mut vmax, mut amax) = (0.0f64, 0.0f64);
            for i in 0..=n {
                let t = ts * i as f64 / n as f64;
                for (j, s) in plan.samples(t).iter().enumerate() {
                    assert!(lim.min[j] <= s.s && s.s <= lim.max[j], "joint {j} at {t}: {}", s.s);
                    vmax = vmax.max(s.v.abs() / speed);
                    amax = amax.max(s.acc.abs() / accel);
                }
            }
            assert!(vmax <= 1.01 && amax <= 1.03, "{vmax} {amax}");
            // One of them binds (or the shortest move does).
            assert!(vmax > 0.98 || amax > 0.97 || ts == 0.5, "ts {ts}: {vmax} {amax}");
        }
    }
}

#[test]
fn lift_refusals_say_why() {
    let lim = limits(2.94, 17.1);
    for h in [0.0, -0.1, 0.51, f64::NAN] {
        assert_eq!(LiftPlan::new(&request([0.6, 0.9, -1.9], h), &lim), Err(LiftError::BadHeight), "h {h}");
    }
    // Both ends high and far: the via pose is beyond l2 + l3.
    let r = LiftRequest { start: [FRAC_PI_2, 1.2, -0.2], ..request([1.0, 1.2, -0.2], 0.5) };
    assert_eq!(LiftPlan::new(&r, &lim), Err(LiftError::ViaUnreachable));
    // Joints too slow for a lift within the longest move.
    match LiftPlan::new(&request([0.6, 0.9, -1.9], 0.3), &limits(0.01, 0.01)) {
        Err(LiftError::TooSlow { ts_min }) => assert!(ts_min > 30.0),
        other => panic!("{other:?}"),
    }
    // Over the elbow's straight pose: S_v* overshoots past 0 on the way.
    let stretched = LiftRequest { start: [FRAC_PI_2, 0.3, -0.05], ..request([1.2, 0.3, -0.05], 0.05) };
    assert!(matches!(LiftPlan::new(&stretched, &lim), Err(LiftError::JointLimit { .. } | LiftError::ViaUnreachable)));
    assert_eq!(LiftError::<f64>::BadHeight.to_string(), "lift height must be in (0, 0.5]");
}

#[test]
fn a_check_stepped_in_chunks_decides_what_the_one_shot_plan_does() {
    use touch_arm::motion::lift::LiftCheck;
    for (target, h) in TARGETS {
        for lim in [limits(2.94, 17.1), limits(0.05, 17.1), limits(2.94, 0.2)] {
            let whole = LiftPlan::new(&request(target, h), &lim);
            for chunk in [1u16, 7, 40] {
                let mut c = LiftCheck::new(&request(target, h), &lim).unwrap();
                let mut units = 0u32;
                let got = loop {
                    units += u32::from(chunk);
                    if let Some(r) = c.step(chunk) {
                        break r;
                    }
                };
                assert_eq!(got, whole, "chunk {chunk}");
                // One unit per scan point (513), decided in the last one.
                assert!(units >= 513 && units < 513 + u32::from(chunk), "{units} units in chunks of {chunk}");
            }
        }
    }
    // Refusals decide early: the first point past a joint's limit. The first
    // target's shoulder goes from π/2 down to 0.9 through the via pose's
    // 1.468, but the sum of the two terms first overshoots to 1.78 rad near
    // 0.35·tₛ: with its limit at 1.7 the move is refused by t_v (point 256).
    let mut narrow = limits(2.94, 17.1);
    narrow.max[1] = 1.7;
    let mut c = LiftCheck::new(&request(TARGETS[0].0, 0.2), &narrow).unwrap();
    assert_eq!(c.step(257), Some(Err(LiftError::JointLimit { joint: 1 })));
}

#[test]
fn the_via_frame_angles_are_the_positions() {
    for (target, h) in TARGETS {
        let plan = LiftPlan::new(&request(target, h), &limits(2.94, 17.1)).unwrap();
        for i in 0..=200 {
            let t = plan.ts() * f64::from(i) / 200.0;
            let (a, p) = (plan.angles(t), plan.positions(t));
            assert!((0..3).all(|j| (a[j] - p[j]).abs() < 1e-12), "t = {t}: {a:?} vs {p:?}");
        }
        assert_eq!(plan.angles(plan.ts()), target);
        assert_eq!(plan.start(), &HOME);
        assert_eq!(plan.target(), &target);
    }
}
