//! The one reader of the simulated truth outside the world: after the
//! measuring, each reported point's `true_deviation_mm`, the deviation of
//! the true surface point nearest to the measured point, so that
//! `deviation_mm - true_deviation_mm` is the measurement error itself.
//!
//! A reported point is in the part frame of the measuring side's final
//! placement (the alignment's result); the true part stands at the
//! world's placement. The measured point is taken to the true part's frame
//! (through machine coordinates) to find the true surface point nearest to
//! it, and that point is taken back to the reported frame, where its
//! deviation from the design is measured as the point's own was. An
//! alignment thus changes nothing of the truth, and `deviation_mm -
//! true_deviation_mm` stays the measurement error.
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
    let same_frame = frames.reported == frames.world;
    let p = if same_frame {
        reported
    } else {
        frames.world.to_part(frames.reported.to_machine(reported))
    };
    // The other faces are searched as far as the true part's seeds need.
    let reach = truth.seed_reach();
    let Ok(foot) = wp.closest_point_reaching(p, 0..wp.faces.len(), hint, Some(&reach)) else {
        return f64::NAN;
    };
    let known = Some((p, &foot));
    if same_frame {
        return (truth.true_deviation_tracked(wp, p, known, hint)).unwrap_or(f64::NAN);
    }
    let Ok(true_foot) = truth.closest_point_tracked(wp, p, known, hint) else {
        return f64::NAN;
    };
    let q = frames
        .reported
        .to_part(frames.world.to_machine(true_foot.point));
    let mut nominal_hint = None;
    (wp.closest_point_tracked(q, 0..wp.faces.len(), &mut nominal_hint))
        .map_or(f64::NAN, |f| f.projection.signed_distance)
}
