//! Where a face lies and which way it faces, for a programmer choosing the
//! faces a feature names (`cmm import --list`): its box, its area, and a
//! point on it near its middle with the outward normal there, from a grid
//! of the face's parameters (cell midpoints inside the trim) and the
//! points of its boundary.
use super::Face;
use crate::math::{Point3, Vec2, Vec3};

/// Cells per side of the parameter grid a summary samples.
pub const SUMMARY_GRID: usize = 48;

/// A face's extent and orientation, part coordinates (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceSummary {
    /// Corners of the box round the sampled points (the boundary's and
    /// the grid's inside the trim).
    pub lo: Point3,
    /// See [`Self::lo`].
    pub hi: Point3,
    /// Area by the midpoint rule over the grid's cells inside the trim,
    /// mm^2.
    pub area_mm2: f64,
    /// The sampled point nearest the face's centroid.
    pub at: Point3,
    /// The outward unit normal there.
    pub normal: Vec3,
}

impl Face {
    /// The face's summary from a `grid` x `grid` sampling of its parameter
    /// box; `None` when no cell midpoint lies inside its trim (a sliver
    /// narrower than a cell).
    pub fn summary(&self, grid: usize) -> Option<FaceSummary> {
        let (lo, hi) = self.parameter_box();
        let n = grid.max(1);
        let step = (hi - lo) / n as f64;
        let mut inside: Vec<(Vec2, Point3, f64)> = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let uv = lo + Vec2::new((i as f64 + 0.5) * step.x, (j as f64 + 0.5) * step.y);
                if !self.contains(uv) {
                    continue;
                }
                let d = self.surface.derivs(uv.x, uv.y, 1);
                let da = d.su().cross(&d.sv()).norm() * step.x * step.y;
                inside.push((uv, d.point(), da));
            }
        }
        let area_mm2: f64 = inside.iter().map(|s| s.2).sum();
        let centroid = inside
            .iter()
            .fold(Vec3::zeros(), |c, s| c + s.1.coords * s.2)
            / area_mm2.max(f64::MIN_POSITIVE);
        let (uv, at, _) = *inside.iter().min_by(|a, b| {
            let da = (a.1.coords - centroid).norm_squared();
            da.total_cmp(&(b.1.coords - centroid).norm_squared())
        })?;
        let first = (at, at);
        let (lo3, hi3) = (inside.iter().map(|s| s.1))
            .chain(self.boundary_points(n))
            .fold(first, |(l, h), p| (l.inf(&p), h.sup(&p)));
        Some(FaceSummary {
            lo: lo3,
            hi: hi3,
            area_mm2,
            at,
            normal: self.surface.normal(uv.x, uv.y),
        })
    }

    /// The box of the face's parameters: its trim's, else its domain.
    fn parameter_box(&self) -> (Vec2, Vec2) {
        let ((u0, u1), (v0, v1)) = self.surface.domain();
        let domain = (Vec2::new(u0, v0), Vec2::new(u1, v1));
        let Some(trim) = &self.trim else {
            return domain;
        };
        let far = (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY));
        let (lo, hi) = trim
            .segments()
            .fold(far, |(l, h), (a, _)| (l.inf(&a), h.sup(&a)));
        if lo.x <= hi.x && lo.y <= hi.y {
            (lo, hi)
        } else {
            domain
        }
    }

    /// Points of the face's boundary: the trim's vertices, else `n` points
    /// along each side of the domain.
    fn boundary_points(&self, n: usize) -> Vec<Point3> {
        let uvs: Vec<Vec2> = match &self.trim {
            Some(trim) => trim.segments().map(|(a, _)| a).collect(),
            None => {
                let (lo, hi) = self.parameter_box();
                (0..=n)
                    .flat_map(|k| {
                        let t = k as f64 / n as f64;
                        let (u, v) = (lo.x + (hi.x - lo.x) * t, lo.y + (hi.y - lo.y) * t);
                        [
                            Vec2::new(u, lo.y),
                            Vec2::new(u, hi.y),
                            Vec2::new(lo.x, v),
                            Vec2::new(hi.x, v),
                        ]
                    })
                    .collect()
            }
        };
        uvs.iter()
            .map(|uv| self.surface.point(uv.x, uv.y))
            .collect()
    }
}
