//! The arm's own geometry on the real firmware ELF in simavr (issue #21
//! §4): link lengths change the pose a touch point gives, the home pose
//! set and saved on the chip is where it powers up, and `park` goes to the
//! park pose.
//!
//! Default servo calibration: 10 µs per degree, base and shoulder 600 µs at
//! 0°, elbow 2400 µs at 0°. The angles are derived in
//! `hal-sim/twin/tests/scenarios/arm_geometry.scn`: raw (700, 700) with
//! links of 120 and 80 mm is (60.1733, 101.9263, −134.4632)°, i.e.
//! 1201.733, 1619.263 and 1055.368 µs; pulses are whole Timer5 ticks of
//! 0.5 µs.

use touch_arm_rig::firmware::{self, Session};

fn boot(eeprom: Option<&[u8]>) -> Session {
    Session::boot_product(eeprom).expect("firmware ELF (cargo avr)")
}

fn go(s: &mut Session, cmd: &str, want: &str) {
    s.go(cmd, want, 0.3).unwrap();
}

fn assert_pulses(s: &Session, want: [f64; 3], tol: f64, what: &str) {
    let last = s.last_pulses();
    for (j, w) in want.iter().enumerate() {
        assert!((last[j].unwrap() - w).abs() <= tol, "{what}, joint {j}: {last:?}, want {want:?}");
    }
}

#[test]
fn links_home_and_park_set_on_the_chip() {
    let mut s = boot(None);
    assert_eq!(s.command("cal set arm l2 120").unwrap(), "ok cal set");
    assert_eq!(s.command("cal set arm l3 80").unwrap(), "ok cal set");
    // Inside the 0.4-unit disc the unequal links cannot reach.
    assert_eq!(s.command("move 600 400").unwrap(), "err unreachable");
    go(&mut s, "move 700 700", "ok move cond ");
    assert_pulses(&s, [1201.733, 1619.263, 1055.368], 0.3, "links 120/80");
    assert_eq!(s.command("cal set home 45 100 -80").unwrap(), "ok cal set");
    assert_eq!(s.command("cal set park 90 150 -150").unwrap(), "ok cal set");
    assert_eq!(s.command("cal set park 90 150 -181").unwrap(), "err joint limit elbow");
    assert!(s.command("cal save").unwrap().starts_with("ok cal save seq "));
    let ee = s.avr.eeprom().unwrap();

    let mut s = boot(Some(&ee));
    assert_pulses(&s, [1050.0, 1600.0, 1600.0], 0.0, "home after the power cycle");
    go(&mut s, "park", "ok park ts_ms ");
    assert_pulses(&s, [1500.0, 2100.0, 900.0], 0.0, "park");
    // The saved links came back too.
    go(&mut s, "move 700 700", "ok move cond ");
    assert_pulses(&s, [1201.733, 1619.263, 1055.368], 0.3, "links after the power cycle");
}

/// Unequal links end to end: a touch on the screen's map, with links of 120
/// and 80 mm set over serial, lands on the host's f64 IK pose of the
/// touched point for the same lengths (`ArmGeometry::from_lengths`), in
/// the measured pulses.
#[test]
fn a_touch_with_unequal_links_lands_on_the_hosts_pose() {
    use touch_arm::geometry::ik::Branch;
    use touch_arm::geometry::pose::{pose_for_point, ArmGeometry};
    let mut s = boot(None);
    assert_eq!(s.command("cal set arm l2 120").unwrap(), "ok cal set");
    assert_eq!(s.command("cal set arm l3 80").unwrap(), "ok cal set");
    // The map repaints with the new reach shading; a touch while a repaint
    // is drawn is cancelled (only STOP answers then), so wait for it.
    s.run_for(2.0).unwrap();
    let geo = ArmGeometry::from_lengths(1.0f64, 120.0, 80.0, Branch::Minus).unwrap();
    for (x, y) in [(0.3f32, 0.6f32), (-0.5, 0.4)] {
        let ((rx, ry), (wx, wy)) = firmware::map_touch(x, y).expect("point on the map");
        let p = pose_for_point(&geo, wx, wy).unwrap();
        let deg = 180.0 / std::f64::consts::PI;
        let want = [600.0 + 10.0 * p.alpha * deg, 600.0 + 10.0 * p.q2 * deg, 2400.0 + 10.0 * p.q3 * deg];
        s.press_raw(rx, ry).unwrap();
        s.run_for(0.3).unwrap();
        s.release();
        s.run_for(4.0).unwrap();
        let out = s.avr.uart_output_string();
        assert!(s.command("status").unwrap().starts_with("ok status holding"), "{out}");
        // The chip's f32 chain and its half-µs ticks.
        assert_pulses(
            &s,
            want,
            0.6,
            &format!("touch at ({x}, {y}): {}", out.lines().rev().take(8).collect::<Vec<_>>().join(" | ")),
        );
    }
}
