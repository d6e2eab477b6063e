//! The `armsim` command line: argument definitions and the commands, as a
//! library so the binary stays a thin shell and tests can call it directly.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use touch_arm::geometry::ik::{base_angle, fk2, ik2, ik3, Branch, IkError};
use touch_arm::geometry::pose::{pose_for_point, ArmGeometry, PoseError};
use touch_arm::geometry::workspace::WorkspacePoint;
use touch_arm::motion::laws::{Law, LawParams, LawPlan};
use touch_arm::motion::scaled::ScaledZat;
use touch_arm::motion::via::{iterate_paper, via_shape_for, Continuity, ViaParams, ViaPlan};
use touch_arm::motion::zat::{smooth_stop_a, u_min, zeta, Shape, ShapeParams, ZatParams, ZatPlan};
use touch_arm::motion::{Sample, TrajError};
use touch_arm::touch::map::Calibration;

use crate::args::{parse_pair, parse_raw};
use crate::opts::{links, times, LawKindArg, LinkArgs, Times, PLOT_SAMPLES};
use crate::path::{cmd_path, plot_path, PathArgs, PlotPath};
use crate::plot::{self, Curve, Panel};
use crate::report::{csv_row, Json, Val};

#[derive(Parser, Debug)]
#[command(
    name = "armsim",
    version,
    about = "The touch-arm method on a PC (f64): touch mapping, IK, ζ-a-tₛ / via-point / classic trajectories and plots"
)]
/// The `armsim` command line: one subcommand per task ([`Cmd`]); [`run`] executes it.
pub struct Cli {
    #[command(subcommand)]
    /// The task to run.
    pub cmd: Cmd,
}

#[derive(Subcommand, Debug)]
/// armsim's tasks; each prints JSON or CSV (or writes a plot). A new task is a variant here, its argument struct and its `cmd_*` function called from [`run`].
pub enum Cmd {
    /// Map a touch to the normalized workspace: JSON {x_p, y_p, clamped, condition, alpha_deg}
    Map(MapArgs),
    /// 2-link inverse kinematics (3-DoF with --z): JSON {branch, reachable, singular, q2, q3} or {branch, reachable, singular, th1, th2, th3}
    ///
    /// Edge conventions: at the shoulder itself with l2 = l3 the arm is reachable but folded
    /// (q3 = π, −π on the minus branch) and q2 is undefined: `reachable: true, singular: true,
    /// q2: null`. A point out of reach has `reachable: false` and null joint angles, except θ1
    /// of the 3-DoF form, which is defined anyway (0 straight above the base). The solution is on
    /// the firmware's elbow branch (minus, elbow up) unless `--branch plus`; `branch` names it.
    Ik(IkArgs),
    /// Touch → condition, α, transform, IK: JSON {x_p, y_p, condition, alpha_deg, reach, height, branch, reachable, singular, q2, q3, s2, s3, sa}
    ///
    /// Out of reach: `reachable: false`, null q and s. At the shoulder with l2 = l3 (the bottom
    /// centre): `reachable: true, singular: true`, q3 = ±π, q2 and s2 null. On the firmware's
    /// elbow branch (minus, elbow up) unless `--branch plus`; `branch` names it. --l2 and --l3
    /// are taken as the firmware's `cal set arm` takes them (any one unit, millimetres there):
    /// the map's arm unit is their mean, so reach and height are in that unit.
    Plan(PlanArgs),
    /// ζ-a-tₛ trajectory: CSV t,s,v,acc,jerk; --info: JSON {zeta, zeta_infinite, u_min, admissible, a_smooth_stop, end_velocity, monotone}
    ///
    /// ζ = tₛ − log_n(|S_f − q0|·(n^tₛ − n^a)) is infinite for S_f = q0 (no motion): then
    /// `"zeta": null, "zeta_infinite": true`. A null ζ with `zeta_infinite: false` means ζ is
    /// undefined (a ≥ tₛ). CSV cells of non-finite values are empty.
    Traj(TrajArgs),
    /// Via-point trajectory (closed-form S_v): JSON {r, s_v, zeta, zeta_infinite, zeta_v, zeta_v_infinite, condition, converges, a_v, n_v, velocity_jump, acceleration_jump, jerk_jump}; --t/--samples: CSV t,s,v,acc,jerk
    ///
    /// ζ (S_v → S_f) is infinite when S_v = S_f, ζ_v (q0 → S_v) when S_v = q0: the value is then
    /// null and its `_infinite` flag true (likewise `zeta_iter`/`zeta_v_iter` with --iterate).
    /// CSV cells of non-finite values are empty.
    Via(ViaArgs),
    /// Classic motion law: CSV t,s,v,acc
    Law(LawArgs),
    /// Plot position, velocity, acceleration and jerk of a trajectory to PNG or SVG
    Plot(PlotArgs),
    /// End-effector path (straight line or circle) paced by a motion law, solved by IK per sample: CSV t,x,y,z,th1,th2,th3; --info: JSON {ts, ts_asked, slowed, peak_speed, peak_accel}
    ///
    /// The plan is checked first: every point reachable, not singular and inside the joint angle
    /// limits (the servo defaults: base and shoulder [0, π], elbow [−π, 0] on the elbow-up branch),
    /// no joint over its speed or acceleration limit. A too short --ts is refused with the
    /// shortest admissible one, or taken by --slow-down; no joint is ever clamped.
    Path(PathArgs),
    /// The papers' worked examples and figures from their stated inputs: `paper list`, `paper <id> [--json] [--plot FILE] [--csv FILE]`, `paper all --out DIR`
    Paper(crate::paper::PaperArgs),
}

// Every argument struct allows values with a leading hyphen: clap's
// `allow_negative_numbers` misses a negative exponent (`-5e-8` would be an
// unknown flag), and every number armsim prints must be valid input.

#[derive(Args, Debug, Clone)]
#[command(allow_hyphen_values = true)]
/// A ζ-a-tₛ plan: q0 → S_f over tₛ with shape a and base n (shared by `traj`, `via` and the plots).
pub struct ZatArgs {
    /// Start value q0
    #[arg(long)]
    pub q0: f64,
    /// End value S_f
    #[arg(long)]
    pub sf: f64,
    /// Duration tₛ > 0 [s]
    #[arg(long)]
    pub ts: f64,
    /// Shape parameter a (must be < u_min(tₛ))
    #[arg(long)]
    pub a: f64,
    /// Base n > 1
    #[arg(long)]
    pub n: f64,
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim traj`'s arguments: the plan, and the samples or `--info`.
pub struct TrajArgs {
    #[command(flatten)]
    /// The ζ-a-tₛ plan.
    pub p: ZatArgs,
    #[command(flatten)]
    /// Where to sample it.
    pub times: Times,
    /// Print the plan's properties as JSON instead of samples
    #[arg(long, conflicts_with_all = ["t", "samples"])]
    pub info: bool,
}

#[derive(Args, Debug, Clone)]
#[command(allow_hyphen_values = true)]
/// A via-point plan: the main segment and the via value (shared by `via` and `plot via`).
pub struct ViaCore {
    /// The main segment q0 → S_f over tₛ (its shape a and base n).
    #[command(flatten)]
    pub main: ZatArgs,
    /// Desired value θ_v at the via time
    #[arg(long)]
    pub via: f64,
    /// Via time t_v, 0 < t_v < tₛ [s]
    #[arg(long)]
    pub tv: f64,
    /// Shape a_v of the via segment (a_v = t_v − log_{n_v} t_v gives a smooth velocity at t_v); chosen by --continuity c1|c2
    #[arg(long)]
    pub av: Option<f64>,
    /// Base n_v of the via segment; chosen by --continuity c2
    #[arg(long)]
    pub nv: Option<f64>,
    /// Continuity at t_v: c0 position only (--av, --nv as given), c1 also velocity (picks a_v for --nv), c2 also acceleration (picks n_v and a_v; needs t_v > 1)
    #[arg(long, value_enum, default_value_t = ContinuityArg::C0)]
    pub continuity: ContinuityArg,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
/// How smooth the via-point trajectory is at the via time.
pub enum ContinuityArg {
    /// Position continuous only
    C0,
    /// Velocity continuous too (picks a_v)
    C1,
    /// Acceleration continuous too (picks n_v and a_v; t_v > 1 s)
    C2,
}

impl From<ContinuityArg> for Continuity {
    fn from(c: ContinuityArg) -> Self {
        match c {
            ContinuityArg::C0 => Continuity::C0,
            ContinuityArg::C1 => Continuity::C1,
            ContinuityArg::C2 => Continuity::C2,
        }
    }
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim via`'s arguments: the plan, and the samples or the properties.
pub struct ViaArgs {
    #[command(flatten)]
    /// The via-point plan.
    pub p: ViaCore,
    #[command(flatten)]
    /// Where to sample it (else the plan's properties as JSON).
    pub times: Times,
    /// Also run the paper's feedback iteration to this tolerance: adds {iterations, s_v_iter, zeta_iter, zeta_iter_infinite, zeta_v_iter, zeta_v_iter_infinite} (null when it diverges, r ≥ 1)
    #[arg(long, value_name = "TOL", conflicts_with_all = ["t", "samples"])]
    pub iterate: Option<f64>,
}

/// A law of `armsim law` planned over [t0, t_f]: a classic one, or the
/// time-scaled ζ-a-tₛ.
enum LawSampler {
    Classic(LawPlan<f64>),
    Scaled { z: ScaledZat<f64>, p: LawParams<f64> },
}

impl LawSampler {
    /// Position and derivatives, with the classic laws' conventions: the
    /// ends held outside [t0, t_f], exactly s_f from t_f on.
    fn sample(&self, t: f64) -> Sample<f64> {
        match self {
            LawSampler::Classic(l) => l.sample(t),
            LawSampler::Scaled { z, p } => {
                if t < p.t0 {
                    return Sample::at_rest(p.s0);
                }
                if t > p.tf {
                    return Sample::at_rest(p.sf);
                }
                let d = z.g_derivs(t - p.t0);
                let delta = p.sf - p.s0;
                let s = if t >= p.tf { p.sf } else { p.s0 + delta * d.s };
                Sample { s, v: delta * d.v, acc: delta * d.acc, jerk: delta * d.jerk }
            }
        }
    }
}

#[derive(Args, Debug, Clone)]
#[command(allow_hyphen_values = true)]
/// A classic law over [t0, t_f] from s0 to s_f (shared by `law` and `plot law`).
pub struct LawCore {
    /// The motion law
    #[arg(long, value_enum)]
    pub kind: LawKindArg,
    /// Start time t0 [s]
    #[arg(long)]
    pub t0: f64,
    /// End time t_f > t0 [s]
    #[arg(long)]
    pub tf: f64,
    /// Start value s0
    #[arg(long)]
    pub s0: f64,
    /// End value s_f
    #[arg(long)]
    pub sf: f64,
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim law`'s arguments: the law and where to sample it.
pub struct LawArgs {
    #[command(flatten)]
    /// The law.
    pub p: LawCore,
    #[command(flatten)]
    /// Where to sample it.
    pub times: Times,
}

#[derive(Args, Debug)]
/// `armsim plot`'s arguments: what to plot.
pub struct PlotArgs {
    #[command(subcommand)]
    /// A trajectory, law or path.
    pub what: PlotWhat,
}

#[derive(Subcommand, Debug)]
/// What `armsim plot` draws.
pub enum PlotWhat {
    /// Plot a ζ-a-tₛ trajectory (same flags as `traj`)
    Traj(PlotTraj),
    /// Plot a via-point trajectory (same flags as `via`)
    Via(PlotVia),
    /// Plot a classic law (same flags as `law`)
    Law(PlotLaw),
    /// Plot an end-effector path: top and side views of the effector and the joint angles over time (same flags as `path`, plus --out)
    Path(PlotPath),
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// A plot's output file and sample count.
pub struct PlotOut {
    /// Output file, .png or .svg
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Number of samples (default 600)
    #[arg(long, value_name = "K")]
    pub samples: Option<usize>,
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim plot traj`'s arguments.
pub struct PlotTraj {
    #[command(flatten)]
    /// The ζ-a-tₛ plan.
    pub p: ZatArgs,
    #[command(flatten)]
    /// The output.
    pub out: PlotOut,
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim plot via`'s arguments.
pub struct PlotVia {
    #[command(flatten)]
    /// The via-point plan.
    pub p: ViaCore,
    #[command(flatten)]
    /// The output.
    pub out: PlotOut,
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim plot law`'s arguments.
pub struct PlotLaw {
    #[command(flatten)]
    /// The law.
    pub p: LawCore,
    #[command(flatten)]
    /// The output.
    pub out: PlotOut,
}

/// A touch given as raw ADC values or as a normalized point.
#[derive(Args, Debug, Clone)]
#[group(required = true, multiple = false)]
pub struct TouchArg {
    /// Raw ADC reading "X,Y" (default calibration: X 123–932, Y 128–897)
    #[arg(long, value_name = "X,Y", value_parser = parse_raw)]
    pub raw: Option<(u16, u16)>,
    /// Normalized point "x_p,y_p" in [−1,1]×[0,1]
    #[arg(long, value_name = "X,Y", value_parser = parse_pair, allow_hyphen_values = true)]
    pub xy: Option<(f64, f64)>,
}

#[derive(Args, Debug)]
/// `armsim map`'s arguments: the touch.
pub struct MapArgs {
    #[command(flatten)]
    /// The touch to map.
    pub touch: TouchArg,
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim ik`'s arguments: the target and the arm.
pub struct IkArgs {
    /// Target x (planar reach, or x_e with --z)
    #[arg(long)]
    pub x: f64,
    /// Target y (planar height, or y_e with --z)
    #[arg(long)]
    pub y: f64,
    /// Height z_e: solve the lab note's 3-DoF form instead
    #[arg(long)]
    pub z: Option<f64>,
    #[command(flatten)]
    /// The links and the branch.
    pub links: LinkArgs,
}

#[derive(Args, Debug)]
#[command(allow_hyphen_values = true)]
/// `armsim plan`'s arguments: the touch, the scale and the arm.
pub struct PlanArgs {
    #[command(flatten)]
    /// The touch to plan for.
    pub touch: TouchArg,
    /// Screen-to-arm scale of the linear transform
    #[arg(long, default_value_t = 1.0)]
    pub k: f64,
    #[command(flatten)]
    /// The links and the branch.
    pub links: LinkArgs,
}

/// A touch, resolved to the normalized point.
struct Touched {
    x_p: f64,
    y_p: f64,
    clamped: bool,
}

fn resolve_touch(t: &TouchArg) -> Result<Touched, String> {
    if let Some((rx, ry)) = t.raw {
        let m = Calibration::DEFAULT.map::<f64>(rx, ry).map_err(|e| format!("touch mapping: {e:?}"))?;
        return Ok(Touched { x_p: m.x_p, y_p: m.y_p, clamped: m.clamped });
    }
    let (x_p, y_p) = t.xy.ok_or("give --raw X,Y or --xy X,Y")?;
    Ok(Touched { x_p, y_p, clamped: false })
}

/// An IK outcome as the reports give it.
struct IkReport {
    reachable: bool,
    /// The target is the shoulder with l2 = l3: the elbow folds (c = −1, so
    /// q3 = ±acos c = ±π by the branch) and every shoulder angle is a
    /// solution, so there is none to report.
    singular: bool,
    shoulder: Option<f64>,
    elbow: Option<f64>,
}

/// The report of an IK outcome, or the message for input that is no target.
fn ik_report(r: Result<(f64, f64), IkError<f64>>, branch: Branch) -> Result<IkReport, String> {
    Ok(match r {
        Ok((q2, q3)) => IkReport { reachable: true, singular: false, shoulder: Some(q2), elbow: Some(q3) },
        Err(IkError::Singular) => {
            let folded = match branch {
                Branch::Plus => std::f64::consts::PI,
                Branch::Minus => -std::f64::consts::PI,
            };
            IkReport { reachable: true, singular: true, shoulder: None, elbow: Some(folded) }
        }
        Err(IkError::Unreachable { .. }) => IkReport { reachable: false, singular: false, shoulder: None, elbow: None },
        Err(IkError::NotFinite) => return Err("target coordinates must be finite".into()),
    })
}

/// Runs one command and returns what it prints.
pub fn run(cli: &Cli) -> Result<String, String> {
    match &cli.cmd {
        Cmd::Map(a) => cmd_map(a),
        Cmd::Ik(a) => cmd_ik(a),
        Cmd::Plan(a) => cmd_plan(a),
        Cmd::Traj(a) => cmd_traj(a),
        Cmd::Via(a) => cmd_via(a),
        Cmd::Law(a) => cmd_law(a),
        Cmd::Plot(a) => cmd_plot(a),
        Cmd::Path(a) => cmd_path(&a.kind),
        Cmd::Paper(a) => crate::paper::run(a),
    }
}

fn cmd_map(a: &MapArgs) -> Result<String, String> {
    let t = resolve_touch(&a.touch)?;
    let p = WorkspacePoint::new(t.x_p, t.y_p)
        .map_err(|e| format!("point ({}, {}) is outside the workspace [-1,1]x[0,1]: {e:?}", t.x_p, t.y_p))?;
    Ok(Json::new()
        .set("x_p", t.x_p)
        .set("y_p", t.y_p)
        .set("clamped", t.clamped)
        .set("condition", p.condition().number())
        .set("alpha_deg", p.alpha_deg())
        .render()
        + "\n")
}

fn cmd_ik(a: &IkArgs) -> Result<String, String> {
    let l = links(&a.links)?;
    let branch = a.links.branch.into();
    if let Some(z) = a.z {
        let r = ik_report(ik3(&l, a.x, a.y, z, branch).map(|q| (q.th2, q.th3)), branch)?;
        return Ok(Json::new()
            .set("branch", Val::Str(a.links.branch.name().into()))
            .set("reachable", r.reachable)
            .set("singular", r.singular)
            // The direction of (x_e, y_e), reachable or not.
            .set("th1", base_angle(a.x, a.y))
            .set("th2", r.shoulder)
            .set("th3", r.elbow)
            .render()
            + "\n");
    }
    let q = ik2(&l, a.x, a.y, branch).map(|q| {
        debug_assert!({
            let (x, y) = fk2(&l, q.q2, q.q3);
            (x - a.x).abs() + (y - a.y).abs() < 1e-9 * (a.links.l2 + a.links.l3)
        });
        (q.q2, q.q3)
    });
    let r = ik_report(q, branch)?;
    Ok(Json::new()
        .set("branch", Val::Str(a.links.branch.name().into()))
        .set("reachable", r.reachable)
        .set("singular", r.singular)
        .set("q2", r.shoulder)
        .set("q3", r.elbow)
        .render()
        + "\n")
}

fn cmd_plan(a: &PlanArgs) -> Result<String, String> {
    let t = resolve_touch(&a.touch)?;
    if !(a.k.is_finite() && a.k > 0.0) {
        return Err(format!("--k must be positive and finite, got {}", a.k));
    }
    let branch = a.links.branch.into();
    // The firmware's arm: the links in the map's arm unit, their mean.
    links(&a.links)?;
    let geo = ArmGeometry::from_lengths(a.k, a.links.l2, a.links.l3, branch).map_err(|e| format!("{e:?}"))?;
    let p = WorkspacePoint::new(t.x_p, t.y_p)
        .map_err(|e| format!("point ({}, {}) is outside the workspace [-1,1]x[0,1]: {e:?}", t.x_p, t.y_p))?;
    let target = p.target(a.k).map_err(|e| format!("{e:?}"))?;
    let (q, alpha_deg) = match pose_for_point(&geo, t.x_p, t.y_p) {
        Ok(pose) => (Ok((pose.q2, pose.q3)), pose.alpha.to_degrees()),
        Err(PoseError::Ik(e)) => (Err(e), target.alpha_deg()),
        Err(PoseError::Workspace(e)) => return Err(format!("{e:?}")),
    };
    let r = ik_report(q, branch)?;
    let pi = std::f64::consts::PI;
    Ok(Json::new()
        .set("x_p", t.x_p)
        .set("y_p", t.y_p)
        .set("condition", target.condition.number())
        .set("alpha_deg", target.alpha_deg())
        .set("reach", target.reach)
        .set("height", target.height)
        .set("branch", Val::Str(a.links.branch.name().into()))
        .set("reachable", r.reachable)
        .set("singular", r.singular)
        .set("q2", r.shoulder)
        .set("q3", r.elbow)
        .set("s2", r.shoulder.map(|q| q / pi))
        .set("s3", r.elbow.map(|q| q / pi))
        .set("sa", alpha_deg / 180.0)
        .render()
        + "\n")
}

/// The one-line reason for a rejected trajectory.
fn traj_err(e: &TrajError<f64>) -> String {
    e.to_string()
}

fn zat_params(a: &ZatArgs) -> ZatParams<f64> {
    ZatParams { q0: a.q0, sf: a.sf, ts: a.ts, a: a.a, n: a.n }
}

fn zat_plan(a: &ZatArgs) -> Result<ZatPlan<f64>, String> {
    ZatPlan::new(&zat_params(a)).map_err(|e| traj_err(&e))
}

/// The via segment's (a_v, n_v): given, or chosen for the asked continuity.
fn via_shape(a: &ViaCore) -> Result<(f64, f64), String> {
    let (av, nv) = match (a.continuity, a.av, a.nv) {
        (ContinuityArg::C0, Some(av), Some(nv)) => (av, nv),
        (ContinuityArg::C0, _, _) => return Err("--continuity c0 needs --av and --nv".into()),
        (ContinuityArg::C1, None, Some(nv)) => (f64::NAN, nv),
        (ContinuityArg::C1, _, _) => {
            return Err("--continuity c1 needs --nv and picks a_v itself: leave out --av".into())
        }
        (ContinuityArg::C2, None, None) => (f64::NAN, f64::NAN),
        (ContinuityArg::C2, _, _) => {
            return Err("--continuity c2 picks a_v and n_v itself: leave out --av and --nv".into())
        }
    };
    via_shape_for(a.tv, av, nv, a.continuity.into()).map_err(|e| e.to_string())
}

fn via_params(a: &ViaCore) -> Result<ViaParams<f64>, String> {
    let m = &a.main;
    let (av, nv) = via_shape(a)?;
    Ok(ViaParams { q0: m.q0, theta_v: a.via, sf: m.sf, tv: a.tv, ts: m.ts, a: m.a, n: m.n, av, nv })
}

fn via_plan(a: &ViaCore) -> Result<ViaPlan<f64>, String> {
    let p = via_params(a)?;
    // Name the segment whose parameters are wrong before the combined check.
    Shape::new(&ShapeParams { ts: p.tv, a: p.av, n: p.nv })
        .map_err(|e| format!("via segment (--tv, --av, --nv): {}", traj_err(&e)))?;
    Shape::new(&ShapeParams { ts: a.main.ts, a: a.main.a, n: a.main.n })
        .map_err(|e| format!("main segment (--ts, --a, --n): {}", traj_err(&e)))?;
    ViaPlan::new(&p).map_err(|e| traj_err(&e))
}

fn law_plan(a: &LawCore) -> Result<LawSampler, String> {
    let p = LawParams { t0: a.t0, tf: a.tf, s0: a.s0, sf: a.sf };
    let law = match a.kind {
        LawKindArg::Linear => Law::Linear,
        LawKindArg::Cubic => Law::Cubic,
        LawKindArg::Quintic => Law::Quintic,
        LawKindArg::Trapezoid => Law::Trapezoid,
        LawKindArg::Zat => {
            // The classic laws' checks of the interval and the values first.
            LawPlan::new(Law::Linear, &p).map_err(|e| traj_err(&e))?;
            let z = ScaledZat::new(a.tf - a.t0).map_err(|e| traj_err(&e))?;
            return Ok(LawSampler::Scaled { z, p });
        }
    };
    LawPlan::new(law, &p).map(LawSampler::Classic).map_err(|e| traj_err(&e))
}

fn csv(header: &str, ts: &[f64], f: impl Fn(f64) -> Vec<f64>) -> String {
    let mut out = String::from(header);
    out.push('\n');
    for &t in ts {
        let mut row = vec![t];
        row.extend(f(t));
        out.push_str(&csv_row(&row));
        out.push('\n');
    }
    out
}

fn sample_row(s: Sample<f64>) -> Vec<f64> {
    vec![s.s, s.v, s.acc, s.jerk]
}

fn cmd_traj(a: &TrajArgs) -> Result<String, String> {
    let p = zat_params(&a.p);
    if a.info {
        for (name, v) in [("--q0", p.q0), ("--sf", p.sf), ("--ts", p.ts), ("--a", p.a), ("--n", p.n)] {
            if !v.is_finite() {
                return Err(format!("{name} must be finite"));
            }
        }
        if p.ts <= 0.0 {
            return Err(format!("--ts must be > 0, got {}", p.ts));
        }
        if p.n <= 1.0 {
            return Err(format!("--n must be > 1, got {}", p.n));
        }
        let shape = Shape::new(&p.shape());
        let plan = ZatPlan::new(&p).ok();
        return Ok(Json::new()
            .set("zeta", zeta(&p))
            // ζ → ∞ as |Δ| → 0 (ln of a vanishing product); for a ≥ tₛ it is undefined.
            .set("zeta_infinite", p.sf == p.q0 && p.a < p.ts)
            .set("u_min", u_min(p.ts))
            .set("admissible", shape.is_ok())
            .set("a_smooth_stop", smooth_stop_a(p.ts, p.n))
            .set("end_velocity", plan.map(|pl| pl.end_velocity()))
            .set("monotone", shape.ok().map(|s| s.is_monotone()))
            .render()
            + "\n");
    }
    let plan = zat_plan(&a.p)?;
    let ts = times(&a.times, 0.0, p.ts)?;
    Ok(csv("t,s,v,acc,jerk", &ts, |t| sample_row(plan.sample(t))))
}

fn cmd_via(a: &ViaArgs) -> Result<String, String> {
    let plan = via_plan(&a.p)?;
    if a.times.t.is_some() || a.times.samples.is_some() {
        let ts = times(&a.times, 0.0, a.p.main.ts)?;
        return Ok(csv("t,s,v,acc,jerk", &ts, |t| sample_row(plan.sample(t))));
    }
    let r = plan.r();
    let mut j = Json::new()
        .set("r", r)
        .set("s_v", plan.sv())
        // Each ζ is infinite for its term's zero displacement (see `armsim via --help`).
        .set("zeta", plan.zeta())
        .set("zeta_infinite", plan.sv() == a.p.main.sf)
        .set("zeta_v", plan.zeta_v())
        .set("zeta_v_infinite", plan.sv() == a.p.main.q0)
        .set("condition", plan.condition().number())
        .set("converges", r < 1.0)
        .set("a_v", plan.via_shape().a())
        .set("n_v", plan.via_shape().n())
        .set("velocity_jump", plan.velocity_jump())
        .set("acceleration_jump", plan.acc_jump())
        .set("jerk_jump", plan.jumps().jerk);
    if let Some(tol) = a.iterate {
        if !(tol.is_finite() && tol > 0.0) {
            return Err(format!("--iterate tolerance must be positive, got {tol}"));
        }
        match iterate_paper(&via_params(&a.p)?, tol, MAX_PAPER_ITERATIONS) {
            Ok(it) => {
                j = j
                    .set("iterations", it.iterations)
                    .set("s_v_iter", it.sv)
                    .set("zeta_iter", it.zeta)
                    .set("zeta_iter_infinite", it.sv == a.p.main.sf)
                    .set("zeta_v_iter", it.zeta_v)
                    .set("zeta_v_iter_infinite", it.sv == a.p.main.q0);
            }
            // The JSON already says `converges: false`; the closed form above
            // is still the answer.
            Err(TrajError::ViaDiverges { .. }) => {
                j = j
                    .set("iterations", None::<f64>)
                    .set("s_v_iter", None::<f64>)
                    .set("zeta_iter", None::<f64>)
                    .set("zeta_iter_infinite", None::<bool>)
                    .set("zeta_v_iter", None::<f64>)
                    .set("zeta_v_iter_infinite", None::<bool>);
            }
            Err(e) => return Err(format!("paper iteration: {}", traj_err(&e))),
        }
    }
    Ok(j.render() + "\n")
}

/// Generous: with r < 1 the error shrinks by r per step.
const MAX_PAPER_ITERATIONS: u16 = 10_000;

fn cmd_law(a: &LawArgs) -> Result<String, String> {
    let plan = law_plan(&a.p)?;
    let ts = times(&a.times, a.p.t0, a.p.tf)?;
    Ok(csv("t,s,v,acc", &ts, |t| {
        let s = plan.sample(t);
        vec![s.s, s.v, s.acc]
    }))
}

fn cmd_plot(a: &PlotArgs) -> Result<String, String> {
    if let PlotWhat::Path(p) = &a.what {
        return plot_path(p);
    }
    let (title, out, t, samples): (String, &PlotOut, Vec<f64>, Vec<Sample<f64>>) = match &a.what {
        PlotWhat::Traj(p) => {
            let plan = zat_plan(&p.p)?;
            let t = plot_times(&p.out, 0.0, p.p.ts)?;
            let s = t.iter().map(|&t| plan.sample(t)).collect();
            let title = format!("zeta-a-ts: q0={} Sf={} ts={} a={} n={}", p.p.q0, p.p.sf, p.p.ts, p.p.a, p.p.n);
            (title, &p.out, t, s)
        }
        PlotWhat::Via(p) => {
            let plan = via_plan(&p.p)?;
            let t = plot_times(&p.out, 0.0, p.p.main.ts)?;
            let s = t.iter().map(|&t| plan.sample(t)).collect();
            let title = format!(
                "via point: q0={} theta_v={} at tv={} -> Sf={} (S_v*={:.6})",
                p.p.main.q0,
                p.p.via,
                p.p.tv,
                p.p.main.sf,
                plan.sv()
            );
            (title, &p.out, t, s)
        }
        PlotWhat::Path(_) => unreachable!("handled above"),
        PlotWhat::Law(p) => {
            let plan = law_plan(&p.p)?;
            let t = plot_times(&p.out, p.p.t0, p.p.tf)?;
            let s = t.iter().map(|&t| plan.sample(t)).collect();
            let title = format!("{:?} law: s0={} -> sf={} over [{}, {}]", p.p.kind, p.p.s0, p.p.sf, p.p.t0, p.p.tf);
            (title, &p.out, t, s)
        }
    };
    let col = |f: fn(&Sample<f64>) -> f64| samples.iter().map(f).collect::<Vec<f64>>();
    let (s, v, acc, jerk) = (col(|x| x.s), col(|x| x.v), col(|x| x.acc), col(|x| x.jerk));
    let panel =
        |ylabel: &'static str, y: &'static str, data| Panel { ylabel, curves: vec![Curve { label: y, y: data }] };
    plot::panels(
        &out.out,
        &title,
        &t,
        &[
            panel("position", "", &s),
            panel("velocity", "", &v),
            panel("acceleration", "", &acc),
            panel("jerk", "", &jerk),
        ],
    )
    .map_err(|e| e.to_string())?;
    Ok(format!("wrote {}\n", out.out.display()))
}

fn plot_times(o: &PlotOut, start: f64, end: f64) -> Result<Vec<f64>, String> {
    times(&Times { t: None, samples: Some(o.samples.unwrap_or(PLOT_SAMPLES)) }, start, end)
}
