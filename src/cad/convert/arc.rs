//! Exact circular arcs as rational quadratic B-splines.
//!
//! An arc of sweep `phi <= 90 deg` is one rational quadratic Bezier segment
//! with middle weight `cos(phi / 2)`. Its parameter `s in [0, 1]` relates to
//! the angle from the segment's middle by `tan(angle / 2) = tan(phi / 4) (2 s - 1)`,
//! which is what makes the mapping of edge points to parameters exact.
use crate::cad::geom::EPS_PARAM;
use std::f64::consts::FRAC_PI_2;

/// Tolerance on the sweep when counting quarter segments (rad).
const SWEEP_SLACK: f64 = 1e-9;

/// An angular range `[start, start + sweep]` split into `n` equal segments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    /// Start angle (rad).
    pub start: f64,
    /// Sweep (rad), in `(0, 2 pi]`.
    pub sweep: f64,
    /// Number of rational quadratic segments (1..=4).
    pub n: usize,
}

/// A unit-circle control point `(cos, sin)` (off the circle for middle points) with weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPoint {
    /// x coordinate on the unit circle's control polygon.
    pub c: f64,
    /// y coordinate.
    pub s: f64,
    /// Weight.
    pub w: f64,
}

impl Arc {
    /// The arc from `start` to `end` (`end > start`).
    pub fn new(start: f64, end: f64) -> Arc {
        let sweep = (end - start).max(EPS_PARAM);
        let n = ((sweep / FRAC_PI_2 - SWEEP_SLACK).ceil() as usize).clamp(1, 4);
        Arc { start, sweep, n }
    }

    fn seg(&self) -> f64 {
        self.sweep / self.n as f64
    }

    /// Knot vector `[a, a, a, a + d, a + d, ..., b, b, b]`: knots at the
    /// segment joints carry their angle, so the parameter equals the angle there.
    pub fn knots(&self) -> Vec<f64> {
        let mut k = vec![self.start; 3];
        for i in 1..self.n {
            let a = self.start + self.seg() * i as f64;
            k.extend([a, a]);
        }
        k.extend([self.start + self.sweep; 3]);
        k
    }

    /// The `2 n + 1` control points and weights.
    pub fn points(&self) -> Vec<ArcPoint> {
        let d = self.seg();
        let w = (0.5 * d).cos();
        let mut out = vec![unit(self.start, 1.0, 1.0)];
        for i in 0..self.n {
            let a = self.start + d * i as f64;
            out.push(unit(a + 0.5 * d, 1.0 / w, w));
            out.push(unit(a + d, 1.0, 1.0));
        }
        out
    }

    /// The B-spline parameter of the point at `angle` (unwrapped into the arc's range).
    pub fn param(&self, angle: f64) -> f64 {
        let d = self.seg();
        let k = ((angle - self.start) / d)
            .floor()
            .clamp(0.0, (self.n - 1) as f64);
        let mid = self.start + (k + 0.5) * d;
        let s = 0.5 + (0.5 * (angle - mid)).tan() / (2.0 * (0.25 * d).tan());
        (self.start + (k + s) * d)
            .max(self.start)
            .min(self.start + self.sweep)
    }
}

fn unit(angle: f64, scale: f64, w: f64) -> ArcPoint {
    ArcPoint {
        c: angle.cos() * scale,
        s: angle.sin() * scale,
        w,
    }
}
