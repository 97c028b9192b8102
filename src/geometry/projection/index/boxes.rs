//! The boxes of the search tree: distances from a point, and the
//! separating-axis test against a convex shape.
use super::{Aabb, Obb};
use crate::math::{Point3, Vec3};

/// An axis (a unit vector) with the interval a convex shape covers on it.
pub(super) type Shadow = (Vec3, (f64, f64));

/// The gap between the intervals `lo..hi` and `a..b` on one axis (negative
/// when they overlap).
pub(super) fn gap((lo, hi): (f64, f64), (a, b): (f64, f64)) -> f64 {
    (a - hi).max(lo - b)
}

/// The interval of `hull`'s points projected on `axis`.
pub(super) fn extent(hull: &[Point3], axis: &Vec3) -> (f64, f64) {
    hull.iter()
        .map(|p| p.coords.dot(axis))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s), hi.max(s))
        })
}

/// The unit cross products of `axes` with `edges` (unit vectors), leaving
/// out (nearly) parallel pairs: any unit axis bounds the distance, those
/// add little and normalise poorly.
pub(super) fn crossed<'a>(axes: &'a [Vec3], edges: &'a [Vec3]) -> impl Iterator<Item = Vec3> + 'a {
    (axes.iter()).flat_map(move |a| {
        edges
            .iter()
            .filter_map(move |e| a.cross(e).try_normalize(f64::EPSILON))
    })
}

impl Obb {
    /// Whether the box and the convex hull of `hull` (with its shadows on
    /// its face normals, `on_normals`, and its edge directions `edges`) are
    /// at least `reach` apart along one axis of the separating-axis test.
    pub(super) fn separated(
        &self,
        hull: &[Point3],
        on_normals: &[Shadow],
        edges: &[Vec3],
        reach: f64,
    ) -> bool {
        let own = (self.axes.iter().zip(self.half)).any(|(u, half)| {
            let c = self.center.coords.dot(u);
            gap(extent(hull, u), (c - half, c + half)) >= reach
        });
        own || on_normals.iter().any(|s| self.apart(s, reach))
            || crossed(&self.axes, edges).any(|u| self.apart(&(u, extent(hull, &u)), reach))
    }

    /// Whether the box is at least `reach` from a shadow on its axis.
    pub(super) fn apart(&self, (u, shadow): &Shadow, reach: f64) -> bool {
        let c = self.center.coords.dot(u);
        let half: f64 = (self.axes.iter().zip(self.half))
            .map(|(a, h)| h * a.dot(u).abs())
            .sum();
        gap(*shadow, (c - half, c + half)) >= reach
    }

    pub(super) fn dist2(&self, p: Point3) -> f64 {
        let r = p - self.center;
        (0..3)
            .map(|k| (r.dot(&self.axes[k]).abs() - self.half[k]).max(0.0).powi(2))
            .sum()
    }
}

impl Aabb {
    /// Whether the box is at least `reach` from one of the `shadows`.
    pub(super) fn separated(&self, shadows: &[Shadow], reach: f64) -> bool {
        let mid = (self.min.coords + self.max.coords) * 0.5;
        let size = (self.max - self.min) * 0.5;
        shadows.iter().any(|(u, shadow)| {
            let (c, half) = (mid.dot(u), size.dot(&u.abs()));
            gap(*shadow, (c - half, c + half)) >= reach
        })
    }

    pub(super) fn dist2(&self, p: Point3) -> f64 {
        (0..3)
            .map(|k| {
                (self.min[k] - p[k])
                    .max(p[k] - self.max[k])
                    .max(0.0)
                    .powi(2)
            })
            .sum()
    }
    pub(super) fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.inf(&o.min),
            max: self.max.sup(&o.max),
        }
    }
}
