//! Re-planning by superposition (issue #12): the correction's cell tables
//! against the laws, continuity of position, velocity and acceleration at a
//! re-plan and where a term ends, the exact end, the limits of the sum
//! (dense scans of the continuous motion), the bounded state, and the
//! servo track's pulses across a re-plan.

use proptest::prelude::*;
use touch_arm::motion::laws::Law;
use touch_arm::motion::plan::{JointLaw, LawKind, MultiPlan, JOINTS};
use touch_arm::motion::planner::cells::{cell_table, CELLS};
use touch_arm::motion::planner::correction::{correction_duration, correction_duration_within, Correction, Running};
use touch_arm::motion::planner::plan_move::scaling_law;
use touch_arm::motion::planner::request::{PlanError, PlanLimits};
use touch_arm::motion::scaled::ScaledZat;
use touch_arm::motion::superpose::{Superposed, TERMS};
use touch_arm::servo::map::{JointCal, ServoMap};
use touch_arm::servo::track::{Replan, ServoTrack};

const SCALING: [LawKind; 4] = [LawKind::Zat, LawKind::Quintic, LawKind::Cubic, LawKind::Trapezoid];

fn unit_law(kind: LawKind) -> JointLaw<f64> {
    match kind {
        LawKind::Zat => JointLaw::Scaled(ScaledZat::new(1.0).unwrap()),
        LawKind::Quintic => JointLaw::classic(Law::Quintic, 1.0).unwrap(),
        LawKind::Cubic => JointLaw::classic(Law::Cubic, 1.0).unwrap(),
        _ => JointLaw::classic(Law::Trapezoid, 1.0).unwrap(),
    }
}

#[test]
fn cell_tables_bound_the_laws() {
    for kind in SCALING {
        let tab = cell_table(kind).unwrap();
        let law = unit_law(kind);
        for i in 0..CELLS {
            let (lo, hi) = (i as f64 / CELLS as f64, (i + 1) as f64 / CELLS as f64);
            let (mut v, mut a) = (0.0f64, 0.0f64);
            for k in 0..=8000 {
                // Just inside the cell: the trapezoid's acceleration steps.
                let s = (lo + (hi - lo) * k as f64 / 8000.0).clamp(lo + 1e-12, hi - 1e-12);
                let d = law.g_derivs(s);
                v = v.max(d.v.abs());
                a = a.max(d.acc.abs());
            }
            let (tv, ta) = tab.max_over::<f64>(i, i + 1);
            assert!(tv >= v && tv <= v * (1.0 + 2e-6) + 1e-9, "{kind:?} cell {i}: v {tv} vs {v}");
            assert!(ta >= a && ta <= a * (1.0 + 2e-6) + 1e-9, "{kind:?} cell {i}: a {ta} vs {a}");
            let f: f64 = tab.f_at(i);
            assert!((f - law.g(lo)).abs() <= 6e-8, "{kind:?} f({lo}): {f} vs {}", law.g(lo));
        }
        assert_eq!(tab.f_at::<f64>(CELLS), 1.0);
        assert_eq!(tab.f_at::<f64>(CELLS + 3), 1.0);
    }
    assert!(cell_table(LawKind::Linear).is_none() && cell_table(LawKind::ZatPaper).is_none());
}

fn law_strategy() -> impl Strategy<Value = LawKind> {
    prop::sample::select(SCALING.to_vec())
}

/// The three terms' local times at `t` after the correction started, the
/// running move having run `elapsed` before.
fn times(t: f64, elapsed: f64) -> [f64; TERMS] {
    [t + elapsed, t, t]
}

fn limits(speed: [f64; 3], accel: [f64; 3]) -> PlanLimits<f64> {
    PlanLimits { speed, accel, ts_min: 0.5, zat_ts_min: 1.2, ts_max: 30.0, n: 2.0 }
}

const RANGE: [[f64; 2]; JOINTS] = [[-3.0, 3.0], [-3.0, 3.0], [-3.0, 3.0]];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// At the re-plan the position, velocity and (for profiles whose
    /// acceleration starts at 0) acceleration of the sum are the running
    /// move's; the sum ends exactly on the new target; and with the planned
    /// duration the continuous sum keeps every joint within its speed and
    /// acceleration (with the slack) and its angle range, on a dense scan;
    /// also with the duration of a search the chip cut short.
    #[test]
    fn a_correction_is_continuous_within_the_limits_and_ends_exactly(
        old_law in law_strategy(),
        new_law in law_strategy(),
        d_old in prop::array::uniform3(-2.0f64..2.0),
        d_new in prop::array::uniform3(-2.0f64..2.0),
        frac in 0.0f64..1.0,
        speed in prop::array::uniform3(0.5f64..4.0),
        accel in prop::array::uniform3(2.0f64..40.0),
        cut in 0u8..6,
    ) {
        let lim = limits(speed, accel);
        let start = [0.1, -0.2, 0.3];
        let old_target = [start[0] + d_old[0], start[1] + d_old[1], start[2] + d_old[2]];
        let m0 = touch_arm::motion::planner::plan_move::plan_move(
            &touch_arm::motion::planner::request::MoveRequest { start, target: old_target, law: old_law },
            &lim,
        ).unwrap();
        let old = Superposed::new(&m0.plan);
        let elapsed = frac * m0.ts;
        let target = [start[0] + d_new[0], start[1] + d_new[1], start[2] + d_new[2]];
        let c = Correction {
            delta: [target[0] - old_target[0], target[1] - old_target[1], target[2] - old_target[2]],
            target,
            law: new_law,
            range: RANGE,
            slack: 1.0 / 0.98,
        };
        let run = Running { law: old_law, delta: *m0.plan.delta(), duration: m0.ts, elapsed };
        let full = correction_duration(&c, Some(&run), &lim);
        // The chip's search when the period's time runs out after `cut`
        // bisections (5: never, the full search): the duration may only be
        // longer, and the scan below holds for it just the same.
        let mut asked = 0u8;
        let within = correction_duration_within(&c, Some(&run), &lim, &mut || {
            asked += 1;
            asked <= cut
        });
        let ts = match (full, within) {
            (Ok(full), Ok(ts)) => {
                prop_assert!(ts >= full, "cut after {cut}: {ts} < {full}");
                if cut >= 4 {
                    prop_assert_eq!(ts, full);
                }
                ts
            }
            (Err(e), Err(f)) => {
                prop_assert_eq!(e, PlanError::SpeedLimit);
                prop_assert_eq!(f, e);
                return Ok(());
            }
            (a, b) => {
                prop_assert!(false, "the cut search disagrees: {a:?} vs {b:?}");
                return Ok(());
            }
        };
        let profile = scaling_law(new_law, ts).unwrap();
        let mut next = old;
        next.add_correction(&target, &profile, 1).unwrap();
        // Continuity at the re-plan.
        let before = old.sample_full(&times(0.0, elapsed));
        let after = next.sample_full(&times(0.0, elapsed));
        for j in 0..JOINTS {
            prop_assert!((before[j].s - after[j].s).abs() <= 1e-12, "position {j}");
            prop_assert!((before[j].v - after[j].v).abs() <= 1e-12, "velocity {j}");
            if matches!(new_law, LawKind::Zat | LawKind::Quintic) {
                prop_assert!((before[j].acc - after[j].acc).abs() <= 1e-12, "acceleration {j}");
            }
        }
        // The exact end (a hair past the later end: t + elapsed may round
        // below the running term's duration).
        let end = ts.max(m0.ts - elapsed) * (1.0 + 1e-12);
        prop_assert_eq!(next.positions(&times(end, elapsed)), target);
        prop_assert_eq!(next.positions(&times(end + 1.0, elapsed)), target);
        // The limits of the sum, densely.
        for k in 0..=4000 {
            let t = end * k as f64 / 4000.0;
            let s = next.sample_full(&times(t, elapsed));
            for j in 0..JOINTS {
                prop_assert!(s[j].v.abs() <= speed[j] / 0.98 * (1.0 + 1e-9), "speed {j} at {t}: {}", s[j].v);
                prop_assert!(s[j].acc.abs() <= accel[j] / 0.98 * (1.0 + 1e-9), "accel {j} at {t}: {}", s[j].acc);
                prop_assert!(s[j].s >= RANGE[j][0] - 1e-9 && s[j].s <= RANGE[j][1] + 1e-9, "range {j} at {t}: {}", s[j].s);
            }
        }
    }

    /// A dragged finger: a run of targets at random moments keeps at most
    /// two running terms and one waiting, every step of it continuous in
    /// position, velocity and acceleration (quintic and ζ-a-tₛ), including
    /// where a term ends and is dropped, and the motion ends on the last
    /// target.
    #[test]
    fn a_dragged_finger_keeps_the_state_bounded_and_continuous(
        law in prop::sample::select(vec![LawKind::Zat, LawKind::Quintic]),
        targets in prop::collection::vec((prop::array::uniform3(-1.5f64..1.5), 1u16..40), 1..12),
    ) {
        let lim = limits([2.0; 3], [20.0; 3]);
        let dt = 0.02;
        let first = touch_arm::motion::planner::plan_move::plan_move(
            &touch_arm::motion::planner::request::MoveRequest { start: [0.0; 3], target: [1.0, -1.0, 0.5], law },
            &lim,
        ).unwrap();
        let mut m = Superposed::new(&first.plan);
        // Frames each term has run (negative: waiting).
        let mut clock = [0i32; TERMS];
        let mut last = [1.0, -1.0, 0.5];
        let t_of = |clock: &[i32; TERMS]| clock.map(|c| c as f64 * dt);
        let mut prev = m.sample_full(&t_of(&clock));
        let mut pending = targets.into_iter();
        let mut next_at = 0u16;
        let mut frames = 0u32;
        loop {
            // A new target this frame?
            if next_at == 0 {
                if let Some((target, gap)) = pending.next() {
                    next_at = gap;
                    let n = m.len();
                    let (slot, wait) = if n > 0 && clock[n - 1] < 0 {
                        (n - 1, -clock[n - 1])
                    } else if n < 2 {
                        (n, 0)
                    } else {
                        let d = m.terms()[0].unwrap().duration();
                        (2, ((d / dt) as i32 + 1 - clock[0]).max(0))
                    };
                    let base_target = match m.terms()[slot] {
                        Some(w) => [m.target()[0] - w.delta[0], m.target()[1] - w.delta[1], m.target()[2] - w.delta[2]],
                        None => *m.target(),
                    };
                    let run = (0..n).filter(|&k| k != slot).find_map(|k| {
                        let term = m.terms()[k].unwrap();
                        let e = (clock[k] + wait) as f64 * dt;
                        (e >= 0.0 && e < term.duration()).then_some(Running { law, delta: term.delta, duration: term.duration(), elapsed: e })
                    });
                    let c = Correction {
                        delta: [target[0] - base_target[0], target[1] - base_target[1], target[2] - base_target[2]],
                        target,
                        law,
                        range: RANGE,
                        slack: 1.0 / 0.98,
                    };
                    if let Ok(ts) = correction_duration(&c, run.as_ref(), &lim) {
                        let before = m.sample_full(&t_of(&clock));
                        m.add_correction(&target, &scaling_law(law, ts).unwrap(), slot).unwrap();
                        clock[slot] = -wait;
                        last = target;
                        let after = m.sample_full(&t_of(&clock));
                        for j in 0..JOINTS {
                            prop_assert!((before[j].s - after[j].s).abs() <= 1e-12);
                            prop_assert!((before[j].v - after[j].v).abs() <= 1e-12);
                            prop_assert!((before[j].acc - after[j].acc).abs() <= 1e-12);
                        }
                    }
                }
            }
            next_at = next_at.saturating_sub(1);
            prop_assert!(m.len() <= TERMS);
            // Evaluated this frame: started and not yet ended.
            let running = (0..m.len())
                .filter(|&k| clock[k] >= 0 && (clock[k] as f64 * dt) < m.terms()[k].unwrap().duration())
                .count();
            prop_assert!(running <= 2, "{running} terms running");
            // Drop what has ended, then the next frame.
            let gone = m.retire(&t_of(&clock));
            let mut k = 0;
            let old = clock;
            for (i, c) in old.iter().enumerate() {
                if gone & (1 << i) == 0 {
                    clock[k] = *c;
                    k += 1;
                }
            }
            for c in clock.iter_mut() {
                *c += 1;
            }
            // Continuity between frames: the velocity changes by at most the
            // acceleration limit (with slack) times a frame.
            let now = m.sample_full(&t_of(&clock));
            for j in 0..JOINTS {
                prop_assert!((now[j].v - prev[j].v).abs() <= 20.0 / 0.98 * dt * (1.0 + 1e-9), "velocity step {j}");
            }
            prev = now;
            frames += 1;
            if m.is_empty() && pending.len() == 0 && next_at == 0 {
                break;
            }
            prop_assert!(frames < 50_000);
        }
        prop_assert_eq!(m.positions(&t_of(&clock)), last);
    }
}

/// The servo track tests' move: from the home pose to (0.6, 2.2, −2.4) rad
/// in 2 s (100 frames) under the default maps, and the limits a re-plan
/// plans under.
fn track_move() -> ([ServoMap; JOINTS], MultiPlan<f32>, PlanLimits<f32>) {
    let maps = JointCal::DEFAULTS.map(|c| ServoMap::new(&c).unwrap());
    let start = [1.5707964f32, 1.5707964, -1.5707964];
    let target = [0.6f32, 2.2, -2.4];
    let law = scaling_law(LawKind::Zat, 2.0f32).unwrap();
    let plan = MultiPlan::with_law(&start, &target, &law).unwrap();
    let lim = PlanLimits { speed: [1.47f32; 3], accel: [17.1; 3], ts_min: 0.5, zat_ts_min: 1.2, ts_max: 30.0, n: 2.0 };
    (maps, plan, lim)
}

/// The servo track across a re-plan: the re-plan frame's pulses are the
/// running move's, bit for bit, the running term's clock goes on, and the
/// motion ends on the map's own pulses of the new target; a second re-plan
/// while both run waits for the older to end, a third replaces it.
#[test]
fn the_track_keeps_its_pulses_across_a_re_plan() {
    let (maps, plan, lim) = track_move();
    let new_target = [1.2f32, 1.9, -1.0];
    let replan = Replan { target: &new_target, law: LawKind::Zat, lim: &lim, slack: 1.0 / 0.98 };
    for at in [1u16, 17, 50, 99] {
        let mut old = ServoTrack::new(&plan, &maps, 0.02).unwrap();
        for _ in 0..at {
            old.advance();
        }
        let mut new = old;
        let (ts, wait) = new.replan(&replan, &maps, &mut || true).unwrap().unwrap();
        assert_eq!(wait, 0);
        let (a, b) = (old.frame_now(), new.frame_now());
        assert_eq!(a.pulses, b.pulses, "re-plan at frame {at}");
        let (q_old, q_new) = (old.positions(&a), new.positions(&b));
        let (v_old, v_new) = (old.velocities(&a), new.velocities(&b));
        for j in 0..JOINTS {
            assert!((q_old[j] - q_new[j]).abs() <= 2e-6, "{at}: {q_old:?} vs {q_new:?}");
            assert!((v_old[j] - v_new[j]).abs() <= 1e-6, "{at}: {v_old:?} vs {v_new:?}");
        }
        assert_eq!(new.clock(0), Some(i32::from(at)));
        assert_eq!(new.clock(1), Some(0));
        let mut last = b;
        let mut frames = 0;
        while !new.is_done() {
            last = new.frame_now();
            new.advance();
            frames += 1;
        }
        let want: Vec<u16> =
            new_target.iter().zip(maps.iter()).map(|(q, m)| m.angle_to_pulse(*q).unwrap().ticks).collect();
        assert_eq!(last.pulses.to_vec(), want);
        assert_eq!(new.positions(&last), new_target);
        // The last frame is the first at or past both ends.
        let ends = (ts / 0.02).ceil().max(((2.0 - f32::from(at) * 0.02) / 0.02).ceil());
        assert_eq!(frames as f32, 1.0 + ends, "{at}");
    }
    // Beside two running terms a correction waits for the older to end,
    // then a later one replaces it, moving nothing either time.
    let mut t = ServoTrack::new(&plan, &maps, 0.02).unwrap();
    for _ in 0..10 {
        t.advance();
    }
    t.replan(&replan, &maps, &mut || true).unwrap().unwrap();
    t.advance();
    let third = [1.0f32, 1.0, -1.5];
    let before = t.frame_now();
    let (_, wait) = t.replan(&Replan { target: &third, ..replan }, &maps, &mut || true).unwrap().unwrap();
    // The move had run 11 frames of its 100.
    assert_eq!((wait, t.motion().len()), (90, 3));
    assert_eq!(t.frame_now().pulses, before.pulses);
    let fourth = [0.9f32, 1.2, -1.4];
    let (_, wait) = t.replan(&Replan { target: &fourth, ..replan }, &maps, &mut || true).unwrap().unwrap();
    assert_eq!((wait, t.motion().len()), (90, 3));
    assert_eq!(t.frame_now().pulses, before.pulses);
    assert_eq!(t.motion().target(), &fourth);
    let mut last = before;
    while !t.is_done() {
        last = t.frame_now();
        assert!(t.motion().len() <= TERMS);
        t.advance();
    }
    assert_eq!(t.positions(&last), fourth);
}

/// A correction that waits for the older term while the newer one ends
/// first starts alone: its first frame is the pulses of the pose reached,
/// not the pulses the track's first move started from (the long random run
/// found a 377.5 µs step there when the older term's duration was a whole
/// number of frames).
#[test]
fn a_waiting_correction_that_starts_alone_keeps_the_pulses() {
    // The older term ends on a frame boundary (100 frames).
    let (maps, plan, lim) = track_move();
    let mut t = ServoTrack::new(&plan, &maps, 0.02).unwrap();
    for _ in 0..10 {
        t.advance();
    }
    // A small correction (short: it ends long before the older term) ...
    let near = [0.62f32, 2.18, -2.38];
    t.replan(&Replan { target: &near, law: LawKind::Zat, lim: &lim, slack: 1.0 / 0.98 }, &maps, &mut || true)
        .unwrap()
        .unwrap();
    t.advance();
    // ... and one that waits for the older term to end.
    let third = [0.7f32, 2.1, -2.3];
    let (_, wait) = t
        .replan(&Replan { target: &third, law: LawKind::Zat, lim: &lim, slack: 1.0 / 0.98 }, &maps, &mut || true)
        .unwrap()
        .unwrap();
    assert!(wait > 0);
    let mut prev = t.frame_now().pulses;
    let mut frames = 0;
    while !t.is_done() {
        let f = t.frame_now();
        for j in 0..JOINTS {
            let step = (i32::from(f.pulses[j]) - i32::from(prev[j])).abs();
            // 1.47 rad/s at 572.96 µs/rad is 16.8 µs (34 ticks) a frame.
            assert!(step <= 36, "frame {frames}: joint {j} steps {step} ticks: {prev:?} -> {:?}", f.pulses);
        }
        prev = f.pulses;
        t.advance();
        frames += 1;
    }
    let want: Vec<u16> = third.iter().zip(maps.iter()).map(|(q, m)| m.angle_to_pulse(*q).unwrap().ticks).collect();
    assert_eq!(prev.to_vec(), want);
}
