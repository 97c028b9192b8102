//! `junit.xml`: one test case per feature, so CI systems show a part's
//! inspection like a test run (`fail` = failure, `incomplete` = error).

use super::markup::{escape, fixed, json_name};
use super::model::{FeatureReport, Report, Verdict};
use super::plots::outside_count;

/// Decimals of times (s) in the XML.
const TIME_DECIMALS: usize = 3;
/// Decimals of deviations and tolerances (mm) in messages: 0.1 um.
const MM_DECIMALS: usize = 4;

/// JUnit XML for one part: `<testsuites>` holding one `<testsuite>` named
/// after the program.
pub fn junit_xml(report: &Report) -> String {
    document(&[(report.program.clone(), report)])
}

/// JUnit XML for a batch: one `<testsuite>` per `(part name, report)`
/// (reports owned or borrowed).
pub fn junit_batch<R: std::borrow::Borrow<Report>>(parts: &[(String, R)]) -> String {
    let suites: Vec<(String, &Report)> = (parts.iter())
        .map(|(n, r)| (n.clone(), r.borrow()))
        .collect();
    document(&suites)
}

/// The whole document around the given suites.
fn document(suites: &[(String, &Report)]) -> String {
    let reports = || suites.iter().map(|(_, r)| *r);
    let counts = reports().fold(Counts::default(), |acc, r| acc.add(Counts::of(r)));
    let time: f64 = reports().map(|r| r.machine_time_s).sum();
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(&format!(
        "<testsuites name=\"cmm\" {} time=\"{}\">\n",
        counts.attributes(),
        fixed(time, TIME_DECIMALS)
    ));
    for (name, report) in suites {
        out.push_str(&testsuite(name, report));
    }
    out.push_str("</testsuites>\n");
    out
}

/// Test, failure and error counts.
#[derive(Debug, Default, Clone, Copy)]
struct Counts {
    tests: usize,
    failures: usize,
    errors: usize,
}

impl Counts {
    /// Counts of one report's features.
    fn of(report: &Report) -> Counts {
        let with = |v: Verdict| report.features.iter().filter(|f| f.status == v).count();
        Counts {
            tests: report.features.len(),
            failures: with(Verdict::Fail),
            errors: with(Verdict::Incomplete),
        }
    }

    /// Sum of two counts.
    fn add(self, other: Counts) -> Counts {
        Counts {
            tests: self.tests + other.tests,
            failures: self.failures + other.failures,
            errors: self.errors + other.errors,
        }
    }

    /// `tests="..." failures="..." errors="..."`.
    fn attributes(self) -> String {
        format!(
            "tests=\"{}\" failures=\"{}\" errors=\"{}\"",
            self.tests, self.failures, self.errors
        )
    }
}

/// One `<testsuite>` with its properties and test cases.
fn testsuite(name: &str, report: &Report) -> String {
    let name = escape(name);
    let mut out = format!(
        "  <testsuite name=\"{name}\" {} skipped=\"0\" time=\"{}\">\n",
        Counts::of(report).attributes(),
        fixed(report.machine_time_s, TIME_DECIMALS)
    );
    out.push_str(&properties(report));
    for feature in &report.features {
        out.push_str(&testcase(&name, feature));
    }
    out.push_str("  </testsuite>\n");
    out
}

/// `<properties>`: program, seed, status, ideal flag, probe source.
fn properties(report: &Report) -> String {
    let items = [
        ("program", report.program.clone()),
        ("seed", report.seed.to_string()),
        ("status", json_name(&report.status)),
        ("ideal", report.ideal.to_string()),
        ("probe_source", report.probe.source.clone()),
    ];
    let mut out = String::from("    <properties>\n");
    for (key, value) in items {
        let value = escape(&value);
        out.push_str(&format!(
            "      <property name=\"{key}\" value=\"{value}\"/>\n"
        ));
    }
    out.push_str("    </properties>\n");
    out
}

/// One `<testcase>`; `classname` is already escaped.
fn testcase(classname: &str, feature: &FeatureReport) -> String {
    let time: f64 = feature.attempts.iter().map(|a| a.machine_time_s).sum();
    let head = format!(
        "    <testcase classname=\"{classname}\" name=\"{}\" time=\"{}\"",
        escape(&feature.name),
        fixed(time, TIME_DECIMALS)
    );
    match feature.status {
        Verdict::Pass => format!("{head}/>\n"),
        Verdict::Fail => format!("{head}>\n{}    </testcase>\n", failure(feature)),
        Verdict::Incomplete => format!("{head}>\n{}    </testcase>\n", error(feature)),
    }
}

/// `<failure>`: the deviation range against the tolerance band.
fn failure(feature: &FeatureReport) -> String {
    let (s, t) = (feature.deviation_mm, feature.tolerance_mm);
    let mm = |v: f64| fixed(v, MM_DECIMALS);
    let message = format!(
        "deviation {}..{} mm outside tolerance {}..{} mm ({} of {} points)",
        mm(s.min),
        mm(s.max),
        mm(t.lower),
        mm(t.upper),
        outside_count(feature),
        feature.points.len()
    );
    let body = format!("mean {} mm, rms {} mm", mm(s.mean), mm(s.rms));
    let kind = "out_of_tolerance";
    element("failure", kind, &message, &body, &feature.notes)
}

/// `<error>`: how the last attempt ended, and the notes.
fn error(feature: &FeatureReport) -> String {
    let last = match feature.attempts.last() {
        Some(a) => format!(
            "last attempt {} ended {}",
            json_name(&a.mode),
            json_name(&a.outcome)
        ),
        None => "no attempt was made".to_string(),
    };
    let mut message = format!("incomplete: {last}");
    if !feature.notes.is_empty() {
        message.push_str(&format!("; {}", feature.notes.join("; ")));
    }
    let body = format!("{} attempts", feature.attempts.len());
    element("error", "incomplete", &message, &body, &feature.notes)
}

/// A `<failure>`/`<error>` element with message, type and a text body.
fn element(tag: &str, kind: &str, message: &str, body: &str, notes: &[String]) -> String {
    let mut text = body.to_string();
    for note in notes {
        text.push('\n');
        text.push_str(note);
    }
    format!(
        "      <{tag} message=\"{}\" type=\"{kind}\">{}</{tag}>\n",
        escape(message),
        escape(&text)
    )
}
