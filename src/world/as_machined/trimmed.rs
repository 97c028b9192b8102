//! The as-machined part restricted to the faces' trims: what a search over
//! the true surface `q(u, v)` needs besides Newton on the whole face (the
//! bounds of the form, the per-cycle jets, the closest point on a trim
//! segment's image) and the trimmed closest point of one face.
use super::AsMachined;
use crate::geometry::projection::{minimise_with, Bounds, Foot};
use crate::geometry::{Jet2, ProjectionError, ProjectionOptions};
use crate::math::{Point3, Vec2};
use crate::workpiece::Workpiece;

impl AsMachined {
    /// Upper bound of `|h|` (the sum of the form terms' amplitudes) on
    /// face `face`, mm: the true face lies within this distance of the
    /// nominal one before the transform `T`.
    pub fn max_form_height(&self, face: usize) -> f64 {
        self.max_height(face)
    }

    /// Upper bound of the form's |h| on `face` at the nominal points of
    /// the box `lo..hi`, mm.
    pub fn max_form_height_over(&self, face: usize, lo: Point3, hi: Point3) -> f64 {
        self.face_terms(face)
            .map(|f| f.amplitude_over(lo, hi))
            .sum()
    }

    /// The linear part `L` of the transform `T(x) = L x + t`.
    pub(crate) fn linear_part(&self) -> &crate::math::Mat3 {
        self.affine.linear()
    }

    /// The translation `t` of the transform `T(x) = L x + t`, mm.
    pub(crate) fn translation(&self) -> crate::math::Vec3 {
        self.affine.offset()
    }

    /// Largest factor by which the transform `T` stretches lengths (at
    /// least 1): `T` moves a displacement of length `l` by at most this
    /// times `l`.
    pub fn stretch_factor(&self) -> f64 {
        self.stretch()
    }

    /// `q(u, v)` with its derivatives to second order on `face`, as the
    /// Newton iterations of the true closest-point searches evaluate it.
    pub(crate) fn true_jet_into(&self, wp: &Workpiece, face: usize, uv: Vec2, out: &mut Jet2) {
        self.jet_into(wp, face, uv, out);
    }

    /// The true closest point of a foot found by a search on `face`.
    pub(crate) fn finish_foot(
        &self,
        wp: &Workpiece,
        x: Point3,
        face: usize,
        foot: &Foot,
    ) -> super::TrueProjection {
        self.finish(wp, x, face, foot)
    }

    /// The closest point to `x` of the image under `q` of the parameter
    /// segment `a..b` of `face` (end points included).
    pub(crate) fn closest_on_segment(
        &self,
        wp: &Workpiece,
        face: usize,
        (a, b): (Vec2, Vec2),
        x: Point3,
        opts: &ProjectionOptions,
    ) -> Foot {
        let eval = |uv: Vec2, out: &mut Jet2| self.jet_into(wp, face, uv, out);
        minimise_on_segment(eval, (a, b), x, opts)
    }

    /// Newton's foot on `face` (whole face) from `uv`, moved onto the trim
    /// boundary when it lies outside the face's trim: the closest point of
    /// the trimmed face then lies on its boundary (for a foot found in the
    /// basin of the closest point, as the seeds of the nominal search give
    /// it).
    pub(super) fn trimmed_newton(
        &self,
        wp: &Workpiece,
        x: Point3,
        face: usize,
        uv: Vec2,
        bounds: &Bounds,
    ) -> Result<Foot, ProjectionError> {
        let eval = |p: Vec2, out: &mut Jet2| self.jet_into(wp, face, p, out);
        let foot = minimise_with(eval, x, uv, bounds, &wp.options)?;
        let Some(trim) = wp.faces.get(face).and_then(|f| f.trim.as_ref()) else {
            return Ok(foot);
        };
        if trim.contains(foot.uv) {
            return Ok(foot);
        }
        let Some(f) = wp.faces.get(face) else {
            return Ok(foot);
        };
        let mut best: Option<Foot> = None;
        for (a, b) in trim.segments() {
            let seg = (f.surface.clamp(a), f.surface.clamp(b));
            let found = self.closest_on_segment(wp, face, seg, x, &wp.options);
            if best.is_none_or(|b| found.dist2 < b.dist2) {
                best = Some(found);
            }
        }
        Ok(best.unwrap_or(foot))
    }
}

/// Bounded Newton on `t` in [0, 1] for `|Q(a + t (b - a)) - p|^2`, `Q`
/// given by its second-order jet `eval`, started from the best of the two
/// ends and the middle.
pub(crate) fn minimise_on_segment<F: Fn(Vec2, &mut Jet2)>(
    eval: F,
    (a, b): (Vec2, Vec2),
    p: Point3,
    opts: &ProjectionOptions,
) -> Foot {
    let e = b - a;
    let at = |t: f64| a + e * t;
    let foot_at = |t: f64| {
        let mut f = Foot::unevaluated(at(t));
        eval(f.uv, &mut f.d);
        f.dist2 = (f.d.point() - p).norm_squared();
        f
    };
    let (mut t, mut foot) = [0.0, 0.5, 1.0]
        .into_iter()
        .map(|t| (t, foot_at(t)))
        .min_by(|x, y| x.1.dist2.total_cmp(&y.1.dist2))
        .unwrap_or((0.0, foot_at(0.0)));
    for it in 1..=opts.max_iterations {
        let d = &foot.d;
        let r = d.point() - p;
        let c1 = d.su() * e.x + d.sv() * e.y;
        let c2 = d.suu() * (e.x * e.x) + d.suv() * (2.0 * e.x * e.y) + d.svv() * (e.y * e.y);
        let (g, h) = (c1.dot(&r), c1.dot(&c1) + c2.dot(&r));
        let step = if h > 0.0 { -g / h } else { -g.signum() * 0.25 };
        let next = (t + step).clamp(0.0, 1.0);
        if (c1 * (next - t)).norm() <= opts.step_tol_mm {
            foot.iterations = it;
            return foot;
        }
        let cand = foot_at(next);
        if cand.dist2 < foot.dist2 {
            (t, foot) = (next, cand);
            continue;
        }
        let half = 0.5 * (t + next);
        let hc = foot_at(half);
        if hc.dist2 >= foot.dist2 {
            foot.iterations = it;
            return foot;
        }
        (t, foot) = (half, hc);
    }
    foot
}
