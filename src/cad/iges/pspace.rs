//! Parameter-space trims of B-spline faces: boundary curves given in the
//! surface's (u, v) plane (142 BPTR, 141 and 508 parameter curves), sampled
//! to the chord tolerance measured on the surface; and, where a face gives
//! only model-space curves, their points projected onto the surface.
use super::curves::{pieces, Piece};
use super::entities::{Affine, Model};
use super::records::Entry;
use crate::cad::error::CadResult;
use crate::cad::geom::EPS_UV;
use crate::cad::options::ImportOptions;
use crate::cad::sample::adaptive;
use crate::geometry::{NurbsSurface, ProjectionIndex, ProjectionOptions};
use crate::math::Point3;

/// A (u, v) pair.
pub type P2 = [f64; 2];

/// Appends `pts` to `out`, merging a repeated joint point.
pub fn join(out: &mut Vec<P2>, pts: Vec<P2>) {
    let skip = usize::from(out.last().is_some_and(|l| {
        pts.first()
            .is_some_and(|f| (l[0] - f[0]).hypot(l[1] - f[1]) < EPS_UV)
    }));
    out.extend(pts.into_iter().skip(skip));
}

/// Drops the closing point of a loop that repeats its first point.
pub fn close(mut out: Vec<P2>) -> Vec<P2> {
    if out.len() > 1
        && out
            .first()
            .zip(out.last())
            .is_some_and(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]) < EPS_UV)
    {
        out.pop();
    }
    out
}

/// The (u, v) polyline of parameter-space curve `e` on `surface`.
pub fn uv_curve(
    m: &Model,
    e: &Entry,
    surface: &NurbsSurface,
    opts: &ImportOptions,
) -> CadResult<Vec<P2>> {
    let mut out: Vec<P2> = Vec::new();
    for p in &pieces(m, e, &Affine::identity())? {
        join(&mut out, sample_piece(p, surface, opts));
    }
    Ok(out)
}

fn sample_piece(p: &Piece, surface: &NurbsSurface, opts: &ImportOptions) -> Vec<P2> {
    match p {
        Piece::Segment(a, b) => vec![[a.x, a.y], [b.x, b.y]],
        Piece::Arc(c, t0, t1) => {
            let f = |t: f64| {
                let q = c.eval(t);
                surface.point(q.x, q.y)
            };
            let initial = crate::cad::step::topology::initial_segments(c, *t0, *t1);
            adaptive(
                &f,
                *t0,
                *t1,
                initial,
                opts.chord_tolerance_mm,
                opts.max_edge_samples,
            )
            .into_iter()
            .map(|(t, _)| {
                let q = c.eval(t);
                [q.x, q.y]
            })
            .collect()
        }
    }
}

/// Projects model-space loop points onto `surface`; `Err` with the largest
/// miss (mm) when a point is farther than the projection tolerance.
pub fn projected_loop(
    surface: &NurbsSurface,
    index: &ProjectionIndex,
    points: &[Point3],
    opts: &ImportOptions,
) -> Result<Vec<P2>, String> {
    let mut out = Vec::with_capacity(points.len());
    let mut worst: f64 = 0.0;
    for p in points {
        let pr = index
            .project(surface, *p)
            .map_err(|e| format!("projection failed: {e}"))?;
        worst = worst.max(pr.distance);
        out.push([pr.uv.x, pr.uv.y]);
    }
    if worst > opts.projection_tolerance_mm {
        return Err(format!(
            "boundary lies up to {worst:.3e} mm off the surface (projection tolerance {:.1e} mm)",
            opts.projection_tolerance_mm
        ));
    }
    Ok(close(out))
}

/// The projection index of `surface` with default options.
pub fn index(surface: &NurbsSurface) -> ProjectionIndex {
    ProjectionIndex::new(surface, &ProjectionOptions::default())
}
