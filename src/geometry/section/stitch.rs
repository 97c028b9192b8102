//! Orientation of section branches and stitching across faces and seams.
use super::SectionCurve;
use crate::geometry::Plane;

/// Orients a curve so its tangent follows `plane_normal x surface_normal`.
pub(super) fn orient(mut curve: SectionCurve, plane: &Plane) -> SectionCurve {
    let pts = &curve.points;
    let score: f64 = pts
        .windows(2)
        .map(|w| {
            plane
                .normal()
                .cross(&(w[0].normal + w[1].normal))
                .dot(&(w[1].point - w[0].point))
        })
        .sum();
    if score < 0.0 {
        curve.points.reverse();
    }
    curve
}

/// Joins curves whose end meets another's start and closes those whose
/// ends meet: first within `join_tol` (ends that coincide), then, among the
/// curves still open, within `gap_tol` (ends on an edge two faces share,
/// apart by how much the faces' trims disagree), mm.
pub(super) fn stitch(curves: Vec<SectionCurve>, join_tol: f64, gap_tol: f64) -> Vec<SectionCurve> {
    join(join(curves, join_tol), gap_tol)
}

/// One joining pass at `tol`, mm: each curve's end goes to the nearest
/// start within `tol`.
fn join(mut curves: Vec<SectionCurve>, tol: f64) -> Vec<SectionCurve> {
    let mut k = 0;
    while k < curves.len() {
        if curves[k].closed {
            k += 1;
            continue;
        }
        match find_successor(&curves, k, tol) {
            Some(m) => {
                let next = curves.remove(m);
                let at = if m < k { k - 1 } else { k };
                curves[at].points.extend(next.points.into_iter().skip(1));
                k = at;
            }
            None => {
                close_if_meeting(&mut curves[k], tol);
                k += 1;
            }
        }
    }
    curves
}

fn find_successor(curves: &[SectionCurve], k: usize, tol: f64) -> Option<usize> {
    let end = curves[k].points.last()?.point;
    let gap = |c: &SectionCurve| c.points.first().map(|p| (p.point - end).norm());
    curves
        .iter()
        .enumerate()
        .filter(|&(m, c)| m != k && !c.closed)
        .filter_map(|(m, c)| gap(c).filter(|&g| g <= tol).map(|g| (m, g)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(m, _)| m)
}

fn close_if_meeting(curve: &mut SectionCurve, tol: f64) {
    let n = curve.points.len();
    if n > 2 && (curve.points[0].point - curve.points[n - 1].point).norm() <= tol {
        curve.points.pop();
        curve.closed = true;
    }
}
