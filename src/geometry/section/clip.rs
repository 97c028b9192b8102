//! Clipping section curves to a trimmed face.
use super::{SectionCurve, SectionOptions, SectionPoint};
use crate::geometry::{NurbsSurface, Plane, Trim};
use crate::math::Vec2;

/// Bisection steps locating where a curve leaves the face.
const CROSSING_BISECTIONS: usize = 60;

/// The parts of `curve` that lie on the face, each ending exactly on the
/// trim boundary where it leaves it.
pub(super) fn clip(
    curve: SectionCurve,
    surface: &NurbsSurface,
    trim: &Trim,
    plane: &Plane,
    opts: &SectionOptions,
) -> Vec<SectionCurve> {
    let inside: Vec<bool> = curve.points.iter().map(|p| trim.contains(p.uv)).collect();
    if inside.iter().all(|&b| b) {
        return vec![curve];
    }
    let n = curve.points.len();
    // Start a closed curve at an outside point so no run wraps around.
    let start = if curve.closed {
        inside.iter().position(|&b| !b).unwrap_or(0)
    } else {
        0
    };
    let order: Vec<usize> = (0..n).map(|k| (start + k) % n).collect();
    let pairs = if curve.closed { n } else { n.saturating_sub(1) };
    let mut runs = Vec::new();
    let mut run: Vec<SectionPoint> = Vec::new();
    if inside[order[0]] {
        run.push(curve.points[order[0]]);
    }
    for k in 0..pairs {
        let (a, b) = (order[k], order[(k + 1) % n]);
        let (pa, pb) = (curve.points[a], curve.points[b]);
        match (inside[a], inside[b]) {
            (true, true) => run.push(pb),
            (true, false) => {
                run.push(crossing(surface, trim, plane, pa, pb, opts));
                runs.push(std::mem::take(&mut run));
            }
            (false, true) => {
                run.push(crossing(surface, trim, plane, pb, pa, opts));
                run.push(pb);
            }
            (false, false) => {}
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs.into_iter()
        .filter(|r| r.len() >= 2)
        .map(|points| SectionCurve {
            points,
            closed: false,
        })
        .collect()
}

/// The boundary point between an inside point `a` and an outside point `b`.
fn crossing(
    surface: &NurbsSurface,
    trim: &Trim,
    plane: &Plane,
    a: SectionPoint,
    b: SectionPoint,
    opts: &SectionOptions,
) -> SectionPoint {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let at = |t: f64| a.uv + (b.uv - a.uv) * t;
    for _ in 0..CROSSING_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if trim.contains(at(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let uv = onto_plane(surface, plane, at(lo), opts);
    let d = surface.derivs(uv.x, uv.y, 2);
    SectionPoint {
        face: a.face,
        uv,
        point: d.point(),
        normal: surface.normal_from(&d, uv),
    }
}

/// A few gradient-Newton steps in parameter space back onto the plane
/// (the chord between two section points leaves it by a sagitta).
fn onto_plane(surface: &NurbsSurface, plane: &Plane, mut uv: Vec2, opts: &SectionOptions) -> Vec2 {
    for _ in 0..20 {
        let d = surface.derivs(uv.x, uv.y, 1);
        let g = plane.signed_distance(d.point());
        let grad = Vec2::new(d.su().dot(&plane.normal()), d.sv().dot(&plane.normal()));
        if g.abs() <= opts.plane_tol_mm || grad.norm_squared() == 0.0 {
            break;
        }
        uv = surface.clamp(uv - grad * (g / grad.norm_squared()));
    }
    uv
}
