//! Batches of parts: several programs and random as-machined variants of
//! each, run in parallel, with corrections learned across parts.
//!
//! Learning is deterministic whatever the number of jobs: the first part of
//! each program runs with the corrections known before the batch; every
//! later part of that program starts from what the first part learned.
use rayon::prelude::*;

use super::run::run_variant;
use super::{RunError, RunOptions, SimulatedPart};
use crate::host::inspect::learned::CorrectionsFile;
use crate::host::inspect::LearnedSet;
use crate::host::trace::TraceRow;
use crate::report::Report;

/// One part of a batch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Part {
    /// Index of its program.
    pub program: usize,
    /// Variant number (0 = the program's own as-machined part).
    pub variant: usize,
    /// Seed of its simulation.
    pub seed: u64,
}

/// The parts of a batch: `variants` per program, seeds derived from `seed`,
/// keeping those of shard `k` of `n` (1-based `k`).
pub fn plan_parts(programs: usize, variants: usize, seed: u64, shard: (usize, usize)) -> Vec<Part> {
    let all = (0..programs).flat_map(|p| (0..variants.max(1)).map(move |v| (p, v)));
    all.enumerate()
        .filter(|(i, _)| shard.1 <= 1 || i % shard.1 == shard.0.saturating_sub(1))
        .map(|(_, (program, variant))| Part {
            program,
            variant,
            seed: derive_seed(seed, variant),
        })
        .collect()
}

/// Seed of variant `v` (variant 0 keeps the given seed).
fn derive_seed(seed: u64, v: usize) -> u64 {
    if v == 0 {
        seed
    } else {
        seed.wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407u64.wrapping_mul(v as u64))
    }
}

/// Result of one part.
pub type PartResult = Result<(Report, LearnedSet), RunError>;

/// Runs the parts on `jobs` threads; returns results in part order and
/// the updated corrections.
/// `done` is called with every finished part's number (in `parts`) and
/// result, as it finishes (for progress display, and to write its files
/// while the others run).
pub fn run_batch(
    programs: &[SimulatedPart],
    parts: &[Part],
    base: &RunOptions,
    known: &CorrectionsFile,
    jobs: usize,
    done: &(dyn Fn(usize, &PartResult) + Sync),
) -> (Vec<PartResult>, CorrectionsFile) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build();
    let run = || {
        let first: Vec<usize> = (0..parts.len())
            .filter(|&i| !parts[..i].iter().any(|p| p.program == parts[i].program))
            .collect();
        let mut results: Vec<Option<PartResult>> = (0..parts.len()).map(|_| None).collect();
        let phase1: Vec<(usize, PartResult)> = first
            .par_iter()
            .map(|&i| {
                (i, {
                    let r = run_part(programs, &parts[i], base, known, &[]);
                    done(i, &r);
                    r
                })
            })
            .collect();
        let learned_first: Vec<(usize, LearnedSet)> = phase1
            .iter()
            .filter_map(|(i, r)| r.as_ref().ok().map(|(_, l)| (parts[*i].program, l.clone())))
            .collect();
        let rest: Vec<usize> = (0..parts.len()).filter(|i| !first.contains(i)).collect();
        // The first parts counted the programs' loading.
        let later = RunOptions {
            count_load: false,
            ..base.clone()
        };
        let phase2: Vec<(usize, PartResult)> = rest
            .par_iter()
            .map(|&i| {
                (i, {
                    let r = run_part(programs, &parts[i], &later, known, &learned_first);
                    done(i, &r);
                    r
                })
            })
            .collect();
        for (i, r) in phase1.into_iter().chain(phase2) {
            results[i] = Some(r);
        }
        results.into_iter().flatten().collect::<Vec<_>>()
    };
    let results = match pool {
        Ok(p) => p.install(run),
        Err(_) => run(),
    };
    let mut updated = known.clone();
    for (part, r) in parts.iter().zip(&results) {
        if let (Ok((report, learned)), Some(_)) = (r, programs.get(part.program)) {
            updated.merge(&report.program, learned);
        }
    }
    (results, updated)
}

fn run_part(
    programs: &[SimulatedPart],
    part: &Part,
    base: &RunOptions,
    known: &CorrectionsFile,
    first: &[(usize, LearnedSet)],
) -> PartResult {
    run_part_traced(programs, part, base, (known, first), false).map(|(r, l, _)| (r, l))
}

/// One part of a batch on its own variant of the as-machined part, with
/// the corrections `known` before the batch and those the `first` parts
/// of its program learned; with `trace`, also the motion trace of every
/// cycle. A part run alone (`--shard`, `--trace`) measures exactly what
/// it measures in its batch.
pub fn run_part_traced(
    programs: &[SimulatedPart],
    part: &Part,
    base: &RunOptions,
    (known, first): (&CorrectionsFile, &[(usize, LearnedSet)]),
    trace: bool,
) -> Result<(Report, LearnedSet, Vec<TraceRow>), RunError> {
    let Some(program) = programs.get(part.program) else {
        return Err(RunError::NoProgram {
            index: part.program,
        });
    };
    let mut learned = known.for_program(&program.program.name);
    for (_, set) in first.iter().filter(|(p, _)| *p == part.program) {
        for (key, l) in set {
            learned.retain(|(k, _)| k != key);
            learned.push((key.clone(), l.clone()));
        }
    }
    let variant;
    let truth = if part.variant > 0 {
        variant = program.as_machined.variant(part.seed);
        &variant
    } else {
        &program.as_machined
    };
    let opts = RunOptions {
        seed: part.seed,
        learned,
        ..base.clone()
    };
    run_variant(program, truth, &opts, trace)
}
