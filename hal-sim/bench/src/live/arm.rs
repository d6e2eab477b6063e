//! The arm the page draws: joint angles from the measured servo pulses
//! through the default calibration, joint positions by forward kinematics,
//! the touched target by the host's f64 chain, and the region of the map
//! the arm can reach.

use touch_arm::geometry::ik::Links;
use touch_arm::servo::map::ServoMap;
use touch_arm::touch::map::Calibration;
use touch_arm::ui::layout::Layout;

use hal_sim::arm::effector;
use touch_arm_rig::firmware::{self, HostTarget};

/// The paper's geometry, as the firmware uses it (k = l2 = l3 = 1).
pub const L2: f64 = 1.0;
pub const L3: f64 = 1.0;

/// The arm as measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmPose {
    pub angles_deg: [f64; 3],
    /// Elbow and tip in the arm's plane: (reach from the base axis, height
    /// above the shoulder).
    pub elbow: [f64; 2],
    pub tip: [f64; 2],
}

/// Angle of a measured pulse width. `ServoMap::pulse_to_angle` takes whole
/// microseconds; the pins are measured to 1/16 µs, and rounding would put
/// 0.1° steps into the velocity plot, so the same line is evaluated here on
/// the fractional width.
pub fn pulse_to_angle_deg(map: &ServoMap, us: f64) -> f64 {
    let c = map.cal();
    ((us - f64::from(c.offset_us)) / f64::from(c.us_per_rad)).to_degrees()
}

/// Angles and joint positions for measured pulses (µs), joint order base,
/// shoulder, elbow.
pub fn pose_from_pulses(maps: &[ServoMap; 3], pulses_us: [f64; 3]) -> ArmPose {
    let angles_deg: [f64; 3] = std::array::from_fn(|j| pulse_to_angle_deg(&maps[j], pulses_us[j]));
    let rad = angles_deg.map(f64::to_radians);
    let links = Links::new(L2, L3).expect("unit links are valid");
    let e = effector(&links, &rad);
    ArmPose { angles_deg, elbow: [L2 * rad[1].cos(), L2 * rad[1].sin()], tip: [e.reach, e.height] }
}

/// A touch on the screen's map: the pixel, the workspace point the firmware
/// takes from it (the pixel's centre), the host's chain for that point, and
/// the firmware's reason if it refused the touch.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    pub px: (i16, i16),
    pub x_p: f64,
    pub y_p: f64,
    pub host: HostTarget,
    pub refused: Option<String>,
}

/// The target a press at screen pixel (x, y) picks, if the pixel is on the map.
pub fn target_at_pixel(lay: &Layout, x: i16, y: i16) -> Option<Target> {
    let (x_p, y_p) = lay.ws_pixel_to_point(x, y)?;
    let (x_p, y_p) = (f64::from(x_p), f64::from(y_p));
    let host = firmware::host_target(x_p, y_p).ok()?;
    Some(Target { px: (x, y), x_p, y_p, host, refused: None })
}

/// What a line from the firmware says about the arm's target.
#[derive(Debug, Clone, PartialEq)]
pub enum TargetNews {
    /// `info touch <x> <y> …` or `err touch <x> <y> <reason>`: the touch the
    /// firmware confirmed (raw panel reading, default calibration), which
    /// is where the finger came to rest, not where a drag began.
    Touched(Target),
    /// `ok goto` / `ok move`: a target set over the serial port.
    Cleared,
}

/// The map point a raw reading names through `cal` on a screen laid out as
/// `lay` (the firmware's own chain: calibration, panel to pixel, pixel to
/// the map).
fn raw_to_map_point(cal: &Calibration, lay: &Layout, raw_x: u16, raw_y: u16) -> Option<(f64, f64)> {
    let m = cal.map::<f32>(raw_x, raw_y).ok()?;
    let (px, py) = lay.panel_to_pixel(m.x_p, m.y_p)?;
    let (wx, wy) = lay.ws_pixel_to_point(px, py)?;
    Some((f64::from(wx), f64::from(wy)))
}

/// What `line` says about the target, read with the touch calibration the
/// firmware runs with and the screen's layout.
pub fn target_news(cal: &Calibration, lay: &Layout, line: &str) -> Option<TargetNews> {
    if line.starts_with("ok goto ") || line.starts_with("ok move ") {
        return Some(TargetNews::Cleared);
    }
    let (rest, refused) = match (line.strip_prefix("info touch "), line.strip_prefix("err touch ")) {
        (Some(r), _) => (r, false),
        (_, Some(r)) => (r, true),
        _ => return None,
    };
    let mut words = rest.split_whitespace();
    let raw_x: u16 = words.next()?.parse().ok()?;
    let raw_y: u16 = words.next()?.parse().ok()?;
    let (x_p, y_p) = raw_to_map_point(cal, lay, raw_x, raw_y)?;
    let px = lay.ws_point_to_pixel(x_p as f32, y_p as f32)?;
    let host = firmware::host_target(x_p, y_p).ok()?;
    let refused = refused.then(|| words.collect::<Vec<_>>().join(" "));
    Some(TargetNews::Touched(Target { px, x_p, y_p, host, refused }))
}

impl Target {
    pub fn to_json(&self) -> serde_json::Value {
        let h = &self.host;
        serde_json::json!({
            "px": [self.px.0, self.px.1],
            "x_p": self.x_p,
            "y_p": self.y_p,
            "condition": h.pose.condition.number(),
            "alpha_deg": h.pose.alpha.to_degrees(),
            "reach": h.pose.reach,
            "height": h.pose.height,
            "angles_deg": h.q.map(f64::to_degrees),
            "pulses_us": h.pulses_us,
            "within_limits": h.within_limits,
            "refused": self.refused,
        })
    }
}

/// Which map pixels the arm can reach: one string per map row, top row
/// first, `1` where the host chain gives a pose within every joint's limits.
pub fn reach_rows(lay: &Layout) -> Vec<String> {
    let ws = lay.ws();
    (ws.y..ws.bottom())
        .map(|y| {
            (ws.x..ws.right())
                .map(|x| if target_at_pixel(lay, x, y).is_some_and(|t| t.host.within_limits) { '1' } else { '0' })
                .collect()
        })
        .collect()
}

/// What the page needs to draw the views, sent once.
pub fn geometry_json(lay: &Layout) -> serde_json::Value {
    let ws = lay.ws();
    serde_json::json!({
        "l2": L2,
        "l3": L3,
        "screen": [lay.width(), lay.height()],
        "map": { "x": ws.x, "y": ws.y, "w": ws.w, "h": ws.h, "scale": lay.scale(), "origin_x": lay.ws_origin_x() },
        "reach_rows": reach_rows(lay),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::live::LAYOUT;

    #[test]
    fn home_pulses_give_the_home_pose() {
        let maps = firmware::default_servo_maps().unwrap();
        let p = pose_from_pulses(&maps, [1500.0, 1500.0, 1500.0]);
        // The calibration's µs per radian is an f32: 1e-5° off.
        for (got, want) in p.angles_deg.iter().zip([90.0, 90.0, -90.0]) {
            assert!((got - want).abs() < 1e-4, "{:?}", p.angles_deg);
        }
        // Upper arm straight up, forearm bent forward: elbow (0, 1), tip (1, 1).
        assert!(p.elbow[0].abs() < 1e-6 && (p.elbow[1] - 1.0).abs() < 1e-6, "{:?}", p.elbow);
        assert!((p.tip[0] - 1.0).abs() < 1e-6 && (p.tip[1] - 1.0).abs() < 1e-6, "{:?}", p.tip);
    }

    #[test]
    fn a_map_pixel_targets_its_centre_through_the_host_chain() {
        let (x, y) = LAYOUT.ws_point_to_pixel(0.4, 0.6).unwrap();
        let t = target_at_pixel(&LAYOUT, x, y).unwrap();
        let h = firmware::host_target(t.x_p, t.y_p).unwrap();
        assert_eq!(t.host, h);
        assert!((t.x_p - 0.4).abs() < 0.01 && (t.y_p - 0.6).abs() < 0.01);
        assert!(target_at_pixel(&LAYOUT, 300, 50).is_none(), "STOP is not on the map");
        let target_news = |l: &str| target_news(&Calibration::DEFAULT, &LAYOUT, l);
        // The firmware's own report of the same touch names the same target.
        let ((rx, ry), _) = firmware::map_touch(0.4, 0.6).unwrap();
        let line = format!("info touch {rx} {ry} cond 2 ts_ms 2498");
        assert_eq!(target_news(&line), Some(TargetNews::Touched(t.clone())));
        let Some(TargetNews::Touched(r)) = target_news(&format!("err touch {rx} {ry} joint limit elbow")) else {
            panic!()
        };
        assert_eq!(r.refused.as_deref(), Some("joint limit elbow"));
        assert_eq!(target_news("ok goto ts_ms 3064"), Some(TargetNews::Cleared));
        assert_eq!(target_news("info touch-arm 0.1.0 reset power-on"), None);
        let rows = reach_rows(&LAYOUT);
        assert_eq!((rows.len(), rows[0].len()), (112, 224));
        assert!(rows.iter().any(|r| r.contains('1')));
    }
}
