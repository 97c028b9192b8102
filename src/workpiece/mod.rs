//! Workpieces: the part's nominal design data as named NURBS faces, read
//! from `cmm-workpiece/1` files (the cmm-workpiece/1 format), and the global closest-point
//! query over all faces.

pub mod examples;
pub use crate::formats::workpiece as format;
mod faces_near;
mod near;
mod section;
mod summary;
#[cfg(test)]
pub(crate) use near::walk as walk_support;
pub use summary::{FaceSummary, SUMMARY_GRID};
mod validate;

use std::path::{Path, PathBuf};

use crate::geometry::projection::{Foot, LeafMemo};
use crate::geometry::{
    NurbsSurface, Projection, ProjectionError, ProjectionIndex, ProjectionOptions, Trim,
};
use crate::math::{Point3, Vec2};
pub use format::{SurfaceSpec, TrimSpec, WorkpieceFile, WORKPIECE_FORMAT};
pub use near::{FaceList, FeetWithinReach, FootHint, KnownFoot, Reach};
pub use section::section_faces;

/// Why a workpiece could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum WorkpieceError {
    /// The file could not be read.
    #[error("{file}: cannot read: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// Not valid JSON, or a value of the wrong type or an unknown key.
    #[error(transparent)]
    Syntax(#[from] crate::jsonfile::JsonSyntaxError),
    /// The file parses but its content is invalid.
    #[error("{file}: {json_path}: {reason}")]
    Invalid {
        /// The file.
        file: PathBuf,
        /// JSON path of the offending value.
        json_path: String,
        /// What is wrong.
        reason: String,
    },
    /// A STEP/IGES file could not be read or holds no usable face; the
    /// error names the file, the line:column and the reason.
    #[error(transparent)]
    Cad(#[from] crate::cad::CadError),
}

/// One face of a workpiece: a named surface with its search hierarchy.
#[derive(Debug, Clone)]
pub struct Face {
    /// Unique name.
    pub name: String,
    /// The geometry.
    pub surface: NurbsSurface,
    /// Cold-projection hierarchy of `surface`, built on first use
    /// ([`Face::index`]): a program that measures a few faces of a part
    /// with hundreds builds those and the ones its moves pass near.
    index: std::sync::OnceLock<ProjectionIndex>,
    /// The projection tolerances the hierarchy is built with.
    options: ProjectionOptions,
    /// The box of the surface's control points (the surface lies in
    /// their hull), corners.
    bounds: (Point3, Point3),
    /// The face's trim region, when the surface is trimmed.
    pub trim: Option<Trim>,
}

/// A validated workpiece.
#[derive(Debug, Clone)]
pub struct Workpiece {
    /// Part name.
    pub name: String,
    /// Faces in file order.
    pub faces: Vec<Face>,
    /// Projection tolerances used for every query.
    pub options: ProjectionOptions,
    /// Every face's box in one tree (made on first use): a query finds
    /// the faces near a point without touching the others.
    face_tree: std::sync::OnceLock<faces_near::FaceTree>,
    /// [`Self::design_hash`], made on first use.
    design_hash: std::sync::OnceLock<u64>,
}

/// The global closest point over all faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceProjection {
    /// Index of the face in [`Workpiece::faces`].
    pub face: usize,
    /// The projection onto that face.
    pub projection: Projection,
}

impl Workpiece {
    /// Reads and validates a workpiece: a STEP (.step/.stp) or IGES
    /// (.iges/.igs) file, any case, goes through [`crate::cad::import`];
    /// anything else is read as `cmm-workpiece/1` JSON.
    pub fn from_path(path: &Path) -> Result<Workpiece, WorkpieceError> {
        if is_cad_path(path) {
            let import = crate::cad::import(path)?;
            return Workpiece::from_file(&import.workpiece, path);
        }
        let text = crate::jsonfile::read_text(path).map_err(|source| WorkpieceError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        let file = validate::parse(&text, path)?;
        Workpiece::from_file(&file, path)
    }

    /// Validates parsed file content; `path` is used in messages only.
    pub fn from_file(file: &WorkpieceFile, path: &Path) -> Result<Workpiece, WorkpieceError> {
        validate::check_header(file, path)?;
        let options = ProjectionOptions::default();
        let faces = file
            .surfaces
            .iter()
            .enumerate()
            .map(|(i, spec)| {
                validate::surface(spec, i, path).map(|s| {
                    let trim = spec.trim.as_ref().map(|t| Trim::new(&t.outer, &t.holes));
                    Face::new(spec.name.clone(), s, &options).with_trim(trim)
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Workpiece::new(file.name.clone(), faces, options))
    }

    /// The part `name` of `faces`, queried with `options`.
    pub fn new(name: String, faces: Vec<Face>, options: ProjectionOptions) -> Workpiece {
        Workpiece {
            name,
            faces,
            options,
            face_tree: std::sync::OnceLock::new(),
            design_hash: std::sync::OnceLock::new(),
        }
    }

    /// A hash of the whole design (every face's knots, control points,
    /// weights, orientation and trim vertices; SipHash with fixed keys:
    /// the same in every process), made once: what is derived from the
    /// design alone can be kept under it.
    pub fn design_hash(&self) -> u64 {
        *self.design_hash.get_or_init(|| {
            use std::hash::{DefaultHasher, Hash, Hasher};
            let mut h = DefaultHasher::new();
            let mut put = |x: f64| x.to_bits().hash(&mut h);
            for f in &self.faces {
                let s = &f.surface;
                for x in s.knots_u().as_slice().iter().chain(s.knots_v().as_slice()) {
                    put(*x);
                }
                for p in s.homogeneous_points() {
                    p.iter().for_each(|x| put(*x));
                }
                put(f64::from(u8::from(s.is_reversed())));
                for (a, b) in f.trim.iter().flat_map(|t| t.segments()) {
                    [a.x, a.y, b.x, b.y].into_iter().for_each(&mut put);
                }
                put(f64::NAN);
            }
            self.faces.len().hash(&mut h);
            h.finish()
        })
    }

    /// A lower bound of the distance from `p` to face `i` (its box), mm;
    /// infinite for no such face.
    #[inline]
    pub fn face_box_distance(&self, i: usize, p: Point3) -> f64 {
        self.face_tree().distance(i, p)
    }

    /// The faces whose box comes no farther than `d` (mm) from `p`, in
    /// ascending order, into `out`; every face when `d` is not finite.
    pub fn faces_within(&self, p: Point3, d: f64, out: &mut Vec<usize>) {
        self.face_tree().within(p, d, out);
    }

    /// The faces whose box meets the box from `lo` to `hi`, in ascending
    /// order, into `out` (a face without a box never does).
    pub fn faces_overlapping(&self, lo: Point3, hi: Point3, out: &mut Vec<usize>) {
        self.face_tree().overlapping(lo, hi, out);
    }

    /// The least of `best` and `value(face, box distance)` over the faces
    /// whose box comes nearer to `p` than the least so far, nearer boxes
    /// first (mm): with `value` a lower bound of a face's distance that is
    /// at least its box distance (its leaf boxes, say), a lower bound of
    /// the part's distance from `p`. `value` may leave a face out (`None`).
    pub fn nearest_face_box(
        &self,
        p: Point3,
        best: f64,
        value: impl FnMut(usize, f64) -> Option<f64>,
    ) -> f64 {
        self.face_tree().nearest(p, best, value)
    }

    fn face_tree(&self) -> &faces_near::FaceTree {
        self.face_tree.get_or_init(|| {
            let boxes: Vec<faces_near::FaceBox> = (self.faces.iter())
                .map(|f| {
                    let (lo, hi) = f.bounds();
                    [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z]
                })
                .collect();
            faces_near::FaceTree::new(&boxes)
        })
    }

    /// Index of the face called `name`.
    pub fn face_index(&self, name: &str) -> Option<usize> {
        self.faces.iter().position(|f| f.name == name)
    }

    /// Global closest point over all faces (ties go to the earlier face).
    pub fn closest_point(&self, p: Point3) -> Result<FaceProjection, ProjectionError> {
        self.closest_point_among(p, 0..self.faces.len())
    }

    /// Global closest point over the faces listed in `faces`.
    pub fn closest_point_among(
        &self,
        p: Point3,
        faces: impl IntoIterator<Item = usize>,
    ) -> Result<FaceProjection, ProjectionError> {
        self.closest_point_within(p, faces, f64::INFINITY, None)?
            .map(|(found, _)| found)
            .ok_or(ProjectionError::NotFinite {
                x: p.x,
                y: p.y,
                z: p.z,
            })
    }
}

/// True when `path` has a STEP or IGES extension (any case).
pub fn is_cad_path(path: &Path) -> bool {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    ["step", "stp", "iges", "igs"]
        .iter()
        .any(|c| ext.eq_ignore_ascii_case(c))
}

impl Face {
    /// Wraps a surface (its hierarchy is built on first use).
    pub fn new(name: String, surface: NurbsSurface, options: &ProjectionOptions) -> Face {
        let points = surface.homogeneous_points().iter();
        let cartesian = points.map(|p| Point3::new(p.x / p.w, p.y / p.w, p.z / p.w));
        let bounds = cartesian.fold(
            (
                Point3::from([f64::INFINITY; 3]),
                Point3::from([f64::NEG_INFINITY; 3]),
            ),
            |(lo, hi), q| (lo.inf(&q), hi.sup(&q)),
        );
        Face {
            name,
            surface,
            index: std::sync::OnceLock::new(),
            options: *options,
            bounds,
            trim: None,
        }
    }

    /// The cold-projection hierarchy of the surface, built on first use.
    pub fn index(&self) -> &ProjectionIndex {
        self.index
            .get_or_init(|| ProjectionIndex::new(&self.surface, &self.options))
    }

    /// The corners of a box that holds the whole surface (that of its
    /// control points), without building the hierarchy.
    pub fn bounds(&self) -> (Point3, Point3) {
        self.bounds
    }

    /// A lower bound of the distance from `p` to the surface (its
    /// control points' box), mm, without building the hierarchy.
    pub fn lower_bound(&self, p: Point3) -> f64 {
        let (lo, hi) = self.bounds;
        let gap = (lo - p).sup(&(p - hi)).sup(&crate::math::Vec3::zeros());
        gap.norm()
    }

    /// The same face restricted to a trim region.
    pub fn with_trim(mut self, trim: Option<Trim>) -> Face {
        self.trim = trim;
        self
    }

    /// Whether `uv` lies on the face (inside its trim, if any).
    pub fn contains(&self, uv: Vec2) -> bool {
        self.trim.as_ref().is_none_or(|t| t.contains(uv))
    }

    /// The closest point of the face (trim respected) closer than
    /// `sqrt(best_dist2)`, if any, leaving out leaf `skip`, with the leaf of
    /// the foot (`None` on the trim boundary); depth first when `tight`
    /// (`best_dist2` comes from a point found nearby), else best first.
    /// `memo` (depth first only) spares leaves that earlier queries found
    /// far enough, and learns from this one.
    fn search(
        &self,
        (p, best_dist2): (Point3, f64),
        skip: Option<usize>,
        tight: bool,
        memo: &mut dyn LeafMemo,
    ) -> Result<Option<(Option<usize>, Foot)>, ProjectionError> {
        let (surface, trim) = (&self.surface, self.trim.as_ref());
        if tight {
            (self.index()).search_depth_first(surface, trim, (p, best_dist2), skip, memo)
        } else {
            self.index().search(surface, trim, p, best_dist2, skip)
        }
    }

    /// The closest point of one leaf of the search tree closer than
    /// `sqrt(best_dist2)`, as [`Self::search`] finds it.
    fn search_leaf(
        &self,
        p: Point3,
        leaf: usize,
        best_dist2: f64,
    ) -> Result<Option<Foot>, ProjectionError> {
        self.index()
            .search_leaf(&self.surface, self.trim.as_ref(), leaf, p, best_dist2)
    }
}
