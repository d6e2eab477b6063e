//! The benchmark's moves against the time-optimal profile (issue #22 §5),
//! computed on the host: the default law (the time-scaled ζ-a-tₛ) and the
//! quintic as the firmware plans them (`plan_move` in f32, the app's limits
//! at each speed preset), against the time-optimal rest-to-rest profile of
//! each joint under its speed and acceleration limit and the jerk the
//! default law gives it, from [rsruckig](https://crates.io/crates/rsruckig)
//! (a Rust port of Ruckig). [`seven_segment`] is an independent closed form
//! of the same profile that the tests hold the port to.
//!
//! A move's planned duration is the max over its joints (the synchronized
//! law: every joint follows one profile, the planner's rule); its
//! time-optimal reference is the max over joints of each joint's own
//! time-optimal time (the joints unsynchronized, a lower bound).
//!
//! Arrival is what `scripts/run.sh` reports: the first instant after which
//! every joint stays within 1 µs of its final pulse. The quintic ends on
//! 1 − g = 10·s³ (s = 1 − t/tₛ), the time-scaled ζ-a-tₛ, whose smooth stop
//! leaves an acceleration, on 1.72·s²: the quintic arrives earlier in its
//! duration, so a move's arrival ratio exceeds its duration ratio.

use core::f32::consts::{FRAC_PI_2, FRAC_PI_4};
use rsruckig::prelude::*;
use touch_arm::app::AppParams;
use touch_arm::config::settings::SpeedPreset;
use touch_arm::motion::plan::{LawKind, JOINTS};
use touch_arm::motion::planner::plan_move::plan_move;
use touch_arm::motion::planner::request::{MoveRequest, PlanLimits};
use touch_arm::motion::scaled::{ScaledZat, JERK_RATIO};
use touch_arm::servo::map::JointCal;

/// The bench firmware's start pose (`src/bin/bench.rs`'s `START`; the
/// shoulder at π/4, not the home pose's π/2).
const START: [f32; JOINTS] = [FRAC_PI_2, FRAC_PI_4, -FRAC_PI_2];
/// The bench firmware's count of moves (`REPS`).
const REPS: usize = 15;
/// A pulse within this of its final width has arrived, µs (`touch-arm-sim`'s rule).
const ARRIVED_US: f64 = 1.0;

/// The time-optimal duration of a rest-to-rest move of `delta` under speed
/// `v`, acceleration `a` and jerk `j` (all > 0), s, from rsruckig.
pub fn ruckig_duration(delta: f64, v: f64, a: f64, j: f64) -> Result<f64, String> {
    if delta == 0.0 {
        return Ok(0.0);
    }
    let mut otg = Ruckig::<1, ThrowErrorHandler>::new(None, 0.001);
    let mut input = InputParameter::new(None);
    input.current_position[0] = 0.0;
    input.target_position[0] = delta.abs();
    input.max_velocity[0] = v;
    input.max_acceleration[0] = a;
    input.max_jerk[0] = j;
    let mut traj = Trajectory::new(None);
    otg.calculate(&input, &mut traj).map_err(|e| format!("ruckig: {e:?}"))?;
    Ok(traj.get_duration())
}

/// The same duration in closed form: the classic 7-segment profile,
/// symmetric for a rest-to-rest move. Accelerating to a peak speed `w`
/// takes t(w) = w/a + a/j and covers w·t(w)/2 where the acceleration
/// saturates (w ≥ a²/j), else 2√(w/j) and w·√(w/j). If reaching `v` twice
/// covers at most Δ, T = 2t(v) + (Δ − 2d(v))/v; otherwise the peak speed
/// is the root of 2d(w) = Δ: w = (Δ/2)^(2/3)·j^(1/3) below a²/j
/// (d = w^1.5/√j), else the root of w² + w·a²/j − a·Δ = 0.
pub fn seven_segment(delta: f64, v: f64, a: f64, j: f64) -> f64 {
    let d = delta.abs();
    let w_sat = a * a / j;
    let t_acc = |w: f64| if w >= w_sat { w / a + a / j } else { 2.0 * (w / j).sqrt() };
    let d_acc = |w: f64| w * t_acc(w) / 2.0;
    if 2.0 * d_acc(v) <= d {
        return 2.0 * t_acc(v) + (d - 2.0 * d_acc(v)) / v;
    }
    // Below a²/j: 2·w·√(w/j) = Δ.
    let w = (d / 2.0).powf(2.0 / 3.0) * j.powf(1.0 / 3.0);
    let w = if w <= w_sat {
        w
    } else {
        // w·(w/a + a/j) = Δ.
        let b = a * a / j;
        (-b + (b * b + 4.0 * a * d).sqrt()) / 2.0
    };
    2.0 * t_acc(w)
}

/// One move's figures under one set of limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveFigures {
    /// The default law's planned duration, s.
    pub zat: f64,
    /// The quintic's, s.
    pub quintic: f64,
    /// max over joints of the time-optimal time, s.
    pub optimal: f64,
    /// Arrival (within [`ARRIVED_US`] of every final pulse) of the default law, s.
    pub zat_arrival: f64,
    /// The quintic's arrival, s.
    pub quintic_arrival: f64,
    /// The speed bound binds the default law's duration (not the acceleration's, nor ts_min).
    pub speed_bound: bool,
}

/// The app's limits at `pct` % of the default calibration's speeds
/// (`App::plan_limits`: the speed share and the acceleration, both less the
/// safety margin).
pub fn preset_limits(pct: u8) -> PlanLimits<f32> {
    let p = AppParams::DEFAULT;
    let keep = 1.0 - p.speed_margin;
    let share = f32::from(pct) * 0.01 * keep;
    let c = JointCal::DEFAULTS;
    PlanLimits {
        speed: [0, 1, 2].map(|j| c[j].max_speed_rad_s * share),
        accel: [0, 1, 2].map(|j| c[j].max_accel_rad_s2 * keep),
        ts_min: p.ts_min,
        zat_ts_min: p.zat_ts_min,
        ts_max: p.ts_max,
        n: p.n,
    }
}

/// The bench firmware's i-th target (`src/bin/bench.rs`: `spread` over the joints' ranges).
pub fn bench_target(i: usize) -> [f32; JOINTS] {
    let spread = |lo: f32, hi: f32| lo + (hi - lo) * (i as f32) / ((REPS - 1) as f32);
    [spread(0.3, 2.8), spread(0.4, 2.6), spread(-2.8, -0.4)]
}

/// When a joint moving `delta_us` by the normalized profile `g` over `ts`
/// has arrived: the last t with |Δ|·(1 − g(t)) > [`ARRIVED_US`] (bisection;
/// g rises monotonically).
fn arrival(delta_us: f64, ts: f64, g: &dyn Fn(f64) -> f64) -> f64 {
    let d = delta_us.abs();
    if d <= ARRIVED_US {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, ts);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if d * (1.0 - g(mid)) > ARRIVED_US {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The quintic's normalized position.
fn quintic_g(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * s * (10.0 + s * (-15.0 + 6.0 * s))
}

/// A move's figures from `start` to `target` under `lim`.
pub fn figures(start: &[f32; JOINTS], target: &[f32; JOINTS], lim: &PlanLimits<f32>) -> Result<MoveFigures, String> {
    let plan = |law| {
        plan_move(&MoveRequest { start: *start, target: *target, law }, lim)
            .map(|p| f64::from(p.ts))
            .map_err(|e| format!("{law:?}: {e:?}"))
    };
    let (zat, quintic) = (plan(LawKind::Zat)?, plan(LawKind::Quintic)?);
    let mut optimal = 0.0f64;
    let (mut zat_arrival, mut quintic_arrival) = (0.0f64, 0.0f64);
    let scaled = ScaledZat::<f64>::new(zat).map_err(|e| format!("{e:?}"))?;
    let mut vel_time = 0.0f64;
    for j in 0..JOINTS {
        let d = f64::from(target[j]) - f64::from(start[j]);
        if d == 0.0 {
            continue;
        }
        // The jerk the default law gives this joint: max |g‴|·|Δ|.
        let jerk = JERK_RATIO * d.abs() / (zat * zat * zat);
        let t = ruckig_duration(d, f64::from(lim.speed[j]), f64::from(lim.accel[j]), jerk)?;
        optimal = optimal.max(t);
        vel_time = vel_time.max(d.abs() / f64::from(lim.speed[j]));
        let us = d * f64::from(JointCal::DEFAULTS[j].us_per_rad);
        zat_arrival = zat_arrival.max(arrival(us, zat, &|t| scaled.g(t)));
        quintic_arrival = quintic_arrival.max(arrival(us, quintic, &|t| quintic_g(t / quintic)));
    }
    let speed_bound = (vel_time * touch_arm::motion::scaled::VEL_RATIO - zat).abs() < 1e-4 * zat;
    Ok(MoveFigures { zat, quintic, optimal, zat_arrival, quintic_arrival, speed_bound })
}

/// Median, min and max.
fn spread_of(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    (v[v.len() / 2], v[0], v[v.len() - 1])
}

/// One row: `label`, the moves' ratios (median, range).
fn row(label: &str, f: &[MoveFigures]) -> String {
    let r = |num: fn(&MoveFigures) -> f64, den: fn(&MoveFigures) -> f64| {
        let (m, lo, hi) = spread_of(f.iter().map(|x| num(x) / den(x)).collect());
        format!("{m:.3} ({lo:.3}–{hi:.3})")
    };
    let bound = f.iter().filter(|x| x.speed_bound).count();
    format!(
        "| {label} | {} ({bound}) | {} | {} | {} | {} |",
        f.len(),
        r(|x| x.zat, |x| x.optimal),
        r(|x| x.quintic, |x| x.optimal),
        r(|x| x.zat, |x| x.quintic),
        r(|x| x.zat_arrival, |x| x.quintic_arrival),
    )
}

/// The moves `scripts/run.sh --xy` makes from home that the benchmark adds
/// (their targets' joint angles by the firmware's IK, f64 rounded to f32).
pub const RUN_XY: [(f64, f64); 3] = [(0.62, 0.24), (0.3, 0.5), (-0.5, 0.4)];

/// Reference shapes (n, T₀) of the time-scaled ζ-a-tₛ the section weighs:
/// the default's, and smooth stops from docs/method.md §10.2's table and a
/// scan near it.
pub const SHAPES: [(f64, f64); 4] = [(2.0, 1.5), (1.9, 1.45), (1.85, 1.5), (1.65, 1.4)];

/// A reference shape's figures over a set of moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeFigures {
    /// max g′·tₛ, max |g″|·tₛ², max |g‴|·tₛ³ (dense scan) and g″(tₛ⁻)·tₛ².
    pub ratios: [f64; 4],
    /// The largest planned duration over the quintic's, and the largest arrival ratio.
    pub worst: [f64; 2],
}

/// The time-scaled ζ-a-tₛ of reference (n, T₀) against the quintic over
/// `moves` (start, target, limits): its duration in the closed form of the
/// laws that scale (`max(ts_min, c_v·R_v, √(c_a·R_a))`), the quintic's as
/// planned.
pub fn shape_figures(
    n: f64,
    t0: f64,
    moves: &[([f32; JOINTS], [f32; JOINTS], PlanLimits<f32>)],
) -> Result<ShapeFigures, String> {
    let shape = touch_arm::motion::zat::Shape::<f64>::smooth_stop(t0, n).map_err(|e| format!("{e:?}"))?;
    let steps = 4000;
    let mut r = [0.0f64; 4];
    for i in 1..steps {
        let s = shape.g_derivs(t0 * i as f64 / steps as f64);
        r[0] = r[0].max(s.v * t0);
        r[1] = r[1].max(s.acc.abs() * t0 * t0);
        r[2] = r[2].max(s.jerk.abs() * t0 * t0 * t0);
    }
    r[3] = shape.g_derivs(t0 * (1.0 - 1e-9)).acc * t0 * t0;
    let mut worst = [0.0f64; 2];
    for (start, target, lim) in moves {
        let q = figures(start, target, lim)?;
        let (mut rv, mut ra) = (0.0f64, 0.0f64);
        for j in 0..JOINTS {
            let d = (f64::from(target[j]) - f64::from(start[j])).abs();
            rv = rv.max(d / f64::from(lim.speed[j]));
            ra = ra.max(d / f64::from(lim.accel[j]));
        }
        let ts = (r[0] * rv).max((r[1] * ra).sqrt()).max(f64::from(lim.ts_min));
        let mut arrived = 0.0f64;
        for j in 0..JOINTS {
            let us = (f64::from(target[j]) - f64::from(start[j])) * f64::from(JointCal::DEFAULTS[j].us_per_rad);
            arrived = arrived.max(arrival(us, ts, &|t| shape.g(t * t0 / ts)));
        }
        worst[0] = worst[0].max(ts / q.quintic);
        worst[1] = worst[1].max(arrived / q.quintic_arrival);
    }
    Ok(ShapeFigures { ratios: r, worst })
}

/// The section of BENCHMARKS.md (Markdown, ending with a blank line).
pub fn section() -> Result<String, String> {
    let home = touch_arm::config::settings::ArmSettings::DEFAULT.pose_rad(touch_arm::config::settings::NamedPose::Home);
    let mut rows = Vec::new();
    let mut xy_rows = Vec::new();
    let mut moves = Vec::new();
    for preset in SpeedPreset::ALL {
        let lim = preset_limits(preset.percent());
        moves.extend((0..REPS).map(|i| (START, bench_target(i), lim)));
        let f: Result<Vec<_>, _> = (0..REPS).map(|i| figures(&START, &bench_target(i), &lim)).collect();
        rows.push(row(&format!("{preset:?} ({} %)", preset.percent()), &f?));
        for (x, y) in RUN_XY {
            let t = touch_arm_rig::firmware::host_target(x, y)?;
            let target = t.q.map(|q| q as f32);
            moves.push((home, target, lim));
            let m = figures(&home, &target, &lim)?;
            xy_rows.push(format!(
                "| {x}, {y} | {preset:?} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |",
                m.optimal,
                m.zat,
                m.quintic,
                m.zat / m.optimal,
                m.zat / m.quintic,
                m.zat_arrival,
                m.quintic_arrival,
                m.zat_arrival / m.quintic_arrival,
            ));
        }
    }
    let mut shape_rows = Vec::new();
    for (n, t0) in SHAPES {
        let f = shape_figures(n, t0, &moves)?;
        let [v, a, j, e] = f.ratios;
        shape_rows.push(format!(
            "| {n} | {t0} | {v:.3} | {a:.3} | {j:.1} | {e:.2} | {:.3} | {:.3} |",
            f.worst[0], f.worst[1]
        ));
    }
    Ok(format!(
        "{SECTION_INTRO}\n\n| moves (speed-bound) | | ζ-a-tₛ / optimal | quintic / optimal | ζ-a-tₛ / quintic | arrival ζ-a-tₛ / quintic |\n| --- | ---: | ---: | ---: | ---: | ---: |\n{}\n\n{XY_INTRO}\n\n| `--xy` | preset | optimal s | ζ-a-tₛ s | quintic s | ζ-a-tₛ / optimal | ζ-a-tₛ / quintic | arrival ζ-a-tₛ s | arrival quintic s | arrival ratio |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n{}\n\n{TAIL}\n\n{SHAPES_INTRO}\n\n| n | T₀ s | max g′·tₛ | max \\|g″\\|·tₛ² | max \\|g‴\\|·tₛ³ | g″(tₛ⁻)·tₛ² | worst duration / quintic | worst arrival / quintic |\n| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n{}\n\n{SHAPES_TAIL}\n\n",
        rows.join("\n"),
        xy_rows.join("\n"),
        shape_rows.join("\n"),
    ))
}

const SECTION_INTRO: &str = "## Moves against the time-optimal profile

The benchmark's 15 moves (the bench firmware's, from its start pose) at each speed preset of the default
calibration, planned on the host as the firmware plans them (`plan_move` in f32 under the app's
limits: the preset's share of 3 rad/s and 17.45 rad/s², less the 2 % margin), against the
time-optimal rest-to-rest profile of each joint under the same speed and acceleration and the peak
jerk the default law gives that joint (62.34·|Δ|/tₛ³), from rsruckig 3.0.1 (a Rust port of Ruckig;
the tests check it against the closed-form 7-segment profile and a brute-force search). A move's
duration is the max over its joints (one synchronized profile, the planner's rule); its optimal
time is the max over joints of each joint's own (the joints unsynchronized). Ratios: median
(min–max); arrival is the first instant every joint stays within 1 µs of its final pulse (what
`scripts/run.sh` reports, less the touch's latency). Computed by `xtask::bench_report::optimal`.";

const XY_INTRO: &str = "Moves of `scripts/run.sh --xy X,Y` from home, added to the set (the first one is issue #22's
1.107×: the first move runs at the slow preset, `--law zat` against `--law quintic`):";

const TAIL: &str = "At the slow and normal presets every move is speed-bound (the count in parentheses) and its planned
duration keeps the closed-form ratio of peak velocities, 2.020/1.875 = 1.077× (√(6.637/5.774) =
1.072× where the acceleration binds; at the fast preset some moves sit at the 0.5 s floor, 1.000×):
issue #22's move is planned at 1.077× like the benchmark's. What misses 1.10× is its arrival. The
time-scaled ζ-a-tₛ stops with zero velocity but not zero acceleration (g″(tₛ⁻) = −3.44/tₛ²,
docs/method.md §10.2), so it ends on 1 − g ≈ 1.72·s² (s = 1 − t/tₛ) where the quintic ends on
10·s³: a joint moving D µs is within 1 µs from s ≈ (1.72·D)^(−1/2) against (10·D)^(−1/3), 2.4 %
against 4.7 % of the duration for D = 1000 µs. That adds 2.5–3.5 % to the arrival ratio of every
move of a few hundred µs or more at every preset, the benchmark's 15 included: what the 15 moves
missed is not a regime of the limits but the measure (the chip's ratio compares planned
durations). The duration is already the shortest the shape allows under the binding limit (closed
form, no search slack), so only another reference shape moves these figures.";

const SHAPES_INTRO: &str =
    "Other reference shapes (smooth stops of n and T₀) over every move above, each planned by the
closed form of the laws that scale under the same limits, against the quintic as planned (ratios
from a dense f64 scan of the shape):";

const SHAPES_TAIL: &str = "No shape of the scan (n from 1.6 to 2.4, T₀ from 1.2 to 2 s in steps of 0.05) keeps both the
default's peak acceleration ratio and its jerk and arrives within 1.10× on every move; n = 1.9,
T₀ = 1.45 s does with a lower velocity and acceleration ratio than the default's but 11 % more
jerk, n = 1.85 and 1.65 with 32 % and 86 % more. Every smooth stop ends with an acceleration, so
each keeps the quadratic end. The default law is unchanged: a new reference shape changes every
plan the chip and twin tests compare bit for bit, the planner's tabulated cells and the
scenarios' derived numbers, and gives up the chip's exact ln 2.";

#[cfg(test)]
mod tests {
    use super::*;

    /// Grid of moves and limits: every regime of the 7-segment profile
    /// (neither limit reached, acceleration only, speed only, both).
    fn cases() -> Vec<(f64, f64, f64, f64)> {
        let mut out = Vec::new();
        for d in [0.01, 0.1, 0.5, 1.0, 2.5] {
            for v in [0.3, 1.0, 3.0] {
                for a in [1.0, 5.0, 17.1] {
                    for j in [5.0, 60.0, 500.0] {
                        out.push((d, v, a, j));
                    }
                }
            }
        }
        out
    }

    #[test]
    fn ruckig_matches_the_closed_form_seven_segment_profile() {
        for (d, v, a, j) in cases() {
            let r = ruckig_duration(d, v, a, j).unwrap();
            let c = seven_segment(d, v, a, j);
            assert!((r - c).abs() <= 1e-7 * c, "Δ {d} v {v} a {a} j {j}: ruckig {r}, closed form {c}");
        }
    }

    #[test]
    fn known_cases() {
        // Jerk alone binds: four jerk phases of t, Δ = 2·j·t³, T = 4t.
        let (d, j) = (0.5f64, 60.0f64);
        let t = (d / (2.0 * j)).cbrt();
        assert!((ruckig_duration(d, 100.0, 1000.0, j).unwrap() - 4.0 * t).abs() < 1e-9);
        // Every limit reached: T = Δ/v + v/a + a/j.
        let (d, v, a, j) = (2.5f64, 1.0, 5.0, 60.0);
        assert!((ruckig_duration(d, v, a, j).unwrap() - (d / v + v / a + a / j)).abs() < 1e-9);
        // Direction does not matter; no move takes no time.
        assert_eq!(ruckig_duration(-d, v, a, j).unwrap(), ruckig_duration(d, v, a, j).unwrap());
        assert_eq!(ruckig_duration(0.0, v, a, j).unwrap(), 0.0);
    }

    /// The shortest symmetric rest-to-rest profile by search: jerk ±j for
    /// t_j, constant acceleration j·t_j for t_a, the same mirrored, a cruise
    /// covering the rest at the peak speed; within the limits.
    fn brute_force(d: f64, v: f64, a: f64, j: f64) -> f64 {
        let mut best = f64::INFINITY;
        let n = 400;
        let tj_max = a / j;
        let ta_max = v / a + 2.0 * (d / a).sqrt();
        for p in 1..=n {
            let tj = tj_max * p as f64 / n as f64;
            for q in 0..=n {
                let ta = ta_max * q as f64 / n as f64;
                let vp = j * tj * (tj + ta);
                let dist = vp * (2.0 * tj + ta);
                if vp > v * (1.0 + 1e-12) || dist > d {
                    continue;
                }
                best = best.min(2.0 * (2.0 * tj + ta) + (d - dist) / vp);
            }
        }
        best
    }

    #[test]
    fn the_closed_form_is_the_shortest_profile_a_search_finds() {
        for (d, v, a, j) in cases() {
            let c = seven_segment(d, v, a, j);
            let b = brute_force(d, v, a, j);
            // The search never beats it, and comes within its grid's reach.
            assert!(b >= c * (1.0 - 1e-9), "Δ {d} v {v} a {a} j {j}: search {b} below {c}");
            assert!(b <= c * 1.02, "Δ {d} v {v} a {a} j {j}: search {b} far above {c}");
        }
    }

    #[test]
    fn the_benchmark_moves_keep_the_closed_form_ratio_and_the_optimal_bound() {
        let lim = preset_limits(SpeedPreset::Slow.percent());
        for i in 0..REPS {
            let f = figures(&START, &bench_target(i), &lim).unwrap();
            // Nothing beats the time-optimal profile under the law's own jerk.
            assert!(f.optimal <= f.zat && f.optimal <= f.quintic, "{i}: {f:?}");
            // At 0.735 rad/s every move is speed-bound: the peak-velocity ratio.
            assert!(f.speed_bound, "{i}: {f:?}");
            let r = touch_arm::motion::scaled::VEL_RATIO / 1.875;
            assert!((f.zat / f.quintic - r).abs() < 1e-3, "{i}: {} against {r}", f.zat / f.quintic);
            assert!(f.zat_arrival < f.zat && f.quintic_arrival < f.quintic);
        }
    }

    #[test]
    fn the_default_shape_scans_to_its_own_constants() {
        use touch_arm::motion::scaled::{ACC_RATIO, REF_N, REF_T0, VEL_RATIO};
        let lim = preset_limits(SpeedPreset::Slow.percent());
        let moves = [(START, bench_target(7), lim)];
        let f = shape_figures(REF_N, REF_T0, &moves).unwrap();
        let [v, a, j, e] = f.ratios;
        // The constants are rounded up from finer scans; 4000 points land just below.
        assert!(v <= VEL_RATIO && v > VEL_RATIO - 1e-4, "{v}");
        assert!(a <= ACC_RATIO && a > ACC_RATIO - 1e-3, "{a}");
        assert!(j <= JERK_RATIO && j > JERK_RATIO - 0.05, "{j}");
        // docs/method.md §10.2: the smooth stop's end acceleration.
        assert!((e + 3.438).abs() < 1e-3, "{e}");
        // Its closed-form duration is the planner's.
        let q = figures(&START, &bench_target(7), &lim).unwrap();
        assert!((f.worst[0] - q.zat / q.quintic).abs() < 1e-4, "{f:?} {q:?}");
    }

    #[test]
    fn arrival_of_the_quintic_is_where_its_cubic_end_meets_one_microsecond() {
        // 1 − g = 10s³ − 15s⁴ + 6s⁵ near the end (s = 1 − t/tₛ): to second
        // order s = s₀·(1 + s₀/2), s₀ = (1 µs / (10·Δ))^(1/3).
        let (d, ts) = (1000.0, 3.0);
        let s0 = (ARRIVED_US / (10.0 * d)).cbrt();
        let s = s0 * (1.0 + s0 / 2.0);
        let t = arrival(d, ts, &|t| quintic_g(t / ts));
        assert!((t - ts * (1.0 - s)).abs() < 0.005 * ts * s, "{t} against {}", ts * (1.0 - s));
    }
}
