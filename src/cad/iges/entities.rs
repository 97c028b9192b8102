//! Access to IGES entities: parameter fields, 124 transformations, the 128
//! rational B-spline surface and parameter-space curves (110, 100, 126, 102).
use super::params::{tokenize, Token, Tokens};
use super::records::{Entry, Global, Line};
use crate::cad::error::{CadError, CadResult};
use crate::cad::geom::EPS_PARAM;
use crate::cad::geom::{angle, Curve, Frame};
use crate::cad::nurbs::{new_curve, NurbsCurve};
use crate::math::{Mat3, Point3, Vec3};
use crate::workpiece::format::SurfaceSpec;
use std::f64::consts::TAU;

/// Deepest chain of 124 transformations or nested composite curves followed.
const MAX_CHAIN: usize = 16;

/// One piece of a parameter-space curve.
#[derive(Debug, Clone, PartialEq)]
pub enum Piece {
    /// Straight segment.
    Segment(Point3, Point3),
    /// Curve over `[t0, t1]`.
    Arc(Curve, f64, f64),
}

/// An affine map `x -> m x + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    /// Linear part.
    pub m: Mat3,
    /// Translation.
    pub t: Vec3,
}

impl Affine {
    fn identity() -> Affine {
        Affine {
            m: Mat3::identity(),
            t: Vec3::zeros(),
        }
    }

    /// Applies the map to a point.
    pub fn apply(&self, p: Point3) -> Point3 {
        Point3::from(self.m * p.coords + self.t)
    }
}

/// The parsed file: directory entries plus lazily tokenized parameters.
pub struct Model<'a> {
    /// File name for errors.
    pub file: &'a str,
    /// Directory entries in order.
    pub entries: Vec<Entry>,
    /// P records.
    pub params: &'a [Line],
    /// Delimiters and units.
    pub global: Global,
}

impl Model<'_> {
    /// The entry with DE pointer `de`.
    pub fn entry(&self, de: u64) -> CadResult<&Entry> {
        let k = usize::try_from(de.saturating_sub(1) / 2).unwrap_or(usize::MAX);
        self.entries
            .get(k)
            .filter(|e| e.seq == de)
            .ok_or_else(|| CadError::Entity {
                file: self.file.to_string(),
                line: 1,
                column: 1,
                entity: de,
                reason: "pointer to a missing Directory Entry".into(),
            })
    }

    /// An entity error at the entry's D record.
    pub fn err(&self, e: &Entry, reason: impl Into<String>) -> CadError {
        CadError::Entity {
            file: self.file.to_string(),
            line: e.line,
            column: 1,
            entity: e.seq,
            reason: reason.into(),
        }
    }

    /// The parameter fields of an entry (field 0 is the entity type).
    pub fn fields(&self, e: &Entry) -> CadResult<Fields<'_>> {
        let start = e.param_start.saturating_sub(1);
        let lines = self
            .params
            .get(start..start + e.param_count.max(1))
            .ok_or_else(|| self.err(e, "parameter data pointer outside the P section"))?;
        let toks = tokenize(lines, self.global.param, self.global.record, self.file)?;
        if toks.items.first().and_then(Token::as_int) != Some(e.kind) {
            return Err(self.err(
                e,
                format!("parameter data does not start with entity type {}", e.kind),
            ));
        }
        Ok(Fields {
            model: self,
            entry: e.clone(),
            toks,
        })
    }

    /// The composed 124 transformation of an entry (identity when none).
    pub fn transform(&self, e: &Entry) -> CadResult<Affine> {
        let mut out = Affine::identity();
        let mut next = e.transform;
        for _ in 0..MAX_CHAIN {
            if next == 0 {
                return Ok(out);
            }
            let te = self.entry(next)?;
            let f = self.fields(te)?;
            let r = |k: usize| f.real(k);
            let m = Mat3::new(
                r(1)?,
                r(2)?,
                r(3)?,
                r(5)?,
                r(6)?,
                r(7)?,
                r(9)?,
                r(10)?,
                r(11)?,
            );
            let t = Vec3::new(r(4)?, r(8)?, r(12)?);
            out = Affine {
                m: m * out.m,
                t: m * out.t + t,
            };
            next = te.transform;
        }
        Err(self.err(e, "transformation matrix chain too long or cyclic"))
    }
}

/// The fields of one entity.
pub struct Fields<'a> {
    model: &'a Model<'a>,
    /// The entry.
    pub entry: Entry,
    toks: Tokens,
}

impl Fields<'_> {
    fn bad(&self, k: usize, what: &str) -> CadError {
        let (line, column) = self
            .toks
            .places
            .get(k)
            .copied()
            .unwrap_or((self.entry.line, 1));
        CadError::Entity {
            file: self.model.file.to_string(),
            line,
            column,
            entity: self.entry.seq,
            reason: format!("parameter {k} {what}"),
        }
    }

    /// Field `k` as a real.
    pub fn real(&self, k: usize) -> CadResult<f64> {
        self.toks
            .items
            .get(k)
            .and_then(Token::as_real)
            .ok_or_else(|| self.bad(k, "is missing or not a number"))
    }

    /// Field `k` as an integer.
    pub fn int(&self, k: usize) -> CadResult<i64> {
        self.toks
            .items
            .get(k)
            .and_then(Token::as_int)
            .ok_or_else(|| self.bad(k, "is missing or not an integer"))
    }

    /// Field `k` as a non-negative count (bounded to guard hostile input).
    pub fn count(&self, k: usize) -> CadResult<usize> {
        let v = self.int(k)?;
        usize::try_from(v)
            .ok()
            .filter(|n| *n < 10_000_000)
            .ok_or_else(|| self.bad(k, "is not a valid count"))
    }

    /// Field `k` as a DE pointer.
    pub fn ptr(&self, k: usize) -> CadResult<u64> {
        u64::try_from(self.int(k)?).map_err(|_| self.bad(k, "is not a valid pointer"))
    }

    /// `n` reals starting at `k`.
    pub fn reals(&self, k: usize, n: usize) -> CadResult<Vec<f64>> {
        (k..k + n).map(|i| self.real(i)).collect()
    }

    /// `n` reals from `*at`, advancing `*at`.
    pub fn take(&self, at: &mut usize, n: usize) -> CadResult<Vec<f64>> {
        let out = self.reals(*at, n)?;
        *at += n;
        Ok(out)
    }

    /// Number of fields.
    pub fn len(&self) -> usize {
        self.toks.items.len()
    }

    /// True when there are no fields.
    pub fn is_empty(&self) -> bool {
        self.toks.items.is_empty()
    }
}

/// Entity 128, in mm, with its transformation applied; also returns the
/// parameter range `[u0, u1, v0, v1]`.
pub fn surface128(m: &Model, e: &Entry) -> CadResult<(SurfaceSpec, [f64; 4])> {
    let f = m.fields(e)?;
    let (k1, k2, m1, m2) = (f.count(1)?, f.count(2)?, f.count(3)?, f.count(4)?);
    let (n1, n2) = (k1 + 1, k2 + 1);
    let mut at = 10;
    let knots_u = f.take(&mut at, k1 + m1 + 2)?;
    let knots_v = f.take(&mut at, k2 + m2 + 2)?;
    let w = f.take(&mut at, n1 * n2)?;
    let xyz = f.take(&mut at, 3 * n1 * n2)?;
    let range: [f64; 4] = f
        .take(&mut at, 4)?
        .try_into()
        .map_err(|_| m.err(e, "missing parameter range"))?;
    let (tr, s) = (m.transform(e)?, m.global.unit_mm);
    let point = |k: usize| {
        let c = |d: usize| xyz.get(3 * k + d).copied().unwrap_or(0.0);
        let p = tr.apply(Point3::new(c(0), c(1), c(2)));
        [p.x * s, p.y * s, p.z * s]
    };
    let weights = grid(n1, n2, |k| w.get(k).copied().unwrap_or(1.0));
    let rational = weights.iter().flatten().any(|x| *x != 1.0);
    let spec = SurfaceSpec {
        name: String::new(),
        degree: [m1, m2],
        knots_u,
        knots_v,
        control_points: grid(n1, n2, point),
        weights: rational.then_some(weights),
        reversed: false,
        trim: None,
    };
    crate::cad::step::surfaces::check_spline(&spec).map_err(|r| m.err(e, r))?;
    Ok((spec, range))
}

/// `out[i][j] = f(i + n1 j)`: IGES lists the first index fastest.
fn grid<T>(n1: usize, n2: usize, f: impl Fn(usize) -> T) -> Vec<Vec<T>> {
    (0..n1)
        .map(|i| (0..n2).map(|j| f(i + n1 * j)).collect())
        .collect()
}

/// A parameter-space curve (102 composite of 110/100/126) as pieces.
pub fn param_curve(m: &Model, de: u64, depth: usize) -> CadResult<Vec<Piece>> {
    let e = m.entry(de)?;
    if depth > MAX_CHAIN {
        return Err(m.err(e, "composite curves nested too deeply"));
    }
    let f = m.fields(e)?;
    let tr = m.transform(e)?;
    match e.kind {
        102 => {
            let n = f.count(1)?;
            let mut out = Vec::new();
            for k in 0..n {
                out.extend(param_curve(m, f.ptr(2 + k)?, depth + 1)?);
            }
            Ok(out)
        }
        110 => {
            let c = f.reals(1, 6)?;
            let p = |k: usize| {
                tr.apply(Point3::new(
                    c.get(k).copied().unwrap_or(0.0),
                    c.get(k + 1).copied().unwrap_or(0.0),
                    c.get(k + 2).copied().unwrap_or(0.0),
                ))
            };
            Ok(vec![Piece::Segment(p(0), p(3))])
        }
        100 => arc100(&f, &tr).map(|p| vec![p]),
        126 => curve126(&f, &tr).map(|(c, t0, t1)| vec![Piece::Arc(Curve::Nurbs(c), t0, t1)]),
        other => Err(m.err(e, format!("unsupported parameter-space curve type {other}"))),
    }
}

fn arc100(f: &Fields, tr: &Affine) -> CadResult<Piece> {
    let v = f.reals(1, 7)?;
    let g = |k: usize| v.get(k).copied().unwrap_or(0.0);
    let (zt, c, s, e) = (g(0), (g(1), g(2)), (g(3), g(4)), (g(5), g(6)));
    let radius = (s.0 - c.0).hypot(s.1 - c.1);
    let center = tr.apply(Point3::new(c.0, c.1, zt));
    let x = tr.m * Vec3::x();
    let frame = Frame::new(center, tr.m * Vec3::z(), Some(x))
        .ok_or_else(|| f.bad(0, "degenerate arc transform"))?;
    let t0 = angle(s.1 - c.1, s.0 - c.0);
    let mut sweep = (angle(e.1 - c.1, e.0 - c.0) - t0).rem_euclid(TAU);
    if sweep <= EPS_PARAM {
        sweep = TAU;
    }
    let t1 = t0 + sweep;
    Ok(Piece::Arc(Curve::Circle { frame, radius }, t0, t1))
}

fn curve126(f: &Fields, tr: &Affine) -> CadResult<(NurbsCurve, f64, f64)> {
    let (k, deg) = (f.count(1)?, f.count(2)?);
    let n = k + 1;
    let knots = f.reals(7, k + deg + 2)?;
    let at = 7 + k + deg + 2;
    let weights = f.reals(at, n)?;
    let xyz = f.reals(at + n, 3 * n)?;
    let (t0, t1) = (f.real(at + 4 * n)?, f.real(at + 4 * n + 1)?);
    let points: Vec<Point3> = (0..n)
        .map(|i| {
            let c = |d: usize| xyz.get(3 * i + d).copied().unwrap_or(0.0);
            tr.apply(Point3::new(c(0), c(1), c(2)))
        })
        .collect();
    let c = new_curve(deg, knots, &points, weights)
        .map_err(|e| f.bad(1, &format!("describes an inconsistent B-spline curve: {e}")))?;
    Ok((c, t0, t1))
}
