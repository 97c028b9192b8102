mod common;
use cmm::host::modes::*;
use cmm::host::path::{BallPath, PathOptions, SpeedOptions, SpeedPlan};
use cmm::math::{Point3, Vec3};
use cmm::program::{load, Feature};
use cmm::world::cmm::{SimulatedCmm, TruePart};
use cmm::world::machine::{MachineModel, MachineProfile};
use cmm::world::probe::TrueProbe;

#[test]
fn smoke() {
    let prog = load(&common::repo("part-programs/blade-z60.json")).unwrap();
    let am = prog.as_machined.clone().without_roughness();
    let part = TruePart { workpiece: &prog.workpiece, as_machined: &am, pose: prog.placement };
    let pv = Vec3::new(0.0, 0.0, -50.0);
    let probe = TrueProbe::ideal(pv, 1.5);
    let start = Point3::new(350.0, 480.0, 300.0);
    let mut sim = SimulatedCmm::new(part, MachineModel::default_bridge(), MachineProfile::default().ideal(), probe, 1, start).unwrap();
    let Feature::Section { curves, settings, .. } = &prog.features[0] else { panic!() };
    let c = &curves[0];
    let pts: Vec<(Point3, Vec3)> = c.points.iter().map(|p| (prog.placement.to_machine(p.point), prog.placement.dir_to_machine(p.normal))).collect();
    let path = BallPath::from_section(&pts, c.closed, 1.5 - settings.deflection_mm, PathOptions::default()).unwrap();
    let plan = SpeedPlan::new(&path, &SpeedOptions { speed_mm_s: settings.speed_mm_s, ..Default::default() }).unwrap();
    let hp = HostProbe { probe_vector: pv, tip_radius_mm: 1.5 };
    let t0 = std::time::Instant::now();
    let at = design_value_scan(&mut sim, hp, &path, &plan, ScanKind::Active, ScanTargets { deflection_mm: 0.3, pitch_mm: 0.5, trajectory_tolerance_mm: 1.5 }, &ModeOptions::default());
    let wall = t0.elapsed().as_secs_f64();
    println!("outcome {:?} points {} time {} maxdl {} wall {wall} plan {}", at.outcome, at.points.len(), at.machine_time_s, at.max_trajectory_error_mm, plan.duration());
    let mut worst: f64 = 0.0;
    for m in &at.points {
        let y = prog.placement.to_part(m.point);
        let d = am.closest_point(&prog.workpiece, y).unwrap().distance;
        worst = worst.max(d);
    }
    println!("worst {worst}");
}
