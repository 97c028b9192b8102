//! One area's check against the faces: which faces' leaf boxes come near a
//! piece of it, and a lower bound of the distance from a sample point to
//! the part. Both ask the faces' box tree first, so only the faces near the
//! piece or the point are looked at.
use super::{Axes, PartClearance, Piece};
use crate::geometry::HullShadows;
use crate::math::{Point3, Vec3};
use crate::workpiece::FootHint;

/// Added to the required distance, relative to the coordinates' size, when
/// the faces' boxes pick the faces a piece's separating-axis test looks
/// at: a face whose box keeps farther than that along an axis has every
/// leaf's box (inside its own) at least the required distance away along
/// it, however the test rounds.
const BOX_ROUNDING: f64 = 1e-9;

/// Faces whose leaf hint is kept (the faces near one area are few).
const LEAF_HINTS: usize = 32;

/// The check of one area: what it must keep and what it has learnt.
pub(super) struct AreaCheck {
    /// Ball radius plus margin, mm.
    pub(super) need: f64,
    /// Pieces whose points all lie within this of their samples are judged
    /// by the samples, mm.
    pub(super) fine_reach: f64,
    /// The area's separating axes.
    axes: Axes,
    /// Faces near the piece or sample at hand (reused buffer).
    near: Vec<usize>,
    /// The faces whose leaf boxes came closer than required to the last
    /// sample.
    faces: Vec<usize>,
    /// Where the last exact foot lay, to start the next projection from.
    hint: Option<FootHint>,
    /// Per face, the leaf the last box query found nearest or near, to try
    /// first in the next (a few faces, the latest last).
    leaves: Vec<(usize, usize)>,
    /// The face whose boxes were found near last.
    near_face: usize,
}

impl AreaCheck {
    /// The check of an area with the separating axes `axes` for the
    /// distance `need` (mm), judging pieces within `fine_reach` (mm) of
    /// their samples by the samples alone.
    pub(super) fn new(need: f64, fine_reach: f64, axes: Axes) -> AreaCheck {
        AreaCheck {
            need,
            fine_reach,
            axes,
            near: Vec::new(),
            faces: Vec::new(),
            hint: None,
            leaves: Vec::new(),
            near_face: 0,
        }
    }

    fn leaf_hint(&self, face: usize) -> Option<usize> {
        self.leaves.iter().rev().find(|e| e.0 == face).map(|e| e.1)
    }

    fn note_leaf(&mut self, face: usize, leaf: Option<usize>) {
        let Some(leaf) = leaf else {
            return;
        };
        self.leaves.retain(|e| e.0 != face);
        if self.leaves.len() >= LEAF_HINTS {
            self.leaves.remove(0);
        }
        self.leaves.push((face, leaf));
    }
}

/// A piece of a checked area: the check looks at its sample, bounds the
/// rest by its reach and its hull, and cuts it in two while undecided.
pub(super) trait AreaPiece: Sized {
    /// Points whose convex hull holds the piece.
    type Hull: AsRef<[Point3]>;

    /// Points whose convex hull holds the piece (part coordinates).
    fn hull(&self) -> Self::Hull;

    /// The point that stands for the piece (part coordinates).
    fn sample(&self) -> Point3;

    /// An upper bound of the distance from the sample to the piece's
    /// farthest point, mm.
    fn reach(&self) -> f64;

    /// The piece cut in two, the half looked at first first.
    fn halves(&self) -> [Self; 2];
}

impl AreaPiece for Piece {
    type Hull = [Point3; 4];

    fn hull(&self) -> [Point3; 4] {
        self.corners()
    }

    fn sample(&self) -> Point3 {
        Piece::sample(self)
    }

    fn reach(&self) -> f64 {
        Piece::reach(self)
    }

    fn halves(&self) -> [Piece; 2] {
        Piece::halves(self)
    }
}

/// The box round `points`.
fn box_of(points: &[Point3]) -> (Point3, Point3) {
    let first = points.first().copied().unwrap_or_else(Point3::origin);
    (points.iter()).fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
}

impl PartClearance<'_> {
    /// Whether some face's leaf boxes may come within the required
    /// distance of the convex hull of `hull` (with the axes of the area it
    /// was cut from). The face found near last is tried first.
    pub(super) fn boxes_near(&self, hull: &[Point3], check: &mut AreaCheck) -> bool {
        let (lo, hi) = box_of(hull);
        let size = lo.coords.abs().max().max(hi.coords.abs().max());
        let pad = Vec3::repeat(check.need + BOX_ROUNDING * (1.0 + size));
        let mut near = std::mem::take(&mut check.near);
        self.workpiece
            .faces_overlapping(lo - pad, hi + pad, &mut near);
        let axes = (check.axes.normals.as_slice(), check.axes.edges.as_slice());
        let shape = HullShadows::new(hull, axes);
        let first = near.partition_point(|&i| i < check.near_face);
        let (before, after) = near.split_at(first);
        let found = after.iter().chain(before).copied().find(|&i| {
            let Some(face) = self.workpiece.faces.get(i) else {
                return false;
            };
            let leaf = face
                .index()
                .leaf_near(&shape, check.need, check.leaf_hint(i));
            check.note_leaf(i, leaf);
            leaf.is_some()
        });
        check.near = near;
        check.near_face = found.unwrap_or(check.near_face);
        found.is_some()
    }

    /// A lower bound of the distance from `q` (part) to the part, mm: the
    /// distance to the faces' nearest leaf boxes, exact once that comes
    /// closer than the required distance; projection failures count as
    /// touching (0).
    pub(super) fn distance_bound(&self, q: Point3, check: &mut AreaCheck) -> f64 {
        let wp = self.workpiece;
        let mut near = std::mem::take(&mut check.near);
        wp.faces_within(q, check.need, &mut near);
        check.faces.clear();
        let mut beyond = f64::INFINITY;
        for &i in &near {
            let d = self.leaf_box_distance(q, i, check);
            if d < check.need {
                check.faces.push(i);
            } else {
                beyond = beyond.min(d);
            }
        }
        // The faces farther than `need` by their boxes: the nearest leaf
        // box among them (when no face comes nearer), else their boxes.
        let listed = |i: usize| near.binary_search(&i).is_ok();
        let d = if check.faces.is_empty() {
            wp.nearest_face_box(q, beyond, |i, _| {
                (!listed(i)).then(|| self.leaf_box_distance(q, i, check))
            })
        } else {
            let others = wp.nearest_face_box(q, beyond, |i, root| (!listed(i)).then_some(root));
            self.exact_distance(q, check).map_or(0.0, |d| d.min(others))
        };
        check.near = near;
        d
    }

    /// The distance from `q` to face `i`'s leaf boxes, mm.
    fn leaf_box_distance(&self, q: Point3, i: usize, check: &mut AreaCheck) -> f64 {
        let Some(f) = self.workpiece.faces.get(i) else {
            return f64::INFINITY;
        };
        let (d, nearest) = f.index().box_distance_near(q, check.leaf_hint(i));
        check.note_leaf(i, nearest);
        d
    }

    /// The distance from `q` (part) to the faces whose leaf boxes came
    /// closer than required (a projection started from the check's last
    /// foot).
    fn exact_distance(&self, q: Point3, check: &mut AreaCheck) -> Option<f64> {
        let found = self
            .workpiece
            .closest_point_near(q, &check.faces, check.hint);
        let (fp, hint) = found.ok()?;
        check.hint = hint.or(check.hint);
        Some(fp.projection.distance)
    }
}
