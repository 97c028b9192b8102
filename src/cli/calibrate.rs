//! `cmm calibrate-probe [--machine URDF] [--machine-profile FILE]
//! [--probe FILE | --probe-tip-diameter D --stylus-length L] [--sphere-diameter 25]
//! [--deflections 0.1,0.2,0.3,0.5] [--directions cw,ccw] [--seed N]
//! [--ideal] [--out probe-cal.json]`.
use std::path::PathBuf;

use super::{CliError, Status};
use crate::app::calibrate::simulate::{calibrate_simulated, ProbeTruth, SimulatedSetup};
use crate::host::calibrate::file::{to_file, to_json};
use crate::host::calibrate::probe_file::{read_probe_file, NominalProbe};
use crate::host::calibrate::{Calibration, CalibrationOptions};
use crate::machine::{MachineModel, MachineProfile};

/// Arguments of `cmm calibrate-probe`.
#[derive(Debug, clap::Args)]
pub struct CalibrateArgs {
    /// Machine kinematics (URDF); the embedded bridge CMM when omitted.
    #[arg(long)]
    pub machine: Option<PathBuf>,
    /// Machine profile (cmm-machine-profile/1); defaults when omitted.
    #[arg(long)]
    pub machine_profile: Option<PathBuf>,
    /// Nominal probe from a file: a part program's `probe` block
    /// (`{"tip_diameter_mm": 3, "stylus_length_mm": 50}`) or a whole part
    /// program; replaces --probe-tip-diameter and --stylus-length.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["probe_tip_diameter", "stylus_length"])]
    pub probe: Option<PathBuf>,
    /// Nominal tip (ball) diameter, mm.
    #[arg(long, default_value_t = 3.0)]
    pub probe_tip_diameter: f64,
    /// Nominal stylus length (vertical stylus), mm.
    #[arg(long, default_value_t = 50.0)]
    pub stylus_length: f64,
    /// Reference sphere diameter, mm.
    #[arg(long, default_value_t = 25.0)]
    pub sphere_diameter: f64,
    /// Scan deflections, mm (comma separated); by default those of
    /// 0.1,0.2,0.3,0.5 the tip allows (at most 0.9 of its radius).
    #[arg(long, value_delimiter = ',')]
    pub deflections: Option<Vec<f64>>,
    /// Scan directions (comma separated `cw`, `ccw`).
    #[arg(long, value_delimiter = ',', default_values_t = vec!["cw".to_string(), "ccw".to_string()],
          value_parser = ["cw", "ccw"])]
    pub directions: Vec<String>,
    /// Seed of every simulated random draw.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Switch off every simulated error and all noise.
    #[arg(long)]
    pub ideal: bool,
    /// With --ideal, keep the machine profile's geometric error terms (the
    /// measuring side corrects them with its error map).
    #[arg(long, requires = "ideal")]
    pub keep_geometric_errors: bool,
    /// Probe-head orientations to calibrate, deg: entries separated by ';',
    /// one angle per head axis (order of --head-axes) separated by ','.
    /// The first entry is the reference, calibrated in full; every other
    /// one with a few points from its predicted sphere centre.
    #[arg(long, value_name = "A,B;A,B;...")]
    pub head_angles: Option<String>,
    /// Head axes (URDF joint names) in the order of --head-angles' values.
    #[arg(long, value_delimiter = ',', default_values_t = vec!["a".to_string(), "b".to_string()])]
    pub head_axes: Vec<String>,
    /// Points on the sphere at every further head orientation (at least 4).
    #[arg(long, default_value_t = 4)]
    pub orientation_points: usize,
    /// Calibration file to write.
    #[arg(long, default_value = "probe-cal.json")]
    pub out: PathBuf,
}

/// Stylus ball diameters accepted, mm (real styli: 0.3 to 30 mm).
pub const TIP_DIAMETER_RANGE_MM: (f64, f64) = (0.1, 50.0);
/// Stylus lengths accepted, mm (the longest extensions are about 400 mm;
/// the machine's travel may allow less).
pub const STYLUS_LENGTH_RANGE_MM: (f64, f64) = (1.0, 1000.0);
/// Reference sphere diameters accepted, mm (calibration spheres are 8 to
/// 50 mm; a smaller one cannot be scanned with a real ball).
pub const SPHERE_DIAMETER_RANGE_MM: (f64, f64) = (2.0, 200.0);
/// Largest scan deflection accepted, mm (and at most 0.9 of the tip radius).
pub const MAX_DEFLECTION_MM: f64 = 1.0;
/// Most sphere points per further head orientation.
pub const MAX_ORIENTATION_POINTS: usize = 1_000;

fn in_range(
    option: &'static str,
    v: f64,
    (lo, hi): (f64, f64),
    unit: &str,
) -> Result<(), CliError> {
    if v.is_finite() && v >= lo && v <= hi {
        return Ok(());
    }
    Err(CliError::Value {
        option,
        value: v.to_string(),
        reason: format!("must lie in [{lo}, {hi}] {unit}"),
    })
}

/// The deflections calibrated without `--deflections`, mm.
pub const DEFAULT_DEFLECTIONS_MM: [f64; 4] = [0.1, 0.2, 0.3, 0.5];

/// The largest deflection a probe takes, mm: [`MAX_DEFLECTION_MM`] and
/// 0.9 of the tip's radius.
fn max_deflection(nominal: &NominalProbe) -> f64 {
    MAX_DEFLECTION_MM.min(0.45 * nominal.tip_diameter_mm)
}

/// The deflections to calibrate, mm: `--deflections`, or those of
/// [`DEFAULT_DEFLECTIONS_MM`] the tip allows, or (a tip under 0.23 mm,
/// which allows none of them) its largest deflection and a half of it.
fn deflections(args: &CalibrateArgs, nominal: &NominalProbe) -> Vec<f64> {
    if let Some(given) = &args.deflections {
        return given.clone();
    }
    let max = max_deflection(nominal);
    let allowed: Vec<f64> = (DEFAULT_DEFLECTIONS_MM.iter().copied())
        .filter(|&d| d <= max)
        .collect();
    if allowed.is_empty() {
        vec![0.5 * max, max]
    } else {
        allowed
    }
}

/// Every number of the command line (or the probe file) within its
/// physical range.
fn check_values(args: &CalibrateArgs, nominal: &NominalProbe) -> Result<(), CliError> {
    let (tip, stylus) = match &args.probe {
        Some(_) => ("probe file tip_diameter_mm", "probe file stylus_length_mm"),
        None => ("--probe-tip-diameter", "--stylus-length"),
    };
    in_range(tip, nominal.tip_diameter_mm, TIP_DIAMETER_RANGE_MM, "mm")?;
    in_range(
        stylus,
        nominal.stylus_length_mm,
        STYLUS_LENGTH_RANGE_MM,
        "mm",
    )?;
    in_range(
        "--sphere-diameter",
        args.sphere_diameter,
        SPHERE_DIAMETER_RANGE_MM,
        "mm",
    )?;
    let max_deflection = max_deflection(nominal);
    for d in deflections(args, nominal) {
        if !(d.is_finite() && d > 0.0 && d <= max_deflection) {
            return Err(CliError::Value {
                option: "--deflections",
                value: d.to_string(),
                reason: format!("a deflection must lie in (0, {max_deflection}] mm (at most {MAX_DEFLECTION_MM} mm and 0.9 of the tip radius)"),
            });
        }
    }
    let points = args.orientation_points;
    if !(4..=MAX_ORIENTATION_POINTS).contains(&points) {
        return Err(CliError::Value {
            option: "--orientation-points",
            value: points.to_string(),
            reason: format!(
                "expected 4 (a sphere needs at least 4 points) to {MAX_ORIENTATION_POINTS}"
            ),
        });
    }
    Ok(())
}

/// A calibration failure, naming the machine and probe it ran on.
pub(super) fn failed(
    args: &CalibrateArgs,
    setup: &SimulatedSetup,
    source: crate::app::calibrate::simulate::SimulatedCalError,
) -> CliError {
    let machine = match &args.machine {
        Some(path) => path.display().to_string(),
        None => "built-in bridge CMM".to_string(),
    };
    let profile = match &args.machine_profile {
        Some(path) => format!(", profile {}", path.display()),
        None => String::new(),
    };
    let hint = match source {
        crate::app::calibrate::simulate::SimulatedCalError::Machine(_) => {
            " (the probe starts above the sphere: a shorter --stylus-length or another machine fits)"
        }
        _ => "",
    };
    let machine = format!(
        "{machine}{profile}: probe tip {} mm, stylus {} mm, sphere {} mm{hint}",
        setup.tip_diameter_mm, setup.stylus_length_mm, args.sphere_diameter
    );
    CliError::Calibration {
        machine,
        source: Box::new(source),
    }
}

/// A machine with a probe head needs `--head-angles`: its head joints put
/// the stylus elsewhere than the nominal vertical probe of a 3-axis
/// calibration.
fn check_no_head(args: &CalibrateArgs, machine: &MachineModel) -> Result<(), CliError> {
    let head: Vec<String> = machine
        .revolute_axes()
        .iter()
        .filter_map(|&i| machine.axes().get(i).map(|a| format!("'{}'", a.name)))
        .collect();
    if head.is_empty() {
        return Ok(());
    }
    let file = args
        .machine
        .as_ref()
        .map_or_else(|| "machine".to_string(), |p| p.display().to_string());
    Err(CliError::Usage(format!(
        "{file}: the machine has probe-head joints {}: give the orientations to calibrate with --head-angles (e.g. --head-angles 0,0) and the joints' order with --head-axes",
        head.join(", ")
    )))
}

/// Runs `cmm calibrate-probe`.
pub fn run(args: &CalibrateArgs) -> Result<Status, CliError> {
    let nominal = match &args.probe {
        Some(path) => read_probe_file(path)?,
        None => NominalProbe {
            tip_diameter_mm: args.probe_tip_diameter,
            stylus_length_mm: args.stylus_length,
            shaft_diameter_mm: None,
        },
    };
    check_values(args, &nominal)?;
    crate::output::check_writable(&args.out, false)?;
    let setup = SimulatedSetup {
        machine: match &args.machine {
            Some(path) => MachineModel::from_urdf_file(path)?,
            None => MachineModel::default_bridge(),
        },
        profile: match &args.machine_profile {
            Some(path) => MachineProfile::from_json_file(path)?,
            None => MachineProfile::default(),
        },
        tip_diameter_mm: nominal.tip_diameter_mm,
        stylus_length_mm: nominal.stylus_length_mm,
        shaft_diameter_mm: nominal.shaft_diameter_mm,
        seed: args.seed,
        ideal: args.ideal,
        keep_geometric_errors: args.keep_geometric_errors,
    };
    let opts = CalibrationOptions {
        sphere_diameter_mm: args.sphere_diameter,
        deflections_mm: deflections(args, &nominal),
        directions: args.directions.iter().map(|d| d == "ccw").collect(),
        shaft_radius_mm: nominal.shaft_diameter_mm.map(|d| 0.5 * d),
        ..CalibrationOptions::default()
    };
    if let Some(text) = &args.head_angles {
        return super::calibrate_head::run(args, &setup, &opts, text);
    }
    check_no_head(args, &setup.machine)?;
    let (cal, truth) =
        calibrate_simulated(&setup, &opts).map_err(|source| failed(args, &setup, source))?;
    let text = to_json(&to_file(&cal, &opts), Some(truth));
    crate::output::write_atomic(&args.out, text.as_bytes())?;
    super::say(&summary(&cal, &truth, args))?;
    Ok(Status::Pass)
}

/// The reference calibration's figures, for the terminal.
pub(super) fn summary(cal: &Calibration, truth: &ProbeTruth, args: &CalibrateArgs) -> String {
    let p = cal.probe.probe_vector;
    let mut lines = vec![format!(
        "probe vector     [{:.5}, {:.5}, {:.5}] mm",
        p.x, p.y, p.z
    )];
    lines.push(format!(
        "tip radius       {:.5} mm",
        cal.probe.tip_radius_mm
    ));
    lines.push(format!(
        "probing error P  {:.5} mm (nominal probe values: {:.5} mm)",
        cal.probing_error_mm, cal.probing_error_before_mm
    ));
    lines.push(
        "scan                 deflection    points  before rms/range mm   after rms/range mm"
            .to_string(),
    );
    for s in &cal.scans {
        lines.push(format!(
            "{:<3} {:<4} {:>17.3} {:>9} {:>10.5} {:>9.5} {:>10.5} {:>9.5}",
            serde_json::to_string(&s.plane)
                .unwrap_or_default()
                .trim_matches('"'),
            s.direction,
            s.deflection_mm,
            s.points,
            s.before.rms_mm,
            s.before.range_mm,
            s.after.rms_mm,
            s.after.range_mm
        ));
    }
    let dv = cal.probe.probe_vector - truth.probe_vector;
    lines.push(format!(
        "vs simulation truth: probe vector off by {:.3} um, tip radius by {:.3} um",
        dv.norm() * 1e3,
        (cal.probe.tip_radius_mm - truth.tip_radius_mm) * 1e3
    ));
    lines.push(format!("written {}", args.out.display()));
    lines.join("\n") + "\n"
}
