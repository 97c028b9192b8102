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
use crate::world::contact::{ContactOptions, ContactSearch, Cursor};

/// A measured point whose true surface lies within this (mm) is answered
/// by the world's contact search (the leaves and tree the simulated
/// machine measured on, warm from the previous point); a point farther
/// off, by a search over every face. A measured point lies within the
/// measurement error of the true surface, hundredths of a millimetre.
pub const TRUTH_REACH_MM: f64 = 1.0;

/// Where the measured part and the true part stand on the machine.
#[derive(Debug, Clone, Copy)]
pub struct Frames {
    /// Part to machine as the measuring side reported its points.
    pub reported: Pose,
    /// Part to machine of the true part in the world.
    pub world: Pose,
}

/// The true part the true deviations are taken on.
#[derive(Debug, Clone, Copy)]
pub struct Truth<'a> {
    /// The design the part was made from.
    pub workpiece: &'a Workpiece,
    /// The part as machined.
    pub part: &'a AsMachined,
    /// A contact search on that part (the simulated machine's).
    pub search: &'a ContactSearch,
}

/// Fills in `true_deviation_mm` of every point of `features` (NaN where
/// the true foot cannot be found); `faces[k]` are the faces feature `k`'s
/// deviations are measured against. Builds a contact search on the true
/// part; [`fill_true_deviations_on`] uses one already built.
pub fn fill_true_deviations(
    features: &mut [FeatureReport],
    faces: &[&[usize]],
    workpiece: &Workpiece,
    truth: &AsMachined,
    frames: Frames,
) {
    let search = ContactSearch::new(workpiece, truth, &ContactOptions::default());
    let truth = Truth {
        workpiece,
        part: truth,
        search: &search,
    };
    fill_true_deviations_on(features, faces, truth, frames);
}

/// [`fill_true_deviations`] on the true part `truth`, with its search.
pub fn fill_true_deviations_on(
    features: &mut [FeatureReport],
    faces: &[&[usize]],
    truth: Truth<'_>,
    frames: Frames,
) {
    for (f, listed) in features.iter_mut().zip(faces) {
        let listed = FeatureFaces::new(truth.workpiece, listed);
        f.points.par_chunks_mut(CHUNK_POINTS).for_each(|chunk| {
            let mut hints = TruthHints {
                cursor: truth.search.cursor(),
                search: None,
                nominal: Hints::default(),
            };
            for p in chunk.iter_mut() {
                let known = Known {
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
    truth: Truth<'a>,
    faces: FeatureFaces<'a>,
}

/// Where the previous point's searches ended.
struct TruthHints {
    /// The contact search's stream of queries.
    cursor: Cursor,
    /// The nominal foot of the measured point (then of the true point's
    /// nominal parameters), over all faces, for a point beyond the
    /// contact search's reach.
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
    let reported = Point3::from(point.measured);
    let same_frame = frames.reported == frames.world;
    let p = if same_frame {
        reported
    } else {
        frames.world.to_part(frames.reported.to_machine(reported))
    };
    let Some(true_point) = nearest_true_point(p, known.truth, hints) else {
        return f64::NAN;
    };
    let q = if same_frame {
        true_point
    } else {
        frames.reported.to_part(frames.world.to_machine(true_point))
    };
    // The true point's deviation is measured as the point's own was.
    let wp = known.truth.workpiece;
    feature_foot(wp, q, known.faces, &mut hints.nominal)
        .map_or(f64::NAN, |f| f.projection.signed_distance)
}

/// The true surface point nearest to `p` (the true part's frame): the
/// contact search's foot within [`TRUTH_REACH_MM`], else the nominal
/// foot's faces searched on the true part.
fn nearest_true_point(p: Point3, truth: Truth<'_>, hints: &mut TruthHints) -> Option<Point3> {
    let (wp, am) = (truth.workpiece, truth.part);
    let near = (truth.search).query_on(&mut hints.cursor, (wp, am), p, TRUTH_REACH_MM, &wp.options);
    if let Ok(Some(c)) = near {
        return Some(c.point);
    }
    // The other faces are searched as far as the true part's seeds need.
    let reach = am.seed_reach();
    let all = 0..wp.faces.len();
    let foot = wp
        .closest_point_reaching(p, all, &mut hints.search, Some(&reach))
        .ok()?;
    let true_foot = am
        .closest_point_tracked(wp, p, Some((p, &foot)), &mut hints.search)
        .ok()?;
    Some(true_foot.point)
}
