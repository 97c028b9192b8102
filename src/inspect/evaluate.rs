//! Measured points to reported deviations (nominal and true).
use crate::host::modes::Measured;
use crate::program::Program;
use crate::report::PointReport;
use crate::workpiece::as_machined::AsMachined;

/// Deviation of every measured point (machine frame) from the nominal
/// surfaces `faces`, with the true deviation from the simulated part.
pub fn point_reports(
    program: &Program,
    truth: &AsMachined,
    faces: &[usize],
    points: &[Measured],
) -> Vec<PointReport> {
    points
        .iter()
        .filter_map(|m| point_report(program, truth, faces, m))
        .collect()
}

fn point_report(
    program: &Program,
    truth: &AsMachined,
    faces: &[usize],
    m: &Measured,
) -> Option<PointReport> {
    let p = program.placement.to_part(m.point);
    let nominal = program
        .workpiece
        .closest_point_among(p, faces.iter().copied())
        .ok()?
        .projection;
    // The truth is read here only, for the report's true_deviation_mm.
    let true_dev = truth.true_deviation(&program.workpiece, p).ok()?;
    Some(PointReport {
        measured: p.into(),
        nominal: nominal.point.into(),
        normal: nominal.normal.into(),
        deviation_mm: nominal.signed_distance,
        true_deviation_mm: true_dev,
    })
}
