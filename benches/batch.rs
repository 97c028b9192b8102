//! Benchmark: a batch of 10 parts of the blade program with a
//! repeating deviation (`part-programs/blade-batch.json`: both blade
//! sections, a uniform 2.5 mm overcut, +-10 % and +-0.02 mm from part to
//! part), total machine time of error-correcting scanning with learned
//! corrections against autonomous-only scanning of the same sections.
//! Machine time is simulated, so this prints figures instead of timing
//! anything: `cargo bench --bench batch`.
use std::path::Path;

use cmm::app::batch::{plan_parts, run_batch, PartResult};
use cmm::app::{load, run_program_traced, RunOptions, SimulatedPart};
use cmm::host::inspect::learned::CorrectionsFile;
use cmm::host::observe::Phase;
use cmm::host::trace::time_by_phase;
use cmm::program::{Feature, Mode};

/// Parts in the batch.
const PARTS: usize = 10;
/// Seed of the batch (variant seeds derive from it).
const SEED: u64 = 1;
/// Threads.
const JOBS: usize = 2;

fn program() -> SimulatedPart {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("part-programs/blade-batch.json");
    load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The same program with every section scanned autonomously.
fn autonomous(p: &SimulatedPart) -> SimulatedPart {
    let mut out = p.clone();
    for f in &mut out.program.features {
        if let Feature::Section { settings, .. } = f {
            settings.mode = Mode::Autonomous;
        }
    }
    out
}

/// Runs the batch; returns per-part machine times and the corrections.
fn batch(p: &SimulatedPart, known: &CorrectionsFile) -> (Vec<f64>, CorrectionsFile) {
    let parts = plan_parts(1, PARTS, SEED, (1, 1));
    let base = RunOptions::default();
    let (results, learned) = run_batch(
        std::slice::from_ref(p),
        &parts,
        &base,
        known,
        JOBS,
        &|_, _| {},
    );
    let times = results.iter().map(part_time).collect();
    (times, learned)
}

fn part_time(r: &PartResult) -> f64 {
    match r {
        Ok((report, _)) => report.machine_time_s,
        Err(e) => panic!("{e}"),
    }
}

/// Machine time per phase of one part (variant 0), s.
fn breakdown(p: &SimulatedPart, known: &CorrectionsFile) -> String {
    let opts = RunOptions {
        learned: known.for_program(&p.program.name),
        ..RunOptions::default()
    };
    let (report, _, rows) = run_program_traced(p, &opts, true).unwrap_or_else(|e| panic!("{e}"));
    let parts: Vec<String> = time_by_phase(&rows)
        .iter()
        .filter(|(ph, t)| *t > 0.0 && *ph != Phase::Idle)
        .map(|(ph, t)| format!("{} {t:.2}", ph.name()))
        .collect();
    format!("{:.2} s = {}", report.machine_time_s, parts.join(" + "))
}

fn main() {
    let p = program();
    let auto = autonomous(&p);
    let (cold, learned) = batch(&p, &CorrectionsFile::empty());
    let (warm, _) = batch(&p, &learned);
    let (aut, _) = batch(&auto, &CorrectionsFile::empty());
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    let (t_cold, t_warm, t_auto) = (sum(&cold), sum(&warm), sum(&aut));
    println!(
        "{PARTS} parts of {} (seed {SEED}), machine time:",
        p.program.name
    );
    println!("  autonomous only:                          {t_auto:7.1} s");
    println!(
        "  error-correcting, first part learns:      {t_cold:7.1} s  ({:.2}x less; first part {:.1} s)",
        t_auto / t_cold,
        cold.first().copied().unwrap_or(0.0)
    );
    println!(
        "  error-correcting, corrections from before: {t_warm:6.1} s  ({:.2}x less)",
        t_auto / t_warm
    );
    println!("one part, by phase:");
    println!("  learned corrections: {}", breakdown(&p, &learned));
    println!(
        "  autonomous only:     {}",
        breakdown(&auto, &CorrectionsFile::empty())
    );
}
