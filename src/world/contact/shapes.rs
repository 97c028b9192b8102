//! The probe's shapes beyond the ball, as the collision check sees them: a
//! segment of the probe's axis (for the broad phase) and a solid finite
//! cylinder round it (for the exact check).
use super::leaves::{Aabb, Leaf};
use super::tree::Shape;
use crate::math::{Point3, Vec3};

/// The segment `a..b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Segment {
    pub(crate) a: Point3,
    pub(crate) b: Point3,
}

impl Segment {
    /// The squared gap between the segment's own box and `b` (a lower
    /// bound of their squared distance).
    #[inline(always)]
    fn box_gap2(&self, b: &Aabb) -> f64 {
        let (lo, hi) = (self.a.inf(&self.b), self.a.sup(&self.b));
        (b.min - hi)
            .sup(&(lo - b.max))
            .sup(&Vec3::zeros())
            .norm_squared()
    }
}

impl Shape for Segment {
    fn box_dist2(&self, b: &Aabb) -> f64 {
        segment_box(self.a, self.b, b).0
    }

    /// The gap between the segment's own box and `b` first (a lower bound
    /// of their distance, exact for a segment along an axis).
    #[inline(always)]
    fn box_beyond(&self, b: &Aabb, r2: f64) -> bool {
        self.box_gap2(b) >= r2 || self.box_dist2(b) >= r2
    }

    fn leaf_bound(&self, leaf: &Leaf) -> f64 {
        leaf.segment_lower_bound(self.a, self.b)
    }

    /// The box test and the bound from one segment-box distance.
    #[inline(always)]
    fn leaf_bound_within(&self, leaf: &Leaf, r2: f64) -> Option<f64> {
        let b = &leaf.aabb;
        if self.box_gap2(b) >= r2 {
            return None;
        }
        let d2 = segment_box(self.a, self.b, b).0;
        (d2 < r2).then(|| leaf.segment_lower_bound_from(d2, self.a, self.b))
    }
}

/// A cylinder seen by the broad phase: its axis segment, with each box
/// or leaf bounded by its distance from the axis and, with `caps`, by the
/// radius plus how far it lies beyond the plane of either end cap, the
/// larger (the cylinder's distance is at least this less the radius). A
/// probe body standing above a part, wider than the part, prunes every box
/// below its bottom cap rather than listing the whole part by its axis
/// distance. A stylus shaft's caps prune little (its lower one sits at
/// the ball, among the leaves it comes near) for what they cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CappedAxis {
    pub(crate) cyl: Cylinder,
    pub(crate) seg: Segment,
    pub(crate) caps: bool,
}

impl CappedAxis {
    /// The broad-phase shape of `cyl`, its end caps bounding with `caps`.
    pub(crate) fn of(cyl: &Cylinder, caps: bool) -> CappedAxis {
        CappedAxis {
            cyl: *cyl,
            seg: cyl.segment(),
            caps,
        }
    }

    /// The radius plus the end gap of `b` (zero without caps: no bound),
    /// mm.
    #[inline(always)]
    fn capped(&self, b: &Aabb) -> f64 {
        if !self.caps {
            return 0.0;
        }
        self.cyl.radius + self.cyl.end_gap(b)
    }
}

impl Shape for CappedAxis {
    fn box_dist2(&self, b: &Aabb) -> f64 {
        let cap = self.capped(b);
        self.seg.box_dist2(b).max(cap * cap)
    }

    /// The segment's own box first (cheapest), then the caps, then the
    /// exact segment-box distance.
    #[inline(always)]
    fn box_beyond(&self, b: &Aabb, r2: f64) -> bool {
        if self.seg.box_gap2(b) >= r2 {
            return true;
        }
        let cap = self.capped(b);
        cap * cap >= r2 || self.seg.box_dist2(b) >= r2
    }

    fn leaf_bound(&self, leaf: &Leaf) -> f64 {
        self.seg.leaf_bound(leaf).max(self.capped(&leaf.aabb))
    }

    #[inline(always)]
    fn leaf_bound_within(&self, leaf: &Leaf, r2: f64) -> Option<f64> {
        if self.seg.box_gap2(&leaf.aabb) >= r2 {
            return None;
        }
        let cap = self.capped(&leaf.aabb);
        if cap * cap >= r2 {
            return None;
        }
        (self.seg.leaf_bound_within(leaf, r2)).map(|b| b.max(cap))
    }
}

/// The squared distance from the segment `a..b` to the box `bx` and the
/// parameter `s` in `[0, 1]` of the segment's point `a + s (b - a)` that
/// attains it (exact: the squared distance is a piecewise quadratic in
/// `s`, with its pieces split where a coordinate crosses a side of the
/// box), or for a segment within [`NEAR_AXIS_MM`] of a coordinate axis a
/// lower bound of it at most its extents across short (see
/// [`along_axis`]).
pub(crate) fn segment_box(a: Point3, b: Point3, bx: &Aabb) -> (f64, f64) {
    let d = b - a;
    if let Some(found) = along_axis(a, d, bx) {
        return found;
    }
    let mut ts = [0.0f64; 8];
    ts[1] = 1.0;
    let mut n = 2;
    for k in 0..3 {
        if d[k] == 0.0 {
            continue;
        }
        for side in [bx.min[k], bx.max[k]] {
            let t = (side - a[k]) / d[k];
            if t > 0.0 && t < 1.0 {
                if let Some(slot) = ts.get_mut(n) {
                    *slot = t;
                    n += 1;
                }
            }
        }
    }
    let ts = ts.get_mut(..n).unwrap_or_default();
    insertion_sort(ts);
    let mut best = (bx.dist2(a), 0.0);
    for w in ts.windows(2) {
        let &[t0, t1] = w else {
            continue;
        };
        let t = piece_minimum(a, d, bx, t0, t1);
        let d2 = bx.dist2(a + d * t);
        if d2 < best.0 {
            best = (d2, t);
        }
    }
    best
}

/// Sorts a few numbers (no NaN among them) in place.
#[inline(always)]
fn insertion_sort(ts: &mut [f64]) {
    for i in 1..ts.len() {
        let mut j = i;
        while j > 0 && ts[j - 1] > ts[j] {
            ts.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// A segment whose extent across its main coordinate axis is at most this
/// (mm) in each other coordinate counts as along that axis in
/// [`segment_box`]: its distance is bounded from below through the gaps of
/// its own intervals, short of the exact one by at most its extents across
/// (a stylus standing up through a machine's angular errors, a few
/// micrometres over its length, is bounded at the cost of a coordinate
/// test rather than of the piecewise search).
const NEAR_AXIS_MM: f64 = 1e-2;

/// [`segment_box`] of a segment along a coordinate axis (a stylus
/// standing straight up, the common case), or within [`NEAR_AXIS_MM`] of
/// one across it: the squared distance is at least the squared gaps
/// between the segment's intervals and the box's in the other two
/// coordinates plus the gap along the axis at the segment's point nearest
/// to the box's interval (exact for a segment exactly along the axis).
/// `None` for any other segment.
fn along_axis(a: Point3, d: Vec3, bx: &Aabb) -> Option<(f64, f64)> {
    let k = d.iamax();
    let across = (0..3).filter(|&j| j != k);
    if d[k] == 0.0 || across.clone().any(|j| d[j].abs() > NEAR_AXIS_MM) {
        return None;
    }
    let mut d2 = 0.0;
    for j in across {
        let (lo, hi) = (a[j].min(a[j] + d[j]), a[j].max(a[j] + d[j]));
        let gap = (bx.min[j] - hi).max(lo - bx.max[j]).max(0.0);
        d2 += gap * gap;
    }
    // The segment's coordinate along the axis nearest to the box's
    // interval (its centre when they overlap).
    let mid = 0.5 * (bx.min[k] + bx.max[k]);
    let s = ((mid - a[k]) / d[k]).clamp(0.0, 1.0);
    let x = a[k] + d[k] * s;
    let gap = (bx.min[k] - x).max(x - bx.max[k]).max(0.0);
    Some((d2 + gap * gap, s))
}

/// The minimiser over `[t0, t1]` of the squared distance from `a + t d`
/// to `bx`, on a piece where no coordinate crosses a side of the box.
fn piece_minimum(a: Point3, d: Vec3, bx: &Aabb, t0: f64, t1: f64) -> f64 {
    let mid = 0.5 * (t0 + t1);
    let (mut aa, mut bb) = (0.0, 0.0);
    for k in 0..3 {
        let x = a[k] + d[k] * mid;
        let side = if x < bx.min[k] {
            bx.min[k]
        } else if x > bx.max[k] {
            bx.max[k]
        } else {
            continue;
        };
        // (a_k - side + t d_k)^2
        aa += d[k] * d[k];
        bb += (a[k] - side) * d[k];
    }
    let t = if aa > 0.0 { -bb / aa } else { t0 };
    if t.is_finite() {
        t.clamp(t0, t1)
    } else {
        t0
    }
}

/// A solid finite cylinder: the points within `radius` of the axis whose
/// axial coordinate lies in `[0, length]` from `a` along the unit `axis`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cylinder {
    pub(crate) a: Point3,
    pub(crate) axis: Vec3,
    pub(crate) length: f64,
    pub(crate) radius: f64,
}

/// Directions whose component along (or across) the axis is below this
/// fraction of their length count as square to (or along) it.
const TIE: f64 = 1e-12;

impl Cylinder {
    /// The cylinder of `radius` round the segment `a..b`; `None` when the
    /// segment has no length.
    pub(crate) fn between(a: Point3, b: Point3, radius: f64) -> Option<Cylinder> {
        let d = b - a;
        let length = d.norm();
        let axis = d.try_normalize(1e-12)?;
        Some(Cylinder {
            a,
            axis,
            length,
            radius,
        })
    }

    /// The axis segment.
    pub(crate) fn segment(&self) -> Segment {
        Segment {
            a: self.a,
            b: self.a + self.axis * self.length,
        }
    }

    /// A lower bound of the distance from the cylinder to every point of
    /// `b` from the axis alone: how far the box lies beyond the plane of
    /// either end cap (zero when its span along the axis meets the
    /// cylinder's), mm. A bound from the axis segment less the radius
    /// treats the ends as hemispheres reaching a radius past the caps; a
    /// wide, short cylinder (a probe body) standing above a part needs
    /// this one.
    pub(crate) fn end_gap(&self, b: &Aabb) -> f64 {
        let centre = b.centre() - self.a;
        let half = (b.max - b.min) * 0.5;
        let t = centre.dot(&self.axis);
        let spread = half.dot(&self.axis.abs());
        (-(t + spread)).max(t - spread - self.length).max(0.0)
    }

    /// Axial coordinate and radial offset of `q`.
    fn split(&self, q: Point3) -> (f64, Vec3) {
        let v = q - self.a;
        let t = v.dot(&self.axis);
        (t, v - self.axis * t)
    }

    /// Signed distance of `q` from the cylinder (negative inside), mm.
    pub(crate) fn signed_distance(&self, q: Point3) -> f64 {
        let (t, w) = self.split(q);
        let dx = w.norm() - self.radius;
        let dy = (-t).max(t - self.length);
        let inside = dx.max(dy).min(0.0);
        let outside = dx.max(0.0).hypot(dy.max(0.0));
        inside + outside
    }

    /// The point of the cylinder closest to `q` (`q` itself inside).
    pub(crate) fn closest(&self, q: Point3) -> Point3 {
        let (t, w) = self.split(q);
        let rho = w.norm();
        let w = if rho > self.radius {
            w * (self.radius / rho)
        } else {
            w
        };
        self.a + self.axis * t.clamp(0.0, self.length) + w
    }

    /// A point of the cylinder furthest along `v`; where that is not one
    /// point (`v` square to the axis, or along it), the one nearest to
    /// `near` among them.
    pub(crate) fn support(&self, v: Vec3, near: Point3) -> Point3 {
        let size = v.norm();
        let along = v.dot(&self.axis);
        let across = v - self.axis * along;
        let (t_near, w_near) = self.split(near);
        let t = if along > TIE * size {
            self.length
        } else if along < -TIE * size {
            0.0
        } else {
            t_near.clamp(0.0, self.length)
        };
        let w = match across.try_normalize(TIE * size.max(1e-300)) {
            Some(u) => u * self.radius,
            None => {
                let rho = w_near.norm();
                if rho > self.radius {
                    w_near * (self.radius / rho)
                } else {
                    w_near
                }
            }
        };
        self.a + self.axis * t + w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Aabb {
        Aabb {
            min: Point3::new(0.0, 0.0, 0.0),
            max: Point3::new(1.0, 1.0, 1.0),
        }
    }

    /// The segment-box distance against a dense sampling of the segment.
    #[test]
    fn segment_box_matches_sampling() {
        let cases = [
            ([-1.0, 2.0, 0.5], [2.0, 2.0, 0.5], 1.0),
            ([-1.0, -1.0, -1.0], [2.0, 2.5, 3.0], 0.0),
            ([2.0, 3.0, -2.0], [3.0, 1.5, 2.0], 49.0 / 13.0),
            ([3.0, 3.0, 3.0], [4.0, 2.0, 5.0], 12.0),
            ([-2.0, 0.5, 3.0], [0.5, 0.5, 1.5], 0.25),
            // Along an axis: beside the box, above it, off a corner,
            // through it, and pointing the other way.
            ([2.0, 0.5, -1.0], [2.0, 0.5, 3.0], 1.0),
            ([0.5, 0.5, 2.0], [0.5, 0.5, 5.0], 1.0),
            ([3.0, 3.0, -2.0], [3.0, 3.0, -0.5], 8.25),
            ([0.5, 0.2, -3.0], [0.5, 0.2, 3.0], 0.0),
            ([-1.0, 4.0, 0.3], [-6.0, 4.0, 0.3], 10.0),
        ];
        for (a, b, want) in cases {
            let (a, b) = (Point3::from(a), Point3::from(b));
            let (d2, s) = segment_box(a, b, &cube());
            let sampled = (0..=100_000)
                .map(|k| cube().dist2(a + (b - a) * (k as f64 / 100_000.0)))
                .fold(f64::INFINITY, f64::min);
            assert!(d2 <= sampled + 1e-12, "{a} {b}: {d2} vs {sampled}");
            assert!(sampled - d2 < 1e-8, "{a} {b}: {d2} vs {sampled}");
            assert!((cube().dist2(a + (b - a) * s) - d2).abs() < 1e-12);
            assert!((d2 - want).abs() < 1e-9, "{a} {b}: {d2} vs {want}");
        }
        // Known values: a line 1 above the top face; one corner 1 away in
        // each of x, y and z (distance sqrt(3)).
        let (d2, _) = segment_box(Point3::new(-1., 2., 0.5), Point3::new(2., 2., 0.5), &cube());
        assert!((d2 - 1.0).abs() < 1e-12);
        let (d2, _) = segment_box(Point3::new(2., 2., 2.), Point3::new(3., 2., 2.), &cube());
        assert!((d2 - 3.0).abs() < 1e-12);
    }

    /// A segment a few micrometres off a coordinate axis (a stylus tilted
    /// by a machine's angular errors): a lower bound of the sampled
    /// distance, short of it by no more than the segment's extent across
    /// the axis.
    #[test]
    fn near_axis_segment_is_bounded() {
        for (a, b) in [
            ([2.0, 0.5, -1.0], [2.0004, 0.5003, 3.0]),
            ([3.0, 3.0, -2.0], [2.9995, 3.0008, -0.5]),
            ([0.5, 1.7, 3.0], [0.5009, 1.7, 5.0]),
            ([-0.2, 0.5, 0.5], [-5.0, 0.5002, 0.4999]),
        ] {
            let (a, b) = (Point3::from(a), Point3::from(b));
            let across = {
                let d = (b - a).abs();
                d.sum() - d.max()
            };
            let (d2, _) = segment_box(a, b, &cube());
            let sampled = (0..=100_000)
                .map(|k| cube().dist2(a + (b - a) * (k as f64 / 100_000.0)))
                .fold(f64::INFINITY, f64::min);
            assert!(d2 <= sampled + 1e-12, "{a} {b}: {d2} vs {sampled}");
            assert!(sampled.sqrt() - d2.sqrt() <= across + 1e-9, "{a} {b}");
        }
    }

    /// The cylinder's signed distance, closest point and support point on
    /// a cylinder of radius 2 from the origin up 10 along z.
    #[test]
    fn cylinder_distances() {
        let c = Cylinder::between(Point3::origin(), Point3::new(0., 0., 10.), 2.0).unwrap();
        let sd = |x: f64, y: f64, z: f64| c.signed_distance(Point3::new(x, y, z));
        assert!((sd(5.0, 0.0, 5.0) - 3.0).abs() < 1e-12);
        assert!((sd(1.0, 0.0, -0.5) - 0.5).abs() < 1e-12);
        assert!((sd(5.0, 0.0, 14.0) - 5.0).abs() < 1e-12);
        assert!((sd(0.0, 1.0, 5.0) + 1.0).abs() < 1e-12);
        assert!((sd(0.0, 0.0, 9.5) + 0.5).abs() < 1e-12);
        let p = c.closest(Point3::new(0.0, 6.0, -3.0));
        assert!((p - Point3::new(0.0, 2.0, 0.0)).norm() < 1e-12);
        // Furthest down and along -x: the rim point (-2, 0, 0).
        let s = c.support(Vec3::new(-1.0, 0.0, -1.0), Point3::origin());
        assert!((s - Point3::new(-2.0, 0.0, 0.0)).norm() < 1e-12);
        // Square to the axis: the side line, at the height of `near`.
        let s = c.support(Vec3::new(0.0, 1.0, 0.0), Point3::new(0.0, 0.0, 7.0));
        assert!((s - Point3::new(0.0, 2.0, 7.0)).norm() < 1e-12);
        // Along the axis: the top disk, below `near`.
        let s = c.support(Vec3::z(), Point3::new(1.0, 1.0, 3.0));
        assert!((s - Point3::new(1.0, 1.0, 10.0)).norm() < 1e-12);
    }

    /// The end gap against sampled boxes round tilted cylinders: never
    /// above the least distance from a sample of the box to the solid
    /// cylinder (by its axial and radial coordinates), and equal to the
    /// gap for a box straight below the bottom cap.
    #[test]
    fn end_gap_is_a_lower_bound_of_the_box_cylinder_distance() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(7);
        let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
        let mut positive = 0;
        for _ in 0..400 {
            let a = Point3::new(u(-5.0, 5.0), u(-5.0, 5.0), u(-5.0, 5.0));
            let b = a + Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)) * 20.0;
            let Some(c) = Cylinder::between(a, b, u(0.5, 15.0)) else {
                continue;
            };
            let lo = Point3::new(u(-20.0, 20.0), u(-20.0, 20.0), u(-20.0, 20.0));
            let bx =
                Aabb::of([lo, lo + Vec3::new(u(0.0, 8.0), u(0.0, 8.0), u(0.0, 8.0))].into_iter());
            let solid = |q: Point3| {
                let (t, off) = c.split(q);
                let gap = (-t).max(t - c.length).max(0.0);
                let out = (off.norm() - c.radius).max(0.0);
                (gap * gap + out * out).sqrt()
            };
            let mut least = f64::INFINITY;
            for (i, j, k) in
                (0..=8).flat_map(|i| (0..=8).flat_map(move |j| (0..=8).map(move |k| (i, j, k))))
            {
                let f = Vec3::new(i as f64, j as f64, k as f64) / 8.0;
                least = least.min(solid(bx.min + (bx.max - bx.min).component_mul(&f)));
            }
            let gap = c.end_gap(&bx);
            assert!(gap <= least + 1e-9, "{gap} > {least}");
            positive += usize::from(gap > 0.0);
        }
        assert!(positive > 50, "{positive}");
        // A body of radius 12.5 standing 9 mm above a small part.
        let body = Cylinder::between(
            Point3::new(0.0, 0.0, 11.0),
            Point3::new(0.0, 0.0, 91.0),
            12.5,
        )
        .unwrap();
        let part = Aabb::of([Point3::new(-3.0, -2.0, 0.0), Point3::new(5.0, 2.0, 2.0)].into_iter());
        assert!((body.end_gap(&part) - 9.0).abs() < 1e-12);
    }
}
