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
use super::nominal::{feature_foot, FeatureFaces, Hints, CHUNK_POINTS};
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
/// the true foot cannot be found); `faces[k]` are the faces feature `k`'s
/// deviations are measured against.
pub fn fill_true_deviations(
    features: &mut [FeatureReport],
    faces: &[&[usize]],
    workpiece: &Workpiece,
    truth: &AsMachined,
    frames: Frames,
) {
    for (f, listed) in features.iter_mut().zip(faces) {
        let listed = FeatureFaces::new(workpiece, listed);
        f.points.par_chunks_mut(CHUNK_POINTS).for_each(|chunk| {
            let mut hints = TruthHints::default();
            for p in chunk.iter_mut() {
                let known = Known {
                    wp: workpiece,
                    truth,
                    faces: listed,
                };
                p.true_deviation_mm = true_deviation(p, &known, frames, &mut hints);
            }
        });
    }
}

/// What a point's true deviation is found from.
struct Known<'a> {
    wp: &'a Workpiece,
    truth: &'a AsMachined,
    faces: FeatureFaces<'a>,
}

/// Where the previous point's searches ended.
#[derive(Default)]
struct TruthHints {
    /// The nominal foot of the measured point (then of the true point's
    /// nominal parameters), over all faces.
    search: Option<FootHint>,
    /// The nominal feet of the true point.
    nominal: Hints,
}

fn true_deviation(
    point: &PointReport,
    known: &Known,
    frames: Frames,
    hints: &mut TruthHints,
) -> f64 {
    let (wp, truth) = (known.wp, known.truth);
    let reported = Point3::from(point.measured);
    let same_frame = frames.reported == frames.world;
    let p = if same_frame {
        reported
    } else {
        frames.world.to_part(frames.reported.to_machine(reported))
    };
    // The other faces are searched as far as the true part's seeds need.
    let reach = truth.seed_reach();
    let all = 0..wp.faces.len();
    let Ok(foot) = wp.closest_point_reaching(p, all, &mut hints.search, Some(&reach)) else {
        return f64::NAN;
    };
    let Ok(true_foot) = truth.closest_point_tracked(wp, p, Some((p, &foot)), &mut hints.search)
    else {
        return f64::NAN;
    };
    let q = if same_frame {
        true_foot.point
    } else {
        frames
            .reported
            .to_part(frames.world.to_machine(true_foot.point))
    };
    // The true point's deviation is measured as the point's own was.
    feature_foot(wp, q, known.faces, &mut hints.nominal)
        .map_or(f64::NAN, |f| f.projection.signed_distance)
}
