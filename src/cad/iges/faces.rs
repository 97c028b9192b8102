//! Faces from a surface and its boundary loops: 144 trimmed surfaces, 143
//! bounded surfaces (141 boundaries), and the shared conversion of a
//! surface with model-space (and optionally parameter-space) loops.
use super::curves::{pieces, polyline};
use super::entities::{is_hard, Affine, Fields, Model};
use super::pspace::{close, index, join, projected_loop, uv_curve, P2};
use super::records::Entry;
use super::surfaces::{surface, Surf};
use crate::cad::convert::swept::Swept;
use crate::cad::convert::trim::{analytic_face, Extent, LoopPoints};
use crate::cad::error::CadResult;
use crate::cad::options::ImportOptions;
use crate::formats::workpiece::{SurfaceSpec, TrimSpec};
use crate::math::Point3;

/// A converted face: the surface (name empty), why it has no trim (when
/// `spec.trim` is `None`) and the surface entity type.
pub type FaceOut = (SurfaceSpec, Option<String>, i64);

/// One boundary loop of a face.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceLoop {
    /// Model-space points (mm) in traversal order.
    pub points: Vec<Point3>,
    /// The loop in the surface's (u, v) plane, when the file gives it.
    pub uv: Option<Vec<P2>>,
    /// True for the outer boundary.
    pub outer: bool,
}

/// The surface `surf` bounded by `loops`; `same_sense` false flips the
/// normal. Analytic and swept surfaces get exact trims from the model-space
/// loops; B-spline surfaces use the (u, v) loops, else projected points.
pub fn bounded(
    surf: &Surf,
    loops: &[FaceLoop],
    same_sense: bool,
    opts: &ImportOptions,
) -> Result<(SurfaceSpec, Option<String>), String> {
    let ext = Extent {
        margin_mm: opts.extent_margin_mm,
        axis_tol_mm: opts.point_tolerance_mm,
    };
    let lp: Vec<LoopPoints> = loops
        .iter()
        .map(|l| LoopPoints {
            points: l.points.clone(),
            outer: l.outer,
        })
        .collect();
    match surf {
        Surf::Analytic(a) => analytic_face(a, &lp, same_sense, ext).map(|s| (s, None)),
        Surf::Revolution { frame, profile, .. } => analytic_face(
            &Swept::Revolution(*frame, profile.clone()),
            &lp,
            same_sense,
            ext,
        )
        .map(|s| (s, None)),
        Surf::Extrusion { profile, dir, .. } => analytic_face(
            &Swept::Extrusion(profile.clone(), *dir),
            &lp,
            same_sense,
            ext,
        )
        .map(|s| (s, None)),
        Surf::Spline(spec, _) => {
            let mut spec = spec.clone();
            spec.reversed = !same_sense;
            match spline_trim(&spec, loops, opts) {
                Ok(t) => {
                    spec.trim = Some(t);
                    Ok((spec, None))
                }
                Err(why) => Ok((spec, Some(why))),
            }
        }
    }
}

fn spline_trim(
    spec: &SurfaceSpec,
    loops: &[FaceLoop],
    opts: &ImportOptions,
) -> Result<TrimSpec, String> {
    if loops.is_empty() {
        return Err("face has no boundary loops".into());
    }
    let mut uv: Vec<(bool, Vec<P2>)> = Vec::new();
    let mut projector = None;
    for l in loops {
        if let Some(p) = &l.uv {
            uv.push((l.outer, p.clone()));
            continue;
        }
        if projector.is_none() {
            let s = spec
                .to_surface()
                .map_err(|e| format!("surface cannot be evaluated: {e}"))?;
            let idx = index(&s);
            projector = Some((s, idx));
        }
        if let Some((s, idx)) = &projector {
            uv.push((l.outer, projected_loop(s, idx, &l.points, opts)?));
        }
    }
    crate::cad::step::pcurves::assemble(&uv)
}

/// A 144 trimmed surface (`place`: parent definition space to mm).
pub fn face144(m: &Model, e: &Entry, place: &Affine, opts: &ImportOptions) -> CadResult<FaceOut> {
    let f = m.fields(e)?;
    let place = place.then_inner(&m.transform(e)?);
    let base = f.target(1)?;
    let surf = surface(m, base, &place)?;
    let (n1, n2) = (f.int(2)?, f.count(3)?);
    let first = usize::from(n1 == 0);
    let loops = (first..=n2)
        .map(|k| boundary142(m, &f, 4 + k, &surf, &place, k == 0, opts))
        .collect::<CadResult<Vec<_>>>();
    let loops = match loops {
        Ok(l) => l,
        Err(x) if is_hard(&x) => return Err(x),
        Err(x) => {
            let s = surf.untrimmed().map_err(|r| m.err(e, r))?;
            return Ok((s, Some(x.to_string()), base.kind));
        }
    };
    let out = if n1 == 0 {
        natural_outer(&surf, loops, opts)
    } else {
        bounded(&surf, &loops, true, opts)
    };
    let (s, note) = out.map_err(|r| m.err(e, r))?;
    Ok((s, note, base.kind))
}

/// A face whose outer boundary is the surface's own domain boundary.
fn natural_outer(
    surf: &Surf,
    holes: Vec<FaceLoop>,
    opts: &ImportOptions,
) -> Result<(SurfaceSpec, Option<String>), String> {
    let Surf::Spline(_, [u0, u1, v0, v1]) = surf else {
        let note = (!holes.is_empty()).then(|| {
            "holes of a face bounded by its surface's own boundary are not applied".into()
        });
        return surf.untrimmed().map(|s| (s, note));
    };
    let mut loops = vec![FaceLoop {
        points: Vec::new(),
        uv: Some(vec![[*u0, *v0], [*u1, *v0], [*u1, *v1], [*u0, *v1]]),
        outer: true,
    }];
    loops.extend(holes);
    bounded(surf, &loops, true, opts)
}

/// The loop of a 142 curve on surface: (u, v) from BPTR on B-spline
/// surfaces, model-space points from CPTR.
fn boundary142(
    m: &Model,
    f: &Fields,
    k: usize,
    surf: &Surf,
    place: &Affine,
    outer: bool,
    opts: &ImportOptions,
) -> CadResult<FaceLoop> {
    let e = f.target(k)?;
    if e.kind != 142 {
        return Err(f.bad(k, &format!("points to entity {} (expected 142)", e.kind)));
    }
    let g = m.fields(e)?;
    let (bptr, cptr) = (g.target_opt(3)?, g.target_opt(4)?);
    let uv = match (surf, bptr) {
        (Surf::Spline(spec, _), Some(b)) => {
            let s = spec
                .to_surface()
                .map_err(|x| m.err(e, format!("surface cannot be evaluated: {x}")))?;
            Some(close(uv_curve(m, b, &s, opts)?))
        }
        _ => None,
    };
    let points = match cptr {
        Some(c) if uv.is_none() => model_points(m, c, place, opts)?,
        None if uv.is_none() => {
            return Err(m.err(e, "curve on surface has no usable boundary curve"))
        }
        _ => Vec::new(),
    };
    Ok(FaceLoop { points, uv, outer })
}

/// A model-space curve sampled to the chord tolerance, from start to end.
fn sampled(m: &Model, c: &Entry, place: &Affine, opts: &ImportOptions) -> CadResult<Vec<Point3>> {
    let ps = pieces(m, c, place)?;
    Ok(polyline(
        &ps,
        opts.chord_tolerance_mm,
        opts.max_edge_samples,
        opts.point_tolerance_mm,
    ))
}

/// A closed model-space curve sampled, closing point dropped.
fn model_points(
    m: &Model,
    c: &Entry,
    place: &Affine,
    opts: &ImportOptions,
) -> CadResult<Vec<Point3>> {
    let mut pts = sampled(m, c, place, opts)?;
    let closed = pts
        .first()
        .zip(pts.last())
        .is_some_and(|(a, b)| (a - b).norm() <= opts.point_tolerance_mm);
    if pts.len() > 1 && closed {
        pts.pop();
    }
    Ok(pts)
}

/// A 143 bounded surface: 141 boundaries, the first one outer.
pub fn face143(m: &Model, e: &Entry, place: &Affine, opts: &ImportOptions) -> CadResult<FaceOut> {
    let f = m.fields(e)?;
    let place = place.then_inner(&m.transform(e)?);
    let base = f.target(2)?;
    let surf = surface(m, base, &place)?;
    let n = f.count(3)?;
    let loops = (0..n)
        .map(|k| boundary141(m, &f, 4 + k, &surf, &place, k == 0, opts))
        .collect::<CadResult<Vec<_>>>()?;
    let (s, note) = bounded(&surf, &loops, true, opts).map_err(|r| m.err(e, r))?;
    Ok((s, note, base.kind))
}

fn boundary141(
    m: &Model,
    f: &Fields,
    k: usize,
    surf: &Surf,
    place: &Affine,
    outer: bool,
    opts: &ImportOptions,
) -> CadResult<FaceLoop> {
    let e = f.target(k)?;
    if e.kind != 141 {
        return Err(f.bad(k, &format!("points to entity {} (expected 141)", e.kind)));
    }
    let g = m.fields(e)?;
    let n = g.count(4)?;
    let spline = match surf {
        Surf::Spline(spec, _) => Some(
            spec.to_surface()
                .map_err(|x| m.err(e, format!("surface cannot be evaluated: {x}")))?,
        ),
        _ => None,
    };
    let (mut points, mut uv): (Vec<Point3>, Option<Vec<P2>>) = (Vec::new(), Some(Vec::new()));
    let mut at = 5;
    for _ in 0..n {
        let reverse = g.int(at + 1)? == 2;
        let k_psc = g.count(at + 2)?;
        let mut pts = sampled(m, g.target(at)?, place, opts)?;
        if reverse {
            pts.reverse();
        }
        points.extend(pts);
        match (&spline, k_psc, uv.as_mut()) {
            (Some(s), 1.., Some(acc)) => {
                let mut p = Vec::new();
                for j in 0..k_psc {
                    join(&mut p, uv_curve(m, g.target(at + 3 + j)?, s, opts)?);
                }
                if reverse {
                    p.reverse();
                }
                join(acc, p);
            }
            _ => uv = None,
        }
        at += 3 + k_psc;
    }
    points.dedup_by(|a, b| (*a - *b).norm() <= opts.point_tolerance_mm);
    let closed = points
        .first()
        .zip(points.last())
        .is_some_and(|(a, b)| points.len() > 1 && (a - b).norm() <= opts.point_tolerance_mm);
    if closed {
        points.pop();
    }
    Ok(FaceLoop {
        points,
        uv: uv.map(close),
        outer,
    })
}
