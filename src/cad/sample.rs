//! Adaptive sampling of parametric curves to a chord tolerance.
use crate::math::Point3;

/// Deepest bisection of one initial interval.
const MAX_DEPTH: usize = 14;

/// Samples `f` on `[t0, t1]` so that the chord error is below `tol` (mm),
/// starting from `initial` equal intervals; returns `(t, point)` pairs in
/// order, both ends included, at most about `max_points` entries.
pub fn adaptive(
    f: &dyn Fn(f64) -> Point3,
    t0: f64,
    t1: f64,
    initial: usize,
    tol: f64,
    max_points: usize,
) -> Vec<(f64, Point3)> {
    let initial = initial.clamp(1, max_points.max(2));
    let mut out = vec![(t0, f(t0))];
    for k in 0..initial {
        let b = t0 + (t1 - t0) * (k + 1) as f64 / initial as f64;
        refine(f, b, tol, max_points, &mut out);
    }
    out
}

/// Appends samples of `(a, b]` to `out`, which ends with the point at `a`.
fn refine(f: &dyn Fn(f64) -> Point3, b: f64, tol: f64, max: usize, out: &mut Vec<(f64, Point3)>) {
    let mut stack = vec![(b, f(b), 0usize)];
    while let Some((t, p, depth)) = stack.pop() {
        let Some(&(ta, pa)) = out.last() else { return };
        let split =
            depth < MAX_DEPTH && out.len() + stack.len() < max && !flat(f, ta, pa, t, p, tol);
        if split {
            let tm = 0.5 * (ta + t);
            stack.push((t, p, depth + 1));
            stack.push((tm, f(tm), depth + 1));
        } else {
            out.push((t, p));
        }
    }
}

/// True when the curve between `a` and `b` stays within `tol` of the chord
/// (checked at the quarter points).
fn flat(f: &dyn Fn(f64) -> Point3, ta: f64, pa: Point3, tb: f64, pb: Point3, tol: f64) -> bool {
    [0.25, 0.5, 0.75].iter().all(|s| {
        let q = f(ta + (tb - ta) * s);
        distance_to_segment(q, pa, pb) <= tol
    })
}

/// Distance from `q` to the segment `a b`.
pub fn distance_to_segment(q: Point3, a: Point3, b: Point3) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let s = if len2 > 0.0 {
        ((q - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q - (a + ab * s)).norm()
}
