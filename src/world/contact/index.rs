//! The leaves of one true part, made one face at a time: each face's
//! leaves (its pieces mapped onto the true part) and their tree are made
//! the first time a query comes within [`LeafOptions::split_within_mm`] of
//! the face's box beyond what it looks at. Until then the face counts with
//! its box: the box of its nominal control points mapped by the part's
//! transform and widened by the form's bound over it, which holds the
//! face's true surface, so a bound from it is a true lower bound too.
//!
//! The answers do not depend on which faces are made: a query that needs
//! a face's leaves (one whose box comes within what it looks at) makes
//! them, and a bound from a box is at most the bound of any leaf in it.
use std::sync::{Arc, OnceLock};

use super::leaves::{Aabb, Chord, Leaf, Leaves, Pieces};
use super::pieces::LazyPieces;
use super::tree::{kept, LeafTree, Shape};
use super::LeafOptions;
use crate::math::{Mat3, Point3, Vec2, Vec3};
use crate::workpiece::Workpiece;
use crate::world::as_machined::AsMachined;

/// The leaves of one face on the true part.
#[derive(Debug, Clone)]
pub(crate) struct FaceIndex {
    pub(crate) leaves: Leaves,
    pub(crate) tree: LeafTree,
}

/// The part's leaves, face by face, shared by every search on the part.
#[derive(Debug, Clone)]
pub(crate) struct PartIndex {
    /// The nominal pieces the leaves are made of (one leaf a piece).
    pub(crate) pieces: Arc<LazyPieces>,
    /// Each face's box on the true part, and their tree.
    boxes: Vec<Aabb>,
    tree: LeafTree,
    faces: Vec<OnceLock<FaceIndex>>,
    /// [`LeafOptions::split_within_mm`].
    split_within: f64,
    /// The part's transform undone: the inverse of its linear part, its
    /// translation and a lower bound of the factor by which it shortens
    /// lengths (`None` for a transform with no inverse).
    pub(crate) undo: Option<Undo>,
}

/// Relative error allowed for the SVD's least singular value (a few
/// hundred rounding errors of a 3 x 3 decomposition).
const SHRINK_ROUNDING: f64 = 1e-12;

/// The inverse of a part's transform `T(x) = L x + t`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Undo {
    /// `L^-1`.
    pub(crate) inverse: Mat3,
    /// `t`, mm.
    pub(crate) offset: Vec3,
    /// A lower bound of the least singular value of `L`: `T` keeps
    /// points at least this times their distance apart.
    pub(crate) shrink: f64,
}

impl Undo {
    /// The inverse of `am`'s transform, when it has one.
    fn of(am: &AsMachined) -> Option<Undo> {
        let linear = am.linear_part();
        let inverse = linear.try_inverse()?;
        // The SVD's least singular value, a few rounding errors lowered.
        let least = linear.singular_values().min();
        let shrink = least * (1.0 - SHRINK_ROUNDING);
        (shrink.is_finite() && shrink > 0.0).then_some(Undo {
            inverse,
            offset: am.translation(),
            shrink,
        })
    }

    /// The nominal point `T^-1(x)`.
    pub(crate) fn point(&self, x: Point3) -> Point3 {
        Point3::from(self.inverse * (x.coords - self.offset))
    }
}

/// Something leaves are looked up in by number.
pub(crate) trait LeafSource {
    /// Leaf `id`, when there is one.
    fn leaf(&self, id: u32) -> Option<&Leaf>;
}

impl LeafSource for [Leaf] {
    #[inline(always)]
    fn leaf(&self, id: u32) -> Option<&Leaf> {
        self.get(id as usize)
    }
}

impl LeafSource for PartIndex {
    #[inline(always)]
    fn leaf(&self, id: u32) -> Option<&Leaf> {
        let (face, local) = self.pieces.split_id(id);
        let made = self.faces.get(face)?.get()?;
        made.leaves.leaves.get(local as usize)
    }
}

impl PartIndex {
    /// The index of the part `wp` as machined by `am`, no face made yet.
    pub(crate) fn new(wp: &Workpiece, am: &AsMachined, opts: &LeafOptions) -> PartIndex {
        let pieces = am.pieces.pieces(wp, opts);
        let stretch = am.stretch_factor();
        let boxes = (0..pieces.face_count())
            .map(|f| {
                let b = pieces.nominal_box(f).copied().unwrap_or_else(Aabb::empty);
                let inflate = am.max_form_height_over(f, b.min, b.max) * stretch;
                b.mapped(|p| am.transform_point(p)).grown(inflate)
            })
            .collect::<Vec<Aabb>>();
        let tree = pieces
            .tree
            .refit_with(|f| boxes.get(f as usize).copied().unwrap_or_else(Aabb::empty));
        PartIndex {
            tree,
            faces: (0..pieces.face_count()).map(|_| OnceLock::new()).collect(),
            boxes,
            pieces,
            split_within: opts.split_within_mm,
            undo: Undo::of(am),
        }
    }

    /// Number of leaves made so far.
    pub(crate) fn leaves_made(&self) -> usize {
        (self.faces.iter())
            .filter_map(|f| f.get())
            .map(|f| f.leaves.leaves.len())
            .sum()
    }

    /// Face `face`'s leaves, made on first use.
    pub(crate) fn face(
        &self,
        (wp, am): (&Workpiece, &AsMachined),
        face: usize,
    ) -> Option<&FaceIndex> {
        let slot = self.faces.get(face)?;
        let pieces = self.pieces.face(wp, face)?;
        Some(slot.get_or_init(|| {
            let leaves = Leaves::of(pieces, am);
            let tree = pieces.tree.refit(&leaves.leaves);
            FaceIndex { leaves, tree }
        }))
    }

    /// Face `face`'s leaves when they are made.
    fn face_made(&self, face: usize) -> Option<&FaceIndex> {
        self.faces.get(face)?.get()
    }

    /// Appends to `out` every leaf whose lower bound from `p` is below
    /// `radius`, with its bound (making the faces whose box comes that
    /// near).
    pub(crate) fn within_bounds<S: Shape>(
        &self,
        part: (&Workpiece, &AsMachined),
        p: S,
        radius: f64,
        out: &mut Vec<(f64, u32)>,
    ) {
        self.tree.items_within(&self.boxes, p, radius, |f| {
            let Some(fi) = self.face(part, f as usize) else {
                return;
            };
            let from = out.len();
            fi.tree.within_bounds(&fi.leaves.leaves, p, radius, out);
            for e in out.iter_mut().skip(from) {
                e.1 = self.pieces.id(f as usize, e.1);
            }
        });
    }

    /// A lower bound of the distance from `p` to the part that keeps at
    /// least `ratio` of the least leaf bound's excess over `offset` (see
    /// [`LeafTree::nearest_within`]), mm. A face not made yet whose box
    /// keeps more than [`LeafOptions::split_within_mm`] beyond `offset`
    /// counts with its box.
    pub(crate) fn nearest_within<S: Shape>(
        &self,
        part: (&Workpiece, &AsMachined),
        p: S,
        (offset, ratio): (f64, f64),
    ) -> f64 {
        let keep = (offset, ratio);
        let visit = |f: u32, d: f64, best: f64| {
            let f = f as usize;
            if self.face_made(f).is_none() && d > offset + self.split_within {
                return best.min(d);
            }
            match self.face(part, f) {
                Some(fi) => fi.tree.nearest_from(&fi.leaves.leaves, p, keep, best),
                None => best,
            }
        };
        let best = self
            .tree
            .nearest_items(&self.boxes, p, keep, f64::INFINITY, visit);
        kept(best, keep)
    }

    /// The pieces of leaf `id`'s face and its number among them.
    pub(crate) fn piece_of(&self, id: u32) -> Option<(&Pieces, usize)> {
        let (face, local) = self.pieces.split_id(id);
        Some((self.pieces.face_made(face)?, local as usize))
    }

    /// The trim segments of leaf `id` with their chords on the true part
    /// `am` ([`Leaves::trim_chords`]).
    pub(crate) fn trim_chords<'a>(
        &'a self,
        id: u32,
        am: &'a AsMachined,
    ) -> impl Iterator<Item = ((Vec2, Vec2), Chord)> + 'a {
        let (face, local) = self.pieces.split_id(id);
        let made = self.face_made(face).zip(self.pieces.face_made(face));
        made.into_iter()
            .flat_map(move |(fi, p)| fi.leaves.trim_chords(p, local as usize, am))
    }

    /// The true points of leaf `id`'s sample grid: its piece's nominal
    /// ones mapped by the part's transform (none for a leaf of no piece).
    pub(crate) fn true_samples(&self, id: u32, (wp, am): (&Workpiece, &AsMachined)) -> [Point3; 9] {
        let piece = self.piece_of(id).and_then(|(p, k)| p.pieces.get(k));
        let surface = piece.and_then(|p| wp.faces.get(p.face)).map(|f| &f.surface);
        match (piece, surface) {
            (Some(p), Some(s)) => p.nominal_samples(s).map(|q| am.transform_point(q)),
            _ => [Point3::origin(); 9],
        }
    }

    /// Every leaf of the part with its number, every face made.
    #[cfg(test)]
    pub(crate) fn all_leaves(&self, part: (&Workpiece, &AsMachined)) -> Vec<(u32, &Leaf)> {
        (0..self.faces.len())
            .filter_map(|f| self.face(part, f).map(|fi| (f, fi)))
            .flat_map(|(f, fi)| {
                let ids = (0..).map(move |k| self.pieces.id(f, k));
                ids.zip(fi.leaves.leaves.iter())
            })
            .collect()
    }
}
