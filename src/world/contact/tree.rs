//! One box tree over every face's leaves (the broad phase of the contact
//! search): the nearest leaf bound from a point, and the leaves within a
//! distance of it, at a cost that grows with the depth of the tree, not
//! with the number of faces.
use super::leaves::{Aabb, Leaf};
use crate::math::Point3;

/// What the tree is asked about: a point, or a segment of the probe's
/// axis.
pub(crate) trait Shape: Copy {
    /// Squared distance to the box `b` (zero when they meet), mm^2.
    fn box_dist2(&self, b: &Aabb) -> f64;
    /// Whether the box `b` lies at least `sqrt(r2)` away (a cheaper test
    /// may answer first).
    #[inline(always)]
    fn box_beyond(&self, b: &Aabb, r2: f64) -> bool {
        self.box_dist2(b) >= r2
    }
    /// A lower bound of the distance to the true surface over `leaf`, mm.
    fn leaf_bound(&self, leaf: &Leaf) -> f64;
    /// [`Self::leaf_bound`] when the leaf's box comes nearer than
    /// `sqrt(r2)` (by [`Self::box_beyond`]), else `None`.
    #[inline(always)]
    fn leaf_bound_within(&self, leaf: &Leaf, r2: f64) -> Option<f64> {
        (!self.box_beyond(&leaf.aabb, r2)).then(|| self.leaf_bound(leaf))
    }
}

impl Shape for Point3 {
    #[inline(always)]
    fn box_dist2(&self, b: &Aabb) -> f64 {
        b.dist2(*self)
    }

    #[inline(always)]
    fn leaf_bound(&self, leaf: &Leaf) -> f64 {
        leaf.lower_bound(*self)
    }
}

/// `offset + ratio (best - offset)` when `best` exceeds `offset`, else
/// `best`: the bound that keeps `ratio` of `best`'s excess over `offset`.
pub(crate) fn kept(best: f64, (offset, ratio): (f64, f64)) -> f64 {
    if best > offset {
        offset + ratio * (best - offset)
    } else {
        best
    }
}

/// The square of [`kept`] of `best` (infinite for an infinite one).
fn cut2_of(best: f64, keep: (f64, f64)) -> f64 {
    let cut = kept(best, keep);
    if cut.is_finite() {
        cut * cut
    } else {
        f64::INFINITY
    }
}

/// Most leaves under one node of the tree.
pub(super) const BUCKET: usize = 4;

/// A node of a box tree: its box and either its children or a range of
/// the items under it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Node {
    pub(super) aabb: Aabb,
    /// Leaf node: `order[a..b]`; inner node: children `a` and `b`.
    pub(super) a: u32,
    pub(super) b: u32,
    pub(super) leaf: bool,
}

/// The tree.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LeafTree {
    nodes: Vec<Node>,
    /// Leaf indices, grouped by the tree's leaf nodes.
    order: Vec<u32>,
}

impl LeafTree {
    /// The tree over the boxes `boxes` (leaf `i` has `boxes[i]`; median
    /// splits along the longest side of the boxes' centres).
    pub(crate) fn over(boxes: &[Aabb]) -> LeafTree {
        let mut tree = LeafTree {
            nodes: Vec::with_capacity(2 * boxes.len() / BUCKET + 1),
            order: (0..boxes.len() as u32).collect(),
        };
        let boxes: Vec<(Aabb, Point3)> = boxes.iter().map(|b| (*b, b.centre())).collect();
        if !boxes.is_empty() {
            tree.build(&boxes, 0, boxes.len());
        }
        tree
    }

    /// The same tree over `leaves` (as many as it was built over, in the
    /// same order), its boxes made anew from theirs: the splits stay, so
    /// it costs one pass. Any split answers every query the same way (the
    /// queries are exact and their results do not depend on the order
    /// the tree visits leaves in); splits made for nearly the same boxes
    /// keep it as quick.
    pub(crate) fn refit(&self, leaves: &[Leaf]) -> LeafTree {
        self.refit_with(|l| leaves.get(l as usize).map_or(Aabb::empty(), |l| l.aabb))
    }

    /// [`Self::refit`] with item `i`'s box `box_of(i)`.
    pub(crate) fn refit_with(&self, box_of: impl Fn(u32) -> Aabb) -> LeafTree {
        let mut tree = self.clone();
        // Children come after their parent: from the back, every child's
        // box is made before its parent's.
        for i in (0..tree.nodes.len()).rev() {
            let Some(&node) = tree.nodes.get(i) else {
                continue;
            };
            let aabb = if node.leaf {
                let ids = tree.order.get(node.a as usize..node.b as usize);
                (ids.unwrap_or_default().iter()).fold(Aabb::empty(), |a, &l| a.union(&box_of(l)))
            } else {
                let child = |c: u32| tree.nodes.get(c as usize).map_or(Aabb::empty(), |n| n.aabb);
                child(node.a).union(&child(node.b))
            };
            if let Some(n) = tree.nodes.get_mut(i) {
                n.aabb = aabb;
            }
        }
        tree
    }

    /// Builds the node over `order[lo..hi]` (`boxes`: every leaf's box
    /// and its centre); returns its index.
    fn build(&mut self, boxes: &[(Aabb, Point3)], lo: usize, hi: usize) -> u32 {
        let empty = (Aabb::empty(), Point3::origin());
        let of = |i: &u32| boxes.get(*i as usize).unwrap_or(&empty);
        let at = self.nodes.len() as u32;
        self.nodes.push(Node {
            aabb: Aabb::empty(),
            a: lo as u32,
            b: hi as u32,
            leaf: true,
        });
        let ids = self.order.get(lo..hi).unwrap_or_default();
        let aabb = if hi - lo <= BUCKET {
            (ids.iter()).fold(Aabb::empty(), |a, i| a.union(&of(i).0))
        } else {
            let spread = (ids.iter()).fold(Aabb::empty(), |a, i| {
                a.union(&Aabb {
                    min: of(i).1,
                    max: of(i).1,
                })
            });
            let axis = (spread.max - spread.min).imax();
            let mid = (lo + hi) / 2;
            if let Some(slice) = self.order.get_mut(lo..hi) {
                slice.select_nth_unstable_by(mid - lo, |x, y| {
                    of(x).1[axis].total_cmp(&of(y).1[axis])
                });
            }
            let left = self.build(boxes, lo, mid);
            let right = self.build(boxes, mid, hi);
            if let Some(n) = self.nodes.get_mut(at as usize) {
                (n.a, n.b, n.leaf) = (left, right, false);
            }
            // The union of the children's boxes is the union of their
            // leaves' boxes (min and max are exact).
            let child = |c: u32| self.nodes.get(c as usize).map_or(Aabb::empty(), |n| n.aabb);
            child(left).union(&child(right))
        };
        if let Some(n) = self.nodes.get_mut(at as usize) {
            n.aabb = aabb;
        }
        at
    }

    /// The least lower bound of the leaves' distances from `p` (infinite
    /// for no leaf), mm.
    #[cfg(test)]
    pub(crate) fn nearest<S: Shape>(&self, leaves: &[Leaf], p: S) -> f64 {
        self.nearest_within(leaves, p, (0.0, 1.0))
    }

    /// A lower bound of the leaves' distances from `p` that keeps at least
    /// `ratio` (in `(0, 1]`) of their least lower bound's excess over
    /// `offset` (mm; the reach or the radius the caller takes off), mm:
    /// every node whose box is farther than `offset + ratio (best -
    /// offset)` is skipped, `best` the least bound so far (which only
    /// falls, so a skipped node's leaves keep that of the final one). Far
    /// from the part, where many leaves lie at about the same distance,
    /// this skips most of them.
    #[cfg(test)]
    pub(crate) fn nearest_within<S: Shape>(
        &self,
        leaves: &[Leaf],
        p: S,
        (offset, ratio): (f64, f64),
    ) -> f64 {
        let best = self.nearest_from(leaves, p, (offset, ratio), f64::INFINITY);
        kept(best, (offset, ratio))
    }

    /// The least of `best` (mm) and the lower bounds of the leaves that
    /// [`Self::nearest_within`] looks at, starting from `best`: a node
    /// whose box keeps farther than `kept` of the least bound so far is
    /// skipped, so `kept` of the result is what `nearest_within` of all
    /// the leaves looked at together with `best`'s would give.
    pub(crate) fn nearest_from<S: Shape>(
        &self,
        leaves: &[Leaf],
        p: S,
        keep: (f64, f64),
        best: f64,
    ) -> f64 {
        self.nearest_walk(p, keep, best, |ids, best| {
            (ids.iter())
                .filter_map(|&l| leaves.get(l as usize))
                .fold(best, |b, l| b.min(p.leaf_bound(l)))
        })
    }

    /// Appends to `out` every leaf whose lower bound from `p` is below
    /// `radius` (in tree order).
    #[cfg(test)]
    pub(crate) fn within<S: Shape>(&self, leaves: &[Leaf], p: S, radius: f64, out: &mut Vec<u32>) {
        self.for_each_within(leaves, p, radius, |_, id| out.push(id));
    }

    /// [`Self::within`], each leaf with its bound: appends `(bound, leaf)`.
    pub(crate) fn within_bounds<S: Shape>(
        &self,
        leaves: &[Leaf],
        p: S,
        radius: f64,
        out: &mut Vec<(f64, u32)>,
    ) {
        self.for_each_within(leaves, p, radius, |bound, id| out.push((bound, id)));
    }

    /// Calls `visit(bound, leaf)` for every leaf whose lower bound from `p`
    /// is below `radius`, in tree order (a leaf's box is tested before its
    /// bound).
    fn for_each_within<S: Shape>(
        &self,
        leaves: &[Leaf],
        p: S,
        radius: f64,
        mut visit: impl FnMut(f64, u32),
    ) {
        let r2 = radius * radius;
        self.walk_within(p, r2, |id| {
            let Some(l) = leaves.get(id as usize) else {
                return;
            };
            match p.leaf_bound_within(l, r2) {
                Some(bound) if bound < radius => visit(bound, id),
                _ => {}
            }
        });
    }

    /// Calls `visit(item)` for every item whose box (`boxes[item]`, the
    /// boxes the tree was built or refitted over) comes nearer than
    /// `radius` to `p`, in tree order.
    pub(crate) fn items_within<S: Shape>(
        &self,
        boxes: &[Aabb],
        p: S,
        radius: f64,
        mut visit: impl FnMut(u32),
    ) {
        let r2 = radius * radius;
        self.walk_within(p, r2, |id| {
            if boxes.get(id as usize).is_some_and(|b| !p.box_beyond(b, r2)) {
                visit(id);
            }
        });
    }

    /// Calls `at(item)` for every item under a node whose box comes nearer
    /// than `sqrt(r2)` to `p`, in tree order.
    fn walk_within<S: Shape>(&self, p: S, r2: f64, mut at: impl FnMut(u32)) {
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(i) = stack.pop() {
            let Some(node) = self.nodes.get(i as usize) else {
                continue;
            };
            if p.box_beyond(&node.aabb, r2) {
                continue;
            }
            if !node.leaf {
                stack.extend([node.b, node.a]);
                continue;
            }
            let ids = self.order.get(node.a as usize..node.b as usize);
            ids.unwrap_or_default().iter().for_each(|&id| at(id));
        }
    }

    /// The least bound `best` (mm) once `visit(item, d, best)` (which
    /// returns the least bound with the item looked at, at most `best`)
    /// has been called for each item whose box distance `d` from `p`
    /// comes below [`kept`] of the least bound so far (nearer node first,
    /// as [`Self::nearest_from`]): the items skipped have boxes at least
    /// `kept` of the final least bound away.
    pub(crate) fn nearest_items<S: Shape>(
        &self,
        boxes: &[Aabb],
        p: S,
        keep: (f64, f64),
        best: f64,
        mut visit: impl FnMut(u32, f64, f64) -> f64,
    ) -> f64 {
        self.nearest_walk(p, keep, best, |ids, mut best| {
            for &id in ids {
                let Some(b) = boxes.get(id as usize) else {
                    continue;
                };
                let d2 = p.box_dist2(b);
                if d2 < cut2_of(best, keep) {
                    best = visit(id, d2.sqrt(), best);
                }
            }
            best
        })
    }

    /// The least bound after `bucket(items, best)` (the least bound with
    /// those items looked at) for the items of every tree leaf whose node
    /// comes nearer to `p` than [`kept`] of the least bound so far, nearer
    /// node first.
    fn nearest_walk<S: Shape>(
        &self,
        p: S,
        keep: (f64, f64),
        mut best: f64,
        mut bucket: impl FnMut(&[u32], f64) -> f64,
    ) -> f64 {
        let mut cut2 = cut2_of(best, keep);
        let mut stack: Vec<(f64, u32)> = Vec::with_capacity(64);
        if let Some(root) = self.nodes.first() {
            stack.push((p.box_dist2(&root.aabb), 0));
        }
        while let Some((d2, i)) = stack.pop() {
            let Some(node) = self.nodes.get(i as usize).filter(|_| d2 < cut2) else {
                continue;
            };
            if node.leaf {
                let ids = self.order.get(node.a as usize..node.b as usize);
                best = bucket(ids.unwrap_or_default(), best);
                cut2 = cut2_of(best, keep);
                continue;
            }
            let da = self.node_dist2(node.a, p);
            let db = self.node_dist2(node.b, p);
            // The nearer child is popped first.
            let (near, far) = if da <= db {
                ((da, node.a), (db, node.b))
            } else {
                ((db, node.b), (da, node.a))
            };
            stack.extend([far, near].into_iter().filter(|c| c.0 < cut2));
        }
        best
    }

    fn node_dist2<S: Shape>(&self, i: u32, p: S) -> f64 {
        self.nodes
            .get(i as usize)
            .map_or(f64::INFINITY, |n| p.box_dist2(&n.aabb))
    }
}
