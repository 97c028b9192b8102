//! Leaves and faces that earlier queries found far away, carried from one
//! query to the next in the hint: a leaf's (or a whole face's) least
//! distance from a point, less the distance from that point, bounds its
//! distance from any other point, so a leaf found well beyond the bound of
//! one query needs no Newton iteration in the next ones (the other side of
//! a thin part, say), and a face searched within a wide bound needs no
//! search in nearby queries with narrower ones.
use crate::geometry::projection::LeafMemo;
use crate::math::Point3;

/// Leaves and faces remembered.
const SLOTS: usize = 6;

/// The `leaf` of an entry for a whole face.
const WHOLE: usize = usize::MAX;

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

    /// A lower bound of the distance from `p` to face `face` (zero or less
    /// when nothing is known).
    pub(crate) fn face_floor(&self, face: usize, p: Point3) -> f64 {
        FaceMemo::floor_of(&self.slots, face, WHOLE, p)
    }

    /// Notes that face `face` comes no closer to `p` than `dist`.
    pub(crate) fn note_face(&mut self, face: usize, p: Point3, dist: f64) {
        FaceMemo::note_in(&mut self.slots, (face, WHOLE), p, dist);
    }
}

/// [`FarLeaves`] seen from one face's search tree.
pub(crate) struct FaceMemo<'a> {
    face: usize,
    far: &'a mut FarLeaves,
}

impl FaceMemo<'_> {
    /// The best floor `slots` give of leaf `leaf` of face `face` from `p`.
    fn floor_of(slots: &[FarLeaf], face: usize, leaf: usize, p: Point3) -> f64 {
        (slots.iter())
            .filter(|s| s.face == face && s.leaf == leaf)
            .map(|s| s.dist - (p - s.at).norm())
            .fold(0.0, f64::max)
    }

    /// Notes in `slots` that leaf `leaf` of face `face` comes no closer
    /// to `p` than `dist`, replacing the entry of that leaf, else the
    /// least useful for `p`.
    fn note_in(slots: &mut [FarLeaf; SLOTS], (face, leaf): (usize, usize), p: Point3, dist: f64) {
        let same = slots.iter().position(|s| s.face == face && s.leaf == leaf);
        let worth = |s: &FarLeaf| s.dist - (p - s.at).norm();
        let least_useful =
            || (0..SLOTS).min_by(|&a, &b| worth(&slots[a]).total_cmp(&worth(&slots[b])));
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

impl LeafMemo for FaceMemo<'_> {
    fn floor(&self, leaf: usize, p: Point3) -> f64 {
        FaceMemo::floor_of(&self.far.slots, self.face, leaf, p)
    }

    fn note(&mut self, leaf: usize, p: Point3, dist: f64) {
        FaceMemo::note_in(&mut self.far.slots, (self.face, leaf), p, dist);
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
        // A whole face is no leaf.
        far.note_face(3, o, 2.0);
        assert_eq!(far.face_floor(3, Point3::new(0.0, 0.5, 0.0)), 1.5);
        assert_eq!(far.of_face(3).floor(0, o), 0.0);
    }
}
