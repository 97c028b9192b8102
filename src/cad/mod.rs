//! CAD import: a focused STEP and IGES reader that turns B-rep
//! faces into trimmed NURBS [`SurfaceSpec`]s of a [`WorkpieceFile`].
//!
//! Entry point: [`import`] (dispatch on `.step`/`.stp`/`.iges`/`.igs`, any
//! case) returning an [`Import`]: the workpiece (mm), one [`FaceRecord`] per
//! converted face and [`Diagnostic`]s for faces skipped or left untrimmed.
//!
//! * STEP (ISO 10303-21): [`step::parse_step_str`] tokenizes and parses the
//!   exchange structure and resolves references (unknown and cyclic
//!   references are errors); it never panics and never recurses deeper than
//!   [`step::parser::MAX_NESTING`]. Faces (ADVANCED_FACE, FACE_SURFACE) on
//!   planes, cylinders, cones, spheres and tori are converted exactly
//!   (rational quadratic arcs, [`convert::arc`]); surfaces of revolution and
//!   linear extrusion are revolved/extruded NURBS of their profile; B-spline
//!   surfaces (simple and rational complex form) are taken as they are.
//!   Trims: elementary and swept faces map their sampled edges to (u, v)
//!   analytically ([`convert::trim`]); B-spline faces use PCURVEs (checked
//!   against the vertices, [`ImportOptions::pcurve_tolerance_mm`]), else
//!   their 3-D edges projected onto the surface with the geometry kernel
//!   ([`step::projected`], every sample within
//!   [`ImportOptions::projection_tolerance_mm`] of the surface), else they
//!   are left `trim: None` with a diagnostic giving the miss in mm.
//! * IGES 5.3: 144 trimmed surfaces on 128 rational B-spline surfaces with
//!   parameter-space boundaries (142 -> 102 / 110 / 100 / 126), 124
//!   transformations, units from the Global section; free 128s untrimmed.
//!
//! Trims are clamped into the surface domain and oriented (outer loop
//! counter-clockwise in (u, v), holes clockwise). Face names: the face's name
//! when non-empty, else `face<N>` (N = 1-based order in the file), made unique
//! with a `-face<N>` suffix.
//!
//! STEP assemblies ([`step::assembly`]): every product instance
//! (NEXT_ASSEMBLY_USAGE_OCCURRENCE with its ITEM_DEFINED_TRANSFORMATION,
//! MAPPED_ITEM, nested) is placed into the top frame and named
//! `instance#k/face<N>`; [`Import::products`] holds the tree. The
//! edge-on-surface tolerance follows the file's declared uncertainty
//! ([`ImportOptions::use_file_uncertainty`]).
//!
//! Not handled (yet): offsets of non-elementary surfaces, compressed IGES.
//!
//! Speed (`cargo bench --bench cad`, 2-core shared machine, before the
//! projected trims): parse of linkrods.step (1.8 MB) ~30 ms, its full import
//! ~80 ms; nist_ctc_05 (0.3 MB) ~48 ms; bearing.iges (1.3 MB) ~19 ms.
//! Projected trims add a projection per edge sample (not yet benchmarked).
pub mod convert;
pub mod error;
pub mod geom;
pub mod iges;
pub mod nurbs;
pub mod options;
pub mod sample;
pub mod step;

pub use error::{CadError, CadResult};
pub use options::ImportOptions;
pub use step::parse_step_str;

use crate::formats::workpiece::{SurfaceSpec, WorkpieceFile, WORKPIECE_FORMAT};
use std::collections::HashSet;
use std::path::Path;

/// What happened to a face that did not convert fully.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiagnosticKind {
    /// The face could not be converted and is not in the workpiece.
    Skipped,
    /// The face was converted but has no trim (`trim: None`).
    Untrimmed,
}

/// One import note about an entity.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Entity id (STEP instance number, IGES directory-entry sequence number).
    pub entity: u64,
    /// Entity type (`ADVANCED_FACE`, `IGES 144`, ...).
    pub entity_type: String,
    /// Line of the entity.
    pub line: usize,
    /// Column of the entity.
    pub column: usize,
    /// Skipped or untrimmed.
    pub kind: DiagnosticKind,
    /// Why.
    pub message: String,
}

/// One converted face.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceRecord {
    /// Surface name in the workpiece.
    pub name: String,
    /// Face entity id.
    pub entity: u64,
    /// Type of the underlying surface entity (`PLANE`, `IGES 128`, ...).
    pub surface_type: String,
}

/// Where a face comes from: entity id, type and position.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Source {
    /// Entity id.
    pub entity: u64,
    /// Surface type (converted faces) or face entity type (skipped faces).
    pub entity_type: String,
    /// Position of the entity.
    pub pos: step::lexer::Pos,
}

/// The result of an import.
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    /// The converted workpiece (mm).
    pub workpiece: WorkpieceFile,
    /// One record per converted face, in workpiece order.
    pub faces: Vec<FaceRecord>,
    /// Faces skipped or left untrimmed, with reasons.
    pub diagnostics: Vec<Diagnostic>,
    /// The product tree (STEP assemblies); empty for files without one.
    pub products: Vec<step::assembly::ProductNode>,
    names: HashSet<String>,
}

impl Import {
    pub(crate) fn new(name: &str) -> Import {
        let workpiece = WorkpieceFile {
            format: WORKPIECE_FORMAT.into(),
            name: name.into(),
            units: "mm".into(),
            surfaces: Vec::new(),
        };
        Import {
            workpiece,
            faces: Vec::new(),
            diagnostics: Vec::new(),
            products: Vec::new(),
            names: HashSet::new(),
        }
    }

    /// Adds face number `n` (1-based, file order) under a unique name.
    pub(crate) fn push_face(
        &mut self,
        n: usize,
        name: &str,
        src: Source,
        mut spec: SurfaceSpec,
        untrimmed: Option<String>,
    ) {
        let unique = self.unique_name(n, name);
        spec.name = unique.clone();
        clamp_trim(&mut spec);
        orient_trim(&mut spec);
        if let Some(message) = untrimmed {
            self.note(&src, DiagnosticKind::Untrimmed, message);
        }
        self.faces.push(FaceRecord {
            name: unique,
            entity: src.entity,
            surface_type: src.entity_type,
        });
        self.workpiece.surfaces.push(spec);
    }

    /// The face's own name, or `face<n>`; made unique with a `-face<n>` suffix.
    fn unique_name(&mut self, n: usize, name: &str) -> String {
        let base = if name.trim().is_empty() {
            format!("face{n}")
        } else {
            name.to_string()
        };
        let unique = if self.names.contains(&base) {
            format!("{base}-face{n}")
        } else {
            base
        };
        self.names.insert(unique.clone());
        unique
    }

    /// Records a diagnostic about `src`.
    pub(crate) fn note(&mut self, src: &Source, kind: DiagnosticKind, message: String) {
        let Source {
            entity,
            entity_type,
            pos,
        } = src.clone();
        self.diagnostics.push(Diagnostic {
            entity,
            entity_type,
            line: pos.line,
            column: pos.column,
            kind,
            message,
        });
    }

    pub(crate) fn finish(self, file: &str, line: usize, column: usize) -> CadResult<Import> {
        if !self.workpiece.surfaces.is_empty() {
            return Ok(self);
        }
        let skipped = self.diagnostics.len();
        let first = self
            .diagnostics
            .first()
            .map(|d| format!(": first: #{} {}", d.entity, d.message))
            .unwrap_or_default();
        Err(CadError::NoFaces {
            file: file.into(),
            line,
            column,
            reason: format!("{skipped} face(s) could not be converted{first}"),
        })
    }
}

/// Clamps trim points into the surface's parameter domain (files carry
/// boundary curves that overshoot it by round-off).
fn clamp_trim(spec: &mut SurfaceSpec) {
    let domain = |k: &[f64], p: usize| {
        (
            k.get(p).copied().unwrap_or(0.0),
            k.get(k.len().saturating_sub(p + 1)).copied().unwrap_or(0.0),
        )
    };
    let (u0, u1) = domain(&spec.knots_u, spec.degree[0]);
    let (v0, v1) = domain(&spec.knots_v, spec.degree[1]);
    if !(u0 <= u1 && v0 <= v1) {
        return;
    }
    if let Some(t) = spec.trim.as_mut() {
        for p in t.outer.iter_mut().chain(t.holes.iter_mut().flatten()) {
            *p = [p[0].clamp(u0, u1), p[1].clamp(v0, v1)];
        }
    }
}

/// Orients trims: outer loop counter-clockwise in (u, v), holes clockwise.
fn orient_trim(spec: &mut SurfaceSpec) {
    if let Some(t) = spec.trim.as_mut() {
        if signed_area(&t.outer) < 0.0 {
            t.outer.reverse();
        }
        for h in t.holes.iter_mut().filter(|h| signed_area(h) > 0.0) {
            h.reverse();
        }
    }
}

/// Shoelace area of a closed polyline (positive when counter-clockwise).
pub fn signed_area(pts: &[[f64; 2]]) -> f64 {
    let next = pts.iter().cycle().skip(1);
    0.5 * pts
        .iter()
        .zip(next)
        .map(|(a, b)| a[0] * b[1] - b[0] * a[1])
        .sum::<f64>()
}

/// Imports a STEP (.step/.stp) or IGES (.iges/.igs) file with default options.
pub fn import(path: impl AsRef<Path>) -> CadResult<Import> {
    import_with(path, &ImportOptions::default())
}

/// Imports a CAD file with the given tolerances.
pub fn import_with(path: impl AsRef<Path>, opts: &ImportOptions) -> CadResult<Import> {
    let path = path.as_ref();
    let file = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("part")
        .to_string();
    let io = |e: std::io::Error| CadError::Io {
        file: file.clone(),
        line: 0,
        column: 0,
        reason: e.to_string(),
    };
    match ext.as_str() {
        "step" | "stp" => {
            let bytes = std::fs::read(path).map_err(io)?;
            step::import_step(&String::from_utf8_lossy(&bytes), &file, &name, opts)
        }
        "iges" | "igs" => {
            let bytes = std::fs::read(path).map_err(io)?;
            iges::import_iges(&String::from_utf8_lossy(&bytes), &file, &name, opts)
        }
        _ => Err(CadError::UnsupportedType {
            file: file.clone(),
            line: 0,
            column: 0,
            reason: format!("extension {ext:?}; expected .step, .stp, .iges or .igs"),
        }),
    }
}
