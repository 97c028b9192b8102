//! Bounded Newton minimisation of `|S(u, v) - p|^2 / 2` over a parameter box,
//! with an active set for the box faces, a regularised Hessian and a
//! backtracking line search.
use super::{Projection, ProjectionError, ProjectionOptions};
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

impl Bounds {
    /// Whether `x` lies in the box (its boundary included).
    pub(crate) fn contains(&self, x: Vec2) -> bool {
        (self.lo.x..=self.hi.x).contains(&x.x) && (self.lo.y..=self.hi.y).contains(&x.y)
    }

    pub(crate) fn clamp(&self, x: Vec2) -> Vec2 {
        Vec2::new(
            x.x.clamp(self.lo.x, self.hi.x),
            x.y.clamp(self.lo.y, self.hi.y),
        )
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
        }
    }
}

/// Minimises the squared distance from `p` over `bounds`, starting at `start`.
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
    let mut foot = Foot::unevaluated(start);
    evaluate_at(&eval, p, &mut foot, bounds.clamp(start), 0);
    newton_from(&eval, p, &mut foot, None, bounds, opts)?;
    Ok(foot)
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
    let x0 = bounds.clamp(foot.uv);
    let prev_dist2 = (foot.d.point() - p).norm_squared();
    let delta = bounds.clamp(x0 + newton_step(&foot.d, p, x0, bounds)) - x0;
    let step = (foot.d.su() * delta.x + foot.d.sv() * delta.y).norm();
    evaluate_at(&eval, p, foot, x0 + delta, 1);
    if foot.dist2 <= prev_dist2 * (1.0 + 1e-12) + 1e-24 {
        newton_from(&eval, p, foot, Some(step), bounds, opts)
    } else {
        evaluate_at(&eval, p, foot, x0, 0);
        newton_from(&eval, p, foot, None, bounds, opts)
    }
}

/// Replaces `foot` by the evaluation at `x`.
#[inline(always)]
fn evaluate_at<F: Fn(Vec2, &mut Jet2)>(eval: &F, p: Point3, foot: &mut Foot, x: Vec2, it: usize) {
    foot.uv = x;
    eval(x, &mut foot.d);
    foot.dist2 = (foot.d.point() - p).norm_squared();
    foot.iterations = it;
}

/// The Newton iteration from an evaluated foot, in place; `full_step` is
/// the length of the full Newton step (no line-search halving) that led to
/// it, if any.
#[inline(always)]
fn newton_from<F: Fn(Vec2, &mut Jet2)>(
    eval: &F,
    p: Point3,
    foot: &mut Foot,
    mut full_step: Option<f64>,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> Result<(), ProjectionError> {
    let mut last_step = f64::INFINITY;
    for it in foot.iterations + 1..=opts.max_iterations {
        let delta = bounds.clamp(foot.uv + newton_step(&foot.d, p, foot.uv, bounds)) - foot.uv;
        last_step = (foot.d.su() * delta.x + foot.d.sv() * delta.y).norm();
        if last_step <= opts.step_tol_mm {
            foot.iterations = it;
            return Ok(());
        }
        if is_final(last_step, full_step, opts) {
            final_step(p, foot, delta, it);
            return Ok(());
        }
        match line_search(eval, p, foot, delta, opts) {
            Some(full) => {
                full_step = full.then_some(last_step);
                foot.iterations = it;
            }
            None => {
                foot.iterations = it;
                return Ok(());
            }
        }
    }
    Err(ProjectionError::NoConvergence {
        x: p.x,
        y: p.y,
        z: p.z,
        iterations: opts.max_iterations,
        last_step_mm: last_step,
    })
}

/// Whether a Newton step of `step` mm is the last one: it is tiny, or
/// quadratic convergence (error ~ K step^2, K estimated from the previous
/// full step as `step / previous^2`) predicts a foot error below
/// `final_error_mm` after it.
fn is_final(step: f64, previous: Option<f64>, opts: &ProjectionOptions) -> bool {
    if step <= opts.final_step_mm {
        return true;
    }
    let Some(prev) = previous.filter(|&d| d > 0.0) else {
        return false;
    };
    let predicted = step * step * step / (prev * prev);
    step <= opts.final_step_max_mm && step <= 0.1 * prev && predicted <= opts.final_error_mm
}

/// Inside the region of quadratic convergence the last Newton step is
/// taken without another evaluation: the foot at `x + delta` comes from the
/// second-order Taylor expansion of the current derivatives (error of the
/// order of the third derivative times the step cubed, far below the
/// Newton error left anyway). It is kept unless it makes the distance
/// visibly worse.
#[inline(always)]
fn final_step(p: Point3, foot: &mut Foot, delta: Vec2, it: usize) {
    foot.iterations = it;
    let dist2 = (foot.d.taylor_point(delta) - p).norm_squared();
    let slack = 1e-12 * foot.dist2 + 1e-24;
    if dist2 <= foot.dist2 + slack {
        foot.uv += delta;
        foot.d.advance(delta);
        foot.dist2 = dist2;
    }
}

/// Backtracking: moves `foot` to the first of `delta, delta/2, ...` that
/// lowers the distance and tells whether it was the full step; `None`
/// (with `foot` as it was) when none does.
fn line_search<F: Fn(Vec2, &mut Jet2)>(
    eval: &F,
    p: Point3,
    foot: &mut Foot,
    delta: Vec2,
    opts: &ProjectionOptions,
) -> Option<bool> {
    let (x0, dist0, it) = (foot.uv, foot.dist2, foot.iterations);
    let mut t = 1.0;
    for _ in 0..=opts.max_halvings {
        evaluate_at(eval, p, foot, x0 + delta * t, it);
        if foot.dist2 < dist0 {
            return Some(t == 1.0);
        }
        t *= 0.5;
    }
    // Rare: no step helped. The evaluation is pure, so this restores the
    // foot exactly.
    evaluate_at(eval, p, foot, x0, it);
    None
}

/// Newton step for the free variables (those not pinned at a box face with
/// the gradient pushing outward).
fn newton_step(d: &Jet2, p: Point3, x: Vec2, bounds: &Bounds) -> Vec2 {
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
    let pinned =
        |k: usize| (x[k] <= bounds.lo[k] && g[k] > 0.0) || (x[k] >= bounds.hi[k] && g[k] < 0.0);
    match (pinned(0), pinned(1)) {
        (false, false) => solve_2x2(h, g, metric),
        (true, false) => Vec2::new(0.0, -g.y / regularised(h.m22, metric)),
        (false, true) => Vec2::new(-g.x / regularised(h.m11, metric), 0.0),
        (true, true) => Vec2::zeros(),
    }
}

/// Smallest curvature of the model accepted, relative to the metric scale.
const MIN_CURVATURE_RATIO: f64 = 1e-9;
/// Shift applied to an indefinite Hessian, relative to the metric scale.
const INDEFINITE_SHIFT_RATIO: f64 = 1e-2;

fn regularised(h: f64, metric: f64) -> f64 {
    if h > MIN_CURVATURE_RATIO * metric {
        h
    } else {
        h.abs() + INDEFINITE_SHIFT_RATIO * metric + f64::MIN_POSITIVE
    }
}

fn solve_2x2(h: Mat2, g: Vec2, metric: f64) -> Vec2 {
    let tr = h.m11 + h.m22;
    let det = h.m11 * h.m22 - h.m12 * h.m21;
    // The smaller eigenvalue is at least det / tr when both are positive, so
    // a clearly positive-definite Hessian (smaller eigenvalue above the
    // threshold) needs neither the eigenvalue nor a shift.
    let clearly_convex = tr > 0.0 && det > MIN_CURVATURE_RATIO * metric * tr;
    let hs = if clearly_convex {
        h
    } else {
        let lambda_min = 0.5 * tr - (0.25 * tr * tr - det).max(0.0).sqrt();
        let shift = if lambda_min > MIN_CURVATURE_RATIO * metric {
            0.0
        } else {
            -lambda_min + INDEFINITE_SHIFT_RATIO * metric + f64::MIN_POSITIVE
        };
        h + Mat2::identity() * shift
    };
    let det_s = hs.m11 * hs.m22 - hs.m12 * hs.m21;
    if det_s <= 0.0 || !det_s.is_finite() {
        return Vec2::zeros();
    }
    Vec2::new(
        -(hs.m22 * g.x - hs.m12 * g.y) / det_s,
        -(hs.m11 * g.y - hs.m21 * g.x) / det_s,
    )
}
