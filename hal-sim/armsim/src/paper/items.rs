//! The items of `armsim paper`: each one's stated inputs, computed through
//! the core's plans, with the formula and correction behind every value.

use touch_arm::motion::via::{c2_ln_base, iterate_paper, smooth_via_a, ViaParams, ViaPlan};
use touch_arm::motion::zat::{smooth_stop_a, u_min, Shape, ShapeParams, ZatParams, ZatPlan};
use touch_arm::motion::{Sample, TrajError};

use super::poly::{max_on, poly_derivs, via_poly};
use super::{Figure, Item, Quantity, Val};
use crate::opts::{LawKindArg, Times};
use crate::path::{path_plan, PathCircle, PathCommon, PathKind, PathLine};

/// Every item: id and one-line description (`armsim paper list`).
pub const ITEMS: [(&str, &str); 12] = [
    ("p1-ex1", "paper 1, Figure 2: q0 = 0.45 -> S_f = 0.8 in ts = 4 s, a = 0, n = 2 and n = 12"),
    ("p1-ex2", "paper 1, Figure 3: the falling move q0 = 0.65 -> S_f = -0.85 in ts = 1 s, a = 0, n = 2"),
    ("p1-fig4", "paper 1, Figure 4: ts = 1 s, n = 2, 0 -> 1, a = 0, 0.5, 0.9, 0.99 (a approaching ts)"),
    ("p1-fig5", "paper 1, Figure 5: ts = 5 s, n = 2, 0 -> 1, a = 0, 1, 2, 3, 4 (which shapes are monotone)"),
    ("p2-fig2", "paper 2, Figure 2: -12 -> 5 at tv = 1.5 -> 30, nv = 2, av = 0.05, n = 2.5, a = -1.4"),
    ("p2-fig3", "paper 2, Figure 3: as p2-fig2 with av = 1.2481, a = 1.8"),
    ("p2-fig4", "paper 2, Figure 4: 10 -> 25 at tv = 2.6 -> 62, nv = 1.7, av = 0.05, n = 1.8, a = 1.2"),
    ("p2-fig6", "paper 2, Figure 6: 10 -> 25 at tv = 2.6 -> 62, nv = 125, av = -100, n = 70, a = 2.2"),
    ("p2-williams-c1", "paper 2, Williams case 1: 30 -> 180 at tv = 1.5 -> 120, nv = 1.91, av = 0.8734, n = 81.7467, a = 2.4, and Williams' 6th-order polynomial"),
    ("p2-williams-c2", "paper 2, Williams case 2: 30 -> 180 at tv = 1.5 -> 120, nv = 5, av = 0.5865, n = 5, a = 1.95, and Williams' 6th-order polynomial"),
    ("lab-line", "lab note: the straight line (1, 0.3, 0.2) -> (-0.4, 0.9, 0.7) in 3 s, quintic law, 3-DoF arm l2 = l3 = 1"),
    ("lab-circle", "lab note: the circle around (0.8, 0.6, 0.4), r = 0.2, in 4 s, quintic law, 3-DoF arm l2 = l3 = 1"),
];

/// The paper's iteration stops at the first |ΔS_v| = |S_v,i+1 − S_v,i| below
/// this (|ΔS_v| is the via error |e_i| exactly: S_v,i+1 − S_v,i = −e_i).
pub const VIA_TOL: f64 = 1e-9;

/// Generous: with r < 1 the error shrinks by r per step.
const MAX_ITER: u16 = 10_000;

/// Samples per curve in figures and CSV.
const SAMPLES: usize = 601;

const ZETA: &str = "ζ = tₛ − log_n(|S_f − q₀|·(n^tₛ − n^a)), as −ln(|Δ|·(1 − n^(a−tₛ)))/ln n";
const END: &str = "S(tₛ) = q₀ + Δ·G(tₛ), G(tₛ) = 1 (eq. 13 normalized)";
const EQ13: &str = "eq-13-the-position-formula";
const FALLING: &str = "eqs-14-and-15-velocity-and-acceleration-of-a-falling-move";
const END_EXACT: &str = "the-trajectory-reaches-the-end-point-exactly";
const ADMISSIBLE: &str = "the-admissible-shapes-a--tₛ";
const PROP1: &str = "proposition-1-the-iteration-always-converges";
const OMISSIONS: &str = "not-corrections-but-omissions-that-matter";
const IK3: &str = "the-distance-in-the-3-dof-ik";
const QUINTIC: &str = "quintic-acceleration";

/// Computes the item `id`.
pub fn compute(id: &str) -> Result<Item, String> {
    let (id, about) = *ITEMS
        .iter()
        .find(|(i, _)| *i == id)
        .ok_or_else(|| format!("no item {id:?} (armsim paper list names them)"))?;
    let mut item = match id {
        "p1-ex1" => p1_ex1()?,
        "p1-ex2" => p1_ex2()?,
        "p1-fig4" => p1_fig4()?,
        "p1-fig5" => p1_fig5()?,
        "p2-fig2" => via_item(&via(-12.0, 5.0, 30.0, 1.5, 2.0, 0.05, 2.5, -1.4), None)?,
        "p2-fig3" => via_item(&via(-12.0, 5.0, 30.0, 1.5, 2.0, 1.2481, 2.5, 1.8), None)?,
        "p2-fig4" => via_item(&via(10.0, 25.0, 62.0, 2.6, 1.7, 0.05, 1.8, 1.2), None)?,
        "p2-fig6" => via_item(&via(10.0, 25.0, 62.0, 2.6, 125.0, -100.0, 70.0, 2.2), None)?,
        "p2-williams-c1" => via_item(&via(30.0, 180.0, 120.0, 1.5, 1.91, 0.8734, 81.7467, 2.4), Some(1))?,
        "p2-williams-c2" => via_item(&via(30.0, 180.0, 120.0, 1.5, 5.0, 0.5865, 5.0, 1.95), Some(2))?,
        "lab-line" => lab(line())?,
        "lab-circle" => lab(circle())?,
        _ => unreachable!("every id of ITEMS has its computation"),
    };
    item.id = id;
    item.about = about;
    Ok(item)
}

fn q(key: &'static str, value: Val, formula: &'static str, correction: Option<&'static str>) -> Quantity {
    Quantity { key, value, formula, correction }
}

fn blank(inputs: Vec<(&'static str, Val)>, values: Vec<Quantity>, notes: Vec<String>, figure: Figure) -> Item {
    Item { id: "", about: "", inputs, values, notes, figure }
}

fn zat(q0: f64, sf: f64, ts: f64, a: f64, n: f64) -> Result<ZatPlan<f64>, String> {
    ZatPlan::new(&ZatParams { q0, sf, ts, a, n }).map_err(|e| format!("ts = {ts}, a = {a}, n = {n}: {e}"))
}

/// `SAMPLES` even times over [0, ts].
fn times(ts: f64) -> Vec<f64> {
    (0..SAMPLES).map(|i| ts * i as f64 / (SAMPLES - 1) as f64).collect()
}

fn samples(t: &[f64], f: impl Fn(f64) -> Sample<f64>) -> Vec<Sample<f64>> {
    t.iter().map(|&t| f(t)).collect()
}

/// The note on a plan's end velocity (the papers' "exact end").
fn end_note(label: &str, plan: &ZatPlan<f64>) -> String {
    format!(
        "{label}: the move ends exactly on S_f, but with velocity S'(ts-) = {} (zero only for the smooth stop \
         a* = ts - log_n ts): the papers' exact end holds for position only (docs/corrections.md#{END_EXACT})",
        plan.end_velocity()
    )
}

fn p1_ex1() -> Result<Item, String> {
    let (q0, sf, ts, a) = (0.45, 0.8, 4.0, 0.0);
    let (p2, p12) = (zat(q0, sf, ts, a, 2.0)?, zat(q0, sf, ts, a, 12.0)?);
    let zeta = |p: &ZatPlan<f64>| Val::Num(p.zeta().unwrap_or(f64::NAN));
    let mut notes = vec![end_note("n = 2", &p2), end_note("n = 12", &p12)];
    for (n, p) in [(2, &p2), (12, &p12)] {
        if !p.shape().is_monotone() {
            notes.push(format!(
                "n = {n}: the shape is not monotone, G peaks at {} (overshoot; docs/corrections.md#{OMISSIONS})",
                p.shape().peak()
            ));
        }
    }
    let t = times(ts);
    Ok(blank(
        vec![
            ("q0", Val::Num(q0)),
            ("sf", Val::Num(sf)),
            ("ts", Val::Num(ts)),
            ("a", Val::Num(a)),
            ("n", Val::Arr(vec![2.0, 12.0])),
        ],
        vec![
            q("zeta_n2", zeta(&p2), ZETA, None),
            q("zeta_n12", zeta(&p12), ZETA, None),
            q("end_n2", Val::Num(p2.position(ts)), END, Some(EQ13)),
            q("end_n12", Val::Num(p12.position(ts)), END, Some(EQ13)),
        ],
        notes,
        Figure::Series {
            title: format!("paper 1, Fig. 2: q0 = {q0} -> Sf = {sf}, ts = {ts}, a = {a}"),
            curves: vec![("n2".into(), samples(&t, |t| p2.sample(t))), ("n12".into(), samples(&t, |t| p12.sample(t)))],
            t,
            shown: 3,
        },
    ))
}

fn p1_ex2() -> Result<Item, String> {
    let (q0, sf, ts, a, n) = (0.65, -0.85, 1.0, 0.0, 2.0);
    let p = zat(q0, sf, ts, a, n)?;
    let notes = vec![
        end_note("the falling move", &p),
        format!(
            "falling move: velocity and acceleration are Δ·G', Δ·G'' with Δ = {} signed, the printed eqs. 14-15 \
             negated (docs/corrections.md#{FALLING})",
            sf - q0
        ),
    ];
    let t = times(ts);
    Ok(blank(
        vec![("q0", Val::Num(q0)), ("sf", Val::Num(sf)), ("ts", Val::Num(ts)), ("a", Val::Num(a)), ("n", Val::Num(n))],
        vec![
            q("zeta", Val::Num(p.zeta().unwrap_or(f64::NAN)), ZETA, None),
            q("end", Val::Num(p.position(ts)), END, Some(EQ13)),
        ],
        notes,
        Figure::Series {
            title: format!("paper 1, Fig. 3: q0 = {q0} -> Sf = {sf}, ts = {ts}, a = {a}, n = {n}"),
            curves: vec![("falling".into(), samples(&t, |t| p.sample(t)))],
            t,
            shown: 3,
        },
    ))
}

/// Largest velocity of a plan over [0, tₛ] and where (the left limit at tₛ).
pub(crate) fn peak_velocity(plan: &ZatPlan<f64>) -> (f64, f64) {
    let ts = plan.shape().ts();
    max_on(|t| plan.sample(t).v, 0.0, ts, 4000)
}

fn p1_fig4() -> Result<Item, String> {
    let (q0, sf, ts, n) = (0.0, 1.0, 1.0, 2.0);
    const AS: [(f64, &str, &str); 4] = [
        (0.0, "a0", "peak_velocity_a0"),
        (0.5, "a0.5", "peak_velocity_a0.5"),
        (0.9, "a0.9", "peak_velocity_a0.9"),
        (0.99, "a0.99", "peak_velocity_a0.99"),
    ];
    let t = times(ts);
    let (mut values, mut curves, mut notes) = (vec![], vec![], vec![]);
    for (a, label, key) in AS {
        let p = zat(q0, sf, ts, a, n)?;
        let (tp, vp) = peak_velocity(&p);
        values.push(q(key, Val::Num(vp), "max over [0, tₛ] of Δ·G'(t), G' = G·L·(1 − u'·(1 + q))", Some(END_EXACT)));
        notes.push(format!("a = {a}: peak velocity {vp} at t = {tp}; end velocity {}", p.end_velocity()));
        curves.push((label.to_string(), samples(&t, |t| p.sample(t))));
    }
    notes.push(format!(
        "ts = 1: u'(ts) = 0, so every shape ends with velocity L·Δ = ln 2 = {}, whatever a is: no smooth stop exists \
         for ts <= 1 (docs/corrections.md#{END_EXACT}); for ts <= 1 the papers' a < ts is the exact admissible domain",
        2f64.ln()
    ));
    Ok(blank(
        vec![
            ("q0", Val::Num(q0)),
            ("sf", Val::Num(sf)),
            ("ts", Val::Num(ts)),
            ("n", Val::Num(n)),
            ("a", Val::Arr(AS.iter().map(|x| x.0).collect())),
        ],
        values,
        notes,
        Figure::Series { title: "paper 1, Fig. 4: ts = 1, n = 2, a -> ts".into(), t, curves, shown: 3 },
    ))
}

fn p1_fig5() -> Result<Item, String> {
    let (q0, sf, ts, n) = (0.0, 1.0, 5.0, 2.0);
    const KEYS: [&str; 5] = ["monotone_a0", "monotone_a1", "monotone_a2", "monotone_a3", "monotone_a4"];
    let t = times(ts);
    let (mut values, mut curves, mut notes) = (vec![], vec![], vec![]);
    let um = u_min(ts);
    for (i, key) in KEYS.iter().enumerate() {
        let a = i as f64;
        let mono = match Shape::new(&ShapeParams { ts, a, n }) {
            Ok(shape) => {
                let p = zat(q0, sf, ts, a, n)?;
                if !shape.is_monotone() {
                    notes.push(format!(
                        "a = {a}: admissible but not monotone, G peaks at {} (docs/corrections.md#{OMISSIONS})",
                        shape.peak()
                    ));
                }
                curves.push((format!("a{i}"), samples(&t, |t| p.sample(t))));
                shape.is_monotone()
            }
            Err(_) => {
                // u(t) = a ⇔ t² − (a + 1)·t + tₛ = 0: the poles inside the move.
                let disc = ((a + 1.0) * (a + 1.0) - 4.0 * ts).sqrt();
                notes.push(format!(
                    "a = {a}: satisfies the paper's a < ts = {ts} but not a < u_min = 2*sqrt(ts) - 1 = {um}: the \
                     denominator vanishes at t = {} and t = {} inside the move, so the printed figure's curve for a = {a} \
                     cannot come from the stated inputs; not drawn (docs/corrections.md#{ADMISSIBLE})",
                    (a + 1.0 - disc) / 2.0,
                    (a + 1.0 + disc) / 2.0
                ));
                false
            }
        };
        values.push(q(
            key,
            Val::Bool(mono),
            "a < u_min = 2√tₛ − 1 and min φ ≥ 0 on [√tₛ, tₛ] (method §7.5, §7.7)",
            Some(ADMISSIBLE),
        ));
    }
    Ok(blank(
        vec![
            ("q0", Val::Num(q0)),
            ("sf", Val::Num(sf)),
            ("ts", Val::Num(ts)),
            ("n", Val::Num(n)),
            ("a", Val::Arr(vec![0.0, 1.0, 2.0, 3.0, 4.0])),
        ],
        values,
        notes,
        Figure::Series {
            title: "paper 1, Fig. 5: ts = 5, n = 2, a = 0..3 (a = 4 has a pole)".into(),
            t,
            curves,
            shown: 3,
        },
    ))
}

/// The via-point paper's inputs, all with tₛ = 3 s.
#[allow(clippy::too_many_arguments)]
fn via(q0: f64, theta_v: f64, sf: f64, tv: f64, nv: f64, av: f64, n: f64, a: f64) -> ViaParams<f64> {
    ViaParams { q0, theta_v, sf, tv, ts: 3.0, a, n, av, nv }
}

/// The `p2-*` items' computation for any via-point inputs (id and
/// description left empty): S_v, ζ, ζ_v, r, the paper's iteration (`null`
/// when it diverges) and the jumps at t_v.
pub fn via_values(p: &ViaParams<f64>) -> Result<Item, String> {
    via_item(p, None)
}

/// A `p2-*` item; `williams` is the continuity the case's name claims
/// (1: velocity, 2: velocity and acceleration), which adds the polynomial.
fn via_item(p: &ViaParams<f64>, williams: Option<u8>) -> Result<Item, String> {
    let plan = ViaPlan::new(p).map_err(|e| e.to_string())?;
    let (sv, r, jumps) = (plan.sv(), plan.r(), plan.jumps());
    let mut notes = vec![];
    let iterations = match iterate_paper(p, VIA_TOL, MAX_ITER) {
        Ok(it) => {
            notes.push(format!(
                "the paper's iteration from S_v = theta_v = {}: {} steps to S_v = {} (closed form {sv}; the error \
                 shrinks by r = {r} per step)",
                p.theta_v, it.iterations, it.sv
            ));
            Val::Int(it.iterations.into())
        }
        Err(TrajError::ViaDiverges { r }) => {
            notes.push(format!(
                "r = G(tv) = {r} >= 1: the paper's iteration diverges (each step multiplies the distance to S_v by r), \
                 against its Proposition 1; iterations = null, the closed form still gives S_v = {sv} \
                 (docs/corrections.md#{PROP1})"
            ));
            Val::Null
        }
        Err(TrajError::NoConvergence) => {
            notes.push(format!(
                "the paper's iteration did not converge in {MAX_ITER} steps (r = {r}); iterations = null"
            ));
            Val::Null
        }
        Err(e) => return Err(format!("paper iteration: {e}")),
    };
    let ve = plan.end_velocity();
    if ve.abs() > 1e-9 * (p.sf - sv).abs() {
        notes.push(format!(
            "the move ends exactly on S_f but with velocity S'(ts-) = {ve} (the main shape's a = {} is not its smooth \
             stop a* = {}): the exact end holds for position only (docs/corrections.md#{END_EXACT})",
            p.a,
            smooth_stop_a(p.ts, p.n).map_or("none (not admissible)".into(), |a| a.to_string())
        ));
    }
    let main = plan.main_shape();
    if !main.is_monotone() {
        notes.push(format!(
            "the main shape (ts = {}, a = {}, n = {}) is not monotone: G peaks at {} (docs/corrections.md#{OMISSIONS})",
            p.ts,
            p.a,
            p.n,
            main.peak()
        ));
    }
    let (lo, hi) = (-max_on(|t| -plan.position(t), 0.0, p.ts, 4000).1, max_on(|t| plan.position(t), 0.0, p.ts, 4000).1);
    let amplify = 1.0 / (1.0 - r);
    if amplify > 10.0 {
        notes.push(format!(
            "r = {r} is close to 1: the closed form amplifies by 1/(1 - r) = {amplify}, S_v = {sv}, and the trajectory \
             computed from the stated inputs ranges over [{lo}, {hi}], far outside [q0, S_f]: a printed figure that stays \
             between the ends cannot come from these inputs"
        ));
    } else {
        notes.push(format!("the trajectory ranges over [{lo}, {hi}] on [0, ts]"));
    }
    let c1 = smooth_via_a(p.tv, p.nv);
    let c2 = c2_ln_base(p.tv).map(|l| l.exp());
    let c2_a = c2.and_then(|nv| smooth_via_a(p.tv, nv));
    notes.push(format!(
        "at tv: velocity jumps by {}, acceleration by {}, jerk by {}; the smooth stop of the via segment (c1) for \
         n_v = {} is a_v = {} (given {}); c2 needs n_v = e^(2/(tv - 1)) = {} with a_v = {}",
        jumps.v,
        jumps.acc,
        jumps.jerk,
        p.nv,
        c1.map_or("none (not admissible)".into(), |a| a.to_string()),
        p.av,
        c2.map_or("none (tv <= 1)".into(), |n| n.to_string()),
        c2_a.map_or("none".into(), |a| a.to_string()),
    ));
    // A printed a_v that is another whole base's smooth stop, to its printed
    // digits, hints at a base other than the stated one: say so, compute
    // with the stated one.
    let off_c1 = c1.is_none_or(|a| (a - p.av).abs() > 5e-5);
    if let Some(k) = (2..=10)
        .map(f64::from)
        .filter(|&k| k != p.nv)
        .find(|&k| off_c1 && smooth_via_a(p.tv, k).is_some_and(|a| (a - p.av).abs() <= 5e-5))
    {
        notes.push(format!(
            "a_v = {} is, to its printed digits, the smooth stop of n_v = {k} at tv = {} ({}), not of the stated \
             n_v = {}: computed with the stated n_v, the velocity jumps by {} at tv",
            p.av,
            p.tv,
            smooth_via_a(p.tv, k).unwrap_or(f64::NAN),
            p.nv,
            jumps.v
        ));
    }
    if let Some(c) = williams {
        let scale = (sv - p.q0).abs();
        let (v_small, a_small) = (jumps.v.abs() <= 1e-3 * scale, jumps.acc.abs() <= 1e-3 * scale);
        let claim = if c == 1 { "continuous velocity" } else { "continuous velocity and acceleration" };
        let holds = if c == 1 { v_small } else { v_small && a_small };
        notes.push(if holds {
            format!("case {c} claims {claim}: it holds to the printed digits of a_v (jumps above)")
        } else {
            format!(
                "case {c} claims {claim}, but the stated inputs give a velocity jump of {} and an acceleration jump of {} \
                 at tv: computed from the stated inputs, not tuned",
                jumps.v, jumps.acc
            )
        });
    }
    let mut values = vec![
        q("S_v", Val::Num(sv), "S_v* = (θ_v − r·S_f)/(1 − r)", Some(PROP1)),
        q("zeta", Val::Num(plan.zeta().unwrap_or(f64::NAN)), "ζ = tₛ − log_n(|S_f − S_v|·(n^tₛ − n^a))", None),
        q(
            "zeta_v",
            Val::Num(plan.zeta_v().unwrap_or(f64::NAN)),
            "ζ_v = t_v − log_n_v(|S_v − q₀|·(n_v^t_v − n_v^a_v))",
            None,
        ),
        q("r", Val::Num(r), "r = G(t_v) = n^(1 − tₛ/t_v)·(1 + q(t_v))/(1 + q(tₛ))", None),
        q(
            "iterations",
            iterations,
            "S_v,i+1 = θ_v − σ_i·M_i(t_v) from S_v,0 = θ_v until |ΔS_v| < 1e-9 (null: diverges)",
            Some(PROP1),
        ),
        q("jump_v", Val::Num(jumps.v), "−(S_v − q₀)·G_v'(t_v⁻)", None),
        q("jump_a", Val::Num(jumps.acc), "−(S_v − q₀)·G_v''(t_v⁻)", None),
        q("jump_j", Val::Num(jumps.jerk), "−(S_v − q₀)·G_v'''(t_v⁻)", None),
    ];
    let t = times(p.ts);
    let mut curves = vec![("zat_via".to_string(), samples(&t, |t| plan.sample(t)))];
    if williams.is_some() {
        let c = via_poly(p.q0, p.theta_v, p.sf, p.tv, p.ts).ok_or("via time outside (0, ts)")?;
        let (tm, m) = max_on(|t| poly_derivs(&c, t)[0], 0.0, p.ts, 4000);
        values.push(q(
            "poly",
            Val::Arr(c.to_vec()),
            "Williams 2013: θ = q₀ + Δ(10τ³ − 15τ⁴ + 6τ⁵) + c·τ³(1 − τ)³, τ = t/tₛ, as c₀..c₆ of t⁰..t⁶",
            None,
        ));
        values.push(q("poly_max", Val::Num(m), "max of θ(t) on [0, tₛ]", None));
        values.push(q("poly_max_t", Val::Num(tm), "argmax of θ(t) on [0, tₛ]", None));
        notes.push(format!(
            "Williams' polynomial peaks at {m} at t = {tm}; the via-point trajectory's largest value is {}",
            max_on(|t| plan.position(t), 0.0, p.ts, 4000).1
        ));
        let at = |t: f64| {
            let d = poly_derivs(&c, t);
            Sample { s: d[0], v: d[1], acc: d[2], jerk: d[3] }
        };
        curves.push(("poly6".to_string(), samples(&t, at)));
    }
    Ok(blank(
        vec![
            ("q0", Val::Num(p.q0)),
            ("theta_v", Val::Num(p.theta_v)),
            ("sf", Val::Num(p.sf)),
            ("ts", Val::Num(p.ts)),
            ("tv", Val::Num(p.tv)),
            ("n_v", Val::Num(p.nv)),
            ("a_v", Val::Num(p.av)),
            ("n", Val::Num(p.n)),
            ("a", Val::Num(p.a)),
        ],
        values,
        notes,
        Figure::Series {
            title: format!(
                "via point: q0 = {} -> {} at tv = {} -> Sf = {} (S_v = {sv:.6})",
                p.q0, p.theta_v, p.tv, p.sf
            ),
            t,
            curves,
            shown: 4,
        },
    ))
}

fn common(ts: f64) -> PathCommon {
    PathCommon {
        ts,
        law: LawKindArg::Quintic,
        slow_down: false,
        max_speed: None,
        max_accel: None,
        l2: 1.0,
        l3: 1.0,
        times: Times { t: None, samples: Some(SAMPLES) },
        info: false,
    }
}

/// The lab note's straight-line task, our choice of segment: from the front
/// right, reaching up and across to the left (both ends inside the servo
/// defaults' ranges, elbow up).
fn line() -> PathKind {
    PathKind::Line(PathLine { from: [1.0, 0.3, 0.2], to: [-0.4, 0.9, 0.7], common: common(3.0) })
}

/// The lab note's circle task, our choice: radius 0.2 around (0.8, 0.6, 0.4)
/// in the arm's vertical plane.
fn circle() -> PathKind {
    PathKind::Circle(PathCircle { center: [0.8, 0.6, 0.4], radius: 0.2, common: common(4.0) })
}

fn lab(kind: PathKind) -> Result<Item, String> {
    let plan = path_plan(&kind)?;
    let ts = plan.ts();
    let q_at = |t: f64| plan.state(t).map(|s| s.q.to_vec()).map_err(|e| e.to_string());
    let (start, end) = (q_at(0.0)?, q_at(ts)?);
    let peaks = plan.peaks();
    let mut inputs = match &kind {
        PathKind::Line(l) => {
            vec![("path", Val::Str("line")), ("from", Val::Arr(l.from.to_vec())), ("to", Val::Arr(l.to.to_vec()))]
        }
        PathKind::Circle(c) => {
            vec![("path", Val::Str("circle")), ("center", Val::Arr(c.center.to_vec())), ("radius", Val::Num(c.radius))]
        }
    };
    inputs.extend([("ts", Val::Num(ts)), ("law", Val::Str("quintic")), ("l2", Val::Num(1.0)), ("l3", Val::Num(1.0))]);
    let ik = "ik3: θ₁ = atan2(y, x), planar IK on (√(x² + y²), z), elbow up";
    let notes = vec![format!(
        "segment and circle are this project's choice (the note's tasks give no numbers we could use); the plan checks \
         every scan point reachable and inside the servo defaults' angle, speed and acceleration limits (`armsim path`)"
    )];
    Ok(blank(
        inputs,
        vec![
            q("ts", Val::Num(ts), "tₛ as asked, admissible under the servo defaults' limits", None),
            q("start_angles", Val::Arr(start), ik, Some(IK3)),
            q("end_angles", Val::Arr(end), ik, Some(IK3)),
            q("peak_speed", Val::Arr(peaks.speed.to_vec()), "max |θ̇_j| on the plan's scan, θ̇ = θ'(s)·ġ", None),
            q(
                "peak_accel",
                Val::Arr(peaks.accel.to_vec()),
                "max |θ̈_j| on the plan's scan, θ̈ = θ''(s)·ġ² + θ'(s)·g̈ (quintic g)",
                Some(QUINTIC),
            ),
        ],
        notes,
        Figure::Path(kind),
    ))
}
