//! The application layer: the only code that builds a simulated world and
//! wires it to the measuring software (the host) through the
//! [`crate::seam::Cmm`] seam — for a scan, a batch of parts, a probe
//! calibration and a motion trace.
//!
//! Loading a part program for simulation ([`load`]) gives the measuring
//! side's view ([`Program`]) and, apart from it, the simulated scenario
//! (the as-machined part). The host only ever receives the first.

pub mod batch;
pub mod calibrate;
pub mod nominal_form;
pub mod reach;
mod run;

use std::path::Path;
use std::time::Instant;

pub use run::{probe_calibration, run_program, run_program_traced, RunError, RunOptions};

use crate::formats::as_machined::AsMachinedSpec;
use crate::host::inspect::clearance::memo::FreeSpaceMemo;
use crate::host::inspect::design_memo::DesignMemo;
use crate::machine::MachineProfile;
use crate::program::{MachineFiles, ProfileSource, Program, ProgramError};
use crate::world::as_machined::AsMachined;

/// A part program loaded for simulation: the measuring side's view and the
/// simulated scenario, kept apart.
#[derive(Debug, Clone)]
pub struct SimulatedPart {
    /// What the measuring side sees.
    pub program: Program,
    /// The true part the world measures (never given to the host).
    pub as_machined: AsMachined,
    /// The machine's profile: its dynamics, noise and true geometric
    /// errors (the world's; the host gets only a copy of the error terms
    /// as its compensation map).
    pub profile: MachineProfile,
    /// How long loading the program and its design data took, s (counted
    /// in each of its reports' `wall_time_s`).
    pub load_s: f64,
    /// The free-space answers of the design data, shared by every run of
    /// the program (a batch's variants).
    pub free_space: FreeSpaceMemo,
    /// The section designs of its curves, shared by every run of the
    /// program.
    pub designs: DesignMemo,
}

/// Reads and validates a part program and the scenario it names; every
/// error names the file, the JSON path and the reason.
pub fn load(file: &Path) -> Result<SimulatedPart, ProgramError> {
    load_on(file, &MachineFiles::default())
}

/// [`load`] on the machine files `files` names (`--machine`,
/// `--machine-profile`; each overrides the program's key).
pub fn load_on(file: &Path, files: &MachineFiles) -> Result<SimulatedPart, ProgramError> {
    let started = Instant::now();
    let (program, spec) = crate::program::read_on(file, files)?;
    let as_machined = scenario(&program, &spec.as_machined, file)?;
    let profile = match &spec.machine_profile {
        None => MachineProfile::default(),
        Some(ProfileSource::CommandLine(path)) => MachineProfile::from_json_file(path)?,
        Some(ProfileSource::Program(path)) => {
            MachineProfile::from_json_file(path).map_err(|e| ProgramError::Invalid {
                file: file.to_path_buf(),
                json_path: "$.machine_profile".into(),
                reason: e.to_string(),
            })?
        }
    };
    Ok(SimulatedPart {
        program,
        as_machined,
        profile,
        load_s: started.elapsed().as_secs_f64(),
        free_space: FreeSpaceMemo::default(),
        designs: DesignMemo::default(),
    })
}

/// The simulated true part of `program` from its `as_machined` block
/// (`file` names the program in messages).
pub fn scenario(
    program: &Program,
    spec: &AsMachinedSpec,
    file: &Path,
) -> Result<AsMachined, ProgramError> {
    AsMachined::from_spec(spec, &program.workpiece).map_err(|e| ProgramError::Invalid {
        file: file.to_path_buf(),
        json_path: format!("$.as_machined.{}", e.json_path),
        reason: e.reason,
    })
}

/// Replaces every part's as-machined part by the one in `file` (an
/// `as_machined` object, the as-machined format).
pub fn override_as_machined(parts: &mut [SimulatedPart], file: &Path) -> Result<(), ProgramError> {
    let text = crate::jsonfile::read_text(file).map_err(|source| ProgramError::Io {
        file: file.to_path_buf(),
        source,
    })?;
    let spec: AsMachinedSpec = crate::jsonfile::parse_json(&text, file)?;
    crate::program::limits::check_as_machined(&spec, file, "$")?;
    for part in parts.iter_mut() {
        part.as_machined = AsMachined::from_spec(&spec, &part.program.workpiece).map_err(|e| {
            ProgramError::Invalid {
                file: file.to_path_buf(),
                json_path: format!("$.{}", e.json_path),
                reason: e.reason,
            }
        })?;
    }
    Ok(())
}
