//! Per-feature plots that are plain x-y charts: deviation along the section
//! and the timeline of attempts and corrections.

use super::markup::{fixed, json_name};
use super::model::{AttemptReport, CorrectionReport, FeatureReport, Tolerance};
use super::svg::{
    empty_plot, padded, px_text, range, Frame, PixelTexts, Svg, MARGIN_BOTTOM, MARGIN_TOP,
};
use crate::host::modes::Outcome;

/// Width of the deviation plot and the timeline, px.
pub const PLOT_WIDTH: f64 = 1000.0;
/// Height of the deviation plot, px.
pub const DEVIATION_HEIGHT: f64 = 300.0;
/// Height of a placeholder plot that only says why it is empty, px.
pub const EMPTY_PLOT_HEIGHT: f64 = 80.0;
/// Radius of a point marker in the deviation plot, px.
const MARKER_RADIUS: f64 = 2.5;
/// Fraction of the position range added left and right of the points.
const X_PAD_FRACTION: f64 = 0.02;
/// Fraction of the data range added above and below, so markers stay inside.
const PAD_FRACTION: f64 = 0.08;
/// Height of one attempt's row in the timeline, px.
const ROW_HEIGHT: f64 = 30.0;
/// Height of a bar in its row, px.
const BAR_HEIGHT: f64 = 18.0;
/// Height of one line of the correction legend under the timeline, px.
const LEGEND_LINE: f64 = 18.0;
/// Half-diagonal of a correction marker, px.
const DIAMOND_PX: f64 = 6.0;
/// Typical bytes of one point's marker and trace in the deviation plot.
const POINT_MARKUP_BYTES: usize = 80;
/// Decimals of machine times (s) in labels.
const TIME_DECIMALS: usize = 2;
/// Decimals of deviations (mm) in labels: 0.1 um.
const MM_DECIMALS: usize = 4;

/// Whether a deviation lies outside the tolerance band.
pub fn out_of_tolerance(deviation: f64, tolerance: Tolerance) -> bool {
    !(tolerance.lower..=tolerance.upper).contains(&deviation)
}

/// How many points of a feature lie outside its tolerance band.
pub fn outside_count(feature: &FeatureReport) -> usize {
    let tol = feature.tolerance_mm;
    let outside = |d: f64| out_of_tolerance(d, tol);
    feature
        .points
        .iter()
        .filter(|p| outside(p.deviation_mm))
        .count()
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
    let usable = total.is_finite() && total > 0.0;
    if feature.kind == crate::report::FeatureKind::TouchPoints || !usable {
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
/// zero line, and points outside the band in red; appended to `out`.
pub fn deviation_plot(out: &mut Vec<u8>, feature: &FeatureReport) {
    let title = format!("{}: deviation along the section", feature.name);
    if feature.points.is_empty() {
        let message = "no points measured";
        return empty_plot(out, PLOT_WIDTH, EMPTY_PLOT_HEIGHT, &title, message);
    }
    let (xs, x_title) = positions(feature);
    let frame = deviation_frame(feature, &xs);
    let mut svg = Svg::new(out, PLOT_WIDTH, DEVIATION_HEIGHT, &title);
    svg.reserve(feature.points.len() * POINT_MARKUP_BYTES);
    draw_band(&mut svg, &frame, feature.tolerance_mm);
    frame.draw_axes(&mut svg, x_title, "deviation (mm)");
    let (x0, x1) = (frame.x.lo, frame.x.hi);
    svg.line(frame.map(x0, 0.0), frame.map(x1, 0.0), "zero");
    draw_points(&mut svg, &frame, &xs, feature);
    let legend = deviation_legend(feature);
    svg.text((PLOT_WIDTH - 20.0, 18.0), "end", "legend", &legend);
    svg.finish()
}

/// The deviation plot's axes: all positions; all deviations, the tolerance
/// limits and zero.
fn deviation_frame(feature: &FeatureReport, xs: &[f64]) -> Frame {
    let tol = feature.tolerance_mm;
    let devs = feature.points.iter().map(|p| p.deviation_mm);
    let y = range(devs.chain([tol.lower, tol.upper, 0.0])).unwrap_or((-1.0, 1.0));
    let x = range(xs.iter().copied()).unwrap_or((0.0, 1.0));
    let (x, y) = (
        padded(x.0, x.1, X_PAD_FRACTION),
        padded(y.0, y.1, PAD_FRACTION),
    );
    Frame::new(PLOT_WIDTH, DEVIATION_HEIGHT, x, y)
}

/// The shaded tolerance band with its limit lines.
fn draw_band(svg: &mut Svg<'_>, frame: &Frame, tol: Tolerance) {
    let (x0, x1) = (frame.x.lo, frame.x.hi);
    let (left, top) = frame.map(x0, tol.upper);
    let (right, bottom) = frame.map(x1, tol.lower);
    svg.rect((left, top), (right - left, bottom - top), "band");
    svg.line((left, top), (right, top), "limit");
    svg.line((left, bottom), (right, bottom), "limit");
}

/// The deviation trace and one marker per point (non-finite deviations
/// are left out).
fn draw_points(svg: &mut Svg<'_>, frame: &Frame, xs: &[f64], feature: &FeatureReport) {
    let tol = feature.tolerance_mm;
    let shown: Vec<((f64, f64), bool)> = xs
        .iter()
        .zip(&feature.points)
        .filter(|(_, p)| p.deviation_mm.is_finite())
        .map(|(x, p)| {
            (
                frame.map(*x, p.deviation_mm),
                out_of_tolerance(p.deviation_mm, tol),
            )
        })
        .collect();
    let texts = PixelTexts::new(shown.iter().map(|s| s.0));
    if feature.kind != crate::report::FeatureKind::TouchPoints {
        svg.polyline_texts(&texts, false, "trace");
    }
    let radius = px_text(MARKER_RADIUS);
    for (k, (_, out)) in shown.iter().enumerate() {
        let class = if *out { "pt-out" } else { "pt-in" };
        svg.circle_at(&texts, k, &radius, class);
    }
}

/// "12 points, 3 outside tolerance -0.0500..0.0500 mm".
fn deviation_legend(feature: &FeatureReport) -> String {
    let tol = feature.tolerance_mm;
    format!(
        "{} points, {} outside tolerance {}..{} mm (shaded)",
        feature.points.len(),
        outside_count(feature),
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
/// surplus corrections after the last attempt. Appended to `out`.
pub fn timeline_plot(out: &mut Vec<u8>, feature: &FeatureReport) {
    let title = format!("{}: attempts and corrections", feature.name);
    if feature.attempts.is_empty() {
        return empty_plot(
            out,
            PLOT_WIDTH,
            EMPTY_PLOT_HEIGHT,
            &title,
            "no measuring attempt",
        );
    }
    let spans = attempt_spans(feature);
    let frame = timeline_frame(feature, &spans);
    let mut svg = Svg::new(out, PLOT_WIDTH, timeline_height(feature), &title);
    frame.draw_x_axis(&mut svg, "cumulative machine time (s)");
    draw_bars(&mut svg, &frame, feature, &spans);
    draw_corrections(&mut svg, &frame, feature, &spans);
    svg.finish()
}

/// Time across (0 to the total), one row per attempt down from the top.
fn timeline_frame(feature: &FeatureReport, spans: &[(f64, f64)]) -> Frame {
    let total = spans.last().map_or(0.0, |s| s.1);
    let rows = (feature.attempts.len() as f64, 0.0);
    let legend = feature.corrections.len() as f64 * LEGEND_LINE;
    let height = timeline_height(feature) - legend;
    Frame::new(PLOT_WIDTH, height, padded(0.0, total, 0.0), rows)
}

/// One bar per attempt with its label.
fn draw_bars(svg: &mut Svg<'_>, frame: &Frame, feature: &FeatureReport, spans: &[(f64, f64)]) {
    for (row, (attempt, span)) in feature.attempts.iter().zip(spans).enumerate() {
        let centre = frame.y.map(row as f64 + 0.5);
        let (left, right) = (frame.x.map(span.0), frame.x.map(span.1));
        let completed = attempt.outcome == Outcome::Completed;
        let class = if completed { "bar-ok" } else { "bar-bad" };
        let top = centre - BAR_HEIGHT / 2.0;
        svg.rect((left, top), ((right - left).max(1.0), BAR_HEIGHT), class);
        let (x, anchor) = label_place(frame, left, right);
        svg.text(
            (x, centre + 4.0),
            anchor,
            "label",
            &attempt_label(row, attempt),
        );
    }
}

/// "#1 active: completed, 7.25 s, 72 points".
fn attempt_label(row: usize, attempt: &AttemptReport) -> String {
    format!(
        "#{} {}: {}, {} s, {} points",
        row + 1,
        json_name(&attempt.mode),
        json_name(&attempt.outcome),
        fixed(attempt.machine_time_s, TIME_DECIMALS),
        attempt.points
    )
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
fn draw_corrections(svg: &mut Svg<'_>, frame: &Frame, f: &FeatureReport, spans: &[(f64, f64)]) {
    let legend_top = timeline_height(f) - f.corrections.len() as f64 * LEGEND_LINE;
    for (k, correction) in f.corrections.iter().enumerate() {
        let time = spans.get(k).or(spans.last()).map_or(0.0, |s| s.1);
        draw_marker(svg, frame, frame.x.map(time), k + 1);
        let line_y = legend_top + (k as f64 + 0.8) * LEGEND_LINE;
        let text = format!("C{}: {}", k + 1, correction_text(correction));
        svg.text((frame.x.px_lo, line_y), "start", "label", &text);
    }
}

/// Correction number `number` at pixel column `x`: a dashed line across
/// the rows and a labelled diamond above them.
fn draw_marker(svg: &mut Svg<'_>, frame: &Frame, x: f64, number: usize) {
    let (top, bottom) = (frame.y.px_hi, frame.y.px_lo);
    svg.line((x, top), (x, bottom), "corr-line");
    let (d, y) = (DIAMOND_PX, top - 10.0);
    svg.polygon(&[(x, y - d), (x + d, y), (x, y + d), (x - d, y)], "corr");
    let label = format!("C{number}");
    svg.text((x + d + 2.0, y + 4.0), "start", "corr-label", &label);
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
