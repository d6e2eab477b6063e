//! Benchmark firmware: times the chip's hot routines in exact CPU cycles
//! (run it in simavr; `scripts/bench.sh` does and writes BENCHMARKS.md).
//!
//! Every routine runs [`REPS`] times on varied inputs; each run is timed alone
//! between two cycle stamps (Timer1/Timer3, see `board::cycles`), with its
//! input passed through `black_box` after the first stamp and its result
//! through `black_box` before the second, so the compiler can neither hoist
//! nor sink the work. Output over USART0, one line each:
//!
//! - `O <overhead>`: stamp overhead already subtracted from every figure;
//! - `B <name> <median> <min> <max> <stack>`: cycles, and the stack high-water
//!   in bytes (from the top of RAM) while that routine ran;
//! - `I <name> <median> <min> <max>`: a count per run (iterations);
//! - `E <x> <exp> <expm1>`: f32 bit patterns (decimal) of the chip's
//!   `exp`/`expm1`, which the host reproduces bit for bit;
//! - `A <ts> <a> <n> <t> <g> <rate> <paper_g>`: f32 bit patterns of inputs and
//!   the chip's G, G′ and the printed ζ form's G, for comparison with f64;
//! - `S <high_water> <free>`: stack high-water over the whole run;
//! - `done`.
//!
//! To add a routine: one `b.run("name", |i| input(i), |x| work(x));` line.
#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;
use core::hint::black_box;
use touch_arm::board::adc::Adc;
use touch_arm::board::cycles::CycleCounter;
use touch_arm::board::fault::halt;
use touch_arm::board::shield::ShieldBus;
use touch_arm::board::shield::TouchWiring;
use touch_arm::board::stack;
use touch_arm::board::usart::Usart0;
use touch_arm::geometry::ik::{Branch, Links};
use touch_arm::geometry::path::Path;
use touch_arm::geometry::pose::{pose_for_point, ArmGeometry};
use touch_arm::math::real::Real;
use touch_arm::motion::laws::Law;
use touch_arm::motion::lift::{LiftCheck, LiftPlan, LiftRequest};
use touch_arm::motion::lift_hull;
use touch_arm::motion::path::{path_angles, Pace, PathArm, PathCheck, PathLimits, PathRequest};
use touch_arm::motion::plan::LawKind;
use touch_arm::motion::plan::{JointLaw, MultiPlan, JOINTS};
use touch_arm::motion::planner::{plan_move, request as app_policy};
use touch_arm::motion::scaled::ScaledZat;
use touch_arm::motion::via::{iterate_paper, ViaParams, ViaPlan};
use touch_arm::motion::zat::{smooth_stop_a, zeta, Shape, ShapeParams, ZatParams};
use touch_arm::seam::RawSample;
use touch_arm::seam::TouchPanel;
use touch_arm::servo::map::{JointCal, ServoMap, TickMap};
use touch_arm::servo::track::{Replan, ServoTrack};
use touch_arm::touch::map::Calibration;
use ufmt::uwriteln;

/// The i-th plan input: a raw touch spread over the panel and a duration
/// (shared by the plan rows and the bit-for-bit plan dump the runner checks).
fn plan_input(i: usize) -> (u16, u16, f32) {
    let raw_x = 150 + (i as u16) * 50;
    let raw_y = 200 + ((i as u16 * 7) % 15) * 40;
    (raw_x, raw_y, spread(i, 1.5, 4.0))
}

/// Runs per routine (odd, so the median is one of them).
const REPS: usize = 15;

/// A typical move (radians, elbow-up branch): a realistic frame load.
const START: [f32; JOINTS] = [1.570_796_3, 0.785_398_2, -1.570_796_3];
const TARGET: [f32; JOINTS] = [0.785_398_2, 0.2, -2.2];
const TS: f32 = 2.0;
const N: f32 = 2.0;
/// Where a re-plan sends the arm instead.
const TARGET2: [f32; JOINTS] = [1.2, 1.9, -1.0];
/// The app's frame, s.
const FRAME_S: f32 = 0.02;

/// avr-libc's `exp`/`log` called directly (AVR `double` is 32 bits), to time
/// them beside the crate's own.
mod avr_libm {
    extern "C" {
        pub fn exp(x: f32) -> f32;
        pub fn log(x: f32) -> f32;
        pub fn atan2(y: f32, x: f32) -> f32;
    }
}

struct Bench {
    serial: Usart0,
    clock: CycleCounter,
}

/// Median, min, max of a run's counts.
fn stats(c: &mut [u32; REPS]) -> (u32, u32, u32) {
    // Insertion sort: 15 elements, no panicking index.
    let mut i = 1;
    while i < REPS {
        let mut j = i;
        while j > 0 {
            let (Some(&a), Some(&b)) = (c.get(j - 1), c.get(j)) else { break };
            if a <= b {
                break;
            }
            c.swap(j - 1, j);
            j -= 1;
        }
        i += 1;
    }
    (c[REPS / 2], c[0], c[REPS - 1])
}

impl Bench {
    /// Times `work` on `input(i)` for i in 0..REPS and prints a `B` line.
    /// Only one input is alive at a time, so the stack figure is the
    /// routine's, not the harness's.
    #[inline(never)] // reason: measured
    fn run<T, U>(&mut self, name: &str, input: impl Fn(usize) -> T, mut work: impl FnMut(&T) -> U) {
        let mut c = [0u32; REPS];
        stack::paint();
        for (i, slot) in c.iter_mut().enumerate() {
            let x = input(black_box(i));
            let s = self.clock.now();
            let r = work(black_box(&x));
            let r = black_box(r);
            let e = self.clock.now();
            *slot = self.clock.cycles(s, e);
            drop(r);
        }
        self.report(name, &mut c);
    }

    /// [`Bench::run`] for work that changes its input (a fresh one each run).
    #[inline(never)] // reason: measured
    fn run_mut<T, U>(&mut self, name: &str, input: impl Fn(usize) -> T, mut work: impl FnMut(&mut T) -> U) {
        let mut c = [0u32; REPS];
        stack::paint();
        for (i, slot) in c.iter_mut().enumerate() {
            let mut x = input(black_box(i));
            let s = self.clock.now();
            let r = work(black_box(&mut x));
            let r = black_box(r);
            let e = self.clock.now();
            *slot = self.clock.cycles(s, e);
            drop(r);
        }
        self.report(name, &mut c);
    }

    /// Prints a `B` line for a routine's counts and the stack high-water
    /// since [`Bench::run`] painted it: one copy for every routine (`run`
    /// is built once per routine, so what it need not hold stays out).
    #[inline(never)] // reason: measured
    fn report(&mut self, name: &str, c: &mut [u32; REPS]) {
        let hw = stack::high_water();
        let (m, lo, hi) = stats(c);
        let _ = uwriteln!(self.serial, "B {} {} {} {} {}", name, m, lo, hi, hw);
    }

    /// Prints an `I` line for per-run counts.
    fn counts(&mut self, name: &str, c: &mut [u32; REPS]) {
        let (m, lo, hi) = stats(c);
        let _ = uwriteln!(self.serial, "I {} {} {} {}", name, m, lo, hi);
    }
}

/// i-th of REPS values spread over [lo, hi] (inclusive).
fn spread(i: usize, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * (i as f32) / ((REPS - 1) as f32)
}

fn servo_maps() -> [ServoMap; JOINTS] {
    let mut out = [None; JOINTS];
    for (o, c) in out.iter_mut().zip(JointCal::DEFAULTS.iter()) {
        *o = ServoMap::new(c).ok();
    }
    match out {
        [Some(a), Some(b), Some(c)] => [a, b, c],
        _ => halt(),
    }
}

/// The printed ζ form, per joint, in f32 with the `libm` crate's `powf`:
/// S = q0 ± n^(t−ζ)/|n^(t + tₛ/t − 1) − n^a| (position only).
#[derive(Clone, Copy)]
struct PaperJoint {
    q0: f32,
    sf: f32,
    zeta: f32,
}

#[inline(never)] // reason: measured
fn paper_position(j: &PaperJoint, sh: &ShapeParams<f32>, t: f32) -> f32 {
    if t <= 0.0 {
        return j.q0;
    }
    if t > sh.ts {
        return j.sf;
    }
    let u = t + sh.ts / t - 1.0;
    let m = libm::powf(sh.n, t - j.zeta) / libm::fabsf(libm::powf(sh.n, u) - libm::powf(sh.n, sh.a));
    if j.sf >= j.q0 {
        j.q0 + m
    } else {
        j.q0 - m
    }
}

fn paper_joints(sh: &ShapeParams<f32>) -> [PaperJoint; JOINTS] {
    let mut out = [PaperJoint { q0: 0.0, sf: 0.0, zeta: 0.0 }; JOINTS];
    for ((o, q0), sf) in out.iter_mut().zip(START.iter()).zip(TARGET.iter()) {
        let z = zeta(&ZatParams { q0: *q0, sf: *sf, ts: sh.ts, a: sh.a, n: sh.n }).unwrap_or(f32::INFINITY);
        *o = PaperJoint { q0: *q0, sf: *sf, zeta: z };
    }
    out
}

#[avr_device::entry]
fn main() -> ! {
    stack::paint();
    let Some(dp) = pac::Peripherals::take() else { halt() };
    let serial = Usart0::new(dp.USART0);
    let clock = CycleCounter::new(dp.TC1, dp.TC3);
    let mut b = Bench { serial, clock };
    let _ = uwriteln!(b.serial, "bench touch-arm {}", env!("CARGO_PKG_VERSION"));
    let _ = uwriteln!(b.serial, "O {}", b.clock.overhead());

    let a_star = smooth_stop_a(TS, N).unwrap_or(1.0);
    let shape = ShapeParams { ts: TS, a: a_star, n: N };
    let Ok(plan) = MultiPlan::new(&START, &TARGET, &shape) else { halt() };
    let Ok(g) = Shape::new(&shape) else { halt() };
    let maps = servo_maps();
    // Frame times over the whole move, the end (tₛ) included.
    let t_at = |i: usize| spread(i, TS / (REPS as f32), TS);

    // Context: the soft-float primitives.
    b.run("f32_mul", |i| (spread(i, 0.3, 7.0), spread(i, 1.1, 2.9)), |&(x, y)| x * y);
    b.run("f32_add", |i| (spread(i, 0.3, 7.0), spread(i, -1.1, 2.9)), |&(x, y)| x + y);
    b.run("f32_div", |i| (spread(i, 0.3, 7.0), spread(i, 1.1, 2.9)), |&(x, y)| x / y);
    b.run("f32_lt", |i| (spread(i, 0.3, 7.0), spread(i, -1.1, 9.9)), |&(x, y)| x < y);
    b.run("f32_to_i32", |i| spread(i, -3000.0, 3000.0), |&x| x as i32);
    b.run("i32_to_f32", |i| (i as i32) * 12345 - 7, |&x| x as f32);
    b.run("u32_mul", |i| (i as u32 * 0x1234_5677, i as u32 * 0x0ABC_DEF1 + 3), |&(x, y)| x.wrapping_mul(y));
    b.run(
        "u64_mul_hi",
        |i| (i as u32 * 0x1234_5677, i as u32 * 0x0ABC_DEF1 + 3),
        |&(x, y)| ((u64::from(x) * u64::from(y)) >> 32) as u32,
    );
    b.run(
        "avrlibc_exp",
        |i| spread(i, -9.0, 3.0),
        |&x| {
            // SAFETY: a pure function of a float.
            unsafe { avr_libm::exp(x) }
        },
    );
    b.run(
        "avrlibc_log",
        |i| spread(i, 0.01, 50.0),
        |&x| {
            // SAFETY: a pure function of a float.
            unsafe { avr_libm::log(x) }
        },
    );
    b.run("exp", |i| spread(i, -9.0, 3.0), |&x| x.exp());
    b.run("expm1", |i| spread(i, 0.001, 3.0), |&x| x.expm1());
    b.run("ln", |i| spread(i, 0.01, 50.0), |&x| x.ln());
    b.run("libm_powf", |i| (spread(i, 1.1, 9.0), spread(i, -3.0, 2.0)), |&(x, y)| libm::powf(x, y));

    // The ζ-a-tₛ profile alone, and with its rate.
    b.run("g", t_at, |&t| g.g(t));
    b.run("g_rate", t_at, |&t| g.g_rate(t));
    frames(&mut b, &plan, &maps);
    path_frames(&mut b, &maps);
    // The printed form with libm::powf, 3 joints, position only.
    let pj = paper_joints(&shape);
    b.run("paper_frame", t_at, |&t| {
        let mut s = [0.0f32; JOINTS];
        for (o, j) in s.iter_mut().zip(pj.iter()) {
            *o = paper_position(j, &shape, t);
        }
        s
    });

    // Plan: touch → workspace → IK → 3-joint ζ-a-tₛ plan with a* and checks.
    let geo = match Links::new(1.0f32, 1.0) {
        Ok(links) => ArmGeometry { k: 1.0f32, links, branch: Branch::Minus },
        Err(_) => halt(),
    };
    let cal = Calibration::DEFAULT;
    b.run("plan", plan_input, |&(rx, ry, ts)| plan_move(&cal, &geo, rx, ry, ts));

    // What the product firmware really runs per touch: the app's policy,
    // the shortest tₛ within every joint's speed and acceleration: closed
    // form for the time-scaled ζ-a-tₛ, searched for the papers' form.
    let limits = app_policy::PlanLimits {
        speed: [0.5f32, 0.5, 0.5],
        accel: [17.1f32; JOINTS],
        ts_min: 0.5,
        zat_ts_min: 1.2,
        ts_max: 30.0,
        n: 2.0,
    };
    let request = |law| {
        move |i| app_policy::MoveRequest {
            start: START,
            target: [spread(i, 0.3, 2.8), spread(i, 0.4, 2.6), spread(i, -2.8, -0.4)],
            law,
        }
    };
    b.run("app_plan_move", request(LawKind::Zat), |req| plan_move::plan_move(req, &limits).ok().map(|p| p.ts));
    b.run("app_plan_move_paper", request(LawKind::ZatPaper), |req| {
        plan_move::plan_move(req, &limits).ok().map(|p| p.ts)
    });
    // The move time of ζ-a-tₛ over the quintic's under the same limits, ‰:
    // 15 moves at 3 rad/s, from speed-bound (60 rad/s²) to
    // acceleration-bound (1 rad/s²).
    let mut ratio = [0u32; REPS];
    for (i, r) in ratio.iter_mut().enumerate() {
        let lim = app_policy::PlanLimits { speed: [3.0; JOINTS], accel: [spread(i, 60.0, 1.0); JOINTS], ..limits };
        let req = request(LawKind::Zat)(i);
        let q = app_policy::MoveRequest { law: LawKind::Quintic, ..req };
        if let (Ok(z), Ok(q)) = (plan_move::plan_move(&req, &lim), plan_move::plan_move(&q, &lim)) {
            *r = (z.ts / q.ts * 1000.0 + 0.5) as u32;
        }
    }
    b.counts("zat_time_over_quintic_permille", &mut ratio);
    // One touch read: 5 samples of X, Y and the two pressure channels on the
    // shared pins, with settle times, pins handed back after.
    let mut bus = ShieldBus::new(dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH);
    let mut adc = Adc::new(dp.ADC);
    b.run(
        "touch_sample",
        |_| (),
        |_| {
            let mut samples = [RawSample { x: 0, y: 0, z: 0, z1: 0 }; 5];
            bus.touch(&mut adc, Some(&TouchWiring::A)).read(&mut samples)
        },
    );

    // The plans themselves, for the runner to compare with the host bit for
    // bit: `P <i> <planned 0/1> <target α, q2, q3> <a*>` (f32 bit patterns).
    for i in 0..REPS {
        let (raw_x, raw_y, ts) = plan_input(i);
        let (ok, t, a) = match plan_move(&cal, &geo, raw_x, raw_y, ts) {
            Some(p) => {
                let a = match p.law() {
                    JointLaw::Zat(s) => s.a(),
                    JointLaw::Scaled(_) | JointLaw::Classic(_) => f32::NAN,
                };
                (1u8, *p.target(), a)
            }
            None => (0, [0.0; JOINTS], 0.0),
        };
        let _ = uwriteln!(
            b.serial,
            "P {} {} {} {} {} {}",
            i,
            ok,
            t[0].to_bits(),
            t[1].to_bits(),
            t[2].to_bits(),
            a.to_bits()
        );
    }
    // Where the plan's cycles go, step by step on the same inputs.
    let touch = |i: usize| (150 + (i as u16) * 50, 200 + ((i as u16 * 7) % 15) * 40);
    let mapped = |i: usize| {
        let (rx, ry) = touch(i);
        cal.map::<f32>(rx, ry).map_or((0.5, 0.5), |p| (p.x_p, p.y_p))
    };
    let shape_at = |i: usize| {
        let ts = spread(i, 1.5, 4.0);
        ShapeParams { ts, a: smooth_stop_a(ts, 2.0).unwrap_or(0.0), n: 2.0f32 }
    };
    b.run("plan_map", touch, |&(rx, ry)| cal.map::<f32>(rx, ry).ok());
    b.run("plan_pose", mapped, |&(x, y)| pose_for_point(&geo, x, y).ok());
    b.run("plan_a_star", |i| spread(i, 1.5, 4.0), |&ts| smooth_stop_a(ts, 2.0f32));
    b.run("shape_new", shape_at, |p| Shape::new(p).ok());
    b.run("shape_smooth_stop", |i| spread(i, 1.5, 4.0), |&ts| Shape::smooth_stop(ts, 2.0f32).ok());
    b.run("check_monotone", |i| Shape::new(&shape_at(i)), |s| s.as_ref().map(|s| s.check_monotone().is_ok()).ok());
    b.run("multiplan_new", |i| (shape_at(i), [0.3f32, 1.1, -1.9]), |(p, tgt)| MultiPlan::new(&START, tgt, p).ok());
    b.run("sqrt", |i| spread(i, 0.01, 50.0), |&x| x.sqrt());
    b.run(
        "avrlibc_atan2",
        |i| (spread(i, 0.01, 1.0), spread(i, -1.0, 1.0)),
        |&(y, x)| {
            // SAFETY: a pure function of two floats.
            unsafe { avr_libm::atan2(y, x) }
        },
    );
    b.run("atan2", |i| (spread(i, 0.01, 1.0), spread(i, -1.0, 1.0)), |&(y, x)| y.atan2(x));

    // Via points: closed form with ζ, ζ_v; then the paper's iteration.
    let via = |i: usize| ViaParams {
        q0: 0.1f32,
        theta_v: spread(i, -0.3, 0.95),
        sf: 0.8,
        tv: 1.5,
        ts: 3.0,
        a: 1.0,
        n: 2.0,
        av: 0.5,
        nv: 3.0,
    };
    b.run("via_solve", via, |p| ViaPlan::new(p).map(|v| (v.sv(), v.zeta(), v.zeta_v())).ok());
    b.run("via_new", via, |p| ViaPlan::new(p).ok());
    b.run("via_zeta", via, |p| zeta(&ZatParams { q0: p.q0, sf: p.theta_v, ts: p.ts, a: p.a, n: p.n }));
    let mut iters = [0u32; REPS];
    b.run("via_paper", via, |p| iterate_paper(p, 1e-5, 200).ok());
    for (i, it) in iters.iter_mut().enumerate() {
        *it = iterate_paper(&via(i), 1e-5, 200).map_or(u32::MAX, |r| u32::from(r.iterations));
    }
    b.counts("via_paper_iterations", &mut iters);

    accuracy_dump(&mut b);

    let _ = uwriteln!(b.serial, "S {} {}", stack::high_water(), stack::free_now());
    let _ = uwriteln!(b.serial, "done");
    b.serial.flush();
    halt()
}

/// The 50 Hz frame: 3 joints, position and velocity → pulse widths, for the
/// default law (the time-scaled ζ-a-tₛ), the papers' form (`paper`) and the
/// classic laws; a re-plan 0.1 .. 1.78 s into the move (a ζ-a-tₛ correction
/// superposed on it) and the frame of the two terms while both run. One
/// track at a time: it is the largest object on the AVR's stack.
#[inline(never)] // reason: measured
fn frames(b: &mut Bench, paper: &MultiPlan<f32>, maps: &[ServoMap; JOINTS]) {
    let t_at = |i: usize| spread(i, TS / (REPS as f32), TS);
    let Ok(zat) = ScaledZat::new(TS) else { halt() };
    let Ok(scaled) = MultiPlan::with_law(&START, &TARGET, &JointLaw::Scaled(zat)) else { halt() };
    let Ok(mut track) = ServoTrack::new(paper, maps, FRAME_S) else { halt() };
    b.run("frame_zat_paper", t_at, |&t| track.frame(t));
    for (name, law) in [
        ("frame_linear", Law::Linear),
        ("frame_cubic", Law::Cubic),
        ("frame_quintic", Law::Quintic),
        ("frame_trapezoid", Law::Trapezoid),
    ] {
        let Ok(l) = JointLaw::classic(law, TS) else { halt() };
        let Ok(p) = MultiPlan::with_law(&START, &TARGET, &l) else { halt() };
        let Ok(()) = track.start(&p, maps) else { halt() };
        b.run(name, t_at, |&t| track.frame(t));
    }
    let Ok(()) = track.start(&scaled, maps) else { halt() };
    b.run("frame", t_at, |&t| track.frame(t));
    let limits = app_policy::PlanLimits {
        speed: [1.47f32; JOINTS],
        accel: [17.1f32; JOINTS],
        ts_min: 0.5,
        zat_ts_min: 1.2,
        ts_max: 30.0,
        n: 2.0,
    };
    let replan = Replan { target: &TARGET2, law: LawKind::Zat, lim: &limits, slack: 1.0 / 0.98 };
    let running = |i: usize| {
        let mut t = track;
        for _ in 0..5 + 6 * i {
            t.advance();
        }
        t
    };
    b.run_mut("app_replan", running, |t| t.replan(&replan, maps, &mut || true).ok().flatten().map(|(ts, _)| ts));
    for _ in 0..29 {
        track.advance();
    }
    let Ok(Some(_)) = track.replan(&replan, maps, &mut || true) else { halt() };
    b.run("frame_superposed", |i| spread(i, 0.0, 1.4), |&t| track.frame(t));
}

/// Angles through the calibration to Timer5 ticks, as a path frame writes
/// them (`TickMap`: `angle_to_pulse`'s value).
#[inline(always)]
fn to_ticks(q: &[f32; JOINTS], maps: &[TickMap; JOINTS]) -> Option<[u16; JOINTS]> {
    let mut out = [0u16; JOINTS];
    for ((o, m), q) in out.iter_mut().zip(maps.iter()).zip(q.iter()) {
        *o = m.ticks(*q)?;
    }
    Some(out)
}

/// A frame of a straight-line effector move (the law's g, the point, the
/// 3-DoF IK, three pulses) and of a via-point move (both shapes once, then a
/// multiply-add per joint, three pulses).
#[inline(never)] // reason: measured
fn path_frames(b: &mut Bench, maps: &[ServoMap; JOINTS]) {
    let t_at = |i: usize| spread(i, TS / (REPS as f32), TS);
    let (Some(m0), Some(m1), Some(m2)) = (TickMap::new(&maps[0]), TickMap::new(&maps[1]), TickMap::new(&maps[2]))
    else {
        halt()
    };
    let maps = &[m0, m1, m2];
    let Ok(links) = Links::new(1.0f32, 1.0) else { halt() };
    let arm = PathArm { links, branch: Branch::Minus };
    let Ok(line) = Path::line(&[1.0f32, 0.3, 0.2], &[-0.4, 0.9, 0.7]) else { halt() };
    let Ok(zat) = ScaledZat::new(TS) else { halt() };
    let law = JointLaw::Scaled(zat);
    b.run("path_frame", t_at, |&t| path_angles(&line, &law, &arm, t).ok().and_then(|q| to_ticks(&q, maps)));
    // One unit of a line's plan-time check (a visit: law, IK and joint rates;
    // or a search for a critical instant), at points of the first 116 units
    // that include both searches (the scan goes on with 2 × 45 units around
    // its ends, whose instants need no search: units of the same two kinds).
    let lim = PathLimits {
        min: [0.0, 0.0, -3.141_592_7],
        max: [3.141_592_7, 3.141_592_7, 0.0],
        speed: [2.94; JOINTS],
        accel: [17.1; JOINTS],
        ts_max: 30.0,
    };
    let req = PathRequest { path: line, law: LawKind::Zat, ts: TS, pace: Pace::SlowDown, samples: 24, refine: 24 };
    const UNITS_AT: [u16; REPS] = [0, 5, 10, 15, 20, 24, 25, 26, 30, 40, 50, 60, 70, 71, 100];
    let at = |i: usize| {
        let Ok(mut c) = PathCheck::new(&req, &arm, &lim) else { halt() };
        let _ = c.step(UNITS_AT.get(i).copied().unwrap_or(0));
        c
    };
    b.run_mut("path_check_unit", at, |c| c.step(1).is_some());
    // One unit of it that `PathCheck::next_is_visit` says is at most a visit
    // (what the app fits more of into a frame): the grid and the
    // refinement's instants, from the same points on, to the next such unit.
    let at = |i: usize| {
        let Ok(mut c) = PathCheck::new(&req, &arm, &lim) else { halt() };
        let _ = c.step(UNITS_AT.get(i).copied().unwrap_or(0));
        while !c.next_is_visit() {
            let _ = c.step(1);
        }
        c
    };
    b.run_mut("path_visit_unit", at, |c| c.step(1).is_some());
    // One unit of the bounds between the scan's points (issue #24, F4: a
    // visit of a stretch's far end, the path rates' interval bound and the
    // law's cell bounds), after the grid and the refinement's 205 units.
    const BOUND_AT: [u16; REPS] = [205, 206, 207, 208, 210, 212, 215, 218, 220, 224, 228, 232, 236, 240, 250];
    let at = |i: usize| {
        let Ok(mut c) = PathCheck::new(&req, &arm, &lim) else { halt() };
        let _ = c.step(BOUND_AT.get(i).copied().unwrap_or(205));
        c
    };
    b.run_mut("path_bound_unit", at, |c| c.step(1).is_some());
    lift_frames(b, maps, &lim);
    let p = ViaParams { q0: 0.0f32, theta_v: 0.0, sf: 0.0, tv: 1.5, ts: 3.0, a: 1.0, n: 2.0, av: 0.5, nv: 3.0 };
    let (Ok(gv), Ok(g)) = (
        Shape::new(&ShapeParams { ts: p.tv, a: p.av, n: p.nv }),
        Shape::new(&ShapeParams { ts: p.ts, a: p.a, n: p.n }),
    ) else {
        halt()
    };
    // Per joint: q0, S_v, S_f of a lift over the default move.
    let joints = [[START[0], 1.2, TARGET[0]], [START[1], 1.6, TARGET[1]], [START[2], -1.2, TARGET[2]]];
    b.run(
        "via_frame",
        |i| spread(i, 0.1, 2.9),
        |&t| {
            let (wv, w) = (gv.g(t), g.g(t));
            let mut q = [0.0f32; JOINTS];
            for (q, [q0, sv, sf]) in q.iter_mut().zip(joints.iter()) {
                *q = *q0 + (*sv - *q0) * wv + (*sf - *sv) * w;
            }
            to_ticks(&q, maps)
        },
    );
}

/// A lift's check unit and its frame on the chip (own function: the path
/// frame's row is sensitive to what shares its caller's frame).
#[inline(never)] // reason: measured
fn lift_frames(b: &mut Bench, maps: &[TickMap; JOINTS], lim: &PathLimits<f32>) {
    let Ok(links) = Links::new(1.0f32, 1.0) else { halt() };
    // One unit of a lift's check (a hull vertex: two products and a sum per
    // joint) across its units, the last (the duration) included, and the
    // lift's frame on the chip (`LiftPlan::angles`, both shapes' G, three
    // pulses).
    let lreq = LiftRequest { start: START, target: TARGET, h: 0.2, links, branch: Branch::Minus, ts_min: 0.5 };
    let lat = |i: usize| {
        let Ok(mut c) = LiftCheck::new(&lreq, lim) else { halt() };
        let _ = c.step((i * (lift_hull::UNITS - 1) / (REPS - 1)) as u16);
        c
    };
    b.run_mut("lift_check_unit", lat, |c| c.step(1).is_some());
    let Ok(lift) = LiftPlan::new(&lreq, lim) else { halt() };
    let lts = lift.ts();
    b.run("lift_frame", |i| spread(i, 0.0, lts), |&t| to_ticks(&lift.angles(t), maps));
}

/// Map a touch, solve the pose, plan the move from the start pose: the
/// smooth-stop shape (a = a*, `Shape::smooth_stop`, which settles
/// monotonicity on the way) and `MultiPlan::with_law`, which checks it.
#[inline(never)] // reason: measured
fn plan_move(cal: &Calibration, geo: &ArmGeometry<f32>, rx: u16, ry: u16, ts: f32) -> Option<MultiPlan<f32>> {
    let p = cal.map::<f32>(rx, ry).ok()?;
    let pose = pose_for_point(geo, p.x_p, p.y_p).ok()?;
    let shape = Shape::smooth_stop(ts, 2.0f32).ok()?;
    let target = [pose.alpha, pose.q2, pose.q3];
    MultiPlan::with_law(&START, &target, &JointLaw::Zat(shape)).ok()
}

/// On-chip results for the runner to check: `E` lines (exp, expm1 on a
/// sweep, to compare bit for bit with the host) and `A` lines (G, G′ and the
/// printed ζ form's G over a parameter sweep, to compare with f64).
fn accuracy_dump(b: &mut Bench) {
    for i in 0..=120u8 {
        // −90 … 90 in steps of 1.5, then ±2^-k for small arguments.
        let x = -90.0 + 1.5 * f32::from(i);
        let _ = uwriteln!(b.serial, "E {} {} {}", x.to_bits(), x.exp().to_bits(), x.expm1().to_bits());
    }
    let mut x = 0.9f32;
    for _ in 0..30 {
        for v in [x, -x] {
            let _ = uwriteln!(b.serial, "E {} {} {}", v.to_bits(), v.exp().to_bits(), v.expm1().to_bits());
        }
        x *= 0.43;
    }
    // ln, atan2 and the split square root, to compare bit for bit with the
    // host: ln over 2^-30 … 2^30 in steps of 2^(1/4)·(1 + small), and near 1.
    let mut x = 9.3e-10f32;
    for _ in 0..125 {
        let _ = uwriteln!(b.serial, "L {} {}", x.to_bits(), x.ln().to_bits());
        let (s, c) = touch_arm::math::sqrt_split::sqrt_split(x);
        let _ = uwriteln!(b.serial, "Q {} {} {}", x.to_bits(), s.to_bits(), c.to_bits());
        x *= 1.189_213_7;
    }
    for i in 0..40u16 {
        let x = 0.96 + f32::from(i) * 0.0027;
        let _ = uwriteln!(b.serial, "L {} {}", x.to_bits(), x.ln().to_bits());
    }
    // mul_hi_approx (assembly on the chip): every pair of carry-heavy
    // patterns, then pseudo-random pairs.
    let pats = [0u32, 1, 0xFFFF_FFFF, 0x8000_0000, 0xFFFF_0000, 0x0000_FFFF, 0x00FF_00FF, 0xFF00_FF00];
    for &a in pats.iter() {
        for &c in pats.iter() {
            let _ = uwriteln!(b.serial, "M {} {} {}", a, c, touch_arm::math::fixed::mul_hi_approx(a, c));
        }
    }
    let mut r = 0x2545_F491u32;
    for _ in 0..64 {
        let a = r;
        r = r.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let _ = uwriteln!(b.serial, "M {} {} {}", a, r, touch_arm::math::fixed::mul_hi_approx(a, r));
        r = r.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
    }
    // atan2 around the circle (every octant) at radii 1e-3 … 1e3.
    for i in 0..96u16 {
        let phi = -3.1 + f32::from(i) * 0.0653;
        let r = [1e-3f32, 0.7, 1e3][usize::from(i % 3)];
        let (y, x) = (r * phi.sin(), r * phi.cos());
        let _ = uwriteln!(b.serial, "T {} {} {}", y.to_bits(), x.to_bits(), y.atan2(x).to_bits());
    }
    let tss = [0.2f32, 0.7, 1.0, 2.0, 3.5, 6.0, 10.0];
    let ns = [1.1f32, 2.0, 7.0, 30.0, 100.0];
    let margins = [0.01f32, 0.3, 2.0];
    for &ts in tss.iter() {
        for &n in ns.iter() {
            for &m in margins.iter() {
                let ps = ShapeParams { ts, a: touch_arm::motion::zat::u_min(ts) - m, n };
                let Ok(s) = Shape::new(&ps) else { continue };
                if !s.is_monotone() {
                    continue;
                }
                let pj = PaperJoint {
                    q0: 0.0,
                    sf: 1.0,
                    zeta: zeta(&ZatParams { q0: 0.0, sf: 1.0, ts, a: ps.a, n }).unwrap_or(f32::INFINITY),
                };
                for k in 1..=8u8 {
                    let t = ts * f32::from(k) / 8.0;
                    let (g, r) = s.g_rate(t);
                    let pg = paper_position(&pj, &ps, t);
                    let _ = uwriteln!(
                        b.serial,
                        "A {} {} {} {} {} {} {}",
                        ps.ts.to_bits(),
                        ps.a.to_bits(),
                        ps.n.to_bits(),
                        t.to_bits(),
                        g.to_bits(),
                        r.to_bits(),
                        pg.to_bits()
                    );
                }
            }
        }
    }
}
