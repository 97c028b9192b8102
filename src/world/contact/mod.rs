//! The world's per-cycle contact search: the distance from the stylus ball
//! centre to the true (as-machined, trimmed) part, at a cost that does not
//! grow with the number of faces.
//!
//! - **Leaves** ([`leaves`]): every face split into near-flat pieces (and
//!   along its trim boundary into small ones), each bounded on the true
//!   surface `q = T(p + h n)` by a box and a slab: the nominal control
//!   points mapped by `T`, widened by the form's largest `|h|` on the face
//!   times the largest stretch of `T`. Pieces outside a face's trim are
//!   left out: the part has material only where its trimmed faces are.
//! - **Broad phase** ([`tree`], [`index`]): a box tree over the faces'
//!   boxes, and one over each face's leaves. A face is split into leaves
//!   the first time a query comes near its box (a program that measures a
//!   few faces of a part with hundreds splits only those and the faces its
//!   moves pass near); until then its box stands in for it.
//! - **Free air**: a query remembers a lower bound `L` of the distance at
//!   the point `a` it was asked at (the nearest leaf bound, or the least
//!   distance found). By the triangle inequality the distance at `y` is at
//!   least `L - |y - a|`, so no search runs until the ball centre has moved
//!   `L - reach` from `a` (measured from the true ball positions, not from
//!   a speed limit: the bound holds for any motion). `reach` is the tip
//!   radius plus a margin; the form's deviation is inside the leaf bounds.
//! - **Near the part**: the leaves within `reach + 2 slack` of a point are
//!   listed once and serve every query within `slack` of it; of those,
//!   only the leaves whose bound comes below the best distance so far get
//!   a Newton iteration on the true surface (warm from their last foot),
//!   and only a leaf crossed by its trim whose foot leaves the trim gets
//!   the boundary search over its (clipped) trim segments.
//! - **Sign**: from the closest foot's outward normal; at a foot on a face
//!   boundary the sign is that of the face, among those whose distance
//!   comes within `edge_tie_mm` of the least, whose normal is best aligned
//!   with the ball's offset from its foot (the adjacent faces' rule for
//!   the edges and corners of a closed B-rep). A boundary foot with no
//!   other face near counts as outside (an open sheet's edge).
//! - **The rest of the probe** ([`collide`]): the stylus shaft and the
//!   probe body, each a solid cylinder, checked against the same leaves
//!   and tree with a segment-box broad phase, a free-air bound of their
//!   own and an exact descent of the same point query over the cylinder.
mod box_tree;
#[cfg(test)]
mod chord_tests;
mod collide;
mod index;
mod leaves;
mod line;
mod mapped;
mod near;
mod pieces;
#[cfg(test)]
mod refit_tests;
mod search;
mod shapes;
mod tree;
mod trimmed_box;
#[cfg(test)]
mod trimmed_tests;

pub use collide::{CollisionOptions, PartCheck, Strike};
pub(crate) use index::PartIndex;
pub use leaves::LeafOptions;
pub use pieces::PieceCache;
pub use search::{ContactSearch, Cursor};
pub(crate) use shapes::Cylinder;

use crate::math::{Point3, Vec2, Vec3};

/// Tolerances of the contact search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactOptions {
    /// How far (mm) the ball centre may move before the list of leaves
    /// near it is made again (it holds the leaves within `reach + 2 slack`).
    /// The most: a list of more than [`Self::dense_list`] leaves halves
    /// the slack of the next one, down to [`Self::min_slack_mm`], and a
    /// list of less than a quarter of that doubles it again (near faces cut
    /// into tiny pieces, a small ball's list holds thousands of leaves
    /// within a few tenths of a millimetre, and each query would look at
    /// those its move since the listing brought near).
    pub slack_mm: f64,
    /// See [`Self::slack_mm`], mm.
    pub min_slack_mm: f64,
    /// See [`Self::slack_mm`]: leaves in a list.
    pub dense_list: usize,
    /// Feet on other faces whose distance comes within this (mm) of the
    /// least one take part in the sign rule at a face boundary (the gaps
    /// and overlaps of a B-rep's trimmed faces along their common edges).
    pub edge_tie_mm: f64,
    /// How the faces are split into leaves.
    pub leaves: LeafOptions,
    /// In free air the bound a query or a shaft check leaves behind may
    /// keep only this fraction (dimensionless, in `(0, 1]`) of the
    /// nearest leaf's distance beyond the query's reach or the cylinder's
    /// radius (how far the probe may move before the next search): the
    /// search for the nearest leaf then skips every part of the tree that
    /// cannot bring it below that.
    pub free_air_ratio: f64,
}

impl Default for ContactOptions {
    fn default() -> Self {
        ContactOptions {
            slack_mm: 0.3,
            min_slack_mm: 0.02,
            dense_list: 256,
            edge_tie_mm: 1e-3,
            leaves: LeafOptions::default(),
            free_air_ratio: 0.9,
        }
    }
}

/// The closest point of the true part to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrueContact {
    /// Face of the foot.
    pub face: usize,
    /// Nominal parameters of the face that map to the foot.
    pub uv: Vec2,
    /// The foot on the true surface (part frame), mm.
    pub point: Point3,
    /// Signed distance from the query point: positive outside the
    /// material, mm.
    pub distance: f64,
    /// Unit direction in which the surface pushes a ball centred at the
    /// query point (the outward normal at a foot inside a face).
    pub push: Vec3,
    /// Whether the foot lies on a face boundary (an edge of the part).
    pub edge: bool,
}
