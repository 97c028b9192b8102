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
    /// Scan deflections, mm (comma separated).
    #[arg(long, value_delimiter = ',', default_values_t = vec![0.1, 0.2, 0.3, 0.5])]
    pub deflections: Vec<f64>,
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

/// Runs `cmm calibrate-probe`.
pub fn run(args: &CalibrateArgs) -> Result<Status, CliError> {
    let nominal = match &args.probe {
        Some(path) => read_probe_file(path)?,
        None => NominalProbe {
            tip_diameter_mm: args.probe_tip_diameter,
            stylus_length_mm: args.stylus_length,
        },
    };
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
        seed: args.seed,
        ideal: args.ideal,
        keep_geometric_errors: args.keep_geometric_errors,
    };
    let opts = CalibrationOptions {
        sphere_diameter_mm: args.sphere_diameter,
        deflections_mm: args.deflections.clone(),
        directions: args.directions.iter().map(|d| d == "ccw").collect(),
        ..CalibrationOptions::default()
    };
    if let Some(text) = &args.head_angles {
        return super::calibrate_head::run(args, &setup, &opts, text);
    }
    let (cal, truth) = calibrate_simulated(&setup, &opts)?;
    let text = to_json(&to_file(&cal, &opts), Some(truth));
    crate::output::write_atomic(&args.out, text.as_bytes())?;
    print_summary(&cal, &truth, args);
    Ok(Status::Pass)
}

/// Prints the reference calibration's figures.
pub(super) fn print_summary(cal: &Calibration, truth: &ProbeTruth, args: &CalibrateArgs) {
    let p = cal.probe.probe_vector;
    println!("probe vector     [{:.5}, {:.5}, {:.5}] mm", p.x, p.y, p.z);
    println!("tip radius       {:.5} mm", cal.probe.tip_radius_mm);
    println!(
        "probing error P  {:.5} mm (nominal probe values: {:.5} mm)",
        cal.probing_error_mm, cal.probing_error_before_mm
    );
    println!("scan                 deflection    points  before rms/range mm   after rms/range mm");
    for s in &cal.scans {
        println!(
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
        );
    }
    let dv = cal.probe.probe_vector - truth.probe_vector;
    println!(
        "vs simulation truth: probe vector off by {:.3} um, tip radius by {:.3} um",
        dv.norm() * 1e3,
        (cal.probe.tip_radius_mm - truth.tip_radius_mm) * 1e3
    );
    println!("written {}", args.out.display());
}
