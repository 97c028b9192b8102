//! The list of leaves near the ball and their order by bound at a query
//! point, found lazily: a query looks at the few leaves its search reaches,
//! not at every listed one.
//!
//! The list holds every leaf whose bound at the listing point `a` is below
//! the listing radius, sorted by that bound. A leaf's bound is 1-Lipschitz
//! in the point (the larger of two distances), so at `y` it is at least its
//! bound at `a` less `|y - a|`: a leaf further down the list than the best
//! bound found so far, by that shift, cannot come before it. The order a
//! query gets is the same as sorting every listed leaf's bound at `y`
//! (ties by leaf number).
use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::index::LeafSource;
use crate::math::Point3;

/// Added to the shift for the rounding of the bounds, mm: a leaf is looked
/// at when its listed bound less the shift comes within this of the
/// threshold (looking at one more leaf never changes the order).
const BOUND_ROUNDING_MM: f64 = 1e-9;

/// Lists up to this long are ordered by sorting all their bounds at the
/// query point (cheaper than a heap for the few leaves a list mostly
/// holds; the order is the same).
const SORTED_MAX: usize = 24;

/// A longer list is sorted only this far when it is made (its least
/// entries, chosen by selection in linear time); the rest is sorted the
/// first time a query walks past them. Near a part of many small faces (a
/// fillet cut into tiny pieces) a list holds thousands of leaves while a
/// query looks at a few dozen: sorting them all cost more than the
/// queries.
const SORTED_PREFIX: usize = 48;

/// The order of `(bound, leaf)` pairs: bound first, ties by leaf number.
pub(super) fn by_bound(a: &(f64, u32), b: &(f64, u32)) -> Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

/// A leaf's bound at the query point and its number, least first in a
/// [`BinaryHeap`].
#[derive(Debug, Clone, Copy)]
struct Ranked(f64, u32);

impl Ord for Ranked {
    fn cmp(&self, other: &Self) -> Ordering {
        by_bound(&(other.0, other.1), &(self.0, self.1))
    }
}

impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Ranked {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Ranked {}

/// The near leaves of one stream of queries (see the module docs).
#[derive(Debug, Clone, Default)]
pub(super) struct NearList {
    /// Where the list was made and the radius it was made within, mm.
    at: Option<(Point3, f64)>,
    /// `(bound at the listing point, leaf)`, least first up to
    /// `sorted_upto`; every later entry comes after those.
    entries: Vec<(f64, u32)>,
    sorted_upto: usize,
    /// The current query: its point, the shift from the listing point,
    /// the bound a leaf must be under, the leaf it skips, the next entry
    /// not looked at, and the looked-at leaves not yet taken.
    y: Point3,
    shift: f64,
    cap: f64,
    skip: Option<u32>,
    next: usize,
    heap: BinaryHeap<Ranked>,
    /// A short list's bounds at the query point, sorted, and how many of
    /// them were taken.
    sorted: Vec<(f64, u32)>,
    taken: usize,
}

impl NearList {
    /// Number of leaves listed.
    pub(super) fn len(&self) -> usize {
        self.entries.len()
    }

    /// Forgets the list.
    pub(super) fn clear(&mut self) {
        self.at = None;
    }

    /// The listing radius less the distance of `y` from the listing point,
    /// mm: the list holds every leaf whose bound at `y` is below it (`None`
    /// before a list is made).
    pub(super) fn margin_at(&self, y: Point3) -> Option<f64> {
        self.at.map(|(a, listed)| listed - (y - a).norm())
    }

    /// Lists the leaves whose bound at `y` is below `listed` (mm), which
    /// `fill` appends with their bounds; `false` when there is none.
    pub(super) fn list(
        &mut self,
        y: Point3,
        listed: f64,
        fill: impl FnOnce(&mut Vec<(f64, u32)>),
    ) -> bool {
        self.entries.clear();
        fill(&mut self.entries);
        if self.entries.len() > SORTED_PREFIX {
            let k = SORTED_PREFIX - 1;
            self.entries.select_nth_unstable_by(k, by_bound);
            self.entries[..k].sort_unstable_by(by_bound);
            self.sorted_upto = SORTED_PREFIX;
        } else {
            self.entries.sort_unstable_by(by_bound);
            self.sorted_upto = self.entries.len();
        }
        self.at = Some((y, listed));
        !self.entries.is_empty()
    }

    /// Whether `leaf` is on the list: its bound at the listing point, made
    /// as the listing made it (the same bits), is looked up in the sorted
    /// entries.
    pub(super) fn holds<L: LeafSource + ?Sized>(&self, leaves: &L, leaf: u32) -> bool {
        let (Some((a, _)), Some(l)) = (self.at, leaves.leaf(leaf)) else {
            return false;
        };
        let key = (l.lower_bound(a), leaf);
        let (sorted, rest) = self
            .entries
            .split_at(self.sorted_upto.min(self.entries.len()));
        sorted.binary_search_by(|e| by_bound(e, &key)).is_ok()
            || rest.iter().any(|e| by_bound(e, &key).is_eq())
    }

    /// Starts a query at `y` for the leaves whose bound is below `cap`
    /// (mm), leaving out `skip`.
    pub(super) fn start<L: LeafSource + ?Sized>(
        &mut self,
        leaves: &L,
        y: Point3,
        cap: f64,
        skip: Option<u32>,
    ) {
        self.y = y;
        self.shift = self.at.map_or(0.0, |(a, _)| (y - a).norm()) + BOUND_ROUNDING_MM;
        self.cap = cap;
        self.skip = skip;
        self.next = 0;
        self.heap.clear();
        self.sorted.clear();
        self.taken = 0;
        if self.entries.len() <= SORTED_MAX {
            self.next = self.entries.len();
            self.sort_all(leaves);
        }
    }

    /// Every listed leaf's bound below the cap into `sorted`, in order.
    fn sort_all<L: LeafSource + ?Sized>(&mut self, leaves: &L) {
        let mut sorted = std::mem::take(&mut self.sorted);
        sorted.extend(
            (self.entries.iter())
                .filter_map(|&(_, id)| self.bound_below_cap(leaves, id).map(|b| (b, id))),
        );
        sorted.sort_unstable_by(by_bound);
        self.sorted = sorted;
    }

    /// The listed leaf with the least bound at the query point below the
    /// cap and its bound, not taken yet (least leaf number among equal
    /// bounds); `None` when none is left.
    pub(super) fn pop<L: LeafSource + ?Sized>(&mut self, leaves: &L) -> Option<(f64, u32)> {
        if let Some(&e) = self.sorted.get(self.taken) {
            self.taken += 1;
            return Some(e);
        }
        // The threshold falls as leaves come in: a listed leaf whose bound
        // here cannot come under the least one looked at stays unlooked.
        loop {
            self.sort_through(self.next);
            let Some(&(listed, id)) = self.entries.get(self.next) else {
                break;
            };
            let threshold = self.heap.peek().map_or(self.cap, |r| r.0.min(self.cap));
            if listed - self.shift > threshold {
                break;
            }
            self.next += 1;
            if let Some(b) = self.bound_below_cap(leaves, id) {
                self.heap.push(Ranked(b, id));
            }
        }
        self.heap.pop().map(|Ranked(b, id)| (b, id))
    }

    /// Sorts the entries on from `sorted_upto` as far as entry `k`, in
    /// steps that double the sorted part (each step selects its entries
    /// from the rest in linear time).
    fn sort_through(&mut self, k: usize) {
        let len = self.entries.len();
        while k >= self.sorted_upto && self.sorted_upto < len {
            let from = self.sorted_upto;
            let end = from + from.max(SORTED_PREFIX);
            let rest = &mut self.entries[from..];
            if end < len {
                let nth = end - from - 1;
                rest.select_nth_unstable_by(nth, by_bound);
                rest[..nth].sort_unstable_by(by_bound);
                self.sorted_upto = end;
            } else {
                rest.sort_unstable_by(by_bound);
                self.sorted_upto = len;
            }
        }
    }

    /// The bound at the query point of `id` when it is below the cap and
    /// `id` is not the leaf left out.
    fn bound_below_cap<L: LeafSource + ?Sized>(&self, leaves: &L, id: u32) -> Option<f64> {
        let leaf = leaves.leaf(id).filter(|_| self.skip != Some(id))?;
        Some(leaf.lower_bound(self.y)).filter(|&b| b < self.cap)
    }
}

#[cfg(test)]
mod tests {
    use super::super::leaves::{Leaf, LeafOptions, Leaves, Pieces};
    use super::super::refit_tests::{flange, machined};
    use super::super::tree::LeafTree;
    use super::*;
    use crate::math::Vec3;
    use rand::{RngExt, SeedableRng};

    /// Every leaf's bound at `y` below `cap`, sorted (ties by leaf),
    /// without `skip`, looking at each: what the lazy order must give.
    fn sorted(leaves: &[Leaf], y: Point3, cap: f64, skip: Option<u32>) -> Vec<(f64, u32)> {
        let mut all: Vec<(f64, u32)> = (0..leaves.len() as u32)
            .filter(|&id| Some(id) != skip)
            .map(|id| (leaves[id as usize].lower_bound(y), id))
            .filter(|e| e.0 < cap)
            .collect();
        all.sort_unstable_by(by_bound);
        all
    }

    /// The machined flange's leaves and their tree.
    fn flange_leaves() -> (Vec<Leaf>, LeafTree) {
        let wp = flange();
        let pieces = Pieces::new(&wp, &LeafOptions::default());
        let leaves = Leaves::of(&pieces, &machined(&wp)).leaves;
        let tree = pieces.tree.refit(&leaves);
        (leaves, tree)
    }

    /// The first leaf of a long list is found looking at the few leaves
    /// whose listed bound, less the shift, comes under the least bound
    /// found so far, not at every leaf under the cap.
    #[test]
    fn the_first_leaf_is_found_looking_at_few() {
        let (leaves, tree) = flange_leaves();
        let mut list = NearList::default();
        let (mut lists, mut looked, mut listed) = (0, 0, 0);
        for k in 0..40 {
            let leaf = &leaves[(k * 37) % leaves.len()];
            let a = leaf.aabb.min + (leaf.aabb.max - leaf.aabb.min) * 0.5;
            let radius = 8.0;
            list.list(a, radius, |out| tree.within_bounds(&leaves, a, radius, out));
            if list.entries.len() <= SORTED_MAX {
                continue;
            }
            let y = a + Vec3::new(0.01, -0.02, 0.015);
            let want = sorted(&leaves, y, radius - 0.03, None);
            list.start(&leaves[..], y, radius - 0.03, None);
            assert_eq!(list.pop(&leaves[..]), want.first().copied(), "query {k}");
            (lists, looked, listed) = (lists + 1, looked + list.next, listed + want.len());
        }
        assert!(lists > 10, "{lists} long lists");
        assert!(looked * 10 < listed, "looked at {looked} of {listed}");
    }

    /// Queries at points moved up to the list's slack from where it was
    /// made get every listed leaf below the cap in order of its bound at the
    /// query point, as sorting them all does; and the list holds exactly
    /// the leaves whose bound at its point is below its radius.
    #[test]
    fn the_lazy_order_is_the_sorted_order() {
        let (leaves, tree) = flange_leaves();
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(11);
        let mut unit =
            || Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - Vec3::repeat(1.0);
        let mut list = NearList::default();
        let (mut checked, mut taken, mut short) = (0, 0, 0);
        for k in 0..300 {
            // Points near the surface: a leaf's sample moved by up to 1 mm.
            let leaf = &leaves[(k * 37) % leaves.len()];
            let a = leaf.aabb.min + (leaf.aabb.max - leaf.aabb.min) * 0.5 + unit();
            let listed = 1.0 + (k % 4) as f64;
            list.list(a, listed, |out| tree.within_bounds(&leaves, a, listed, out));
            for (id, l) in leaves.iter().enumerate() {
                assert_eq!(
                    list.holds(&leaves[..], id as u32),
                    l.lower_bound(a) < listed,
                    "leaf {id}"
                );
            }
            for j in 0..4 {
                let y = a + unit() * (0.1 * j as f64);
                let cap = list.margin_at(y).unwrap_or(0.0);
                let skip = list.entries.get(j).map(|e| e.1).filter(|_| j % 2 == 1);
                let want = sorted(&leaves, y, cap, skip);
                list.start(&leaves[..], y, cap, skip);
                let mut got = Vec::new();
                while let Some(e) = list.pop(&leaves[..]) {
                    got.push(e);
                    // Stop early now and then: what came before is right.
                    if got.len() == 3 && j == 2 {
                        break;
                    }
                }
                assert_eq!(got[..], want[..got.len()], "query {k}.{j}");
                if j != 2 {
                    assert_eq!(got.len(), want.len());
                }
                checked += 1;
                taken += got.len();
                short += usize::from(list.entries.len() <= SORTED_MAX);
            }
        }
        assert!(checked == 1200 && taken > 2000, "{taken}");
        // Both ways of ordering were tried.
        assert!(short > 200 && short < 1000, "{short} short lists");
    }
}
