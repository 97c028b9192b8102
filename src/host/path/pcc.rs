//! One parametric cubic curve segment (PCC) of a ball-centre path.

use crate::math::{Point3, Vec3};

/// Gauss-Legendre nodes on `[-1, 1]` (5 points, exact for degree 9).
const GL_NODES: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683_1,
    0.0,
    0.538_469_310_105_683_1,
    0.906_179_845_938_664,
];
/// Gauss-Legendre weights matching [`GL_NODES`].
const GL_WEIGHTS: [f64; 5] = [
    0.236_926_885_056_189_1,
    0.478_628_670_499_366_5,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
];

/// A cubic `P(u) = c0 + c1 u + c2 u^2 + c3 u^3` over the local parameter
/// `u` in `[0, h]`, where `h` is the chord length between its end points
/// (chord-length parameterisation), with its arc length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicSegment {
    coeffs: [Vec3; 4],
    param_len: f64,
    arc_len: f64,
    quad_panels: usize,
    /// Arc length from the start to the start of each quadrature panel.
    panel_arcs: [f64; MAX_QUAD_PANELS],
}

/// The parts of a segment's curvature `|P' x P''| / |P'|^3` at one
/// parameter (`P' = dP/du`, `P'' = d2P/du2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CurvatureParts {
    /// `|P'|`, mm/mm (about 1: the parameter is close to arc length).
    pub speed: f64,
    /// `|P' x P''|`, 1/mm.
    pub cross: f64,
    /// `|P''|`, 1/mm.
    pub d2: f64,
}

impl CurvatureParts {
    /// The curvature, 1/mm (0 where `|P'|` is 0).
    #[inline]
    pub fn curvature(&self) -> f64 {
        let speed = self.speed;
        if speed == 0.0 {
            return 0.0;
        }
        self.cross / (speed * speed * speed)
    }
}

/// Most Gauss-Legendre panels per segment (more are clamped to this).
pub const MAX_QUAD_PANELS: usize = 8;

impl CubicSegment {
    /// Segment from its start point, unit chord direction `d`, chord length
    /// `h` and the second derivatives `m0`, `m1` at its ends.
    pub(crate) fn from_moments(
        p0: Point3,
        d: Vec3,
        h: f64,
        m0: Vec3,
        m1: Vec3,
        quad_panels: usize,
    ) -> Self {
        let c1 = d - (m0 * 2.0 + m1) * (h / 6.0);
        let c3 = (m1 - m0) / (6.0 * h);
        let mut seg = CubicSegment {
            coeffs: [p0.coords, c1, m0 * 0.5, c3],
            param_len: h,
            arc_len: 0.0,
            quad_panels: quad_panels.clamp(1, MAX_QUAD_PANELS),
            panel_arcs: [0.0; MAX_QUAD_PANELS],
        };
        let w = seg.panel_width();
        for k in 1..seg.quad_panels {
            let before = seg.panel_arcs[k - 1];
            seg.panel_arcs[k] = before + seg.panel_len(w * (k - 1) as f64, w);
        }
        seg.arc_len = seg.arc_len_to(h);
        seg
    }

    /// Coefficients `[c0, c1, c2, c3]` of `P(u)` (mm, mm/mm, 1/mm, 1/mm^2).
    pub fn coefficients(&self) -> &[Vec3; 4] {
        &self.coeffs
    }

    /// Length of the local parameter range `[0, h]` (the chord), mm.
    pub fn param_len(&self) -> f64 {
        self.param_len
    }

    /// Arc length of the whole segment, mm.
    pub fn arc_len(&self) -> f64 {
        self.arc_len
    }

    /// Point at local parameter `u`, mm.
    pub fn position(&self, u: f64) -> Point3 {
        let [c0, c1, c2, c3] = self.coeffs;
        Point3::from(c0 + (c1 + (c2 + c3 * u) * u) * u)
    }

    /// First derivative `dP/du`.
    pub fn d1(&self, u: f64) -> Vec3 {
        let [_, c1, c2, c3] = self.coeffs;
        c1 + (c2 * 2.0 + c3 * (3.0 * u)) * u
    }

    /// Second derivative `d2P/du2`, 1/mm.
    pub fn d2(&self, u: f64) -> Vec3 {
        let [_, _, c2, c3] = self.coeffs;
        c2 * 2.0 + c3 * (6.0 * u)
    }

    /// Curvature at local parameter `u`, 1/mm (0 where `dP/du` vanishes).
    pub fn curvature(&self, u: f64) -> f64 {
        self.curvature_parts(u).curvature()
    }

    /// The parts the curvature at local parameter `u` is made of.
    #[inline]
    pub(crate) fn curvature_parts(&self, u: f64) -> CurvatureParts {
        let (d1, d2) = (self.d1(u), self.d2(u));
        CurvatureParts {
            speed: d1.norm(),
            cross: d1.cross(&d2).norm(),
            d2: d2.norm(),
        }
    }

    /// `|d2/du2 (dP/du x d2P/du2)| = 12 |c2 x c3|`, 1/mm^3: the second
    /// derivative of `dP/du x d2P/du2` (a quadratic in `u`) is constant.
    pub(crate) fn cross_d2(&self) -> f64 {
        let [_, _, c2, c3] = self.coeffs;
        12.0 * c2.cross(&c3).norm()
    }

    /// Arc length from `u = 0` to `u`, mm (composite Gauss-Legendre).
    ///
    /// The segment's parameter range is split into equal panels whose
    /// starts' arc lengths are kept, so a query integrates only the part of
    /// one panel up to `u` (one 5-node rule).
    pub fn arc_len_to(&self, u: f64) -> f64 {
        let w = self.panel_width();
        // `as usize` saturates: negative and NaN give panel 0.
        let k = ((u / w) as usize).min(self.quad_panels - 1);
        let u0 = w * k as f64;
        self.panel_arcs.get(k).copied().unwrap_or(0.0) + self.panel_len(u0, u - u0)
    }

    /// Parameter width of one quadrature panel.
    fn panel_width(&self) -> f64 {
        self.param_len / self.quad_panels as f64
    }

    /// Arc length over `[u0, u0 + width]` by one 5-node Gauss-Legendre rule.
    fn panel_len(&self, u0: f64, width: f64) -> f64 {
        let mid = u0 + 0.5 * width;
        let integral: f64 = GL_NODES
            .iter()
            .zip(&GL_WEIGHTS)
            .map(|(x, w)| w * self.d1(mid + 0.5 * width * x).norm())
            .sum();
        0.5 * width * integral
    }

    /// Local parameter at arc length `sl` from the segment start (clamped to
    /// the segment), by safeguarded Newton to `tol_mm`.
    pub fn param_at_arc(&self, sl: f64, tol_mm: f64, max_iters: usize) -> f64 {
        let sl = sl.clamp(0.0, self.arc_len);
        let (mut lo, mut hi) = (0.0, self.param_len);
        let mut u = sl / self.arc_len * self.param_len;
        for _ in 0..max_iters {
            let f = self.arc_len_to(u) - sl;
            if f.abs() <= tol_mm {
                break;
            }
            if f > 0.0 {
                hi = u
            } else {
                lo = u
            }
            let next = u - f / self.d1(u).norm();
            u = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
        }
        u.clamp(0.0, self.param_len)
    }
}
