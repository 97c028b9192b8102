//! Searches that start with a tight bound (a foot found nearby): the
//! leaves near the query point come from the grid, and a warm start's foot
//! is confirmed without a Newton iteration in the leaf that holds it when
//! the leaf's certificate allows.
use super::grid::Cells;
use super::stack::NodeStack;
use super::ProjectionIndex;
use crate::geometry::projection::newton::Foot;
use crate::geometry::{NurbsSurface, ProjectionError};
use crate::math::{Point3, Vec2};

/// What earlier queries learnt of leaves' distances, for the searches
/// with a tight bound: the distance from a point to a set changes no
/// faster than the point, so a leaf's least distance from one point bounds
/// it from nearby ones.
pub(crate) trait LeafMemo {
    /// A lower bound of the distance from `p` to leaf `leaf` (mm; zero or
    /// less when nothing is known).
    fn floor(&self, leaf: usize, p: Point3) -> f64;
    /// Notes that the least distance from `p` to leaf `leaf` is `dist` (mm,
    /// the end of its Newton iteration).
    fn note(&mut self, leaf: usize, p: Point3, dist: f64);
}

/// A memo that knows and keeps nothing.
pub(crate) struct NoMemo;

impl LeafMemo for NoMemo {
    fn floor(&self, _: usize, _: Point3) -> f64 {
        0.0
    }
    fn note(&mut self, _: usize, _: Point3, _: f64) {}
}

impl ProjectionIndex {
    /// Calls `visit(leaf, bound2)` for every leaf whose axis-aligned box
    /// comes closer to `p` than `sqrt(bound2)`, the bound as it is at that
    /// moment (`visit` may lower it). The leaves come from the cells of
    /// the grid the first bound reaches when they are few, else from a
    /// depth-first walk down the tree (nearer child first).
    pub(super) fn for_leaves_near<E>(
        &self,
        p: Point3,
        bound2: &mut f64,
        mut visit: impl FnMut(usize, &mut f64) -> Result<(), E>,
    ) -> Result<(), E> {
        match self.grid.cells_near(p, bound2.sqrt()) {
            Cells::Miss => Ok(()),
            Cells::Range(lo, hi) => self.grid.for_leaves((lo, hi), |leaf| {
                let near = (self.leaves.get(leaf)).is_some_and(|l| l.aabb.dist2(p) < *bound2);
                if near {
                    visit(leaf, bound2)?;
                }
                Ok(())
            }),
            Cells::Many => self.walk_near(p, bound2, visit),
        }
    }

    /// [`Self::for_leaves_near`] down the tree.
    fn walk_near<E>(
        &self,
        p: Point3,
        bound2: &mut f64,
        mut visit: impl FnMut(usize, &mut f64) -> Result<(), E>,
    ) -> Result<(), E> {
        let Some(root) = self.nodes.len().checked_sub(1) else {
            return Ok(());
        };
        let mut stack = NodeStack::new();
        stack.push((self.child_dist2(root, p), root));
        while let Some((d2, i)) = stack.pop() {
            let Some(node) = self.nodes.get(i).filter(|_| d2 < *bound2) else {
                continue;
            };
            match node.kind {
                Ok(leaf) => visit(leaf, bound2)?,
                Err(children) => {
                    let next = self.children_far_near(children, p);
                    (next.into_iter())
                        .filter(|c| c.0 < *bound2)
                        .for_each(|c| stack.push(c));
                }
            }
        }
        Ok(())
    }

    /// The closest point of `surface` (untrimmed) to `p` given `foot`, a
    /// local minimum of the distance on it (a warm Newton's foot), which
    /// it replaces when it finds a closer one; returns the leaf of the
    /// answer (`None` for `foot` when no leaf holding it came closer). The
    /// leaves whose boxes come closer than the best foot so far are
    /// searched, each as [`Self::search_leaf`] does, except a leaf whose
    /// parameter box holds the first `foot` when its certificate
    /// ([`super::convex`]) shows that none of its points comes closer.
    pub(crate) fn confirm(
        &self,
        surface: &NurbsSurface,
        p: Point3,
        foot: &mut Foot,
        memo: &mut dyn LeafMemo,
    ) -> Result<Option<usize>, ProjectionError> {
        let known = (foot.uv, foot.dist2.sqrt());
        let mut leaf_of = None;
        let mut bound2 = foot.dist2;
        self.for_leaves_near(p, &mut bound2, |leaf, bound2| {
            let spared = self.holds_known(leaf, p, known, *bound2, &mut leaf_of);
            if !spared {
                if let Some(found) =
                    self.search_leaf_with(surface, None, leaf, (p, *bound2), memo)?
                {
                    *bound2 = found.dist2;
                    *foot = found;
                    leaf_of = Some(leaf);
                }
            }
            Ok(())
        })?;
        Ok(leaf_of)
    }

    /// Whether leaf `leaf`, whose boxes come closer than
    /// `sqrt(best_dist2)`, holds the local minimum `known` (parameters and
    /// distance; noted in `leaf_of` when no closer foot was found yet) and
    /// its certificate excludes closer points.
    fn holds_known(
        &self,
        leaf: usize,
        p: Point3,
        (uv, dist): (Vec2, f64),
        best_dist2: f64,
        leaf_of: &mut Option<usize>,
    ) -> bool {
        let Some(l) = self.leaves.get(leaf) else {
            return true;
        };
        if !l.bounds.contains(uv) || l.obb.dist2(p) >= best_dist2 {
            return false;
        }
        if best_dist2 >= dist * dist {
            leaf_of.get_or_insert(leaf);
        }
        l.convexity().excludes_closer(dist)
    }
}
