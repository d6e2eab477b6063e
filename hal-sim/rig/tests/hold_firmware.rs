//! Hold to run on the real firmware ELF in simavr (issue #20 §5): under
//! `mode hold` a finger held on the screen's map moves the arm, the lift
//! brings it to rest along its path within the acceleration limit (the
//! measured pulses' second differences), a new held finger resumes it to
//! the target, and the stack stays within its budget. The numbers are
//! derived in `hal-sim/twin/tests/scenarios/hold_release.scn`.

use touch_arm_rig::firmware::{self, Session};

/// 10 µs per degree (the default calibration), 1000 °/s² (its max_accel):
/// one 20 ms period's second difference of a pulse at that acceleration.
const ACCEL_US_PER_FRAME2: f64 = 10.0 * 1000.0 * 0.02 * 0.02;

#[test]
fn a_lifted_finger_brings_the_arm_to_rest_and_a_held_one_resumes() {
    let mut s = Session::boot_product(None).expect("firmware ELF (cargo avr)");
    assert_eq!(s.command("mode hold").unwrap(), "ok mode hold");
    let ((rx, ry), _) = firmware::map_touch(0.3, 0.6).expect("point on the map");
    let from = s.avr.uart_output().len();
    s.press_raw(rx, ry).unwrap();
    let touch = s.await_line(from, &["info touch", "err touch"], 1.0).unwrap().expect("a commit while held");
    assert!(touch.0.starts_with("info touch"), "{touch:?}");
    s.run_for(0.6).unwrap();
    assert!(s.command("status").unwrap().starts_with("ok status moving"));
    let released = s.avr.uart_output().len();
    s.release();
    let (line, _) = s.await_line(released, &["info hold released"], 0.5).unwrap().expect("released");
    let ms: f64 = line.rsplit(' ').next().unwrap().parse().unwrap();
    assert!(ms > 0.0 && ms <= 500.0, "{line}");
    let rest = s.await_line(released, &["info hold rest"], 1.0).unwrap().expect("at rest");
    // At rest: the pulses do not change for half a second.
    s.run_for(0.1).unwrap();
    let held = s.last_pulses();
    s.run_for(0.5).unwrap();
    assert_eq!(s.last_pulses(), held, "{rest:?}");
    // Paused, not over: `status` says so.
    let status = s.command("status").unwrap();
    assert!(status.starts_with("ok status paused"), "{status}");
    // A new finger held on the map: the same move resumes and arrives.
    let again = s.avr.uart_output().len();
    s.press_raw(rx, ry).unwrap();
    assert!(s.await_line(again, &["info hold resumed"], 1.0).unwrap().is_some());
    s.run_for(4.0).unwrap();
    s.release();
    s.run_for(0.3).unwrap();
    let status = s.command("status").unwrap();
    assert!(status.starts_with("ok status holding"), "{status}");
    // Every period's second difference of every pulse within the limit
    // (plus a tick of rounding on each of the three pulses).
    for (j, p) in s.pulses().iter().enumerate() {
        for w in p.windows(3) {
            let a = (w[2].1 - 2.0 * w[1].1 + w[0].1).abs();
            assert!(a <= ACCEL_US_PER_FRAME2 + 1.5, "joint {j} at {:.3} s: {a} us", w[2].0);
        }
    }
    assert!(s.stack_high_water().unwrap() <= 2048);
}
