//! Trims of B-spline faces from the PCURVEs of their edges.
use super::access::{has_record, Ctx};
use super::surfaces::param_curve;
use super::topology::{edge_ends, initial_segments, Bound, EdgeEnds, EdgeSampler, FaceData};
use crate::cad::geom::{closest_on, Curve};
use crate::cad::nurbs::{breaks, NurbsCurve};
use crate::cad::options::ImportOptions;
use crate::cad::sample::adaptive;
use crate::formats::workpiece::TrimSpec;
use crate::geometry::NurbsSurface;
use crate::math::Point3;

type P2 = [f64; 2];

/// The face's trim in the surface's parameter domain, or why there is none.
pub fn pcurve_trim(
    ctx: &Ctx,
    _s: &mut EdgeSampler,
    face: &FaceData,
    spec: &NurbsSurface,
    opts: &ImportOptions,
) -> Result<TrimSpec, String> {
    let mut loops: Vec<(bool, Vec<P2>)> = Vec::new();
    for b in face.bounds.iter().filter(|b| !b.edges.is_empty()) {
        loops.push((b.outer, bound_uv(ctx, b, face.surface, spec, opts)?));
    }
    assemble(&loops)
}

/// A trim from `(is outer bound, loop)` pairs: the FACE_OUTER_BOUND (or the
/// largest loop) is the outer loop, the others are holes.
pub fn assemble(loops: &[(bool, Vec<P2>)]) -> Result<TrimSpec, String> {
    let outer_k = loops
        .iter()
        .position(|l| l.0)
        .or_else(|| largest(loops))
        .ok_or("face has no edge loops")?;
    let outer = loops.get(outer_k).map(|l| l.1.clone()).unwrap_or_default();
    let holes = loops
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != outer_k)
        .map(|(_, l)| l.1.clone())
        .collect();
    Ok(TrimSpec { outer, holes })
}

fn largest(loops: &[(bool, Vec<P2>)]) -> Option<usize> {
    let area = |pts: &Vec<P2>| {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in pts {
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
        (hi[0] - lo[0]) * (hi[1] - lo[1])
    };
    (0..loops.len()).max_by(|&a, &b| {
        let fa = loops.get(a).map_or(0.0, |l| area(&l.1));
        let fb = loops.get(b).map_or(0.0, |l| area(&l.1));
        fa.partial_cmp(&fb).unwrap_or(std::cmp::Ordering::Equal)
    })
}

fn bound_uv(
    ctx: &Ctx,
    b: &Bound,
    surface: u64,
    spec: &NurbsSurface,
    opts: &ImportOptions,
) -> Result<Vec<P2>, String> {
    let mut out: Vec<P2> = Vec::new();
    for &(edge, forward) in &b.edges {
        let candidates =
            edge_uv(ctx, edge, forward, surface, spec, opts).map_err(|e| e.to_string())??;
        let prev = out.last().copied();
        let dist = |c: &Vec<P2>| {
            prev.zip(c.first())
                .map_or(0.0, |(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        };
        let best = candidates.into_iter().min_by(|a, b| {
            dist(a)
                .partial_cmp(&dist(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        let best =
            best.ok_or_else(|| format!("edge #{edge} has no PCURVE on surface #{surface}"))?;
        let skip = usize::from(prev.is_some_and(|p| best.first() == Some(&p)));
        out.extend(best.into_iter().skip(skip));
    }
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    Ok(out)
}

type Nested = crate::cad::error::CadResult<Result<Vec<Vec<P2>>, String>>;

/// The sampled pcurves of `edge` on `surface`, in traversal direction.
fn edge_uv(
    ctx: &Ctx,
    edge: u64,
    forward: bool,
    surface: u64,
    spec: &NurbsSurface,
    opts: &ImportOptions,
) -> Nested {
    let ends = edge_ends(ctx, edge, opts)?;
    let (mut found, mut gaps) = (Vec::new(), Vec::new());
    for pc in pcurves_on(ctx, ends.geometry, surface)? {
        match fit_pcurve(&pc, spec, &ends, opts) {
            Ok(mut uv) => {
                if ends.same != forward {
                    uv.reverse();
                }
                found.push(uv);
            }
            Err(gap) => gaps.push(gap),
        }
    }
    if found.is_empty() {
        return Ok(Err(no_pcurve(edge, surface, &gaps)));
    }
    Ok(Ok(found))
}

fn no_pcurve(edge: u64, surface: u64, gaps: &[f64]) -> String {
    let detail = match gaps.iter().copied().reduce(f64::min) {
        None => "no PCURVE".to_string(),
        Some(gap) => format!("PCURVE ends miss the vertices by {gap:.3e} mm"),
    };
    format!("edge #{edge} on surface #{surface}: {detail}")
}

/// The pcurve sampled in the curve's direction between the edge's ends, or
/// the gap by which its ends miss the vertices.
fn fit_pcurve(
    pc: &Curve,
    spec: &NurbsSurface,
    e: &EdgeEnds,
    opts: &ImportOptions,
) -> Result<Vec<P2>, f64> {
    let uv = sample_uv(pc, spec, e.range.0, e.range.1, opts);
    if end_gap(&uv, spec, e.from, e.to) <= opts.pcurve_tolerance_mm {
        return Ok(uv);
    }
    let Curve::Nurbs(n) = pc else {
        return Err(end_gap(&uv, spec, e.from, e.to));
    };
    let uv = resampled(pc, n, spec, (e.from, e.to), e.closed, opts);
    let gap = end_gap(&uv, spec, e.from, e.to);
    if gap <= opts.pcurve_tolerance_mm {
        Ok(uv)
    } else {
        Err(gap)
    }
}

/// Samples a B-spline pcurve between the parameters whose surface points are
/// closest to the edge's ends (for pcurves parameterised unlike the 3-D curve).
fn resampled(
    pc: &Curve,
    n: &NurbsCurve,
    spec: &NurbsSurface,
    (from, to): (Point3, Point3),
    closed: bool,
    opts: &ImportOptions,
) -> Vec<P2> {
    let (lo, hi) = n.domain();
    if closed {
        return sample_uv(pc, spec, lo, hi, opts);
    }
    let on_surface = |t: f64| {
        let q = pc.eval(t);
        spec.point(q.x, q.y)
    };
    let breaks = breaks(n);
    let (ta, tb) = (
        closest_on(&on_surface, &breaks, from),
        closest_on(&on_surface, &breaks, to),
    );
    if ta <= tb {
        return sample_uv(pc, spec, ta, tb, opts);
    }
    let mut uv = sample_uv(pc, spec, tb, ta, opts);
    uv.reverse();
    uv
}

/// The larger distance between an edge end and its pcurve end's surface point.
fn end_gap(uv: &[P2], spec: &NurbsSurface, from: Point3, to: Point3) -> f64 {
    let at = |p: Option<&P2>, target: Point3| {
        p.map_or(f64::INFINITY, |q| (spec.point(q[0], q[1]) - target).norm())
    };
    at(uv.first(), from).max(at(uv.last(), to))
}

fn sample_uv(pc: &Curve, spec: &NurbsSurface, t0: f64, t1: f64, opts: &ImportOptions) -> Vec<P2> {
    let f = |t: f64| {
        let q = pc.eval(t);
        spec.point(q.x, q.y)
    };
    let initial = initial_segments(pc, t0, t1);
    let samples = adaptive(
        &f,
        t0,
        t1,
        initial,
        opts.chord_tolerance_mm,
        opts.max_edge_samples,
    );
    samples
        .into_iter()
        .map(|(t, _)| {
            let q = pc.eval(t);
            [q.x, q.y]
        })
        .collect()
}

/// The 2-D curves of the PCURVEs of a SURFACE_CURVE/SEAM_CURVE that lie on `surface`.
fn pcurves_on(ctx: &Ctx, geometry: u64, surface: u64) -> crate::cad::error::CadResult<Vec<Curve>> {
    let inst = ctx.inst(geometry)?;
    let assoc = inst.records.first().filter(|_| {
        ["SURFACE_CURVE", "SEAM_CURVE", "INTERSECTION_CURVE"]
            .iter()
            .any(|n| has_record(inst, n))
    });
    let Some(rec) = assoc else {
        return Ok(Vec::new());
    };
    let Some(super::parser::Value::List(items)) = rec.params.get(2) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for id in items.iter().filter_map(super::access::as_ref) {
        let Ok(pc) = ctx.args(id, "PCURVE") else {
            continue;
        };
        if pc.reference(1)? != surface {
            continue;
        }
        let rep = ctx.first(pc.reference(2)?)?;
        if let Some(&curve_id) = rep.refs(1)?.first() {
            out.push(param_curve(ctx, curve_id)?);
        }
    }
    Ok(out)
}
