//! What each bench routine is, in the report's words, and the cycle targets
//! the issue set.

/// A routine's row label; unknown names are shown as they are.
pub fn describe(name: &str) -> &str {
    DESCRIPTIONS.iter().find(|(n, _)| *n == name).map_or(name, |(_, d)| d)
}

/// The median target (for `frame` and `path_frame`: their max, see [`judged`]), if any.
pub fn target(name: &str) -> Option<u64> {
    TARGETS.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// The figure a target judges: the median, except for the frames, which must
/// also hold at its worst (a frame that overran would delay the pulses).
pub fn judged(name: &str, median: u64, max: u64) -> u64 {
    if name == "frame" || name == "path_frame" {
        max
    } else {
        median
    }
}

const TARGETS: [(&str, u64); 4] = [("frame", 8000), ("path_frame", 16000), ("plan", 20000), ("via_solve", 20000)];

const DESCRIPTIONS: &[(&str, &str)] = &[
    ("f32_mul", "f32 multiply (avr-libc)"),
    ("f32_add", "f32 add (avr-libc)"),
    ("f32_div", "f32 divide (avr-libc)"),
    ("f32_mul_x10", "10 chained f32 multiplies"),
    ("f32_add_x10", "10 chained f32 adds"),
    ("f32_lt", "f32 compare"),
    ("f32_to_i32", "f32 → i32"),
    ("i32_to_f32", "i32 → f32"),
    ("u32_mul", "u32 × u32 (libgcc)"),
    ("u64_mul_hi", "u64 product, high word (compiler-builtins `__muldi3`)"),
    ("avrlibc_exp", "avr-libc `exp`"),
    ("avrlibc_log", "avr-libc `log`"),
    ("exp", "`exp` (math::exp, integer core)"),
    ("expm1", "`expm1` (math::exp, integer core)"),
    ("ln", "`ln` (math::exp, integer core)"),
    ("libm_powf", "`libm::powf` (Rust libm crate)"),
    ("g", "ζ-a-tₛ G alone"),
    ("g_rate", "ζ-a-tₛ G and G′"),
    ("sample3", "`MultiPlan::sample`: 3 joints, positions + velocities (rad)"),
    ("frame", "**50 Hz frame**: `ServoTrack::frame`, 3 joints, time-scaled ζ-a-tₛ G + G′ → pulse widths + speed check"),
    ("frame_zat_paper", "frame, the papers' ζ-a-tₛ (tₛ in seconds)"),
    (
        "path_frame",
        "**straight-line path frame**: time-scaled ζ-a-tₛ g, the point on the segment, 3-DoF IK (`ik3`), 3 pulses (`TickMap`)",
    ),
    ("via_frame", "via-point frame: Gv and G once, S = q0 + (S_v − q0)·Gv + (S_f − S_v)·G per joint, 3 pulses"),
    (
        "path_check_unit",
        "one unit of a path's plan-time check (`PathCheck::step(1)`: a visit, law + IK + joint rates; or the search for a critical instant)",
    ),
    (
        "path_visit_unit",
        "one unit of it that is a visit (`PathCheck::next_is_visit`: a grid or refinement instant, law + IK + joint rates)",
    ),
    (
        "path_bound_unit",
        "one unit of a path check's bounds between its samples (issue #24, F4: a stretch's far end visited, the interval bound of the path rates, the law's cell bounds)",
    ),
    (
        "lift_check_unit",
        "one unit of a lift's check (`LiftCheck::step(1)`: a vertex of the scan's hulls, 3 joints; the last also the duration)",
    ),
    ("lift_frame", "lift frame on the chip: `LiftPlan::angles` (both shapes' G, 3 joints), 3 pulses (`TickMap`)"),
    ("frame_superposed", "frame with a correction superposed: two ζ-a-tₛ terms → pulse widths"),
    (
        "app_replan",
        "**a re-plan mid-move**: correction superposed on the running move (`ServoTrack::replan`: cell bounds, duration search, in place)",
    ),
    (
        "app_plan_move_paper",
        "the app's plan per touch for `law zat-paper` (tₛ search for the speed bound, a*, the largest G″ for the acceleration)",
    ),
    ("frame_generic", "same frame via `MultiPlan::sample` + `ServoMap::angle_to_pulse` ×3"),
    ("frame_linear", "frame, linear law"),
    ("frame_cubic", "frame, cubic law"),
    ("frame_quintic", "frame, quintic law"),
    ("frame_trapezoid", "frame, trapezoid law"),
    ("paper_frame", "naive printed ζ form, 3 joints, position only (`libm::powf`)"),
    ("plan", "**plan**: touch map + pose (IK) + `Shape::smooth_stop` (a*) + `MultiPlan::with_law` with checks"),
    ("plan_generic", "same plan via `smooth_stop_a` + `MultiPlan::new` (shape and checks built twice)"),
    ("plan_map", "plan step: touch map (`Calibration::map`)"),
    ("plan_pose", "plan step: pose (`pose_for_point`: α, workspace, IK)"),
    ("plan_ik2", "`ik2` alone (its own direction arctangent)"),
    ("plan_alpha", "α alone (`workspace::alpha`)"),
    ("plan_a_star", "`smooth_stop_a` alone"),
    ("shape_new", "`Shape::new` (a = a*)"),
    ("shape_smooth_stop", "plan step: `Shape::smooth_stop` (a*, shape, monotonicity)"),
    ("check_monotone", "`Shape::check_monotone` from scratch"),
    ("multiplan_new", "`MultiPlan::new` (shape + checks + copies)"),
    ("sqrt", "`sqrt` (avr-libc)"),
    ("avrlibc_atan2", "avr-libc `atan2`"),
    ("atan2", "`atan2` (math::atan, integer core)"),
    ("acos", "`acos` (avr-libc; unused, the IK takes atan2)"),
    ("via_solve", "**via point**, closed form + ζ + ζ_v"),
    ("via_new", "`ViaPlan::new` alone (two shapes, r = G(t_v), S_v)"),
    ("via_zeta", "`zat::zeta` from scratch (ViaPlan's ζ reuse the shape)"),
    ("via_paper", "via point, the paper's iteration (tol 1e-5)"),
    (
        "app_plan_move",
        "**the app's plan per touch** (`planner::plan_move`: time-scaled ζ-a-tₛ, closed-form tₛ for speed and acceleration, checks)",
    ),
    ("touch_sample", "**touch sample**: 5 × (X, Y, z1, z2) ADC reads with settle times, shared pins lent and restored"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_and_targets() {
        assert_eq!(describe("g_rate"), "ζ-a-tₛ G and G′");
        assert_eq!(describe("new_routine"), "new_routine");
        assert_eq!((target("frame"), target("plan"), target("g")), (Some(8000), Some(20000), None));
        // The frame is judged on its max, the others on their median.
        assert_eq!(judged("frame", 6778, 7000), 7000);
        assert_eq!((target("path_frame"), judged("path_frame", 15500, 15771)), (Some(16000), 15771));
        assert_eq!(judged("plan", 16849, 69474), 16849);
    }
}
