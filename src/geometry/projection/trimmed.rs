//! Closest point on the boundary of a trimmed face: each trim segment is a
//! straight line in (u, v) whose image on the surface is minimised over by a
//! bounded one-dimensional Newton iteration.
use super::{Foot, ProjectionError, ProjectionOptions};
use crate::geometry::{Jet2, NurbsSurface, SurfaceDerivs, Trim};
use crate::math::{Point3, Vec2};

/// The closest boundary point closer than `sqrt(best_dist2)`, if any.
pub(crate) fn closest_on_boundary(
    surface: &NurbsSurface,
    trim: &Trim,
    p: Point3,
    best_dist2: f64,
    opts: &ProjectionOptions,
) -> Result<Option<Foot>, ProjectionError> {
    let mut best: Option<Foot> = None;
    let mut bound = best_dist2;
    for (a, b) in trim.segments() {
        let (a, b) = (surface.clamp(a), surface.clamp(b));
        if segment_lower_bound2(surface, a, b, p) >= bound {
            continue;
        }
        let foot = minimise_on_segment(surface, a, b, p, opts);
        if foot.dist2 < bound {
            bound = foot.dist2;
            best = Some(foot);
        }
    }
    Ok(best)
}

/// A cheap lower bound of the squared distance from `p` to the image of the
/// segment: the distance to the chord minus a generous bulge allowance.
fn segment_lower_bound2(surface: &NurbsSurface, a: Vec2, b: Vec2, p: Point3) -> f64 {
    let (pa, pb, pm) = (
        surface.point(a.x, a.y),
        surface.point(b.x, b.y),
        surface.point(0.5 * (a.x + b.x), 0.5 * (a.y + b.y)),
    );
    let chord = pb - pa;
    let t = ((p - pa).dot(&chord) / chord.norm_squared().max(1e-300)).clamp(0.0, 1.0);
    let d = (p - (pa + chord * t)).norm();
    let bulge = 4.0 * (pm - (pa + chord * 0.5)).norm() + 1e-9;
    (d - bulge).max(0.0).powi(2)
}

fn foot_at(surface: &NurbsSurface, uv: Vec2, p: Point3) -> (Foot, SurfaceDerivs) {
    let d = surface.derivs(uv.x, uv.y, 2);
    (
        Foot {
            uv,
            d: Jet2::from(&d),
            dist2: (d.point() - p).norm_squared(),
            iterations: 0,
        },
        d,
    )
}

/// Bounded Newton on `t` in [0, 1] for `|S(a + t (b - a)) - p|^2`.
fn minimise_on_segment(
    surface: &NurbsSurface,
    a: Vec2,
    b: Vec2,
    p: Point3,
    opts: &ProjectionOptions,
) -> Foot {
    let e = b - a;
    let at = |t: f64| a + e * t;
    let mut t = [0.0, 0.5, 1.0]
        .into_iter()
        .min_by(|&x, &y| {
            let (fx, fy) = (
                surface.point(at(x).x, at(x).y),
                surface.point(at(y).x, at(y).y),
            );
            (fx - p).norm_squared().total_cmp(&(fy - p).norm_squared())
        })
        .unwrap_or(0.0);
    let (mut foot, mut d) = foot_at(surface, at(t), p);
    for it in 1..=opts.max_iterations {
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
        let (cand, cd) = foot_at(surface, at(next), p);
        if cand.dist2 >= foot.dist2 {
            let half = (t + next) * 0.5;
            let (hc, hd) = foot_at(surface, at(half), p);
            if hc.dist2 >= foot.dist2 {
                foot.iterations = it;
                return foot;
            }
            (t, foot, d) = (half, hc, hd);
            continue;
        }
        (t, foot, d) = (next, cand, cd);
    }
    foot
}
