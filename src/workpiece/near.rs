//! Closest-point queries near earlier ones (consecutive measured points,
//! the true part's seeds): the search starts in the leaf of an earlier
//! foot, so that it begins with a tight bound and leaves out almost
//! everything else; the answers are the global closest points all the same.
use super::{FaceProjection, Workpiece};
use crate::geometry::projection::Foot;
use crate::geometry::ProjectionError;
use crate::math::{Point3, Vec2};

impl Workpiece {
    /// [`Self::closest_point_among`] for a query near an earlier one: the
    /// leaf of the earlier foot (`hint`) is searched first, so that the
    /// search starts with a tight bound and leaves out almost everything
    /// else. The answer is the global closest point all the same (up to
    /// exact ties). Also returns the hint for the next query.
    pub fn closest_point_near(
        &self,
        p: Point3,
        faces: &[usize],
        hint: Option<FootHint>,
    ) -> Result<(FaceProjection, Option<FootHint>), ProjectionError> {
        self.closest_point_within(p, faces.iter().copied(), f64::INFINITY, hint)?
            .ok_or(ProjectionError::NotFinite {
                x: p.x,
                y: p.y,
                z: p.z,
            })
    }

    /// The closest point over `faces` among the points closer than
    /// `sqrt(bound2)` (`None` when there is none), searching the leaf of
    /// `hint` first, with the hint of its foot.
    pub(super) fn closest_point_within(
        &self,
        p: Point3,
        faces: impl IntoIterator<Item = usize>,
        bound2: f64,
        hint: Option<FootHint>,
    ) -> Result<Option<(FaceProjection, Option<FootHint>)>, ProjectionError> {
        let mut order: Vec<(f64, usize)> = faces
            .into_iter()
            .filter_map(|i| self.faces.get(i).map(|f| (f.index.lower_bound(p), i)))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let hint = hint.filter(|h| order.iter().any(|o| o.1 == h.face));
        let mut best: Option<(usize, Option<usize>, Foot)> = None;
        let mut best_d2 = bound2;
        if let Some(h) = hint {
            if let Some(foot) = self.faces[h.face].search_leaf(p, h.leaf, best_d2)? {
                best_d2 = foot.dist2;
                best = Some((h.face, Some(h.leaf), foot));
            }
        }
        // A foot from the hint's leaf is (nearly always) the answer: the
        // rest only has to confirm it, depth first. Else best first.
        let tight = best.is_some();
        for (lb, i) in order {
            if lb * lb > best_d2 {
                break;
            }
            let skip = hint.filter(|h| h.face == i).map(|h| h.leaf);
            if let Some((leaf, foot)) = self.faces[i].search(p, best_d2, skip, tight)? {
                best_d2 = foot.dist2;
                best = Some((i, leaf, foot));
            }
        }
        Ok(best.map(|(face, leaf, foot)| {
            let projection = foot.into_projection(&self.faces[face].surface, p);
            let next = leaf.map(|leaf| FootHint { face, leaf });
            (FaceProjection { face, projection }, next)
        }))
    }

    /// The faces whose nominal distance from `y` is at most `reach(face,
    /// smallest distance)`, each with its foot parameters, in face order,
    /// and where the global foot lies. The faces are searched nearest first
    /// (by their trees' root boxes), the global foot `near` (when known, as
    /// it is when its query is `y`, else started from its hint) first of
    /// all, and each only within the reach of the smallest distance so far;
    /// `reach` must grow with the distance.
    pub fn feet_within_reach(
        &self,
        y: Point3,
        near: Option<&KnownFoot>,
        reach: impl Fn(usize, f64) -> f64,
    ) -> Result<FeetWithinReach, ProjectionError> {
        /// Relative slack on the squared search radius, so that rounding
        /// cannot drop a face right at the reach (the exact reach test
        /// follows).
        const BOUND_SLACK: f64 = 1e-9;
        let (nearest, hint) = match near {
            None => (None, None),
            Some(k) if k.query == y => (Some(k.foot), k.hint),
            Some(k) => {
                let all: Vec<usize> = (0..self.faces.len()).collect();
                let (foot, hint) = self.closest_point_near(y, &all, k.hint)?;
                (Some(foot), hint)
            }
        };
        let mut order: Vec<(f64, usize)> = (self.faces.iter().enumerate())
            .filter(|(i, _)| nearest.is_none_or(|n| n.face != *i))
            .map(|(i, f)| (f.index.lower_bound(y), i))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut found: Vec<(usize, f64, Vec2)> = nearest
            .map(|n| (n.face, n.projection.distance, n.projection.uv))
            .into_iter()
            .collect();
        let mut best = found.first().map_or(f64::INFINITY, |s| s.1);
        for (lb, i) in order {
            let within = reach(i, best);
            let (Some(f), false) = (self.faces.get(i), lb > within) else {
                continue;
            };
            let bound2 = within * within * (1.0 + BOUND_SLACK);
            if let Some(foot) = f.project_within(y, bound2)? {
                let d = foot.dist2.sqrt();
                best = best.min(d);
                found.push((i, d, foot.uv));
            }
        }
        found.sort_by_key(|s| s.0);
        let feet = found
            .into_iter()
            .filter(|s| s.1 <= reach(s.0, best))
            .map(|s| (s.0, s.2))
            .collect();
        Ok(FeetWithinReach { feet, hint })
    }
}

/// The result of [`Workpiece::feet_within_reach`].
#[derive(Debug, Clone, PartialEq)]
pub struct FeetWithinReach {
    /// Faces within reach with their foot parameters, in face order.
    pub feet: Vec<(usize, Vec2)>,
    /// Where the global foot lies (when it came from a hinted search).
    pub hint: Option<FootHint>,
}

/// A nominal foot already found: the global closest point over all faces
/// of `query`, with the hint to start nearby queries from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnownFoot {
    /// The query point.
    pub query: Point3,
    /// Its closest point over all faces.
    pub foot: FaceProjection,
    /// Where that lies in the search trees.
    pub hint: Option<FootHint>,
}

/// Where the foot of a closest-point query lies (face and leaf of its
/// search tree), to start a query near it from
/// ([`Workpiece::closest_point_near`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FootHint {
    face: usize,
    leaf: usize,
}
