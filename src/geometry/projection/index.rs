//! The cold-search hierarchy: near-flat Bezier leaves with oriented boxes
//! under an axis-aligned bounding-box tree, searched best-first.
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::OnceLock;

use super::newton::{Bounds, Foot};
use super::SearchStatus;
use super::{check_query, closest_on_boundary, Projection, ProjectionError, ProjectionOptions};
use crate::geometry::{BezierPatch, NurbsSurface, Trim};
use crate::math::{Point3, Vec2, Vec3};

mod boxes;
mod build;
mod convex;
mod grid;
mod leaf;
mod stack;
#[cfg(test)]
mod tests;
mod warm;

use boxes::{crossed, extent, Shadow};
pub(crate) use leaf::Searched;
use leaf::{Best, Doubt};
use stack::NodeStack;
pub(crate) use warm::{LeafMemo, NoMemo};

/// Search structure for global closest-point queries on one surface.
#[derive(Debug, Clone)]
pub struct ProjectionIndex {
    leaves: Vec<Leaf>,
    nodes: Vec<Node>,
    /// The leaves listed by place, for searches with a tight bound.
    grid: grid::Grid,
    opts: ProjectionOptions,
}

#[derive(Debug, Clone)]
struct Leaf {
    bounds: Bounds,
    obb: Obb,
    /// The axis-aligned box (that of its node in the tree).
    aabb: Aabb,
    /// The Bezier piece (for its certificate).
    patch: BezierPatch,
    /// The certificate that spares a warm search the Newton iteration in
    /// the leaf of its foot, made when first needed.
    convexity: OnceLock<convex::Convexity>,
    /// A 3 x 3 grid of surface points with their parameters.
    samples: [(Vec2, Point3); 9],
}

#[derive(Debug, Clone, Copy)]
struct Obb {
    center: Point3,
    axes: [Vec3; 3],
    half: [f64; 3],
}

/// A convex shape as the separating-axis tests of
/// [`ProjectionIndex::leaf_near`] see it: its points, its edge directions,
/// and its shadows on the world axes, its face normals and their cross
/// products with its edges (the same for every face's index, so made once
/// per shape).
#[derive(Debug, Clone)]
pub struct HullShadows {
    hull: Vec<Point3>,
    edges: Vec<Vec3>,
    /// The world axes' shadows, then the normals', then the crossed axes'.
    fixed: Vec<Shadow>,
    normals: usize,
}

impl HullShadows {
    /// The convex hull of `hull`, a shape with the face normals `normals`
    /// and the edge directions `edges` (unit vectors).
    pub fn new(hull: &[Point3], (normals, edges): (&[Vec3], &[Vec3])) -> HullShadows {
        let world = [Vec3::x(), Vec3::y(), Vec3::z()];
        let mut fixed: Vec<Shadow> = Vec::with_capacity(3 + normals.len() + 3 * edges.len());
        fixed.extend(
            (world.iter().chain(normals).copied())
                .chain(crossed(&world, edges))
                .map(|u| (u, extent(hull, &u))),
        );
        HullShadows {
            hull: hull.to_vec(),
            edges: edges.to_vec(),
            fixed,
            normals: normals.len(),
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct Aabb {
    min: Point3,
    max: Point3,
}

#[derive(Debug, Clone, Copy)]
struct Node {
    aabb: Aabb,
    /// `Ok(leaf)` or `Err((left, right))` child node indices.
    kind: Result<usize, (usize, usize)>,
}

impl ProjectionIndex {
    /// Builds the hierarchy for `surface`.
    pub fn new(surface: &NurbsSurface, opts: &ProjectionOptions) -> ProjectionIndex {
        build::index(surface, opts)
    }

    /// Number of leaves (near-flat pieces) in the hierarchy.
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// The corners of the box round the whole surface (`None` for an
    /// empty index).
    pub fn root_box(&self) -> Option<(Point3, Point3)> {
        self.nodes.last().map(|n| (n.aabb.min, n.aabb.max))
    }

    /// Lower bound of the distance from `p` to the surface, mm.
    pub fn lower_bound(&self, p: Point3) -> f64 {
        self.nodes
            .last()
            .map_or(f64::INFINITY, |n| n.aabb.dist2(p).sqrt())
    }

    /// Lower bound of the distance from `p` to the surface from the leaves'
    /// boxes, mm: the smallest distance from `p` to a leaf's boxes (each
    /// leaf lies inside its axis-aligned and its oriented box, both spanned
    /// by its control points). Far tighter than [`Self::lower_bound`] and
    /// found without any Newton iteration, by a depth-first search over the
    /// tree. A trimmed face lies on its surface, so it bounds the face too.
    pub fn box_distance(&self, p: Point3) -> f64 {
        self.box_distance_near(p, None).0
    }

    /// [`Self::box_distance`] for a point near an earlier query: the leaf
    /// nearest to that one (`hint`, as that query returned it) bounds the
    /// search from the start. The same value for any hint (one that is no
    /// leaf is ignored); also returns the nearest leaf, for the next query.
    pub fn box_distance_near(&self, p: Point3, hint: Option<usize>) -> (f64, Option<usize>) {
        let Some(root) = self.nodes.len().checked_sub(1) else {
            return (f64::INFINITY, None);
        };
        let mut best = (f64::INFINITY, None);
        if let Some(d2) = hint.and_then(|h| self.leaf_box_dist2(h, p)) {
            best = (d2, hint);
        }
        // Depth-first, nearer child first, pruning boxes no nearer than the
        // nearest leaf so far (a median-split tree is shallow).
        let mut stack = NodeStack::new();
        stack.push((self.child_dist2(root, p), root));
        while let Some((d2, i)) = stack.pop() {
            let Some(node) = self.nodes.get(i).filter(|_| d2 < best.0) else {
                continue;
            };
            match node.kind {
                Ok(leaf) => {
                    let obb = self.leaves.get(leaf).map_or(0.0, |l| l.obb.dist2(p));
                    if obb.max(d2) < best.0 {
                        best = (obb.max(d2), Some(i));
                    }
                }
                Err(children) => {
                    let next = self.children_far_near(children, p);
                    (next.into_iter())
                        .filter(|c| c.0 < best.0)
                        .for_each(|c| stack.push(c));
                }
            }
        }
        (best.0.sqrt(), best.1)
    }

    /// The leaf (its index) whose boxes come nearest to `p`, with
    /// [`Self::box_distance`]; `None` for an empty hierarchy.
    pub(crate) fn box_nearest_leaf(&self, p: Point3) -> (f64, Option<usize>) {
        let (d, node) = self.box_distance_near(p, None);
        (d, node.and_then(|i| self.nodes.get(i)?.kind.ok()))
    }

    /// A leaf (its node, as [`Self::box_distance_near`] returns it, for the
    /// next query's `hint`) whose boxes may come within `reach` (mm) of the
    /// convex hull of `shape` (see [`HullShadows::new`]); `hint` is tried
    /// first.
    /// `None` when each leaf is at least `reach` from the shape along an
    /// axis of the separating-axis test (its normals, the boxes' own axes
    /// and their cross products with its edges). A gap along one axis
    /// bounds the distance from below, so a leaf that is farther may still
    /// be returned, never the other way round.
    pub fn leaf_near(&self, shape: &HullShadows, reach: f64, hint: Option<usize>) -> Option<usize> {
        let on_normals = shape.fixed.get(3..3 + shape.normals).unwrap_or_default();
        let near_leaf = |i: usize| -> bool {
            let Some(node) = self.nodes.get(i) else {
                return false;
            };
            let obb = node.kind.ok().and_then(|leaf| self.leaves.get(leaf));
            obb.is_some_and(|l| {
                !node.aabb.separated(&shape.fixed, reach)
                    && !(l.obb).separated(&shape.hull, on_normals, &shape.edges, reach)
            })
        };
        if let Some(h) = hint.filter(|&h| near_leaf(h)) {
            return Some(h);
        }
        // Most faces are cleared by the root box alone, before any stack.
        let root = self.nodes.len().checked_sub(1)?;
        if (self.nodes.get(root)).is_some_and(|n| n.aabb.separated(&shape.fixed, reach)) {
            return None;
        }
        let mut stack = Vec::with_capacity(64);
        stack.push(root);
        while let Some(i) = stack.pop() {
            let Some(node) = self.nodes.get(i) else {
                continue;
            };
            match node.kind {
                Ok(_) if near_leaf(i) => return Some(i),
                Err((a, b)) if !node.aabb.separated(&shape.fixed, reach) => stack.extend([a, b]),
                _ => {}
            }
        }
        None
    }

    /// Squared distance from `p` to the boxes of the leaf at node `i`
    /// (`None` when that is not a leaf).
    fn leaf_box_dist2(&self, i: usize, p: Point3) -> Option<f64> {
        let node = self.nodes.get(i)?;
        let leaf = self.leaves.get(node.kind.ok()?)?;
        Some(leaf.obb.dist2(p).max(node.aabb.dist2(p)))
    }

    /// The two children of a node with their squared box distances from
    /// `p`, the farther first (the order a depth-first stack takes them, so
    /// that the nearer is searched first; the first child on a tie).
    fn children_far_near(&self, (a, b): (usize, usize), p: Point3) -> [(f64, usize); 2] {
        let (da, db) = (self.child_dist2(a, p), self.child_dist2(b, p));
        if da <= db {
            [(db, b), (da, a)]
        } else {
            [(da, a), (db, b)]
        }
    }

    /// Squared distance from `p` to node `i`'s box (infinite for a missing
    /// node).
    fn child_dist2(&self, i: usize, p: Point3) -> f64 {
        self.nodes.get(i).map_or(f64::INFINITY, |n| n.aabb.dist2(p))
    }

    /// Global closest point of `surface` (the one this index was built
    /// for): always the best point found, its
    /// [`status`](Projection::status) unconfirmed when some piece that
    /// could hold a closer point could not be confirmed. An error only for
    /// an invalid query point (see [`super::check_query`]).
    pub fn project(
        &self,
        surface: &NurbsSurface,
        p: Point3,
    ) -> Result<Projection, ProjectionError> {
        self.project_face(surface, None, p)
    }

    /// [`Self::project`] onto the face of `surface` inside `trim` (its
    /// boundary included).
    pub fn project_face(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        p: Point3,
    ) -> Result<Projection, ProjectionError> {
        let searched = self.search_checked(surface, trim, p, f64::INFINITY, None)?;
        let status = searched.status;
        let (_, foot) = searched.found.ok_or(ProjectionError::OutOfRange {
            x: p.x,
            y: p.y,
            z: p.z,
            limit_mm: super::MAX_QUERY_MM,
        })?;
        let mut pr = foot.into_projection(surface, p);
        pr.status = status;
        Ok(pr)
    }

    /// Best-first search; only points closer than `sqrt(best_dist2)` count.
    /// With a trim, only points on the face count, and its boundary is
    /// searched too. Leaf `skip` (which the caller has searched already,
    /// see [`Self::search_leaf`]) is left out. Returns the foot with the
    /// leaf it lies in (`None` for a foot on the trim boundary).
    pub(crate) fn search(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        p: Point3,
        best_dist2: f64,
        skip: Option<usize>,
    ) -> Result<Option<(Option<usize>, Foot)>, ProjectionError> {
        Ok(self
            .search_checked(surface, trim, p, best_dist2, skip)?
            .into_found())
    }

    /// [`Self::search`] with the status of the whole search apart: it is
    /// unconfirmed also when nothing closer was found but a leaf that could
    /// hold a closer point could not be confirmed.
    pub(crate) fn search_checked(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        p: Point3,
        best_dist2: f64,
        skip: Option<usize>,
    ) -> Result<Searched, ProjectionError> {
        let Some((root, mut best)) = self.start(p, best_dist2)? else {
            return Ok(Searched::nothing());
        };
        let mut heap = BinaryHeap::new();
        heap.push(Entry {
            dist2: self.nodes[root].aabb.dist2(p),
            node: root,
        });
        while let Some(Entry { dist2, node }) = heap.pop() {
            if dist2 >= best.dist2 {
                break;
            }
            match self.nodes[node].kind {
                Err((a, b)) => {
                    for child in [a, b] {
                        let d2 = self.nodes[child].aabb.dist2(p);
                        if d2 < best.dist2 {
                            heap.push(Entry {
                                dist2: d2,
                                node: child,
                            });
                        }
                    }
                }
                Ok(leaf) => {
                    self.visit_leaf(surface, trim, leaf, p, skip, &mut best, &mut NoMemo)?
                }
            }
        }
        self.with_boundary(surface, trim, p, best)
    }

    /// [`Self::search`] over the leaves near `p` (from the grid, or depth
    /// first down the tree, nearer child first) instead of best first: no
    /// heap, and as good when `best_dist2` is already tight (a bound from a
    /// nearby foot). The same answer up to exact ties. `memo` spares the
    /// leaves that earlier queries found far enough, and learns from this
    /// one.
    pub(crate) fn search_depth_first(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        (p, best_dist2): (Point3, f64),
        skip: Option<usize>,
        memo: &mut dyn LeafMemo,
    ) -> Result<Option<(Option<usize>, Foot)>, ProjectionError> {
        let Some((_, mut best)) = self.start(p, best_dist2)? else {
            return Ok(None);
        };
        let mut bound2 = best_dist2;
        self.for_leaves_near(p, &mut bound2, |leaf, bound2| {
            self.visit_leaf(surface, trim, leaf, p, skip, &mut best, memo)?;
            *bound2 = best.dist2;
            Ok(())
        })?;
        Ok(self.with_boundary(surface, trim, p, best)?.into_found())
    }

    /// The root node and the empty best of a search for `p` that must beat
    /// `best_dist2`; `None` for an empty hierarchy.
    fn start(&self, p: Point3, best_dist2: f64) -> Result<Option<(usize, Best)>, ProjectionError> {
        check_query(p)?;
        let best = Best::new(best_dist2);
        Ok(self.nodes.len().checked_sub(1).map(|root| (root, best)))
    }

    /// Searches leaf `leaf` (unless it is `skip`) and keeps its foot when
    /// it beats `best`.
    #[allow(clippy::too_many_arguments)]
    fn visit_leaf(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        leaf: usize,
        p: Point3,
        skip: Option<usize>,
        best: &mut Best,
        memo: &mut dyn LeafMemo,
    ) -> Result<(), ProjectionError> {
        if skip == Some(leaf) {
            return Ok(());
        }
        let (better, doubt) = self.leaf_search(surface, trim, leaf, (p, best.dist2), memo)?;
        best.doubt = Doubt::least(best.doubt, doubt);
        if let Some(foot) = better {
            best.dist2 = foot.dist2;
            best.found = Some((Some(leaf), foot));
        }
        Ok(())
    }

    /// The end of a search: with a trim, its boundary is searched too.
    #[inline]
    fn with_boundary(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        p: Point3,
        mut best: Best,
    ) -> Result<Searched, ProjectionError> {
        if let Some(t) = trim {
            if let Some(foot) = closest_on_boundary(surface, t, p, best.dist2, &self.opts)? {
                best.dist2 = foot.dist2;
                best.found = Some((None, foot));
            }
        }
        Ok(best.finish())
    }

    /// The closest point of leaf `leaf` (on the face, with a trim) closer
    /// than `sqrt(best_dist2)`, exactly as the search finds it there; `None`
    /// also for a leaf that does not exist.
    pub(crate) fn search_leaf(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        leaf: usize,
        p: Point3,
        best_dist2: f64,
    ) -> Result<Option<Foot>, ProjectionError> {
        self.search_leaf_with(surface, trim, leaf, (p, best_dist2), &mut NoMemo)
    }

    /// [`Self::search_leaf`], but `None` without a Newton iteration when
    /// `memo` knows the leaf to be far enough; on an untrimmed surface the
    /// least distance of a leaf whose foot is confirmed is noted in `memo`.
    fn search_leaf_with(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        leaf: usize,
        (p, best_dist2): (Point3, f64),
        memo: &mut dyn LeafMemo,
    ) -> Result<Option<Foot>, ProjectionError> {
        Ok(self
            .leaf_search(surface, trim, leaf, (p, best_dist2), memo)?
            .0)
    }
}

impl Leaf {
    /// The leaf's certificate (made on first use).
    fn convexity(&self) -> &convex::Convexity {
        self.convexity
            .get_or_init(|| convex::Convexity::of(&self.patch, &self.obb))
    }

    /// The parameters of the sample nearest to `p` (the first on a tie)
    /// and its squared distance.
    fn nearest_sample(&self, p: Point3) -> (Vec2, f64) {
        let dist2 = |s: &(Vec2, Point3)| (s.1 - p).norm_squared();
        (self.samples.iter())
            .min_by(|a, b| dist2(a).total_cmp(&dist2(b)))
            .map_or((self.bounds.lo, f64::INFINITY), |s| (s.0, dist2(s)))
    }
}

/// Heap entry ordered by smallest distance first.
struct Entry {
    dist2: f64,
    node: usize,
}
impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.dist2.total_cmp(&self.dist2)
    }
}
