//! Every number `armsim` prints reads back as the f64 it computed, bit for
//! bit: powers of two of every exponent and their neighbours (where decimal
//! rounding is most fragile: the spacing halves below them) and random doubles,
//! through each JSON and CSV output. Echoed inputs are compared with the input,
//! computed values with the same computation done here through the core crate.

use std::f64::consts::PI;

use armsim::cli::{run, Cli};
use clap::Parser;
use serde_json::Value;
use touch_arm::geometry::ik::{base_angle, ik2, ik3, Branch, IkError, Links};
use touch_arm::geometry::pose::{pose_for_point, ArmGeometry, PoseError};
use touch_arm::geometry::workspace::WorkspacePoint;
use touch_arm::motion::laws::{Law, LawParams, LawPlan};
use touch_arm::motion::via::{ViaParams, ViaPlan};
use touch_arm::motion::zat::{smooth_stop_a, u_min, zeta, ZatParams, ZatPlan};
use touch_arm::motion::Sample;
use touch_arm::servo::map::ELBOW_BRANCH;

/// 2^e for every exponent, subnormals included, and the doubles either side.
fn powers_of_two() -> Vec<f64> {
    let mut v = Vec::new();
    for e in -1074i32..=1023 {
        let bits = if e >= -1022 { ((e + 1023) as u64) << 52 } else { 1u64 << (e + 1074) };
        v.extend([bits - 1, bits, bits + 1].map(f64::from_bits).into_iter().filter(|x| x.is_finite() && *x > 0.0));
    }
    v
}

/// Finite doubles with uniformly random bits (every exponent equally likely).
fn random_doubles(n: usize, seed: u64) -> Vec<f64> {
    let mut state = seed;
    let mut next = move || {
        // splitmix64
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    std::iter::repeat_with(|| f64::from_bits(next())).filter(|x| x.is_finite()).take(n).collect()
}

/// Random doubles in [0, 1) with all 52 fraction bits in play.
fn random_unit(n: usize, seed: u64) -> Vec<f64> {
    random_doubles(n, seed).iter().map(|x| f64::from_bits(x.to_bits() >> 12 | 0x3FF0_0000_0000_0000) - 1.0).collect()
}

/// An argument that reads back as `v` exactly (Rust's shortest round trip).
fn arg(v: f64) -> String {
    format!("{v:e}")
}

/// What `armsim ARGS` prints (the binary prints `run`'s text as it is).
fn try_armsim(args: &[String]) -> Result<String, String> {
    let cli = Cli::try_parse_from(std::iter::once("armsim".to_string()).chain(args.iter().cloned()))
        .unwrap_or_else(|e| panic!("armsim {args:?}: {e}"));
    run(&cli)
}

fn armsim(args: &[String]) -> String {
    try_armsim(args).unwrap_or_else(|e| panic!("armsim {args:?}: {e}"))
}

/// The joint angles the IK reports: none out of reach, and at the singular
/// point (the shoulder, or a target so close that r² underflows) the folded
/// elbow without q2: q3 = −π on the firmware's branch (minus, armsim's
/// default), +π on the plus branch.
fn reported(r: Result<(f64, f64), IkError<f64>>) -> (Option<f64>, Option<f64>) {
    let folded = if ELBOW_BRANCH == Branch::Minus { -PI } else { PI };
    match r {
        Ok((q2, q3)) => (Some(q2), Some(q3)),
        Err(IkError::Singular) => (None, Some(folded)),
        Err(_) => (None, None),
    }
}

fn strs(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// `printed` (a CSV cell or a JSON value) is what a non-finite `expect`
/// becomes, or reads back as `expect` bit for bit.
fn same(printed: &str, expect: Option<f64>, ctx: &str) {
    match expect.filter(|v| v.is_finite()) {
        None => assert!(printed.is_empty() || printed == "null", "{ctx}: {printed:?} for {expect:?}"),
        Some(v) => {
            let got: f64 = printed.parse().unwrap_or_else(|_| panic!("{ctx}: {printed:?} is not a number"));
            assert_eq!(got.to_bits(), v.to_bits(), "{ctx}: {printed} reads back as {got:e}, not {v:e}");
        }
    }
}

/// A JSON object's fields as printed, checked against the expected values;
/// also a real JSON parser (serde_json, exact float parsing) must agree.
fn check_json(out: &str, expect: &[(&str, Option<f64>)], ctx: &str) {
    let parsed: Value = serde_json::from_str(out).unwrap_or_else(|e| panic!("{ctx}: bad JSON {out:?}: {e}"));
    for &(key, v) in expect {
        let token = out
            .split(&format!("\"{key}\": "))
            .nth(1)
            .and_then(|rest| rest.split([',', '}']).next())
            .unwrap_or_else(|| panic!("{ctx}: no {key} in {out}"));
        same(token, v, &format!("{ctx}: {key}"));
        match v.filter(|v| v.is_finite()) {
            Some(v) => assert_eq!(parsed[key].as_f64().map(f64::to_bits), Some(v.to_bits()), "{ctx}: {key}"),
            None => assert!(parsed[key].is_null(), "{ctx}: {key}"),
        }
    }
}

/// CSV output: the header, then one row per time with `t` echoed and the
/// rest equal to `sample(t)`.
fn check_csv(out: &str, header: &str, times: &[f64], sample: impl Fn(f64) -> Vec<f64>, ctx: &str) {
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some(header), "{ctx}");
    let mut n = 0;
    for (line, &t) in lines.zip(times) {
        let cells: Vec<&str> = line.split(',').collect();
        let expect: Vec<f64> = std::iter::once(t).chain(sample(t)).collect();
        assert_eq!(cells.len(), expect.len(), "{ctx}: {line}");
        for (c, v) in cells.iter().zip(expect) {
            same(c, Some(v), &format!("{ctx} at t = {t:e}"));
        }
        n += 1;
    }
    assert_eq!(n, times.len(), "{ctx}: one row per time");
}

/// Every evaluation time the CSV tests use: the fragile values (held before
/// 0 or after the end, so echoed and constant) and random times inside the
/// motion (so every column varies).
fn times(end: f64) -> Vec<f64> {
    let mut t = powers_of_two();
    t.extend(t.clone().iter().map(|x| -x));
    t.extend(random_doubles(2000, 1));
    t.extend(random_unit(2000, 2).iter().map(|u| u * end));
    t
}

fn time_list(t: &[f64]) -> String {
    t.iter().map(|&x| arg(x)).collect::<Vec<_>>().join(",")
}

fn row(s: Sample<f64>) -> Vec<f64> {
    vec![s.s, s.v, s.acc, s.jerk]
}

#[test]
fn traj_csv_reads_back_exactly() {
    let p = ZatParams { q0: 0.2, sf: 1.3, ts: 2.5, a: 1.1, n: 3.0 };
    let plan = ZatPlan::new(&p).unwrap();
    let t = times(p.ts);
    let args = strs(&["traj", "--q0", "0.2", "--sf", "1.3", "--ts", "2.5", "--a", "1.1", "--n", "3", "--t"]);
    let out = armsim(&[args, vec![time_list(&t)]].concat());
    check_csv(&out, "t,s,v,acc,jerk", &t, |t| row(plan.sample(t)), "traj");
}

#[test]
fn via_csv_reads_back_exactly() {
    let p = ViaParams { q0: 0.0, theta_v: 0.5, sf: 1.0, tv: 1.2, ts: 2.0, a: 1.0, n: 2.0, av: 0.8, nv: 2.0 };
    let plan = ViaPlan::new(&p).unwrap();
    let t = times(p.ts);
    let args = strs(&[
        "via", "--q0", "0", "--via", "0.5", "--sf", "1", "--tv", "1.2", "--ts", "2", "--a", "1", "--n", "2", "--av",
        "0.8", "--nv", "2", "--t",
    ]);
    let out = armsim(&[args, vec![time_list(&t)]].concat());
    check_csv(&out, "t,s,v,acc,jerk", &t, |t| row(plan.sample(t)), "via");
}

#[test]
fn law_csv_reads_back_exactly() {
    let t = times(3.0);
    for (kind, law) in
        [("linear", Law::Linear), ("cubic", Law::Cubic), ("quintic", Law::Quintic), ("trapezoid", Law::Trapezoid)]
    {
        let plan = LawPlan::new(law, &LawParams { t0: 0.0, tf: 3.0, s0: -0.7, sf: 2.9 }).unwrap();
        let args = strs(&["law", "--kind", kind, "--t0", "0", "--tf", "3", "--s0", "-0.7", "--sf", "2.9", "--t"]);
        let out = armsim(&[args, vec![time_list(&t)]].concat());
        check_csv(
            &out,
            "t,s,v,acc",
            &t,
            |t| {
                let s = plan.sample(t);
                vec![s.s, s.v, s.acc]
            },
            kind,
        );
    }
}

/// Points of the workspace [-1,1]×[0,1]: the fragile values ≤ 1 on both axes
/// (x of either sign, by exponent) and random points.
fn workspace_points() -> Vec<(f64, f64)> {
    let small: Vec<f64> = powers_of_two().into_iter().filter(|&v| v <= 1.0).collect();
    let sign = |i: usize| if i.is_multiple_of(2) { 1.0 } else { -1.0 };
    let mut pts: Vec<(f64, f64)> =
        small.iter().enumerate().map(|(i, &v)| (sign(i / 3) * v, small[small.len() - 1 - i])).collect();
    let (u, w) = (random_unit(1000, 3), random_unit(1000, 4));
    pts.extend(u.iter().zip(&w).map(|(&u, &w)| (2.0 * u - 1.0, w)));
    pts
}

#[test]
fn map_and_plan_json_read_back_exactly() {
    let geo = ArmGeometry { k: 1.0, links: Links::new(1.0, 1.0).unwrap(), branch: ELBOW_BRANCH };
    for (x, y) in workspace_points() {
        let xy = format!("{},{}", arg(x), arg(y));
        let p = WorkspacePoint::new(x, y).unwrap();
        let ctx = format!("map --xy {xy}");
        check_json(
            &armsim(&strs(&["map", "--xy", &xy])),
            &[("x_p", Some(x)), ("y_p", Some(y)), ("alpha_deg", Some(p.alpha_deg()))],
            &ctx,
        );
        let target = p.target(1.0).unwrap();
        let pose = pose_for_point(&geo, x, y);
        let sa = pose.as_ref().map_or(target.alpha_deg(), |p| p.alpha.to_degrees()) / 180.0;
        let (q2, q3) = reported(pose.map(|p| (p.q2, p.q3)).map_err(|e| match e {
            PoseError::Ik(e) => e,
            PoseError::Workspace(e) => panic!("({x:e}, {y:e}) is in the workspace: {e:?}"),
        }));
        check_json(
            &armsim(&strs(&["plan", "--xy", &xy])),
            &[
                ("x_p", Some(x)),
                ("y_p", Some(y)),
                ("alpha_deg", Some(target.alpha_deg())),
                ("reach", Some(target.reach)),
                ("height", Some(target.height)),
                ("q2", q2),
                ("q3", q3),
                ("s2", q2.map(|q| q / PI)),
                ("s3", q3.map(|q| q / PI)),
                ("sa", Some(sa)),
            ],
            &format!("plan --xy {xy}"),
        );
    }
}

#[test]
fn ik_json_reads_back_exactly() {
    let links = Links::new(1.0, 1.0).unwrap();
    // Reachable targets in the square of side 2 (q2, q3 vary), and the
    // fragile values as 3-DoF targets (θ1 is defined even out of reach).
    for (x, y) in workspace_points() {
        let (q2, q3) = reported(ik2(&links, x, y, ELBOW_BRANCH).map(|q| (q.q2, q.q3)));
        let out = armsim(&strs(&["ik", "--x", &arg(x), "--y", &arg(y)]));
        check_json(&out, &[("q2", q2), ("q3", q3)], &format!("ik {x:e} {y:e}"));
    }
    let far = powers_of_two();
    for (i, &x) in far.iter().enumerate().step_by(3) {
        let y = -far[far.len() - 1 - i];
        let out = armsim(&strs(&["ik", "--x", &arg(x), "--y", &arg(y), "--z", "0.5"]));
        let (th2, th3) = reported(ik3(&links, x, y, 0.5, ELBOW_BRANCH).map(|q| (q.th2, q.th3)));
        check_json(&out, &[("th1", Some(base_angle(x, y))), ("th2", th2), ("th3", th3)], &format!("ik3 {x:e} {y:e}"));
    }
}

#[test]
fn traj_info_json_reads_back_exactly() {
    // tₛ over every power of two: u_min = tₛ below 1 (an echo), 2√tₛ − 1 above.
    let mut ts_values = powers_of_two();
    ts_values.extend(random_doubles(1000, 5).iter().map(|x| x.abs()).filter(|&x| x > 0.0));
    for ts in ts_values {
        let p = ZatParams { q0: 0.25, sf: -1.5, ts, a: 0.0, n: 2.0 };
        let out = armsim(&strs(&[
            "traj",
            "--q0",
            "0.25",
            "--sf",
            "-1.5",
            "--ts",
            &arg(ts),
            "--a",
            "0",
            "--n",
            "2",
            "--info",
        ]));
        let plan = ZatPlan::new(&p).ok();
        check_json(
            &out,
            &[
                ("zeta", zeta(&p)),
                ("u_min", Some(u_min(ts))),
                ("a_smooth_stop", smooth_stop_a(ts, 2.0)),
                ("end_velocity", plan.map(|pl| pl.end_velocity())),
            ],
            &format!("traj --ts {ts:e} --info"),
        );
    }
}

#[test]
fn via_json_reads_back_exactly() {
    let mut targets = powers_of_two();
    targets.extend(random_doubles(1000, 6));
    for theta_v in targets.into_iter().step_by(2) {
        let p = ViaParams { q0: 0.0, theta_v, sf: 1.0, tv: 1.2, ts: 2.0, a: 1.0, n: 2.0, av: 0.8, nv: 2.0 };
        let args = format!("via --q0 0 --via {} --sf 1 --tv 1.2 --ts 2 --a 1 --n 2 --av 0.8 --nv 2", arg(theta_v));
        let out = try_armsim(&strs(&args.split(' ').collect::<Vec<_>>()));
        // A θ_v so far off that S_v* overflows is refused by both.
        let (Ok(plan), Ok(out)) = (ViaPlan::new(&p), &out) else {
            assert_eq!(ViaPlan::new(&p).is_ok(), out.is_ok(), "via --via {theta_v:e}: {out:?}");
            continue;
        };
        check_json(
            out,
            &[
                ("r", Some(plan.r())),
                ("s_v", Some(plan.sv())),
                ("zeta", plan.zeta()),
                ("zeta_v", plan.zeta_v()),
                ("velocity_jump", Some(plan.velocity_jump())),
                ("acceleration_jump", Some(plan.acc_jump())),
            ],
            &format!("via --via {theta_v:e}"),
        );
    }
}

/// The one formatter behind all of the above, on the values that broke it.
#[test]
fn report_numbers_read_back_exactly_with_15_digits() {
    let mut values = powers_of_two();
    values.extend(random_doubles(20_000, 7));
    for v in values.iter().flat_map(|&v| [v, -v]) {
        let s = armsim::report::num(v);
        same(&s, Some(v), "num");
        let digits = s.split('e').next().unwrap().trim_start_matches(['-', '0', '.']).replace('.', "");
        assert!(digits.len() >= 15, "{s}: fewer than 15 significant digits");
        assert_eq!(armsim::report::csv_row(&[v, f64::NAN, f64::INFINITY, -0.0]), format!("{s},,,-0.0"));
    }
    assert_eq!(armsim::report::num(2f64.powi(-24)), "5.960464477539063e-8");
    assert_eq!(armsim::report::num(0.3), "0.300000000000000");
    assert_eq!(armsim::report::num(1e15), "1.00000000000000e15");
    assert_eq!(armsim::report::num(123456789012345.0), "123456789012345.0");
    assert_eq!(armsim::report::num(-0.0001), "-0.000100000000000000");
    assert_eq!(armsim::report::num(f64::NAN), "null");
}
