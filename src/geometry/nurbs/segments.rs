//! Bezier segments of NURBS curves: the decomposition by knot insertion
//! (The NURBS Book, A5.6 by repeated A5.1), the product of two Bezier
//! polynomials on the same range, and the joining of segments back into
//! one curve.
use super::binomial;
use super::curve::NurbsCurve;
use super::insert::InsertError;
use super::knots::KnotVector;
use super::NurbsError;
use crate::math::Vec4;

/// One polynomial piece of a curve in Bezier form.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Segment {
    /// Parameter range.
    pub span: (f64, f64),
    /// Homogeneous control points, degree + 1 of them.
    pub pw: Vec<Vec4>,
}

/// The Bezier segments of `c`, split at its own breakpoints and at the
/// values of `extra` that lie inside its domain.
pub(crate) fn segments(c: &NurbsCurve, extra: &[f64]) -> Result<Vec<Segment>, InsertError> {
    let p = c.knots().degree();
    let (lo, hi) = c.domain();
    let mut cuts = c.knots().breakpoints();
    cuts.extend(extra.iter().filter(|t| (lo..=hi).contains(*t)));
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut refined = c.clone();
    for u in cuts {
        let need = p.saturating_sub(refined.knots().multiplicity(u));
        if need > 0 {
            refined = refined.insert_knot(u, need)?;
        }
    }
    // Every breakpoint now has multiplicity at least p, so the p + 1
    // points ending at a non-empty span's index are its Bezier points.
    let knots = refined.knots().as_slice();
    let pw = refined.homogeneous_points();
    let out = (p..refined.knots().num_basis())
        .filter_map(|s| {
            let (a, b) = (*knots.get(s)?, *knots.get(s + 1)?);
            let points = pw.get(s.checked_sub(p)?..=s)?;
            (a < b).then(|| Segment {
                span: (a, b),
                pw: points.to_vec(),
            })
        })
        .collect();
    Ok(out)
}

/// The product of the Bezier polynomial with homogeneous coefficients `a`
/// and the scalar one with coefficients `b` (same parameter range), in
/// Bezier form of degree `deg a + deg b`:
/// `c_k = sum_{i+j=k} C(p, i) C(r, j) / C(p + r, k) a_i b_j`.
/// Multiplying by `b = [1; t + 1]` raises the degree by `t`.
pub(crate) fn product(a: &[Vec4], b: &[f64]) -> Vec<Vec4> {
    let (p, r) = (a.len().saturating_sub(1), b.len().saturating_sub(1));
    (0..=p + r)
        .map(|k| {
            let scale = binomial(p + r, k);
            a.iter()
                .enumerate()
                .filter_map(|(i, ai)| {
                    let bj = b.get(k.checked_sub(i)?)?;
                    Some(ai * (binomial(p, i) * binomial(r, k - i) / scale * bj))
                })
                .fold(Vec4::zeros(), |acc, x| acc + x)
        })
        .collect()
}

/// Consecutive segments of degree `q` (each `q + 1` points, each starting
/// where the one before ends) as one curve; interior breakpoints get
/// multiplicity `q`, and a segment's first point is its predecessor's last.
pub(crate) fn join(q: usize, segs: &[Segment]) -> Result<NurbsCurve, NurbsError> {
    let mut knots = Vec::new();
    let mut pw = Vec::new();
    for (k, s) in segs.iter().enumerate() {
        let (times, skip) = if k == 0 { (q + 1, 0) } else { (q, 1) };
        knots.extend(std::iter::repeat_n(s.span.0, times));
        pw.extend(s.pw.iter().skip(skip));
    }
    let end = segs.last().map_or(0.0, |s| s.span.1);
    knots.extend(std::iter::repeat_n(end, q + 1));
    let kv =
        KnotVector::try_new(knots, q).map_err(|source| NurbsError::Knots { dir: "", source })?;
    if pw.len() != kv.num_basis() {
        return Err(NurbsError::Count {
            dir: "points".into(),
            expected: kv.num_basis(),
            found: pw.len(),
        });
    }
    Ok(NurbsCurve::from_parts(kv, pw))
}
