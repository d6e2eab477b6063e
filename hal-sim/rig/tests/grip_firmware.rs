//! The gripper on the real firmware ELF in simavr (issue #14 §3): its pulses
//! on D11 (Timer1's OC1A), none before the configuration is loaded, then
//! open with the joints' home pose; a grip moved by the selected law, frame
//! by frame what the planner plans on the host, inside its limits; STOP
//! freezing it.
//!
//! Default gripper calibration (`config::grip::GRIP_DEFAULT`): 600 µs at 0°,
//! 10 µs per degree, 600..1500 µs over 0..90° (open 0°, closed 90°).

use touch_arm::app::AppParams;
use touch_arm::config::grip::GRIP_DEFAULT;
use touch_arm::config::settings::SpeedPreset;
use touch_arm::motion::plan::LawKind;
use touch_arm::motion::planner::plan_move::plan_move;
use touch_arm::motion::planner::request::{MoveRequest, PlanLimits};
use touch_arm::servo::map::ServoMap;
use touch_arm_rig::firmware::{self, Session};
use touch_arm_rig::panel::PanelWiring;

/// 600 µs and 1500 µs in ticks of 0.5 µs.
const OPEN_TICKS: u16 = 1200;
const CLOSED_TICKS: u16 = 3000;

fn ready() -> Session {
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::A, 5).expect("firmware ELF (cargo avr)");
    s.run_for(1.0).unwrap();
    s.run_until_ready(2.0).unwrap();
    s
}

/// The gripper pulses (ticks) rising after `cycle`.
fn grip_after(s: &Session, cycle: u64) -> Vec<u16> {
    s.grip_pulse_ticks().into_iter().filter(|(c, _)| *c > cycle).map(|(_, t)| t).collect()
}

#[test]
fn no_gripper_pulse_before_the_configuration_then_open_with_the_home_pose() {
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::A, 3).unwrap();
    s.run_for(0.05).unwrap();
    assert!(s.grip_pulse_ticks().is_empty(), "a gripper pulse before the configuration was loaded");
    s.run_for(1.0).unwrap();
    let grip = s.grip_pulse_ticks();
    let base = &s.pulse_ticks()[0];
    assert!(grip.len() > 10, "{grip:?}");
    assert!(grip.iter().all(|(_, t)| *t == OPEN_TICKS), "the gripper opens at 600 us: {grip:?}");
    // Its first pulse comes in the period of the joints' first (the home
    // pose's), its rise within a timer tick (8 cycles) of theirs.
    let first_base = (base[0].0 * f64::from(firmware::CPU_HZ)).round() as i64;
    assert!((grip[0].0 as i64 - first_base).abs() <= 8, "gripper first rise {} vs base {first_base}", grip[0].0);
}

/// `grip close` after power-up: the first grip runs at the slow preset
/// (25 % of 3 rad/s less the 2 % margin); its pulses, frame by frame, are
/// the host planner's plan through the gripper's map (±1 tick for the chip's
/// float rounding), within 600..1500 µs, and end on 1500 µs.
#[test]
fn a_grip_moves_by_the_law_within_its_limits() {
    let mut s = ready();
    let t0 = s.avr.cycles();
    assert_eq!(s.command("grip close").unwrap(), "ok grip 9000 ts_ms 4317");
    s.run_for(4.6).unwrap();
    let chip = grip_after(&s, t0);

    let p = AppParams::DEFAULT;
    let keep = 1.0 - p.speed_margin;
    let speed = GRIP_DEFAULT.max_speed_rad_s * f32::from(SpeedPreset::Slow.percent()) * 0.01 * keep;
    let accel = GRIP_DEFAULT.max_accel_rad_s2 * keep;
    let lim = PlanLimits {
        speed: [speed; 3],
        accel: [accel; 3],
        ts_min: p.ts_min,
        zat_ts_min: p.zat_ts_min,
        ts_max: p.ts_max,
        n: p.n,
    };
    let req = MoveRequest { start: [0.0, 0.0, 0.0], target: [GRIP_DEFAULT.max_rad, 0.0, 0.0], law: LawKind::Zat };
    let planned = plan_move(&req, &lim).unwrap();
    assert_eq!((planned.ts * 1000.0).round(), 4317.0);
    let map = ServoMap::new(&GRIP_DEFAULT).unwrap();
    let frames = (planned.ts / 0.02).ceil() as usize + 1;
    let host: Vec<u16> =
        (0..frames).map(|k| map.angle_to_pulse(planned.plan.positions(k as f32 * 0.02)[0]).unwrap().ticks).collect();

    assert!(chip.iter().all(|t| (OPEN_TICKS..=CLOSED_TICKS).contains(t)), "outside 600..1500 us: {chip:?}");
    assert_eq!(*chip.last().unwrap(), CLOSED_TICKS);
    // Align on the first pulse that left the open end.
    let c0 = chip.iter().position(|t| *t != OPEN_TICKS).unwrap();
    let h0 = host.iter().position(|t| *t != OPEN_TICKS).unwrap();
    let chip_move = &chip[c0..c0 + (host.len() - h0)];
    for (k, (c, h)) in chip_move.iter().zip(&host[h0..]).enumerate() {
        assert!(c.abs_diff(*h) <= 1, "frame {k} of the move: chip {c}, host {h}");
    }
    // Smooth: never back, and at most 8.42 us (16.8 ticks) a frame.
    for w in chip.windows(2) {
        assert!(w[1] >= w[0] && w[1] - w[0] <= 17, "step {} -> {}", w[0], w[1]);
    }
    assert!(chip[c0 + host.len() - h0..].iter().all(|t| *t == CLOSED_TICKS));
}

#[test]
fn stop_freezes_the_gripper_and_refuses_grips() {
    let mut s = ready();
    assert!(s.command("grip close").unwrap().starts_with("ok grip 9000"));
    s.run_for(1.5).unwrap();
    assert_eq!(s.command("stop").unwrap(), "ok stop");
    // The frame that read `stop` already holds; allow the period in flight.
    s.run_for(0.05).unwrap();
    let t_stop = s.avr.cycles();
    s.run_for(1.0).unwrap();
    let held = grip_after(&s, t_stop);
    assert!(held.len() >= 45, "{held:?}");
    assert!(held.iter().all(|t| *t == held[0]), "the gripper moved under STOP: {held:?}");
    assert!(held[0] > OPEN_TICKS && held[0] < CLOSED_TICKS, "stopped mid-grip: {}", held[0]);
    assert_eq!(s.command("grip open").unwrap(), "err stopped (send resume)");
    assert_eq!(s.command("resume").unwrap(), "ok resume");
    assert!(s.command("grip open").unwrap().starts_with("ok grip 0 ts_ms "));
    s.run_for(3.0).unwrap();
    assert_eq!(s.grip_pulse_ticks().last().unwrap().1, OPEN_TICKS);
}
