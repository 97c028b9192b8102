//! Measured points to reported deviations (nominal and true).
//!
//! Consecutive measured points lie close together, so each point's
//! closest-point searches start where the previous point's foot lies
//! ([`crate::workpiece::Workpiece::closest_point_near`]); the answers are
//! the global closest points all the same.
use crate::host::modes::Measured;
use crate::program::Program;
use crate::report::PointReport;
use crate::workpiece::as_machined::AsMachined;
use crate::workpiece::FootHint;

/// Deviation of every measured point (machine frame) from the nominal
/// surfaces `faces`, with the true deviation from the simulated part.
pub fn point_reports(
    program: &Program,
    truth: &AsMachined,
    faces: &[usize],
    points: &[Measured],
) -> Vec<PointReport> {
    let count = program.workpiece.faces.len();
    let mut listed = faces.to_vec();
    listed.sort_unstable();
    listed.dedup();
    let mut hints = Hints {
        all: None,
        faces: None,
        faces_are_all: listed.iter().copied().eq(0..count),
    };
    points
        .iter()
        .filter_map(|m| point_report(program, truth, faces, m, &mut hints))
        .collect()
}

/// Where the previous point's nominal feet lie.
struct Hints {
    /// Foot over all faces (that of the true point, once it is found).
    all: Option<FootHint>,
    /// Foot over the feature's faces.
    faces: Option<FootHint>,
    /// Whether the feature's faces are all faces.
    faces_are_all: bool,
}

fn point_report(
    program: &Program,
    truth: &AsMachined,
    faces: &[usize],
    m: &Measured,
    hints: &mut Hints,
) -> Option<PointReport> {
    let wp = &program.workpiece;
    let p = program.placement.to_part(m.point);
    let all = 0..wp.faces.len();
    // The other faces are searched as far as the true part's seeds need.
    let reach = truth.seed_reach();
    let foot = (wp.closest_point_reaching(p, all, &mut hints.all, Some(&reach))).ok()?;
    // The closest point over all faces is the closest over the feature's
    // faces too when it lies on one of them.
    let nominal = if hints.faces_are_all || faces.contains(&foot.face) {
        foot
    } else {
        let listed = faces.iter().copied();
        wp.closest_point_tracked(p, listed, &mut hints.faces).ok()?
    }
    .projection;
    // The truth is read here only, for the report's true_deviation_mm.
    let known = Some((p, &foot));
    let true_dev = (truth.true_deviation_tracked(wp, p, known, &mut hints.all)).ok()?;
    Some(PointReport {
        measured: p.into(),
        nominal: nominal.point.into(),
        normal: nominal.normal.into(),
        deviation_mm: nominal.signed_distance,
        true_deviation_mm: true_dev,
    })
}
