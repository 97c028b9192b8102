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

/// Joins curves whose end meets another's start (within `tol`, mm) and
/// closes those whose ends meet.
pub(super) fn stitch(mut curves: Vec<SectionCurve>, tol: f64) -> Vec<SectionCurve> {
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
    curves.iter().enumerate().position(|(m, c)| {
        m != k
            && !c.closed
            && c.points
                .first()
                .is_some_and(|p| (p.point - end).norm() <= tol)
    })
}

fn close_if_meeting(curve: &mut SectionCurve, tol: f64) {
    let n = curve.points.len();
    if n > 2 && (curve.points[0].point - curve.points[n - 1].point).norm() <= tol {
        curve.points.pop();
        curve.closed = true;
    }
}
