//! Issue #13's path moves on the real firmware ELF in simavr, from the servo
//! pulses measured on the pins: `path line` moves the effector along the
//! straight segment (every measured pulse back through the default
//! calibration to its angle, then the FK: within 0.005 of the segment);
//! `circle <r>` makes one turn and ends where it started; the plan-time
//! check spread over frames answers within a bounded time; STOP cancels a
//! check and freezes a path move; refusals and the joint limits.

use touch_arm::geometry::ik::{fk3, Links};
use touch_arm_rig::firmware::{self, effector_at, Session};

/// Frame period of the firmware (one servo PWM period), s.
const FRAME_S: f64 = 0.02;

/// The firmware homed, its slow first move done, at the fast preset.
fn start() -> Session {
    Session::start_moved_fast(5).expect("firmware ELF (cargo avr)")
}

/// `ts_ms` of a move reply, s.
fn ts(reply: &str) -> f64 {
    firmware::reply_ts(reply).unwrap()
}

/// Sends `line` and waits (up to 5 s of chip time) for the reply of a path
/// move, which comes when the check decides; (reply, seconds it took).
fn path_command(s: &mut Session, line: &str) -> (String, f64) {
    path_command_within(s, line, 5.0)
}

/// [`path_command`] waiting up to `secs` of chip time.
fn path_command_within(s: &mut Session, line: &str, secs: f64) -> (String, f64) {
    let from = s.avr.uart_output().len();
    let t0 = s.avr.time_s();
    s.avr.uart_send(format!("{line}\n").as_bytes());
    let (reply, t) = s.await_line(from, &["ok", "err"], secs).unwrap().unwrap_or_else(|| panic!("no reply to {line}"));
    (reply, t - t0)
}

fn links() -> Links<f64> {
    Links::new(1.0, 1.0).unwrap()
}

/// The effector (arm units) of every measured period from `t0` on.
fn measured_path(s: &Session, t0: f64) -> Vec<[f64; 3]> {
    let maps = firmware::default_servo_maps().unwrap();
    let p = s.pulses().map(|p| p.into_iter().filter(|(t, _)| *t >= t0).map(|(_, w)| w).collect::<Vec<_>>());
    let n = p.iter().map(Vec::len).min().unwrap();
    (0..n).map(|i| effector_at(&maps, &links(), &[p[0][i], p[1][i], p[2][i]])).collect()
}

fn fk_deg(q: [f64; 3]) -> [f64; 3] {
    let (x, y, z) = fk3(&links(), q[0].to_radians(), q[1].to_radians(), q[2].to_radians());
    [x, y, z]
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Distance of `p` from the segment a → b.
fn off_segment(p: &[f64; 3], a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let s = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) / dd).clamp(0.0, 1.0);
    dist(p, &[a[0] + d[0] * s, a[1] + d[1] * s, a[2] + d[2] * s])
}

#[test]
fn a_line_move_keeps_the_measured_effector_on_its_segment() {
    let mut s = start();
    assert_eq!(s.command("path line").unwrap(), "ok path line");
    let t0 = s.avr.time_s();
    let (reply, decided) = path_command(&mut s, "goto 40 70 -110");
    assert!(reply.starts_with("ok goto path line ts_ms "), "{reply}");
    eprintln!("md: line check decided in {decided:.3} s ({:.0} frames): {reply}", decided / FRAME_S);
    s.run_for(ts(&reply) + 0.3).unwrap();
    let path = measured_path(&s, t0);
    let (a, b) = (fk_deg([90.0, 100.0, -100.0]), fk_deg([40.0, 70.0, -110.0]));
    let worst = path.iter().map(|p| off_segment(p, &a, &b)).fold(0.0, f64::max);
    eprintln!("md: line move: measured effector at most {worst:.5} off its segment ({} periods)", path.len());
    assert!(worst <= 0.005, "{worst}");
    // It went somewhere along the segment, and ends on the target.
    assert!(dist(path.last().unwrap(), &b) < 0.002, "{:?} vs {b:?}", path.last());
    assert!(path.iter().any(|p| dist(p, &a) > 0.3 && dist(p, &b) > 0.3));
    assert!(s.command("status").unwrap().starts_with("ok status holding law zat speed fast path line "));
    // The check (IK with its rates) and the path frame within the stack
    // budget (painted at load: the deepest since power-up).
    let used = s.stack_high_water().expect("stack painted at load");
    let budget = firmware::budget("stack").unwrap() as usize;
    eprintln!("md: stack high-water after a path check and move: {used} B of {budget}");
    assert!(used <= budget, "{used} B");
}

#[test]
fn a_circle_turns_once_through_where_the_effector_was() {
    let mut s = start();
    let t0 = s.avr.time_s();
    let (reply, decided) = path_command(&mut s, "circle 0.2");
    assert!(reply.starts_with("ok circle r_milli 200 ts_ms "), "{reply}");
    eprintln!("md: circle check decided in {decided:.3} s ({:.0} frames): {reply}", decided / FRAME_S);
    s.run_for(ts(&reply) + 0.3).unwrap();
    let path = measured_path(&s, t0);
    // The circle's farthest point out is the start; its centre lies 0.2
    // nearer the base axis, in the vertical plane of the base at 90°.
    let a = fk_deg([90.0, 100.0, -100.0]);
    let rho = a[1];
    let c = [0.0, rho - 0.2, a[2]];
    let worst = path.iter().map(|p| (dist(p, &c) - 0.2).abs().max(p[0].abs())).fold(0.0, f64::max);
    eprintln!("md: circle: measured effector at most {worst:.5} off its circle ({} periods)", path.len());
    assert!(worst <= 0.005, "{worst}");
    // One whole turn: it went to the far side, and came back.
    assert!(path.iter().any(|p| dist(p, &a) > 0.39));
    assert!(dist(path.last().unwrap(), &a) < 0.002);
}

#[test]
fn stop_cancels_a_check_and_freezes_a_path_move() {
    let mut s = start();
    assert_eq!(s.command("path line").unwrap(), "ok path line");
    let before = s.last_pulses();
    // STOP while the check runs: the move never starts, its requester hears.
    let from = s.avr.uart_output().len();
    s.avr.uart_send(b"goto 40 70 -110\n");
    s.run_for(0.2).unwrap();
    assert!(s.command("status").unwrap().starts_with("ok status checking "));
    assert_eq!(s.command("stop").unwrap(), "ok stop");
    let (cancelled, _) = s.await_line(from, &["err"], 0.2).unwrap().expect("the cancelled move's reply");
    assert_eq!(cancelled, "err path check stopped");
    s.run_for(1.0).unwrap();
    assert_eq!(s.last_pulses(), before);
    assert!(s.command("status").unwrap().starts_with("ok status stopped "));
    assert_eq!(s.command("goto 40 70 -110").unwrap(), "err stopped (send resume)");
    assert_eq!(s.command("resume").unwrap(), "ok resume");
    // STOP mid-move: the pulses freeze on a pose of the segment.
    let (reply, _) = path_command(&mut s, "goto 40 70 -110");
    assert!(reply.starts_with("ok goto path line"), "{reply}");
    s.run_for(0.5 * ts(&reply)).unwrap();
    // A new target during a path move is refused: nothing is superposed.
    assert_eq!(s.command("goto 90 100 -100").unwrap(), "err busy moving");
    assert_eq!(s.command("stop").unwrap(), "ok stop");
    let t_stop = s.avr.time_s();
    s.run_for(0.1).unwrap();
    let held = s.last_pulses();
    s.run_for(1.0).unwrap();
    assert_eq!(s.last_pulses(), held);
    let p = measured_path(&s, t_stop);
    let last = p.last().unwrap();
    let (a, b) = (fk_deg([90.0, 100.0, -100.0]), fk_deg([40.0, 70.0, -110.0]));
    assert!(off_segment(last, &a, &b) <= 0.005 && dist(last, &a) > 0.1 && dist(last, &b) > 0.1, "{last:?}");
    assert!(s.command("status").unwrap().starts_with("ok status stopped "));
}

#[test]
fn path_moves_are_refused_with_their_reason() {
    let mut s = start();
    assert_eq!(s.command("path line").unwrap(), "ok path line");
    // The papers' own form changes shape with its duration.
    assert_eq!(s.command("law zat-paper").unwrap(), "ok law zat-paper");
    assert_eq!(s.command("goto 40 70 -110").unwrap(), "err path: law zat-paper not offered");
    assert_eq!(s.command("circle 0.1").unwrap(), "err path: law zat-paper not offered");
    assert_eq!(s.command("law zat").unwrap(), "ok law zat");
    // Where the arm already is: an empty segment.
    assert_eq!(s.command("goto 90 100 -100").unwrap(), "err path empty or through base axis");
    // The target itself outside a joint's limits, as for any move.
    assert_eq!(s.command("goto 190 70 -110").unwrap(), "err joint limit base");
    // Circles need no path mode; the arm is placed by joint moves.
    assert_eq!(s.command("path joint").unwrap(), "ok path joint");
    // A circle over the rim: from 1.97 out (goto 90 80 -20), the circle's
    // top, 0.1 higher and 0.1 nearer, is 2.03 from the shoulder.
    let r = s.command("goto 90 80 -20").unwrap();
    s.run_for(ts(&r) + 0.2).unwrap();
    let (reply, _) = path_command(&mut s, "circle 0.1");
    assert_eq!(reply, "err path leaves reach");
    // A radius beyond the effector's distance from the base axis (0.045 at
    // 90 10 -170): the circle would cross the axis.
    let r = s.command("goto 90 10 -170").unwrap();
    s.run_for(ts(&r) + 0.2).unwrap();
    let (reply, _) = path_command(&mut s, "circle 0.5");
    assert_eq!(reply, "err path empty or through base axis");
    let r = s.command("goto 90 100 -100").unwrap();
    s.run_for(ts(&r) + 0.2).unwrap();
    assert_eq!(s.command("path line").unwrap(), "ok path line");
    // A joint limit inside the segment: from (90, 100, -100) to (40, 70,
    // -110) the effector passes 1.077 from the shoulder (segment's closest
    // approach), where the elbow folds to -114.8°; with the elbow's limit at
    // -112° the target is inside, the path is not.
    assert_eq!(s.command("cal set elbow min_deg -112").unwrap(), "ok cal set");
    let (reply, _) = path_command(&mut s, "goto 40 70 -110");
    assert_eq!(reply, "err path joint limit elbow");
    assert!(s.command("status").unwrap().ends_with("refused path joint limit elbow"));
    // The joint mode still goes there (each joint straight to its angle).
    assert_eq!(s.command("path joint").unwrap(), "ok path joint");
    assert!(s.command("goto 40 70 -110").unwrap().starts_with("ok goto ts_ms "));
}

/// The host's f64 plan of the chip's `lift 0.2` from (90, 100, -100) to
/// (40, 70, -110) at the fast preset: the same request and limits (angle
/// limits of the default calibration, 98 % of the speed and acceleration).
fn host_lift(h: f64) -> touch_arm::motion::lift::LiftPlan<f64> {
    use touch_arm::geometry::ik::Branch;
    use touch_arm::motion::lift::{LiftPlan, LiftRequest};
    use touch_arm::motion::path::PathLimits;
    let maps = firmware::default_servo_maps().unwrap();
    let lim = PathLimits {
        min: std::array::from_fn(|j| maps[j].angle_limits::<f64>().0),
        max: std::array::from_fn(|j| maps[j].angle_limits::<f64>().1),
        speed: std::array::from_fn(|j| maps[j].max_speed::<f64>() * 0.98),
        accel: std::array::from_fn(|j| maps[j].max_accel::<f64>() * 0.98),
        ts_max: 30.0,
    };
    let rad = |d: [f64; 3]| d.map(f64::to_radians);
    let req = LiftRequest {
        start: rad([90.0, 100.0, -100.0]),
        target: rad([40.0, 70.0, -110.0]),
        h,
        links: links(),
        branch: Branch::Minus,
        ts_min: 0.5,
    };
    LiftPlan::new(&req, &lim).unwrap()
}

#[test]
fn a_lift_passes_its_via_pose_at_tv_and_reaches_the_height() {
    let mut s = start();
    assert_eq!(s.command("lift 0.2").unwrap(), "ok lift 0.20");
    let t0 = s.avr.time_s();
    let (reply, decided) = path_command(&mut s, "goto 40 70 -110");
    assert!(reply.starts_with("ok goto lift 0.20 ts_ms "), "{reply}");
    eprintln!("md: lift check decided in {decided:.3} s ({:.0} frames): {reply}", decided / FRAME_S);
    s.run_for(ts(&reply) + 0.3).unwrap();
    let plan = host_lift(0.2);
    assert!((ts(&reply) - plan.ts()).abs() <= 0.0005, "{reply} vs {}", plan.ts());
    // The measured pulse train against the host's plan, every period: the
    // move's first frame is some period after the reply; the alignment that
    // fits best must fit within a tick (0.5 µs) everywhere.
    let maps = firmware::default_servo_maps().unwrap();
    let trains = s.pulse_ticks().map(|p| p.into_iter().filter(|(t, _)| *t >= t0).map(|(_, w)| w).collect::<Vec<_>>());
    let n = trains.iter().map(Vec::len).min().unwrap();
    let frames = (plan.ts() / FRAME_S).ceil() as usize + 1;
    let predicted = |k: usize| -> [u16; 3] {
        let q = plan.positions(k as f64 * FRAME_S);
        std::array::from_fn(|j| maps[j].angle_to_pulse(q[j] as f32).unwrap().ticks)
    };
    let worst_at = |start: usize| -> i32 {
        (0..frames)
            .map(|k| {
                let p = predicted(k);
                (0..3).map(|j| (i32::from(trains[j][start + k]) - i32::from(p[j])).abs()).max().unwrap()
            })
            .max()
            .unwrap()
    };
    let (start, worst) = (0..n - frames).map(|st| (st, worst_at(st))).min_by_key(|x| x.1).unwrap();
    eprintln!("md: lift: measured pulses within {worst} tick(s) of the host plan at every period");
    assert!(worst <= 1, "{worst} ticks");
    // Through the via pose at t_v: the periods around t_v bracket the via
    // pose's pulses, each within the pulse resolution of the plan there.
    let tv = plan.tv();
    let k = (tv / FRAME_S).floor() as usize;
    let via: [u16; 3] = std::array::from_fn(|j| maps[j].angle_to_pulse(plan.via()[j] as f32).unwrap().ticks);
    for j in 0..3 {
        let (a, b) = (trains[j][start + k], trains[j][start + k + 1]);
        // Linear between the two periods; the shapes' curvature over 20 ms
        // adds at most α·dt²/8 (≈ 0.3 tick at the acceleration limit).
        let w = (tv - k as f64 * FRAME_S) / FRAME_S;
        let at_tv = f64::from(a) + (f64::from(b) - f64::from(a)) * w;
        assert!((at_tv - f64::from(via[j])).abs() <= 1.5, "joint {j}: {at_tv} vs via {}", via[j]);
    }
    // Reaches the height: 0.2 above the higher end.
    let path = measured_path(&s, t0);
    let top = path.iter().map(|p| p[2]).fold(f64::MIN, f64::max);
    let want = fk_deg([90.0, 100.0, -100.0])[2].max(fk_deg([40.0, 70.0, -110.0])[2]) + 0.2;
    eprintln!("md: lift: the measured effector rises to {top:.4} (the via pose's height {want:.4})");
    // Joint-space shapes: the effector passes the via pose at t_v but may
    // rise above it on the way (the height is a floor, not a ceiling).
    assert!((plan.via_point()[2] - want).abs() < 1e-12 && top >= want - 0.005, "{top} vs {want}");
    // No velocity step at t_v: the per-period pulse step changes around t_v
    // by no more than the acceleration limit allows (α·dt² in ticks) plus
    // the roundings of two pulses.
    let accel_ticks = 1000f64.to_radians() * FRAME_S * FRAME_S * 2.0 * 1800.0 / std::f64::consts::PI;
    for (j, train) in trains.iter().enumerate() {
        let w = &train[start + k - 2..start + k + 4];
        let d: Vec<i32> = w.windows(2).map(|x| i32::from(x[1]) - i32::from(x[0])).collect();
        let jump = d.windows(2).map(|x| (x[1] - x[0]).abs()).max().unwrap();
        assert!(f64::from(jump) <= accel_ticks + 2.0, "joint {j}: step change {jump} ticks around t_v ({d:?})");
    }
    // Ends on the target at rest.
    let end: [u16; 3] = std::array::from_fn(|j| *trains[j].last().unwrap());
    assert_eq!(end, predicted(frames + 5));
    assert!(s.command("status").unwrap().contains(" lift 0.20 "));
    let used = s.stack_high_water().expect("stack painted at load");
    eprintln!("md: stack high-water after a lift check and move: {used} B");
    assert!(used <= firmware::budget("stack").unwrap() as usize, "{used} B");
}

#[test]
fn lift_refusals_stop_and_the_line_exclusion() {
    let mut s = start();
    assert_eq!(s.command("lift 0.2").unwrap(), "ok lift 0.20");
    // Lift and line exclude each other.
    assert_eq!(s.command("path line").unwrap(), "err lift and path line exclusive");
    assert_eq!(s.command("lift 0.6").unwrap(), "err out of range");
    assert_eq!(s.command("lift 0").unwrap(), "err out of range");
    // A via pose over the rim: from (90, 80, -20) (1.97 from the shoulder)
    // 0.5 higher than the higher end is out of reach.
    assert_eq!(s.command("lift off").unwrap(), "ok lift off");
    let r = s.command("goto 90 80 -20").unwrap();
    s.run_for(ts(&r) + 0.2).unwrap();
    assert_eq!(s.command("lift 0.5").unwrap(), "ok lift 0.50");
    let (reply, _) = path_command(&mut s, "goto 80 80 -20");
    assert_eq!(reply, "err lift via pose unreachable");
    // STOP while a lift is checked, then mid-lift: frozen, a new target
    // refused while it runs.
    assert_eq!(s.command("lift off").unwrap(), "ok lift off");
    let r = s.command("goto 90 100 -100").unwrap();
    s.run_for(ts(&r) + 0.2).unwrap();
    assert_eq!(s.command("lift 0.2").unwrap(), "ok lift 0.20");
    let from = s.avr.uart_output().len();
    // One frame in: the check (a few frames of hull vertices) is still
    // running.
    s.avr.uart_send(b"goto 40 70 -110\n");
    s.run_for(0.02).unwrap();
    assert_eq!(s.command("stop").unwrap(), "ok stop");
    let (cancelled, _) = s.await_line(from, &["err"], 0.2).unwrap().expect("the cancelled move's reply");
    assert_eq!(cancelled, "err path check stopped");
    assert_eq!(s.command("resume").unwrap(), "ok resume");
    let (reply, _) = path_command(&mut s, "goto 40 70 -110");
    s.run_for(0.4 * ts(&reply)).unwrap();
    assert_eq!(s.command("goto 90 100 -100").unwrap(), "err busy moving");
    assert_eq!(s.command("stop").unwrap(), "ok stop");
    s.run_for(0.1).unwrap();
    let held = s.last_pulses();
    s.run_for(1.0).unwrap();
    assert_eq!(s.last_pulses(), held);
    assert!(s.command("status").unwrap().starts_with("ok status stopped "));
    // A joint limit where the two terms overshoot: some joint of this lift
    // (h = 0.5) goes past both its ends and the via pose on its way; with
    // its limit halfway into that overshoot the target and the via pose are
    // inside, the move is not.
    assert_eq!(s.command("resume").unwrap(), "ok resume");
    assert_eq!(s.command("lift off").unwrap(), "ok lift off");
    let r = s.command("goto 90 100 -100").unwrap();
    s.run_for(ts(&r) + 0.2).unwrap();
    let plan = host_lift(0.5);
    let (start, target) = ([90.0f64, 100.0, -100.0].map(f64::to_radians), [40.0f64, 70.0, -110.0].map(f64::to_radians));
    let names = ["base", "shoulder", "elbow"];
    let mut found = None;
    for j in 0..3 {
        let qs: Vec<f64> = (0..=400).map(|i| plan.positions(plan.ts() * f64::from(i) / 400.0)[j]).collect();
        let (lo, hi) = qs.iter().fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(*q), b.max(*q)));
        let top = start[j].max(target[j]).max(plan.via()[j]);
        let bottom = start[j].min(target[j]).min(plan.via()[j]);
        if hi > top + 0.02 {
            found = Some((j, "max_deg", (hi + top) / 2.0));
        } else if lo < bottom - 0.02 {
            found = Some((j, "min_deg", (lo + bottom) / 2.0));
        }
        eprintln!(
            "lift 0.5: {} from {:.2}° to {:.2}° (ends and via {:.2}°..{:.2}°)",
            names[j],
            lo.to_degrees(),
            hi.to_degrees(),
            bottom.to_degrees(),
            top.to_degrees()
        );
    }
    let (j, field, limit) = found.expect("a joint overshoots");
    let line = format!("cal set {} {field} {:.2}", names[j], limit.to_degrees());
    assert_eq!(s.command(&line).unwrap(), "ok cal set", "{line}");
    assert_eq!(s.command("lift 0.5").unwrap(), "ok lift 0.50");
    let (reply, _) = path_command(&mut s, "goto 40 70 -110");
    assert_eq!(reply, format!("err lift joint limit {}", names[j]));
}

/// Issue #24, F1 on the chip: the check keeps every joint in its output
/// window (angle ∩ pulse limits). From (90, 60, -60) `circle 0.1` needs the
/// shoulder up to 72.336° (scenario `path_pulse_window.scn` derives it);
/// with its pulse limit at 1320 µs (72.0° at 10 µs per degree from 600 µs)
/// it is refused as the angle limit 72° is, with 1330 µs (73.0°) it runs
/// and the measured effector stays on its circle: no pulse stopped at a
/// clamp while the plan went on.
#[test]
fn a_pulse_limit_bounds_a_path_as_an_angle_limit_does() {
    let mut s = start();
    let r = s.command("goto 90 60 -60").unwrap();
    s.run_for(ts(&r) + 0.2).unwrap();
    assert_eq!(s.command("cal set shoulder max_us 1320").unwrap(), "ok cal set");
    let before = s.last_pulses();
    let (reply, _) = path_command(&mut s, "circle 0.1");
    assert_eq!(reply, "err path joint limit shoulder");
    assert_eq!(s.last_pulses(), before);
    assert_eq!(s.command("cal set shoulder max_us 2400").unwrap(), "ok cal set");
    assert_eq!(s.command("cal set shoulder max_deg 72").unwrap(), "ok cal set");
    let (reply, _) = path_command(&mut s, "circle 0.1");
    assert_eq!(reply, "err path joint limit shoulder");
    assert_eq!(s.command("cal set shoulder max_deg 180").unwrap(), "ok cal set");
    assert_eq!(s.command("cal set shoulder max_us 1330").unwrap(), "ok cal set");
    let t0 = s.avr.time_s();
    let (reply, _) = path_command(&mut s, "circle 0.1");
    assert!(reply.starts_with("ok circle r_milli 100 ts_ms "), "{reply}");
    s.run_for(ts(&reply) + 0.3).unwrap();
    let path = measured_path(&s, t0);
    let a = fk_deg([90.0, 60.0, -60.0]);
    let c = [0.0, a[1] - 0.1, a[2]];
    let worst = path.iter().map(|p| (dist(p, &c) - 0.1).abs().max(p[0].abs())).fold(0.0, f64::max);
    eprintln!("md: circle under a 1330 µs shoulder limit: at most {worst:.5} off its circle");
    assert!(worst <= 0.005, "{worst}");
    assert!(path.iter().any(|p| dist(p, &a) > 0.19));
}

/// Issue #24, F4 on the chip: the line from the nearly stretched arm
/// (elbow at −0.63°) at the fast preset. The check refines around the path's
/// ends as around its critical points, where a joint's path rate near the
/// rim meets the law starting or stopping; the chip decides what the host's
/// f64 check of the same request decides (its duration, to the
/// millisecond's rounding), and the measured pulses' second differences stay
/// within 98 % of max_accel plus the two ticks of rounding.
#[test]
fn a_line_from_the_rim_is_slowed_to_its_acceleration_limit() {
    use touch_arm::geometry::ik::Branch;
    use touch_arm::geometry::path::Path;
    use touch_arm::motion::path::{Pace, PathArm, PathLimits, PathPlan, PathRequest};
    use touch_arm::motion::plan::LawKind;
    let mut s = start();
    let r = s.command("goto 0.9 36.82 -0.63").unwrap();
    s.run_for(ts(&r) + 0.3).unwrap();
    assert_eq!(s.command("path line").unwrap(), "ok path line");
    let t0 = s.avr.time_s();
    // The bounds between the samples halve many stretches next to the rim:
    // the check takes seconds here (printed).
    let (reply, decided) = path_command_within(&mut s, "goto 81.64 124.21 -138.52", 60.0);
    assert!(reply.starts_with("ok goto path line ts_ms "), "{reply}");
    eprintln!("md: rim line check decided in {decided:.3} s ({:.0} frames)", decided / FRAME_S);
    // The host's check of the same line: the default calibration's windows,
    // the fast preset's 98 % of 3 rad/s and 98 % of max_accel, the chip's
    // scan (its intervals and refinement).
    let maps = firmware::default_servo_maps().unwrap();
    let (mut min, mut max, mut speed, mut accel) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
    for j in 0..3 {
        let (lo, hi) = maps[j].output_window();
        (min[j], max[j]) = (f64::from(lo), f64::from(hi));
        speed[j] = maps[j].max_speed::<f64>() * 0.98;
        accel[j] = maps[j].max_accel::<f64>() * 0.98;
    }
    let lim = PathLimits { min, max, speed, accel, ts_max: 30.0 };
    let (a, b) = (fk_deg([0.9, 36.82, -0.63]), fk_deg([81.64, 124.21, -138.52]));
    let req = PathRequest {
        path: Path::line(&a, &b).unwrap(),
        law: LawKind::Zat,
        ts: 0.5,
        pace: Pace::SlowDown,
        samples: touch_arm::app::CHECK_SAMPLES,
        refine: touch_arm::app::CHECK_REFINE,
    };
    let host = PathPlan::new(&req, &PathArm { links: links(), branch: Branch::Minus }, &lim).unwrap();
    eprintln!("md: rim line on the chip: {reply}; host f64 ts {:.4} s", host.ts());
    assert!((ts(&reply) - host.ts()).abs() <= 0.0015, "{reply} vs {}", host.ts());
    s.run_for(ts(&reply) + 0.3).unwrap();
    let p = s.pulses().map(|p| p.into_iter().filter(|(t, _)| *t >= t0).map(|(_, w)| w).collect::<Vec<_>>());
    let mut worst = 0.0f64;
    for j in 0..3 {
        let k = f64::from(maps[j].cal().us_per_rad).abs();
        for w in p[j].windows(3) {
            let acc = (w[2] - 2.0 * w[1] + w[0]).abs() / k / (FRAME_S * FRAME_S);
            let allowed = accel[j] + 1.0 / k / (FRAME_S * FRAME_S);
            worst = worst.max(acc / allowed);
        }
    }
    eprintln!("md: rim line on the chip: measured acceleration at most {worst:.3} of the limit plus rounding");
    assert!(worst <= 1.0, "{worst}");
}
