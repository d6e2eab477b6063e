//! Issue #24, F2: a catch-up frame (the one after a frame that ran past its
//! period, `App::frame_was_late`) does no heavy thing: no serial line, no
//! panel read, no plan, and that includes the gripper target a `pose go`
//! leaves for the frame after the arm's plan, which is the frame most likely
//! to be a catch-up (it follows the arm's plan). A twin test rather than a
//! scenario: the late frame is the firmware loop's word, not an input.

use hal_sim::{Sim, SimSetup};

/// Runs frames until a line starting with `prefix` has been written (at most
/// `max` frames); the number of frames run.
fn until_line(sim: &mut Sim, prefix: &str, max: u32) -> u32 {
    for n in 1..=max {
        sim.step();
        if sim.serial.lines().iter().any(|l| l.starts_with(prefix)) {
            return n;
        }
    }
    panic!("no {prefix:?} in {max} frames: {:?}", sim.serial.lines());
}

fn deg(rad: f32) -> f64 {
    f64::from(rad).to_degrees()
}

#[test]
fn a_pose_grip_is_not_planned_in_a_catch_up_frame() {
    let mut sim = Sim::new(&SimSetup::default()).expect("default setup");
    sim.run_ms(2000);
    for (line, ms) in [("goto 30 120 -60", 4000), ("grip 40", 3000), ("pose save 1", 100), ("grip 0", 3000)] {
        sim.send_line(line);
        sim.run_ms(ms);
    }
    sim.send_line("goto 90 90 -90");
    sim.run_ms(4000);
    assert!(sim.serial.lines().iter().any(|l| l.starts_with("ok pose save 1 seq ")), "{:?}", sim.serial.lines());
    // Frame k reads `pose go 1` and plans the arm; its gripper is due next.
    sim.send_line("pose go 1");
    until_line(&mut sim, "ok pose go 1 ", 10);
    let st = sim.app.status();
    assert!(!st.grip_moving && deg(st.grip_target).abs() < 1e-3, "planned with the arm: {st:?}");
    // Frame k ran long: frame k + 1 is a catch-up and plans nothing.
    sim.app.frame_was_late();
    sim.step();
    let st = sim.app.status();
    assert!(!st.grip_moving, "the gripper was planned in the catch-up frame");
    assert!(deg(st.grip_target).abs() < 1e-3, "grip target {}", deg(st.grip_target));
    // Frame k + 2 plans it: the pose's 40°.
    sim.step();
    let st = sim.app.status();
    assert!(st.grip_moving, "not planned after the catch-up frame");
    assert!((deg(st.grip_target) - 40.0).abs() < 1e-3, "grip target {}", deg(st.grip_target));
    sim.run_ms(4000);
    let st = sim.app.status();
    assert!((deg(st.grip) - 40.0).abs() < 1e-3 && (deg(st.commanded[0]) - 30.0).abs() < 1e-3, "{st:?}");
    // 600 µs at 0°, 10 µs per degree: 1000 µs = 2000 ticks.
    assert_eq!(st.grip_pulse, Some(2000));
}
