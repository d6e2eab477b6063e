//! `armsim` as users and scripts call it: outputs parse, numbers match the
//! formulas, bad input exits non-zero with one line naming the problem.

use std::f64::consts::PI;
use std::process::Command;

use reference::zat::Zat;
use serde_json::Value;

fn armsim(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_armsim")).args(args).output().expect("run armsim");
    (out.status.code().unwrap_or(-1), String::from_utf8(out.stdout).unwrap(), String::from_utf8(out.stderr).unwrap())
}

fn json(args: &[&str]) -> Value {
    let (code, out, err) = armsim(args);
    assert_eq!(code, 0, "armsim {args:?} failed: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("armsim {args:?}: bad JSON {out:?}: {e}"))
}

fn f(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} missing or not a number in {v}"))
}

fn fails(args: &[&str], needle: &str) {
    let (code, out, err) = armsim(args);
    assert_ne!(code, 0, "armsim {args:?} should fail, printed {out}");
    assert!(out.is_empty(), "a failing command prints nothing on stdout: {out}");
    assert!(
        err.to_lowercase().contains(&needle.to_lowercase()),
        "armsim {args:?}: error {err:?} should mention {needle:?}"
    );
}

#[test]
fn map_raw_corners_and_midpoint() {
    let v = json(&["map", "--raw", "123,128"]);
    assert_eq!(f(&v, "x_p"), -1.0);
    assert_eq!(f(&v, "y_p"), 0.0);
    assert_eq!(v["clamped"], false);
    assert_eq!(v["condition"], 4);
    assert_eq!(f(&v, "alpha_deg"), 180.0);

    let v = json(&["map", "--raw", "932,897"]);
    assert_eq!((f(&v, "x_p"), f(&v, "y_p")), (1.0, 1.0));
    assert_eq!(v["condition"], 1);
    assert!((f(&v, "alpha_deg") - 45.0).abs() < 1e-12);

    // method.md §3: x_p = (raw − 527.5)/404.5, y_p = (raw − 128)/769.
    let v = json(&["map", "--raw", "600,500"]);
    assert!((f(&v, "x_p") - (600.0 - 527.5) / 404.5).abs() < 1e-15);
    assert!((f(&v, "y_p") - (500.0 - 128.0) / 769.0).abs() < 1e-15);
}

#[test]
fn map_out_of_range_raw_is_clamped_and_flagged() {
    let v = json(&["map", "--raw", "50,1000"]);
    assert_eq!(v["clamped"], true);
    assert_eq!((f(&v, "x_p"), f(&v, "y_p")), (-1.0, 1.0));
}

#[test]
fn map_conditions_on_the_boundaries_take_the_lower_number() {
    for (xy, cond, alpha) in [
        ("0.5,0.5", 1, 45.0),
        ("0,0.5", 2, 90.0),
        ("-0.5,0.5", 3, 135.0),
        ("0,0", 1, 0.0),
        ("-0.9,0.1", 4, 173.65980825409008),
    ] {
        let v = json(&["map", "--xy", xy]);
        assert_eq!(v["condition"], cond, "{xy}");
        assert!((f(&v, "alpha_deg") - alpha).abs() < 1e-12, "{xy}: {}", v["alpha_deg"]);
    }
}

#[test]
fn numbers_keep_at_least_15_significant_digits() {
    let (_, out, _) = armsim(&["map", "--xy", "0.3,0.6"]);
    assert!(out.contains("\"x_p\": 0.300000000000000"), "{out}");
    let v = json(&["plan", "--xy", "0.3,0.6"]);
    let q2 = f(&v, "q2");
    let (_, out, _) = armsim(&["plan", "--xy", "0.3,0.6"]);
    let printed = out.split("\"q2\": ").nth(1).unwrap().split(',').next().unwrap();
    assert!(printed.trim_start_matches('-').replace('.', "").trim_start_matches('0').len() >= 15, "{printed}");
    assert_eq!(printed.parse::<f64>().unwrap(), q2);
}

#[test]
fn ik_matches_forward_kinematics_for_both_branches() {
    for branch in ["plus", "minus"] {
        let v = json(&["ik", "--x", "0.7", "--y", "0.9", "--l2", "1.2", "--l3", "0.8", "--branch", branch]);
        assert_eq!(v["reachable"], true);
        let (q2, q3) = (f(&v, "q2"), f(&v, "q3"));
        let x = 1.2 * q2.cos() + 0.8 * (q2 + q3).cos();
        let y = 1.2 * q2.sin() + 0.8 * (q2 + q3).sin();
        assert!((x - 0.7).abs() < 1e-12 && (y - 0.9).abs() < 1e-12, "{branch}: ({x}, {y})");
        assert_eq!(q3 > 0.0, branch == "plus");
        assert_eq!(v["branch"], branch);
    }
}

#[test]
fn ik_known_values_and_unreachable() {
    // (1, 1) with l2 = l3 = 1: the firmware's branch (minus, elbow up, the
    // default) raises the upper arm straight up, q2 = π/2, and bends the
    // forearm down to horizontal, q3 = −π/2; the plus branch mirrors it about
    // the line to the target: q2 = 0, q3 = +π/2.
    let v = json(&["ik", "--x", "1", "--y", "1"]);
    assert_eq!(v["branch"], "minus");
    assert!((f(&v, "q2") - PI / 2.0).abs() < 1e-15 && (f(&v, "q3") + PI / 2.0).abs() < 1e-15, "{v}");
    assert_eq!(v["singular"], false);
    let v = json(&["ik", "--x", "1", "--y", "1", "--branch", "plus"]);
    assert_eq!(v["branch"], "plus");
    assert!(f(&v, "q2").abs() < 1e-15 && (f(&v, "q3") - PI / 2.0).abs() < 1e-15, "{v}");
    let v = json(&["ik", "--x", "2.5", "--y", "0"]);
    assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(false), &Value::Bool(false)));
    assert!(v["q2"].is_null() && v["q3"].is_null());
}

#[test]
fn ik_at_the_shoulder_is_folded_with_no_shoulder_angle() {
    // l2 = l3: the hand reaches the shoulder with the elbow folded (c = −1),
    // and every q2 puts it there.
    for (branch, q3) in [("plus", PI), ("minus", -PI)] {
        let v = json(&["ik", "--x", "0", "--y", "0", "--l2", "0.7", "--l3", "0.7", "--branch", branch]);
        assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(true), &Value::Bool(true)), "{v}");
        assert!(v["q2"].is_null(), "{v}");
        assert_eq!(f(&v, "q3"), q3);
    }
    // l2 ≠ l3: the shoulder lies in the annulus's hole.
    let v = json(&["ik", "--x", "0", "--y", "0", "--l2", "1", "--l3", "0.5"]);
    assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(false), &Value::Bool(false)));
    assert!(v["q3"].is_null());
    // 3-DoF: straight above the base θ1 is free (0 by convention); folded
    // on the default (firmware's, minus) branch, θ3 = −π.
    let v = json(&["ik", "--x", "0", "--y", "0", "--z", "0"]);
    assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(true), &Value::Bool(true)));
    assert_eq!(v["branch"], "minus");
    assert_eq!((f(&v, "th1"), f(&v, "th3")), (0.0, -PI));
    assert!(v["th2"].is_null());
}

#[test]
fn ik_three_dof_form() {
    let (xe, ye, ze): (f64, f64, f64) = (0.6, 0.8, 0.5);
    let v = json(&["ik", "--x", "0.6", "--y", "0.8", "--z", "0.5"]);
    assert_eq!(v["reachable"], true);
    let (th1, th2, th3) = (f(&v, "th1"), f(&v, "th2"), f(&v, "th3"));
    assert!((th1 - ye.atan2(xe)).abs() < 1e-15);
    let r = th2.cos() + (th2 + th3).cos();
    let z = th2.sin() + (th2 + th3).sin();
    assert!((r - (xe * xe + ye * ye).sqrt()).abs() < 1e-12 && (z - ze).abs() < 1e-12);

    // Out of reach, θ1 is still the direction of (x_e, y_e).
    let v = json(&["ik", "--x", "-3", "--y", "4", "--z", "0.5"]);
    assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(false), &Value::Bool(false)));
    assert_eq!(f(&v, "th1"), 4f64.atan2(-3.0));
    assert!((f(&v, "th1") - (PI - (4.0f64 / 3.0).atan())).abs() < 1e-15);
    assert!(v["th2"].is_null() && v["th3"].is_null());
}

#[test]
fn plan_normalized_joint_values() {
    let v = json(&["plan", "--raw", "700,600", "--k", "1.2", "--l2", "1", "--l3", "1"]);
    let (x_p, y_p) = ((700.0 - 527.5) / 404.5, (600.0 - 128.0) / 769.0);
    assert!((f(&v, "x_p") - x_p).abs() < 1e-15 && (f(&v, "y_p") - y_p).abs() < 1e-15);
    assert!((f(&v, "reach") - 1.2 * x_p).abs() < 1e-15 && (f(&v, "height") - 1.2 * y_p).abs() < 1e-15);
    assert_eq!(v["reachable"], true);
    let (q2, q3) = (f(&v, "q2"), f(&v, "q3"));
    assert_eq!(f(&v, "s2"), q2 / PI);
    assert_eq!(f(&v, "s3"), q3 / PI);
    let alpha = f(&v, "alpha_deg");
    assert!((alpha - y_p.atan2(x_p).to_degrees()).abs() < 1e-12);
    assert!((f(&v, "sa") - alpha / 180.0).abs() < 1e-15);
    let (x, y) = (q2.cos() + (q2 + q3).cos(), q2.sin() + (q2 + q3).sin());
    assert!((x - 1.2 * x_p).abs() < 1e-12 && (y - 1.2 * y_p).abs() < 1e-12);
}

/// `plan` takes the links as the firmware's `cal set arm` does (issue #21
/// §4): any one unit, the map's arm unit their mean. 120 and 80 (mm) are 1.2
/// and 0.8 arm units: the same pose as `--l2 1.2 --l3 0.8`, the FK of the
/// pose in those units lands on (k·|x_p|, k·y_p), and the point inside
/// radius |1.2 − 0.8| = 0.4 the scenario `arm_geometry.scn` refuses is out
/// of reach here too.
#[test]
fn plan_takes_the_firmwares_link_lengths() {
    let mm = json(&["plan", "--raw", "700,700", "--l2", "120", "--l3", "80"]);
    let units = json(&["plan", "--raw", "700,700", "--l2", "1.2", "--l3", "0.8"]);
    for key in ["q2", "q3", "reach", "height"] {
        assert!((f(&mm, key) - f(&units, key)).abs() < 1e-12, "{key}: {mm} vs {units}");
    }
    let (q2, q3) = (f(&mm, "q2"), f(&mm, "q3"));
    // The f64 values of the scenario's comment.
    assert!((q2.to_degrees() - 101.9263).abs() < 1e-4 && (q3.to_degrees() + 134.4632).abs() < 1e-4);
    let (x, y) = (1.2 * q2.cos() + 0.8 * (q2 + q3).cos(), 1.2 * q2.sin() + 0.8 * (q2 + q3).sin());
    assert!((x - f(&mm, "reach")).abs() < 1e-12 && (y - f(&mm, "height")).abs() < 1e-12);
    // Equal links of any length are the paper's 1 and 1.
    let equal = json(&["plan", "--raw", "700,700", "--l2", "250", "--l3", "250"]);
    let paper = json(&["plan", "--raw", "700,700"]);
    assert_eq!((f(&equal, "q2"), f(&equal, "q3")), (f(&paper, "q2"), f(&paper, "q3")));
    let close = json(&["plan", "--raw", "600,400", "--l2", "120", "--l3", "80"]);
    assert_eq!(close["reachable"], false);
}

#[test]
fn ik_and_plan_default_to_the_firmwares_branch() {
    // The default is the branch the firmware solves on and its servo
    // calibration assumes: the plan's angles for a point are the core's
    // pose for it on ELBOW_BRANCH.
    use touch_arm::geometry::ik::{Branch, Links};
    use touch_arm::geometry::pose::{pose_for_point, ArmGeometry};
    use touch_arm::servo::map::ELBOW_BRANCH;
    let name = if ELBOW_BRANCH == Branch::Minus { "minus" } else { "plus" };
    let v = json(&["plan", "--xy", "0.3,0.6", "--k", "1.2"]);
    assert_eq!(v["branch"], name);
    let geo = ArmGeometry { k: 1.2, links: Links::new(1.0, 1.0).unwrap(), branch: ELBOW_BRANCH };
    let pose = pose_for_point(&geo, 0.3, 0.6).unwrap();
    assert_eq!((f(&v, "q2"), f(&v, "q3")), (pose.q2, pose.q3));
    let v = json(&["ik", "--x", "0.7", "--y", "0.9"]);
    assert_eq!(v["branch"], name);
}

#[test]
fn plan_unreachable_and_singular_points() {
    // The bottom centre with l2 = l3 is the shoulder: folded, no q2; on the
    // default (firmware's, minus) branch q3 = −π.
    let v = json(&["plan", "--xy", "0,0"]);
    assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(true), &Value::Bool(true)), "{v}");
    assert!(v["q2"].is_null() && v["s2"].is_null(), "{v}");
    assert_eq!(v["branch"], "minus");
    assert_eq!((f(&v, "q3"), f(&v, "s3")), (-PI, -1.0));
    let v = json(&["plan", "--xy", "0,0", "--branch", "plus"]);
    assert_eq!((v["branch"].as_str(), f(&v, "q3"), f(&v, "s3")), (Some("plus"), PI, 1.0));
    let v = json(&["plan", "--xy", "1,1", "--k", "2"]);
    assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(false), &Value::Bool(false)));
    assert!(v["q2"].is_null() && v["s3"].is_null());
    // With the default scale every other workspace point is reachable.
    let v = json(&["plan", "--xy", "0.001,0"]);
    assert_eq!((&v["reachable"], &v["singular"]), (&Value::Bool(true), &Value::Bool(false)));
}

#[test]
fn printed_numbers_read_back_exactly_and_are_valid_input() {
    // 2⁻²⁴ is a tie for 16 digits: re-rounding printed 5.960464477539062e-8,
    // another double. Negative exponents with a minus sign are valid input.
    let p = 2f64.powi(-24);
    let (code, out, err) = armsim(&[
        "law",
        "--kind",
        "linear",
        "--t0",
        "-1",
        "--tf",
        "0",
        "--s0",
        "-1",
        "--sf",
        "0",
        "--t",
        &format!("{}", -p),
    ]);
    assert_eq!(code, 0, "{err}");
    let cells: Vec<&str> = out.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(cells[..2], ["-5.960464477539063e-8", "-5.960464477539063e-8"], "{out}");
    assert_eq!(cells[0].parse::<f64>().unwrap(), -p);
    let v = json(&["map", "--xy", &format!("{:e},{p:e}", -p)]);
    assert_eq!((f(&v, "x_p"), f(&v, "y_p")), (-p, p));
}

#[test]
fn csv_cells_of_non_finite_values_are_empty() {
    // A quintic over 1e-200 s moving 1e200: v and acc overflow.
    let (code, out, err) = armsim(&[
        "law", "--kind", "quintic", "--t0", "0", "--tf", "1e-200", "--s0", "0", "--sf", "1e200", "--t", "5e-201",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out, "t,s,v,acc\n5.00000000000000e-201,5.00000000000000e199,,\n");
}

#[test]
fn bad_input_fails_with_one_clear_line() {
    fails(&["map", "--raw", "2000,5"], "0..=1023");
    fails(&["map", "--raw", "12"], "X,Y");
    fails(&["map", "--xy", "1.5,0.2"], "outside the workspace");
    fails(&["map"], "required");
    fails(&["ik", "--x", "1", "--y", "nan"], "finite");
    fails(&["ik", "--x", "1", "--y", "1", "--l2", "-1"], "positive");
    fails(&["plan", "--xy", "0.2,0.2", "--k", "0"], "--k");
    fails(&["frobnicate"], "unrecognized subcommand");
}

#[test]
fn every_subcommand_has_help() {
    for cmd in ["map", "ik", "plan", "traj", "via", "law", "plot", "path"] {
        let (code, out, _) = armsim(&[cmd, "--help"]);
        assert_eq!(code, 0);
        assert!(out.contains("Usage: armsim"), "{cmd}: {out}");
    }
    // The edge conventions are stated where the fields are.
    for (cmd, words) in [
        ("traj", &["zeta_infinite", "S_f = q0"][..]),
        ("via", &["zeta_infinite", "zeta_v_infinite"]),
        ("ik", &["singular", "folded", "θ1"]),
        ("plan", &["singular"]),
    ] {
        let (_, out, _) = armsim(&[cmd, "--help"]);
        for w in words {
            assert!(out.contains(w), "armsim {cmd} --help should mention {w}: {out}");
        }
    }
}

#[test]
fn argument_errors_are_a_single_line() {
    let (code, _, err) = armsim(&["map", "--raw", "2000,5"]);
    assert_eq!(code, 2);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("armsim: "), "{err}");
}

fn csv(args: &[&str]) -> (Vec<String>, Vec<Vec<f64>>) {
    let (code, out, err) = armsim(args);
    assert_eq!(code, 0, "armsim {args:?} failed: {err}");
    let mut lines = out.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines.map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect()).collect();
    (header, rows)
}

/// The papers' printed form (method.md §7), evaluated independently in f64
/// (`reference`).
fn printed_zat(q0: f64, sf: f64, ts: f64, a: f64, n: f64, t: f64) -> f64 {
    Zat::new(ts, a, n).printed(q0, sf, t)
}

#[test]
fn traj_samples_match_the_printed_formula_and_end_exactly() {
    let (q0, sf, ts, a, n) = (0.2, 1.3, 2.5, 1.1, 3.0);
    let (h, rows) = csv(&[
        "traj",
        "--q0",
        "0.2",
        "--sf",
        "1.3",
        "--ts",
        "2.5",
        "--a",
        "1.1",
        "--n",
        "3",
        "--t",
        "-1,0,0.3,0.9,1.6,2.2,2.5,4",
    ]);
    assert_eq!(h, ["t", "s", "v", "acc", "jerk"]);
    for r in &rows {
        let expect = printed_zat(q0, sf, ts, a, n, r[0]);
        assert!((r[1] - expect).abs() < 1e-12, "t={}: {} vs {}", r[0], r[1], expect);
    }
    assert_eq!(rows[6][1], sf, "exact at tₛ");
    assert_eq!(&rows[7][1..], &[sf, 0.0, 0.0, 0.0], "held after tₛ");
    assert_eq!(&rows[0][1..], &[q0, 0.0, 0.0, 0.0], "held before 0");
    // Velocity against a central difference of the printed form.
    let t = 1.6;
    let h = 1e-6;
    let fd = (printed_zat(q0, sf, ts, a, n, t + h) - printed_zat(q0, sf, ts, a, n, t - h)) / (2.0 * h);
    assert!((rows[4][2] - fd).abs() < 1e-7, "{} vs {fd}", rows[4][2]);
}

#[test]
fn traj_descending_motion_and_sample_count() {
    let (_, rows) =
        csv(&["traj", "--q0", "1", "--sf", "-0.5", "--ts", "0.8", "--a", "0.3", "--n", "2", "--samples", "9"]);
    assert_eq!(rows.len(), 9);
    assert_eq!(rows[0][0], 0.0);
    assert_eq!(rows[8][0], 0.8);
    assert_eq!(rows[8][1], -0.5);
    for w in rows.windows(2) {
        assert!(w[1][1] <= w[0][1], "monotone descent");
        assert!(w[1][2] <= 1e-12, "velocity is negative for S_f < q0");
    }
    for r in &rows {
        assert!((r[1] - printed_zat(1.0, -0.5, 0.8, 0.3, 2.0, r[0])).abs() < 1e-12);
    }
}

#[test]
fn traj_info_domain_smooth_stop_and_overshoot() {
    let v = json(&["traj", "--q0", "0", "--sf", "1", "--ts", "4", "--a", "1", "--n", "2", "--info"]);
    assert_eq!(f(&v, "u_min"), 2.0 * 4f64.sqrt() - 1.0);
    assert_eq!(v["admissible"], true);
    assert!((f(&v, "a_smooth_stop") - (4.0 - 2.0)).abs() < 1e-15, "a* = tₛ − log₂ tₛ");
    let zeta = 4.0 - (16f64 - 2.0).log2();
    assert!((f(&v, "zeta") - zeta).abs() < 1e-12);
    assert_eq!(v["zeta_infinite"], false);
    // method.md §7: S'(tₛ⁻) = Δ·L·[1 − (1 − 1/tₛ)(1 + q(tₛ))], q = 1/(n^(tₛ−a) − 1).
    let q = 1.0 / (2f64.powf(3.0) - 1.0);
    let ev = 2f64.ln() * (1.0 - (1.0 - 0.25) * (1.0 + q));
    assert!((f(&v, "end_velocity") - ev).abs() < 1e-12);
    assert_eq!(v["monotone"], true);

    // tₛ < 1: u_min = tₛ; no smooth stop exists.
    let v = json(&["traj", "--q0", "0", "--sf", "1", "--ts", "0.5", "--a", "0.2", "--n", "2", "--info"]);
    assert_eq!(f(&v, "u_min"), 0.5);
    assert!(v["a_smooth_stop"].is_null());

    // No motion (S_f = q0): ζ = tₛ − log_n(0) is infinite.
    let v = json(&["traj", "--q0", "0.5", "--sf", "0.5", "--ts", "4", "--a", "1", "--n", "2", "--info"]);
    assert!(v["zeta"].is_null());
    assert_eq!(v["zeta_infinite"], true);
    assert_eq!(f(&v, "end_velocity"), 0.0);
    // a ≥ tₛ: ζ is undefined, not infinite.
    let v = json(&["traj", "--q0", "0", "--sf", "1", "--ts", "3", "--a", "3.5", "--n", "2", "--info"]);
    assert!(v["zeta"].is_null());
    assert_eq!(v["zeta_infinite"], false);

    // method.md's example of a pole-near shape that overshoots.
    let v = json(&["traj", "--q0", "0", "--sf", "1", "--ts", "3", "--a", "2.45", "--n", "2", "--info"]);
    assert_eq!(v["admissible"], true);
    assert_eq!(v["monotone"], false);

    // The papers' a < tₛ is not enough: a = 2.9 < tₛ = 3 has a pole.
    let v = json(&["traj", "--q0", "0", "--sf", "1", "--ts", "3", "--a", "2.9", "--n", "2", "--info"]);
    assert_eq!(v["admissible"], false);
    assert!(v["end_velocity"].is_null());
}

#[test]
fn traj_inadmissible_parameters_name_the_bound() {
    fails(
        &["traj", "--q0", "0", "--sf", "1", "--ts", "3", "--a", "2.9", "--n", "2", "--t", "1"],
        "u_min = 2.46410161513775",
    );
    fails(&["traj", "--q0", "0", "--sf", "1", "--ts", "0", "--a", "-1", "--n", "2", "--t", "1"], "duration");
    fails(&["traj", "--q0", "0", "--sf", "1", "--ts", "1", "--a", "0", "--n", "1", "--t", "1"], "n");
    fails(&["traj", "--q0", "0", "--sf", "1", "--ts", "1", "--a", "0", "--n", "2"], "--samples");
    fails(&["traj", "--q0", "0", "--sf", "1", "--ts", "1", "--a", "0", "--n", "2", "--samples", "1"], "at least 2");
    fails(
        &["traj", "--q0", "0", "--sf", "1", "--ts", "1", "--a", "0", "--n", "2", "--t", "0,x"],
        "not a finite number",
    );
}

#[test]
fn via_closed_form_passes_through_the_via_point() {
    let args = [
        "via", "--q0", "0", "--via", "0.5", "--sf", "1", "--tv", "1.2", "--ts", "2", "--a", "1", "--n", "2", "--av",
        "0.8", "--nv", "2",
    ];
    let v = json(&[&args[..], &["--iterate", "1e-10"]].concat());
    // r = G(t_v) of the main segment: the printed form with q0 = 0, S_f = 1.
    let r = printed_zat(0.0, 1.0, 2.0, 1.0, 2.0, 1.2);
    assert!((f(&v, "r") - r).abs() < 1e-12);
    let sv = (0.5 - r * 1.0) / (1.0 - r);
    assert!((f(&v, "s_v") - sv).abs() < 1e-12);
    assert_eq!(v["converges"], true);
    assert!(v["iterations"].as_u64().unwrap() > 0);
    assert!((f(&v, "s_v_iter") - sv).abs() < 1e-9);
    for key in ["zeta_infinite", "zeta_v_infinite", "zeta_iter_infinite", "zeta_v_iter_infinite"] {
        assert_eq!(v[key], false, "{key}");
    }
    assert_eq!(v["condition"], if sv < 0.0 { 3 } else { 1 });
    // The trajectory hits θ_v at t_v and ends at S_f.
    let (_, rows) = csv(&[&args[..], &["--t", "1.2,2"]].concat());
    assert!((rows[0][1] - 0.5).abs() < 1e-12, "S(t_v) = {}", rows[0][1]);
    assert_eq!(rows[1][1], 1.0);
}

#[test]
fn via_paper_iteration_diverges_when_r_exceeds_one() {
    // method.md §8: tₛ = 3, a = 2.45, n = 2, t_v = 1.7 gives r = 18.4.
    let v = json(&[
        "via",
        "--q0",
        "0",
        "--via",
        "0.5",
        "--sf",
        "1",
        "--tv",
        "1.7",
        "--ts",
        "3",
        "--a",
        "2.45",
        "--n",
        "2",
        "--av",
        "1",
        "--nv",
        "2",
        "--iterate",
        "1e-9",
    ]);
    assert!((f(&v, "r") - 18.4).abs() < 0.01);
    assert_eq!(v["converges"], false);
    assert!(v["iterations"].is_null());
}

#[test]
fn via_smooth_via_shape_has_no_velocity_jump() {
    let (tv, nv): (f64, f64) = (1.5, 2.0);
    let av = tv - tv.ln() / nv.ln();
    let av = format!("{av}");
    let v = json(&[
        "via", "--q0", "0", "--via", "0.6", "--sf", "1", "--tv", "1.5", "--ts", "2", "--a", "1", "--n", "2", "--av",
        &av, "--nv", "2",
    ]);
    assert!(f(&v, "velocity_jump").abs() < 1e-9, "{}", v["velocity_jump"]);
}

#[test]
fn via_zeta_of_a_zero_term_is_infinite() {
    // θ_v = S_f: S_v* = (S_f − r·S_f)/(1 − r) = S_f, so the main term S_v → S_f
    // does not move and its ζ is infinite; ζ_v (0 → 1) is finite.
    let args = "via --q0 0 --via 1 --sf 1 --tv 1.2 --ts 2 --a 1 --n 2 --av 0.8 --nv 2 --iterate 1e-12";
    let v = json(&args.split(' ').collect::<Vec<_>>());
    assert_eq!(f(&v, "s_v"), 1.0);
    assert!(v["zeta"].is_null() && v["zeta_iter"].is_null(), "{v}");
    assert_eq!((&v["zeta_infinite"], &v["zeta_iter_infinite"]), (&Value::Bool(true), &Value::Bool(true)));
    // ζ_v = −ln(|Δ|·(1 − n_v^(a_v − t_v)))/ln n_v with Δ = 1.
    let zeta_v = -(1.0 - 2f64.powf(0.8 - 1.2)).ln() / 2f64.ln();
    assert!((f(&v, "zeta_v") - zeta_v).abs() < 1e-15, "{v}");
    assert_eq!(v["zeta_v_infinite"], false);
}

#[test]
fn via_bad_segment_is_named() {
    fails(
        &[
            "via", "--q0", "0", "--via", "0.5", "--sf", "1", "--tv", "1", "--ts", "2", "--a", "1", "--n", "2", "--av",
            "1", "--nv", "2",
        ],
        "via segment",
    );
}

#[test]
fn law_values_match_the_corrected_formulas() {
    let (h, rows) =
        csv(&["law", "--kind", "quintic", "--t0", "1", "--tf", "3", "--s0", "2", "--sf", "-1", "--t", "0,1.5,2.2,3,5"]);
    assert_eq!(h, ["t", "s", "v", "acc"]);
    let (t0, tf, s0, d) = (1.0, 3.0, 2.0, -3.0);
    let big_t: f64 = tf - t0;
    for r in &rows[1..4] {
        let tau: f64 = (r[0] - t0) / big_t;
        let s = s0 + (10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5)) * d;
        let v = 30.0 * d * (tau * tau - 2.0 * tau.powi(3) + tau.powi(4)) / big_t;
        let acc = 60.0 * d * (tau - 3.0 * tau * tau + 2.0 * tau.powi(3)) / (big_t * big_t);
        assert!((r[1] - s).abs() < 1e-12 && (r[2] - v).abs() < 1e-12 && (r[3] - acc).abs() < 1e-12, "{r:?}");
    }
    assert_eq!(&rows[0][1..], &[2.0, 0.0, 0.0]);
    assert_eq!(&rows[4][1..], &[-1.0, 0.0, 0.0]);

    // Cubic reaches its end exactly (method.md §9: the papers' 3.053 was read at 0.9 s).
    let (_, rows) = csv(&[
        "law",
        "--kind",
        "cubic",
        "--t0",
        "0",
        "--tf",
        "1",
        "--s0",
        "0",
        "--sf",
        "3.141592653589793",
        "--t",
        "0.9,1",
    ]);
    assert!((rows[0][1] - 3.0536).abs() < 1e-4);
    assert_eq!(rows[1][1], std::f64::consts::PI);

    // Trapezoid: cruise velocity 1.5Δ/T, acceleration 4.5Δ/T².
    let (_, rows) =
        csv(&["law", "--kind", "trapezoid", "--t0", "0", "--tf", "2", "--s0", "0", "--sf", "4", "--t", "0.2,1"]);
    assert!((rows[0][3] - 4.5 * 4.0 / 4.0).abs() < 1e-12);
    assert!((rows[1][2] - 1.5 * 4.0 / 2.0).abs() < 1e-12);
    assert!((rows[1][1] - (6.0 * 0.5 - 1.0) * 4.0 / 4.0).abs() < 1e-12);

    let (_, rows) =
        csv(&["law", "--kind", "linear", "--t0", "0", "--tf", "2", "--s0", "1", "--sf", "3", "--samples", "3"]);
    assert_eq!(rows.iter().map(|r| r[1]).collect::<Vec<_>>(), [1.0, 2.0, 3.0]);
    fails(
        &["law", "--kind", "cubic", "--t0", "1", "--tf", "1", "--s0", "0", "--sf", "1", "--t", "1"],
        "tf must be > t0",
    );
    fails(
        &["law", "--kind", "septic", "--t0", "0", "--tf", "1", "--s0", "0", "--sf", "1", "--t", "1"],
        "invalid value",
    );
}

/// `law --kind zat`: the reference shape (n = 2, T₀ = 1.5 s, a* = T₀ −
/// log₂ T₀) of method.md's normalized form at τ = (t − t0)·T₀/(t_f − t0),
/// ending exactly on s_f at rest; `traj` stays the papers' own form.
#[test]
fn law_zat_is_the_time_scaled_reference_shape() {
    let (h, rows) =
        csv(&["law", "--kind", "zat", "--t0", "1", "--tf", "3", "--s0", "2", "--sf", "-1", "--t", "0,1.5,2.2,2.9,3,5"]);
    assert_eq!(h, ["t", "s", "v", "acc"]);
    let (t0, tf, s0, d, big_t0, l) = (1.0, 3.0, 2.0, -3.0, 1.5f64, std::f64::consts::LN_2);
    let a = big_t0 - big_t0.log2();
    // G(τ) = n^(1 − T₀/τ)·(1 + q(τ))/(1 + q(T₀)), q = 1/(n^(u − a) − 1), u = τ + T₀/τ − 1.
    let q = |u: f64| 1.0 / (l * (u - a)).exp_m1();
    let g = |tau: f64| (l * (1.0 - big_t0 / tau)).exp() * (1.0 + q(tau + big_t0 / tau - 1.0)) / (1.0 + q(big_t0));
    for r in &rows[1..4] {
        let tau = (r[0] - t0) * big_t0 / (tf - t0);
        assert!((r[1] - (s0 + d * g(tau))).abs() < 1e-12, "{r:?}");
        // The velocity is Δ·G′(τ)·T₀/(t_f − t0): a central difference of G.
        let h = 1e-6;
        let v = d * (g(tau + h) - g(tau - h)) / (2.0 * h) * big_t0 / (tf - t0);
        assert!((r[2] - v).abs() < 1e-6, "{r:?} vs {v}");
    }
    assert_eq!(&rows[0][1..], &[2.0, 0.0, 0.0]);
    assert_eq!(rows[4][1], -1.0);
    assert!(rows[4][2].abs() < 1e-12, "smooth stop: {:?}", rows[4]);
    assert_eq!(&rows[5][1..], &[-1.0, 0.0, 0.0]);
    fails(&["law", "--kind", "zat", "--t0", "1", "--tf", "0", "--s0", "0", "--sf", "1", "--t", "1"], "tf must be > t0");
}

#[test]
fn plot_writes_png_and_svg() {
    let dir = std::env::temp_dir().join(format!("armsim-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("traj.png");
    let (code, _, err) = armsim(&[
        "plot",
        "traj",
        "--q0",
        "0",
        "--sf",
        "1",
        "--ts",
        "2",
        "--a",
        "1",
        "--n",
        "2",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert!(bytes.len() > 10_000, "a real picture, not an empty canvas");

    let svg = dir.join("law.svg");
    let (code, _, err) = armsim(&[
        "plot",
        "law",
        "--kind",
        "quintic",
        "--t0",
        "0",
        "--tf",
        "1",
        "--s0",
        "0",
        "--sf",
        "1",
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.matches("<polyline").count() >= 4, "four panels drawn");

    let via = dir.join("via.png");
    let (code, _, err) = armsim(&[
        "plot",
        "via",
        "--q0",
        "0",
        "--via",
        "0.5",
        "--sf",
        "1",
        "--tv",
        "1.2",
        "--ts",
        "2",
        "--a",
        "1",
        "--n",
        "2",
        "--av",
        "0.8",
        "--nv",
        "2",
        "--out",
        via.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");

    fails(
        &[
            "plot",
            "traj",
            "--q0",
            "0",
            "--sf",
            "1",
            "--ts",
            "2",
            "--a",
            "1",
            "--n",
            "2",
            "--out",
            dir.join("x.jpg").to_str().unwrap(),
        ],
        ".png or .svg",
    );
    fails(
        &[
            "plot",
            "traj",
            "--q0",
            "0",
            "--sf",
            "1",
            "--ts",
            "2",
            "--a",
            "5",
            "--n",
            "2",
            "--out",
            png.to_str().unwrap(),
        ],
        "u_min",
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Right minus left one-sided derivatives (second order) of S at t_v from the
/// CSV positions: (velocity jump, acceleration jump).
fn fd_jumps(base: &[&str], tv: f64, h: f64) -> (f64, f64) {
    let ts: Vec<String> = (-3..=3).map(|k| format!("{}", tv + k as f64 * h)).collect();
    let (_, rows) = csv(&[base, &["--t", &ts.join(",")]].concat());
    let s = |k: i32| rows[(k + 3) as usize][1];
    let v_l = (3.0 * s(0) - 4.0 * s(-1) + s(-2)) / (2.0 * h);
    let v_r = (-3.0 * s(0) + 4.0 * s(1) - s(2)) / (2.0 * h);
    let a_l = (2.0 * s(0) - 5.0 * s(-1) + 4.0 * s(-2) - s(-3)) / (h * h);
    let a_r = (2.0 * s(0) - 5.0 * s(1) + 4.0 * s(2) - s(3)) / (h * h);
    (v_r - v_l, a_r - a_l)
}

#[test]
fn via_continuity_picks_the_shape_and_reports_the_jumps() {
    let base = ["via", "--q0", "0", "--via", "0.6", "--sf", "1", "--tv", "1.5", "--ts", "2.5", "--a", "1", "--n", "2"];
    let h = 2e-4;
    // c0: the given shape; the jumps it reports are the finite differences'.
    let c0 = [&base[..], &["--av", "1", "--nv", "2"]].concat();
    let v = json(&c0);
    let (dv, da) = fd_jumps(&c0, 1.5, h);
    assert!(f(&v, "velocity_jump").abs() > 1e-2);
    assert!((dv - f(&v, "velocity_jump")).abs() < 1e-5, "fd {dv} vs {}", v["velocity_jump"]);
    assert!((da - f(&v, "acceleration_jump")).abs() < 1e-2 * f(&v, "acceleration_jump").abs(), "fd {da} vs {v}");
    // c1: a_v = t_v − log_{n_v} t_v, the velocity continuous, the acceleration not.
    let c1 = [&base[..], &["--nv", "2", "--continuity", "c1"]].concat();
    let v = json(&c1);
    assert!((f(&v, "a_v") - (1.5 - 1.5f64.log2())).abs() < 1e-15);
    assert_eq!(f(&v, "n_v"), 2.0);
    assert!(f(&v, "velocity_jump").abs() < 1e-14, "{v}");
    // Gv″(t_v⁻) = (L/t_v)(L − 2/(t_v − 1)) with L = ln 2; the jump is −(S_v − q0) times it.
    let l = 2f64.ln();
    let want = -f(&v, "s_v") * (l / 1.5) * (l - 4.0);
    assert!((f(&v, "acceleration_jump") - want).abs() < 1e-12, "{v}");
    let (dv, da) = fd_jumps(&c1, 1.5, h);
    assert!(dv.abs() < 1e-5, "fd velocity jump {dv}");
    assert!((da - want).abs() < 1e-2 * want.abs(), "fd {da} vs {want}");
    // c2: n_v = e^(2/(t_v − 1)) = e⁴; velocity and acceleration continuous, the
    // jerk steps by −(S_v − q0)·4(t_v + 1)/(t_v²(t_v − 1)³).
    let c2 = [&base[..], &["--continuity", "c2"]].concat();
    let v = json(&c2);
    assert!((f(&v, "n_v") - 4f64.exp()).abs() < 1e-12, "{v}");
    assert!(f(&v, "velocity_jump").abs() < 1e-14 && f(&v, "acceleration_jump").abs() < 1e-13, "{v}");
    let jerk = -f(&v, "s_v") * 4.0 * 2.5 / (1.5 * 1.5 * 0.125);
    assert!((f(&v, "jerk_jump") - jerk).abs() < 1e-9 * jerk.abs(), "{v} vs {jerk}");
    let (dv, da) = fd_jumps(&c2, 1.5, h);
    assert!(dv.abs() < 1e-5 && da.abs() < 2e-2, "fd jumps {dv} {da}");
    // The same S_v for every choice: the via value is met whatever the shape.
    let (_, rows) = csv(&[&c2[..], &["--t", "1.5"]].concat());
    assert!((rows[0][1] - 0.6).abs() < 1e-14);
}

#[test]
fn via_continuity_refusals_are_clear() {
    let base = ["via", "--q0", "0", "--via", "0.6", "--sf", "1", "--ts", "2.5", "--a", "1", "--n", "2"];
    fails(&[&base[..], &["--tv", "0.8", "--continuity", "c2"]].concat(), "admissible only for t_v > 1");
    fails(&[&base[..], &["--tv", "0.8", "--nv", "2", "--continuity", "c1"]].concat(), "t_v > 1");
    fails(&[&base[..], &["--tv", "1.5", "--nv", "5000", "--continuity", "c1"]].concat(), "n_v <");
    fails(&[&base[..], &["--tv", "1.5", "--av", "1", "--continuity", "c2"]].concat(), "leave out");
    fails(&[&base[..], &["--tv", "1.5", "--av", "1", "--nv", "2", "--continuity", "c1"]].concat(), "leave out --av");
    fails(&[&base[..], &["--tv", "1.5", "--nv", "2"]].concat(), "needs --av and --nv");
}

/// FK of the app's arm (l2 = l3 = 1), written out here: the base turns the
/// planar (ρ, z) = (cos θ2 + cos(θ2 + θ3), sin θ2 + sin(θ2 + θ3)).
fn fk(th1: f64, th2: f64, th3: f64) -> [f64; 3] {
    let (rho, z) = (th2.cos() + (th2 + th3).cos(), th2.sin() + (th2 + th3).sin());
    [rho * th1.cos(), rho * th1.sin(), z]
}

/// The firmware's default law: ζ-a-tₛ with n = 2 and the smooth stop of
/// T₀ = 1.5 s, run over tₛ (the independent f64 reference).
fn scaled_zat(t: f64, ts: f64) -> f64 {
    let t0: f64 = 1.5;
    Zat::new(t0, t0 - t0.log2(), 2.0).g(t * t0 / ts)
}

#[test]
fn path_line_follows_the_segment_paced_by_the_law() {
    let (a, b) = ([1.0, 0.3, 0.2], [-0.4, 0.9, 0.7]);
    let (header, rows) =
        csv(&["path", "line", "--from", "1,0.3,0.2", "--to", "-0.4,0.9,0.7", "--ts", "3", "--samples", "61"]);
    assert_eq!(header, ["t", "x", "y", "z", "th1", "th2", "th3"]);
    assert_eq!(rows.len(), 61);
    for r in &rows {
        let g = scaled_zat(r[0], 3.0);
        // P(t) = P_a + (P_b − P_a)·g(t).
        for i in 0..3 {
            assert!((r[1 + i] - (a[i] + (b[i] - a[i]) * g)).abs() < 1e-13, "t {}: {r:?} vs g = {g}", r[0]);
        }
        // FK(IK(P(t))) = P(t), with θ1 the direction of P in the top view.
        let p = fk(r[4], r[5], r[6]);
        assert!((0..3).all(|i| (p[i] - r[1 + i]).abs() < 1e-13), "{p:?} vs {r:?}");
        assert!((r[4] - r[2].atan2(r[1])).abs() < 1e-15);
        // Elbow up, inside the servo defaults' ranges.
        assert!(r[6] <= 0.0 && r[6] >= -PI && (0.0..=PI).contains(&r[5]));
    }
    assert_eq!(&rows[0][1..4], &a[..]);
    assert_eq!(&rows[60][1..4], &b[..]);
}

#[test]
fn path_circle_is_one_turn_in_the_arms_vertical_plane() {
    let (c, r) = ([0.8, 0.6, 0.4], 0.2);
    let (_, rows) = csv(&[
        "path",
        "circle",
        "--center",
        "0.8,0.6,0.4",
        "--radius",
        "0.2",
        "--ts",
        "4",
        "--law",
        "quintic",
        "--samples",
        "81",
    ]);
    for row in &rows {
        let d = ((row[1] - c[0]).powi(2) + (row[2] - c[1]).powi(2) + (row[3] - c[2]).powi(2)).sqrt();
        assert!((d - r).abs() < 1e-14, "{row:?}");
        // In the vertical plane through the base axis and C: θ1 constant.
        assert!((row[4] - 0.6f64.atan2(0.8)).abs() < 1e-14);
        let p = fk(row[4], row[5], row[6]);
        assert!((0..3).all(|i| (p[i] - row[1 + i]).abs() < 1e-13));
        // The angle round the centre is 2π·quintic(t/tₛ).
        let tau = row[0] / 4.0;
        let g = 10.0 * tau.powi(3) - 15.0 * tau.powi(4) + 6.0 * tau.powi(5);
        let (radial, up) = (((row[1] - c[0]) * 0.8 + (row[2] - c[1]) * 0.6) / r, (row[3] - c[2]) / r);
        let want = 2.0 * PI * g;
        assert!((radial - want.cos()).abs() < 1e-12 && (up - want.sin()).abs() < 1e-12, "t {}", row[0]);
    }
    // Starts farthest out and comes back there.
    let (first, last) = (&rows[0], &rows[80]);
    assert!((first[1] - 0.96).abs() < 1e-15 && (first[2] - 0.72).abs() < 1e-15 && first[3] == 0.4);
    assert!((0..7).skip(1).all(|i| (first[i] - last[i]).abs() < 1e-13));
}

#[test]
fn path_limits_refuse_or_slow_down() {
    let line = ["path", "line", "--from", "1,0.3,0.2", "--to", "-0.4,0.9,0.7"];
    // At 0.5 s the base would exceed the default 3 rad/s: refused with the shortest tₛ.
    fails(&[&line[..], &["--ts", "0.5", "--samples", "3"]].concat(), "base speed limit: the path needs ts >=");
    let v = json(&[&line[..], &["--ts", "0.5", "--slow-down", "--info"]].concat());
    assert_eq!(v["slowed"], true);
    let ts = f(&v, "ts");
    let peak = v["peak_speed"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).fold(0.0, f64::max);
    assert!(peak <= 3.0 && peak > 2.999, "{v}");
    // The slowed duration is admissible without slowing; a bit less is refused.
    let v2 = json(&[&line[..], &["--ts", &format!("{ts}"), "--info"]].concat());
    assert_eq!(v2["slowed"], false);
    fails(&[&line[..], &["--ts", &format!("{}", ts * 0.999), "--info"]].concat(), "speed limit");
    // Stricter limits lengthen it further.
    let v3 = json(
        &[&line[..], &["--ts", "0.5", "--slow-down", "--max-speed", "1.5", "--max-accel", "4", "--info"]].concat(),
    );
    assert!(f(&v3, "ts") > ts);
    // Geometry: through the base axis, out of reach, behind the base, a circle reaching the axis.
    fails(
        &["path", "line", "--from", "0.5,0.5,0.2", "--to", "-0.5,-0.5,0.9", "--ts", "3", "--samples", "3"],
        "base axis",
    );
    fails(&["path", "line", "--from", "1,0.5,0.2", "--to", "1,2,0.2", "--ts", "3", "--samples", "3"], "reach");
    fails(
        &["path", "line", "--from", "1,0.5,0.2", "--to", "1,-0.5,0.2", "--ts", "3", "--samples", "3"],
        "base joint limit",
    );
    fails(
        &["path", "circle", "--center", "0.3,0.4,0.5", "--radius", "0.5", "--ts", "3", "--samples", "3"],
        "base axis",
    );
    fails(&["path", "circle", "--center", "0.3,0.4,0.5", "--radius", "0", "--ts", "3", "--samples", "3"], "radius");
    fails(&["path", "line", "--from", "1,0.5", "--to", "1,2,0.2", "--ts", "3", "--samples", "3"], "X,Y,Z");
    fails(&[&line[..], &["--ts", "3", "--max-speed", "0", "--info"]].concat(), "--max-speed");
    fails(&[&line[..], &["--ts", "-1", "--info"]].concat(), "duration");
}

#[test]
fn plot_path_draws_the_views() {
    let dir = std::env::temp_dir().join(format!("armsim-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (kind, args) in [
        ("line", &["line", "--from", "1,0.3,0.2", "--to", "-0.4,0.9,0.7", "--ts", "3"][..]),
        ("circle", &["circle", "--center", "0.8,0.6,0.4", "--radius", "0.2", "--ts", "4"][..]),
    ] {
        let out = dir.join(format!("{kind}.png"));
        let (code, stdout, err) = armsim(&[&["plot", "path"][..], args, &["--out", out.to_str().unwrap()]].concat());
        assert_eq!(code, 0, "{err}");
        assert!(stdout.starts_with("wrote "));
        let png = std::fs::read(&out).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        assert!(png.len() > 10_000, "{kind}: {} bytes", png.len());
    }
    std::fs::remove_dir_all(&dir).ok();
}
