//! The real firmware ELF under simavr: its 50 Hz demo frames (f32 on the chip)
//! against the same ζ-a-tₛ plan computed on the host in f64.
//! The ELF is built by `scripts/test.sh` (`cargo avr`) before the tests run.

use hal_sim::firmware::{self, parse_frame};
use touch_arm::plan::MultiPlan;
use touch_arm::zat::{smooth_stop_a, ShapeParams};

/// The demo move in src/main.rs, as the f32 constants the chip holds.
const START: [f32; 3] = [1.570_796_3, 0.785_398_2, 1.570_796_3];
const TARGET: [f32; 3] = [0.785_398_2, 0.2, 2.2];
const TS: f64 = 2.0;
const N: f64 = 2.0;

#[test]
fn demo_frames_match_the_host_f64_plan() {
    let mut avr = firmware::load(&firmware::default_elf()).unwrap();
    avr.run_until_output(b"done\n", 16_000_000 * 5).expect("firmware finishes the demo");
    let text = avr.uart_output_string();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("touch-arm "), "{text}");

    let a = smooth_stop_a(TS, N).unwrap();
    assert_eq!(a, 1.0);
    let plan = MultiPlan::new(&START.map(f64::from), &TARGET.map(f64::from), &ShapeParams { ts: TS, a, n: N }).unwrap();
    let p = lines.iter().find(|l| l.starts_with("P ")).expect("plan line");
    assert_eq!(*p, "P 2000000 1000000 2000000");

    let frames: Vec<_> = lines.iter().filter_map(|l| parse_frame(l)).collect();
    assert_eq!(frames.len(), 103, "k = 0..=102 at 50 Hz");
    let mut worst_q = 0.0f64;
    let mut worst_v = 0.0f64;
    for (i, f) in frames.iter().enumerate() {
        assert_eq!(f.k as usize, i);
        assert_eq!(f.t_us, 20_000 * i as u32);
        let s = plan.sample(f.t_us as f64 * 1e-6);
        for j in 0..3 {
            let dq = (f.q_urad[j] as f64 - s[j].pos * 1e6).abs();
            let dv = (f.v_urad_s[j] as f64 - s[j].vel * 1e6).abs();
            worst_q = worst_q.max(dq);
            worst_v = worst_v.max(dv);
            // µrad rounding (0.5) + f32 evaluation (SPEC: 4e-7 of |Δ| ≤ 0.8 rad).
            assert!(dq <= 1.0, "frame {i} joint {j}: chip {} µrad vs host {:.3}", f.q_urad[j], s[j].pos * 1e6);
            assert!(dv <= 3.0, "frame {i} joint {j}: chip {} µrad/s vs host {:.3}", f.v_urad_s[j], s[j].vel * 1e6);
        }
    }
    eprintln!("demo frames: worst |Δq| {worst_q:.2} µrad, worst |Δv| {worst_v:.2} µrad/s");
    // Exact arrival: the frame at tₛ prints the targets.
    let end = &frames[100];
    assert_eq!(end.t_us, 2_000_000);
    for j in 0..3 {
        assert_eq!(end.q_urad[j], (TARGET[j] as f64 * 1e6).round() as i32);
    }
}
