//! Stacked time-series panels (position, velocity, acceleration, jerk), like the
//! source papers' figures, to PNG or SVG by the output file's extension.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

/// One curve in a panel.
pub struct Curve<'a> {
    /// The legend's label.
    pub label: &'a str,
    /// One value per time of the shared axis.
    pub y: &'a [f64],
}

/// One panel: a y-axis label and its curves, all over the shared time axis.
pub struct Panel<'a> {
    /// The y-axis label.
    pub ylabel: &'a str,
    /// The curves drawn in the panel.
    pub curves: Vec<Curve<'a>>,
}

#[derive(Debug)]
/// Why a plot was not written.
pub enum PlotError {
    /// Neither .png nor .svg.
    UnknownFormat,
    /// The embedded font did not register with plotters.
    NoFont,
    /// No time samples or no panels.
    Empty,
    /// plotters failed to draw or write the file.
    Draw(String),
}

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlotError::UnknownFormat => write!(f, "plot output must end in .png or .svg"),
            PlotError::NoFont => write!(f, "the embedded font (DejaVu Sans) did not load"),
            PlotError::Empty => write!(f, "nothing to plot"),
            PlotError::Draw(e) => write!(f, "plot failed: {e}"),
        }
    }
}

impl std::error::Error for PlotError {}

/// DejaVu Sans, embedded so the plots draw their text on every OS without a
/// font installed (assets/LICENSE-DejaVu.txt: free to redistribute).
const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// plotters' ab_glyph backend needs the font bytes registered once per process.
fn ensure_font() -> Result<(), PlotError> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    if *REGISTERED.get_or_init(|| register_font("sans-serif", FontStyle::Normal, FONT).is_ok()) {
        Ok(())
    } else {
        Err(PlotError::NoFont)
    }
}

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// Draws `panels` stacked vertically over the common time axis `t`.
pub fn panels(out: &Path, title: &str, t: &[f64], panels: &[Panel<'_>]) -> Result<(), PlotError> {
    if t.is_empty() || panels.is_empty() {
        return Err(PlotError::Empty);
    }
    ensure_font()?;
    let size = (900, 260 * panels.len() as u32 + 40);
    match out.extension().and_then(|e| e.to_str()) {
        Some("png") => draw(BitMapBackend::new(out, size).into_drawing_area(), title, t, panels),
        Some("svg") => draw(SVGBackend::new(out, size).into_drawing_area(), title, t, panels),
        _ => Err(PlotError::UnknownFormat),
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    t: &[f64],
    panels: &[Panel<'_>],
) -> Result<(), PlotError> {
    let err = |e: &dyn std::fmt::Debug| PlotError::Draw(format!("{e:?}"));
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(|e| err(&e))?;
    let areas = root.split_evenly((panels.len(), 1));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, t, panel)?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// One time-series panel over the time axis `t` (shared by every figure).
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    t: &[f64],
    panel: &Panel<'_>,
) -> Result<(), PlotError> {
    let err = |e: &dyn std::fmt::Debug| PlotError::Draw(format!("{e:?}"));
    let (t0, t1) = range(t.iter().copied());
    let (lo, hi) = range(panel.curves.iter().flat_map(|c| c.y.iter().copied()));
    let pad = ((hi - lo) * 0.08).max(1e-9);
    let mut chart = ChartBuilder::on(area)
        .margin(8)
        .x_label_area_size(32)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("t [s]")
        .y_desc(panel.ylabel)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| err(&e))?;
    for (i, c) in panel.curves.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        chart
            .draw_series(LineSeries::new(
                t.iter().copied().zip(c.y.iter().copied()).filter(|(_, y)| y.is_finite()),
                color.stroke_width(2),
            ))
            .map_err(|e| err(&e))?
            .label(c.label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
    }
    if panel.curves.len() > 1 || !panel.curves[0].label.is_empty() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// Finite min/max of the values; a flat or empty set gets a unit-wide range.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        (0.0, 1.0)
    } else if hi - lo < 1e-12 {
        (lo - 0.5, hi + 0.5)
    } else {
        (lo, hi)
    }
}

/// One projection of a path (top or side view), with labelled marks
/// (start, via, target).
pub struct View<'a> {
    /// The view's caption (e.g. "top view").
    pub title: &'a str,
    /// The horizontal axis' label.
    pub xlabel: &'a str,
    /// The vertical axis' label.
    pub ylabel: &'a str,
    /// The path's horizontal coordinates.
    pub x: &'a [f64],
    /// The path's vertical coordinates, one per x.
    pub y: &'a [f64],
    /// Labelled points drawn over the path: (label, x, y).
    pub marks: Vec<(&'a str, f64, f64)>,
}

/// A path figure: two views side by side above a time-series panel (the
/// joint angles), to PNG or SVG by the extension.
pub fn path_figure(
    out: &Path,
    title: &str,
    views: &[View<'_>; 2],
    t: &[f64],
    panel: &Panel<'_>,
) -> Result<(), PlotError> {
    if t.is_empty() || views.iter().any(|v| v.x.is_empty()) {
        return Err(PlotError::Empty);
    }
    ensure_font()?;
    let size = (1000, 900);
    match out.extension().and_then(|e| e.to_str()) {
        Some("png") => draw_path(BitMapBackend::new(out, size).into_drawing_area(), title, views, t, panel),
        Some("svg") => draw_path(SVGBackend::new(out, size).into_drawing_area(), title, views, t, panel),
        _ => Err(PlotError::UnknownFormat),
    }
}

fn draw_path<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    views: &[View<'_>; 2],
    t: &[f64],
    panel: &Panel<'_>,
) -> Result<(), PlotError> {
    let err = |e: &dyn std::fmt::Debug| PlotError::Draw(format!("{e:?}"));
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(|e| err(&e))?;
    let (top, bottom) = root.split_vertically(520);
    let halves = top.split_evenly((1, 2));
    for (area, v) in halves.iter().zip(views) {
        draw_view(area, v)?;
    }
    draw_panel(&bottom, t, panel)?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// A view with equal scales on both axes, so a straight path looks straight
/// and a circle round.
fn draw_view<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    v: &View<'_>,
) -> Result<(), PlotError> {
    let err = |e: &dyn std::fmt::Debug| PlotError::Draw(format!("{e:?}"));
    let (x0, x1) = range(v.x.iter().copied().chain(v.marks.iter().map(|m| m.1)));
    let (y0, y1) = range(v.y.iter().copied().chain(v.marks.iter().map(|m| m.2)));
    let half = ((x1 - x0).max(y1 - y0) * 0.6).max(1e-6);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let mut chart = ChartBuilder::on(area)
        .caption(v.title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(32)
        .y_label_area_size(60)
        .build_cartesian_2d((cx - half)..(cx + half), (cy - half)..(cy + half))
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(v.xlabel)
        .y_desc(v.ylabel)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| err(&e))?;
    chart
        .draw_series(LineSeries::new(
            v.x.iter().copied().zip(v.y.iter().copied()).filter(|(x, y)| x.is_finite() && y.is_finite()),
            COLORS[0].stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
    for (i, (label, x, y)) in v.marks.iter().enumerate() {
        let color = COLORS[(i + 1) % COLORS.len()];
        chart
            .draw_series(std::iter::once(Circle::new((*x, *y), 5, color.filled())))
            .map_err(|e| err(&e))?
            .label(*label)
            .legend(move |(x, y)| Circle::new((x + 9, y), 5, color.filled()));
    }
    if !v.marks.is_empty() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The embedded font is a TrueType file (sfnt version 1.0) and plotters
    /// takes it, so no system font is needed.
    #[test]
    fn embedded_font_is_truetype_and_registers() {
        assert_eq!(&FONT[..4], &[0, 1, 0, 0]);
        assert!(ensure_font().is_ok());
    }
}
