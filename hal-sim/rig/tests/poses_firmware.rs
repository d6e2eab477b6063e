//! Saved poses on the real firmware ELF in simavr (issue #14 §4): a pose
//! saved on the chip survives a power cycle (a new chip with the old
//! EEPROM) and is reached through the planner, and a power cycle at any
//! point of a pose save loads the poses before it or the new ones.
//!
//! Default servo calibration: 10 µs per degree, base and shoulder 600 µs at
//! 0°, elbow 2400 µs at 0°: (30, 120, −150)° is 900, 1800, 900 µs; the
//! gripper's 600 µs at 0° (open, where it starts), 10 µs per degree: 45° is
//! 1050 µs.

use touch_arm::config::poses::{POSE_RECORD_LEN, POSE_SLOT_A, POSE_SLOT_B};
use touch_arm_rig::firmware::Session;

fn boot(eeprom: Option<&[u8]>) -> Session {
    Session::boot_product(eeprom).expect("firmware ELF (cargo avr)")
}

fn go(s: &mut Session, cmd: &str, want: &str) {
    s.go(cmd, want, 0.2).unwrap();
}

const LIST_EMPTY: &str = "ok pose list 1 empty 2 empty 3 empty 4 empty";
const LIST_SAVED: &str = "ok pose list 1 empty 2 30.00 120.00 -150.00 grip 0.00 3 empty 4 empty";

/// The pose holds the gripper's angle too: after the power cycle the
/// gripper starts open (600 µs) and `pose go` closes it to 45° (1050 µs)
/// with the arm's move; the grip is planned a frame after the arm's, and
/// its first grip after power-up runs slow (1.5708/2 rad at 0.735 rad/s:
/// 2.15868 s), longer than the arm's 1.43912 s: the wait covers it.
#[test]
fn a_pose_saved_on_the_chip_survives_a_power_cycle_and_is_reached() {
    let mut s = boot(None);
    assert_eq!(s.command("pose list").unwrap(), LIST_EMPTY);
    go(&mut s, "goto 30 120 -150", "ok goto ");
    assert!(s.command("grip 45").unwrap().starts_with("ok grip 4500 ts_ms "));
    s.run_for(2.5).unwrap();
    assert_eq!(s.command("pose save 2").unwrap(), "ok pose save 2 seq 1");
    let ee = s.avr.eeprom().unwrap();

    let mut s = boot(Some(&ee));
    assert_eq!(
        s.command("pose list").unwrap(),
        "ok pose list 1 empty 2 30.00 120.00 -150.00 grip 45.00 3 empty 4 empty"
    );
    assert_eq!(s.grip_pulse_ticks().last().unwrap().1, 1200, "open after the power cycle");
    go(&mut s, "pose go 2", "ok pose go 2 ts_ms ");
    s.run_for(1.0).unwrap();
    let last = s.last_pulses();
    for (j, want) in [900.0, 1800.0, 900.0].iter().enumerate() {
        assert!((last[j].unwrap() - want).abs() <= 0.25, "joint {j}: {:?}", last);
    }
    let grip: Vec<u16> = s.grip_pulse_ticks().into_iter().map(|(_, t)| t).collect();
    assert_eq!(*grip.last().unwrap(), 2100, "the gripper at 45 deg = 1050 us");
    assert!(grip.windows(2).all(|w| w[1] >= w[0]), "the gripper went back on its way");
}

/// The save is cut by taking the EEPROM as it is every 100 cycles of the
/// save (every state the byte-by-byte writes pass through) and booting a new
/// chip with some of them, spread over the whole save.
#[test]
fn a_power_cycle_during_a_pose_save_loads_the_old_or_the_new_poses() {
    let mut s = boot(None);
    go(&mut s, "goto 30 120 -150", "ok goto ");
    assert_eq!(s.command("pose save 2").unwrap(), "ok pose save 2 seq 1");
    go(&mut s, "goto 90 90 -90", "ok goto ");
    let before = s.avr.eeprom().unwrap();
    let slots =
        |e: &[u8]| [POSE_SLOT_A, POSE_SLOT_B].map(|a| e[usize::from(a)..usize::from(a) + POSE_RECORD_LEN].to_vec());
    let from = s.avr.uart_output().len();
    s.avr.uart_send(b"pose clear 2\n");
    let mut cuts = Vec::new();
    for _ in 0..20_000 {
        s.avr.run_cycles(100).unwrap();
        let now = s.avr.eeprom().unwrap();
        if slots(&now) != slots(&before) && cuts.last() != Some(&now) {
            cuts.push(now);
        }
        if s.avr.uart_output_string()[from..].contains("ok pose clear") {
            break;
        }
    }
    // The rest of the reply line.
    s.run_for(0.01).unwrap();
    let out = s.avr.uart_output_string()[from..].to_string();
    assert!(out.contains("ok pose clear 2 seq 2"), "{out}");
    // The EEPROM driver skips bytes that already hold their value. Per slot:
    // the commit byte cleared; the sequence's low byte (1 -> 2); slot 2's flag
    // and the non-zero bytes of 3000 (b8 0b 00 00: 2), 12000 (e0 2e 00 00: 2)
    // and -15000 (68 c5 ff ff: 4), now zeros; both CRC bytes; the commit byte
    // set: 14 writes, each a state the EEPROM passes through; two slots.
    assert_eq!(cuts.len(), 28);
    let (mut old, mut new) = (0, 0);
    for (k, e) in cuts.iter().enumerate().step_by(cuts.len() / 8) {
        let mut c = boot(Some(e));
        let list = c.command("pose list").unwrap();
        assert!(list == LIST_SAVED || list == LIST_EMPTY, "cut {k} of {}: {list}", cuts.len());
        if list == LIST_SAVED {
            old += 1;
        } else {
            new += 1;
        }
    }
    assert!(old > 0 && new > 0, "old {old}, new {new}");
}
