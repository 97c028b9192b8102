//! The nominal feet within reach of a point on every face: the seeds of
//! the true part's closest-point search.
use super::far::FarLeaves;
use super::hint::{FootHint, KnownFoot};
use crate::geometry::ProjectionError;
use crate::math::{Point3, Vec2};
use crate::workpiece::{FaceProjection, Workpiece};

/// How far from a point the faces other than the one of the least
/// distance found so far are searched.
pub trait Reach {
    /// Face `face` is searched within this (mm) when the least distance so
    /// far is `best`; it must not fall when `best` grows.
    fn of(&self, face: usize, best: f64) -> f64;
    /// At least [`Self::of`] for every face, mm.
    fn cap(&self, best: f64) -> f64;
}

/// The faces a query looks at: an iterator over them (in the order the
/// query takes them) that also tells whether it holds a face.
pub trait FaceList: Iterator<Item = usize> + Clone {
    /// Whether `face` is one of them.
    fn holds(&self, face: usize) -> bool;

    /// Keeps in `near` (ascending face indices) the faces of the list, in
    /// the list's order.
    fn select(&self, near: &mut Vec<usize>);
}

/// A range of face indices.
impl FaceList for std::ops::Range<usize> {
    fn holds(&self, face: usize) -> bool {
        self.contains(&face)
    }

    fn select(&self, near: &mut Vec<usize>) {
        near.retain(|i| self.contains(i));
    }
}

/// A list of face indices (short: a feature's faces).
impl FaceList for std::iter::Copied<std::slice::Iter<'_, usize>> {
    fn holds(&self, face: usize) -> bool {
        self.clone().any(|i| i == face)
    }

    fn select(&self, near: &mut Vec<usize>) {
        let listed = self.clone().filter(|i| near.binary_search(i).is_ok());
        *near = listed.collect();
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

impl Workpiece {
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
        reach: &impl Reach,
    ) -> Result<FeetWithinReach, ProjectionError> {
        let mut hint = near.and_then(|k| k.hint);
        let known = near.map(|k| (k.query, &k.foot));
        let mut feet = Vec::new();
        self.for_feet_within_reach(y, known, &mut hint, reach, |face, uv| {
            feet.push((face, uv));
            Ok(())
        })?;
        Ok(FeetWithinReach { feet, hint })
    }

    /// [`Self::feet_within_reach`] handing each foot to `seed` in face
    /// order, with `known`, the global foot of a query point found with
    /// `hint`, and `hint` moved in place to the global foot of `y`.
    pub fn for_feet_within_reach(
        &self,
        y: Point3,
        known: Option<(Point3, &FaceProjection)>,
        hint: &mut Option<FootHint>,
        reach: &impl Reach,
        mut seed: impl FnMut(usize, Vec2) -> Result<(), ProjectionError>,
    ) -> Result<(), ProjectionError> {
        let nearest = match known {
            None => None,
            Some((q, foot)) if q == y => Some(*foot),
            Some(_) => Some(self.closest_point_tracked(y, 0..self.faces.len(), hint)?),
        };
        let Some(n) = nearest else {
            return self.cold_feet_within_reach(y, reach, seed);
        };
        // The global foot's distance is the least: each face is searched
        // within its reach of it, in face order (learning in the hint's
        // memo of far leaves in place, when there is a hint); a face whose
        // box keeps farther than every reach is not looked at.
        let mut own = FarLeaves::default();
        let far = hint.as_mut().map_or(&mut own, |h| &mut h.far);
        let best = n.projection.distance;
        let mut near = Vec::with_capacity(super::NEAR_FACES);
        self.faces_within(y, reach.cap(best), &mut near);
        if let Err(at) = near.binary_search(&n.face) {
            near.insert(at, n.face);
        }
        for i in near {
            if i == n.face {
                seed(i, n.projection.uv)?;
            } else if let Some(uv) = self.foot_within(y, i, reach.of(i, best), far)? {
                seed(i, uv)?;
            }
        }
        Ok(())
    }

    /// The foot parameters of face `i` when it comes within `within` of
    /// `y`.
    fn foot_within(
        &self,
        y: Point3,
        i: usize,
        within: f64,
        far: &mut FarLeaves,
    ) -> Result<Option<Vec2>, ProjectionError> {
        Ok(self
            .face_within(y, i, within, far)?
            .filter(|(_, foot)| foot.dist2.sqrt() <= within)
            .map(|(_, foot)| foot.uv))
    }

    /// [`Self::for_feet_within_reach`] with no foot known: the faces
    /// nearest first, each within the reach of the least distance so far.
    fn cold_feet_within_reach(
        &self,
        y: Point3,
        reach: &impl Reach,
        mut seed: impl FnMut(usize, Vec2) -> Result<(), ProjectionError>,
    ) -> Result<(), ProjectionError> {
        let mut order: Vec<(f64, usize)> = (self.faces.iter().enumerate())
            .map(|(i, f)| (f.lower_bound(y), i))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut found: Vec<(usize, f64, Vec2)> = Vec::new();
        let mut best = f64::INFINITY;
        let mut far = FarLeaves::default();
        for (lb, i) in order {
            let within = reach.of(i, best);
            let (Some(f), false) = (self.faces.get(i), lb > within) else {
                continue;
            };
            let bound2 = within * within * (1.0 + super::BOUND_SLACK);
            let tight = within.is_finite();
            if let Some((_, foot)) = f.search((y, bound2), None, tight, &mut far.of_face(i))? {
                let d = foot.dist2.sqrt();
                best = best.min(d);
                found.push((i, d, foot.uv));
            }
        }
        found.sort_by_key(|s| s.0);
        for (i, _, uv) in found.into_iter().filter(|s| s.1 <= reach.of(s.0, best)) {
            seed(i, uv)?;
        }
        Ok(())
    }
}
