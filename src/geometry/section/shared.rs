//! Stretches along an edge that two faces share: the section of each face
//! includes its boundary, so the stretch comes once from each; one is kept.
use super::clip::Piece;
use super::SectionCurve;
use crate::math::Point3;

/// The pieces' curves, less every stretch along an edge that repeats one
/// of another face kept before it (within `tol`, mm).
pub(super) fn once(pieces: Vec<Piece>, tol: f64) -> Vec<SectionCurve> {
    let mut kept: Vec<Piece> = Vec::with_capacity(pieces.len());
    for p in pieces {
        let repeated = p.on_edge
            && kept
                .iter()
                .any(|k| k.on_edge && same_stretch(&k.curve, &p.curve, tol));
        if !repeated {
            kept.push(p);
        }
    }
    kept.into_iter().map(|p| p.curve).collect()
}

/// Whether two faces' curves are one stretch: both open or both closed,
/// and the ends and middle of each within `tol` of the other.
fn same_stretch(a: &SectionCurve, b: &SectionCurve, tol: f64) -> bool {
    let face = |c: &SectionCurve| c.points.first().map(|p| p.face);
    a.closed == b.closed && face(a) != face(b) && covers(a, b, tol) && covers(b, a, tol)
}

/// Whether the first, middle and last points of `b` lie within `tol` of
/// the polyline `a`.
fn covers(a: &SectionCurve, b: &SectionCurve, tol: f64) -> bool {
    let n = b.points.len();
    n > 0
        && [0, n / 2, n - 1]
            .iter()
            .all(|&k| polyline_distance(a, b.points[k].point) <= tol)
}

fn polyline_distance(c: &SectionCurve, p: Point3) -> f64 {
    let n = c.points.len();
    let pairs = if c.closed { n } else { n.saturating_sub(1) };
    let single = c
        .points
        .first()
        .map_or(f64::INFINITY, |q| (q.point - p).norm());
    (0..pairs)
        .map(|k| segment_distance(p, c.points[k].point, c.points[(k + 1) % n].point))
        .fold(single, f64::min)
}

fn segment_distance(p: Point3, a: Point3, b: Point3) -> f64 {
    let e = b - a;
    let t = ((p - a).dot(&e) / e.norm_squared().max(1e-300)).clamp(0.0, 1.0);
    (p - (a + e * t)).norm()
}
