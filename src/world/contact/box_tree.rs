//! A small tree over a few dozen boxes (a crossed leaf's trimmed boxes):
//! the least segment distance to them without looking at every box.
use super::leaves::Aabb;
use super::shapes::{segment_box, Segment};
use super::tree::{Node, BUCKET};

/// Boxes ordered into a binary tree by median splits of their centres (a
/// leaf node's range is one of [`BoxTree::boxes`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BoxTree {
    nodes: Vec<Node>,
    boxes: Vec<Aabb>,
}

impl BoxTree {
    /// The tree over `boxes`.
    pub(crate) fn new(boxes: Vec<Aabb>) -> BoxTree {
        let mut t = BoxTree {
            nodes: Vec::with_capacity(boxes.len() / 2 + 1),
            boxes,
        };
        if !t.boxes.is_empty() {
            t.build(0, t.boxes.len());
        }
        t
    }

    /// The box holding every box (empty for none).
    pub(crate) fn bounds(&self) -> Aabb {
        self.nodes.first().map_or_else(Aabb::empty, |n| n.aabb)
    }

    /// Builds the node over `boxes[lo..hi]`; returns its index.
    fn build(&mut self, lo: usize, hi: usize) -> u32 {
        let at = self.nodes.len() as u32;
        let slice = self.boxes.get_mut(lo..hi).unwrap_or_default();
        let aabb = slice.iter().fold(Aabb::empty(), |u, b| u.union(b));
        self.nodes.push(Node {
            aabb,
            a: lo as u32,
            b: hi as u32,
            leaf: true,
        });
        if hi - lo <= BUCKET {
            return at;
        }
        let axis = (aabb.max - aabb.min).imax();
        let centre = |b: &Aabb| b.min[axis] + b.max[axis];
        let mid = (lo + hi) / 2;
        slice.select_nth_unstable_by(mid - lo, |x, y| centre(x).total_cmp(&centre(y)));
        let left = self.build(lo, mid);
        let right = self.build(mid, hi);
        if let Some(n) = self.nodes.get_mut(at as usize) {
            (n.a, n.b, n.leaf) = (left, right, false);
        }
        at
    }

    /// The least distance from `seg` to the boxes (infinite for none),
    /// or zero as soon as a box comes nearer than `need` (mm).
    pub(crate) fn least_distance(&self, seg: Segment, need: f64) -> f64 {
        let need2 = need * need;
        let mut best2 = f64::INFINITY;
        // Median splits keep the depth below 64 for any number of boxes,
        // and the stack holds one entry a level beyond the top one: no
        // allocation on the check's hot path.
        let mut stack = [(0.0, 0u32); 64];
        let mut len = 0usize;
        if let Some(root) = self.nodes.first() {
            stack[0] = (segment_box(seg.a, seg.b, &root.aabb).0, 0);
            len = 1;
        }
        while let Some(&(d2, i)) = len.checked_sub(1).and_then(|top| stack.get(top)) {
            len -= 1;
            let Some(node) = self.nodes.get(i as usize).filter(|_| d2 < best2) else {
                continue;
            };
            if node.leaf {
                let boxes = self.boxes.get(node.a as usize..node.b as usize);
                for b in boxes.unwrap_or_default() {
                    let d2 = segment_box(seg.a, seg.b, b).0;
                    if d2 < need2 {
                        return 0.0;
                    }
                    best2 = best2.min(d2);
                }
                continue;
            }
            let child = |c: u32| {
                let d2 = self
                    .nodes
                    .get(c as usize)
                    .map_or(f64::INFINITY, |n| segment_box(seg.a, seg.b, &n.aabb).0);
                (d2, c)
            };
            let (x, y) = (child(node.a), child(node.b));
            // The nearer child is popped first.
            let (near, far) = if x.0 <= y.0 { (x, y) } else { (y, x) };
            for c in [far, near].into_iter().filter(|c| c.0 < best2) {
                if let Some(slot) = stack.get_mut(len) {
                    *slot = c;
                    len += 1;
                }
            }
        }
        best2.sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;

    /// Against every box in turn, on a grid of boxes and segments through
    /// and beside it (seeded, reproducible).
    #[test]
    fn least_distance_is_the_least_over_every_box() {
        let mut boxes = Vec::new();
        for i in 0..7 {
            for j in 0..5 {
                let (x, y) = (i as f64 * 0.7, j as f64 * 0.45 + 0.05 * i as f64);
                boxes.push(Aabb {
                    min: Point3::new(x, y, 0.1 * j as f64),
                    max: Point3::new(x + 0.3, y + 0.2, 0.1 * j as f64 + 0.05),
                });
            }
        }
        let tree = BoxTree::new(boxes.clone());
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let a = Point3::new(6.0 * next() - 1.0, 4.0 * next() - 1.0, 3.0 * next() - 1.5);
            let b = Point3::new(6.0 * next() - 1.0, 4.0 * next() - 1.0, 3.0 * next() - 1.5);
            let seg = Segment { a, b };
            let want = boxes
                .iter()
                .map(|x| segment_box(a, b, x).0)
                .fold(f64::INFINITY, f64::min)
                .sqrt();
            assert_eq!(tree.least_distance(seg, 0.0), want, "{a} {b}");
            let need = 0.5;
            let got = tree.least_distance(seg, need);
            if want < need {
                assert_eq!(got, 0.0);
            } else {
                assert_eq!(got, want);
            }
        }
    }
}
