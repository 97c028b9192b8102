//! `report.json` (the cmm-report/1 format): the model serialised by serde.

use super::layout::ReportFormatter;
use super::model::Report;

/// Bytes reserved for the JSON besides the points.
const BASE_BYTES: usize = 8 * 1024;
/// Typical bytes of one point as written.
const POINT_BYTES: usize = 300;

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
    let points: usize = report.features.iter().map(|f| f.points.len()).sum();
    let mut bytes = Vec::with_capacity(BASE_BYTES + points * POINT_BYTES);
    let mut ser = serde_json::Serializer::with_formatter(&mut bytes, ReportFormatter::default());
    match serde::Serialize::serialize(report, &mut ser) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::model::*;

    #[test]
    fn pretty_with_trailing_newline() {
        let report = Report {
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
        };
        let text = to_json(&report);
        assert!(text.ends_with("}\n"));
        assert!(text.contains("\n  \"seed\": 7,"));
        assert_eq!(text, to_json(&report));
        assert_eq!(text.as_bytes(), to_json_bytes(&report));
    }
}
