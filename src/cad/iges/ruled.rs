//! Entity 118 (ruled surface) as an exact NURBS surface, and the B-spline
//! curve operations it needs: restriction to a sub-range, reversal,
//! reparameterisation to `[0, 1]`, knot merging and raising a line's degree.
//!
//! The ruled surface `(1 - v) C1(u) + v C2(u)` is a tensor-product NURBS of
//! degree 1 in `v` when both rails share degree, knots and weights. Any two
//! rails are brought to that form exactly: a line is raised onto the other
//! rail's knots, another curve of lower degree is elevated, knots are
//! merged, and rational rails whose weights are then not proportional are
//! each multiplied (homogeneously) by the other's weight function, so both
//! share the weight function `w1 w2`. Both forms (equal arc length, equal
//! parameter) are read as equal relative parameter, each rail's parameter
//! range taken to `[0, 1]`: exact for form 1 and for rails whose speeds are
//! proportional, and what OpenCASCADE's IGES reader makes of a form 0
//! surface on two single curves too (rulings at equal relative arc length
//! are no NURBS surface), so distances to such a face agree with it.
use super::entities::{Affine, Fields, Model};
use super::surfaces::curve_nurbs;
use crate::cad::error::CadResult;
use crate::cad::nurbs::{control_points, new_curve, weights, NurbsCurve};
use crate::formats::workpiece::SurfaceSpec;
use crate::math::Point3;
use std::cmp::Ordering;

/// Knots closer than this (relative to the domain length) are the same knot.
const KNOT_SNAP: f64 = 1e-10;
/// Relative weight mismatch still accepted as proportional.
const WEIGHT_TOL: f64 = 1e-9;

/// Entity 118 mapped by `tr` (mm) over `[0, 1] x [0, 1]`.
pub fn ruled(m: &Model, f: &Fields, tr: &Affine) -> CadResult<SurfaceSpec> {
    let c1 = curve_nurbs(m, f, 1, tr)?;
    let mut c2 = curve_nurbs(m, f, 2, tr)?;
    if f.int(3)? == 1 {
        c2 = reversed(&c2).map_err(|r| f.bad(2, &r))?;
    }
    let (a, b) =
        compatible(&unit(&c1), &unit(&c2)).map_err(|r| f.bad(1, &format!("and 2: {r}")))?;
    let (pa, pb) = (control_points(&a), control_points(&b));
    let (wa, wb) = (weights(&a), weights(&b));
    let rational = wa.iter().any(|w| *w != 1.0);
    let row = |p: &Point3, q: &Point3| vec![[p.x, p.y, p.z], [q.x, q.y, q.z]];
    Ok(SurfaceSpec {
        name: String::new(),
        degree: [a.knots().degree(), 1],
        knots_u: a.knots().as_slice().to_vec(),
        knots_v: vec![0.0, 0.0, 1.0, 1.0],
        control_points: pa.iter().zip(&pb).map(|(p, q)| row(p, q)).collect(),
        weights: rational.then(|| wa.iter().zip(&wb).map(|(x, y)| vec![*x, *y]).collect()),
        reversed: false,
        trim: None,
    })
}

fn rebuild(degree: usize, knots: Vec<f64>, c: &NurbsCurve) -> Result<NurbsCurve, String> {
    new_curve(degree, knots, &control_points(c), weights(c)).map_err(|e| e.to_string())
}

/// The curve with its parameter mapped linearly onto `[0, 1]`.
pub fn unit(c: &NurbsCurve) -> NurbsCurve {
    let (lo, hi) = c.domain();
    let len = (hi - lo).max(f64::MIN_POSITIVE);
    let knots = c
        .knots()
        .as_slice()
        .iter()
        .map(|t| (t - lo) / len)
        .collect();
    rebuild(c.knots().degree(), knots, c).unwrap_or_else(|_| c.clone())
}

/// The same curve traversed backwards (same domain).
pub fn reversed(c: &NurbsCurve) -> Result<NurbsCurve, String> {
    let (lo, hi) = c.domain();
    let knots: Vec<f64> = c
        .knots()
        .as_slice()
        .iter()
        .rev()
        .map(|t| lo + hi - t)
        .collect();
    let mut pts = control_points(c);
    let mut w = weights(c);
    pts.reverse();
    w.reverse();
    new_curve(c.knots().degree(), knots, &pts, w).map_err(|e| e.to_string())
}

/// The curve restricted to `[t0, t1]` (inside its domain) by knot insertion.
pub fn restrict(c: &NurbsCurve, t0: f64, t1: f64) -> Result<NurbsCurve, String> {
    let p = c.knots().degree();
    let (lo, hi) = c.domain();
    let snap = KNOT_SNAP * (hi - lo).abs().max(1.0);
    let (cut0, cut1) = (t0 > lo + snap, t1 < hi - snap);
    if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
        return Err(format!("empty curve range [{t0}, {t1}]"));
    }
    let mut c = c.clone();
    for (cut, t) in [(cut0, t0), (cut1, t1)] {
        if cut {
            let have = c
                .knots()
                .as_slice()
                .iter()
                .filter(|k| (*k - t).abs() <= snap)
                .count();
            if have < p {
                c = c.insert_knot(t, p - have).map_err(|e| e.to_string())?;
            }
        }
    }
    let u = c.knots().as_slice();
    let first = |t: f64| u.iter().position(|k| (k - t).abs() <= snap);
    let s = if cut0 {
        first(t0).map_or(0, |a| a.saturating_sub(1))
    } else {
        0
    };
    let n = c.knots().num_basis();
    let e = if cut1 {
        first(t1).map_or(n - 1, |b| b.saturating_sub(1))
    } else {
        n - 1
    };
    let mut knots = vec![t0];
    knots.extend(u.get(s + 1..e + p + 1).unwrap_or(&[]).iter().copied());
    knots.push(t1);
    let pts = control_points(&c);
    let w = weights(&c);
    let (pts, w) = (pts.get(s..=e).unwrap_or(&[]), w.get(s..=e).unwrap_or(&[]));
    new_curve(p, knots, pts, w.to_vec()).map_err(|e| format!("sub-curve: {e}"))
}

fn is_polynomial(c: &NurbsCurve) -> bool {
    weights(c).iter().all(|w| *w == 1.0)
}

/// A straight (degree 1, two points) curve expressed on `knots` of degree `p`
/// (control points at the Greville abscissae: exact by linear precision).
fn raise_line(c: &NurbsCurve, p: usize, knots: &[f64]) -> Result<NurbsCurve, String> {
    if p == 0 {
        return Err("a line cannot be lowered to degree 0".into());
    }
    let n = knots.len().saturating_sub(p + 1);
    let pts: Vec<Point3> = (0..n)
        .map(|i| {
            let g = knots
                .get(i + 1..=i + p)
                .map_or(0.0, |s| s.iter().sum::<f64>() / p as f64);
            c.point(g)
        })
        .collect();
    new_curve(p, knots.to_vec(), &pts, vec![1.0; n]).map_err(|e| e.to_string())
}

fn is_line(c: &NurbsCurve) -> bool {
    c.knots().degree() == 1 && c.knots().num_basis() == 2
}

/// Two curves on `[0, 1]` brought to the same degree, knots and weights.
///
/// The lower degree is raised to the higher (exactly) and the knots are
/// merged. Where the weights are then not proportional, each curve's
/// homogeneous form is multiplied by the other's weight function instead:
/// both get the weight function `w_a w_b` (degree `p_a + p_b`), and the
/// surface is still exactly `(1 - v) C1(u) + v C2(u)`.
fn compatible(a: &NurbsCurve, b: &NurbsCurve) -> Result<(NurbsCurve, NurbsCurve), String> {
    let (ea, eb) = same_degree(a, b)?;
    let (ea, eb) = merge_knots(&ea, &eb)?;
    if let Some(eb) = rescaled_to(&ea, &eb)? {
        return Ok((ea, eb));
    }
    let ra = a.reweighted_by(b).map_err(|e| e.to_string())?;
    let rb = b.reweighted_by(a).map_err(|e| e.to_string())?;
    let (ra, rb) = merge_knots(&ra, &rb)?;
    match rescaled_to(&ra, &rb)? {
        Some(rb) => Ok((ra, rb)),
        None => Err("rails' weight functions differ after reweighting".into()),
    }
}

/// The two curves at one degree: a line raised onto the other polynomial
/// rail's knots, any other curve of lower degree elevated.
fn same_degree(a: &NurbsCurve, b: &NurbsCurve) -> Result<(NurbsCurve, NurbsCurve), String> {
    let (pa, pb) = (a.knots().degree(), b.knots().degree());
    let elevate = |c: &NurbsCurve, t: usize| c.elevate_degree(t).map_err(|e| e.to_string());
    match pa.cmp(&pb) {
        Ordering::Equal => Ok((a.clone(), b.clone())),
        Ordering::Less if is_line(a) && is_polynomial(b) => {
            Ok((raise_line(a, pb, b.knots().as_slice())?, b.clone()))
        }
        Ordering::Greater if is_line(b) && is_polynomial(a) => {
            Ok((a.clone(), raise_line(b, pa, a.knots().as_slice())?))
        }
        Ordering::Less => Ok((elevate(a, pb - pa)?, b.clone())),
        Ordering::Greater => Ok((a.clone(), elevate(b, pa - pb)?)),
    }
}

/// `b` with its weights scaled by the ratio of the first weights (so they
/// equal `a`'s), when `a`'s and `b`'s (same knots) are proportional to
/// within [`WEIGHT_TOL`]; `None` when not.
fn rescaled_to(a: &NurbsCurve, b: &NurbsCurve) -> Result<Option<NurbsCurve>, String> {
    let (wa, wb) = (weights(a), weights(b));
    let ratio = wa.first().zip(wb.first()).map_or(1.0, |(x, y)| x / y);
    let proportional = wa
        .iter()
        .zip(&wb)
        .all(|(x, y)| (x - ratio * y).abs() <= WEIGHT_TOL * x.abs());
    if !proportional {
        return Ok(None);
    }
    let scaled = wb.iter().map(|w| w * ratio).collect();
    let knots = b.knots().as_slice().to_vec();
    new_curve(b.knots().degree(), knots, &control_points(b), scaled)
        .map(Some)
        .map_err(|e| e.to_string())
}

/// Inserts into each curve the knots of the other it lacks.
fn merge_knots(a: &NurbsCurve, b: &NurbsCurve) -> Result<(NurbsCurve, NurbsCurve), String> {
    let mut a = a.clone();
    let mut b = b.clone();
    for _ in 0..2 {
        let missing = |x: &NurbsCurve, y: &NurbsCurve| -> Vec<(f64, usize)> {
            let mut out = Vec::new();
            for &t in y.knots().as_slice() {
                let my = |c: &NurbsCurve| {
                    c.knots()
                        .as_slice()
                        .iter()
                        .filter(|k| (*k - t).abs() <= KNOT_SNAP)
                        .count()
                };
                let need = my(y).saturating_sub(my(x));
                if need > 0
                    && !out
                        .iter()
                        .any(|(s, _): &(f64, usize)| (s - t).abs() <= KNOT_SNAP)
                {
                    out.push((t, need));
                }
            }
            out
        };
        for (t, k) in missing(&a, &b) {
            a = a.insert_knot(t, k).map_err(|e| e.to_string())?;
        }
        for (t, k) in missing(&b, &a) {
            b = b.insert_knot(t, k).map_err(|e| e.to_string())?;
        }
    }
    let snapped = a.knots().as_slice().to_vec();
    if snapped.len() != b.knots().as_slice().len() {
        return Err("rails' knot vectors could not be merged".into());
    }
    let b = rebuild(b.knots().degree(), snapped, &b)?;
    Ok((a, b))
}
