//! `armsim` as users and scripts call it: outputs parse, numbers match the
//! formulas, bad input exits non-zero with one line naming the problem.

use std::f64::consts::PI;
use std::process::Command;

use serde_json::Value;

fn armsim(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_armsim")).args(args).output().expect("run armsim");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
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
    assert!(err.to_lowercase().contains(&needle.to_lowercase()), "armsim {args:?}: error {err:?} should mention {needle:?}");
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

    // SPEC §2: x_p = (raw − 527.5)/404.5, y_p = (raw − 128)/769.
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
    for (xy, cond, alpha) in [("0.5,0.5", 1, 45.0), ("0,0.5", 2, 90.0), ("-0.5,0.5", 3, 135.0), ("0,0", 1, 0.0), ("-0.9,0.1", 4, 173.65980825409008)] {
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
    }
}

#[test]
fn ik_known_values_and_unreachable() {
    let v = json(&["ik", "--x", "1", "--y", "1"]);
    assert!(f(&v, "q2").abs() < 1e-15 && (f(&v, "q3") - PI / 2.0).abs() < 1e-15);
    let v = json(&["ik", "--x", "2.5", "--y", "0"]);
    assert_eq!(v["reachable"], false);
    assert!(v["q2"].is_null());
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

#[test]
fn plan_unreachable_and_singular_points_report_not_reachable() {
    let v = json(&["plan", "--xy", "0,0"]);
    assert_eq!(v["reachable"], false);
    let v = json(&["plan", "--xy", "1,1", "--k", "2"]);
    assert_eq!(v["reachable"], false);
    assert!(v["q2"].is_null() && v["s3"].is_null());
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
    for cmd in ["map", "ik", "plan"] {
        let (code, out, _) = armsim(&[cmd, "--help"]);
        assert_eq!(code, 0);
        assert!(out.contains("Usage: armsim"), "{cmd}: {out}");
    }
}

#[test]
fn argument_errors_are_a_single_line() {
    let (code, _, err) = armsim(&["map", "--raw", "2000,5"]);
    assert_eq!(code, 2);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("armsim: "), "{err}");
}
