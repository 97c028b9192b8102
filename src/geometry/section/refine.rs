//! Chord refinement of a traced branch, with every point on the plane.
use super::{SectionCurve, SectionOptions, SectionPoint};
use crate::geometry::{NurbsSurface, Plane};
use crate::math::{Mat2, Point3, Vec2};

/// Consecutive points closer than this are one point, mm.
const DUPLICATE_MM: f64 = 1e-12;

/// Turns a branch of grid crossings into a refined section curve.
pub(super) fn refine_branch(
    surface: &NurbsSurface,
    face: usize,
    plane: &Plane,
    branch: &(Vec<Vec2>, bool),
    opts: &SectionOptions,
) -> SectionCurve {
    let (uvs, closed) = branch;
    let mut out: Vec<Vec2> = Vec::with_capacity(uvs.len() * 2);
    let pairs = uvs.len().saturating_sub(1) + usize::from(*closed);
    for k in 0..pairs {
        let (a, b) = (uvs[k], uvs[(k + 1) % uvs.len()]);
        out.push(a);
        let ends = ((a, surface.point(a.x, a.y)), (b, surface.point(b.x, b.y)));
        subdivide(surface, plane, ends, opts, opts.max_refine_depth, &mut out);
    }
    if !closed {
        out.extend(uvs.last().copied());
    }
    let mut points: Vec<SectionPoint> = out
        .into_iter()
        .map(|uv| section_point(surface, face, uv))
        .collect();
    // Crossings at grid nodes on the plane repeat; keep one of each.
    points.dedup_by(|b, a| (b.point - a.point).norm() <= DUPLICATE_MM);
    if *closed
        && points.len() > 1
        && (points[0].point - points[points.len() - 1].point).norm() <= DUPLICATE_MM
    {
        points.pop();
    }
    SectionCurve {
        points,
        closed: *closed,
    }
}

fn section_point(surface: &NurbsSurface, face: usize, uv: Vec2) -> SectionPoint {
    let d = surface.derivs(uv.x, uv.y, 2);
    SectionPoint {
        face,
        uv,
        point: d.point(),
        normal: surface.normal_from(&d, uv),
    }
}

/// Inserts points strictly between `a` and `b` (parameters with their
/// surface points) until every chord is within the chord tolerance of the
/// curve.
fn subdivide(
    surface: &NurbsSurface,
    plane: &Plane,
    ((a, pa), (b, pb)): ((Vec2, Point3), (Vec2, Point3)),
    opts: &SectionOptions,
    depth: usize,
    out: &mut Vec<Vec2>,
) {
    if depth == 0 {
        return;
    }
    let Some(m) = on_bisector(
        surface,
        plane,
        (pa, pb),
        0.5 * (a + b),
        (b - a).norm(),
        opts,
    ) else {
        return;
    };
    let pm = surface.point(m.x, m.y);
    if chord_distance(pa, pb, pm) <= opts.chord_tol_mm {
        return;
    }
    subdivide(surface, plane, ((a, pa), (m, pm)), opts, depth - 1, out);
    out.push(m);
    subdivide(surface, plane, ((m, pm), (b, pb)), opts, depth - 1, out);
}

fn chord_distance(a: Point3, b: Point3, p: Point3) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 == 0.0 {
        return (p - a).norm();
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// The point of the section halfway along the chord `pa -> pb`: Newton on
/// `g(u, v) = 0` (on the plane) and `(S - mid) . (pb - pa) = 0` (on the
/// chord's bisecting plane), from the parameter midpoint `start`. `None` when
/// it wanders further than `reach` in parameter space or does not settle.
fn on_bisector(
    surface: &NurbsSurface,
    plane: &Plane,
    (pa, pb): (Point3, Point3),
    start: Vec2,
    reach: f64,
    opts: &SectionOptions,
) -> Option<Vec2> {
    let (mid, t) = (pa + (pb - pa) * 0.5, pb - pa);
    let n = plane.normal();
    let mut uv = start;
    for _ in 0..50 {
        let d = surface.derivs(uv.x, uv.y, 1);
        let f = Vec2::new(
            plane.signed_distance(d.point()),
            (d.point() - mid).dot(&t) / t.norm().max(1e-300),
        );
        if f.x.abs() <= opts.plane_tol_mm && f.y.abs() <= opts.plane_tol_mm {
            return ((uv - start).norm() <= reach).then_some(uv);
        }
        let tn = t / t.norm().max(1e-300);
        let j = Mat2::new(
            d.su().dot(&n),
            d.sv().dot(&n),
            d.su().dot(&tn),
            d.sv().dot(&tn),
        );
        let step = j.try_inverse()? * f;
        if !step.iter().all(|c| c.is_finite()) {
            return None;
        }
        uv = surface.clamp(uv - step);
    }
    None
}
