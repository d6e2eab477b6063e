//! The planned stop (issue #20 §5, `motion::stop`): from a move planned
//! under the joints' limits, released at any time, the warped motion keeps
//! position and velocity continuous where it starts, every frame's second
//! difference within the acceleration limit and its first within the speed
//! limit, comes to rest, and rests on the plan's own path: the stop pose is
//! the plan at some τ. Then it resumes to full speed under the same bounds.

use proptest::prelude::*;
use touch_arm::motion::plan::{LawKind, MultiPlan, JOINTS};
use touch_arm::motion::planner::plan_move::plan_move;
use touch_arm::motion::planner::request::{MoveRequest, PlanLimits};
use touch_arm::motion::stop::{Timeline, Warp};

const DT: f32 = 0.02;
/// Laws with bounded acceleration (linear steps its velocity at both ends).
const LAWS: [LawKind; 5] = [LawKind::Zat, LawKind::ZatPaper, LawKind::Quintic, LawKind::Cubic, LawKind::Trapezoid];

struct Plan(MultiPlan<f32>);
impl Timeline for Plan {
    fn pose(&self, tau: f32) -> Option<[f32; JOINTS]> {
        Some(self.0.positions(tau.clamp(0.0, self.0.duration())))
    }
}

/// The app's limits: plans at 98 % of the acceleration limit `a`.
fn limits(v: [f32; JOINTS], a: [f32; JOINTS]) -> PlanLimits<f32> {
    PlanLimits {
        speed: v.map(|x| x * 0.98),
        accel: a.map(|x| x * 0.98),
        ts_min: 0.5,
        zat_ts_min: 1.2,
        ts_max: 30.0,
        n: 2.0,
    }
}

/// Runs the plan at its own clock up to frame `k0`, then the stop; returns
/// the poses (two running frames first), the frames to rest, and the warp.
fn stop_run(p: &Plan, k0: u16, a: &[f32; JOINTS]) -> (Vec<[f32; JOINTS]>, usize, Warp) {
    let tau = f32::from(k0) * DT;
    let mut poses = vec![p.pose(tau - DT).unwrap(), p.pose(tau).unwrap()];
    let mut w = Warp::begin(p, tau, DT, a).unwrap();
    // Each frame either takes a ramp step (n in all) or pauses, advancing τ
    // by at least the last rate before rest, r(n−1, n)·dt = (3/n² − 2/n³)·dt,
    // until the motion's own end, where it rests: the bound on frames. (A
    // trapezoid released while it accelerates at its limit pauses for long:
    // 118 frames against its 31-frame ramp, found by this test.)
    let n = f32::from(w.frames_to_rest());
    let r_min = (3.0 / (n * n) - 2.0 / (n * n * n)).max(1e-6);
    let limit = usize::from(w.frames_to_rest()) + (p.0.duration() / (DT * r_min)) as usize + 2;
    let mut frames = 0;
    while !w.at_rest() {
        poses.push(w.next(p, a).unwrap());
        frames += 1;
        assert!(frames <= limit, "no rest after {frames} frames");
    }
    (poses, frames, w)
}

/// Every second difference ≤ A·dt², every first ≤ V·dt (f32 slack).
fn assert_bounded(poses: &[[f32; JOINTS]], v: &[f32; JOINTS], a: &[f32; JOINTS]) {
    for (i, w) in poses.windows(3).enumerate() {
        for j in 0..JOINTS {
            let acc = (w[2][j] - 2.0 * w[1][j] + w[0][j]) / (DT * DT);
            assert!(acc.abs() <= a[j] + 1e-2, "frame {i} joint {j}: |accel| {acc} > {}", a[j]);
            let vel = (w[2][j] - w[1][j]) / DT;
            assert!(vel.abs() <= v[j] + 1e-3, "frame {i} joint {j}: |vel| {vel} > {}", v[j]);
        }
    }
}

fn pose_strategy() -> impl Strategy<Value = [f32; JOINTS]> {
    prop::array::uniform3(-1.5f32..1.5)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn a_released_move_comes_to_rest_on_its_path_within_the_limits(
        law in prop::sample::select(LAWS.to_vec()),
        start in pose_strategy(),
        target in pose_strategy(),
        v in prop::array::uniform3(1.0f32..6.0),
        a in prop::array::uniform3(3.0f32..40.0),
        share in 0.0f32..1.0,
    ) {
        let lim = limits(v, a);
        let req = MoveRequest { start, target, law };
        let Ok(planned) = plan_move(&req, &lim) else { return Ok(()) };
        let p = Plan(planned.plan);
        let k0 = ((p.0.duration() * share / DT) as u16).max(1);
        let (poses, frames, w) = stop_run(&p, k0, &a);
        assert_bounded(&poses, &v, &a);
        // On the path: the rest pose is the plan at the warp's τ, no later
        // than the plan's end.
        let rest = poses.last().unwrap();
        let on = p.pose(w.tau()).unwrap();
        for j in 0..JOINTS {
            prop_assert!((rest[j] - on[j]).abs() < 1e-5);
        }
        prop_assert!(w.tau() >= f32::from(k0) * DT);
        // A stop rests after at least its planned frames, unless the motion
        // reached its own end first (then it rests there at once).
        let planned = usize::from(Warp::begin(&p, f32::from(k0) * DT, DT, &a).unwrap().frames_to_rest());
        prop_assert!(frames >= planned || w.tau() >= p.0.duration());
    }

    #[test]
    fn a_resumed_stop_returns_to_full_speed_within_the_limits(
        law in prop::sample::select(LAWS.to_vec()),
        start in pose_strategy(),
        target in pose_strategy(),
        a in prop::array::uniform3(3.0f32..40.0),
        share in 0.0f32..0.8,
        after in 1u16..30,
    ) {
        let v = [4.0; JOINTS];
        let Ok(planned) = plan_move(&MoveRequest { start, target, law }, &limits(v, a)) else { return Ok(()) };
        let p = Plan(planned.plan);
        let k0 = ((p.0.duration() * share / DT) as u16).max(1);
        let tau = f32::from(k0) * DT;
        let mut poses = vec![p.pose(tau - DT).unwrap(), p.pose(tau).unwrap()];
        let mut w = Warp::begin(&p, tau, DT, &a).unwrap();
        for _ in 0..after {
            poses.push(w.next(&p, &a).unwrap());
        }
        w.set_up(true);
        let mut n = 0;
        while !w.full() && w.tau() < p.0.duration() {
            poses.push(w.next(&p, &a).unwrap());
            n += 1;
            prop_assert!(n < 2000);
        }
        assert_bounded(&poses, &v, &a);
    }
}

#[test]
fn a_stop_at_cruise_takes_its_computed_frames_and_stops_short() {
    // Base 0 → 1.5 rad, trapezoid at v = 1, A = 10: released in the cruise.
    let (v, a) = ([1.0f32; JOINTS], [10.0f32; JOINTS]);
    let req = MoveRequest { start: [0.0; JOINTS], target: [1.5, 0.0, 0.0], law: LawKind::Trapezoid };
    let p = Plan(plan_move(&req, &limits(v, a)).unwrap().plan);
    let k0 = (p.0.duration() / 2.0 / DT) as u16;
    let (poses, frames, w) = stop_run(&p, k0, &a);
    assert_bounded(&poses, &v, &a);
    // |v| = 0.98 rad/s at cruise: 3·0.98/10 = 0.294 s = 14.7 frames → n = 15.
    let n = Warp::begin(&p, f32::from(k0) * DT, DT, &a).unwrap().frames_to_rest();
    assert_eq!(n, 15);
    assert_eq!(frames, 15);
    // τ advanced by Σ r·dt ≈ n·dt/2 = 0.15 s: about 0.147 rad past the release.
    let moved = poses.last().unwrap()[0] - poses[1][0];
    assert!((moved - 0.98 * 0.14).abs() < 0.02, "{moved}");
    assert!(poses.last().unwrap()[0] < 1.5 - 0.3);
    let _ = w;
}
