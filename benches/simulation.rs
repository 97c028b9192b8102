//! Simulator speed: control cycles per second during active scanning of
//! the blade (target: >= 2 million per second on one core) and of a real
//! trimmed CAD part (NIST CTC 5, 209 faces, imported at bench time when
//! the shared CAD files are beside the repository; the per-cycle contact
//! search must not grow with the part: within 2x of the blade's cost), and
//! a whole error-correcting part with learned corrections.
//!
//! `cargo bench --bench simulation`
use std::hint::black_box;
use std::path::Path;

use cmm::app::{load, run_program, RunOptions, SimulatedPart};
use cmm::host::modes::{design_value_scan, HostProbe, ModeOptions, ScanPlan, ScanTargets};
use cmm::host::observe::Unobserved;
use cmm::host::path::{BallPath, PathOptions, SegmentSpeeds, SpeedOptions, SpeedPlan};
use cmm::machine::{MachineModel, MachineProfile};
use cmm::math::{Point3, Vec3};
use cmm::program::{Feature, Program};
use cmm::seam::Cmm;
use cmm::world::cmm::{SimulatedCmm, TruePart};
use cmm::world::probe::TrueProbe;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn program(name: &str) -> SimulatedPart {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("part-programs")
        .join(name);
    match load(&path) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    }
}

/// The z60 section's ball path and speed plan, machine frame.
fn path_and_plan(p: &Program) -> (BallPath, SpeedPlan) {
    let Some(Feature::Section {
        curves, settings, ..
    }) = p.features.first()
    else {
        panic!("no section")
    };
    let c = &curves[0];
    let pts: Vec<(Point3, Vec3)> = c
        .points
        .iter()
        .map(|q| {
            (
                p.placement.to_machine(q.point),
                p.placement.dir_to_machine(q.normal),
            )
        })
        .collect();
    let path = BallPath::from_section(
        &pts,
        c.closed,
        p.probe.tip_radius_mm - settings.deflection_mm,
        PathOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let plan = SpeedPlan::new(
        &path,
        &SpeedOptions {
            speed_mm_s: settings.speed_mm_s,
            ..SpeedOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (path, plan)
}

/// One active scan of the section from 5.3 mm off its start; returns the
/// number of control cycles simulated (approach included).
fn scan_once(sp: &SimulatedPart, model: &MachineModel, path: &BallPath, plan: &ScanPlan) -> u64 {
    let p = &sp.program;
    let part = TruePart {
        workpiece: &p.workpiece,
        as_machined: &sp.as_machined,
        pose: p.placement,
    };
    let pv = Vec3::new(0.0, 0.0, -p.probe.stylus_length_mm);
    let probe = TrueProbe::realistic(pv, p.probe.tip_radius_mm);
    let start = path.position(0.0) + path.normal(0.0) * 5.3 - pv;
    let Ok(mut sim) = SimulatedCmm::new(
        part,
        model.clone(),
        MachineProfile::default(),
        probe,
        1,
        start,
    ) else {
        panic!("sim")
    };
    let host = HostProbe::nominal(pv, p.probe.tip_radius_mm);
    let targets = ScanTargets {
        deflection_mm: 0.3,
        pitch_mm: 0.5,
        trajectory_tolerance_mm: 1.5,
        plane_normal: None,
    };
    let modes = ModeOptions::default();
    design_value_scan(
        &mut Unobserved(&mut sim),
        (host, None),
        path,
        plan,
        targets,
        &modes,
    );
    (sim.readings().time_s / sim.cycle_s()).round() as u64
}

/// Criterion's throughput of active scans of the first section curve of
/// `p` (control cycles per second).
fn scan_bench(c: &mut Criterion, name: &str, p: &SimulatedPart) {
    let (path, plan) = path_and_plan(&p.program);
    let plan = ScanPlan::Active(plan.speeds().clone());
    let model = MachineModel::default_bridge();
    let cycles = scan_once(p, &model, &path, &plan);
    println!("{name}: {cycles} control cycles per run");
    let mut g = c.benchmark_group("simulation");
    g.throughput(Throughput::Elements(cycles));
    g.bench_function(name, |b| {
        b.iter(|| black_box(scan_once(p, &model, &path, &plan)))
    });
    g.finish();
}

/// NIST CTC 5 (STEP, 209 trimmed faces) imported through `cmm::cad`,
/// placed at (350, 500, 20) with its z = 100 section: a program written to
/// a temporary directory. `None` when the CAD file is not there.
fn ctc05_program() -> Option<(tempfile::TempDir, SimulatedPart)> {
    let step = Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/nist-ctc05.stp");
    if !step.exists() {
        println!("note: {} not found; skipping the CAD part", step.display());
        return None;
    }
    let import = cmm::cad::import(&step).unwrap_or_else(|e| panic!("{e}"));
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let wp = dir.path().join("ctc05.json");
    let text = serde_json::to_string(&import.workpiece).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(&wp, text).unwrap_or_else(|e| panic!("{e}"));
    let prog = serde_json::json!({
        "format": "cmm-program/1", "name": "ctc05-z100", "workpiece": "ctc05.json",
        "placement": { "translate_mm": [350, 500, 20], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        "defaults": { "speed_mm_s": 80, "deflection_mm": 0.3, "pitch_mm": 0.5,
                      "trajectory_tolerance_mm": 1.5 },
        "as_machined": { "form": [ { "kind": "offset", "mm": 0.01 } ], "roughness_um": 0.2 },
        "features": [ { "name": "z100", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 100], "normal": [0, 0, 1] },
            "tolerance_mm": [-0.1, 0.1] } ] });
    let file = dir.path().join("ctc05-z100.json");
    std::fs::write(&file, prog.to_string()).unwrap_or_else(|e| panic!("{e}"));
    let p = load(&file).unwrap_or_else(|e| panic!("{e}"));
    Some((dir, p))
}

fn bench(c: &mut Criterion) {
    let p = program("blade-z60.json");
    scan_bench(c, "active_scan_blade_z60_cycles", &p);
    if let Some((_dir, cad)) = ctc05_program() {
        scan_bench(c, "active_scan_ctc05_z100_cycles", &cad);
    }
    let overcut = program("blade-overcut.json");
    let Ok((_, learned)) = run_program(&overcut, &RunOptions::default()) else {
        panic!("first part")
    };
    let opts = RunOptions {
        learned,
        seed: 2,
        ..RunOptions::default()
    };
    c.bench_function("part_blade_overcut_with_learned_correction", |b| {
        b.iter(|| black_box(run_program(&overcut, &opts).ok()))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(3));
    targets = bench, overhead
}
criterion_main!(benches);

/// What a run of blade-z60 spends besides the per-cycle loop: re-planning
/// the z60 section's speeds, and the whole run (the real-time ratio is its
/// machine time over this wall time).
fn overhead(c: &mut Criterion) {
    let p = program("blade-z60.json");
    let (path, plan) = path_and_plan(&p.program);
    let Some(Feature::Section { settings, .. }) = p.program.features.first() else {
        panic!("no section")
    };
    let opts = SpeedOptions {
        speed_mm_s: settings.speed_mm_s,
        ..SpeedOptions::default()
    };
    println!("z60 speed plan: {} cycles", plan.profile().cycles());
    c.bench_function("speed_plan_blade_z60", |b| {
        b.iter(|| black_box(SpeedPlan::new(&path, &opts).ok()))
    });
    c.bench_function("segment_speeds_blade_z60", |b| {
        b.iter(|| black_box(SegmentSpeeds::new(&path, &opts).ok()))
    });
    c.bench_function("part_blade_z60", |b| {
        b.iter(|| black_box(run_program(&p, &RunOptions::default()).ok()))
    });
}
