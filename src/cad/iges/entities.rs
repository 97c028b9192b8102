//! Access to IGES entities: the parsed model, parameter fields with their
//! places, DE pointers (unknown ones are errors) and 124 transformations
//! (chains followed, cycles reported).
use super::params::{tokenize, Token, Tokens};
use super::records::{Entry, Global, Line};
use crate::cad::error::{CadError, CadResult};
use crate::math::{Mat3, Point3, Vec3};

/// Deepest chain of 124 transformations, nested composite curves or
/// subfigure instances followed.
pub const MAX_CHAIN: usize = 64;

/// Column of the transformation-matrix field (field 7) of a D record.
const TRANSFORM_COLUMN: usize = 49;

/// True for errors that fail the whole import (dangling or cyclic
/// pointers) rather than only the face they occur in.
pub fn is_hard(e: &CadError) -> bool {
    matches!(
        e,
        CadError::UnknownReference { .. } | CadError::CyclicReference { .. }
    )
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
    /// The identity map.
    pub fn identity() -> Affine {
        Affine {
            m: Mat3::identity(),
            t: Vec3::zeros(),
        }
    }

    /// Uniform scaling by `s` about the origin.
    pub fn scaling(s: f64) -> Affine {
        Affine {
            m: Mat3::identity() * s,
            t: Vec3::zeros(),
        }
    }

    /// Applies the map to a point.
    pub fn apply(&self, p: Point3) -> Point3 {
        Point3::from(self.m * p.coords + self.t)
    }

    /// Applies the linear part to a vector.
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m * v
    }

    /// `self` after `inner`: `x -> self(inner(x))`.
    pub fn then_inner(&self, inner: &Affine) -> Affine {
        Affine {
            m: self.m * inner.m,
            t: self.m * inner.t + self.t,
        }
    }

    /// The length scale of the map (`|det|^(1/3)`; 1 for rigid motions).
    pub fn scale(&self) -> f64 {
        self.m.determinant().abs().cbrt()
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
    /// The entry with DE pointer `de`, if there is one.
    pub fn get(&self, de: u64) -> Option<&Entry> {
        let k = usize::try_from(de.checked_sub(1)? / 2).ok()?;
        self.entries.get(k).filter(|e| e.seq == de)
    }

    /// The entry with DE pointer `de` referenced from `from` at `(line, column)`.
    pub fn target(&self, from: &Entry, de: u64, place: (usize, usize)) -> CadResult<&Entry> {
        self.get(de).ok_or_else(|| CadError::UnknownReference {
            file: self.file.to_string(),
            line: place.0,
            column: place.1,
            entity: from.seq,
            target: de,
        })
    }

    /// The error for a DE pointer that was checked before but is missing.
    pub fn missing(&self, de: u64) -> CadError {
        CadError::Entity {
            file: self.file.to_string(),
            line: 1,
            column: 1,
            entity: de,
            reason: "missing Directory Entry".into(),
        }
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
    pub fn fields<'s>(&'s self, e: &Entry) -> CadResult<Fields<'s>> {
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

    /// The composed 124 transformation of an entry (identity when none):
    /// its own matrix, then the matrix that one points to, and so on.
    pub fn transform(&self, e: &Entry) -> CadResult<Affine> {
        let mut out = Affine::identity();
        let mut chain = vec![e.seq];
        let mut from = e;
        while from.transform != 0 {
            let te = self.target(from, from.transform, (from.line, TRANSFORM_COLUMN))?;
            if te.kind != 124 {
                return Err(self.err(
                    from,
                    format!(
                        "transformation pointer #{} is entity {}, not 124",
                        te.seq, te.kind
                    ),
                ));
            }
            if chain.contains(&te.seq) || chain.len() > MAX_CHAIN {
                chain.push(te.seq);
                return Err(self.cycle(te, &chain));
            }
            chain.push(te.seq);
            out = matrix124(&self.fields(te)?)?.then_inner(&out);
            from = te;
        }
        Ok(out)
    }

    /// A cyclic-reference error at `e` naming the chain `#a -> #b -> #a`.
    pub fn cycle(&self, e: &Entry, chain: &[u64]) -> CadError {
        let names: Vec<String> = chain.iter().map(|d| format!("#{d}")).collect();
        CadError::CyclicReference {
            file: self.file.to_string(),
            line: e.line,
            column: 1,
            entity: e.seq,
            reason: names.join(" -> "),
        }
    }
}

/// The affine map of a 124 entity's own parameters.
fn matrix124(f: &Fields) -> CadResult<Affine> {
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
    if m.determinant().abs() < 1e-12 || !m.iter().all(|x| x.is_finite()) {
        return Err(f.bad(1, "starts a singular transformation matrix"));
    }
    Ok(Affine { m, t })
}

/// The fields of one entity.
pub struct Fields<'a> {
    model: &'a Model<'a>,
    /// The entry.
    pub entry: Entry,
    toks: Tokens,
}

impl<'a> Fields<'a> {
    /// An entity error at field `k`.
    pub fn bad(&self, k: usize, what: &str) -> CadError {
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

    /// `(line, column)` of field `k`.
    pub fn place(&self, k: usize) -> (usize, usize) {
        self.toks
            .places
            .get(k)
            .copied()
            .unwrap_or((self.entry.line, 1))
    }

    /// The entry field `k` points to (unknown pointers are errors).
    pub fn target(&self, k: usize) -> CadResult<&'a Entry> {
        let de = self.ptr(k)?;
        self.model.target(&self.entry, de, self.place(k))
    }

    /// The entry field `k` points to, `None` for a null pointer.
    pub fn target_opt(&self, k: usize) -> CadResult<Option<&'a Entry>> {
        if self.toks.items.get(k).is_none_or(|t| t.as_int() == Some(0)) {
            return Ok(None);
        }
        self.target(k).map(Some)
    }

    /// The model these fields belong to.
    pub fn model(&self) -> &'a Model<'a> {
        self.model
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
