//! report.html: self-contained, one SVG per plot, deterministic, and it
//! renders in headless Chromium when that is installed.
mod report_common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use cmm::report::*;
use report_common::*;

/// Chromium used for the rendering test (installed by `.ci/run`).
const CHROMIUM: &str = "/usr/bin/chromium";
/// Longest a screenshot may take before the browser is killed.
const CHROMIUM_TIMEOUT: Duration = Duration::from_secs(90);
/// Smallest plausible PNG of the rendered page, bytes.
const MIN_PNG_BYTES: u64 = 20_000;

#[test]
fn html_is_self_contained() {
    let html = report_html(&report());
    for needle in [
        "http://", "https://", "src=", "<script", "url(", "@import", "<link",
    ] {
        assert!(!html.contains(needle), "{needle}");
    }
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.ends_with("</html>\n"));
}

#[test]
fn html_has_three_plots_per_feature() {
    let report = report();
    let html = report_html(&report);
    assert_eq!(html.matches("<svg").count(), 3 * report.features.len());
    assert_eq!(html.matches("</svg>").count(), 3 * report.features.len());
    assert_eq!(html.matches("<section id=\"feature-").count(), 3);
    assert!(html.contains("no points measured"));
}

#[test]
fn html_escapes_names_and_marks_out_of_tolerance() {
    let html = report_html(&report());
    assert!(html.contains("blade-7 &lt;demo&gt;"));
    assert!(html.contains("edge &quot;A&quot;, &lt;B&amp;C&gt;"));
    assert!(!html.contains("<B&C>"));
    assert!(html.contains("<td class=\"out\">&#9650; 0.0800</td>"));
    assert!(html.contains("class=\"needle-out\""));
    assert!(html.contains("class=\"pt-out\""));
    assert!(html.contains("deviations amplified x"));
}

#[test]
fn html_says_how_the_end_move_ended_and_where_it_struck() {
    let mut report = report();
    assert!(report_html(&report).contains("<td><b>End move</b></td><td>completed, 0.00 s</td>"));
    report.end_move = EndMoveReport {
        outcome: cmm::host::modes::Outcome::Collision,
        machine_time_s: 0.25,
        collision: Some(CollisionReport {
            probe_part: "shaft",
            at_mm: [1.0, -2.5, 30.125],
            speed_mm_s: 50.0,
            phase: "position",
        }),
    };
    let html = report_html(&report);
    assert!(
        html.contains("collision, 0.25 s; shaft struck at (1.000, -2.500, 30.125) mm"),
        "{html}"
    );
}

#[test]
fn html_is_deterministic_and_ignores_wall_time() {
    let mut other = report();
    other.wall_time_s = 99.0;
    assert_eq!(report_html(&report()), report_html(&other));
}

#[test]
fn html_draws_touch_points_against_the_point_index() {
    let mut report = report();
    report.features[0].kind = cmm::report::FeatureKind::TouchPoints;
    let html = report_html(&report);
    assert!(html.contains("point index"));
    assert!(html.contains("class=\"nominal-pt\""));
}

#[test]
fn html_survives_non_finite_values_and_an_empty_report() {
    let mut report = report();
    report.features[1].points[3].deviation_mm = f64::NAN;
    report.features[1].points[4].nominal[0] = f64::INFINITY;
    let html = report_html(&report);
    let svgs: String = html.split("<svg").skip(1).collect();
    for bad in ["NaN", "=\"inf", "=\"-inf", ",inf", ",-inf", "inf,"] {
        assert!(!svgs.contains(bad), "{bad} in SVG");
    }
    report.features.clear();
    let html = report_html(&report);
    assert_eq!(html.matches("<svg").count(), 0);
    assert!(html.contains("<table class=\"summary\">"));
}

/// Runs the browser, killing it after [`CHROMIUM_TIMEOUT`].
fn screenshot(html: &Path, png: &Path, profile: &Path) -> bool {
    let mut child = Command::new(CHROMIUM)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
        ])
        .args(["--no-first-run", "--disable-background-networking"])
        .args(["--disable-component-update", "--disable-sync"])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", png.display()))
        .arg("--window-size=1200,1600")
        .arg(format!("file://{}", html.display()))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while start.elapsed() < CHROMIUM_TIMEOUT {
        if let Some(status) = child.try_wait().unwrap() {
            return status.success();
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    false
}

#[test]
fn html_renders_in_headless_chromium() {
    if !Path::new(CHROMIUM).exists() {
        eprintln!("note: {CHROMIUM} not installed; rendering test skipped");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    write_reports(tmp.path(), &report()).unwrap();
    let png = tmp.path().join("shot.png");
    let ok = screenshot(
        &tmp.path().join("report.html"),
        &png,
        &tmp.path().join("profile"),
    );
    assert!(ok, "chromium failed or timed out");
    let size = std::fs::metadata(&png).unwrap().len();
    assert!(size > MIN_PNG_BYTES, "screenshot only {size} bytes");
    // Keep the picture and the page for a human look when asked to.
    if let Some(dir) = std::env::var_os("CMM_KEEP_SCREENSHOT") {
        std::fs::copy(&png, Path::new(&dir).join("report-shot.png")).unwrap();
        let html = tmp.path().join("report.html");
        std::fs::copy(html, Path::new(&dir).join("report.html")).unwrap();
    }
}
