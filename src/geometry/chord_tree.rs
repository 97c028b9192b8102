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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec2;
    use rand::{RngExt, SeedableRng};

    /// A closed polyline of chords round a wavy loop, with bulges.
    fn chords(n: usize) -> Vec<Chord> {
        let at = |k: usize| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            let r = 20.0 + 3.0 * (5.0 * t).sin();
            Point3::new(r * t.cos(), r * t.sin(), 2.0 * (3.0 * t).cos())
        };
        (0..n)
            .map(|k| Chord {
                a: Vec2::new(k as f64, 0.0),
                b: Vec2::new(k as f64 + 1.0, 0.0),
                pa: at(k),
                pb: at(k + 1),
                bulge: 0.01 * (k % 5) as f64,
            })
            .collect()
    }

    /// The chords looked at are those whose bound is below the running
    /// bound, and the least found is the least over every chord.
    #[test]
    fn search_finds_what_a_look_at_every_chord_finds() {
        let chords = chords(500);
        let tree = ChordTree::new(&chords);
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(3);
        for _ in 0..300 {
            let p = Point3::new(
                rng.random_range(-30.0..30.0),
                rng.random_range(-30.0..30.0),
                rng.random_range(-5.0..5.0),
            );
            // A value per chord at least its bound: the distance to its
            // end `pa`.
            let value = |c: &Chord| (c.pa - p).norm_squared();
            let least = chords.iter().map(value).fold(f64::INFINITY, f64::min);
            let mut looked = Vec::new();
            let got = tree.search(&chords, p, f64::INFINITY, |i| {
                looked.push(i);
                chords.get(i).map(value)
            });
            assert_eq!(got, least);
            assert!(looked.len() < chords.len() / 4, "{}", looked.len());
            // Within a fixed bound, every chord below it is looked at.
            let bound = 25.0;
            let mut seen = Vec::new();
            tree.search(&chords, p, bound, |i| {
                seen.push(i);
                None
            });
            seen.sort_unstable();
            let all: Vec<usize> = (0..chords.len())
                .filter(|&i| chords[i].lower_bound2(p) < bound)
                .collect();
            assert_eq!(seen, all);
        }
    }
}
