//! Face extents and trimming loops for elementary surfaces, computed from the
//! face's sampled 3-D boundary loops through the surface's own analytic
//! parameterisation (see [`NaturalSurface::natural`]).
use super::analytic::{AxisMap, NaturalSurface};
use crate::cad::geom::EPS_UV;
use crate::formats::workpiece::{SurfaceSpec, TrimSpec};
use crate::math::Point3;
use std::f64::consts::{PI, TAU};

/// One sampled boundary loop of a face, in traversal order.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopPoints {
    /// Points (mm) in the loop's direction (bound orientation applied).
    pub points: Vec<Point3>,
    /// True for a FACE_OUTER_BOUND.
    pub outer: bool,
}

/// Tolerances for the conversion (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    /// Margin added around the face's extent, mm.
    pub margin_mm: f64,
    /// Distance from an axis below which a point is on it (apex, pole), mm.
    pub axis_tol_mm: f64,
}

type P2 = [f64; 2];

struct NLoop {
    pts: Vec<P2>,
    outer: bool,
    degenerate: bool,
    net: [f64; 2],
}

/// Converts an elementary surface bounded by `loops` to a NURBS patch that
/// covers the face, with the face's trim in the NURBS parameter domain.
pub fn analytic_face(
    a: &impl NaturalSurface,
    loops: &[LoopPoints],
    same_sense: bool,
    ext: Extent,
) -> Result<SurfaceSpec, String> {
    let nloops: Vec<NLoop> = loops
        .iter()
        .filter_map(|l| natural_loop(a, l, ext.axis_tol_mm))
        .collect();
    let winding_axis = winding_axis(&nloops)?;
    let (nloops, mut ranges) = ranges(a, nloops, winding_axis, ext.margin_mm)?;
    if let (Some(0), Some(high)) = (winding_axis, single_winding_side(&nloops, same_sense)) {
        ranges[1] = a.extend_v(ranges[1], high);
    }
    let maps = a.maps(ranges[0], ranges[1]);
    let mut spec = a.to_nurbs(&maps);
    spec.reversed = !same_sense;
    let covered = [maps[0].range(), maps[1].range()];
    let trim = build_trim(&nloops, winding_axis, &covered, same_sense)?;
    spec.trim = Some(map_trim(trim, &maps));
    Ok(spec)
}

fn wrap(d: f64) -> f64 {
    d - TAU * (d / TAU).round()
}

fn natural_loop(a: &impl NaturalSurface, l: &LoopPoints, tol: f64) -> Option<NLoop> {
    let raw: Vec<(Option<f64>, f64)> = l.points.iter().map(|p| a.natural(*p, tol)).collect();
    let defined: Vec<usize> = (0..raw.len())
        .filter(|&k| raw.get(k).is_some_and(|r| r.0.is_some()))
        .collect();
    let degenerate = defined.is_empty();
    let mut pts: Vec<P2> = Vec::with_capacity(raw.len() + 2);
    for (k, (u, v)) in raw.iter().enumerate() {
        match u {
            Some(u) => pts.push([*u, *v]),
            None if degenerate => pts.push([0.0, *v]),
            None => {
                let prev = defined.iter().rev().find(|&&d| d < k).or(defined.last());
                let next = defined.iter().find(|&&d| d > k).or(defined.first());
                for n in [prev, next].into_iter().flatten() {
                    pts.push([raw.get(*n).and_then(|r| r.0).unwrap_or(0.0), *v]);
                }
            }
        }
    }
    pts.dedup_by(|x, y| (x[0] - y[0]).abs() < EPS_UV && (x[1] - y[1]).abs() < EPS_UV);
    if pts.is_empty() {
        return None;
    }
    let net = unwrap(&mut pts, a.periodic());
    Some(NLoop {
        pts,
        outer: l.outer,
        degenerate,
        net,
    })
}

/// Makes periodic coordinates continuous along the loop; returns the net change per axis.
fn unwrap(pts: &mut [P2], periodic: [bool; 2]) -> [f64; 2] {
    let mut net = [0.0; 2];
    for axis in 0..2 {
        if !periodic.get(axis).copied().unwrap_or(false) {
            continue;
        }
        for k in 1..pts.len() {
            let prev = pts.get(k - 1).map_or(0.0, |p| coord(p, axis));
            if let Some(p) = pts.get_mut(k) {
                let here = coord(*p, axis);
                *slot(p, axis) = prev + wrap(here - prev);
            }
        }
        let (first, last) = (
            pts.first().map_or(0.0, |p| coord(p, axis)),
            pts.last().map_or(0.0, |p| coord(p, axis)),
        );
        *slot(&mut net, axis) = last - first + wrap(first - last);
    }
    net
}

fn winds(l: &NLoop, axis: usize) -> bool {
    !l.degenerate && l.net.get(axis).is_some_and(|n| n.abs() > PI)
}

/// The axis along which some loop winds all the way round, if any.
fn winding_axis(loops: &[NLoop]) -> Result<Option<usize>, String> {
    let u = loops.iter().any(|l| winds(l, 0));
    let v = loops.iter().any(|l| winds(l, 1));
    match (u, v) {
        (true, true) => Err("boundary loops wind around both parameter directions".into()),
        (true, false) => Ok(Some(0)),
        (false, true) => Ok(Some(1)),
        _ => Ok(None),
    }
}

fn shift(l: &mut NLoop, axis: usize, by: f64) {
    l.pts.iter_mut().for_each(|p| *slot(p, axis) += by);
}

fn mean(l: &NLoop, axis: usize) -> f64 {
    l.pts.iter().map(|p| coord(p, axis)).sum::<f64>() / l.pts.len().max(1) as f64
}

fn bounds(loops: &[NLoop], axis: usize) -> Option<(f64, f64)> {
    let vals = loops
        .iter()
        .filter(|l| axis == 1 || !l.degenerate)
        .flat_map(|l| l.pts.iter().map(move |p| coord(p, axis)));
    vals.fold(None, |acc, x| {
        Some(acc.map_or((x, x), |(lo, hi): (f64, f64)| (lo.min(x), hi.max(x))))
    })
}

/// Natural parameter ranges `[(u0, u1), (v0, v1)]`.
type Ranges = [(f64, f64); 2];

/// Aligns periodic loops with each other and computes the natural ranges.
fn ranges(
    a: &impl NaturalSurface,
    mut loops: Vec<NLoop>,
    winding: Option<usize>,
    margin: f64,
) -> Result<(Vec<NLoop>, Ranges), String> {
    if a.periodic() == [false, false] && loops.iter().all(|l| l.degenerate) {
        return Err("face has no boundary edges".into());
    }
    let mut out: Ranges = [(0.0, 0.0); 2];
    for (axis, (slot, (periodic, metric))) in out
        .iter_mut()
        .zip(a.periodic().into_iter().zip(a.metric()))
        .enumerate()
    {
        let m = margin / metric;
        *slot = if periodic {
            periodic_range(&mut loops, axis, winding == Some(axis), m)
        } else if a.fixed(axis) {
            (0.0, 0.0)
        } else {
            linear_range(&loops, axis, m)?
        };
    }
    let vs: Vec<f64> = loops
        .iter()
        .flat_map(|l| l.pts.iter().map(|p| p[1]))
        .collect();
    let mean_v = vs.iter().sum::<f64>() / vs.len().max(1) as f64;
    out[1] = a.clamp_v(out[1].0, out[1].1, mean_v);
    Ok((loops, out))
}

fn linear_range(loops: &[NLoop], axis: usize, m: f64) -> Result<(f64, f64), String> {
    let (lo, hi) = bounds(loops, axis).ok_or("face has no bounds to take its extent from")?;
    Ok((lo - m, hi + m))
}

fn periodic_range(loops: &mut [NLoop], axis: usize, winding: bool, m: f64) -> (f64, f64) {
    let active = |l: &NLoop| axis == 1 || !l.degenerate;
    if winding {
        for l in loops.iter_mut().filter(|l| active(l)) {
            let lo = l
                .pts
                .iter()
                .map(|p| coord(p, axis))
                .fold(f64::INFINITY, f64::min);
            shift(l, axis, -TAU * (lo / TAU).floor());
        }
        return (0.0, TAU);
    }
    let reference = loops.iter().find(|l| active(l)).map(|l| mean(l, axis));
    let Some(reference) = reference else {
        return (0.0, TAU);
    };
    for l in loops.iter_mut().filter(|l| active(l)) {
        let k = ((reference - mean(l, axis)) / TAU).round();
        shift(l, axis, k * TAU);
    }
    let (lo, hi) = bounds(loops, axis).unwrap_or((0.0, TAU));
    if hi - lo + 2.0 * m >= TAU {
        let mid = 0.5 * (lo + hi);
        return (mid - PI, mid + PI);
    }
    (lo - m, hi + m)
}

fn build_trim(
    loops: &[NLoop],
    winding: Option<usize>,
    ranges: &Ranges,
    same_sense: bool,
) -> Result<(Vec<P2>, Vec<Vec<P2>>), String> {
    let real: Vec<&NLoop> = loops
        .iter()
        .filter(|l| !l.degenerate && l.pts.len() >= 2)
        .collect();
    let Some(axis) = winding else {
        return Ok(plain_trim(&real, ranges));
    };
    let (wind, holes): (Vec<&NLoop>, Vec<&NLoop>) = real.iter().partition(|l| winds(l, axis));
    let holes: Vec<Vec<P2>> = holes.iter().map(|l| l.pts.clone()).collect();
    let cut: Vec<Vec<P2>> = wind.iter().map(|l| cut_ascending(l, axis)).collect();
    let outer = match (cut.as_slice(), wind.first()) {
        ([a, b], _) => a.iter().chain(b.iter().rev()).copied().collect(),
        ([a], Some(l)) => close_one(a, l, axis, ranges, same_sense),
        _ => return Err(format!("{} boundary loops wind around the axis", cut.len())),
    };
    Ok((outer, holes))
}

/// No winding loop: the outer bound (or the largest loop) is the outer trim.
fn plain_trim(real: &[&NLoop], ranges: &Ranges) -> (Vec<P2>, Vec<Vec<P2>>) {
    let area = |l: &NLoop| {
        let (a, b) = (
            bounds(std::slice::from_ref(l), 0),
            bounds(std::slice::from_ref(l), 1),
        );
        a.zip(b).map_or(0.0, |(x, y)| (x.1 - x.0) * (y.1 - y.0))
    };
    let outer_k = real.iter().position(|l| l.outer).or_else(|| {
        (0..real.len()).max_by(|&i, &j| {
            real.get(i)
                .map(|l| area(l))
                .partial_cmp(&real.get(j).map(|l| area(l)))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    });
    let Some(outer_k) = outer_k else {
        let [(u0, u1), (v0, v1)] = *ranges;
        return (vec![[u0, v0], [u1, v0], [u1, v1], [u0, v1]], Vec::new());
    };
    let outer = real.get(outer_k).map(|l| l.pts.clone()).unwrap_or_default();
    let holes = real
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != outer_k)
        .map(|(_, l)| l.pts.clone())
        .collect();
    (outer, holes)
}

/// Closes a single winding loop along the domain edge on the face's side.
/// With exactly one loop winding round in u: whether the face lies on the
/// high-v side of it. The face is on the left of its loops in the (u, v)
/// plane when the face normal agrees with `Su x Sv` (same_sense), else on the right.
fn single_winding_side(loops: &[NLoop], same_sense: bool) -> Option<bool> {
    let mut winding = loops.iter().filter(|l| winds(l, 0));
    let l = winding.next()?;
    if winding.next().is_some() {
        return None;
    }
    Some(face_is_high(l, 0, same_sense))
}

fn face_is_high(l: &NLoop, axis: usize, same_sense: bool) -> bool {
    let forward = l.net.get(axis).copied().unwrap_or(0.0) > 0.0;
    let left_is_high = forward != (axis == 1);
    left_is_high == same_sense
}

fn close_one(a: &[P2], l: &NLoop, axis: usize, ranges: &Ranges, same_sense: bool) -> Vec<P2> {
    let other = 1 - axis.min(1);
    let high = face_is_high(l, axis, same_sense);
    let edge = ranges
        .get(other)
        .map_or(0.0, |r| if high { r.1 } else { r.0 });
    let corner = |t: f64| if axis == 0 { [t, edge] } else { [edge, t] };
    let mut out = a.to_vec();
    out.push(corner(TAU));
    out.push(corner(0.0));
    out
}

/// Splits a winding loop at the seam (0 / 2 pi) into a polyline ascending along `axis` from 0 to 2 pi.
fn cut_ascending(l: &NLoop, axis: usize) -> Vec<P2> {
    let net = l.net.get(axis).copied().unwrap_or(TAU);
    let mut pts = l.pts.clone();
    if let Some(first) = pts.first().copied() {
        pts.push({
            let mut p = first;
            *slot(&mut p, axis) += net;
            p
        });
    }
    // The loops were shifted to start in [0, 2 pi) (`periodic_range`), so a
    // loop spanning one period crosses 2 pi whichever way it runs.
    let boundary = TAU;
    let k = pts.windows(2).position(|w| matches!(w, [p, q] if (coord(p, axis) - boundary) * (coord(q, axis) - boundary) <= 0.0 && coord(p, axis) != coord(q, axis)));
    let Some(k) = k else { return sorted(pts, axis) };
    let (head, tail) = pts.split_at(k + 1);
    let crossing = interpolate(head.last().copied(), tail.first().copied(), axis, boundary);
    let mut out: Vec<P2>;
    if net > 0.0 {
        // head rises to 2 pi, tail from 2 pi on: tail moved down one period first.
        out = vec![crossing_shift(crossing, axis, -net)];
        out.extend(tail.iter().map(|p| crossing_shift(*p, axis, -net)));
        out.extend(head.iter().copied());
        out.push(crossing);
    } else {
        // head falls to 2 pi, tail from 2 pi down: head moved down one period after.
        out = vec![crossing];
        out.extend(tail.iter().copied());
        out.extend(head.iter().map(|p| crossing_shift(*p, axis, net)));
        out.push(crossing_shift(crossing, axis, net));
        out.reverse();
    }
    out.dedup();
    out
}

fn crossing_shift(mut p: P2, axis: usize, by: f64) -> P2 {
    *slot(&mut p, axis) += by;
    p
}

fn interpolate(p: Option<P2>, q: Option<P2>, axis: usize, at: f64) -> P2 {
    let (p, q) = (p.unwrap_or([at, 0.0]), q.unwrap_or([at, 0.0]));
    let s = if coord(q, axis) != coord(p, axis) {
        (at - coord(p, axis)) / (coord(q, axis) - coord(p, axis))
    } else {
        0.0
    };
    let mut r = [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])];
    *slot(&mut r, axis) = at;
    r
}

fn sorted(mut pts: Vec<P2>, axis: usize) -> Vec<P2> {
    pts.sort_by(|a, b| {
        coord(a, axis)
            .partial_cmp(&coord(b, axis))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    pts
}

fn map_trim((outer, holes): (Vec<P2>, Vec<Vec<P2>>), maps: &[AxisMap; 2]) -> TrimSpec {
    let [mu, mv] = maps;
    let map = |pts: Vec<P2>| -> Vec<[f64; 2]> {
        let mut out: Vec<[f64; 2]> = pts
            .into_iter()
            .map(|[u, v]| [mu.map(u), mv.map(v)])
            .collect();
        out.dedup();
        if out.len() > 1 && out.first() == out.last() {
            out.pop();
        }
        out
    };
    TrimSpec {
        outer: map(outer),
        holes: holes.into_iter().map(map).collect(),
    }
}

/// Coordinate `axis` (0 = u, anything else = v) of a parameter pair.
fn coord(p: impl std::borrow::Borrow<P2>, axis: usize) -> f64 {
    let p = *p.borrow();
    if axis == 0 {
        p[0]
    } else {
        p[1]
    }
}

/// Mutable coordinate `axis` (0 = u, anything else = v).
fn slot(p: &mut [f64; 2], axis: usize) -> &mut f64 {
    let [u, v] = p;
    if axis == 0 {
        u
    } else {
        v
    }
}
