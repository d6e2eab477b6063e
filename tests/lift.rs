//! Lift over a via pose (issue #13 §1): the via pose's geometry, the move
//! through it at t_v with continuous velocity and acceleration, the limits on
//! a dense scan, the closed-form duration, and the refusals; the check's
//! hull tables against the 513-point scan they stand for (issue #22 §1).

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
                // One unit per hull vertex, decided in the last one.
                let n = touch_arm::motion::lift_hull::UNITS as u32;
                assert!(units >= n && units < n + u32::from(chunk), "{units} units in chunks of {chunk}");
            }
        }
    }
    // Refusals decide early: at the first vertex past a joint's limit, among
    // the angles' (the first units). The first target's shoulder goes from
    // π/2 down to 0.9 through the via pose's 1.468, but the sum of the two
    // terms first overshoots to 1.78 rad near 0.35·tₛ: with its limit at 1.7
    // the move is refused before any rate is visited.
    let mut narrow = limits(2.94, 17.1);
    narrow.max[1] = 1.7;
    let mut c = LiftCheck::new(&request(TARGETS[0].0, 0.2), &narrow).unwrap();
    let angles = touch_arm::motion::lift_hull::ANGLE.len() as u16;
    assert_eq!(c.step(angles), Some(Err(LiftError::JointLimit { joint: 1 })));
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

/// The scan the check's tables summarize: per point i = 0..=512 of the
/// normalized move, (Gv, G), their rates and their second derivatives (the
/// via term's reference over the first half, scaled ×4, the main term's ×3),
/// from the f64 shapes, rounded to f32.
fn scan_points() -> [Vec<(f32, f32)>; 3] {
    use touch_arm::motion::lift::LIFT_SCAN;
    use touch_arm::motion::via::c2_ln_base;
    use touch_arm::motion::zat::Shape;
    let reference = |t: f64| Shape::smooth_stop(t, c2_ln_base(t).unwrap().exp()).unwrap();
    let (gv, g) = (reference(VIA_REF_T), reference(MAIN_REF_T));
    let (kv, k) = (2.0 * VIA_REF_T, MAIN_REF_T);
    let mut sets = [Vec::new(), Vec::new(), Vec::new()];
    for i in 0..=LIFT_SCAN {
        let t = f64::from(i) / f64::from(LIFT_SCAN);
        // At tₛ the move is at the target, at rest (`LiftPlan::samples`).
        let (dv, dg) = if i == LIFT_SCAN {
            (touch_arm::motion::Sample::at_rest(1.0), touch_arm::motion::Sample::at_rest(1.0))
        } else {
            (gv.g_derivs(t * kv), g.g_derivs(t * k))
        };
        sets[0].push((dv.s as f32, dg.s as f32));
        sets[1].push(((dv.v * kv) as f32, (dg.v * k) as f32));
        sets[2].push(((dv.acc * kv * kv) as f32, (dg.acc * k * k) as f32));
    }
    sets
}

/// The strict vertices of the convex hull of `pts` (with their negatives if
/// `symmetric`, one of each opposite pair kept), as indices into `pts`, in
/// the scan's order. Andrew's monotone chain; the products of f32 values are
/// exact in f64, so collinear points are dropped exactly.
fn hull(pts: &[(f32, f32)], symmetric: bool) -> Vec<usize> {
    // (x, y, index into `pts`); a negated point keeps its original's index.
    type P = (f64, f64, usize);
    let mut all: Vec<P> = pts.iter().enumerate().map(|(i, &(x, y))| (f64::from(x), f64::from(y), i)).collect();
    if symmetric {
        all.extend(pts.iter().enumerate().map(|(i, &(x, y))| (-f64::from(x), -f64::from(y), i)));
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    all.dedup_by(|a, b| a.0 == b.0 && a.1 == b.1);
    let cross = |o: &P, a: &P, b: &P| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let chain = |it: &mut dyn Iterator<Item = &P>| {
        let mut h: Vec<P> = Vec::new();
        for p in it {
            while h.len() >= 2 && cross(&h[h.len() - 2], &h[h.len() - 1], p) <= 0.0 {
                h.pop();
            }
            h.push(*p);
        }
        h.pop();
        h
    };
    let mut v = chain(&mut all.iter());
    v.extend(chain(&mut all.iter().rev()));
    let mut idx: Vec<usize> = v.iter().map(|p| p.2).collect();
    idx.sort_unstable();
    idx.dedup();
    idx
}

#[test]
fn the_checks_tables_are_the_hulls_of_the_scan() {
    use touch_arm::motion::lift_hull::{ACCEL, ANGLE, SPEED};
    let sets = scan_points();
    let tables: Vec<Vec<[u32; 2]>> = sets
        .iter()
        .enumerate()
        .map(|(k, pts)| hull(pts, k > 0).iter().map(|&i| [pts[i].0.to_bits(), pts[i].1.to_bits()]).collect())
        .collect();
    let have = [ANGLE.to_vec(), SPEED.to_vec(), ACCEL.to_vec()];
    if have[..] == tables[..] {
        return;
    }
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/motion/lift_hull.rs");
    if std::env::var_os("LIFT_HULL_WRITE").is_none() {
        panic!("src/motion/lift_hull.rs differs from the hulls of the scan: `LIFT_HULL_WRITE=1 cargo test --test lift` rewrites it");
    }
    let docs = [
        "The angles' hull: (Gv, G) as f32 bits.",
        "The speeds' hull (one of each opposite pair).",
        "The accelerations' hull (one of each opposite pair).",
    ];
    let mut gen = String::from("// BEGIN GENERATED (tests/lift.rs, `LIFT_HULL_WRITE=1`)\n");
    for ((name, doc), rows) in ["ANGLE", "SPEED", "ACCEL"].iter().zip(docs).zip(&tables) {
        gen += &format!(
            "/// {doc}\n#[cfg_attr(target_arch = \"avr\", link_section = \".progmem.data\")]\npub static {name}: [[u32; 2]; {}] = [\n",
            rows.len()
        );
        for r in rows {
            gen += &format!("    [0x{:08X}, 0x{:08X}],\n", r[0], r[1]);
        }
        gen += "];\n";
    }
    gen += "// END GENERATED\n";
    let src = std::fs::read_to_string(path).unwrap();
    let (head, _) = src.split_once("// BEGIN GENERATED").unwrap();
    std::fs::write(path, format!("{head}{gen}")).unwrap();
    panic!("rewrote src/motion/lift_hull.rs: run the tests again");
}

/// What the 513-point scan decides for `r` under `lim` (the check before its
/// tables): every point inside the angle limits, the peaks at tₛ = 1 s, the
/// closed-form duration. `None` when a decision sits within 1e-9 of a limit
/// (the tables' f32 rounding may decide it either way). The points come
/// from a plan under wide limits, at its own duration T0, rescaled.
fn scan_decision(r: &LiftRequest<f64>, lim: &PathLimits<f64>) -> Option<Result<f64, LiftError<f64>>> {
    let wide = PathLimits { min: [-10.0; 3], max: [10.0; 3], speed: [1e9; 3], accel: [1e9; 3], ts_max: 1e9 };
    let plan = match LiftPlan::new(r, &wide) {
        Ok(p) => p,
        Err(e) => return Some(Err(e)),
    };
    let t0 = plan.ts();
    let (mut v, mut a) = ([0.0f64; 3], [0.0f64; 3]);
    let mut outside: Option<u8> = None;
    for i in 0..=512u32 {
        for (j, s) in plan.samples(t0 * f64::from(i) / 512.0).iter().enumerate() {
            let margin = (s.s - lim.min[j]).min(lim.max[j] - s.s);
            if margin.abs() < 1e-9 {
                return None;
            }
            if margin < 0.0 && outside.is_none() {
                outside = Some(j as u8);
            }
            v[j] = v[j].max(s.v.abs() * t0);
            a[j] = a[j].max(s.acc.abs() * t0 * t0);
        }
    }
    if let Some(joint) = outside {
        return Some(Err(LiftError::JointLimit { joint }));
    }
    let mut ts = r.ts_min;
    for j in 0..3 {
        ts = ts.max(v[j] / lim.speed[j]).max((a[j] / lim.accel[j]).sqrt());
    }
    if (ts - lim.ts_max).abs() < 1e-9 * ts {
        return None;
    }
    Some(if lim.ts_max < ts { Err(LiftError::TooSlow { ts_min: ts }) } else { Ok(ts) })
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 400, ..Default::default() })]

    /// The hull's vertices decide what the whole scan decides: the same
    /// refusal (a joint limit named for a joint the scan finds outside), the
    /// same duration to the tables' f32 rounding.
    #[test]
    fn the_hull_check_decides_what_the_scan_does(
        l in (0.8f64..1.2, 0.8f64..1.2),
        start in (0.2f64..2.9, 0.3f64..2.8, -2.8f64..-0.3),
        target in (0.2f64..2.9, 0.3f64..2.8, -2.8f64..-0.3),
        h in 0.01f64..0.5,
        shrink in (0.0f64..0.6, 0.0f64..0.6, 0.0f64..0.6),
        rates in (0.3f64..3.0, 0.5f64..20.0, 2.0f64..30.0),
    ) {
        let r = LiftRequest {
            start: [start.0, start.1, start.2],
            target: [target.0, target.1, target.2],
            h,
            links: Links::new(l.0, l.1).unwrap(),
            branch: Branch::Minus,
            ts_min: 0.5,
        };
        let lim = PathLimits {
            min: [shrink.0, shrink.1, -PI + shrink.2],
            max: [PI - shrink.0, PI - shrink.1, -shrink.2 * 0.5],
            speed: [rates.0; 3],
            accel: [rates.1; 3],
            ts_max: rates.2,
        };
        let Some(want) = scan_decision(&r, &lim) else { return Ok(()) };
        let got = LiftPlan::new(&r, &lim).map(|p| p.ts());
        match (got, want) {
            (Ok(a), Ok(b)) => proptest::prop_assert!((a - b).abs() <= 1e-6 * b, "{a} vs {b}"),
            (Err(LiftError::TooSlow { ts_min: a }), Err(LiftError::TooSlow { ts_min: b })) => {
                proptest::prop_assert!((a - b).abs() <= 1e-6 * b, "{a} vs {b}")
            }
            (Err(LiftError::JointLimit { joint }), Err(LiftError::JointLimit { .. })) => {
                // The joint named is outside somewhere on the scan too.
                let mut one = lim;
                for k in 0..3 {
                    if k != usize::from(joint) {
                        (one.min[k], one.max[k]) = (-10.0, 10.0);
                    }
                }
                let scan = scan_decision(&r, &one);
                let outside = matches!(scan, Some(Err(LiftError::JointLimit { .. })) | None);
                proptest::prop_assert!(outside, "joint {} not outside on the scan: {:?}", joint, scan);
            }
            (a, b) => proptest::prop_assert_eq!(a, b),
        }
    }
}
