//! End-effector paths paced by a motion law (the lab note): the effector
//! follows P(g(t)) for a [`Path`] and the selected law's profile g (0 → 1
//! over tₛ), and the joints follow the IK of every point.
//!
//! Unlike a joint move, the joints are not affine in g, so their speeds and
//! accelerations are checked on a scan of the move when it is planned:
//! θ̇ = θ′(s)·ġ and θ̈ = θ″(s)·ġ² + θ′(s)·g̈ with s = g(t) and θ′, θ″ from
//! [`ik_jet`]. Every law offered here scales with its duration (g(t) = G(t/tₛ)),
//! so the scan's grid τ = t/tₛ sees the same path points for every tₛ and its
//! peaks scale exactly as 1/tₛ and 1/tₛ²: the shortest admissible tₛ follows
//! from one scan in closed form, which is how [`Pace::SlowDown`] lengthens a
//! move instead of clamping any joint. The peaks are bounds over every
//! stretch between the scan's points ([`jet_bound`] for the path, the law's
//! cell tables for g), so no spike between them escapes (issue #24, F4).

use core::fmt;

use crate::geometry::ik::{ik3, Branch, IkError, Links};
use crate::geometry::jet_bound::{jet_bound, Iv};
use crate::geometry::path::{ik_jet, JetError, JointJet, Path, PathShapeError, Vec3};
use crate::math::real::Real;
use crate::motion::plan::{JointLaw, LawKind, JOINTS};
use crate::motion::planner::cells::{cell_table, CELLS};
use crate::motion::zat::ShapeParams;
use crate::motion::TrajError;

/// The arm a path is solved for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathArm<R> {
    /// Upper arm and forearm.
    pub links: Links<R>,
    /// Elbow solution.
    pub branch: Branch,
}

/// What each joint may do along a path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathLimits<R> {
    /// Smallest angle per joint, rad.
    pub min: [R; JOINTS],
    /// Largest angle per joint, rad.
    pub max: [R; JOINTS],
    /// Largest speed per joint, rad/s (> 0).
    pub speed: [R; JOINTS],
    /// Largest acceleration per joint, rad/s² (> 0).
    pub accel: [R; JOINTS],
    /// Longest move [`Pace::SlowDown`] may make, s.
    pub ts_max: R,
}

/// What to do when the asked duration is too short for a joint's limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pace {
    /// Refuse, naming the joint and the shortest admissible duration.
    Refuse,
    /// Take the shortest admissible duration (at most `ts_max`).
    SlowDown,
}

/// A path move to plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathRequest<R> {
    /// The effector's path.
    pub path: Path<R>,
    /// The law pacing it.
    pub law: LawKind,
    /// Asked duration, s.
    pub ts: R,
    /// Too short a duration: refuse or slow down.
    pub pace: Pace,
    /// Intervals of the plan-time scan (≥ 2).
    pub samples: u16,
    /// Refinement steps around each critical point ([`REFINE_FULL`] on the
    /// host; fewer resolve spikes down to tₛ·2^(−refine/4) only).
    pub refine: u16,
}

/// Why a path move cannot be planned. `s` is the path's progress (0..1)
/// where the problem is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PathError<R> {
    /// The path itself (empty, non-finite, through the base axis).
    Shape(PathShapeError),
    /// The law's parameters (non-finite or non-positive duration).
    Law(TrajError<R>),
    /// The papers' own ζ-a-tₛ changes its shape with tₛ: not offered for paths.
    LawNotScalable,
    /// A non-finite limit, a limit ≤ 0, or fewer than 2 scan intervals.
    BadLimits,
    /// A point out of the arm's reach.
    Unreachable {
        /// Progress.
        s: R,
    },
    /// A point on the base axis or with the arm straight or folded.
    Singular {
        /// Progress.
        s: R,
    },
    /// A joint outside its angle limits.
    JointLimit {
        /// 0 base, 1 shoulder, 2 elbow.
        joint: u8,
        /// Progress.
        s: R,
        /// The angle it would need, rad.
        angle: R,
    },
    /// A joint over its speed limit at the asked duration.
    Speed {
        /// 0 base, 1 shoulder, 2 elbow.
        joint: u8,
        /// The shortest duration that keeps it, s.
        ts_min: R,
    },
    /// A joint over its acceleration limit at the asked duration.
    Accel {
        /// 0 base, 1 shoulder, 2 elbow.
        joint: u8,
        /// The shortest duration that keeps it, s.
        ts_min: R,
    },
    /// Slowing down would need more than `ts_max`.
    TooSlow {
        /// The duration it would need, s.
        ts_min: R,
    },
}

/// The joints' names in refusals.
pub const JOINT_NAMES: [&str; JOINTS] = ["base", "shoulder", "elbow"];

fn joint_name(j: u8) -> &'static str {
    JOINT_NAMES.get(j as usize).copied().unwrap_or("?")
}

impl<R: Real> fmt::Display for PathError<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            PathError::Shape(PathShapeError::NotFinite) => f.write_str("path: non-finite coordinate or radius"),
            PathError::Shape(PathShapeError::Degenerate) => f.write_str("path: empty segment or radius not > 0"),
            PathError::Shape(PathShapeError::CrossesBaseAxis) => {
                f.write_str("path crosses the base axis (x = y = 0), where the base would turn by 180 degrees at once")
            }
            PathError::Law(e) => write!(f, "law: {e}"),
            PathError::LawNotScalable => f.write_str(
                "law zat-paper is not offered for paths (its shape changes with ts); use zat or a classic law",
            ),
            PathError::BadLimits => f.write_str(
                "joint limits must be finite, speeds and accelerations > 0, and the scan at least 2 intervals",
            ),
            PathError::Unreachable { s } => write!(f, "path leaves the arm's reach at s = {:.4}", s.to_f64()),
            PathError::Singular { s } => {
                write!(f, "path meets a singular pose (base axis, arm straight or folded) at s = {:.4}", s.to_f64())
            }
            PathError::JointLimit { joint, s, angle } => write!(
                f,
                "{} joint limit: {:.4} rad needed at s = {:.4}",
                joint_name(joint),
                angle.to_f64(),
                s.to_f64()
            ),
            PathError::Speed { joint, ts_min } => write!(
                f,
                "{} speed limit: the path needs ts >= {:.4} s (or slow down)",
                joint_name(joint),
                ts_min.to_f64()
            ),
            PathError::Accel { joint, ts_min } => write!(
                f,
                "{} acceleration limit: the path needs ts >= {:.4} s (or slow down)",
                joint_name(joint),
                ts_min.to_f64()
            ),
            PathError::TooSlow { ts_min } => {
                write!(f, "the joints' limits need ts >= {:.4} s, beyond the longest move", ts_min.to_f64())
            }
        }
    }
}

/// The peaks a scan found: bounds of the joints' rates over the whole move
/// (issue #24, F4), at or above every sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPeaks<R> {
    /// max |θ̇_j|, rad/s.
    pub speed: [R; JOINTS],
    /// max |θ̈_j|, rad/s².
    pub accel: [R; JOINTS],
}

/// A planned path move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPlan<R> {
    path: Path<R>,
    law: JointLaw<R>,
    arm: PathArm<R>,
    peaks: PathPeaks<R>,
}

/// The effector and the joints at one instant of a path move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathState<R> {
    /// Progress s = g(t).
    pub s: R,
    /// Effector position P(s).
    pub p: Vec3<R>,
    /// Joint angles, rad.
    pub q: Vec3<R>,
    /// Joint speeds, rad/s.
    pub dq: Vec3<R>,
    /// Joint accelerations, rad/s².
    pub ddq: Vec3<R>,
}

fn law_for<R: Real>(kind: LawKind, ts: R) -> Result<JointLaw<R>, PathError<R>> {
    if kind == LawKind::ZatPaper {
        return Err(PathError::LawNotScalable);
    }
    // (a, n) are read by the papers' form only.
    JointLaw::from_kind(kind, &ShapeParams { ts, a: R::ZERO, n: R::TWO }).map_err(PathError::Law)
}

fn jet_err<R: Real>(e: JetError<R>, s: R) -> PathError<R> {
    match e {
        JetError::Ik(IkError::Unreachable { .. }) | JetError::Ik(IkError::NotFinite) => PathError::Unreachable { s },
        JetError::Ik(IkError::Singular) | JetError::Singular => PathError::Singular { s },
    }
}

/// Largest change of a joint between two scan points that still counts as
/// one continuous IK branch; more means the solution flipped (a wrap of q2 or
/// of θ1), which rates at the points themselves would not show.
const BRANCH_JUMP_RAD: f64 = 0.5;

fn check_limits<R: Real>(l: &PathLimits<R>) -> Result<(), PathError<R>> {
    for j in 0..JOINTS {
        let ok = l.min[j].is_finite()
            && l.max[j].is_finite()
            && l.min[j] <= l.max[j]
            && l.speed[j].is_finite()
            && l.speed[j].is_positive()
            && l.accel[j].is_finite()
            && l.accel[j].is_positive();
        if !ok {
            return Err(PathError::BadLimits);
        }
    }
    if l.ts_max.is_finite() {
        Ok(())
    } else {
        Err(PathError::BadLimits)
    }
}

/// What a visit of one instant leaves for the bound of the stretch it ends.
#[derive(Debug, Clone, Copy, PartialEq)]
struct End<R> {
    /// Time, s.
    t: R,
    /// Progress g(t) and its rate ġ.
    s: R,
    gv: R,
    /// g̈.
    ga: R,
    /// Joint angles.
    q: Vec3<R>,
    /// The joints' largest (speed/limit)² or acceleration/limit here.
    f: R,
}

/// Checks one instant (reachable, non-singular, inside the angle limits)
/// and folds its rates into `peaks`.
fn visit<R: Real>(
    path: &Path<R>,
    law: &JointLaw<R>,
    arm: &PathArm<R>,
    lim: &PathLimits<R>,
    t: R,
    peaks: &mut PathPeaks<R>,
) -> Result<End<R>, PathError<R>> {
    let g = law.g_derivs(t);
    let jj = ik_jet(&arm.links, arm.branch, &path.jet(g.s)).map_err(|e| jet_err(e, g.s))?;
    let mut f = R::ZERO;
    for j in 0..JOINTS {
        let q = jj.q[j];
        if !(lim.min[j] <= q && q <= lim.max[j]) {
            return Err(PathError::JointLimit { joint: j as u8, s: g.s, angle: q });
        }
        let v = (jj.dq[j] * g.v).abs();
        let a = (jj.ddq[j] * g.v * g.v + jj.dq[j] * g.acc).abs();
        if !(v.is_finite() && a.is_finite()) {
            return Err(PathError::Singular { s: g.s });
        }
        peaks.speed[j] = peaks.speed[j].max(v);
        peaks.accel[j] = peaks.accel[j].max(a);
        let fv = v / lim.speed[j];
        f = f.max(fv * fv).max(a / lim.accel[j]);
    }
    Ok(End { t, s: g.s, gv: g.v, ga: g.acc, q: jj.q, f })
}

/// One IK branch from `a` to `b`: no joint changes by more than
/// [`BRANCH_JUMP_RAD`] (angles are finite here: `visit` checked their rates).
fn branch_kept<R: Real>(a: &End<R>, b: &End<R>) -> Result<(), PathError<R>> {
    for k in 0..JOINTS {
        if R::lit(BRANCH_JUMP_RAD).lt_num((b.q[k] - a.q[k]).abs()) {
            return Err(PathError::Singular { s: b.s });
        }
    }
    Ok(())
}

/// Deepest halving of a scan interval for its bound: 2⁻¹² of it (next to
/// the rim and the base axis the bound closes in on the rates only there;
/// at 2⁻⁸ the line came out 5 % longer than its shortest, at 2⁻¹² 3 %).
const BOUND_DEPTH: u8 = 12;
/// A stretch is halved while its bound's (speed/limit)² or accel/limit
/// exceeds by more than this share the largest the scan has visited (grid,
/// refinement, the stretches' ends so far): about 3 % on the duration the
/// bound asks for. Only stretches near the move's binding
/// peak are halved; and the test is scale-free (all of them scale as
/// 1/tₛ²), so the halving, and with it the bounds, are the same for every
/// tₛ: one scan decides the shortest.
const BOUND_TOL: f64 = 1.0 / 16.0;

/// Halvings a whole scan may spend on its bounds. Past it, every stretch
/// still to come takes its bound as it is (sound, only looser: the move
/// comes out slower, never faster than its limits), and one whose bound is
/// undefined is refused as singular. So a check decides within a known
/// number of units whatever the path: without it, the trapezoid on links
/// of 69 and 100 mm (a line folding the elbow to −170°) halved for 18 195
/// units, minutes on the chip (`tests/path.rs`,
/// `the_scan_decides_within_its_halving_budget`). The moves the tests and the
/// benchmark plan spend far fewer (BENCHMARKS.md).
pub const HALVING_BUDGET: u16 = 256;

/// The largest |f‴| of a law's normalized profile (g(t) = f(t/tₛ)), for
/// laws whose f″ is continuous: ζ-a-tₛ's is 62.34 (at τ = 0.091), the
/// quintic's 60 (at the ends), the cubic's 12; `tests/path_bound.rs`
/// checks each against the law's own f64 evaluation. The trapezoid's f″
/// steps: its cells' bound alone.
pub fn law_jerk(kind: LawKind) -> Option<f64> {
    match kind {
        LawKind::Zat => Some(62.5),
        LawKind::Quintic => Some(60.0),
        LawKind::Cubic => Some(12.0),
        _ => None,
    }
}

/// The cell of the law's table holding x = t/tₛ·`n` (`n` cells), or, with
/// `up`, the one ending at or after it.
#[inline(never)] // reason: code-size
fn law_cell<R: Real>(x: R, n: R, up: bool) -> usize {
    if !R::ZERO.lt_num(x) {
        0
    } else if x.lt_num(n) {
        let i = x.to_f32() as usize;
        if up && R::from_u16(i as u16) < x {
            i + 1
        } else {
            i
        }
    } else {
        CELLS
    }
}

/// Ranges of ġ and g̈ over [a.t, b.t]: the law's cell bounds
/// ([`cell_table`]), tightened by the ends' values and the next
/// derivative's bound (a function with |f′| ≤ A between values fa, fb stays
/// within (fa + fb ± A·h)/2): ġ's by the cells' |g̈|, g̈'s by [`law_jerk`] (the trapezoid's by its sign).
/// Without the latter, a cell's |g̈| is its largest for the whole cell,
/// which next to the rim meets the large path rates of the move's very
/// start. The linear law, which has no table, has constant rates between
/// its steps: its ends' values.
#[inline(never)] // reason: code-size
fn law_bound<R: Real>(law: &JointLaw<R>, a: &End<R>, b: &End<R>) -> (Iv<R>, Iv<R>) {
    let Some(tab) = cell_table(law.kind()) else {
        return (Iv::of(a.gv, b.gv), Iv::of(a.ga, b.ga));
    };
    let ts = law.duration();
    let inv = ts.recip();
    let n = R::from_u16(CELLS as u16);
    let first = law_cell(a.t * inv * n, n, false);
    let (v, acc): (R, R) = tab.max_over(first, law_cell(b.t * inv * n, n, true).max(first + 1));
    let h = b.t - a.t;
    let acc = acc * inv * inv;
    let (vs, dv) = (a.gv + b.gv, acc * h);
    let v = Iv { lo: ((vs - dv) * R::HALF).max(R::ZERO), hi: (v * inv).min((vs + dv) * R::HALF) };
    let g2 = match law_jerk(law.kind()) {
        Some(jerk) => {
            let (s2, d2) = (a.ga + b.ga, R::lit(jerk) * inv * inv * inv * h);
            Iv { lo: ((s2 - d2) * R::HALF).max(-acc), hi: ((s2 + d2) * R::HALF).min(acc) }
        }
        // The trapezoid's f″ is +A, 0, −A by thirds: ≥ 0 on its first half,
        // ≤ 0 on its second; without the sign a stretch would lose the
        // cancellation of θ″·ġ² against θ′·g̈ (16 % too long a move seen).
        None if (b.t + b.t).le_num(ts) => Iv { lo: R::ZERO, hi: acc },
        None if ts.le_num(a.t + a.t) => Iv { lo: -acc, hi: R::ZERO },
        None => Iv { lo: -acc, hi: acc },
    };
    (v, g2)
}

/// The bound over a stretch (speeds and accelerations per joint, folded
/// into `peaks`) and whether to halve it instead: `None` when the path
/// bound is undefined there (base axis, rim, folded arm), else the bound's
/// largest (speed/limit)² or accel/limit.
#[inline(never)] // reason: code-size
fn stretch_bound<R: Real>(c: &Checked<R>, law: &JointLaw<R>, a: &End<R>, b: &End<R>) -> Option<([(R, R); JOINTS], R)> {
    let jb = jet_bound(&c.arm.links, c.arm.branch, &c.path, a.s, b.s)?;
    let (gv, ga) = law_bound(law, a, b);
    let gv2 = gv.sqr();
    let mut out = [(R::ZERO, R::ZERO); JOINTS];
    let mut f_b = R::ZERO;
    for j in 0..JOINTS {
        let (d1, d2) = jb[j];
        // ġ ≥ 0: |θ′·ġ| ≤ max|θ′|·max ġ.
        let (v, acc) = (d1.mag() * gv.hi, d2.times(gv2).plus(d1.times(ga)).mag());
        let fv = v / c.lim.speed[j];
        out[j] = (v, acc);
        f_b = f_b.max(fv * fv).max(acc / c.lim.accel[j]);
    }
    Some((out, f_b))
}

/// Bisections for the instant a critical progress is passed (g is monotone):
/// to the f32 resolution of the duration.
const CRITICAL_BISECTIONS: u8 = 24;
/// Refinement steps of the host's checks (`armsim`): offsets tₛ·2^(−m/4)
/// for m = 4..=80, down to a millionth of the move on each side of a
/// critical instant, so a spike of any width above that is visited within a
/// fifth of its width.
pub const REFINE_FULL: u16 = 80;

/// The instant t with g(t) = s.
fn time_of<R: Real>(law: &JointLaw<R>, s: R) -> R {
    let (mut lo, mut hi) = (R::ZERO, law.duration());
    for _ in 0..CRITICAL_BISECTIONS {
        let mid = (lo + hi) * R::HALF;
        if law.g(mid) < s {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo + hi) * R::HALF
}

/// Where a resumable scan is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ScanAt<R> {
    /// The even grid's instant i of `samples`.
    Grid(u16),
    /// The bound of the stretch of the grid's interval `i` that is its
    /// `j`-th of 2^`d` (the instant 0 first).
    Bound {
        i: u16,
        j: u16,
        d: u8,
    },
    /// The instant of critical point `crit` is still to be found.
    Critical(u8),
    /// Around critical instant `t_c`: offset step `m` (3: `t_c` itself) on
    /// side `late`, the offset `off` for it.
    Cluster {
        crit: u8,
        t_c: R,
        off: R,
        m: u16,
        late: bool,
    },
    Finished,
}

/// The scan of one duration, a unit of work (a visit or a bisection) at a
/// time: the grid (each point reachable, non-singular, inside the angle
/// limits, one IK branch), then the refinement around each of the path's
/// critical points and around its two ends, where narrow rate spikes sit.
/// The ends count since issue #24 (F4): there the law's rate rises from
/// zero while, next to the rim, a joint's path rate (∝ 1/sin θ₃) falls
/// from a large value, and their product peaks between grid points; the
/// grid alone let such a line reach 1.105 × max_accel. Grid-independent: the
/// refinement sits at the same τ = t/tₛ for every tₛ. Last, the bounds
/// over every stretch of the grid (`Scan::bound`), halved where loose: the
/// samples only set the reference the halving is measured against, and the
/// bounds decide.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Scan<R> {
    at: ScanAt<R>,
    peaks: PathPeaks<R>,
    /// The last visited end of a bounded stretch.
    prev: Option<End<R>>,
    /// The largest rate visited so far, as (speed/limit)² or accel/limit.
    f_max: R,
    /// Stretches halved so far ([`HALVING_BUDGET`]).
    halvings: u16,
}

impl<R: Real> Scan<R> {
    fn new() -> Self {
        Scan {
            at: ScanAt::Grid(0),
            peaks: PathPeaks { speed: [R::ZERO; JOINTS], accel: [R::ZERO; JOINTS] },
            prev: None,
            f_max: R::ZERO,
            halvings: 0,
        }
    }

    /// One unit of work; `Ok(true)` once the scan is complete.
    fn step(&mut self, c: &Checked<R>, law: &JointLaw<R>) -> Result<bool, PathError<R>> {
        let ts = law.duration();
        match self.at {
            ScanAt::Grid(i) => {
                let t = if i >= c.samples { ts } else { ts * R::from_u16(i) / R::from_u16(c.samples) };
                let b = visit(&c.path, law, &c.arm, &c.lim, t, &mut self.peaks)?;
                if let Some(a) = self.prev {
                    branch_kept(&a, &b)?;
                }
                self.prev = Some(b);
                self.at = if i >= c.samples { ScanAt::Critical(0) } else { ScanAt::Grid(i + 1) };
            }
            ScanAt::Critical(crit) => {
                let t_c = match crit {
                    0 | 1 => c.path.critical_points().get(usize::from(crit)).map(|&s_c| time_of(law, s_c)),
                    // The ends: where the law starts and stops, its rate is
                    // small while a pose near the rim makes the joints'
                    // path rates large; their product peaks just inside.
                    2 => Some(R::ZERO),
                    3 => Some(ts),
                    _ => None,
                };
                self.at = match t_c {
                    Some(t_c) => ScanAt::Cluster { crit, t_c, off: ts * R::HALF, m: 3, late: false },
                    None => {
                        // The samples' largest rate, a floor for what the
                        // bounds are measured against.
                        self.f_max = stretch(&self.peaks, &c.lim).0;
                        self.f_max = self.f_max * self.f_max;
                        self.prev = None;
                        ScanAt::Bound { i: 0, j: 0, d: 0 }
                    }
                };
            }
            ScanAt::Cluster { crit, t_c, off, m, late } => {
                if m == 3 {
                    visit(&c.path, law, &c.arm, &c.lim, t_c, &mut self.peaks)?;
                    self.at = ScanAt::Cluster { crit, t_c, off, m: 4, late: false };
                } else if m > c.refine {
                    self.at = ScanAt::Critical(crit + 1);
                } else {
                    let t = if late { t_c + off } else { t_c - off };
                    if R::ZERO <= t && t <= ts {
                        visit(&c.path, law, &c.arm, &c.lim, t, &mut self.peaks)?;
                    }
                    self.at = if late {
                        // 2^(−1/4).
                        ScanAt::Cluster { crit, t_c, off: off * R::lit(0.840_896_415_253_714_5), m: m + 1, late: false }
                    } else {
                        ScanAt::Cluster { crit, t_c, off, m, late: true }
                    };
                }
            }
            ScanAt::Bound { i, j, d } => self.bound(c, law, i, j, d)?,
            ScanAt::Finished => return Ok(true),
        }
        Ok(self.at == ScanAt::Finished)
    }

    /// One unit of the bounds: the instant 0, or the far end of the stretch
    /// (i, j, d) and the stretch's bound, halving it instead when that
    /// bound is well above the largest rate so far.
    #[inline(never)] // avr-trap: frame-size
    fn bound(&mut self, c: &Checked<R>, law: &JointLaw<R>, i: u16, j: u16, d: u8) -> Result<(), PathError<R>> {
        let ts = law.duration();
        let Some(a) = self.prev else {
            self.prev = Some(visit(&c.path, law, &c.arm, &c.lim, R::ZERO, &mut self.peaks)?);
            return Ok(());
        };
        let t = if i + 1 >= c.samples && u32::from(j) + 1 >= 1u32 << d {
            ts
        } else {
            let frac = R::from_u16(j + 1) / R::from_u16(1u16 << d);
            ts * (R::from_u16(i) + frac) / R::from_u16(c.samples)
        };
        let b = visit(&c.path, law, &c.arm, &c.lim, t, &mut self.peaks)?;
        branch_kept(&a, &b)?;
        // Measured against rates the move has, never against bounds: each
        // accepted bound would let the next be a share looser.
        self.f_max = self.f_max.max(b.f);
        let bound = stretch_bound(c, law, &a, &b);
        let halve = match bound {
            None => true,
            Some((_, f_b)) => R::lit(BOUND_TOL) * self.f_max < f_b - self.f_max,
        };
        if halve && d < BOUND_DEPTH && self.halvings < HALVING_BUDGET {
            self.halvings += 1;
            self.at = ScanAt::Bound { i, j: j * 2, d: d + 1 };
            return Ok(());
        }
        let Some((rates, _)) = bound else {
            return Err(PathError::Singular { s: a.s });
        };
        for (k, (v, acc)) in rates.iter().enumerate() {
            self.peaks.speed[k] = self.peaks.speed[k].max(*v);
            self.peaks.accel[k] = self.peaks.accel[k].max(*acc);
        }

        self.prev = Some(b);
        // The next stretch: up while this one was a right half.
        let (mut j, mut d) = (j, d);
        while d > 0 && j % 2 == 1 {
            j /= 2;
            d -= 1;
        }
        self.at = if d == 0 {
            if i + 1 >= c.samples {
                ScanAt::Finished
            } else {
                ScanAt::Bound { i: i + 1, j: 0, d: 0 }
            }
        } else {
            ScanAt::Bound { i, j: j + 1, d }
        };
        Ok(())
    }
}

/// What a check holds beside the law it scans.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Checked<R> {
    path: Path<R>,
    arm: PathArm<R>,
    lim: PathLimits<R>,
    samples: u16,
    refine: u16,
    pace: Pace,
}

/// A path plan worked out a bounded amount at a time ([`PathCheck::step`]),
/// so a caller with a frame to keep (the chip) can spread it over frames;
/// [`PathPlan::new`] runs one to the end. The same result either way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathCheck<R> {
    c: Checked<R>,
    law: JointLaw<R>,
    kind: LawKind,
    scan: Scan<R>,
    /// Decided: `Ok` means the plan is the path, this law and the scan's
    /// peaks (not a copy of them: the chip keeps a check in its static RAM).
    outcome: Option<Result<(), PathError<R>>>,
}

impl<R: Real> PathCheck<R> {
    /// Checks the request's limits and law; the scan is to come.
    #[inline(never)] // reason: code-size
    pub fn new(req: &PathRequest<R>, arm: &PathArm<R>, lim: &PathLimits<R>) -> Result<Self, PathError<R>> {
        check_limits(lim)?;
        if req.samples < 2 {
            return Err(PathError::BadLimits);
        }
        let law = law_for(req.law, req.ts)?;
        let c =
            Checked { path: req.path, arm: *arm, lim: *lim, samples: req.samples, refine: req.refine, pace: req.pace };
        Ok(PathCheck { c, law, kind: req.law, scan: Scan::new(), outcome: None })
    }

    /// Does up to `units` units of work (a unit is one visit of the move,
    /// IK with rates, one search for a critical instant, or one stretch's
    /// visit and bound); the plan or the refusal once decided, and from
    /// then on.
    #[inline(never)] // reason: code-size
    pub fn step(&mut self, units: u16) -> Option<Result<PathPlan<R>, PathError<R>>> {
        for _ in 0..units {
            if self.outcome.is_some() {
                break;
            }
            match self.scan.step(&self.c, &self.law) {
                Ok(false) => {}
                Ok(true) => self.outcome = self.decide(),
                Err(e) => self.outcome = Some(Err(e)),
            }
        }
        self.outcome
            .map(|r| r.map(|()| PathPlan { path: self.c.path, law: self.law, arm: self.c.arm, peaks: self.scan.peaks }))
    }

    /// Stretches the scan has halved so far (at most [`HALVING_BUDGET`]).
    pub fn halvings(&self) -> u16 {
        self.scan.halvings
    }

    /// The next unit is at most one visit (a grid or refinement instant, or
    /// a step between the scan's phases), not a search for a critical
    /// instant nor a stretch's bound, which take about three times as long
    /// (BENCHMARKS.md, `path_visit_unit` against `path_check_unit` and
    /// `path_bound_unit`): a caller with a frame to keep can fit more of
    /// them in (`app::path_move`).
    pub fn next_is_visit(&self) -> bool {
        match self.scan.at {
            // The path's two critical points are searched for; the ends
            // and the step to the bounds are not.
            ScanAt::Critical(crit) => crit >= 2,
            ScanAt::Bound { .. } => false,
            ScanAt::Grid(_) | ScanAt::Cluster { .. } | ScanAt::Finished => true,
        }
    }

    /// After a complete scan: the plan at the asked duration, a refusal,
    /// or (slowing down) the plan at the shortest admissible duration. Not
    /// scanned again: the scan's grid, refinement and stretches sit at the
    /// same τ = t/tₛ for every tₛ, so its samples and bounds scale exactly
    /// as 1/tₛ and 1/tₛ² (and the angles do not change); `STRETCH_SLACK`
    /// covers the rounding. A second scan would double the check's time on
    /// the chip (issue #24, F4's bounds made a scan the longer part).
    fn decide(&mut self) -> Option<Result<(), PathError<R>>> {
        let (f, joint, accel) = stretch(&self.scan.peaks, &self.c.lim);
        if f <= R::ONE {
            return Some(Ok(()));
        }
        let ts = self.law.duration();
        let ts_min = ts * f;
        if self.c.pace == Pace::Refuse {
            return Some(Err(if accel {
                PathError::Accel { joint, ts_min }
            } else {
                PathError::Speed { joint, ts_min }
            }));
        }
        let ts_new = ts_min * (R::ONE + R::lit(STRETCH_SLACK));
        // ts is finite (from finite peaks and limits), as is ts_max.
        if self.c.lim.ts_max.lt_num(ts_new) {
            return Some(Err(PathError::TooSlow { ts_min }));
        }
        match law_for(self.kind, ts_new) {
            Ok(law) => {
                self.law = law;
                let k = ts / ts_new;
                let p = &mut self.scan.peaks;
                for j in 0..JOINTS {
                    p.speed[j] *= k;
                    p.accel[j] *= k * k;
                }
                Some(Ok(()))
            }
            Err(e) => Some(Err(e)),
        }
    }
}

/// The factor by which the move must be lengthened (≤ 1: it fits), and the
/// joint and kind (`true` = acceleration) that bind.
fn stretch<R: Real>(peaks: &PathPeaks<R>, lim: &PathLimits<R>) -> (R, u8, bool) {
    let mut worst = (R::ZERO, 0u8, false);
    for j in 0..JOINTS {
        let fv = peaks.speed[j] / lim.speed[j];
        let fa = (peaks.accel[j] / lim.accel[j]).sqrt();
        if worst.0 < fv {
            worst = (fv, j as u8, false);
        }
        if worst.0 < fa {
            worst = (fa, j as u8, true);
        }
    }
    worst
}

/// Rounding allowance of a slowed-down move, whose peaks scale exactly in
/// exact arithmetic: well above the f32 rounding of the scan's dozens of
/// operations per bound.
const STRETCH_SLACK: f64 = 1e-4;

/// The joint angles at time t: the law's g, the path's point, the IK; the
/// per-frame work of a path move (no derivatives).
#[inline]
pub fn path_angles<R: Real>(path: &Path<R>, law: &JointLaw<R>, arm: &PathArm<R>, t: R) -> Result<Vec3<R>, IkError<R>> {
    let p = path.point(law.g(t));
    let q = ik3(&arm.links, p[0], p[1], p[2], arm.branch)?;
    Ok([q.th1, q.th2, q.th3])
}

impl<R: Real> PathPlan<R> {
    /// Plans a path move: checks the path, scans it at the asked duration
    /// and refuses or slows down (never clamps) where a joint's speed or
    /// acceleration would exceed its limit. The linear law steps its velocity
    /// at both ends: like a joint move by it, it honours the speed only
    /// between the steps.
    pub fn new(req: &PathRequest<R>, arm: &PathArm<R>, lim: &PathLimits<R>) -> Result<Self, PathError<R>> {
        let mut check = PathCheck::new(req, arm, lim)?;
        loop {
            if let Some(r) = check.step(u16::MAX) {
                return r;
            }
        }
    }

    /// Duration, s (longer than asked after a slow-down).
    #[inline]
    pub fn ts(&self) -> R {
        self.law.duration()
    }

    /// The path.
    #[inline]
    pub fn path(&self) -> &Path<R> {
        &self.path
    }

    /// The pacing profile.
    #[inline]
    pub fn law(&self) -> &JointLaw<R> {
        &self.law
    }

    /// Bounds of the joints' speeds and accelerations over the whole move
    /// (the plan's scan and the bounds between its points).
    #[inline]
    pub fn peaks(&self) -> &PathPeaks<R> {
        &self.peaks
    }

    /// Joint angles at time t ([`path_angles`]).
    pub fn angles(&self, t: R) -> Result<Vec3<R>, IkError<R>> {
        path_angles(&self.path, &self.law, &self.arm, t)
    }

    /// Effector and joints at time t (held at the ends outside [0, tₛ]).
    pub fn state(&self, t: R) -> Result<PathState<R>, PathError<R>> {
        let g = self.law.g_derivs(t);
        let pj = self.path.jet(g.s);
        let jj: JointJet<R> = ik_jet(&self.arm.links, self.arm.branch, &pj).map_err(|e| jet_err(e, g.s))?;
        let mut dq = [R::ZERO; JOINTS];
        let mut ddq = [R::ZERO; JOINTS];
        for j in 0..JOINTS {
            dq[j] = jj.dq[j] * g.v;
            ddq[j] = jj.ddq[j] * g.v * g.v + jj.dq[j] * g.acc;
        }
        Ok(PathState { s: g.s, p: pj.p, q: jj.q, dq, ddq })
    }
}
