//! Issue #24, F4: a path move keeps every joint within its speed and
//! acceleration limits between the check's samples too, near the stretched
//! arm where the elbow's rates grow like 1/sin θ₃ in a spike no sampling
//! grid is sure to hit. Measured from the commanded angles of every frame:
//! a first difference over one frame is a mean of the joint's speed over
//! it, a second difference over two frames a (triangle-weighted) mean of its
//! acceleration, so neither can exceed the largest value of the move, and
//! both must stay within the limits the check planned for.

use hal_sim::{Sim, SimSetup};
use touch_arm::app::FRAME_S;

/// (largest speed / limit, largest acceleration / limit) over the joints,
/// from the commanded angles of frames `from..`; `speed_share` is the
/// preset's share of the max speed (98 % of it: the planning margin), the
/// acceleration limit is 98 % of max_accel.
fn worst_rates(sim: &Sim, from: usize, speed_share: f64) -> (f64, f64) {
    let cal = &sim.app.config().joints;
    let q: Vec<[f64; 3]> = sim.history[from..].iter().map(|r| r.commanded.map(f64::from)).collect();
    let h = f64::from(FRAME_S);
    let (mut v, mut a) = (0.0f64, 0.0f64);
    for j in 0..3 {
        let vmax = f64::from(cal[j].max_speed_rad_s) * speed_share * 0.98;
        let amax = f64::from(cal[j].max_accel_rad_s2) * 0.98;
        for w in q.windows(3) {
            v = v.max((w[1][j] - w[0][j]).abs() / h / vmax);
            a = a.max((w[2][j] - 2.0 * w[1][j] + w[0][j]).abs() / (h * h) / amax);
        }
    }
    (v, a)
}

fn reply(sim: &Sim, prefix: &str) -> String {
    sim.serial.lines().into_iter().rev().find(|l| l.starts_with(prefix)).unwrap_or_default()
}

/// The reproduction: a line from the nearly stretched arm (elbow at
/// −0.63°) at the fast preset.
#[test]
fn a_line_from_the_rim_keeps_its_acceleration_limit() {
    let mut sim = Sim::new(&SimSetup::default()).expect("default setup");
    sim.run_ms(2000);
    sim.send_line("speed fast");
    sim.run_frames(2);
    sim.send_line("goto 0.9 36.82 -0.63");
    sim.run_ms(7000);
    sim.send_line("path line");
    sim.run_frames(2);
    let from = sim.history.len();
    sim.send_line("goto 81.64 124.21 -138.52");
    // The check's bounds halve the stretches next to the rim: it takes some
    // seconds of frames before the move starts (the figure is printed).
    let mut frames = 0;
    while reply(&sim, "ok goto path line ").is_empty() && frames < 3000 {
        sim.run_frames(1);
        frames += 1;
    }
    sim.run_ms(3000);
    let r = reply(&sim, "ok goto path line ");
    assert!(!r.is_empty(), "{:?}", sim.serial.lines());
    eprintln!("md: rim line: the check answered after {frames} frames");
    let (v, a) = worst_rates(&sim, from, 1.0);
    eprintln!("md: rim line: {r}: speed {v:.4}, acceleration {a:.4} of the limits");
    assert!(v <= 1.0 + 1e-3 && a <= 1.0 + 1e-3, "speed {v}, acceleration {a} of the limits");
}
