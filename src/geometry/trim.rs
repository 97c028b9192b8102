//! Trimming loops: the face of a surface inside an outer loop and outside
//! its holes, all closed polylines in the (u, v) domain.
use crate::math::Vec2;

/// A validated trim region.
#[derive(Debug, Clone, PartialEq)]
pub struct Trim {
    /// Every loop (outer first, then holes), each implicitly closed.
    loops: Vec<Vec<Vec2>>,
    lo: Vec2,
    hi: Vec2,
}

impl Trim {
    /// Builds a trim from an outer loop and holes (each at least 3 points).
    pub fn new(outer: &[[f64; 2]], holes: &[Vec<[f64; 2]>]) -> Trim {
        let to_vec = |l: &[[f64; 2]]| l.iter().map(|p| Vec2::new(p[0], p[1])).collect::<Vec<_>>();
        let mut loops = vec![to_vec(outer)];
        loops.extend(holes.iter().map(|h| to_vec(h)));
        let all = loops.iter().flatten();
        let lo = all
            .clone()
            .fold(Vec2::repeat(f64::INFINITY), |a, b| a.inf(b));
        let hi = all.fold(Vec2::repeat(f64::NEG_INFINITY), |a, b| a.sup(b));
        Trim { loops, lo, hi }
    }

    /// Whether `(u, v)` lies on the face (even-odd rule over all loops).
    pub fn contains(&self, uv: Vec2) -> bool {
        if uv.x < self.lo.x || uv.x > self.hi.x || uv.y < self.lo.y || uv.y > self.hi.y {
            return false;
        }
        let crossings: usize = self.loops.iter().map(|l| crossings(l, uv)).sum();
        crossings % 2 == 1
    }

    /// Whether the parameter rectangle `[lo, hi]` can touch the face.
    pub fn may_touch(&self, lo: Vec2, hi: Vec2) -> bool {
        lo.x <= self.hi.x && hi.x >= self.lo.x && lo.y <= self.hi.y && hi.y >= self.lo.y
    }

    /// Every boundary segment `(a, b)` of every loop.
    pub fn segments(&self) -> impl Iterator<Item = (Vec2, Vec2)> + '_ {
        self.loops
            .iter()
            .flat_map(|l| (0..l.len()).map(move |k| (l[k], l[(k + 1) % l.len()])))
    }
}

/// Number of loop edges crossed by the ray from `p` towards +u.
fn crossings(l: &[Vec2], p: Vec2) -> usize {
    (0..l.len())
        .filter(|&k| {
            let (a, b) = (l[k], l[(k + 1) % l.len()]);
            if (a.y > p.y) == (b.y > p.y) {
                return false;
            }
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            p.x < x
        })
        .count()
}
