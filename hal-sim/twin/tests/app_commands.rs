//! The app's serial commands on the host twin (`hal_sim`): refusals keep
//! the pose and say why, homing and STOP refuse targets, and a move replies
//! with its plan (duration from the speed limits, ζ-a-tₛ's a and smooth stop).

use hal_sim::{Sim, SimSetup};
use touch_arm::app::{AppParams, Refusal, State};

fn sim(params: &AppParams) -> Sim {
    Sim::new(&SimSetup { params: *params, ..SimSetup::default() }).unwrap()
}

/// Boots and runs until homing is over.
fn homed(params: &AppParams) -> Sim {
    let mut s = sim(params);
    s.run_frames(1 + params.home_settle_frames as u64);
    assert_eq!(s.app.state(), State::Holding);
    s
}

/// Sends a line, runs two frames, returns the reply lines (telemetry left out).
fn ask(s: &mut Sim, line: &str) -> Vec<String> {
    s.serial.output.clear();
    s.send_line(line);
    s.run_frames(2);
    s.serial.lines().into_iter().map(|l| l.trim_end().to_string()).filter(|l| !l.starts_with("t ")).collect()
}

#[test]
fn refusals_keep_the_pose_and_say_why() {
    let mut r = homed(&AppParams::DEFAULT);
    let home = r.servos.pulses();
    assert_eq!(home, Some([3000, 3000, 3000]));
    let cases: &[(&str, &str)] = &[
        ("goto 200 90 -90", "err joint limit base"),
        ("goto 90 -10 -90", "err joint limit shoulder"),
        ("goto 90 90 10", "err joint limit elbow"),
        ("goto 90 90 -180.5", "err joint limit elbow"),
        ("move 50 500", "err outside calibrated area"),
        ("move 500 950", "err outside calibrated area"),
        ("move 500", "err missing argument"),
        ("law warp", "err bad argument"),
    ];
    for (cmd, want) in cases {
        assert_eq!(ask(&mut r, cmd), vec![want.to_string()], "{cmd}");
        assert_eq!(r.servos.pulses(), home, "{cmd} moved the arm");
        assert_eq!(r.app.state(), State::Holding);
    }
    // Limits are inclusive: 180° base and a straight elbow are fine.
    assert_eq!(ask(&mut r, "goto 180 90 0")[0].split(' ').take(2).collect::<Vec<_>>(), ["ok", "goto"]);
}

#[test]
fn unreachable_and_singular_points_are_refused() {
    // k = 1.5: the top-right corner lies beyond l2 + l3 = 2.
    let params = AppParams { k: 1.5, ..AppParams::DEFAULT };
    let mut r = homed(&params);
    assert_eq!(ask(&mut r, "move 900 880"), ["err unreachable"]);
    assert_eq!(r.app.status().last_refusal, Some(Refusal::Unreachable));
    assert_eq!(r.servos.pulses(), Some([3000, 3000, 3000]));
    // The origin with l2 = l3: shoulder angle undefined. A span of 123..931
    // puts raw x = 527 exactly at x_p = 0.
    let mut r = homed(&AppParams::DEFAULT);
    assert_eq!(ask(&mut r, "cal set touch x_max 931"), ["ok cal set"]);
    assert_eq!(ask(&mut r, "move 527 128"), ["err singular point"]);
}

#[test]
fn homing_stop_and_speed_limit_refusals() {
    let mut r = sim(&AppParams::DEFAULT);
    r.run_frames(1);
    assert_eq!(r.servos.pulses(), None, "no pulse in the boot frame");
    assert_eq!(ask(&mut r, "goto 45 90 -90"), ["err homing"]);
    r.run_frames(60);
    assert_eq!(ask(&mut r, "stop"), ["ok stop"]);
    assert_eq!(r.app.state(), State::Stopped);
    assert_eq!(ask(&mut r, "goto 45 90 -90"), ["err stopped (send resume)"]);
    assert_eq!(ask(&mut r, "resume"), ["ok resume"]);
    // 0.5 °/s on the base: 90° would need ≫ 30 s.
    assert_eq!(ask(&mut r, "cal set base max_speed 0.5"), ["ok cal set"]);
    assert_eq!(ask(&mut r, "goto 0 90 -90"), ["err speed limit needs ts above max"]);
    assert_eq!(r.servos.pulses(), Some([3000, 3000, 3000]));
}

#[test]
fn first_move_is_slow_and_reports_its_plan() {
    let mut r = homed(&AppParams::DEFAULT);
    assert_eq!(ask(&mut r, "law quintic"), ["ok law quintic"]);
    // 60° on the base at 25 % (first move) of 3 rad/s less 2 %: 0.735 rad/s,
    // T = 1.875·(π/3)/0.735 = 2.6714 s.
    assert_eq!(ask(&mut r, "goto 30 90 -90"), ["ok goto ts_ms 2671 vend 0 0 0"]);
    r.run_frames(200);
    // 30° on the base: 900 µs = 1800 Timer5 ticks of 0.5 µs.
    assert_eq!(r.servos.pulses(), Some([1800, 3000, 3000]));
    // The second at the normal 50 %: T = 1.875·(π/3)/1.47 = 1.3357 s.
    assert_eq!(ask(&mut r, "goto 90 90 -90"), ["ok goto ts_ms 1336 vend 0 0 0"]);
    // The time-scaled ζ-a-tₛ in closed form: T = 2.020156·(π/3)/1.47 =
    // 1.43912 s, ending at rest.
    r.run_frames(100);
    assert_eq!(ask(&mut r, "law zat"), ["ok law zat"]);
    assert_eq!(ask(&mut r, "goto 30 90 -90"), ["ok goto ts_ms 1439 vend 0 0 0"]);
    // The papers' form reports a and the smooth stop; 60° at 50 % → tₛ ≈ 1.444 s.
    r.run_frames(100);
    assert_eq!(ask(&mut r, "law zat-paper"), ["ok law zat-paper"]);
    let reply = ask(&mut r, "goto 90 90 -90");
    let f: Vec<&str> = reply[0].split(' ').collect();
    assert_eq!(&f[..3], ["ok", "goto", "ts_ms"]);
    let ts: f64 = f[3].parse().unwrap();
    assert!((1444.0..1474.0).contains(&ts), "{reply:?}");
    assert_eq!(&f[4..], ["a_milli", f[5], "smooth", "vend", "0", "0", "0"]);
    // A low acceleration limit lengthens a short move: 10° on the base at
    // 100 °/s² less 2 %: T = √(6.636934·(π/18)/(1.7453·0.98)) = 0.8229 s,
    // where the speed alone would take 0.24 s.
    r.run_frames(100);
    assert_eq!(ask(&mut r, "law zat"), ["ok law zat"]);
    assert_eq!(ask(&mut r, "cal set base max_accel 100"), ["ok cal set"]);
    assert_eq!(ask(&mut r, "goto 80 90 -90"), ["ok goto ts_ms 823 vend 0 0 0"]);
    r.run_frames(50);
    assert_eq!(ask(&mut r, "cal set base max_accel 0"), ["err base accel"]);
}

/// The wiring probe's verdict as the app takes it (`app::wiring`; the
/// probe itself runs on the chip: `touch_wiring.rs`): wanted after a boot
/// with no stored wiring, reported, kept by `cal reset`, saved with the
/// configuration; an unidentified wiring is an unsolicited `err touch`
/// line and the screen's top warning.
#[test]
fn the_wiring_verdict_is_reported_kept_and_saved() {
    use touch_arm::config::store;
    use touch_arm::touch::wiring::{Links, Wiring, WiringUnknown};
    use touch_arm::ui::warn;
    let mut s = sim(&AppParams { screen: true, ..AppParams::DEFAULT });
    assert!(!s.app.wiring_probe_wanted(), "before the configuration is loaded");
    s.run_frames(1);
    assert!(s.app.wiring_probe_wanted() && !s.app.pulses_started());
    s.serial.output.clear();
    // Wiring a's plates and one pair (0: D6–A1) neither plate nor open.
    let links = Links { plate: Wiring::A.plates(), open: 0xFFF & !Wiring::A.plates() & !1 };
    s.app.set_wiring(Err(WiringUnknown(links)), &mut s.serial);
    assert_eq!(s.serial.lines(), ["err touch wiring unknown plates 0x880 open 0x77e"]);
    assert_eq!(hal_sim::random_input::replies_in("err touch wiring unknown plates 0x880 open 0x77e"), 0);
    assert!(!s.app.wiring_probe_wanted(), "one probe per boot");
    assert_eq!(s.app.config().wiring, None);
    assert_ne!(s.app.ui_model().warnings & warn::TOUCH_WIRING, 0);
    assert_eq!(touch_arm::ui::warning_line(s.app.ui_model().warnings).as_str(), "! touch wiring unknown");

    s.serial.output.clear();
    s.app.set_wiring(Ok(Wiring::B), &mut s.serial);
    assert_eq!(s.serial.lines(), ["info wiring b"]);
    assert_eq!(s.app.config().wiring, Some(Wiring::B));
    assert_eq!(s.app.ui_model().warnings & warn::TOUCH_WIRING, 0);
    s.run_frames(u64::from(AppParams::DEFAULT.home_settle_frames));
    assert_eq!(ask(&mut s, "cal reset"), ["ok cal reset"]);
    assert_eq!(s.app.config().wiring, Some(Wiring::B), "a fact about the shield, not a setting");
    assert!(ask(&mut s, "cal save")[0].starts_with("ok cal save"));
    assert_eq!(store::load(&mut s.eeprom).config.wiring, Some(Wiring::B));

    // A boot with the stored wiring does not probe.
    let mut again = sim(&AppParams { screen: true, ..AppParams::DEFAULT });
    again.eeprom = s.eeprom.clone();
    again.run_frames(1);
    assert_eq!(again.app.config().wiring, Some(Wiring::B));
    assert!(!again.app.wiring_probe_wanted());
}
