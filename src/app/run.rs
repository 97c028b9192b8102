//! Running a whole program on the simulated CMM: the world (the true part
//! at the program's placement, the machine, the true probe) is built here
//! and handed to the host as a [`crate::seam::Cmm`]; after the measuring,
//! the points are evaluated against the design and, in one separate step
//! ([`crate::evaluate::truth`]), against the truth.
use std::borrow::Cow;
use std::time::Instant;

use super::SimulatedPart;
use crate::evaluate::feature::feature_report;
use crate::evaluate::nominal::{point_reports, Section};
use crate::evaluate::truth::{fill_true_deviations_on, Frames, Truth};
use crate::host::calibrate::file::{ProbeCalError, ProbeCalibration};
use crate::host::compensated::Compensated;
use crate::host::compensation::ErrorMap;
use crate::host::inspect::align::{align, AlignOptions, AlignmentFailure};
use crate::host::inspect::clearance::memo::Remembering;
use crate::host::inspect::clearance::ClearanceOptions;
use crate::host::inspect::feature::{measure_feature, MeasuredFeature, Run};
use crate::host::inspect::supervisor::SupervisorOptions;
use crate::host::inspect::LearnedSet;
use crate::host::modes::{park, FreeSpace, HostProbe, ModeOptions, Outcome};
use crate::host::observe::Machine;
use crate::host::trace::{TraceRow, TracingCmm};
use crate::machine::{MachineModel, MachineProfile};
use crate::program::limits::start_position;
use crate::program::{Feature, Program};
use crate::report::{
    AlignmentReport, EndMoveReport, FeatureReport, PartToMachine, ProbeUsed, Report, Verdict,
    REPORT_FORMAT,
};
use crate::seam::Cmm;
use crate::world::as_machined::AsMachined;
use crate::world::cmm::{SimError, SimulatedCmm, TruePart};
use crate::world::contact::ContactSearch;
use crate::world::probe::{ProbeShape, TrueProbe};

/// How to run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOptions {
    /// Seed of every random draw.
    pub seed: u64,
    /// Switch off every simulated error and all noise.
    pub ideal: bool,
    /// Mode gains and thresholds.
    pub modes: ModeOptions,
    /// Supervisor limits.
    pub supervisor: SupervisorOptions,
    /// Corrections learned on earlier parts, by feature name and curve index.
    pub learned: LearnedSet,
    /// Probe calibration to use (`--probe-cal`); overrides the program's
    /// `probe.calibration`. Nominal probe values when neither is given.
    pub probe_calibration: Option<ProbeCalibration>,
    /// Move straight between measurements when the line is clear of the
    /// part (else always over the clearance height).
    pub direct_moves: bool,
    /// The direct-move check's sampling (its margins are the program's).
    pub clearance: ClearanceOptions,
    /// Correct the scale readings by the machine profile's geometric
    /// error terms (the host's compensation map); `false` shows what the
    /// compensation is worth (the world's errors stay).
    pub compensation: bool,
    /// Count the loading of the program and its design data in the
    /// report's `wall_time_s`: the part that loaded it (a batch's first
    /// part of each program; its later parts share the load and count
    /// their own run only, so a batch's times add up to its run).
    pub count_load: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            seed: 1,
            ideal: false,
            modes: ModeOptions::default(),
            supervisor: SupervisorOptions::default(),
            learned: Vec::new(),
            probe_calibration: None,
            direct_moves: true,
            clearance: ClearanceOptions::default(),
            compensation: true,
            count_load: true,
        }
    }
}

/// Why a run could not start.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// A batch part names a program that does not exist.
    #[error("batch part refers to program {index}, which does not exist")]
    NoProgram {
        /// The index.
        index: usize,
    },
    /// The program's probe calibration file is invalid.
    #[error("{program}: {source}")]
    ProbeCal {
        /// Program name.
        program: String,
        /// The reason.
        source: ProbeCalError,
    },
    /// The simulator could not be set up.
    #[error("{program}: cannot start the simulated machine: {source}")]
    Machine {
        /// Program name.
        program: String,
        /// The reason.
        source: SimError,
    },
}

/// Runs every feature and evaluates the points; also returns what was
/// learned per (feature, curve).
pub fn run_program(
    part: &SimulatedPart,
    opts: &RunOptions,
) -> Result<(Report, LearnedSet), RunError> {
    run_program_traced(part, opts, false).map(|(r, l, _)| (r, l))
}

/// [`run_program`] that can also record a motion trace of every cycle.
///
/// `wall_time_s` covers the part's whole run: loading its program (as
/// measured by [`load`]), setting up, measuring, evaluating and fitting,
/// until the report is complete.
pub fn run_program_traced(
    part: &SimulatedPart,
    opts: &RunOptions,
    trace: bool,
) -> Result<(Report, LearnedSet, Vec<TraceRow>), RunError> {
    run_variant(part, &part.as_machined, opts, trace)
}

/// [`run_program_traced`] of `part`'s program on the true part `truth`
/// (one of a batch's variants).
pub(super) fn run_variant(
    part: &SimulatedPart,
    truth: &AsMachined,
    opts: &RunOptions,
    trace: bool,
) -> Result<(Report, LearnedSet, Vec<TraceRow>), RunError> {
    let started = Instant::now();
    let program = &part.program;
    let profile = machine_profile(&part.profile, opts);
    let setup = Setup::new(program, truth, opts, &profile)?;
    let machine = (program.machine.clone(), profile);
    let m = measure_program(part, opts, (&setup, machine), trace)?;
    let aligned = m.program.as_ref();
    let faces: Vec<Vec<usize>> = m.measured.iter().map(|mf| mf.faces.clone()).collect();
    let mut features: Vec<FeatureReport> = (aligned.features.iter().zip(m.measured))
        .map(|(f, mf)| {
            // A section scan's points lie in its plane, and its fit is
            // compared with the design's section.
            let section = match f {
                Feature::Section { plane, fit, .. } => Some(Section {
                    plane,
                    fitted: fit.is_some(),
                }),
                _ => None,
            };
            let points = (mf.results.iter())
                .flat_map(|r| {
                    let faces = (mf.faces.as_slice(), section);
                    point_reports(&aligned.workpiece, &aligned.placement, faces, &r.points)
                })
                .collect();
            feature_report(f, mf, points)
        })
        .collect();
    let frames = Frames {
        reported: aligned.placement,
        world: program.placement,
    };
    let faces: Vec<&[usize]> = faces.iter().map(Vec::as_slice).collect();
    let truth = Truth {
        workpiece: &program.workpiece,
        part: &setup.truth,
        search: &m.search,
    };
    fill_true_deviations_on(&mut features, &faces, truth, frames);
    let report = Report {
        format: REPORT_FORMAT,
        program: program.name.clone(),
        seed: opts.seed,
        status: program_verdict(&features, m.alignment.as_ref(), &m.end_move),
        machine_time_s: m.machine_time_s,
        wall_time_s: if opts.count_load { part.load_s } else { 0.0 }
            + started.elapsed().as_secs_f64(),
        part_to_machine: part_to_machine(aligned),
        alignment: m.alignment,
        ideal: opts.ideal,
        probe: ProbeUsed {
            source: (setup.calibration.as_ref())
                .map_or("nominal".into(), |c| c.source.display().to_string()),
            tip_radius_mm: setup.host_probe.tip_radius_mm,
            probe_vector_mm: setup.host_probe.probe_vector.into(),
        },
        features,
        end_move: m.end_move,
    };
    Ok((report, m.learned, m.rows))
}

/// What a run sets up before measuring.
struct Setup {
    calibration: Option<ProbeCalibration>,
    host_probe: HostProbe,
    /// The host's geometric error map (none without compensation).
    map: ErrorMap,
    /// The true part (without roughness on an ideal machine).
    truth: AsMachined,
}

impl Setup {
    fn new(
        program: &Program,
        truth: &AsMachined,
        opts: &RunOptions,
        profile: &MachineProfile,
    ) -> Result<Setup, RunError> {
        let calibration = probe_calibration(program, opts)?;
        let host_probe = calibration.as_ref().map_or(
            HostProbe::nominal(program.probe_vector(), program.probe.tip_radius_mm),
            |c| c.probe,
        );
        let truth = if opts.ideal {
            truth.clone().without_roughness()
        } else {
            truth.clone()
        };
        let map = if opts.compensation {
            super::calibrate::simulate::host_error_map(profile)
        } else {
            ErrorMap::none()
        };
        Ok(Setup {
            calibration,
            host_probe,
            map,
            truth,
        })
    }
}

/// What the measuring gives.
struct Measuring<'p> {
    /// The program as measured (its placement the alignment's result).
    program: Cow<'p, Program>,
    measured: Vec<MeasuredFeature>,
    alignment: Option<AlignmentReport>,
    machine_time_s: f64,
    rows: Vec<TraceRow>,
    learned: LearnedSet,
    end_move: EndMoveReport,
    /// The simulated machine's contact search on the true part.
    search: ContactSearch,
}

/// Starts the simulated machine, aligns the part and measures every
/// feature.
fn measure_program<'p>(
    part: &'p SimulatedPart,
    opts: &RunOptions,
    (setup, machine): (&Setup, (MachineModel, MachineProfile)),
    trace: bool,
) -> Result<Measuring<'p>, RunError> {
    let program = &part.program;
    let mut sim = start_machine(program, opts, setup, machine)?;
    let mut raw = TracingCmm::new(&mut sim, trace);
    let host_probe = setup.host_probe;
    let mut traced = Compensated::new(&mut raw, &setup.map, host_probe.probe_vector);
    let modes = ModeOptions {
        clearance_z_mm: Some(start_position(program).1),
        travel_mm: Some(super::reach::travel_box(program)),
        ..opts.modes
    };
    let (aligned, alignment) = match aligned_program((part, opts), &mut traced, host_probe, &modes)
    {
        Ok(a) => a,
        Err(failure) => (
            Cow::Borrowed(program),
            Some(failure.report(&program.placement)),
        ),
    };
    let margins = super::reach::program_margins(&aligned, opts.clearance);
    let clearance = super::reach::part_clearance(&aligned, host_probe, margins);
    let free = Remembering::new(&clearance, &part.free_space);
    let run = Run {
        program: &aligned,
        probe: host_probe,
        modes: &modes,
        supervisor: opts.supervisor,
        learned: &opts.learned,
        free: opts.direct_moves.then_some(&free as &dyn FreeSpace),
        designs: &part.designs,
    };
    let mut learned = Vec::new();
    let measured = aligned
        .features
        .iter()
        .map(|f| measure_feature(&run, f, &mut traced, &mut learned))
        .collect();
    let end_start = traced.readings().time_s;
    let ended = park(&mut traced, host_probe, run.free, &modes);
    let machine_time_s = traced.readings().time_s;
    let end_move = EndMoveReport::new(ended, machine_time_s - end_start, &aligned.placement);
    let rows = raw.into_rows();
    let search = sim.into_contact_search();
    Ok(Measuring {
        program: aligned,
        measured,
        alignment,
        machine_time_s,
        rows,
        learned,
        end_move,
        search,
    })
}

/// The simulated machine with the true part in the program's placement,
/// the probe above the part.
fn start_machine<'a>(
    program: &'a Program,
    opts: &RunOptions,
    setup: &'a Setup,
    (machine, profile): (MachineModel, MachineProfile),
) -> Result<SimulatedCmm<'a>, RunError> {
    let part = TruePart {
        workpiece: &program.workpiece,
        as_machined: &setup.truth,
        pose: program.placement,
    };
    let stylus = program.stylus();
    let r = program.probe.tip_radius_mm;
    let mut true_probe = if opts.ideal {
        TrueProbe::ideal(stylus, r)
    } else {
        TrueProbe::realistic(stylus, r)
    };
    true_probe.shape = ProbeShape {
        shaft_radius_mm: program.probe.shaft_radius_mm,
        body_radius_mm: program.probe.body_radius_mm,
        body_length_mm: program.probe.body_length_mm,
    };
    let start = start_position(program).0;
    SimulatedCmm::new(
        part,
        machine,
        profile,
        true_probe,
        opts.seed,
        start - program.probe_vector(),
    )
    .map_err(|source| RunError::Machine {
        program: program.name.clone(),
        source,
    })
}

/// The machine's profile, every error and all noise off with `ideal`.
fn machine_profile(profile: &MachineProfile, opts: &RunOptions) -> MachineProfile {
    if opts.ideal {
        profile.ideal()
    } else {
        profile.clone()
    }
}

/// The calibration of `--probe-cal`, else the program's, else none.
pub fn probe_calibration(
    program: &Program,
    opts: &RunOptions,
) -> Result<Option<ProbeCalibration>, RunError> {
    if let Some(c) = &opts.probe_calibration {
        return Ok(Some(c.clone()));
    }
    program
        .probe
        .calibration
        .as_deref()
        .map(ProbeCalibration::read)
        .transpose()
        .map_err(|source| RunError::ProbeCal {
            program: program.name.clone(),
            source,
        })
}

/// The program with its placement replaced by the best-fit alignment (when
/// it has alignment points; else the program itself, not a copy).
fn aligned_program<'p>(
    (part, opts): (&'p SimulatedPart, &RunOptions),
    cmm: &mut dyn Machine,
    probe: HostProbe,
    modes: &ModeOptions,
) -> Result<(Cow<'p, Program>, Option<AlignmentReport>), AlignmentFailure> {
    let program = &part.program;
    let Some(points) = &program.alignment else {
        return Ok((Cow::Borrowed(program), None));
    };
    // The touches route round the part as placed nominally.
    let margins = super::reach::program_margins(program, opts.clearance);
    let clearance = super::reach::part_clearance(program, probe, margins);
    let free = Remembering::new(&clearance, &part.free_space);
    let free = opts.direct_moves.then_some(&free as &dyn FreeSpace);
    let (pose, report) = align(
        cmm,
        (probe, free),
        &program.workpiece,
        &program.placement,
        points,
        modes,
        &AlignOptions::default(),
    )?;
    Ok((
        Cow::Owned(Program {
            placement: pose,
            ..program.clone()
        }),
        Some(report),
    ))
}

fn part_to_machine(program: &Program) -> PartToMachine {
    let r = program.placement.rotation;
    PartToMachine {
        rotation: [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]),
        translation_mm: program.placement.translation.into(),
    }
}

/// The program's verdict: incomplete when its alignment failed or its end
/// move struck the part (a crash a batch script must see, though every
/// feature was measured before it), else that of its features.
fn program_verdict(
    features: &[FeatureReport],
    alignment: Option<&AlignmentReport>,
    end_move: &EndMoveReport,
) -> Verdict {
    let failed = alignment.and_then(|a| a.failed).is_some();
    if failed || end_move.outcome == Outcome::Collision {
        return Verdict::Incomplete;
    }
    overall(features)
}

fn overall(features: &[FeatureReport]) -> Verdict {
    if features.iter().any(|f| f.status == Verdict::Incomplete) {
        Verdict::Incomplete
    } else if features.iter().any(|f| f.status == Verdict::Fail) {
        Verdict::Fail
    } else {
        Verdict::Pass
    }
}
