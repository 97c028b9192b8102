//! Tighter boxes for the leaves the trim crosses, made only where the
//! collision check of the shaft or the body needs them.
//!
//! A leaf the trim boundary crosses (a piece of a plate on the edge of a
//! hole or of its outline, up to [`super::LeafOptions::trim_leaf_mm`] across) has
//! the box of its whole parameter rectangle, which reaches over the hole
//! or past the edge. A stylus running beside such an edge (0.45 mm from
//! the wall for a 3 mm ball on a 1.5 mm shaft at 0.3 mm deflection) then
//! finds the leaf's bound at zero and runs an exact check every few
//! cycles. The trimmed box holds only the part of the piece inside the
//! trim: the piece is halved (for the boxes alone), the halves inside kept
//! whole, the halves outside left out, the halves the trim crosses halved
//! until [`super::LeafOptions::trim_box_mm`] across; the leaf's trimmed
//! bound is the least distance to those boxes. They are made once per design
//! (shared by a batch's variants, each of which takes the segment back to
//! the design's frame rather than mapping the boxes), for the leaves
//! a check meets with a bound below its certifying distance only: making
//! it for every crossed piece costs more on parts with many trimmed faces
//! than it saves.
use super::box_tree::BoxTree;
use super::index::PartIndex;
use super::leaves::{centre, halves, rect_of, Aabb, FaceContext, Pieces};
use super::shapes::Segment;
use crate::geometry::nurbs::bezier::BezierPatch;
use crate::math::{Point3, Vec2, Vec3};
use crate::workpiece::Workpiece;
use crate::world::as_machined::AsMachined;

impl Aabb {
    /// The box of the images of this box's corners under `map` (for an
    /// affine map, a box holding the image of the whole box).
    pub(super) fn mapped(&self, map: impl Fn(Point3) -> Point3) -> Aabb {
        let (lo, hi) = (self.min, self.max);
        Aabb::of((0..8).map(|k| {
            let pick = |bit: usize, a: f64, b: f64| if k & bit == 0 { a } else { b };
            map(Point3::new(
                pick(1, lo.x, hi.x),
                pick(2, lo.y, hi.y),
                pick(4, lo.z, hi.z),
            ))
        }))
    }

    /// Whether `o` lies in this box.
    fn holds(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= o.min[k] && o.max[k] <= self.max[k])
    }

    /// This box widened by `d` on every side.
    pub(super) fn grown(&self, d: f64) -> Aabb {
        let g = Vec3::repeat(d);
        Aabb {
            min: self.min - g,
            max: self.max + g,
        }
    }
}

impl Pieces {
    /// The tree of boxes holding the nominal surface over the part of
    /// piece `id` inside its face's trim (`None` for a piece the trim does
    /// not cross: its own box is that), made on first use; `wp` is the
    /// design the pieces were made of.
    pub(crate) fn trimmed_boxes(&self, id: usize, wp: &Workpiece) -> Option<&BoxTree> {
        let piece = self.pieces.get(id)?;
        let patch = piece.crossed.as_ref()?;
        let face = wp.faces.get(piece.face)?;
        let made = piece.trimmed.get_or_init(|| {
            let ctx = FaceContext {
                face: piece.face,
                surface: &face.surface,
                trim: face.trim.as_ref(),
                opts: self.opts,
            };
            BoxTree::new(ctx.trimmed_part_boxes(patch.clone(), piece.segs.clone()))
        });
        Some(made)
    }
}

impl FaceContext<'_> {
    /// The boxes of the control points of the halves of `patch` (crossed
    /// by the trim segments `segs`) that hold its part inside the trim.
    /// Halved level by level, the inside halves first; a crossed half whose
    /// box lies in one kept already adds nothing and is not halved further.
    fn trimmed_part_boxes(&self, patch: BezierPatch, segs: Vec<(Vec2, Vec2)>) -> Vec<Aabb> {
        let mut out: Vec<Aabb> = Vec::new();
        let mut level = vec![(patch, segs)];
        for depth in 0..=self.opts.max_trim_box_depth {
            let mut crossed = Vec::new();
            for (patch, segs) in level {
                if !segs.is_empty() {
                    crossed.push((Aabb::of(patch.points()), patch, segs));
                } else if self
                    .trim
                    .is_none_or(|t| t.contains(centre(&rect_of(&patch))))
                {
                    out.push(Aabb::of(patch.points()));
                }
            }
            let last = depth == self.opts.max_trim_box_depth;
            let mut next = Vec::new();
            for (size, patch, segs) in crossed {
                if out.iter().any(|b| b.holds(&size)) {
                    continue;
                }
                if last || (size.max - size.min).norm() <= self.opts.trim_box_mm {
                    out.push(size);
                    continue;
                }
                let (a, b) = halves(&patch, &segs);
                next.push(a);
                next.push(b);
            }
            if next.is_empty() {
                break;
            }
            level = next;
        }
        out
    }
}

impl PartIndex {
    /// A lower bound of the distance from `seg` to the true surface over
    /// the part of leaf `id` inside its face's trim (`None` for a leaf the
    /// trim does not cross): the least distance to its trimmed boxes when
    /// that is at least `need` (mm), else zero (the boxes are looked at
    /// only until one comes nearer than `need`: a check that needs more
    /// then descends from the leaf anyway).
    ///
    /// The boxes are the design's, shared by every part made of it: the
    /// segment is taken back to the design's frame by the inverse of the
    /// part's transform `T`. A true point is `T(p + h n)` with `p` on the
    /// nominal surface in the boxes and `|h|` at most the form's bound
    /// `H` over them, so a segment `d` from the boxes in the design's
    /// frame keeps at least `s (d - H)` from the true surface (`s` the
    /// least factor by which `T` shortens lengths).
    pub(crate) fn trimmed_bound(
        &self,
        id: u32,
        (wp, am): (&Workpiece, &AsMachined),
        seg: Segment,
        need: f64,
    ) -> Option<f64> {
        let (pieces, local) = self.piece_of(id)?;
        let tree = pieces.trimmed_boxes(local, wp)?;
        let Some(undo) = self.undo else {
            return Some(0.0);
        };
        let face = pieces.pieces.get(local)?.face;
        let whole = tree.bounds();
        let form = am.max_form_height_over(face, whole.min, whole.max);
        let nominal = Segment {
            a: undo.point(seg.a),
            b: undo.point(seg.b),
        };
        let d = tree.least_distance(nominal, need / undo.shrink + form);
        Some((undo.shrink * (d - form)).max(0.0))
    }
}
