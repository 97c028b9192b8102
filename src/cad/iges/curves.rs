//! IGES curves as pieces: 100 circular arcs, 102 composites, 104 ellipse
//! arcs, 106 polylines, 110 lines and 126 rational B-splines, mapped by
//! their 124 transformations (and the caller's placement).
use super::entities::{Affine, Fields, Model, MAX_CHAIN};
use super::records::Entry;
use crate::cad::error::CadResult;
use crate::cad::geom::{angle, Curve, Frame, EPS_PARAM};
use crate::cad::nurbs::{new_curve, NurbsCurve};
use crate::cad::sample::adaptive;
use crate::math::{Point3, Vec3};
use std::f64::consts::TAU;

/// One piece of a curve, in the direction of the curve's parameter.
#[derive(Debug, Clone, PartialEq)]
pub enum Piece {
    /// Straight segment.
    Segment(Point3, Point3),
    /// Curve over `[t0, t1]`.
    Arc(Curve, f64, f64),
}

impl Piece {
    /// First point.
    pub fn start(&self) -> Point3 {
        match self {
            Piece::Segment(a, _) => *a,
            Piece::Arc(c, t0, _) => c.eval(*t0),
        }
    }

    /// Last point.
    pub fn end(&self) -> Point3 {
        match self {
            Piece::Segment(_, b) => *b,
            Piece::Arc(c, _, t1) => c.eval(*t1),
        }
    }
}

/// Most entities visited while expanding one curve (guards shared and
/// cyclic composite structures).
const MAX_VISITS: usize = 100_000;

/// The pieces of curve entity `e`; `place` maps the parent's definition
/// space to the target space (model mm, or a surface's parameter plane).
pub fn pieces(m: &Model, e: &Entry, place: &Affine) -> CadResult<Vec<Piece>> {
    let mut stack = Vec::new();
    let mut budget = MAX_VISITS;
    pieces_in(m, e, place, &mut stack, &mut budget)
}

fn pieces_in(
    m: &Model,
    e: &Entry,
    place: &Affine,
    stack: &mut Vec<u64>,
    budget: &mut usize,
) -> CadResult<Vec<Piece>> {
    if stack.contains(&e.seq) || stack.len() > MAX_CHAIN {
        stack.push(e.seq);
        return Err(m.cycle(e, stack));
    }
    *budget = budget
        .checked_sub(1)
        .ok_or_else(|| m.err(e, "composite curve expands to too many entities"))?;
    let f = m.fields(e)?;
    let tr = place.then_inner(&m.transform(e)?);
    match e.kind {
        102 => {
            let n = f.count(1)?;
            let mut out = Vec::new();
            stack.push(e.seq);
            for k in 0..n {
                out.extend(pieces_in(m, f.target(2 + k)?, &tr, stack, budget)?);
            }
            stack.pop();
            Ok(out)
        }
        110 => {
            let c = f.reals(1, 6)?;
            let p = |k: usize| tr.apply(point_at(&c, k));
            Ok(vec![Piece::Segment(p(0), p(3))])
        }
        106 => polyline106(&f, &tr),
        100 => arc100(&f, &tr).map(|p| vec![p]),
        104 => ellipse104(&f, &tr).map(|p| vec![p]),
        126 => curve126(&f, &tr).map(|(c, t0, t1)| vec![Piece::Arc(Curve::Nurbs(c), t0, t1)]),
        other => Err(m.err(e, format!("unsupported curve type {other}"))),
    }
}

fn point_at(c: &[f64], k: usize) -> Point3 {
    let g = |i: usize| c.get(k + i).copied().unwrap_or(0.0);
    Point3::new(g(0), g(1), g(2))
}

/// A frame in the map's image of the definition xy plane (x and y mapped,
/// so reflections keep the sense of rotation of the definition space).
fn mapped_frame(f: &Fields, tr: &Affine, center: Point3) -> CadResult<Frame> {
    let (x, y) = (tr.vector(Vec3::x()), tr.vector(Vec3::y()));
    Frame::new(tr.apply(center), x.cross(&y), Some(x))
        .ok_or_else(|| f.bad(0, "degenerate transform"))
}

/// Counter-clockwise sweep from angle `t0` to `t1` (a full turn when equal).
fn ccw(t0: f64, t1: f64) -> f64 {
    let sweep = (t1 - t0).rem_euclid(TAU);
    if sweep <= EPS_PARAM {
        TAU
    } else {
        sweep
    }
}

fn arc100(f: &Fields, tr: &Affine) -> CadResult<Piece> {
    let v = f.reals(1, 7)?;
    let g = |k: usize| v.get(k).copied().unwrap_or(0.0);
    let (zt, c, s, e) = (g(0), (g(1), g(2)), (g(3), g(4)), (g(5), g(6)));
    let radius = (s.0 - c.0).hypot(s.1 - c.1) * tr.scale();
    if radius.is_nan() || radius <= 0.0 {
        return Err(f.bad(4, "gives a circular arc of zero radius"));
    }
    let frame = mapped_frame(f, tr, Point3::new(c.0, c.1, zt))?;
    let t0 = angle(s.1 - c.1, s.0 - c.0);
    let t1 = t0 + ccw(t0, angle(e.1 - c.1, e.0 - c.0));
    Ok(Piece::Arc(Curve::Circle { frame, radius }, t0, t1))
}

/// Ellipse arcs (form 1) `x^2 / a^2 + y^2 / b^2 = 1` from the start to the
/// terminate point, counter-clockwise.
fn ellipse104(f: &Fields, tr: &Affine) -> CadResult<Piece> {
    let c = f.reals(1, 11)?;
    let g = |k: usize| c.get(k).copied().unwrap_or(0.0);
    let (a, b, cc, d, e, ff) = (g(0), g(1), g(2), g(3), g(4), g(5));
    let degenerate = [b, d, e]
        .iter()
        .any(|x| x.abs() > 1e-12 * (a.abs() + cc.abs()));
    let (ra, rb) = ((-ff / a).sqrt(), (-ff / cc).sqrt());
    if f.entry.form != 1 || degenerate || !(ra > 0.0 && rb > 0.0) {
        return Err(f.bad(
            1,
            "is not an ellipse in standard position (only form 1 ellipses are supported)",
        ));
    }
    let frame = mapped_frame(f, tr, Point3::new(0.0, 0.0, g(6)))?;
    let s = tr.scale();
    let t0 = angle(g(8) / rb, g(7) / ra);
    let t1 = t0 + ccw(t0, angle(g(10) / rb, g(9) / ra));
    let curve = Curve::Ellipse {
        frame,
        a: ra * s,
        b: rb * s,
    };
    Ok(Piece::Arc(curve, t0, t1))
}

/// Copious data forms 1, 2, 11, 12, 63: polylines.
fn polyline106(f: &Fields, tr: &Affine) -> CadResult<Vec<Piece>> {
    let (ip, n) = (f.int(1)?, f.count(2)?);
    let (stride, planar) = match ip {
        1 => (2, true),
        2 => (3, false),
        3 => (6, false),
        _ => return Err(f.bad(1, "is not a copious-data interpretation flag (1, 2 or 3)")),
    };
    let (first, zt) = if planar { (4, f.real(3)?) } else { (3, 0.0) };
    let pts: Vec<Point3> = (0..n)
        .map(|k| {
            let at = first + stride * k;
            let z = if planar { Ok(zt) } else { f.real(at + 2) };
            Ok(tr.apply(Point3::new(f.real(at)?, f.real(at + 1)?, z?)))
        })
        .collect::<CadResult<_>>()?;
    Ok(pts
        .windows(2)
        .filter_map(|w| match w {
            [a, b] => Some(Piece::Segment(*a, *b)),
            _ => None,
        })
        .collect())
}

/// Entity 126 with its range `[t0, t1]`.
pub fn curve126(f: &Fields, tr: &Affine) -> CadResult<(NurbsCurve, f64, f64)> {
    let (k, deg) = (f.count(1)?, f.count(2)?);
    let n = k + 1;
    let knots = f.reals(7, k + deg + 2)?;
    let at = 7 + k + deg + 2;
    let weights = f.reals(at, n)?;
    let xyz = f.reals(at + n, 3 * n)?;
    let (t0, t1) = (f.real(at + 4 * n)?, f.real(at + 4 * n + 1)?);
    let points: Vec<Point3> = (0..n).map(|i| tr.apply(point_at(&xyz, 3 * i))).collect();
    let c = new_curve(deg, knots, &points, weights)
        .map_err(|e| f.bad(1, &format!("describes an inconsistent B-spline curve: {e}")))?;
    let (lo, hi) = c.domain();
    let (t0, t1) = (t0.clamp(lo, hi), t1.clamp(lo, hi));
    if t1 <= t0 {
        return Ok((c, lo, hi));
    }
    Ok((c, t0, t1))
}

/// Initial sample intervals of a piece before adaptive refinement.
fn initial(p: &Piece) -> usize {
    match p {
        Piece::Segment(..) => 1,
        Piece::Arc(c, t0, t1) => crate::cad::step::topology::initial_segments(c, *t0, *t1),
    }
}

/// The pieces sampled in order to `tol` (mm) chord error, joints merged.
pub fn polyline(pieces: &[Piece], tol: f64, max_samples: usize, join: f64) -> Vec<Point3> {
    let mut out: Vec<Point3> = Vec::new();
    for p in pieces {
        let pts: Vec<Point3> = match p {
            Piece::Segment(a, b) => vec![*a, *b],
            Piece::Arc(c, t0, t1) => {
                let f = |t: f64| c.eval(t);
                adaptive(&f, *t0, *t1, initial(p), tol, max_samples)
                    .into_iter()
                    .map(|(_, q)| q)
                    .collect()
            }
        };
        let skip = usize::from(
            out.last()
                .zip(pts.first())
                .is_some_and(|(l, f)| (l - f).norm() <= join),
        );
        out.extend(pts.into_iter().skip(skip));
    }
    out
}
