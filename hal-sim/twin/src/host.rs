//! The host's f64 references for the firmware's chain, shared by the twin,
//! the simavr rig and the main job: where to press the panel to pick a point
//! on the screen's map (the default calibration, `ui::layout`), the workspace
//! point a raw reading picks, and the joint angles and pulses the firmware
//! should command for a point. Pure arithmetic on the core's types: nothing
//! here runs the firmware.

use touch_arm::ui::Layout;

/// Where to press the panel to pick workspace point (x, y) on the screen's
/// map: the raw reading (default calibration) of the centre of the map pixel
/// that shows the point, and that pixel's centre in workspace coordinates,
/// which is the point the firmware sends the arm to (`ui::layout`). On the
/// 320×240 screen; [`map_touch_on`] for another layout.
pub fn map_touch(x: f32, y: f32) -> Option<((f64, f64), (f64, f64))> {
    map_touch_on(&Layout::QVGA, x, y)
}

/// [`map_touch`] on a screen laid out as `lay`.
pub fn map_touch_on(lay: &Layout, x: f32, y: f32) -> Option<((f64, f64), (f64, f64))> {
    let (px, py) = lay.ws_point_to_pixel(x, y)?;
    let (wx, wy) = lay.ws_pixel_to_point(px, py)?;
    Some((raw_at_pixel(lay, px, py)?, (f64::from(wx), f64::from(wy))))
}

/// The raw reading (default calibration) of a touch on the centre of
/// screen pixel (x, y), rounded to counts.
pub fn raw_at_pixel(lay: &Layout, x: i16, y: i16) -> Option<(f64, f64)> {
    let (panel_x, panel_y) = lay.pixel_center_to_panel(x, y);
    let (raw_x, raw_y) =
        touch_arm::touch::map::Calibration::DEFAULT.unmap_exact::<f64>(f64::from(panel_x), f64::from(panel_y)).ok()?;
    Some((raw_x.round(), raw_y.round()))
}

/// The raw reading of a touch on the centre of screen area `a`.
pub fn raw_at_centre(lay: &Layout, a: touch_arm::ui::draw::Area) -> Option<(f64, f64)> {
    raw_at_pixel(lay, a.x + (a.w / 2) as i16, a.y + (a.h / 2) as i16)
}

/// The workspace point a raw reading picks on the screen's map, if it lands
/// on the map at all (320×240; [`raw_to_map_point_on`] for another layout).
pub fn raw_to_map_point(raw_x: u16, raw_y: u16) -> Option<(f64, f64)> {
    raw_to_map_point_on(&Layout::QVGA, raw_x, raw_y)
}

/// [`raw_to_map_point`] on a screen laid out as `lay`.
pub fn raw_to_map_point_on(lay: &Layout, raw_x: u16, raw_y: u16) -> Option<(f64, f64)> {
    let m = touch_arm::touch::map::Calibration::DEFAULT.map::<f32>(raw_x, raw_y).ok()?;
    let (px, py) = lay.panel_to_pixel(m.x_p, m.y_p)?;
    let (wx, wy) = lay.ws_pixel_to_point(px, py)?;
    Some((f64::from(wx), f64::from(wy)))
}

/// The servo mappings of the default calibration (`Config::DEFAULT`), in
/// joint order base, shoulder, elbow: how the host turns measured pulses
/// back into angles and its own angles into pulses.
pub fn default_servo_maps() -> Result<[touch_arm::servo::map::ServoMap; 3], String> {
    let [b, s, e] = touch_arm::config::settings::Config::DEFAULT.joints;
    let map =
        |j: &touch_arm::servo::map::JointCal| touch_arm::servo::map::ServoMap::new(j).map_err(|e| format!("{e:?}"));
    Ok([map(&b)?, map(&s)?, map(&e)?])
}

/// The host's f64 reference of the chain the firmware runs for a workspace
/// point (method.md §3–6: condition, α, transform, IK with the paper's geometry
/// k = l2 = l3 = 1 and the firmware's elbow branch), and the pulses the
/// default calibration gives those angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HostTarget {
    /// The pose of the point: condition, base angle α and the planar IK angles.
    pub pose: touch_arm::geometry::pose::Pose<f64>,
    /// Joint angles, rad: base α, shoulder q2, elbow q3.
    pub q: [f64; 3],
    /// Pulse per joint, µs (NaN where the angle is not finite).
    pub pulses_us: [f64; 3],
    /// Every angle lies within its joint's limits; the firmware refuses a
    /// target otherwise ("joint limit"), it never clamps one.
    pub within_limits: bool,
}

/// [`HostTarget`] of workspace point (x_p, y_p).
pub fn host_target(x_p: f64, y_p: f64) -> Result<HostTarget, String> {
    use touch_arm::geometry::pose::pose_for_point;
    let geo = host_geometry()?;
    let pose = pose_for_point(&geo, x_p, y_p).map_err(|e| format!("{e:?}"))?;
    let q = [pose.alpha, pose.q2, pose.q3];
    let maps = default_servo_maps()?;
    let mut pulses_us = [f64::NAN; 3];
    let mut within_limits = true;
    for j in 0..3 {
        match maps[j].angle_to_pulse(q[j]) {
            Ok(p) => {
                pulses_us[j] = f64::from(p.us());
                within_limits &= p.clamped.is_none();
            }
            Err(_) => within_limits = false,
        }
    }
    Ok(HostTarget { pose, q, pulses_us, within_limits })
}

/// The firmware's arm ([`touch_arm::app::AppParams::DEFAULT`] with the
/// default [`touch_arm::config::settings::ArmSettings`]) in f64, for the
/// host's references.
pub fn host_geometry() -> Result<touch_arm::geometry::pose::ArmGeometry<f64>, String> {
    let p = touch_arm::app::AppParams::DEFAULT;
    let a = touch_arm::config::settings::ArmSettings::DEFAULT;
    let mm = |cmm: u16| f64::from(cmm) * 0.01;
    touch_arm::geometry::pose::ArmGeometry::from_lengths(f64::from(p.k), mm(a.l2_cmm), mm(a.l3_cmm), p.branch)
        .map_err(|e| format!("{e:?}"))
}

/// Where measured pulses (µs, whole Timer5 ticks) put the effector: each
/// pulse back through its joint's calibration to the angle, then the 3-DoF
/// forward kinematics (x, y horizontal, the base turning by its angle, z up).
pub fn effector_at(
    maps: &[touch_arm::servo::map::ServoMap; 3],
    links: &touch_arm::geometry::ik::Links<f64>,
    pulses_us: &[f64; 3],
) -> [f64; 3] {
    let q: [f64; 3] = std::array::from_fn(|j| maps[j].pulse_to_angle::<f64>((pulses_us[j] * 2.0).round() as u16));
    let (x, y, z) = touch_arm::geometry::ik::fk3(links, q[0], q[1], q[2]);
    [x, y, z]
}
