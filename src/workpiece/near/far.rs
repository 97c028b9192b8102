//! Leaves that earlier queries found far away, carried from one query to
//! the next in the hint: a leaf's least distance from a point, less the
//! distance from that point, bounds its distance from any other point, so
//! a leaf found well beyond the bound of one query needs no Newton
//! iteration in the next ones (the other side of a thin part, say).
use crate::geometry::projection::LeafMemo;
use crate::math::Point3;

/// Leaves remembered.
const SLOTS: usize = 4;

/// One leaf's least distance from a point.
#[derive(Debug, Clone, Copy, PartialEq)]
struct FarLeaf {
    face: usize,
    leaf: usize,
    at: Point3,
    dist: f64,
}

/// An empty slot (its floor is never positive).
const EMPTY: FarLeaf = FarLeaf {
    face: usize::MAX,
    leaf: usize::MAX,
    at: Point3::new(0.0, 0.0, 0.0),
    dist: f64::NEG_INFINITY,
};

/// The leaves remembered (a few; the least useful for the query at hand
/// makes room for a new one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FarLeaves {
    slots: [FarLeaf; SLOTS],
}

impl Default for FarLeaves {
    fn default() -> Self {
        FarLeaves {
            slots: [EMPTY; SLOTS],
        }
    }
}

impl FarLeaves {
    /// The memo of face `face`'s leaves.
    pub(crate) fn of_face(&mut self, face: usize) -> FaceMemo<'_> {
        FaceMemo { face, far: self }
    }
}

/// [`FarLeaves`] seen from one face's search tree.
pub(crate) struct FaceMemo<'a> {
    face: usize,
    far: &'a mut FarLeaves,
}

impl LeafMemo for FaceMemo<'_> {
    fn floor(&self, leaf: usize, p: Point3) -> f64 {
        (self.far.slots.iter())
            .filter(|s| s.face == self.face && s.leaf == leaf)
            .map(|s| s.dist - (p - s.at).norm())
            .fold(0.0, f64::max)
    }

    fn note(&mut self, leaf: usize, p: Point3, dist: f64) {
        let (face, slots) = (self.face, &mut self.far.slots);
        let same = slots.iter().position(|s| s.face == face && s.leaf == leaf);
        let least_useful = || {
            let worth = |s: &FarLeaf| s.dist - (p - s.at).norm();
            (0..SLOTS).min_by(|&a, &b| worth(&slots[a]).total_cmp(&worth(&slots[b])))
        };
        if let Some(slot) = same.or_else(least_useful).and_then(|k| slots.get_mut(k)) {
            *slot = FarLeaf {
                face,
                leaf,
                at: p,
                dist,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A remembered leaf bounds the distance from nearby points by the
    /// triangle inequality; a new leaf replaces the least useful one.
    #[test]
    fn floors_follow_the_triangle_inequality() {
        let mut far = FarLeaves::default();
        let o = Point3::origin();
        let mut memo = far.of_face(1);
        assert_eq!(memo.floor(7, o), 0.0);
        memo.note(7, o, 5.0);
        assert_eq!(memo.floor(7, Point3::new(3.0, 4.0, 0.0)), 0.0);
        assert_eq!(memo.floor(7, Point3::new(1.0, 0.0, 0.0)), 4.0);
        assert_eq!(memo.floor(8, o), 0.0);
        assert_eq!(far.of_face(2).floor(7, o), 0.0);
        let mut memo = far.of_face(1);
        for leaf in 10..10 + SLOTS {
            memo.note(leaf, o, 1.0 + leaf as f64);
        }
        // Leaf 7 (5 mm) went first, the rest stay.
        assert_eq!(memo.floor(7, o), 0.0);
        assert_eq!(memo.floor(10 + SLOTS - 1, o), (10 + SLOTS) as f64);
    }
}
