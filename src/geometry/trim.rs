//! Trimming loops: the face of a surface inside an outer loop and outside
//! its holes, all closed polylines in the (u, v) domain.
use std::sync::OnceLock;

use crate::geometry::chord_tree::ChordTree;
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
    /// A box tree over `chords`, made on first use.
    chord_tree: OnceLock<ChordTree>,
    /// The loop edges by bands of `v`, made on first use.
    bands: OnceLock<Bands>,
}

/// Fewer loop edges than this are tested one by one in [`Trim::contains`].
const BANDED_EDGES: usize = 32;

/// The loop edges sorted into equal bands of `v`: an edge is in every band
/// its `v` range meets, so the edges that a horizontal ray at some `v` can
/// cross are all in that `v`'s band.
#[derive(Debug, Clone, Default)]
struct Bands {
    v0: f64,
    /// Band height (positive).
    dv: f64,
    bands: Vec<Vec<(Vec2, Vec2)>>,
}

impl Bands {
    fn new(trim: &Trim) -> Bands {
        let n = trim.segments().count();
        let count = ((n as f64).sqrt() * 2.0).ceil().max(1.0) as usize;
        let (v0, span) = (trim.lo.y, trim.hi.y - trim.lo.y);
        let dv = if span > 0.0 { span / count as f64 } else { 1.0 };
        let mut bands = Bands {
            v0,
            dv,
            bands: vec![Vec::new(); count],
        };
        for (a, b) in trim.segments() {
            let (k0, k1) = (bands.band(a.y.min(b.y)), bands.band(a.y.max(b.y)));
            for band in bands.bands.get_mut(k0..=k1).into_iter().flatten() {
                band.push((a, b));
            }
        }
        bands
    }

    /// The band of `v` (clamped to the bands; monotone in `v`).
    fn band(&self, v: f64) -> usize {
        let k = ((v - self.v0) / self.dv).floor();
        (k.max(0.0) as usize).min(self.bands.len().saturating_sub(1))
    }

    /// Number of edges crossed by the ray from `p` towards +u.
    fn crossings(&self, p: Vec2) -> usize {
        let edges = self
            .bands
            .get(self.band(p.y))
            .map_or(&[][..], |b| b.as_slice());
        edges.iter().filter(|&&(a, b)| crosses(a, b, p)).count()
    }
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
            chord_tree: OnceLock::new(),
            bands: OnceLock::new(),
        }
    }

    /// The loop edges' chords on `surface` (the surface this trim belongs
    /// to), computed once.
    pub fn chords(&self, surface: &NurbsSurface) -> &[Chord] {
        self.chords
            .get_or_init(|| self.segments().map(|s| Chord::new(surface, s)).collect())
    }

    /// Calls `look(chord)` for every chord of [`Self::chords`] whose
    /// [`Chord::lower_bound2`] from `p` is below the bound (at first
    /// `bound`), nearer chords first as a box tree finds them; `look`
    /// returns a new squared-distance bound when it found a closer point.
    pub fn search_chords(
        &self,
        surface: &NurbsSurface,
        p: Point3,
        bound: f64,
        mut look: impl FnMut(&Chord) -> Option<f64>,
    ) -> f64 {
        let chords = self.chords(surface);
        let tree = self.chord_tree.get_or_init(|| ChordTree::new(chords));
        tree.search(chords, p, bound, |i| chords.get(i).and_then(&mut look))
    }

    /// Whether `(u, v)` lies on the face (even-odd rule over all loops).
    pub fn contains(&self, uv: Vec2) -> bool {
        if uv.x < self.lo.x || uv.x > self.hi.x || uv.y < self.lo.y || uv.y > self.hi.y {
            return false;
        }
        let edges: usize = self.loops.iter().map(Vec::len).sum();
        let crossings: usize = if edges < BANDED_EDGES {
            self.loops.iter().map(|l| crossings(l, uv)).sum()
        } else {
            self.bands.get_or_init(|| Bands::new(self)).crossings(uv)
        };
        crossings % 2 == 1
    }

    /// The distance in `(u, v)` from `uv` to the nearest loop edge.
    pub fn distance(&self, uv: Vec2) -> f64 {
        self.segments()
            .map(|e| segment_distance(uv, e))
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether a loop edge comes within `d` of `uv` (in `(u, v)`): the
    /// edges of the `v` bands `d` reaches (all edges of a small trim),
    /// each first by its box grown by `d`.
    pub fn comes_within(&self, uv: Vec2, d: f64) -> bool {
        let near = |&(a, b): &(Vec2, Vec2)| {
            let (lo, hi) = (a.inf(&b), a.sup(&b));
            let boxed =
                uv.x >= lo.x - d && uv.x <= hi.x + d && uv.y >= lo.y - d && uv.y <= hi.y + d;
            boxed && segment_distance(uv, (a, b)) <= d
        };
        let edges: usize = self.loops.iter().map(Vec::len).sum();
        if edges < BANDED_EDGES {
            return self.segments().any(|e| near(&e));
        }
        let bands = self.bands.get_or_init(|| Bands::new(self));
        let (k0, k1) = (bands.band(uv.y - d), bands.band(uv.y + d));
        (bands.bands.get(k0..=k1).into_iter().flatten()).any(|band| band.iter().any(near))
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

/// The distance in `(u, v)` from `uv` to the edge `a..b`.
pub(crate) fn segment_distance(uv: Vec2, (a, b): (Vec2, Vec2)) -> f64 {
    let e = b - a;
    let t = ((uv - a).dot(&e) / e.norm_squared().max(1e-300)).clamp(0.0, 1.0);
    (uv - (a + e * t)).norm()
}

/// Number of loop edges crossed by the ray from `p` towards +u.
fn crossings(l: &[Vec2], p: Vec2) -> usize {
    (0..l.len())
        .filter(|&k| crosses(l[k], l[(k + 1) % l.len()], p))
        .count()
}

/// Whether the edge `a`-`b` crosses the ray from `p` towards +u.
fn crosses(a: Vec2, b: Vec2, p: Vec2) -> bool {
    if (a.y > p.y) == (b.y > p.y) {
        return false;
    }
    let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
    p.x < x
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// A regular `n`-gon of radius `r` about `c`, counter-clockwise.
    fn polygon(n: usize, r: f64, c: [f64; 2]) -> Vec<[f64; 2]> {
        (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            })
            .collect()
    }

    /// Inside a convex counter-clockwise polygon: left of every edge.
    fn inside_convex(poly: &[[f64; 2]], p: Vec2) -> bool {
        (0..poly.len()).all(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            (b[0] - a[0]) * (p.y - a[1]) - (b[1] - a[1]) * (p.x - a[0]) > 0.0
        })
    }

    #[test]
    fn banded_containment_agrees_with_half_planes() {
        // 300 + 120 edges: the banded test (at least BANDED_EDGES edges).
        let outer = polygon(300, 1.0, [0.5, 0.5]);
        let hole = polygon(120, 0.3, [0.7, 0.4]);
        let trim = Trim::new(&outer, std::slice::from_ref(&hole));
        let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(5);
        for _ in 0..20_000 {
            let p = Vec2::new(rng.random::<f64>(), rng.random::<f64>()) * 2.4 - Vec2::repeat(0.7);
            let want = inside_convex(&outer, p) && !inside_convex(&hole, p);
            assert_eq!(trim.contains(p), want, "{p:?}");
        }
    }

    /// Distance from `p` to the closed polyline `poly`, by sampling each
    /// edge at 2000 points (an upper bound within 1e-3 of the truth for
    /// the polygons here).
    fn sampled_distance(poly: &[[f64; 2]], p: Vec2) -> f64 {
        let mut best = f64::INFINITY;
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            for i in 0..=2000 {
                let t = i as f64 / 2000.0;
                let q = Vec2::new(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t);
                best = best.min((q - p).norm());
            }
        }
        best
    }

    #[test]
    fn comes_within_agrees_with_sampled_distances() {
        // Banded (300 + 120 edges) and one by one (8 edges).
        let (outer, hole) = (polygon(300, 1.0, [0.5, 0.5]), polygon(120, 0.3, [0.7, 0.4]));
        let banded = Trim::new(&outer, std::slice::from_ref(&hole));
        let small = polygon(8, 0.8, [0.4, 0.6]);
        let plain = Trim::new(&small, &[]);
        let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(9);
        for _ in 0..300 {
            let p = Vec2::new(rng.random::<f64>(), rng.random::<f64>()) * 2.4 - Vec2::repeat(0.7);
            let d = rng.random::<f64>() * 0.2;
            let want = sampled_distance(&outer, p).min(sampled_distance(&hole, p));
            if (want - d).abs() > 2e-3 {
                assert_eq!(banded.comes_within(p, d), want <= d, "{p:?} {d} {want}");
            }
            let want = sampled_distance(&small, p);
            if (want - d).abs() > 2e-3 {
                assert_eq!(plain.comes_within(p, d), want <= d, "{p:?} {d} {want}");
            }
        }
    }
}
