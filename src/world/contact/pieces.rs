//! The contact leaves' nominal pieces, kept for every copy of one true
//! part: a batch's variants of a program share its design, so the faces
//! are split once and each variant only maps the pieces. A face is split
//! the first time a query comes near it ([`LazyPieces::face`]): a program
//! that measures a few faces of a part with hundreds splits only those
//! and the faces its moves pass close to. The cache is
//! keyed by a fingerprint of the design (every control point, weight,
//! knot and trim vertex, hashed once per workpiece) and the leaf options,
//! so a part asked with other design data makes its own pieces.
use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::{Arc, Mutex, OnceLock};

use super::leaves::{Aabb, Pieces};
use super::tree::LeafTree;
use super::LeafOptions;
use crate::math::Point3;
use crate::workpiece::Workpiece;

/// The pieces last made, with the fingerprint they were made for.
type Held = Option<(u64, Arc<LazyPieces>)>;

/// The pieces last made for a part and its copies.
#[derive(Clone, Default)]
pub struct PieceCache(Arc<Mutex<Held>>);

impl PieceCache {
    /// The pieces of `wp` split with `opts`, each face's made on first use.
    pub(crate) fn pieces(&self, wp: &Workpiece, opts: &LeafOptions) -> Arc<LazyPieces> {
        let key = fingerprint(wp, opts);
        if let Ok(held) = self.0.lock() {
            if let Some((_, p)) = held.as_ref().filter(|(k, _)| *k == key) {
                return Arc::clone(p);
            }
        }
        let made = Arc::new(LazyPieces::new(wp, opts));
        if let Ok(mut held) = self.0.lock() {
            *held = Some((key, Arc::clone(&made)));
        }
        made
    }
}

/// A cache is no part of the part's value: copies compare equal.
impl PartialEq for PieceCache {
    fn eq(&self, _: &PieceCache) -> bool {
        true
    }
}

impl std::fmt::Debug for PieceCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PieceCache")
    }
}

/// A hash of everything the splits depend on: the design
/// ([`Workpiece::design_hash`]) and the leaf options.
fn fingerprint(wp: &Workpiece, opts: &LeafOptions) -> u64 {
    let mut h = DefaultHasher::new();
    wp.design_hash().hash(&mut h);
    for x in [opts.flatness, opts.trim_leaf_mm, opts.trim_box_mm] {
        x.to_bits().hash(&mut h);
    }
    let depths = (
        opts.max_flat_depth,
        opts.max_trim_depth,
        opts.max_trim_box_depth,
    );
    depths.hash(&mut h);
    h.finish()
}

/// The pieces of a workpiece, one face at a time: each face's pieces (with
/// their own tree) are made the first time they are asked for. A leaf is
/// numbered by its face in the high bits and its number among the face's
/// pieces in the low ones, so leaves keep the order of faces, then of
/// pieces (the order ties are broken in).
#[derive(Debug)]
pub(crate) struct LazyPieces {
    opts: LeafOptions,
    /// Bits of a leaf number that hold the piece's number on its face.
    local_bits: u32,
    faces: Vec<OnceLock<Pieces>>,
    /// The box of each face's nominal control points (its whole surface,
    /// trimmed or not, lies in their hull).
    boxes: Vec<Aabb>,
    /// The tree over those boxes: each part refits it to its own.
    pub(crate) tree: LeafTree,
}

impl LazyPieces {
    /// The pieces of `wp` split with `opts`, none made yet.
    pub(crate) fn new(wp: &Workpiece, opts: &LeafOptions) -> LazyPieces {
        let faces = wp.faces.len().max(1);
        let face_bits = (usize::BITS - (faces - 1).leading_zeros()).clamp(1, 31);
        let boxes = (wp.faces.iter())
            .map(|f| {
                let points = f.surface.homogeneous_points().iter();
                Aabb::of(points.map(|p| Point3::new(p.x / p.w, p.y / p.w, p.z / p.w)))
            })
            .collect::<Vec<Aabb>>();
        LazyPieces {
            tree: LeafTree::over(&boxes),
            opts: *opts,
            local_bits: 32 - face_bits,
            faces: (0..wp.faces.len()).map(|_| OnceLock::new()).collect(),
            boxes,
        }
    }

    /// Number of faces.
    pub(crate) fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// The box of face `face`'s nominal control points.
    pub(crate) fn nominal_box(&self, face: usize) -> Option<&Aabb> {
        self.boxes.get(face)
    }

    /// The pieces of face `face` of `wp` (the design these were made
    /// for), split on first use; `None` for no such face.
    pub(crate) fn face(&self, wp: &Workpiece, face: usize) -> Option<&Pieces> {
        let slot = self.faces.get(face)?;
        Some(slot.get_or_init(|| self.split(wp, face)))
    }

    /// Face `face`'s pieces when they have been made.
    pub(crate) fn face_made(&self, face: usize) -> Option<&Pieces> {
        self.faces.get(face)?.get()
    }

    /// The pieces of one face, coarser (fewer halvings, longer pieces
    /// along the trim) while they would not fit the leaf numbers' low
    /// bits; past the coarsest, the pieces beyond those are left out.
    fn split(&self, wp: &Workpiece, face: usize) -> Pieces {
        let cap = 1usize << self.local_bits;
        let mut opts = self.opts;
        loop {
            let made = Pieces::of_faces(wp, std::iter::once(face), &opts);
            if made.len() <= cap {
                return made;
            }
            if opts.max_flat_depth == 0 && opts.max_trim_depth == 0 {
                return made.truncated(cap);
            }
            opts.max_flat_depth = opts.max_flat_depth.saturating_sub(1);
            opts.max_trim_depth = opts.max_trim_depth.saturating_sub(1);
            opts.trim_leaf_mm *= 2.0;
        }
    }

    /// The leaf number of piece `local` of face `face`.
    pub(crate) fn id(&self, face: usize, local: u32) -> u32 {
        ((face as u32) << self.local_bits) | local
    }

    /// The face and the piece number on it of leaf `id`.
    pub(crate) fn split_id(&self, id: u32) -> (usize, u32) {
        let face = (id >> self.local_bits) as usize;
        (face, id & ((1u32 << self.local_bits) - 1))
    }
}
