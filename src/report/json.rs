//! `report.json` (the cmm-report/1 format): the model serialised by serde.

use super::model::Report;

/// The report as pretty-printed JSON with a trailing newline. Deterministic:
/// keys in model field order, numbers as `serde_json` writes `f64`
/// (shortest round-trip form; non-finite values become `null`).
pub fn to_json(report: &Report) -> String {
    match serde_json::to_string_pretty(report) {
        Ok(mut text) => {
            text.push('\n');
            text
        }
        // Unreachable for this model (no maps, no fallible Serialize impls);
        // still valid JSON that names the problem rather than a panic.
        Err(err) => format!(
            "{{\"format\": {:?}, \"error\": {:?}}}\n",
            report.format,
            err.to_string()
        ),
    }
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
        };
        let text = to_json(&report);
        assert!(text.ends_with("}\n"));
        assert!(text.contains("\n  \"seed\": 7,"));
        assert_eq!(text, to_json(&report));
    }
}
