//! `report.html`: one self-contained page (inline CSS and SVG, no scripts,
//! no fonts, images or links outside the file) for a human reader.

use std::io::Write;

use super::markup::{json_name, push_escaped, push_fixed, TextSink};
use super::model::{FeatureReport, Report};
use super::plots::{
    correction_text, deviation_plot, out_of_tolerance, outside_count, timeline_plot,
};
use super::profile::profile_plot;

/// Decimals of deviations and tolerances (mm) in tables: 0.1 um.
const MM_DECIMALS: usize = 4;
/// Decimals of machine times (s).
const TIME_DECIMALS: usize = 2;
/// Decimals of the placement matrix and probe values.
const MATRIX_DECIMALS: usize = 6;

/// The page's stylesheet (system fonts only).
const CSS: &str = "
body { font-family: sans-serif; margin: 24px; color: #222; max-width: 1100px; }
h1 { font-size: 22px; margin: 0 0 12px 0; }
h2 { font-size: 18px; margin: 32px 0 8px 0; border-bottom: 1px solid #ccc; }
h3 { font-size: 14px; margin: 14px 0 4px 0; color: #555; }
table { border-collapse: collapse; margin: 8px 0; font-size: 13px; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
th { background: #f0f0f0; }
td.name, th.name, td.text { text-align: left; }
table.meta td { text-align: left; border: none; padding: 2px 12px 2px 0; }
table.meta td:first-child { white-space: nowrap; vertical-align: top; }
.pass { background: #d7f5d7; color: #145214; }
.fail { background: #f8d0d0; color: #8a1010; font-weight: bold; }
.incomplete { background: #fde8b0; color: #7a5200; font-weight: bold; }
.status { padding: 2px 8px; border-radius: 3px; }
td.pass, td.fail, td.incomplete { text-align: center; }
td.out { background: #f8d0d0; color: #8a1010; font-weight: bold; }
svg.plot { display: block; max-width: 100%; height: auto; margin: 4px 0; }
svg text { font-family: sans-serif; font-size: 12px; fill: #222; }
svg text.note { font-size: 14px; fill: #777; }
svg text.axis { font-size: 12px; fill: #444; }
svg text.legend { font-size: 12px; fill: #444; }
svg text.corr-label { font-weight: bold; fill: #5b2a86; }
.frame { fill: none; stroke: #888; stroke-width: 1; }
.grid { stroke: #e4e4e4; stroke-width: 1; }
.tick { stroke: #888; }
.band { fill: #cfeecf; stroke: none; }
.limit { stroke: #6aa86a; stroke-width: 1; stroke-dasharray: 4 3; }
.zero { stroke: #333; stroke-width: 1; }
.trace { fill: none; stroke: #7a9cc6; stroke-width: 1; }
.pt-in { fill: #1f6fbf; }
.pt-out { fill: #d01c1c; stroke: #700; stroke-width: 0.5; }
.nominal { fill: none; stroke: #333; stroke-width: 1.5; }
.nominal-pt { fill: #333; }
.tol-line { fill: none; stroke: #999; stroke-width: 1; stroke-dasharray: 5 4; }
.needle-in { stroke: #1a9a1a; stroke-width: 1.5; }
.needle-out { stroke: #d01c1c; stroke-width: 2; }
.scale { stroke: #222; stroke-width: 2; }
.bar-ok { fill: #9fd89f; stroke: #3a8a3a; }
.bar-bad { fill: #f2a7a7; stroke: #b03030; }
.corr { fill: #8e5cc0; stroke: #5b2a86; }
.corr-line { stroke: #8e5cc0; stroke-width: 1.5; stroke-dasharray: 3 3; }
";

/// Bytes reserved for the page besides the stylesheet and the points.
const PAGE_BYTES: usize = 16 * 1024;
/// Typical bytes of the markup of one point (plots and tables).
const POINT_BYTES: usize = 300;

/// The whole page. Deterministic: no timestamps and no wall time, fixed
/// number formatting, features in report order.
pub fn report_html(report: &Report) -> String {
    String::from_utf8(report_html_bytes(report)).unwrap_or_default()
}

/// [`report_html`] as UTF-8 bytes.
pub fn report_html_bytes(report: &Report) -> Vec<u8> {
    let points: usize = report.features.iter().map(|f| f.points.len()).sum();
    let mut out = Vec::with_capacity(CSS.len() + PAGE_BYTES + points * POINT_BYTES);
    out.push_text("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>");
    out.push_text("cmm report: ");
    push_escaped(&mut out, &report.program);
    out.push_text("</title>\n<style>");
    out.push_text(CSS);
    out.push_text("</style>\n</head>\n<body>\n");
    header(&mut out, report);
    summary(&mut out, report);
    for (index, feature) in report.features.iter().enumerate() {
        feature_section(&mut out, index, feature);
    }
    out.push_text("</body>\n</html>\n");
    out
}

/// A status word in its colour.
fn status_badge(out: &mut Vec<u8>, status: &impl serde::Serialize) {
    let name = json_name(status);
    out.push_text("<span class=\"status ");
    out.push_text(&name);
    out.push_text("\">");
    out.push_text(&name.to_uppercase());
    out.push_text("</span>");
}

/// Title and run facts.
fn header(out: &mut Vec<u8>, report: &Report) {
    out.push_text("<h1>Inspection report: ");
    push_escaped(out, &report.program);
    out.push_text("</h1>\n<table class=\"meta\">\n");
    meta_row(out, "Status", |out| status_badge(out, &report.status));
    meta_row(out, "Seed", |out| {
        // Writing into a Vec cannot fail.
        let _ = write!(out, "{}", report.seed);
    });
    meta_row(out, "Machine time", |out| {
        seconds(out, report.machine_time_s)
    });
    meta_row(out, "Ideal machine and probe", |out| {
        out.push_text(ideal_text(report.ideal));
    });
    meta_row(out, "Probe", |out| probe_text(out, report));
    meta_row(out, "Part to machine", |out| placement(out, report));
    meta_row(out, "End move", |out| end_move(out, report));
    out.push_text("</table>\n");
}

/// How the end move ended and its machine time, with where the probe
/// struck the part when it did.
fn end_move(out: &mut Vec<u8>, report: &Report) {
    let end = &report.end_move;
    push_escaped(out, &json_name(&end.outcome));
    out.push_text(", ");
    seconds(out, end.machine_time_s);
    if let Some(c) = &end.collision {
        let [x, y, z] = c.at_mm;
        // Writing into a Vec cannot fail.
        let _ = write!(
            out,
            "; {} struck at ({x:.3}, {y:.3}, {z:.3}) mm",
            c.probe_part
        );
    }
}

/// One row of the run facts; `value` appends the value's markup.
fn meta_row(out: &mut Vec<u8>, key: &str, value: impl FnOnce(&mut Vec<u8>)) {
    out.push_text("<tr><td><b>");
    out.push_text(key);
    out.push_text("</b></td><td>");
    value(out);
    out.push_text("</td></tr>\n");
}

/// A machine time, `12.34 s`.
fn seconds(out: &mut Vec<u8>, time: f64) {
    push_fixed(out, time, TIME_DECIMALS);
    out.push_text(" s");
}

/// What `--ideal` means, in words.
fn ideal_text(ideal: bool) -> &'static str {
    if ideal {
        "yes (no simulated errors or noise)"
    } else {
        "no"
    }
}

/// Probe source, tip radius and probe vector (escaped).
fn probe_text(out: &mut Vec<u8>, report: &Report) {
    let probe = &report.probe;
    push_escaped(out, &probe.source);
    out.push_text("; tip radius ");
    push_fixed(out, probe.tip_radius_mm, MATRIX_DECIMALS);
    out.push_text(" mm; probe vector ");
    vector(out, probe.probe_vector_mm);
    out.push_text(" mm");
}

/// `(x, y, z)` with fixed decimals.
fn vector(out: &mut Vec<u8>, v: [f64; 3]) {
    out.push(b'(');
    for (k, c) in v.iter().enumerate() {
        if k > 0 {
            out.push_text(", ");
        }
        push_fixed(out, *c, MATRIX_DECIMALS);
    }
    out.push(b')');
}

/// The rotation rows and the translation.
fn placement(out: &mut Vec<u8>, report: &Report) {
    let p = &report.part_to_machine;
    out.push_text("rotation [");
    for (k, row) in p.rotation.iter().enumerate() {
        if k > 0 {
            out.push_text(", ");
        }
        vector(out, *row);
    }
    out.push_text("], translation ");
    vector(out, p.translation_mm);
    out.push_text(" mm");
}

/// The feature table with out-of-tolerance cells marked.
fn summary(out: &mut Vec<u8>, report: &Report) {
    out.push_text(
        "<h2>Features</h2>\n<table class=\"summary\">\n\
         <tr><th class=\"name\">Feature</th><th class=\"name\">Type</th><th>Status</th>\
         <th>Points</th><th>Min (mm)</th><th>Max (mm)</th><th>Mean (mm)</th>\
         <th>RMS (mm)</th><th>Tolerance (mm)</th><th>Out of tol.</th><th>Attempts</th></tr>\n",
    );
    for (index, feature) in report.features.iter().enumerate() {
        summary_row(out, index, feature);
    }
    out.push_text("</table>\n");
}

/// One row of the feature table.
fn summary_row(out: &mut Vec<u8>, index: usize, f: &FeatureReport) {
    let (s, t) = (f.deviation_mm, f.tolerance_mm);
    let status = json_name(&f.status);
    let outside = outside_count(f);
    out.push_text("<tr>");
    td(out, "name", |out| {
        let _ = write!(out, "<a href=\"#feature-{}\">", index + 1);
        push_escaped(out, &f.name);
        out.push_text("</a>");
    });
    td(out, "text", |out| push_escaped(out, &json_name(&f.kind)));
    td(out, &status, |out| out.push_text(&status));
    td(out, "", |out| count(out, f.points.len()));
    stat_cell(out, f, s.min, s.min < t.lower);
    stat_cell(out, f, s.max, s.max > t.upper);
    stat_cell(out, f, s.mean, out_of_tolerance(s.mean, t));
    stat_cell(out, f, s.rms, false);
    td(out, "", |out| {
        mm(out, t.lower);
        out.push_text("..");
        mm(out, t.upper);
    });
    let outside_class = if outside > 0 { "out" } else { "" };
    td(out, outside_class, |out| count(out, outside));
    td(out, "", |out| count(out, f.attempts.len()));
    out.push_text("</tr>\n");
}

/// A count in decimal.
fn count(out: &mut Vec<u8>, n: usize) {
    // Writing into a Vec cannot fail.
    let _ = write!(out, "{n}");
}

/// A table cell with an optional class; `content` appends markup.
fn td(out: &mut Vec<u8>, class: &str, content: impl FnOnce(&mut Vec<u8>)) {
    if class.is_empty() {
        out.push_text("<td>");
    } else {
        out.push_text("<td class=\"");
        out.push_text(class);
        out.push_text("\">");
    }
    content(out);
    out.push_text("</td>");
}

/// A deviation statistic: `-` without points, marked when out of tolerance.
fn stat_cell(out: &mut Vec<u8>, feature: &FeatureReport, value: f64, outside: bool) {
    match (feature.points.is_empty(), outside) {
        (true, _) => td(out, "", |out| out.push(b'-')),
        (false, true) => td(out, "out", |out| {
            out.push_text("&#9650; ");
            mm(out, value);
        }),
        (false, false) => td(out, "", |out| mm(out, value)),
    }
}

/// A length in mm with [`MM_DECIMALS`] decimals.
fn mm(out: &mut Vec<u8>, value: f64) {
    push_fixed(out, value, MM_DECIMALS);
}

/// A feature's heading, notes, corrections and its three plots.
fn feature_section(out: &mut Vec<u8>, index: usize, feature: &FeatureReport) {
    // Writing into a Vec cannot fail.
    let _ = write!(out, "<section id=\"feature-{}\">\n<h2>", index + 1);
    push_escaped(out, &feature.name);
    out.push(b' ');
    status_badge(out, &feature.status);
    out.push_text("</h2>\n");
    notes(out, feature);
    out.push_text("<h3>Deviation along the section</h3>\n");
    deviation_plot(out, feature);
    out.push_text("<h3>Profile</h3>\n");
    profile_plot(out, feature);
    out.push_text("<h3>Attempts and corrections</h3>\n");
    timeline_plot(out, feature);
    out.push_text("</section>\n");
}

/// Notes and corrections as a list (nothing when there are none).
fn notes(out: &mut Vec<u8>, feature: &FeatureReport) {
    if feature.notes.is_empty() && feature.corrections.is_empty() {
        return;
    }
    out.push_text("<ul>\n");
    let corrections = feature.corrections.iter().map(correction_text);
    let items = feature.notes.iter().cloned().chain(corrections);
    for (k, item) in items.enumerate() {
        if k > 0 {
            out.push(b'\n');
        }
        out.push_text("<li>");
        push_escaped(out, &item);
        out.push_text("</li>");
    }
    out.push_text("\n</ul>\n");
}
