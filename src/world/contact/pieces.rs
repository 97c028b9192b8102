//! The contact leaves' nominal pieces, kept for every copy of one true
//! part: a batch's variants of a program share its design, so the faces
//! are split once and each variant only maps the pieces. The cache is
//! keyed by a fingerprint of the design (every control point, weight,
//! knot and trim vertex, hashed once per workpiece) and the leaf options,
//! so a part asked with other design data makes its own pieces.
use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::{Arc, Mutex};

use super::leaves::Pieces;
use super::LeafOptions;
use crate::workpiece::Workpiece;

/// The pieces last made, with the fingerprint they were made for.
type Held = Option<(u64, Arc<Pieces>)>;

/// The pieces last made for a part and its copies.
#[derive(Clone, Default)]
pub struct PieceCache(Arc<Mutex<Held>>);

impl PieceCache {
    /// The pieces of `wp` split with `opts`, made on first use.
    pub(crate) fn pieces(&self, wp: &Workpiece, opts: &LeafOptions) -> Arc<Pieces> {
        let key = fingerprint(wp, opts);
        if let Ok(held) = self.0.lock() {
            if let Some((_, p)) = held.as_ref().filter(|(k, _)| *k == key) {
                return Arc::clone(p);
            }
        }
        let made = Arc::new(Pieces::new(wp, opts));
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
