//! Trimming loops: the face of a surface inside an outer loop and outside
//! its holes, all closed polylines in the (u, v) domain.
use std::sync::OnceLock;

use crate::geometry::NurbsSurface;
use crate::math::{Point3, Vec2};

/// A validated trim region.
#[derive(Debug, Clone)]
pub struct Trim {
    /// Every loop (outer first, then holes), each implicitly closed.
    loops: Vec<Vec<Vec2>>,
    lo: Vec2,
    hi: Vec2,
    /// The loop edges' images on the trimmed surface, made on first use
    /// (a trim belongs to one surface).
    chords: OnceLock<Vec<Chord>>,
}

impl PartialEq for Trim {
    fn eq(&self, other: &Trim) -> bool {
        self.loops == other.loops
    }
}

/// A loop edge clamped to the surface's domain, with what bounds its image
/// from below: the chord between the images of its ends and how far the
/// image bulges from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chord {
    /// Start, (u, v) clamped to the domain.
    pub a: Vec2,
    /// End, (u, v) clamped to the domain.
    pub b: Vec2,
    /// Image of `a`.
    pub pa: Point3,
    /// Image of `b`.
    pub pb: Point3,
    /// Allowance for the image's bulge from the chord, mm: four times the
    /// distance of the image of the edge's midpoint from the chord's.
    pub bulge: f64,
}

impl Chord {
    fn new(surface: &NurbsSurface, (a, b): (Vec2, Vec2)) -> Chord {
        let (a, b) = (surface.clamp(a), surface.clamp(b));
        let m = (a + b) * 0.5;
        let (pa, pb, pm) = (
            surface.point(a.x, a.y),
            surface.point(b.x, b.y),
            surface.point(m.x, m.y),
        );
        let bulge = 4.0 * (pm - Point3::from((pa.coords + pb.coords) * 0.5)).norm() + 1e-9;
        Chord {
            a,
            b,
            pa,
            pb,
            bulge,
        }
    }

    /// A lower bound of the squared distance from `p` to the edge's image:
    /// the distance to the chord less the bulge allowance.
    pub fn lower_bound2(&self, p: Point3) -> f64 {
        let chord = self.pb - self.pa;
        let t = ((p - self.pa).dot(&chord) / chord.norm_squared().max(1e-300)).clamp(0.0, 1.0);
        let d = (p - (self.pa + chord * t)).norm();
        (d - self.bulge).max(0.0).powi(2)
    }
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
        Trim {
            loops,
            lo,
            hi,
            chords: OnceLock::new(),
        }
    }

    /// The loop edges' chords on `surface` (the surface this trim belongs
    /// to), computed once.
    pub fn chords(&self, surface: &NurbsSurface) -> &[Chord] {
        self.chords
            .get_or_init(|| self.segments().map(|s| Chord::new(surface, s)).collect())
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
