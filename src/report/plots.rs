//! Per-feature plots that are plain x-y charts: deviation along the section
//! and the timeline of attempts and corrections.

use super::markup::{fixed, json_name};
use super::model::{CorrectionReport, FeatureReport, Tolerance};
use super::svg::{empty_plot, padded, range, Frame, Svg, MARGIN_BOTTOM, MARGIN_TOP};

/// Width of the deviation plot and the timeline, px.
pub const PLOT_WIDTH: f64 = 1000.0;
/// Height of the deviation plot, px.
pub const DEVIATION_HEIGHT: f64 = 300.0;
/// Height of a placeholder plot that only says why it is empty, px.
pub const EMPTY_PLOT_HEIGHT: f64 = 80.0;
/// Radius of a point marker in the deviation plot, px.
const MARKER_RADIUS: f64 = 2.5;
/// Fraction of the data range added above and below, so markers stay inside.
const PAD_FRACTION: f64 = 0.08;
/// Height of one attempt's row in the timeline, px.
const ROW_HEIGHT: f64 = 30.0;
/// Height of a bar in its row, px.
const BAR_HEIGHT: f64 = 18.0;
/// Height of one line of the correction legend under the timeline, px.
const LEGEND_LINE: f64 = 18.0;
/// Decimals of deviations (mm) in labels: 0.1 um.
const MM_DECIMALS: usize = 4;

/// Whether a deviation lies outside the tolerance band.
pub fn out_of_tolerance(deviation: f64, tolerance: Tolerance) -> bool {
    !(tolerance.lower..=tolerance.upper).contains(&deviation)
}

/// The x position of every point: cumulative arc length of the measured
/// points (mm) for scans, the point index for touch points or when all
/// points coincide. Returns the positions and the axis title.
fn positions(feature: &FeatureReport) -> (Vec<f64>, &'static str) {
    let mut total = 0.0;
    let mut arc = Vec::with_capacity(feature.points.len());
    let mut previous: Option<[f64; 3]> = None;
    for point in &feature.points {
        if let Some(p) = previous {
            total += distance(p, point.measured);
        }
        arc.push(total);
        previous = Some(point.measured);
    }
    if feature.kind == "touch_points" || !(total > 0.0) {
        let index = (0..feature.points.len()).map(|i| i as f64).collect();
        return (index, "point index");
    }
    (arc, "arc length of the measured points (mm)")
}

/// Euclidean distance of two points.
fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Deviation (y) along the section (x) with the tolerance band shaded, the
/// zero line, and points outside the band in red.
pub fn deviation_plot(feature: &FeatureReport) -> String {
    let title = format!("{}: deviation along the section", feature.name);
    if feature.points.is_empty() {
        return empty_plot(PLOT_WIDTH, EMPTY_PLOT_HEIGHT, &title, "no points measured");
    }
    let (xs, x_title) = positions(feature);
    let tol = feature.tolerance_mm;
    let devs = feature.points.iter().map(|p| p.deviation_mm);
    let y = range(devs.chain([tol.lower, tol.upper, 0.0])).unwrap_or((-1.0, 1.0));
    let x = range(xs.iter().copied()).unwrap_or((0.0, 1.0));
    let frame = Frame::new(
        PLOT_WIDTH,
        DEVIATION_HEIGHT,
        padded(x.0, x.1, 0.02),
        padded(y.0, y.1, PAD_FRACTION),
    );
    let mut svg = Svg::new(PLOT_WIDTH, DEVIATION_HEIGHT, &title);
    draw_band(&mut svg, &frame, tol);
    frame.draw_axes(&mut svg, x_title, "deviation (mm)");
    let (x0, x1) = (frame.x.lo, frame.x.hi);
    svg.line(frame.map(x0, 0.0), frame.map(x1, 0.0), "zero");
    draw_points(&mut svg, &frame, &xs, feature);
    svg.text(
        (PLOT_WIDTH - 20.0, 18.0),
        "end",
        "legend",
        &deviation_legend(feature),
    );
    svg.finish()
}

/// The shaded tolerance band with its limit lines.
fn draw_band(svg: &mut Svg, frame: &Frame, tol: Tolerance) {
    let (x0, x1) = (frame.x.lo, frame.x.hi);
    let (left, top) = frame.map(x0, tol.upper);
    let (right, bottom) = frame.map(x1, tol.lower);
    svg.rect((left, top), (right - left, bottom - top), "band");
    svg.line((left, top), (right, top), "limit");
    svg.line((left, bottom), (right, bottom), "limit");
}

/// The deviation trace and one marker per point.
fn draw_points(svg: &mut Svg, frame: &Frame, xs: &[f64], feature: &FeatureReport) {
    let pixels: Vec<(f64, f64)> = xs
        .iter()
        .zip(&feature.points)
        .map(|(x, p)| frame.map(*x, p.deviation_mm))
        .collect();
    if feature.kind != "touch_points" {
        svg.polyline(&pixels, "trace");
    }
    for (pixel, point) in pixels.iter().zip(&feature.points) {
        let out = out_of_tolerance(point.deviation_mm, feature.tolerance_mm);
        svg.circle(*pixel, MARKER_RADIUS, if out { "pt-out" } else { "pt-in" });
    }
}

/// "12 points, 3 outside tolerance -0.0500..0.0500 mm".
fn deviation_legend(feature: &FeatureReport) -> String {
    let tol = feature.tolerance_mm;
    let outside = feature
        .points
        .iter()
        .filter(|p| out_of_tolerance(p.deviation_mm, tol))
        .count();
    format!(
        "{} points, {outside} outside tolerance {}..{} mm (shaded)",
        feature.points.len(),
        fixed(tol.lower, MM_DECIMALS),
        fixed(tol.upper, MM_DECIMALS)
    )
}

/// Start and end machine time of every attempt, cumulative from 0 s.
fn attempt_spans(feature: &FeatureReport) -> Vec<(f64, f64)> {
    let mut start = 0.0;
    let mut spans = Vec::with_capacity(feature.attempts.len());
    for attempt in &feature.attempts {
        let end = start + attempt.machine_time_s.max(0.0);
        spans.push((start, end));
        start = end;
    }
    spans
}

/// Height of the timeline for a feature, px.
fn timeline_height(feature: &FeatureReport) -> f64 {
    let rows = feature.attempts.len() as f64 * ROW_HEIGHT;
    let legend = feature.corrections.len() as f64 * LEGEND_LINE;
    MARGIN_TOP + rows + MARGIN_BOTTOM + legend + 10.0
}

/// Attempts as horizontal bars over cumulative machine time (one row each,
/// coloured by outcome, labelled mode, outcome and time), corrections as
/// numbered diamonds on the boundary after the attempt they followed.
///
/// The model does not record which gap a correction belongs to; correction
/// `k` is drawn after attempt `k` (the usual attempt, correct, retry cycle),
/// surplus corrections after the last attempt.
pub fn timeline_plot(feature: &FeatureReport) -> String {
    let title = format!("{}: attempts and corrections", feature.name);
    if feature.attempts.is_empty() {
        return empty_plot(
            PLOT_WIDTH,
            EMPTY_PLOT_HEIGHT,
            &title,
            "no measuring attempt",
        );
    }
    let height = timeline_height(feature);
    let spans = attempt_spans(feature);
    let total = spans.last().map_or(0.0, |s| s.1);
    let rows = (feature.attempts.len() as f64, 0.0);
    let legend = feature.corrections.len() as f64 * LEGEND_LINE;
    let frame = Frame::new(PLOT_WIDTH, height - legend, padded(0.0, total, 0.0), rows);
    let mut svg = Svg::new(PLOT_WIDTH, height, &title);
    frame.draw_x_axis(&mut svg, "cumulative machine time (s)");
    draw_bars(&mut svg, &frame, feature, &spans);
    draw_corrections(&mut svg, &frame, feature, &spans, height - legend);
    svg.finish()
}

/// One bar per attempt with its label.
fn draw_bars(svg: &mut Svg, frame: &Frame, feature: &FeatureReport, spans: &[(f64, f64)]) {
    for (row, (attempt, span)) in feature.attempts.iter().zip(spans).enumerate() {
        let centre = frame.y.map(row as f64 + 0.5);
        let (left, right) = (frame.x.map(span.0), frame.x.map(span.1));
        let outcome = json_name(&attempt.outcome);
        let class = if outcome == "completed" {
            "bar-ok"
        } else {
            "bar-bad"
        };
        let top = centre - BAR_HEIGHT / 2.0;
        svg.rect((left, top), ((right - left).max(1.0), BAR_HEIGHT), class);
        let label = format!(
            "#{} {}: {}, {} s, {} points",
            row + 1,
            attempt.mode,
            outcome,
            fixed(attempt.machine_time_s, 2),
            attempt.points
        );
        let (x, anchor) = label_place(frame, left, right);
        svg.text((x, centre + 4.0), anchor, "label", &label);
    }
}

/// Where a bar's label goes: inside from its left end when the bar is wide,
/// else right of the bar, or left of it near the right edge.
fn label_place(frame: &Frame, left: f64, right: f64) -> (f64, &'static str) {
    /// Room a label needs, px.
    const LABEL_PX: f64 = 330.0;
    if right - left >= LABEL_PX {
        (left + 6.0, "start")
    } else if frame.x.px_hi - right >= LABEL_PX {
        (right + 10.0, "start")
    } else {
        (left - 10.0, "end")
    }
}

/// Correction markers and their legend below the axis.
fn draw_corrections(
    svg: &mut Svg,
    frame: &Frame,
    feature: &FeatureReport,
    spans: &[(f64, f64)],
    legend_top: f64,
) {
    let (top, bottom) = (frame.y.px_hi, frame.y.px_lo);
    for (k, correction) in feature.corrections.iter().enumerate() {
        let time = spans.get(k).or(spans.last()).map_or(0.0, |s| s.1);
        let x = frame.x.map(time);
        svg.line((x, top), (x, bottom), "corr-line");
        let (d, y) = (6.0, top - 10.0);
        svg.polygon(&[(x, y - d), (x + d, y), (x, y + d), (x - d, y)], "corr");
        svg.text(
            (x + d + 2.0, y + 4.0),
            "start",
            "corr-label",
            &format!("C{}", k + 1),
        );
        let line_y = legend_top + (k as f64 + 0.8) * LEGEND_LINE;
        let text = format!("C{}: {}", k + 1, correction_text(correction));
        svg.text((frame.x.px_lo, line_y), "start", "label", &text);
    }
}

/// A correction in words.
pub fn correction_text(correction: &CorrectionReport) -> String {
    match correction {
        CorrectionReport::Geometric {
            model,
            max_residual_mm,
            points,
            source,
        } => format!(
            "geometric correction ({model}, {source}), max residual {} mm over {points} touch points",
            fixed(*max_residual_mm, MM_DECIMALS)
        ),
        CorrectionReport::Autonomous { points } => {
            format!("design data replaced by an autonomous scan ({points} points)")
        }
    }
}
