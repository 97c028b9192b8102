//! The faces' boxes in one tree: the faces whose box comes within a
//! distance of a point, found without a look at every face (a part of a
//! few hundred faces is queried thousands of times per measured feature).
use crate::math::Point3;

/// Most faces in one leaf of the tree.
const LEAF_FACES: usize = 4;

/// A face's box: min x, y, z, then max x, y, z (NaN for a face without
/// one).
pub(crate) type FaceBox = [f64; 6];

/// The distance from `p` to the box `b`, mm; zero (no bound) for a box
/// with NaN corners (`max` passes over a NaN gap).
#[inline(always)]
pub(crate) fn box_distance(b: &FaceBox, p: Point3) -> f64 {
    let gap = |k: usize| (b[k] - p[k]).max(p[k] - b[k + 3]).max(0.0);
    (gap(0).powi(2) + gap(1).powi(2) + gap(2).powi(2)).sqrt()
}

/// One node: its box (the union of its faces' boxes) and either a range
/// of [`FaceTree::order`] or two children.
#[derive(Debug, Clone, PartialEq)]
struct Node {
    aabb: FaceBox,
    kind: Kind,
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Faces(std::ops::Range<usize>),
    Split(usize, usize),
}

/// A bounding-volume tree over the faces' boxes (median splits along the
/// longest extent of the boxes' centres).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FaceTree {
    nodes: Vec<Node>,
    /// Face indices, grouped by leaf.
    order: Vec<usize>,
    /// The faces without a box: near every point.
    unboxed: Vec<usize>,
    /// Every face's box, by face index.
    boxes: Vec<FaceBox>,
}

impl FaceTree {
    /// The tree of `boxes` (face `i` has `boxes[i]`); faces without a box
    /// (NaN corners) are kept apart and count as near every point.
    pub(crate) fn new(boxes: &[FaceBox]) -> FaceTree {
        let boxed = |i: &usize| boxes.get(*i).is_some_and(|b| b.iter().all(|x| !x.is_nan()));
        let (mut order, unboxed): (Vec<usize>, Vec<usize>) = (0..boxes.len()).partition(boxed);
        let mut tree = FaceTree {
            nodes: Vec::new(),
            order: Vec::new(),
            unboxed,
            boxes: boxes.to_vec(),
        };
        if !order.is_empty() {
            let len = order.len();
            tree.build(boxes, &mut order, 0..len);
        }
        tree.order = order;
        tree
    }

    /// Builds the node of `order[range]`; returns its index (children
    /// come before their parent, the root last).
    fn build(
        &mut self,
        boxes: &[FaceBox],
        order: &mut [usize],
        range: std::ops::Range<usize>,
    ) -> usize {
        let aabb = union(boxes, order.get(range.clone()).unwrap_or(&[]));
        let kind = if range.len() <= LEAF_FACES {
            Kind::Faces(range)
        } else {
            let mid = range.start + range.len() / 2;
            if let Some(part) = order.get_mut(range.clone()) {
                sort_along_longest(boxes, part);
            }
            let left = self.build(boxes, order, range.start..mid);
            let right = self.build(boxes, order, mid..range.end);
            Kind::Split(left, right)
        };
        self.nodes.push(Node { aabb, kind });
        self.nodes.len() - 1
    }

    /// Puts into `out`, in ascending order, every face whose box lies no
    /// farther than `d` (mm) from `p` (by [`box_distance`]; every face
    /// without a box); every face when `d` is not finite.
    pub(crate) fn within(&self, p: Point3, d: f64, out: &mut Vec<usize>) {
        out.clear();
        if !d.is_finite() {
            out.extend(0..self.boxes.len());
            return;
        }
        out.extend(self.unboxed.iter().filter(|_| d >= 0.0));
        if let Some(root) = self.nodes.len().checked_sub(1) {
            self.within_node(root, p, d, out);
        }
        out.sort_unstable();
    }

    /// Puts into `out`, in ascending order, every face whose box meets the
    /// box from `lo` to `hi` (touching counts; a face without a box never
    /// does).
    pub(crate) fn overlapping(&self, lo: Point3, hi: Point3, out: &mut Vec<usize>) {
        out.clear();
        if let Some(root) = self.nodes.len().checked_sub(1) {
            self.overlapping_node(root, (lo, hi), out);
        }
        out.sort_unstable();
    }

    /// The least of `best` and `value(face, box distance)` over the faces
    /// whose box comes nearer to `p` than the least so far (nearer boxes
    /// first); `value` (at least the box distance, or `None` to leave the
    /// face out) is asked of no face whose box keeps that least away.
    pub(crate) fn nearest(
        &self,
        p: Point3,
        mut best: f64,
        mut value: impl FnMut(usize, f64) -> Option<f64>,
    ) -> f64 {
        for &f in &self.unboxed {
            best = value(f, 0.0).map_or(best, |v| best.min(v));
        }
        let mut stack: Vec<(f64, usize)> = Vec::with_capacity(32);
        if let Some(root) = self.nodes.len().checked_sub(1) {
            stack.push((0.0, root));
        }
        while let Some((d, i)) = stack.pop() {
            let Some(node) = self.nodes.get(i).filter(|_| d < best) else {
                continue;
            };
            match &node.kind {
                Kind::Split(l, r) => {
                    let dist = |c: usize| {
                        self.nodes
                            .get(c)
                            .map_or(f64::INFINITY, |n| box_distance(&n.aabb, p))
                    };
                    let (dl, dr) = (dist(*l), dist(*r));
                    // The nearer child is looked at first (pushed last).
                    if dl <= dr {
                        stack.extend([(dr, *r), (dl, *l)]);
                    } else {
                        stack.extend([(dl, *l), (dr, *r)]);
                    }
                }
                Kind::Faces(range) => {
                    for &f in self.order.get(range.clone()).unwrap_or(&[]) {
                        let root = self.distance(f, p);
                        if root < best {
                            best = value(f, root).map_or(best, |v| best.min(v));
                        }
                    }
                }
            }
        }
        best
    }

    /// The faces of node `i`'s subtree whose box lies no farther than `d`
    /// from `p`, into `out` (in tree order). Recursive: the median splits
    /// keep the depth at the logarithm of the number of faces, and a
    /// query needs no stack of its own on the heap.
    fn within_node(&self, i: usize, p: Point3, d: f64, out: &mut Vec<usize>) {
        let Some(node) = self.nodes.get(i) else {
            return;
        };
        // A node's box holds its faces' boxes, so it is no farther.
        if box_distance(&node.aabb, p) > d {
            return;
        }
        match &node.kind {
            Kind::Split(l, r) => {
                self.within_node(*l, p, d, out);
                self.within_node(*r, p, d, out);
            }
            Kind::Faces(range) => out.extend(
                (self.order.get(range.clone()).unwrap_or(&[]).iter())
                    .filter(|&&f| self.face_within(f, p, d)),
            ),
        }
    }

    /// The faces of node `i`'s subtree whose box meets the box from `lo`
    /// to `hi`, into `out` (in tree order; recursive as
    /// [`Self::within_node`]).
    fn overlapping_node(&self, i: usize, (lo, hi): (Point3, Point3), out: &mut Vec<usize>) {
        let meets = |b: &FaceBox| (0..3).all(|k| b[k] <= hi[k] && b[k + 3] >= lo[k]);
        let Some(node) = self.nodes.get(i).filter(|n| meets(&n.aabb)) else {
            return;
        };
        match &node.kind {
            Kind::Split(l, r) => {
                self.overlapping_node(*l, (lo, hi), out);
                self.overlapping_node(*r, (lo, hi), out);
            }
            Kind::Faces(range) => out.extend(
                (self.order.get(range.clone()).unwrap_or(&[]).iter())
                    .filter(|&&f| self.boxes.get(f).is_some_and(meets)),
            ),
        }
    }

    fn face_within(&self, f: usize, p: Point3, d: f64) -> bool {
        self.distance(f, p) <= d
    }

    /// The distance from `p` to face `f`'s box, mm (infinite for no such
    /// face, zero for one without a box).
    #[inline(always)]
    pub(crate) fn distance(&self, f: usize, p: Point3) -> f64 {
        self.boxes
            .get(f)
            .map_or(f64::INFINITY, |b| box_distance(b, p))
    }
}

/// The smallest box holding the boxes of `faces`.
fn union(boxes: &[FaceBox], faces: &[usize]) -> FaceBox {
    let mut u = [
        f64::INFINITY,
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for b in faces.iter().filter_map(|&f| boxes.get(f)) {
        for k in 0..3 {
            u[k] = u[k].min(b[k]);
            u[k + 3] = u[k + 3].max(b[k + 3]);
        }
    }
    u
}

/// Sorts `faces` by their boxes' centres along the axis where the centres
/// spread most.
fn sort_along_longest(boxes: &[FaceBox], faces: &mut [usize]) {
    let centre = |f: usize, k: usize| boxes.get(f).map_or(0.0, |b| b[k] + b[k + 3]);
    let spread = |k: usize| {
        let (lo, hi) = faces
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &f| {
                (l.min(centre(f, k)), h.max(centre(f, k)))
            });
        hi - lo
    };
    let axis = (0..3)
        .max_by(|&a, &b| spread(a).total_cmp(&spread(b)))
        .unwrap_or(0);
    faces.sort_by(|&a, &b| centre(a, axis).total_cmp(&centre(b, axis)).then(a.cmp(&b)));
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// Random boxes (some without corners) and points about them.
    fn scene(seed: u64) -> (Vec<FaceBox>, Vec<Point3>) {
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(seed);
        let mut r = move |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
        let boxes = (0..150)
            .map(|i| {
                if i % 37 == 5 {
                    return [f64::NAN; 6];
                }
                let (x, y, z) = (r(-100.0, 100.0), r(-100.0, 100.0), r(-20.0, 20.0));
                let (w, h, d) = (r(0.0, 30.0), r(0.0, 30.0), r(0.0, 5.0));
                [x, y, z, x + w, y + h, z + d]
            })
            .collect();
        let points = (0..300)
            .map(|_| Point3::new(r(-120.0, 140.0), r(-120.0, 140.0), r(-40.0, 40.0)))
            .collect();
        (boxes, points)
    }

    /// The faces within a distance, the faces meeting a box and the
    /// nearest box are those a look at every face finds.
    #[test]
    fn queries_match_a_look_at_every_face() {
        let (boxes, points) = scene(11);
        let tree = FaceTree::new(&boxes);
        let mut got = Vec::new();
        let mut found = 0;
        for (k, &p) in points.iter().enumerate() {
            let d = [0.0, 0.5, 3.0, 10.0, 40.0][k % 5];
            tree.within(p, d, &mut got);
            let all: Vec<usize> = (0..boxes.len())
                .filter(|&i| box_distance(&boxes[i], p) <= d)
                .collect();
            assert_eq!(got, all, "{p:?} within {d}");
            found += got.len();
            let (lo, hi) = (p - Vector3::repeat(d), p + Vector3::repeat(2.0 * d));
            tree.overlapping(lo, hi, &mut got);
            let meets = |b: &FaceBox| (0..3).all(|k| b[k] <= hi[k] && b[k + 3] >= lo[k]);
            let all: Vec<usize> = (0..boxes.len()).filter(|&i| meets(&boxes[i])).collect();
            assert_eq!(got, all, "{p:?} meeting {lo:?}..{hi:?}");
            let least = (boxes.iter())
                .map(|b| box_distance(b, p))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(tree.nearest(p, f64::INFINITY, |_, root| Some(root)), least);
            // Faces left out do not count.
            let odd = (0..boxes.len())
                .filter(|i| i % 2 == 1)
                .map(|i| box_distance(&boxes[i], p))
                .fold(f64::INFINITY, f64::min);
            let got_odd = tree.nearest(p, f64::INFINITY, |f, root| (f % 2 == 1).then_some(root));
            assert_eq!(got_odd, odd);
        }
        assert!(found > 500, "{found}");
        tree.within(Point3::origin(), f64::INFINITY, &mut got);
        assert_eq!(got, (0..boxes.len()).collect::<Vec<_>>());
    }

    use nalgebra::Vector3;
}
