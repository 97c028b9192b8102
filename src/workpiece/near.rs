//! Closest-point queries near earlier ones (consecutive measured points,
//! the true part's seeds): Newton starts from an earlier foot (with its
//! derivatives) on the whole face, and the search trees then only have to
//! confirm that no leaf of any face comes closer, which leaves out almost
//! everything; the answers are the global closest points all the same.
//! The hint of the earlier foot is updated in place to the new one.
use super::{FaceProjection, Workpiece};
use crate::geometry::projection::{Foot, NoMemo};
use crate::geometry::ProjectionError;
use crate::math::Point3;
use far::FarLeaves;
pub use hint::{FootHint, KnownFoot};
pub use reach::{FaceList, FeetWithinReach, Reach};

/// Room for the faces near a query point (more only costs an allocation).
const NEAR_FACES: usize = 64;

/// Relative slack on the squared search radius of a face, so that
/// rounding cannot drop a point right at it (the exact tests follow).
const BOUND_SLACK: f64 = 1e-9;

mod far;
mod hint;
mod reach;
#[cfg(test)]
mod tests;
#[cfg(test)]
pub(crate) mod walk;

impl Workpiece {
    /// [`Self::closest_point_among`] for a query near an earlier one:
    /// Newton starts from the earlier foot (`hint`) on its face, and the
    /// search trees of all `faces` then confirm the foot or find a closer
    /// one. The answer is the global closest point all the same (up to
    /// exact ties and the Newton tolerance). Also returns the hint for the
    /// next query.
    pub fn closest_point_near(
        &self,
        p: Point3,
        faces: &[usize],
        hint: Option<FootHint>,
    ) -> Result<(FaceProjection, Option<FootHint>), ProjectionError> {
        let mut hint = hint;
        let found = self.closest_point_tracked(p, faces.iter().copied(), &mut hint)?;
        Ok((found, hint))
    }

    /// [`Self::closest_point_near`] over the faces `faces` yields, with
    /// the hint moved in place to the new foot. A hint on a face outside
    /// them, or on a trimmed face, only names the leaf to search first.
    pub fn closest_point_tracked(
        &self,
        p: Point3,
        faces: impl FaceList,
        hint: &mut Option<FootHint>,
    ) -> Result<FaceProjection, ProjectionError> {
        self.closest_point_reaching(p, faces, hint, None)
    }

    /// Whether a face of `faces` comes closer to `p` than `d` (mm): faces
    /// whose box keeps that far are not searched.
    pub fn comes_within(
        &self,
        p: Point3,
        faces: impl Iterator<Item = usize>,
        d: f64,
    ) -> Result<bool, ProjectionError> {
        let near = faces.filter(|&i| self.face_box_distance(i, p) < d);
        Ok(self.closest_point_within(p, near, d * d, None)?.is_some())
    }

    /// [`Self::closest_point_tracked`] that searches each face other than
    /// the foot's within `reach(face, distance)` too (at least the
    /// distance), when given, so that queries near `p` within that reach
    /// (the seeds of the true part's search, see
    /// [`Self::for_feet_within_reach`]) find the face searched already.
    pub fn closest_point_reaching(
        &self,
        p: Point3,
        faces: impl FaceList,
        hint: &mut Option<FootHint>,
        reach: Option<&dyn Reach>,
    ) -> Result<FaceProjection, ProjectionError> {
        let warm = hint.as_mut().filter(|h| faces.holds(h.face));
        if let Some(h) = warm {
            if let Some(found) = self.closest_point_warm(p, faces.clone(), h, reach)? {
                return Ok(found);
            }
        }
        let far = hint.map(|h| h.far).unwrap_or_default();
        let (found, next) = (self.closest_point_within(p, faces, f64::INFINITY, *hint)?).ok_or(
            ProjectionError::NotFinite {
                x: p.x,
                y: p.y,
                z: p.z,
            },
        )?;
        *hint = next.map(|h| FootHint { far, ..h });
        Ok(found)
    }

    /// The closest point over `faces` (which hold `h.face`): Newton from
    /// the hint's foot on its face, then the search trees confirm it on
    /// the face's whole surface, depth first with its distance as the
    /// bound (the hint's face first, the others within `reach` when
    /// given); `h` becomes the hint of the answer. `None` (with `h`
    /// spoilt) when that Newton fails or the confirmed foot lies outside
    /// the face's trim.
    fn closest_point_warm(
        &self,
        p: Point3,
        faces: impl FaceList,
        h: &mut FootHint,
        reach: Option<&dyn Reach>,
    ) -> Result<Option<FaceProjection>, ProjectionError> {
        let Some(face) = self.faces.get(h.face) else {
            return Ok(None);
        };
        if face.warm_foot(p, h, &self.options).is_err() {
            return Ok(None);
        }
        let memo = &mut h.far.of_face(h.face);
        h.leaf = face.index().confirm(&face.surface, p, &mut h.foot, memo)?;
        // The untrimmed surface's closest point, inside the trim, is the
        // face's; outside it the face's lies elsewhere (on its boundary).
        if face.trim.as_ref().is_some_and(|t| !t.contains(h.foot.uv)) {
            return Ok(None);
        }
        // Only faces whose box comes within the widest reach can hold a
        // closer point or need a search (the loop below skips the others
        // by the same box test).
        let own = h.face;
        let first = h.foot.dist2.sqrt();
        let cap = reach.map_or(first, |r| r.cap(first).max(first));
        let mut near = Vec::with_capacity(NEAR_FACES);
        self.faces_within(p, cap, &mut near);
        faces.select(&mut near);
        for i in near.into_iter().filter(|&i| i != own) {
            let best = h.foot.dist2.sqrt();
            let within = reach.map_or(best, |r| r.of(i, best).max(best));
            if let Some((leaf, found)) = self.face_within(p, i, within, &mut h.far)? {
                if found.dist2 < h.foot.dist2 {
                    (h.face, h.leaf, h.foot) = (i, leaf, found);
                }
            }
        }
        Ok(self.faces.get(h.face).map(|f| FaceProjection {
            face: h.face,
            projection: h.foot.projection(&f.surface, p),
        }))
    }

    /// The closest point of face `i` to `p` when it comes within `within`
    /// (with its leaf), unless `far` knows the face to be that far; notes
    /// in `far` how far the face is.
    pub(super) fn face_within(
        &self,
        p: Point3,
        i: usize,
        within: f64,
        far: &mut FarLeaves,
    ) -> Result<Option<(Option<usize>, Foot)>, ProjectionError> {
        let Some(f) = self.faces.get(i) else {
            return Ok(None);
        };
        // The root box first: it clears most faces without the memo.
        if self.face_box_distance(i, p) > within || far.face_floor(i, p) > within {
            return Ok(None);
        }
        // The leaves' boxes bound the face's distance without a Newton
        // iteration, often far beyond `within` (the other side of a thin
        // part), which spares the searches of the nearby queries too.
        let boxes = f.index().box_distance(p);
        if boxes > within {
            far.note_face(i, p, boxes);
            return Ok(None);
        }
        let bound2 = within * within * (1.0 + BOUND_SLACK);
        let found = f.search((p, bound2), None, true, &mut far.of_face(i))?;
        // Nothing found: every point is farther than `within` (by about
        // half the slack; a quarter is kept).
        let least = found.map_or(within * (1.0 + 0.25 * BOUND_SLACK), |(_, foot)| {
            foot.dist2.sqrt()
        });
        far.note_face(i, p, least);
        Ok(found)
    }

    /// The leaf whose boxes come nearest to `p` over the faces `order`
    /// (sorted by their lower bounds), as a hint without a foot.
    fn box_nearest_leaf(&self, p: Point3, order: &[(f64, usize)]) -> Option<FootHint> {
        let mut best: Option<(f64, usize, usize)> = None;
        for &(lb, i) in order {
            if best.is_some_and(|b| lb >= b.0) {
                break;
            }
            let Some(f) = self.faces.get(i) else {
                continue;
            };
            if let (d, Some(leaf)) = f.index().box_nearest_leaf(p) {
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, i, leaf));
                }
            }
        }
        let (_, face, leaf) = best?;
        let mut hint = FootHint::at(face, crate::math::Vec2::zeros());
        hint.leaf = Some(leaf);
        Some(hint)
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
            .filter_map(|i| self.faces.get(i).map(|f| (f.lower_bound(p), i)))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let hint = hint.filter(|h| order.iter().any(|o| o.1 == h.face));
        // Without a hint the leaf whose boxes come nearest is searched
        // first: its foot bounds the rest tightly (mostly).
        let hint = hint.or_else(|| self.box_nearest_leaf(p, &order));
        let mut best: Option<(usize, Option<usize>, Foot)> = None;
        let mut best_d2 = bound2;
        if let Some((face, leaf)) = hint.and_then(|h| Some((h.face, h.leaf?))) {
            if let Some(f) = self.faces.get(face) {
                if let Some(foot) = f.search_leaf(p, leaf, best_d2)? {
                    best_d2 = foot.dist2;
                    best = Some((face, Some(leaf), foot));
                }
            }
        }
        // A foot from the hint's leaf is (nearly always) the answer: the
        // rest only has to confirm it, depth first. Else best first.
        let tight = best.is_some();
        for (lb, i) in order {
            if lb * lb > best_d2 {
                break;
            }
            let Some(f) = self.faces.get(i) else {
                continue;
            };
            let skip = hint.filter(|h| h.face == i).and_then(|h| h.leaf);
            if let Some((leaf, foot)) = f.search((p, best_d2), skip, tight, &mut NoMemo)? {
                best_d2 = foot.dist2;
                best = Some((i, leaf, foot));
            }
        }
        Ok(best.and_then(|(face, leaf, foot)| {
            let projection = foot.projection(&self.faces.get(face)?.surface, p);
            let hint = FootHint::found(face, leaf, foot);
            Some((FaceProjection { face, projection }, Some(hint)))
        }))
    }
}
