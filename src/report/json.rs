//! `report.json` (the cmm-report/1 format): the model as serde serialises
//! it, in the layout of [`super::layout`].
//!
//! The report's and the features' own keys and the points are written
//! here directly, each other value by serde with the layout's formatter at
//! its depth: the same bytes, without serde's per-token machinery on the
//! hundreds of thousands of numbers of the points. The tests compare the
//! result with serde's serialisation of the whole report.

use serde::Serialize;

use super::csv::PointsCsv;
use super::layout::ReportFormatter;
use super::model::{FeatureReport, PointReport, Report};

/// Bytes reserved for the JSON besides the points.
const BASE_BYTES: usize = 8 * 1024;
/// Bytes of one point as written, with room for long numbers.
const POINT_BYTES: usize = 400;
/// A line end followed by the indentation of the deepest level written
/// here (two spaces a level).
const NEWLINE_INDENT: &[u8] = b"\n          ";

/// The report as indented JSON ([`super::layout`]: arrays of numbers on
/// one line) with a trailing newline. Deterministic: keys in model field
/// order, numbers as `serde_json` writes `f64` (shortest round-trip form;
/// non-finite values become `null`).
pub fn to_json(report: &Report) -> String {
    String::from_utf8(to_json_bytes(report)).unwrap_or_default()
}

/// [`to_json`] as UTF-8 bytes, written straight into a buffer sized for
/// the report.
pub fn to_json_bytes(report: &Report) -> Vec<u8> {
    json_with(report, None)
}

/// [`to_json_bytes`], and the lines of `points.csv` appended to `csv` on
/// the way (each number is formatted once for both files).
pub(super) fn to_json_bytes_and_csv(report: &Report, csv: &mut PointsCsv) -> Vec<u8> {
    json_with(report, Some(csv))
}

/// The JSON, with the points' CSV lines going to `csv` when given.
fn json_with(report: &Report, csv: Option<&mut PointsCsv>) -> Vec<u8> {
    let points: usize = report.features.iter().map(|f| f.points.len()).sum();
    let mut bytes = Vec::with_capacity(BASE_BYTES + points * POINT_BYTES);
    match write_report(&mut bytes, report, csv) {
        Ok(()) => {
            bytes.push(b'\n');
            bytes
        }
        Err(err) => error_json(report, &err).into_bytes(),
    }
}

/// The JSON written when serialisation fails. Unreachable for this model
/// (no maps, no fallible Serialize impls); still valid JSON that names the
/// problem rather than a panic.
fn error_json(report: &Report, err: &serde_json::Error) -> String {
    format!(
        "{{\"format\": {:?}, \"error\": {:?}}}\n",
        report.format,
        err.to_string()
    )
}

/// A line end and the indentation of `level`.
fn newline(out: &mut Vec<u8>, level: usize) {
    match NEWLINE_INDENT.get(..1 + 2 * level) {
        Some(text) => out.extend_from_slice(text),
        None => {
            out.push(b'\n');
            (0..level).for_each(|_| out.extend_from_slice(b"  "));
        }
    }
}

/// The key of an object's member at `level` (the comma before it unless
/// it is the first); the value follows.
fn key(out: &mut Vec<u8>, level: usize, first: bool, name: &str) {
    if !first {
        out.push(b',');
    }
    newline(out, level);
    out.push(b'"');
    out.extend_from_slice(name.as_bytes());
    out.extend_from_slice(b"\": ");
}

/// An object's member whose value serde writes, as it would inside the
/// whole report at this depth.
fn field<T: Serialize + ?Sized>(
    out: &mut Vec<u8>,
    level: usize,
    first: bool,
    name: &str,
    value: &T,
) -> Result<(), serde_json::Error> {
    key(out, level, first, name);
    let mut ser = serde_json::Serializer::with_formatter(out, ReportFormatter::at_indent(level));
    value.serialize(&mut ser)
}

/// The whole report (without the trailing newline).
fn write_report(
    out: &mut Vec<u8>,
    report: &Report,
    csv: Option<&mut PointsCsv>,
) -> Result<(), serde_json::Error> {
    const LEVEL: usize = 1;
    out.push(b'{');
    field(out, LEVEL, true, "format", report.format)?;
    field(out, LEVEL, false, "program", &report.program)?;
    field(out, LEVEL, false, "seed", &report.seed)?;
    field(out, LEVEL, false, "status", &report.status)?;
    field(out, LEVEL, false, "machine_time_s", &report.machine_time_s)?;
    field(out, LEVEL, false, "wall_time_s", &report.wall_time_s)?;
    field(
        out,
        LEVEL,
        false,
        "part_to_machine",
        &report.part_to_machine,
    )?;
    field(out, LEVEL, false, "ideal", &report.ideal)?;
    field(out, LEVEL, false, "probe", &report.probe)?;
    if let Some(alignment) = &report.alignment {
        field(out, LEVEL, false, "alignment", alignment)?;
    }
    key(out, LEVEL, false, "features");
    write_features(out, LEVEL, &report.features, csv)?;
    field(out, LEVEL, false, "end_move", &report.end_move)?;
    newline(out, LEVEL - 1);
    out.push(b'}');
    Ok(())
}

/// The features array, the value of a key at `level`.
fn write_features(
    out: &mut Vec<u8>,
    level: usize,
    features: &[FeatureReport],
    mut csv: Option<&mut PointsCsv>,
) -> Result<(), serde_json::Error> {
    if features.is_empty() {
        out.extend_from_slice(b"[]");
        return Ok(());
    }
    out.push(b'[');
    for (k, feature) in features.iter().enumerate() {
        if k > 0 {
            out.push(b',');
        }
        newline(out, level + 1);
        write_feature(out, level + 1, feature, csv.as_deref_mut())?;
    }
    newline(out, level);
    out.push(b']');
    Ok(())
}

/// One feature, an object whose braces are at `level`.
fn write_feature(
    out: &mut Vec<u8>,
    level: usize,
    f: &FeatureReport,
    csv: Option<&mut PointsCsv>,
) -> Result<(), serde_json::Error> {
    let inner = level + 1;
    out.push(b'{');
    field(out, inner, true, "name", &f.name)?;
    field(out, inner, false, "type", &f.kind)?;
    field(out, inner, false, "status", &f.status)?;
    field(out, inner, false, "attempts", &f.attempts)?;
    field(out, inner, false, "corrections", &f.corrections)?;
    field(out, inner, false, "deviation_mm", &f.deviation_mm)?;
    field(out, inner, false, "tolerance_mm", &f.tolerance_mm)?;
    field(out, inner, false, "notes", &f.notes)?;
    if let Some(fit) = &f.fit {
        field(out, inner, false, "fit", fit)?;
    }
    key(out, inner, false, "points");
    let mut csv = csv;
    if let Some(csv) = csv.as_deref_mut() {
        csv.begin_feature(&f.name);
    }
    write_points(out, inner, &f.points, &mut csv);
    newline(out, level);
    out.push(b'}');
    Ok(())
}

/// The points array, the value of a key at `level`.
fn write_points(
    out: &mut Vec<u8>,
    level: usize,
    points: &[PointReport],
    csv: &mut Option<&mut PointsCsv>,
) {
    if points.is_empty() {
        out.extend_from_slice(b"[]");
        return;
    }
    let text = PointText::new(level + 1);
    out.push(b'[');
    for (index, point) in points.iter().enumerate() {
        if index > 0 {
            out.push(b',');
        }
        if let Some(csv) = csv {
            csv.begin_line(index);
        }
        write_point(out, &text, point, csv);
        if let Some(csv) = csv {
            csv.end_line();
        }
    }
    newline(out, level);
    out.push(b']');
}

/// The fixed text of a point's object at one depth between its numbers
/// (line ends, indentation, keys), each piece ready to be copied at once.
struct PointText {
    /// From the line end before `{` to the `[` of `measured`.
    open: Vec<u8>,
    /// From the `]` of `measured` to the `[` of `nominal`.
    nominal: Vec<u8>,
    /// From the `]` of `nominal` to the `[` of `normal`.
    normal: Vec<u8>,
    /// From the `]` of `normal` to the value of `deviation_mm`.
    deviation: Vec<u8>,
    /// Up to the value of `true_deviation_mm`.
    true_deviation: Vec<u8>,
    /// The `edge` member.
    edge: Vec<u8>,
    /// The `off_section` member.
    off_section: Vec<u8>,
    /// From the line end before `}` to it.
    close: Vec<u8>,
}

impl PointText {
    /// The text of a point whose braces are at `level`.
    fn new(level: usize) -> PointText {
        let piece = |before: &[u8], first: bool, name: &str, after: &[u8]| {
            let mut text = before.to_vec();
            key(&mut text, level + 1, first, name);
            text.extend_from_slice(after);
            text
        };
        let mut open = Vec::new();
        newline(&mut open, level);
        open.push(b'{');
        let mut close = Vec::new();
        newline(&mut close, level);
        close.push(b'}');
        PointText {
            open: piece(&open, true, "measured", b"["),
            nominal: piece(b"]", false, "nominal", b"["),
            normal: piece(b"]", false, "normal", b"["),
            deviation: piece(b"]", false, "deviation_mm", b""),
            true_deviation: piece(b"", false, "true_deviation_mm", b""),
            edge: piece(b"", false, "edge", b"true"),
            off_section: piece(b"", false, "off_section", b"true"),
            close,
        }
    }
}

/// One point's object.
fn write_point(
    out: &mut Vec<u8>,
    text: &PointText,
    point: &PointReport,
    csv: &mut Option<&mut PointsCsv>,
) {
    let mut numbers = Numbers { out, csv, count: 0 };
    numbers.text(&text.open);
    numbers.triple(&point.measured);
    numbers.text(&text.nominal);
    numbers.triple(&point.nominal);
    numbers.text(&text.normal);
    numbers.triple(&point.normal);
    numbers.text(&text.deviation);
    numbers.number(point.deviation_mm);
    numbers.text(&text.true_deviation);
    numbers.number(point.true_deviation_mm);
    if point.edge {
        numbers.text(&text.edge);
    }
    if point.off_section {
        numbers.text(&text.off_section);
    }
    numbers.text(&text.close);
}

/// The numbers of one point going into the JSON and, when given, into
/// its CSV line.
struct Numbers<'a, 'b, 'c> {
    out: &'a mut Vec<u8>,
    csv: &'b mut Option<&'c mut PointsCsv>,
    /// Numbers of the point written so far.
    count: usize,
}

impl Numbers<'_, '_, '_> {
    /// Fixed text.
    fn text(&mut self, text: &[u8]) {
        self.out.extend_from_slice(text);
    }

    /// Three numbers separated as on one line of an array.
    fn triple(&mut self, values: &[f64; 3]) {
        let [a, b, c] = *values;
        self.number(a);
        self.out.extend_from_slice(b", ");
        self.number(b);
        self.out.extend_from_slice(b", ");
        self.number(c);
    }

    /// A number as serde_json writes it (`null` when not finite), and as
    /// `points.csv` writes it.
    fn number(&mut self, value: f64) {
        if value.is_finite() {
            let mut buffer = zmij::Buffer::new();
            let text = buffer.format_finite(value).as_bytes();
            self.out.extend_from_slice(text);
            if let Some(csv) = self.csv {
                csv.field(self.count, text);
            }
        } else {
            self.out.extend_from_slice(b"null");
            if let Some(csv) = self.csv {
                csv.field(self.count, format!("{value}").as_bytes());
            }
        }
        self.count += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::model::*;

    /// The whole report as serde writes it in the report's layout.
    fn serde_json_of(report: &Report) -> Vec<u8> {
        let mut out = Vec::new();
        let mut ser = serde_json::Serializer::with_formatter(&mut out, ReportFormatter::default());
        report.serialize(&mut ser).unwrap_or_else(|e| panic!("{e}"));
        out.push(b'\n');
        out
    }

    /// A point with every number different, `k` varying them.
    fn point(k: f64) -> PointReport {
        PointReport {
            measured: [1.0 + k, -2.5e-7 * k, 1e21],
            nominal: [0.1 * k, 123456.789, -0.0],
            normal: [0.0, 0.6, -0.8],
            deviation_mm: 0.001 * k,
            true_deviation_mm: 5e-324,
            edge: false,
            off_section: false,
            in_section: None,
            measured_in_section: Some([1.0, 2.0, 3.0]),
        }
    }

    /// A feature with attempts, corrections, notes, a fit and points
    /// (some on an edge, off the section or not finite).
    fn feature(name: &str, points: Vec<PointReport>) -> FeatureReport {
        let summary = crate::evaluate::fitted::ElementSummary {
            center: [1.0, 2.0, 3.0],
            direction: [0.0, 0.0, 1.0],
            diameter_mm: 20.5,
            form_mm: 0.003,
        };
        FeatureReport {
            name: name.into(),
            kind: FeatureKind::SectionScan,
            status: Verdict::Fail,
            attempts: vec![AttemptReport {
                mode: AttemptMode::Active,
                outcome: crate::host::modes::Outcome::Completed,
                machine_time_s: 6.25,
                points: points.len(),
                max_trajectory_error_mm: f64::NAN,
                collision: None,
            }],
            corrections: vec![
                CorrectionReport::Geometric {
                    model: "translation".into(),
                    max_residual_mm: 0.002,
                    points: 6,
                    source: "fitted",
                },
                CorrectionReport::Autonomous { points: 40 },
            ],
            deviation_mm: Stats::of(points.iter().map(|p| p.deviation_mm)),
            tolerance_mm: Tolerance {
                lower: -0.05,
                upper: 0.05,
            },
            notes: vec!["a \"quoted\" note\n\u{1}".into()],
            fit: Some(crate::evaluate::fitted::FitResult {
                element: "circle",
                measured: Some(summary),
                nominal: None,
                size_deviation_mm: 0.01,
                position_deviation_mm: f64::INFINITY,
                status: Verdict::Pass,
                error: None,
            }),
            points,
        }
    }

    /// A report with an alignment and features with and without points.
    fn rich_report() -> Report {
        let mut report = minimal_report();
        report.alignment = Some(AlignmentReport {
            points: 6,
            rms_mm: 0.001,
            max_mm: 0.002,
            iterations: 4,
            machine_time_s: 3.5,
            failed: None,
            failed_point: None,
            collision: None,
            notes: vec!["turn about z".into()],
        });
        let mut points: Vec<PointReport> = (0..5).map(|k| point(k as f64)).collect();
        points[1].edge = true;
        points[2].off_section = true;
        points[3].edge = true;
        points[3].off_section = true;
        points[4].deviation_mm = f64::NAN;
        points[4].measured[1] = f64::NEG_INFINITY;
        let mut empty = feature("empty, \"odd\" name", vec![]);
        empty.fit = None;
        report.features = vec![
            feature("scan", points),
            empty,
            feature("one", vec![point(9.0)]),
        ];
        report
    }

    fn minimal_report() -> Report {
        Report {
            format: REPORT_FORMAT,
            program: "p".into(),
            seed: 7,
            status: Verdict::Pass,
            machine_time_s: 1.5,
            wall_time_s: 0.0,
            part_to_machine: PartToMachine {
                rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                translation_mm: [0.0; 3],
            },
            ideal: true,
            alignment: None,
            probe: ProbeUsed {
                source: "nominal".into(),
                tip_radius_mm: 1.0,
                probe_vector_mm: [0.0, 0.0, -50.0],
            },
            features: vec![],
            end_move: EndMoveReport {
                outcome: crate::host::modes::Outcome::Completed,
                machine_time_s: 0.5,
                collision: None,
            },
        }
    }

    #[test]
    fn written_as_serde_writes_the_whole_report() {
        for report in [minimal_report(), rich_report()] {
            let expected = serde_json_of(&report);
            assert_eq!(
                String::from_utf8_lossy(&to_json_bytes(&report)),
                String::from_utf8_lossy(&expected)
            );
            let mut csv = PointsCsv::new(&report);
            assert_eq!(to_json_bytes_and_csv(&report, &mut csv), expected);
            let csv = String::from_utf8(csv.into_bytes()).unwrap_or_default();
            assert_eq!(csv, crate::report::csv::points_csv(&report));
        }
    }

    #[test]
    fn pretty_with_trailing_newline() {
        let report = minimal_report();
        let text = to_json(&report);
        assert!(text.ends_with("}\n"));
        assert!(text.contains("\n  \"seed\": 7,"));
        assert_eq!(text, to_json(&report));
        assert_eq!(text.as_bytes(), to_json_bytes(&report));
    }
}
