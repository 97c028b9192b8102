//! Knot insertion (The NURBS Book, A5.1): refines the knot vector without
//! changing the shape.
use super::curve::NurbsCurve;
use super::knots::KnotVector;
use super::surface::NurbsSurface;
use crate::math::Vec4;

/// Why a knot could not be inserted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InsertError {
    /// The value lies outside the parameter domain.
    #[error("knot {value} lies outside the domain [{lo}, {hi}]")]
    OutsideDomain {
        /// The knot value.
        value: f64,
        /// Domain start.
        lo: f64,
        /// Domain end.
        hi: f64,
    },
    /// Inserting would raise the multiplicity above the degree.
    #[error("knot {value} already has multiplicity {mult}; inserting {times} more exceeds degree {degree}")]
    Multiplicity {
        /// The knot value.
        value: f64,
        /// Current multiplicity.
        mult: usize,
        /// How many insertions were asked.
        times: usize,
        /// The degree.
        degree: usize,
    },
}

/// Inserts `u` `times` times into a homogeneous control polygon.
pub(crate) fn insert_homogeneous(
    knots: &KnotVector,
    points: &[Vec4],
    u: f64,
    times: usize,
) -> Result<(KnotVector, Vec<Vec4>), InsertError> {
    let (lo, hi) = knots.domain();
    if !(lo..=hi).contains(&u) {
        return Err(InsertError::OutsideDomain { value: u, lo, hi });
    }
    let p = knots.degree();
    let s = knots.multiplicity(u);
    if s + times > p {
        return Err(InsertError::Multiplicity {
            value: u,
            mult: s,
            times,
            degree: p,
        });
    }
    let old = knots.as_slice();
    // Last index with old[k] <= u (the span A5.1 expects).
    let k = old.partition_point(|&x| x <= u).saturating_sub(1).max(p);
    let mut new_knots = Vec::with_capacity(old.len() + times);
    new_knots.extend_from_slice(&old[..=k]);
    new_knots.extend(std::iter::repeat_n(u, times));
    new_knots.extend_from_slice(&old[k + 1..]);
    let pts = insert_points(old, points, p, k, s, u, times);
    let kv = KnotVector::try_new(new_knots, p).map_err(|_| InsertError::Multiplicity {
        value: u,
        mult: s,
        times,
        degree: p,
    })?;
    Ok((kv, pts))
}

fn insert_points(
    old: &[f64],
    pts: &[Vec4],
    p: usize,
    k: usize,
    s: usize,
    u: f64,
    r: usize,
) -> Vec<Vec4> {
    let np = pts.len();
    let mut out = vec![Vec4::zeros(); np + r];
    out[..=k - p].copy_from_slice(&pts[..=k - p]);
    out[k - s + r..np + r].copy_from_slice(&pts[k - s..np]);
    let mut rw: Vec<Vec4> = pts[k - p..=k - s].to_vec();
    let mut l = 0;
    for j in 1..=r {
        l = k - p + j;
        for i in 0..=(p - j - s) {
            let alpha = (u - old[l + i]) / (old[i + k + 1] - old[l + i]);
            rw[i] = rw[i + 1] * alpha + rw[i] * (1.0 - alpha);
        }
        out[l] = rw[0];
        out[k + r - j - s] = rw[p - j - s];
    }
    if l + 1 < k - s {
        out[l + 1..k - s].copy_from_slice(&rw[1..k - s - l]);
    }
    out
}

impl NurbsCurve {
    /// The same curve with `u` inserted `times` times.
    pub fn insert_knot(&self, u: f64, times: usize) -> Result<NurbsCurve, InsertError> {
        let (kv, pts) = insert_homogeneous(self.knots(), self.homogeneous_points(), u, times)?;
        Ok(NurbsCurve::from_parts(kv, pts))
    }
}

impl NurbsSurface {
    /// The same surface with `u` inserted `times` times in the u direction.
    pub fn insert_knot_u(&self, u: f64, times: usize) -> Result<NurbsSurface, InsertError> {
        let (nu, nv) = self.counts();
        let mut columns = Vec::with_capacity(nv);
        let mut new_kv = None;
        for j in 0..nv {
            let col: Vec<Vec4> = (0..nu).map(|i| self.homogeneous_point(i, j)).collect();
            let (kv, pts) = insert_homogeneous(self.knots_u(), &col, u, times)?;
            new_kv = Some(kv);
            columns.push(pts);
        }
        let ku = new_kv.unwrap_or_else(|| self.knots_u().clone());
        let nu2 = ku.num_basis();
        let pw = (0..nu2)
            .flat_map(|i| columns.iter().map(move |c| c[i]))
            .collect();
        Ok(NurbsSurface::from_parts(
            ku,
            self.knots_v().clone(),
            pw,
            self.is_reversed(),
        ))
    }

    /// The same surface with `v` inserted `times` times in the v direction.
    pub fn insert_knot_v(&self, v: f64, times: usize) -> Result<NurbsSurface, InsertError> {
        let (nu, nv) = self.counts();
        let mut pw = Vec::with_capacity(nu * (nv + times));
        let mut new_kv = None;
        for i in 0..nu {
            let row = &self.homogeneous_points()[i * nv..(i + 1) * nv];
            let (kv, pts) = insert_homogeneous(self.knots_v(), row, v, times)?;
            new_kv = Some(kv);
            pw.extend(pts);
        }
        let kv = new_kv.unwrap_or_else(|| self.knots_v().clone());
        Ok(NurbsSurface::from_parts(
            self.knots_u().clone(),
            kv,
            pw,
            self.is_reversed(),
        ))
    }
}
