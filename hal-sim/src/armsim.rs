//! The `armsim` command line: argument definitions and the commands, as a
//! library so the binary stays a thin shell and tests can call it directly.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use touch_arm::ik::{fk2, ik2, ik3, Branch, IkError, Links};
use touch_arm::pose::{pose_for_point, ArmGeometry, PoseError};
use touch_arm::touch_map::Calibration;
use touch_arm::workspace::WorkspacePoint;

use crate::report::Json;

#[derive(Parser, Debug)]
#[command(name = "armsim", version, about = "The touch-arm method on a PC (f64): touch mapping, IK, ζ-a-tₛ / via-point / classic trajectories and plots")]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Cmd,
}

#[derive(Subcommand, Debug)]
pub enum Cmd {
    /// Map a touch to the normalized workspace: JSON {x_p, y_p, clamped, condition, alpha_deg}
    Map(MapArgs),
    /// 2-link inverse kinematics (3-DoF with --z): JSON {reachable, q2, q3} or {reachable, th1, th2, th3}
    Ik(IkArgs),
    /// Touch → condition, α, transform, IK: JSON {x_p, y_p, condition, alpha_deg, reach, height, reachable, q2, q3, s2, s3, sa}
    Plan(PlanArgs),
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
pub struct MapArgs {
    #[command(flatten)]
    pub touch: TouchArg,
}

#[derive(ValueEnum, Clone, Copy, Debug, Default)]
pub enum BranchArg {
    /// q3 = +acos(c)
    #[default]
    Plus,
    /// q3 = −acos(c)
    Minus,
}

impl From<BranchArg> for Branch {
    fn from(b: BranchArg) -> Self {
        match b {
            BranchArg::Plus => Branch::Plus,
            BranchArg::Minus => Branch::Minus,
        }
    }
}

#[derive(Args, Debug, Clone)]
pub struct LinkArgs {
    /// Upper-arm length l2
    #[arg(long, default_value_t = 1.0)]
    pub l2: f64,
    /// Forearm length l3
    #[arg(long, default_value_t = 1.0)]
    pub l3: f64,
    /// Elbow branch
    #[arg(long, value_enum, default_value_t = BranchArg::Plus)]
    pub branch: BranchArg,
}

#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
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
    pub links: LinkArgs,
}

#[derive(Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct PlanArgs {
    #[command(flatten)]
    pub touch: TouchArg,
    /// Screen-to-arm scale of the linear transform
    #[arg(long, default_value_t = 1.0)]
    pub k: f64,
    #[command(flatten)]
    pub links: LinkArgs,
}

fn parse_pair(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s.split_once(',').ok_or_else(|| format!("expected X,Y, got {s:?}"))?;
    let p = |v: &str| v.trim().parse::<f64>().map_err(|_| format!("not a number: {v:?}"));
    let (a, b) = (p(a)?, p(b)?);
    if !(a.is_finite() && b.is_finite()) {
        return Err("coordinates must be finite".into());
    }
    Ok((a, b))
}

fn parse_raw(s: &str) -> Result<(u16, u16), String> {
    let (a, b) = s.split_once(',').ok_or_else(|| format!("expected X,Y, got {s:?}"))?;
    let p = |v: &str| match v.trim().parse::<u16>() {
        Ok(n) if n <= 1023 => Ok(n),
        _ => Err(format!("raw ADC value must be an integer 0..=1023, got {v:?}")),
    };
    Ok((p(a)?, p(b)?))
}

/// Comma-separated list of numbers ("0,0.1,0.5").
pub fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(|v| match v.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!("not a finite number in list: {v:?}")),
        })
        .collect()
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

fn links(a: &LinkArgs) -> Result<Links<f64>, String> {
    Links::new(a.l2, a.l3).map_err(|e| format!("link lengths l2={}, l3={}: {e:?} (must be positive and finite)", a.l2, a.l3))
}

fn ik_error(e: &IkError<f64>) -> Option<String> {
    match e {
        IkError::Unreachable { .. } | IkError::Singular => None,
        IkError::NotFinite => Some("target coordinates must be finite".into()),
    }
}

/// Runs one command and returns what it prints.
pub fn run(cli: &Cli) -> Result<String, String> {
    match &cli.cmd {
        Cmd::Map(a) => cmd_map(a),
        Cmd::Ik(a) => cmd_ik(a),
        Cmd::Plan(a) => cmd_plan(a),
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
        let j = match ik3(&l, a.x, a.y, z, branch) {
            Ok(q) => Json::new().set("reachable", true).set("th1", q.th1).set("th2", q.th2).set("th3", q.th3),
            Err(e) => {
                if let Some(msg) = ik_error(&e) {
                    return Err(msg);
                }
                Json::new().set("reachable", false).set("th1", None::<f64>).set("th2", None::<f64>).set("th3", None::<f64>)
            }
        };
        return Ok(j.render() + "\n");
    }
    let j = match ik2(&l, a.x, a.y, branch) {
        Ok(q) => {
            debug_assert!({
                let (x, y) = fk2(&l, q.q2, q.q3);
                (x - a.x).abs() + (y - a.y).abs() < 1e-9 * (a.links.l2 + a.links.l3)
            });
            Json::new().set("reachable", true).set("q2", q.q2).set("q3", q.q3)
        }
        Err(e) => {
            if let Some(msg) = ik_error(&e) {
                return Err(msg);
            }
            Json::new().set("reachable", false).set("q2", None::<f64>).set("q3", None::<f64>)
        }
    };
    Ok(j.render() + "\n")
}

fn cmd_plan(a: &PlanArgs) -> Result<String, String> {
    let t = resolve_touch(&a.touch)?;
    if !(a.k.is_finite() && a.k > 0.0) {
        return Err(format!("--k must be positive and finite, got {}", a.k));
    }
    let geo = ArmGeometry { k: a.k, links: links(&a.links)?, branch: a.links.branch.into() };
    let p = WorkspacePoint::new(t.x_p, t.y_p)
        .map_err(|e| format!("point ({}, {}) is outside the workspace [-1,1]x[0,1]: {e:?}", t.x_p, t.y_p))?;
    let target = p.target(a.k).map_err(|e| format!("{e:?}"))?;
    let j = Json::new()
        .set("x_p", t.x_p)
        .set("y_p", t.y_p)
        .set("condition", target.condition.number())
        .set("alpha_deg", target.alpha_deg())
        .set("reach", target.reach)
        .set("height", target.height);
    let j = match pose_for_point(&geo, t.x_p, t.y_p) {
        Ok(pose) => j
            .set("reachable", true)
            .set("q2", pose.q2)
            .set("q3", pose.q3)
            .set("s2", pose.q2 / std::f64::consts::PI)
            .set("s3", pose.q3 / std::f64::consts::PI)
            .set("sa", pose.alpha.to_degrees() / 180.0),
        Err(PoseError::Ik(e)) => {
            if let Some(msg) = ik_error(&e) {
                return Err(msg);
            }
            j.set("reachable", false)
                .set("q2", None::<f64>)
                .set("q3", None::<f64>)
                .set("s2", None::<f64>)
                .set("s3", None::<f64>)
                .set("sa", target.alpha_deg() / 180.0)
        }
        Err(PoseError::Workspace(e)) => return Err(format!("{e:?}")),
    };
    Ok(j.render() + "\n")
}

#[allow(dead_code)]
fn out_path(p: &std::path::Path) -> PathBuf {
    p.to_path_buf()
}
