//! A box tree over a trim's chords: the boundary segments near a point,
//! nearest boxes first, without a look at every segment (a face with many
//! holes has thousands).
use super::trim::Chord;
use crate::math::{Point3, Vec3};

/// Most chords in one leaf of the tree.
const BUCKET: usize = 4;

#[derive(Debug, Clone, PartialEq)]
struct Node {
    lo: Point3,
    hi: Point3,
    /// A leaf's range of [`ChordTree::order`], or the two children.
    kind: Kind,
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Chords(std::ops::Range<usize>),
    Split(usize, usize),
}

/// The tree (the root last).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ChordTree {
    nodes: Vec<Node>,
    order: Vec<usize>,
}

/// The box round a chord and its bulge allowance: the edge's image lies
/// in it, and its distance from a point bounds the chord's
/// [`Chord::lower_bound2`] from below.
fn chord_box(c: &Chord) -> (Point3, Point3) {
    let grow = Vec3::repeat(c.bulge);
    (c.pa.inf(&c.pb) - grow, c.pa.sup(&c.pb) + grow)
}

fn dist2((lo, hi): (Point3, Point3), p: Point3) -> f64 {
    (0..3)
        .map(|k| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0).powi(2))
        .sum()
}

impl ChordTree {
    /// The tree over `chords`.
    pub(crate) fn new(chords: &[Chord]) -> ChordTree {
        let boxes: Vec<(Point3, Point3)> = chords.iter().map(chord_box).collect();
        let mut order: Vec<usize> = (0..chords.len()).collect();
        let mut tree = ChordTree {
            nodes: Vec::new(),
            order: Vec::new(),
        };
        if !order.is_empty() {
            let len = order.len();
            tree.build(&boxes, &mut order, 0..len);
        }
        tree.order = order;
        tree
    }

    fn build(
        &mut self,
        boxes: &[(Point3, Point3)],
        order: &mut [usize],
        range: std::ops::Range<usize>,
    ) -> usize {
        let of = |i: &usize| boxes.get(*i).copied();
        let ids = order.get(range.clone()).unwrap_or_default();
        let far = Point3::from(Vec3::repeat(f64::INFINITY));
        let (lo, hi) =
            (ids.iter().filter_map(of)).fold((far, -far), |(l, h), (a, b)| (l.inf(&a), h.sup(&b)));
        let kind = if range.len() <= BUCKET {
            Kind::Chords(range)
        } else {
            let axis = (hi - lo).imax();
            let centre = |i: &usize| of(i).map_or(0.0, |(a, b)| a[axis] + b[axis]);
            let mid = range.len() / 2;
            if let Some(part) = order.get_mut(range.clone()) {
                part.select_nth_unstable_by(mid, |x, y| centre(x).total_cmp(&centre(y)));
            }
            let left = self.build(boxes, order, range.start..range.start + mid);
            let right = self.build(boxes, order, range.start + mid..range.end);
            Kind::Split(left, right)
        };
        self.nodes.push(Node { lo, hi, kind });
        self.nodes.len() - 1
    }

    /// Calls `look(i)` for chord `i` of `chords` (the chords the tree was
    /// built over) whenever its [`Chord::lower_bound2`] from `p` is below
    /// the bound, nearer boxes first; `look` returns a new bound (a squared
    /// distance) when it found a closer point. Returns the last bound.
    pub(crate) fn search(
        &self,
        chords: &[Chord],
        p: Point3,
        mut bound: f64,
        mut look: impl FnMut(usize) -> Option<f64>,
    ) -> f64 {
        let mut stack: Vec<(f64, usize)> = Vec::with_capacity(32);
        stack.extend(self.nodes.len().checked_sub(1).map(|root| (0.0, root)));
        while let Some((d2, i)) = stack.pop() {
            let Some(node) = self.nodes.get(i).filter(|_| d2 < bound) else {
                continue;
            };
            match &node.kind {
                Kind::Split(l, r) => {
                    let near = |c: usize| {
                        self.nodes
                            .get(c)
                            .map_or(f64::INFINITY, |n| dist2((n.lo, n.hi), p))
                    };
                    let (dl, dr) = (near(*l), near(*r));
                    // The nearer child is looked at first (pushed last).
                    let pair = if dl <= dr {
                        [(dr, *r), (dl, *l)]
                    } else {
                        [(dl, *l), (dr, *r)]
                    };
                    stack.extend(pair.into_iter().filter(|c| c.0 < bound));
                }
                Kind::Chords(range) => {
                    for &k in self.order.get(range.clone()).unwrap_or_default() {
                        let near = chords.get(k).is_some_and(|c| c.lower_bound2(p) < bound);
                        if near {
                            bound = look(k).map_or(bound, |b| bound.min(b));
                        }
                    }
                }
            }
        }
        bound
    }
}
