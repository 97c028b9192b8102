//! Measured points to their deviations from the design: the nominal foot
//! over the feature's faces and the signed distance (the cmm-report/1 format). Needs
//! the design data only, so it works the same for a simulated and a real
//! machine; `true_deviation_mm` is filled in afterwards by [`super::truth`]
//! in a simulated run (NaN until then).
//!
//! Consecutive measured points lie close together, so each point's
//! closest-point searches start where the previous point's foot lies
//! ([`crate::workpiece::Workpiece::closest_point_tracked`]); the answers
//! are the global closest points all the same. Points are evaluated in
//! fixed chunks ([`CHUNK_POINTS`]) in parallel; each chunk's first search
//! starts cold, so the results do not depend on the number of threads.
use rayon::prelude::*;

use super::model::PointReport;
use crate::host::modes::Measured;
use crate::program::Pose;
use crate::workpiece::{FootHint, Workpiece};

/// Measured points per evaluation chunk: large enough that the cold start
/// of each chunk's first search costs little, small enough to share the
/// points of one scan between threads.
pub const CHUNK_POINTS: usize = 32;

/// Deviation of every measured point (machine frame, `pose` maps the part
/// to the machine) from the nominal surfaces `faces`. A point whose foot
/// cannot be found is left out.
pub fn point_reports(
    workpiece: &Workpiece,
    pose: &Pose,
    faces: &[usize],
    points: &[Measured],
) -> Vec<PointReport> {
    let all = faces_are_all(workpiece, faces);
    let chunks: Vec<Vec<PointReport>> = points
        .par_chunks(CHUNK_POINTS)
        .map(|chunk| {
            let mut hints = Hints::default();
            (chunk.iter())
                .filter_map(|m| point_report(workpiece, pose, faces, all, m, &mut hints))
                .collect()
        })
        .collect();
    chunks.concat()
}

/// Whether `faces` lists every face of the workpiece.
fn faces_are_all(workpiece: &Workpiece, faces: &[usize]) -> bool {
    let mut listed = faces.to_vec();
    listed.sort_unstable();
    listed.dedup();
    listed.iter().copied().eq(0..workpiece.faces.len())
}

/// Where the previous point's nominal feet lie.
#[derive(Default)]
struct Hints {
    /// Foot over all faces.
    all: Option<FootHint>,
    /// Foot over the feature's faces.
    faces: Option<FootHint>,
}

fn point_report(
    wp: &Workpiece,
    pose: &Pose,
    faces: &[usize],
    faces_are_all: bool,
    m: &Measured,
    hints: &mut Hints,
) -> Option<PointReport> {
    let p = pose.to_part(m.point);
    let foot = wp
        .closest_point_tracked(p, 0..wp.faces.len(), &mut hints.all)
        .ok()?;
    // The closest point over all faces is the closest over the feature's
    // faces too when it lies on one of them.
    let nominal = if faces_are_all || faces.contains(&foot.face) {
        foot
    } else {
        let listed = faces.iter().copied();
        wp.closest_point_tracked(p, listed, &mut hints.faces).ok()?
    }
    .projection;
    Some(PointReport {
        measured: p.into(),
        nominal: nominal.point.into(),
        normal: nominal.normal.into(),
        deviation_mm: nominal.signed_distance,
        true_deviation_mm: f64::NAN,
    })
}
