//! The one reader of the simulated truth outside the world: after the
//! measuring, each reported point's `true_deviation_mm`, the deviation of
//! the true surface point nearest to the measured point, so that
//! `deviation_mm - true_deviation_mm` is the measurement error itself.
//!
//! A reported point is in the part frame of the measuring side's final
//! placement (the alignment's result); the true part stands at the
//! world's placement. The point is taken to machine coordinates with the
//! first and back to the true part's frame with the second, so an
//! alignment changes nothing of the truth.
use rayon::prelude::*;

use super::model::{FeatureReport, PointReport};
use super::nominal::CHUNK_POINTS;
use crate::math::Point3;
use crate::program::Pose;
use crate::workpiece::{FootHint, Workpiece};
use crate::world::as_machined::AsMachined;

/// Where the measured part and the true part stand on the machine.
#[derive(Debug, Clone, Copy)]
pub struct Frames {
    /// Part to machine as the measuring side reported its points.
    pub reported: Pose,
    /// Part to machine of the true part in the world.
    pub world: Pose,
}

/// Fills in `true_deviation_mm` of every point of `features` (NaN where
/// the true foot cannot be found).
pub fn fill_true_deviations(
    features: &mut [FeatureReport],
    workpiece: &Workpiece,
    truth: &AsMachined,
    frames: Frames,
) {
    for f in features.iter_mut() {
        f.points.par_chunks_mut(CHUNK_POINTS).for_each(|chunk| {
            let mut hint = None;
            for p in chunk.iter_mut() {
                p.true_deviation_mm = true_deviation(p, workpiece, truth, frames, &mut hint);
            }
        });
    }
}

fn true_deviation(
    point: &PointReport,
    wp: &Workpiece,
    truth: &AsMachined,
    frames: Frames,
    hint: &mut Option<FootHint>,
) -> f64 {
    let reported = Point3::from(point.measured);
    let p = frames.world.to_part(frames.reported.to_machine(reported));
    // The other faces are searched as far as the true part's seeds need.
    let reach = truth.seed_reach();
    let Ok(foot) = wp.closest_point_reaching(p, 0..wp.faces.len(), hint, Some(&reach)) else {
        return f64::NAN;
    };
    let known = Some((p, &foot));
    truth
        .true_deviation_tracked(wp, p, known, hint)
        .unwrap_or(f64::NAN)
}
