//! Bounded Newton minimisation of `|S(u, v) - p|^2 / 2` over a parameter box,
//! with an active set for the box faces, a regularised Hessian and a
//! backtracking line search.
//!
//! A coordinate that reaches a face of the box is set to that face exactly
//! (never a rounding error short of it), so the face is then active and the
//! free coordinate gets its own one-dimensional Newton step. A line search
//! that finds no descent ends the iteration only at a stationary point;
//! elsewhere a projected-gradient step is tried first (see [`descent`]).
use super::descent::{self, Descent};
use super::{Projection, ProjectionError, ProjectionOptions, SearchStatus, UnconfirmedReason};
use crate::geometry::{Jet2, NurbsSurface};
use crate::math::{Mat2, Point3, Vec2, Vec3};

/// A parameter box (crate-internal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Lower corner.
    pub lo: Vec2,
    /// Upper corner.
    pub hi: Vec2,
}

/// A coordinate within this many units in the last place (of the box's
/// magnitude) of a face of the box is set to the face.
const SNAP_ULPS: f64 = 4.0;

/// A squared distance this much larger, relatively, than another (plus
/// [`ROUNDING_DIST2_MM2`]) counts as no worse: the rounding of squared
/// distances computed from different derivatives (dimensionless).
const ROUNDING_DIST2_RATIO: f64 = 1e-12;

/// The absolute part of that allowance, mm^2 (for feet at distance zero).
const ROUNDING_DIST2_MM2: f64 = 1e-24;

impl Bounds {
    /// Whether `x` lies in the box (its boundary included).
    pub(crate) fn contains(&self, x: Vec2) -> bool {
        (self.lo.x..=self.hi.x).contains(&x.x) && (self.lo.y..=self.hi.y).contains(&x.y)
    }

    /// `x` clamped into the box, each coordinate within a few units in the
    /// last place of a face set to that face exactly: a variable that lands
    /// on a bound is on it, and the bound is active from then on.
    #[inline]
    pub(crate) fn snap(&self, x: Vec2) -> Vec2 {
        Vec2::new(
            snap1(x.x, self.lo.x, self.hi.x),
            snap1(x.y, self.lo.y, self.hi.y),
        )
    }

    /// Whether coordinate `k` of `x` is held at a face of the box by the
    /// gradient `g` (which pushes it outward).
    #[inline]
    pub(crate) fn pinned(&self, x: Vec2, g: Vec2, k: usize) -> bool {
        (x[k] <= self.lo[k] && g[k] > 0.0) || (x[k] >= self.hi[k] && g[k] < 0.0)
    }
}

#[inline]
fn snap1(x: f64, lo: f64, hi: f64) -> f64 {
    let tol = SNAP_ULPS * f64::EPSILON * lo.abs().max(hi.abs()).max(hi - lo);
    if x <= lo + tol {
        lo
    } else if x >= hi - tol {
        hi
    } else {
        x
    }
}

/// A local minimum found by Newton (crate-internal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foot {
    /// Parameters.
    pub uv: Vec2,
    /// Derivatives there (to second order).
    pub d: Jet2,
    /// Squared distance, mm^2.
    pub dist2: f64,
    /// Iterations used.
    pub iterations: usize,
    /// Whether Newton confirmed the foot as a local minimum.
    pub status: SearchStatus,
}

impl Foot {
    /// A start at parameters `uv`, not evaluated yet (no derivatives,
    /// infinite distance).
    pub fn unevaluated(uv: Vec2) -> Foot {
        Foot {
            uv,
            d: Jet2 {
                d: [Vec3::zeros(); 6],
            },
            dist2: f64::INFINITY,
            iterations: 0,
            status: SearchStatus::Confirmed,
        }
    }

    /// Finishes the foot into a projection with the outward normal.
    pub fn into_projection(self, surface: &NurbsSurface, p: Point3) -> Projection {
        self.projection(surface, p)
    }

    /// [`Self::into_projection`] from a borrowed foot (no table copied).
    pub fn projection(&self, surface: &NurbsSurface, p: Point3) -> Projection {
        let normal = surface.normal_from_jet(&self.d, self.uv);
        let point = self.d.point();
        let distance = self.dist2.sqrt();
        let sign = if (p - point).dot(&normal) < 0.0 {
            -1.0
        } else {
            1.0
        };
        Projection {
            uv: self.uv,
            point,
            normal,
            distance,
            signed_distance: sign * distance,
            iterations: self.iterations,
            status: self.status,
        }
    }

    /// `Ok` for a confirmed foot, else the error the strict searches give.
    pub(crate) fn confirmed(&self, p: Point3) -> Result<(), ProjectionError> {
        match self.status {
            SearchStatus::Confirmed => Ok(()),
            SearchStatus::Unconfirmed { last_step_mm, .. } => Err(ProjectionError::NoConvergence {
                x: p.x,
                y: p.y,
                z: p.z,
                iterations: self.iterations,
                last_step_mm,
            }),
        }
    }
}

/// Minimises the squared distance from `p` over `bounds`, starting at
/// `start`; an error when the foot is not confirmed (see
/// [`local_minimum`] for the search that always answers).
pub(crate) fn minimise(
    surface: &NurbsSurface,
    p: Point3,
    start: Vec2,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> Result<Foot, ProjectionError> {
    minimise_with(
        |x, out: &mut Jet2| surface.jet2_into(x.x, x.y, out),
        p,
        start,
        bounds,
        opts,
    )
}

/// [`minimise`] for any parametric surface given by its second-order
/// derivative table at a parameter.
pub(crate) fn minimise_with<F: Fn(Vec2, &mut Jet2)>(
    eval: F,
    p: Point3,
    start: Vec2,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> Result<Foot, ProjectionError> {
    let foot = local_minimum(eval, p, start, bounds, opts);
    foot.confirmed(p)?;
    Ok(foot)
}

/// The local minimum of the squared distance from `p` over `bounds`
/// reached from `start`: always the best point found, with its status.
pub(crate) fn local_minimum<F: Fn(Vec2, &mut Jet2)>(
    eval: F,
    p: Point3,
    start: Vec2,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> Foot {
    let mut foot = Foot::unevaluated(start);
    evaluate_at(&eval, p, &mut foot, bounds.snap(start), 0);
    foot.status = newton_from(&eval, p, &mut foot, None, bounds, opts);
    foot
}

/// Like [`minimise_with`], in place: `foot` holds the derivative table of
/// an earlier foot at `foot.uv` (exact or Taylor-moved), and the first
/// Newton step is taken from it without evaluating the surface. If that
/// step does not lower the distance, Newton restarts from an evaluation at
/// the start. On return `foot` is the new foot (moved and updated in place,
/// so the per-cycle query copies no derivative tables).
#[inline(always)]
pub(crate) fn minimise_cached<F: Fn(Vec2, &mut Jet2)>(
    eval: F,
    p: Point3,
    foot: &mut Foot,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> Result<(), ProjectionError> {
    local_minimum_cached(eval, p, foot, bounds, opts);
    foot.confirmed(p)
}

/// [`minimise_cached`] that always answers: `foot.status` tells whether
/// the new foot is confirmed.
#[inline(always)]
pub(crate) fn local_minimum_cached<F: Fn(Vec2, &mut Jet2)>(
    eval: F,
    p: Point3,
    foot: &mut Foot,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) {
    let x0 = bounds.snap(foot.uv);
    let prev_dist2 = (foot.d.point() - p).norm_squared();
    let target = bounds.snap(x0 + newton_step(&foot.d, p, x0, bounds).0);
    let delta = target - x0;
    let step = (foot.d.su() * delta.x + foot.d.sv() * delta.y).norm();
    evaluate_at(&eval, p, foot, target, 1);
    let allowed = prev_dist2 * (1.0 + ROUNDING_DIST2_RATIO) + ROUNDING_DIST2_MM2;
    foot.status = if foot.dist2 <= allowed {
        newton_from(&eval, p, foot, Some(step), bounds, opts)
    } else {
        evaluate_at(&eval, p, foot, x0, 0);
        newton_from(&eval, p, foot, None, bounds, opts)
    };
}

/// Replaces `foot` by the evaluation at `x`.
#[inline(always)]
pub(super) fn evaluate_at<F: Fn(Vec2, &mut Jet2)>(
    eval: &F,
    p: Point3,
    foot: &mut Foot,
    x: Vec2,
    it: usize,
) {
    foot.uv = x;
    eval(x, &mut foot.d);
    foot.dist2 = (foot.d.point() - p).norm_squared();
    foot.iterations = it;
}

/// The Newton iteration from an evaluated foot, in place; `full_step` is
/// the length of the full Newton step (no line-search halving) that led to
/// it, if any. Returns whether the foot it leaves is confirmed.
#[inline(always)]
fn newton_from<F: Fn(Vec2, &mut Jet2)>(
    eval: &F,
    p: Point3,
    foot: &mut Foot,
    mut full_step: Option<f64>,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> SearchStatus {
    let mut last_step = f64::INFINITY;
    for it in foot.iterations + 1..=opts.max_iterations {
        let (step, pure) = newton_step(&foot.d, p, foot.uv, bounds);
        let target = bounds.snap(foot.uv + step);
        let delta = target - foot.uv;
        last_step = (foot.d.su() * delta.x + foot.d.sv() * delta.y).norm();
        foot.iterations = it;
        // A short step ends the search only where the first-order
        // conditions hold: a regularised step is shortened by its shift,
        // and at a pole the gradient along the collapsed edge vanishes, so
        // that variable may look held at a face before it has moved.
        if last_step <= opts.step_tol_mm
            && descent::is_stationary(&foot.d, p, foot.uv, bounds, opts)
        {
            return SearchStatus::Confirmed;
        }
        if pure && is_final(last_step, full_step, bend_mm(&foot.d, delta), opts) {
            if near_collapsed(&foot.d) {
                // Next to a pole the Taylor expansion is no model of the
                // surface (the normal turns within rounding of it): the
                // last step is evaluated.
                evaluate_at(eval, p, foot, target, it);
            } else {
                final_step(p, foot, target, it);
            }
            if descent::is_stationary(&foot.d, p, foot.uv, bounds, opts) {
                return SearchStatus::Confirmed;
            }
            // Not a minimum after all: on from an exact evaluation there.
            evaluate_at(eval, p, foot, foot.uv, it);
            full_step = None;
            continue;
        }
        match descent::newton_line(eval, p, foot, target, bounds, opts) {
            Descent::Full => full_step = Some(last_step),
            Descent::Partial => full_step = None,
            Descent::Stationary => return SearchStatus::Confirmed,
            Descent::None => {
                return SearchStatus::Unconfirmed {
                    reason: UnconfirmedReason::NoDescent,
                    last_step_mm: last_step,
                }
            }
        }
    }
    SearchStatus::Unconfirmed {
        reason: UnconfirmedReason::IterationLimit,
        last_step_mm: last_step,
    }
}

/// Whether a Newton step of `step` mm is the last one: it is tiny and the
/// surface bends by at most `final_bend_mm` along it (`bend`, mm: near a
/// pole a step short in mm can still be long in the parameter, and
/// Newton's error after it is of the order of this bend), or quadratic
/// convergence (error ~ K step^2, K estimated from the previous full step
/// as `step / previous^2`) predicts a foot error below `final_error_mm`
/// after it.
fn is_final(step: f64, previous: Option<f64>, bend: f64, opts: &ProjectionOptions) -> bool {
    if step <= opts.final_step_mm && bend <= opts.final_bend_mm {
        return true;
    }
    let Some(prev) = previous.filter(|&d| d > 0.0) else {
        return false;
    };
    let predicted = step * step * step / (prev * prev);
    step <= opts.final_step_max_mm && step <= 0.1 * prev && predicted <= opts.final_error_mm
}

/// Below this ratio of the shorter tangent to the longer a foot lies next
/// to a collapsed edge (a pole), where derivatives of higher order dwarf
/// the tangent that vanishes.
const COLLAPSED_TANGENT_RATIO: f64 = 1e-6;

/// Whether the jet `d` is that of a point next to a collapsed edge.
#[inline]
fn near_collapsed(d: &Jet2) -> bool {
    let (a, b) = (d.su().norm_squared(), d.sv().norm_squared());
    let r2 = COLLAPSED_TANGENT_RATIO * COLLAPSED_TANGENT_RATIO;
    a < r2 * b || b < r2 * a
}

/// The second-order Taylor term of the surface along `delta`, mm.
#[inline]
fn bend_mm(d: &Jet2, delta: Vec2) -> f64 {
    let (du, dv) = (delta.x, delta.y);
    ((d.suu() * (du * du) + d.suv() * (2.0 * du * dv) + d.svv() * (dv * dv)) * 0.5).norm()
}

/// Inside the region of quadratic convergence the last Newton step (to
/// `target`) is taken without another evaluation: the foot there comes
/// from the second-order Taylor expansion of the current derivatives
/// (error of the order of the third derivative times the step cubed, far
/// below the Newton error left anyway). It is kept unless it makes the
/// distance visibly worse.
#[inline(always)]
fn final_step(p: Point3, foot: &mut Foot, target: Vec2, it: usize) {
    foot.iterations = it;
    let delta = target - foot.uv;
    let dist2 = (foot.d.taylor_point(delta) - p).norm_squared();
    let slack = ROUNDING_DIST2_RATIO * foot.dist2 + ROUNDING_DIST2_MM2;
    if dist2 <= foot.dist2 + slack {
        foot.uv = target;
        foot.d.advance(delta);
        foot.dist2 = dist2;
    }
}

/// The gradient of `|S - p|^2 / 2` in (u, v).
#[inline]
pub(super) fn gradient(d: &Jet2, p: Point3) -> Vec2 {
    let r = d.point() - p;
    Vec2::new(d.su().dot(&r), d.sv().dot(&r))
}

/// Newton step for the free variables (those not pinned at a box face with
/// the gradient pushing outward), and whether it is the pure Newton step
/// (no shift of an indefinite or nearly singular Hessian).
///
/// Each variable is measured in its own scale, the length of its tangent:
/// near a pole or a collapsed edge one tangent is far shorter than the
/// other, and a shift sized by the longer one would stall the shorter.
pub(super) fn newton_step(d: &Jet2, p: Point3, x: Vec2, bounds: &Bounds) -> (Vec2, bool) {
    let r = d.point() - p;
    let (su, sv) = (d.su(), d.sv());
    let g = Vec2::new(su.dot(&r), sv.dot(&r));
    let h = Mat2::new(
        su.dot(&su) + d.suu().dot(&r),
        su.dot(&sv) + d.suv().dot(&r),
        su.dot(&sv) + d.suv().dot(&r),
        sv.dot(&sv) + d.svv().dot(&r),
    );
    let metric = su.norm_squared() + sv.norm_squared();
    let floor = SCALE_FLOOR_RATIO * metric + f64::MIN_POSITIVE;
    let scale = Vec2::new(su.norm_squared().max(floor), sv.norm_squared().max(floor));
    match (bounds.pinned(x, g, 0), bounds.pinned(x, g, 1)) {
        (false, false) => solve_scaled(h, g, scale),
        (true, false) => {
            let (hh, pure) = regularised(h.m22, scale.y);
            (Vec2::new(0.0, -g.y / hh), pure)
        }
        (false, true) => {
            let (hh, pure) = regularised(h.m11, scale.x);
            (Vec2::new(-g.x / hh, 0.0), pure)
        }
        (true, true) => (Vec2::zeros(), true),
    }
}

/// Smallest curvature of the model accepted, relative to the metric scale.
const MIN_CURVATURE_RATIO: f64 = 1e-9;
/// Shift applied to an indefinite Hessian, relative to the metric scale.
const INDEFINITE_SHIFT_RATIO: f64 = 1e-2;
/// Smallest scale of a variable, relative to the sum of both (a tangent
/// that vanishes at a collapsed edge).
const SCALE_FLOOR_RATIO: f64 = 1e-12;

fn regularised(h: f64, metric: f64) -> (f64, bool) {
    if h > MIN_CURVATURE_RATIO * metric {
        (h, true)
    } else {
        (
            h.abs() + INDEFINITE_SHIFT_RATIO * metric + f64::MIN_POSITIVE,
            false,
        )
    }
}

/// [`solve_2x2`] in the coordinates where each variable is scaled by the
/// square root of `scale` (about a millimetre on the surface per unit).
fn solve_scaled(h: Mat2, g: Vec2, scale: Vec2) -> (Vec2, bool) {
    let q = Vec2::new(scale.x.sqrt(), scale.y.sqrt());
    let hs = Mat2::new(
        h.m11 / scale.x,
        h.m12 / (q.x * q.y),
        h.m21 / (q.x * q.y),
        h.m22 / scale.y,
    );
    let (ys, pure) = solve_2x2(hs, Vec2::new(g.x / q.x, g.y / q.y), 2.0);
    (Vec2::new(ys.x / q.x, ys.y / q.y), pure)
}

fn solve_2x2(h: Mat2, g: Vec2, metric: f64) -> (Vec2, bool) {
    let tr = h.m11 + h.m22;
    let det = h.m11 * h.m22 - h.m12 * h.m21;
    // The smaller eigenvalue is at least det / tr when both are positive, so
    // a clearly positive-definite Hessian (smaller eigenvalue above the
    // threshold) needs neither the eigenvalue nor a shift.
    let clearly_convex = tr > 0.0 && det > MIN_CURVATURE_RATIO * metric * tr;
    let (hs, pure) = if clearly_convex {
        (h, true)
    } else {
        let lambda_min = 0.5 * tr - (0.25 * tr * tr - det).max(0.0).sqrt();
        if lambda_min > MIN_CURVATURE_RATIO * metric {
            (h, true)
        } else {
            let shift = -lambda_min + INDEFINITE_SHIFT_RATIO * metric + f64::MIN_POSITIVE;
            (h + Mat2::identity() * shift, false)
        }
    };
    let det_s = hs.m11 * hs.m22 - hs.m12 * hs.m21;
    if det_s <= 0.0 || !det_s.is_finite() {
        return (Vec2::zeros(), false);
    }
    let step = Vec2::new(
        -(hs.m22 * g.x - hs.m12 * g.y) / det_s,
        -(hs.m11 * g.y - hs.m21 * g.x) / det_s,
    );
    (step, pure)
}
