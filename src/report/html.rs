//! `report.html`: one self-contained page (inline CSS and SVG, no scripts,
//! no fonts, images or links outside the file) for a human reader.

use super::markup::{escape, fixed, json_name};
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

/// The whole page. Deterministic: no timestamps and no wall time, fixed
/// number formatting, features in report order.
pub fn report_html(report: &Report) -> String {
    let title = escape(&format!("cmm report: {}", report.program));
    let mut out = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{title}</title>\n<style>{CSS}</style>\n</head>\n<body>\n"
    );
    out.push_str(&header(report));
    out.push_str(&summary(report));
    for (index, feature) in report.features.iter().enumerate() {
        out.push_str(&feature_section(index, feature));
    }
    out.push_str("</body>\n</html>\n");
    out
}

/// A status word in its colour.
fn status_badge(status: &impl serde::Serialize) -> String {
    let name = json_name(status);
    format!(
        "<span class=\"status {name}\">{}</span>",
        name.to_uppercase()
    )
}

/// Title and run facts.
fn header(report: &Report) -> String {
    let rows = [
        ("Status", status_badge(&report.status)),
        ("Seed", report.seed.to_string()),
        ("Machine time", seconds(report.machine_time_s)),
        (
            "Ideal machine and probe",
            ideal_text(report.ideal).to_string(),
        ),
        ("Probe", probe_text(report)),
        ("Part to machine", placement(report)),
    ];
    let program = escape(&report.program);
    let mut out = format!("<h1>Inspection report: {program}</h1>\n<table class=\"meta\">\n");
    for (key, value) in rows {
        out.push_str(&format!("<tr><td><b>{key}</b></td><td>{value}</td></tr>\n"));
    }
    out.push_str("</table>\n");
    out
}

/// A machine time, `12.34 s`.
fn seconds(time: f64) -> String {
    format!("{} s", fixed(time, TIME_DECIMALS))
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
fn probe_text(report: &Report) -> String {
    let probe = &report.probe;
    format!(
        "{}; tip radius {} mm; probe vector {} mm",
        escape(&probe.source),
        fixed(probe.tip_radius_mm, MATRIX_DECIMALS),
        vector(probe.probe_vector_mm)
    )
}

/// `(x, y, z)` with fixed decimals.
fn vector(v: [f64; 3]) -> String {
    let parts: Vec<String> = v.iter().map(|c| fixed(*c, MATRIX_DECIMALS)).collect();
    format!("({})", parts.join(", "))
}

/// The rotation rows and the translation.
fn placement(report: &Report) -> String {
    let p = &report.part_to_machine;
    let rows: Vec<String> = p.rotation.iter().map(|r| vector(*r)).collect();
    format!(
        "rotation [{}], translation {} mm",
        rows.join(", "),
        vector(p.translation_mm)
    )
}

/// The feature table with out-of-tolerance cells marked.
fn summary(report: &Report) -> String {
    let head = "<tr><th class=\"name\">Feature</th><th class=\"name\">Type</th><th>Status</th>\
                <th>Points</th><th>Min (mm)</th><th>Max (mm)</th><th>Mean (mm)</th>\
                <th>RMS (mm)</th><th>Tolerance (mm)</th><th>Out of tol.</th><th>Attempts</th></tr>\n";
    let mut out = format!("<h2>Features</h2>\n<table class=\"summary\">\n{head}");
    for (index, feature) in report.features.iter().enumerate() {
        out.push_str(&summary_row(index, feature));
    }
    out.push_str("</table>\n");
    out
}

/// One row of the feature table.
fn summary_row(index: usize, f: &FeatureReport) -> String {
    let (s, t) = (f.deviation_mm, f.tolerance_mm);
    let status = json_name(&f.status);
    let link = format!("<a href=\"#feature-{}\">{}</a>", index + 1, escape(&f.name));
    let outside = outside_count(f);
    let cells = [
        td("name", &link),
        td("text", &escape(&json_name(&f.kind))),
        td(&status, &status),
        td("", &f.points.len().to_string()),
        stat_cell(f, s.min, s.min < t.lower),
        stat_cell(f, s.max, s.max > t.upper),
        stat_cell(f, s.mean, out_of_tolerance(s.mean, t)),
        stat_cell(f, s.rms, false),
        td("", &format!("{}..{}", mm(t.lower), mm(t.upper))),
        td(if outside > 0 { "out" } else { "" }, &outside.to_string()),
        td("", &f.attempts.len().to_string()),
    ];
    format!("<tr>{}</tr>\n", cells.concat())
}

/// A table cell with an optional class; `content` is markup.
fn td(class: &str, content: &str) -> String {
    if class.is_empty() {
        format!("<td>{content}</td>")
    } else {
        format!("<td class=\"{class}\">{content}</td>")
    }
}

/// A deviation statistic: `-` without points, marked when out of tolerance.
fn stat_cell(feature: &FeatureReport, value: f64, out: bool) -> String {
    match (feature.points.is_empty(), out) {
        (true, _) => td("", "-"),
        (false, true) => td("out", &format!("&#9650; {}", mm(value))),
        (false, false) => td("", &mm(value)),
    }
}

/// A length in mm with [`MM_DECIMALS`] decimals.
fn mm(value: f64) -> String {
    fixed(value, MM_DECIMALS)
}

/// A feature's heading, notes, corrections and its three plots.
fn feature_section(index: usize, feature: &FeatureReport) -> String {
    let mut out = format!(
        "<section id=\"feature-{}\">\n<h2>{} {}</h2>\n",
        index + 1,
        escape(&feature.name),
        status_badge(&feature.status)
    );
    out.push_str(&notes(feature));
    out.push_str("<h3>Deviation along the section</h3>\n");
    out.push_str(&deviation_plot(feature));
    out.push_str("<h3>Profile</h3>\n");
    out.push_str(&profile_plot(feature));
    out.push_str("<h3>Attempts and corrections</h3>\n");
    out.push_str(&timeline_plot(feature));
    out.push_str("</section>\n");
    out
}

/// Notes and corrections as a list (nothing when there are none).
fn notes(feature: &FeatureReport) -> String {
    let corrections = feature.corrections.iter().map(correction_text);
    let items: Vec<String> = feature.notes.iter().cloned().chain(corrections).collect();
    if items.is_empty() {
        return String::new();
    }
    let lis: Vec<String> = items
        .iter()
        .map(|i| format!("<li>{}</li>", escape(i)))
        .collect();
    format!("<ul>\n{}\n</ul>\n", lis.join("\n"))
}
