//! The `cmm-workpiece/1` file format (the cmm-workpiece/1 format): serde types, from which
//! the JSON Schema (`cmm schema workpiece`) is generated too.
//!
//! These types only describe the file; [`crate::workpiece::Workpiece::from_file`] turns
//! them into validated geometry.
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::geometry::{NurbsError, NurbsSurface};

/// The format tag every workpiece file carries.
pub const WORKPIECE_FORMAT: &str = "cmm-workpiece/1";

/// A workpiece file: named NURBS surfaces in millimetres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WorkpieceFile {
    /// Always `"cmm-workpiece/1"`.
    pub format: String,
    /// Name of the part.
    pub name: String,
    /// Length unit; only `"mm"` is accepted.
    #[serde(default = "default_units")]
    pub units: String,
    /// The part's surfaces (at least one, unique names).
    pub surfaces: Vec<SurfaceSpec>,
}

fn default_units() -> String {
    "mm".into()
}

/// One rational B-spline (NURBS) surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// Unique surface name.
    pub name: String,
    /// Degrees `[degree_u, degree_v]`.
    pub degree: [usize; 2],
    /// Non-decreasing knot vector in u (need not lie in [0, 1]).
    pub knots_u: Vec<f64>,
    /// Non-decreasing knot vector in v.
    pub knots_v: Vec<f64>,
    /// `control_points[i][j]`: i along u (len(knots_u) - degree_u - 1 rows),
    /// j along v (len(knots_v) - degree_v - 1 columns), each `[x, y, z]` in mm.
    pub control_points: Vec<Vec<[f64; 3]>>,
    /// Positive weights with the same shape as `control_points`; all 1 when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<Vec<f64>>>,
    /// When true the outward normal is `-(Su x Sv)`; otherwise `Su x Sv`.
    #[serde(default, skip_serializing_if = "is_false")]
    pub reversed: bool,
    /// Optional trimming loops in the parameter domain (a face of a CAD part).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trim: Option<TrimSpec>,
}

impl SurfaceSpec {
    /// The kernel surface of this spec (degrees, knots, control points,
    /// weights and orientation checked by [`NurbsSurface::try_new`]).
    pub fn to_surface(&self) -> Result<NurbsSurface, NurbsError> {
        NurbsSurface::try_new(
            self.degree,
            self.knots_u.clone(),
            self.knots_v.clone(),
            &self.control_points,
            self.weights.as_deref(),
            self.reversed,
        )
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// Trimming loops: closed polylines in the surface's (u, v) domain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TrimSpec {
    /// The outer boundary `[[u, v], ...]` (closing segment implied).
    pub outer: Vec<[f64; 2]>,
    /// Holes, each a closed polyline `[[u, v], ...]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Vec<[f64; 2]>>,
}
