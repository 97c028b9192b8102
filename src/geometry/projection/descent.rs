//! The line search of a Newton step and its fallback. A Newton step that,
//! clamped into the box, does not point downhill is not searched along,
//! and a line search takes only decreases of the squared distance beyond
//! its rounding. When no step helps, the iteration ends only at a
//! stationary point (to rounding); elsewhere a projected-gradient step is
//! tried.
use super::newton::{evaluate_at, gradient, Bounds, Foot};
use super::ProjectionOptions;
use crate::geometry::Jet2;
use crate::math::{Point3, Vec2};

/// What a line search did to the foot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Descent {
    /// The full Newton step lowered the distance (foot moved there).
    Full,
    /// A shorter step, or a projected-gradient step, did (foot moved).
    Partial,
    /// No step helped, and the foot is stationary to rounding (foot as
    /// it was).
    Stationary,
    /// No step helped though the foot is not stationary (foot as it was).
    None,
}

/// Relative rounding of a surface point as evaluated (units in the last
/// place of its magnitude), for the stationarity test.
const EVAL_ROUNDING_ULPS: f64 = 64.0;

/// Least decrease of the squared distance that a line search takes, in
/// units of `f64::EPSILON` times the squared distance (about a unit in the
/// last place of it): summing and rounding the squares changes it by a few
/// such units, so a smaller change tells nothing of descent. A search that
/// sees no more is left to the stationarity test, whose tolerance is wider.
const DECREASE_ROUNDING_ULPS: f64 = 4.0;

/// Line search along the Newton step from `foot` to `target` (a point of
/// the box), with the projected-gradient fallback, taken at once when the
/// step does not point downhill (a step clamped to a face of the box can
/// point uphill though the unclamped one points down).
pub(super) fn newton_line<F: Fn(Vec2, &mut Jet2)>(
    eval: &F,
    p: Point3,
    foot: &mut Foot,
    target: Vec2,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> Descent {
    let (x0, delta) = (foot.uv, target - foot.uv);
    // The full step lands on `target` exactly (a coordinate clamped to a
    // face stays on it); shorter ones are snapped to the faces they reach.
    let path = |t: f64| {
        if t == 1.0 {
            target
        } else {
            bounds.snap(x0 + delta * t)
        }
    };
    // Along a step that points uphill the backtracking can end at steps so
    // short that the rounding of the parameters decides whether the
    // distance drops, and the iteration creeps; the projected-gradient
    // step points downhill.
    let descends = gradient(&foot.d, p).dot(&delta) < 0.0;
    let found = if descends {
        backtrack(eval, p, foot, path, opts)
    } else {
        None
    };
    match found {
        Some(true) => Descent::Full,
        Some(false) => Descent::Partial,
        None if is_stationary(&foot.d, p, foot.uv, bounds, opts) => Descent::Stationary,
        None => gradient_step(eval, p, foot, bounds, opts),
    }
}

/// A projected-gradient step: each free coordinate moves by the residual's
/// component along its tangent (in mm, divided by the tangent's length),
/// the path clamped into the box, backtracking until the distance drops.
fn gradient_step<F: Fn(Vec2, &mut Jet2)>(
    eval: &F,
    p: Point3,
    foot: &mut Foot,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> Descent {
    let (x0, g) = (foot.uv, gradient(&foot.d, p));
    let lengths2 = [foot.d.su().norm_squared(), foot.d.sv().norm_squared()];
    let component = |k: usize| {
        let s2 = lengths2.get(k).copied().unwrap_or(0.0);
        if bounds.pinned(x0, g, k) || s2 <= 0.0 || !s2.is_finite() {
            0.0
        } else {
            -g[k] / s2
        }
    };
    let dir = Vec2::new(component(0), component(1));
    if dir == Vec2::zeros() || !dir.iter().all(|c| c.is_finite()) {
        return Descent::None;
    }
    match backtrack(eval, p, foot, |t| bounds.snap(x0 + dir * t), opts) {
        Some(_) => Descent::Partial,
        None => Descent::None,
    }
}

/// Backtracking: moves `foot` to the first of `path(1), path(1/2), ...`
/// that lowers the squared distance by more than its rounding (see
/// [`DECREASE_ROUNDING_ULPS`]) and tells whether it was `path(1)`; `None`
/// (with `foot` as it was) when none does.
fn backtrack<F: Fn(Vec2, &mut Jet2), X: Fn(f64) -> Vec2>(
    eval: &F,
    p: Point3,
    foot: &mut Foot,
    path: X,
    opts: &ProjectionOptions,
) -> Option<bool> {
    let (x0, dist0, it) = (foot.uv, foot.dist2, foot.iterations);
    let min_decrease = DECREASE_ROUNDING_ULPS * f64::EPSILON * dist0;
    let mut t = 1.0;
    for _ in 0..=opts.max_halvings {
        let x = path(t);
        if x == x0 {
            break;
        }
        evaluate_at(eval, p, foot, x, it);
        if foot.dist2 < dist0 - min_decrease {
            return Some(t == 1.0);
        }
        t *= 0.5;
    }
    // The evaluation is pure, so this restores the foot exactly.
    evaluate_at(eval, p, foot, x0, it);
    None
}

/// Whether the first-order conditions of a minimum over the box hold at
/// `x` to rounding: along each free coordinate (not held at a face by the
/// gradient) the residual's tangential component is at most
/// `stationary_tol_mm`, or at most what the rounding of the squared
/// distance lets a line search see.
pub(super) fn is_stationary(
    d: &Jet2,
    p: Point3,
    x: Vec2,
    bounds: &Bounds,
    opts: &ProjectionOptions,
) -> bool {
    let r = d.point() - p;
    let g = gradient(d, p);
    // A step of length s along a tangent with residual component c lowers
    // the squared distance by at most about c^2 (at s ~ c); the squared
    // distance carries an error of about 2 |r| ulp(|S|).
    let noise = EVAL_ROUNDING_ULPS * f64::EPSILON * r.norm() * (d.point().coords.norm() + r.norm());
    let tol = opts.stationary_tol_mm.max(noise.sqrt());
    let tangents = [d.su(), d.sv()];
    // A tangent carries a rounding error of about ulp(|Su| + |Sv|), which
    // decides its direction where it nearly vanishes (at a pole).
    let scale = tangents.iter().map(|t| t.norm()).sum::<f64>();
    let slack = EVAL_ROUNDING_ULPS * f64::EPSILON * scale * r.norm();
    (0..2).all(|k| {
        let s = tangents.get(k).map_or(0.0, |t| t.norm());
        bounds.pinned(x, g, k) || g[k].abs() <= tol * s + slack
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    /// The point `(1, 0, v)` for `u <= 0`, `(1 - shift, 0, v)` for `u > 0`:
    /// a step to `u > 0` brings it closer to the origin by `shift` (only
    /// the point of the jet is set; the line search reads no derivative).
    fn line(shift: f64) -> impl Fn(Vec2, &mut Jet2) {
        move |x: Vec2, out: &mut Jet2| {
            let along = if x.x > 0.0 { 1.0 - shift } else { 1.0 };
            out.d = [Vec3::zeros(); 6];
            out.d[0] = Vec3::new(along, 0.0, x.y);
        }
    }

    /// Whether a line search along u from (0, 0) on `line(shift)`, with
    /// the query point at the origin, takes a step.
    fn takes_step(shift: f64) -> bool {
        let (eval, p) = (line(shift), Point3::origin());
        let mut foot = Foot::unevaluated(Vec2::zeros());
        evaluate_at(&eval, p, &mut foot, Vec2::zeros(), 0);
        let path = |t: f64| Vec2::new(t, 0.0);
        let taken = backtrack(&eval, p, &mut foot, path, &ProjectionOptions::default());
        taken.is_some() && foot.uv != Vec2::zeros()
    }

    #[test]
    fn a_line_search_takes_no_decrease_within_rounding() {
        // 1 - EPSILON / 2 is the next double below 1: the squared distance
        // drops from 1 by one unit in the last place, 1 - EPSILON.
        assert!(!takes_step(f64::EPSILON / 2.0));
        assert!(takes_step(1e-6));
    }
}
