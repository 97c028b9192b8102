//! `cmm calibrate-probe --head-angles "A,B;A,B;..."`: probe vectors per
//! probe-head orientation (JP2902285B2).
use super::calibrate::{summary, CalibrateArgs};
use super::{CliError, Status};
use crate::app::calibrate::simulate::{ProbeTruth, SimulatedSetup};
use crate::app::calibrate::simulate_head::{calibrate_head_simulated, HeadSetup, OrientationTruth};
use crate::host::calibrate::file::to_json_with_truth;
use crate::host::calibrate::file_head::{head_file, head_truth};
use crate::host::calibrate::orientation::{HeadCalibration, OrientationOptions};
use crate::host::calibrate::CalibrationOptions;

/// Most head orientations one calibration accepts.
pub const MAX_HEAD_ORIENTATIONS: usize = 1_000;

/// Parses `--head-angles`: entries separated by `;`, angles (deg) by `,`.
/// The message names the entry (1-based) and why it is bad.
pub fn parse_head_angles(text: &str) -> Result<Vec<Vec<f64>>, String> {
    let entries: Vec<&str> = text.split(';').collect();
    if entries.len() > MAX_HEAD_ORIENTATIONS {
        return Err(format!(
            "--head-angles: {} orientations, at most {MAX_HEAD_ORIENTATIONS} accepted",
            entries.len()
        ));
    }
    let mut out = Vec::with_capacity(entries.len());
    for (k, entry) in entries.iter().enumerate() {
        let number = k + 1;
        let bad =
            |why: String| format!("--head-angles: entry {number} ('{}'): {why}", entry.trim());
        if entry.trim().is_empty() {
            return Err(bad(
                "empty (expected angles in deg, e.g. \"0,0;90,0\")".into()
            ));
        }
        let mut angles = Vec::new();
        for value in entry.split(',').map(str::trim) {
            match value.parse::<f64>() {
                Ok(a) if a.is_finite() => angles.push(a),
                Ok(_) => return Err(bad(format!("'{value}' is not a finite angle"))),
                Err(_) => return Err(bad(format!("'{value}' is not a number (deg)"))),
            }
        }
        out.push(angles);
    }
    Ok(out)
}

/// Runs the calibration over every listed head orientation.
pub fn run(
    args: &CalibrateArgs,
    setup: &SimulatedSetup,
    opts: &CalibrationOptions,
    text: &str,
) -> Result<Status, CliError> {
    let angles_deg = parse_head_angles(text).map_err(CliError::Usage)?;
    let head = HeadSetup {
        axes: args.head_axes.clone(),
        angles_deg,
        true_head_errors: None,
    };
    let oopts = OrientationOptions {
        points: args.orientation_points,
        ..OrientationOptions::default()
    };
    let (cal, truth) = calibrate_head_simulated(setup, &head, opts, &oopts)
        .map_err(|source| super::calibrate::failed(args, setup, source))?;
    let file = head_file(&cal, &head.axes, opts);
    let text = to_json_with_truth(&file, head_truth(&truth));
    crate::output::write_atomic(&args.out, text.as_bytes())?;
    if let Some(t) = truth.first() {
        let reference = ProbeTruth {
            probe_vector: t.probe_vector,
            tip_radius_mm: t.tip_radius_mm,
        };
        super::say(&summary(&cal.reference, &reference, args))?;
    }
    super::say(&orientations(&cal, &truth, &head.axes))?;
    Ok(Status::Pass)
}

fn orientations(cal: &HeadCalibration, truth: &[OrientationTruth], axes: &[String]) -> String {
    let mut lines = vec![format!(
        "head orientation ({})   probe vector mm                    tip radius mm  iter  vs truth: vector um  radius um",
        axes.join(",")
    )];
    let reference = (&cal.reference_angles_deg, &cal.reference.probe);
    let rows = std::iter::once(reference)
        .chain(cal.orientations.iter().map(|o| (&o.angles_deg, &o.probe)));
    let iterations =
        std::iter::once(None).chain(cal.orientations.iter().map(|o| Some(o.inverse_iterations)));
    for (((angles, probe), iter), t) in rows.zip(iterations).zip(truth) {
        let p = probe.probe_vector;
        let angles: Vec<String> = angles.iter().map(|a| format!("{a}")).collect();
        lines.push(format!(
            "{:<24} [{:>10.5}, {:>10.5}, {:>10.5}] {:>10.5} {:>5} {:>19.3} {:>10.3}",
            angles.join(","),
            p.x,
            p.y,
            p.z,
            probe.tip_radius_mm,
            iter.map_or("ref".to_string(), |i| i.to_string()),
            (p - t.probe_vector).norm() * 1e3,
            (probe.tip_radius_mm - t.tip_radius_mm) * 1e3
        ));
    }
    lines.join("\n") + "\n"
}
