//! Typed access to entity parameters, with errors that name the entity.
use super::parser::{Instance, StepFile, Value};
use crate::cad::error::{CadError, CadResult};

/// Reading context: the parsed file, its name and the unit scale factors.
#[derive(Clone, Copy)]
pub struct Ctx<'a> {
    /// The parsed exchange structure.
    pub step: &'a StepFile,
    /// File name for errors.
    pub file: &'a str,
    /// Millimetres per file length unit.
    pub length_mm: f64,
    /// Radians per file plane-angle unit.
    pub angle_rad: f64,
}

/// The parameters of one record of one instance.
#[derive(Clone, Copy)]
pub struct Args<'a> {
    ctx: Ctx<'a>,
    /// The instance.
    pub inst: &'a Instance,
    /// The record's parameters.
    pub params: &'a [Value],
}

impl<'a> Ctx<'a> {
    /// The instance `#id`.
    pub fn inst(&self, id: u64) -> CadResult<&'a Instance> {
        self.step.get(id).ok_or_else(|| CadError::Entity {
            file: self.file.to_string(),
            line: self.step.data_pos.line,
            column: self.step.data_pos.column,
            entity: id,
            reason: "instance not defined".into(),
        })
    }

    /// An entity error at `inst`.
    pub fn err(&self, inst: &Instance, reason: impl Into<String>) -> CadError {
        CadError::Entity {
            file: self.file.to_string(),
            line: inst.pos.line,
            column: inst.pos.column,
            entity: inst.id,
            reason: reason.into(),
        }
    }

    /// The parameters of record `name` of `#id` (simple or complex instance).
    pub fn args(&self, id: u64, name: &str) -> CadResult<Args<'a>> {
        let inst = self.inst(id)?;
        let rec = inst.records.iter().find(|r| r.name == name);
        let rec = rec
            .ok_or_else(|| self.err(inst, format!("expected {name}, found {}", type_name(inst))))?;
        Ok(Args {
            ctx: *self,
            inst,
            params: &rec.params,
        })
    }

    /// The parameters of the first record of `#id`.
    pub fn first(&self, id: u64) -> CadResult<Args<'a>> {
        let inst = self.inst(id)?;
        let rec = inst
            .records
            .first()
            .ok_or_else(|| self.err(inst, "empty instance"))?;
        Ok(Args {
            ctx: *self,
            inst,
            params: &rec.params,
        })
    }
}

/// The entity type name: the record name, or `(A B C)` for complex instances.
pub fn type_name(inst: &Instance) -> String {
    if !inst.complex {
        return inst
            .records
            .first()
            .map(|r| r.name.clone())
            .unwrap_or_default();
    }
    let names: Vec<&str> = inst.records.iter().map(|r| r.name.as_str()).collect();
    format!("({})", names.join(" "))
}

/// True when `inst` has a record named `name`.
pub fn has_record(inst: &Instance, name: &str) -> bool {
    inst.records.iter().any(|r| r.name == name)
}

/// A numeric value (integers and typed measures included).
pub fn as_real(v: &Value) -> Option<f64> {
    match v {
        Value::Real(r) => Some(*r),
        Value::Int(i) => Some(*i as f64),
        Value::Typed(_, inner) => as_real(inner),
        _ => None,
    }
}

impl<'a> Args<'a> {
    /// The context.
    pub fn ctx(&self) -> Ctx<'a> {
        self.ctx
    }

    /// An error at this entity.
    pub fn err(&self, reason: impl Into<String>) -> CadError {
        self.ctx.err(self.inst, reason)
    }

    /// An [`CadError::OutOfRange`] error at this entity.
    pub fn out_of_range(&self, what: &str, value: f64) -> CadError {
        CadError::OutOfRange {
            file: self.ctx.file.to_string(),
            line: self.inst.pos.line,
            column: self.inst.pos.column,
            entity: self.inst.id,
            entity_type: type_name(self.inst),
            what: what.to_string(),
            value,
            limit: crate::cad::error::MAX_COORDINATE_MM,
        }
    }

    /// Parameter `i`.
    pub fn get(&self, i: usize) -> CadResult<&'a Value> {
        self.params
            .get(i)
            .ok_or_else(|| self.err(format!("missing parameter {}", i + 1)))
    }

    /// Parameter `i` as a number.
    pub fn real(&self, i: usize) -> CadResult<f64> {
        as_real(self.get(i)?)
            .ok_or_else(|| self.err(format!("parameter {} is not a number", i + 1)))
    }

    /// Parameter `i` as a length in mm (finite, at most
    /// [`crate::cad::error::MAX_COORDINATE_MM`] in magnitude).
    pub fn length(&self, i: usize) -> CadResult<f64> {
        let v = self.real(i)? * self.ctx.length_mm;
        if !in_range(v) {
            return Err(self.out_of_range(&format!("parameter {}", i + 1), v));
        }
        Ok(v)
    }

    /// Parameter `i` as a non-negative integer.
    pub fn count(&self, i: usize) -> CadResult<usize> {
        match self.get(i)? {
            Value::Int(k) => usize::try_from(*k)
                .map_err(|_| self.err(format!("parameter {} is negative", i + 1))),
            _ => Err(self.err(format!("parameter {} is not an integer", i + 1))),
        }
    }

    /// Parameter `i` as a reference.
    pub fn reference(&self, i: usize) -> CadResult<u64> {
        as_ref(self.get(i)?)
            .ok_or_else(|| self.err(format!("parameter {} is not a reference", i + 1)))
    }

    /// Parameter `i` as a list.
    pub fn list(&self, i: usize) -> CadResult<&'a [Value]> {
        match self.get(i)? {
            Value::List(items) => Ok(items),
            _ => Err(self.err(format!("parameter {} is not a list", i + 1))),
        }
    }

    /// Parameter `i` as a boolean `.T.`/`.F.`.
    pub fn boolean(&self, i: usize) -> CadResult<bool> {
        match self.get(i)? {
            Value::Enum(e) if e == "T" => Ok(true),
            Value::Enum(e) if e == "F" => Ok(false),
            _ => Err(self.err(format!("parameter {} is not .T. or .F.", i + 1))),
        }
    }

    /// Parameter `i` as a string (empty for `$`).
    pub fn string(&self, i: usize) -> CadResult<&'a str> {
        match self.get(i)? {
            Value::Str(s) => Ok(s),
            _ => Ok(""),
        }
    }

    /// A list of references.
    pub fn refs(&self, i: usize) -> CadResult<Vec<u64>> {
        let items = self.list(i)?;
        items
            .iter()
            .map(|v| {
                as_ref(v)
                    .ok_or_else(|| self.err(format!("parameter {} must list references", i + 1)))
            })
            .collect()
    }

    /// A list of numbers.
    pub fn reals(&self, i: usize) -> CadResult<Vec<f64>> {
        let items = self.list(i)?;
        items
            .iter()
            .map(|v| {
                as_real(v).ok_or_else(|| self.err(format!("parameter {} must list numbers", i + 1)))
            })
            .collect()
    }

    /// A list of non-negative integers.
    pub fn counts(&self, i: usize) -> CadResult<Vec<usize>> {
        let items = self.list(i)?;
        let bad = || {
            self.err(format!(
                "parameter {} must list non-negative integers",
                i + 1
            ))
        };
        items
            .iter()
            .map(|v| match v {
                Value::Int(k) => usize::try_from(*k).map_err(|_| bad()),
                _ => Err(bad()),
            })
            .collect()
    }

    /// A list of lists of references (control point grids).
    pub fn ref_grid(&self, i: usize) -> CadResult<Vec<Vec<u64>>> {
        let bad = || {
            self.err(format!(
                "parameter {} must be a list of reference lists",
                i + 1
            ))
        };
        let rows = self.list(i)?;
        rows.iter()
            .map(|row| match row {
                Value::List(items) => items.iter().map(|v| as_ref(v).ok_or_else(bad)).collect(),
                _ => Err(bad()),
            })
            .collect()
    }

    /// A list of lists of numbers (weight grids).
    pub fn real_grid(&self, i: usize) -> CadResult<Vec<Vec<f64>>> {
        let bad = || {
            self.err(format!(
                "parameter {} must be a list of number lists",
                i + 1
            ))
        };
        let rows = self.list(i)?;
        rows.iter()
            .map(|row| match row {
                Value::List(items) => items.iter().map(|v| as_real(v).ok_or_else(bad)).collect(),
                _ => Err(bad()),
            })
            .collect()
    }
}

/// A reference value.
pub fn as_ref(v: &Value) -> Option<u64> {
    match v {
        Value::Ref(id) => Some(*id),
        _ => None,
    }
}

/// True when `v` (mm) is finite and at most
/// [`crate::cad::error::MAX_COORDINATE_MM`] in magnitude.
pub fn in_range(v: f64) -> bool {
    v.is_finite() && v.abs() <= crate::cad::error::MAX_COORDINATE_MM
}
