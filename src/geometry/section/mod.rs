//! Plane sections of surfaces: ordered polylines of points with outward
//! normals, refined to a chord tolerance, split into branches where the
//! plane cuts a surface more than once, and stitched across faces and seams
//! into open or closed curves.
//!
//! The zero set of `g(u, v) = (S(u, v) - o) . n` is traced by marching
//! squares on a parameter grid (a few cells per knot span), every crossing
//! is solved exactly on its grid edge, and chords are subdivided (each new
//! point Newton-projected onto `g = 0`) until the curve lies within the chord
//! tolerance of the polyline.

mod clip;
mod march;
mod refine;
mod shared;
mod stitch;

use crate::geometry::Trim;
use crate::geometry::{NurbsSurface, Plane};
use crate::math::{Point3, Vec2, Vec3};

/// Tolerances of section computation (lengths in mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionOptions {
    /// Largest allowed distance between the true section curve and the
    /// chord between neighbouring points, mm.
    pub chord_tol_mm: f64,
    /// Grid cells per knot span in each direction for seeding.
    pub cells_per_span: usize,
    /// Minimum grid cells per direction over the whole domain.
    pub min_cells: usize,
    /// Maximum recursive chord subdivisions between two grid crossings.
    pub max_refine_depth: usize,
    /// Curve ends closer than this are joined (across faces and seams), mm.
    pub join_tol_mm: f64,
    /// Curve ends still apart after joining at `join_tol_mm` are joined,
    /// nearest first, when closer than this, mm: two faces' curves meet on
    /// their shared edge only as well as the faces' trim loops (polylines,
    /// sampled by the CAD importers to about 1 um) agree.
    pub gap_tol_mm: f64,
    /// Section points closer than this to a face's boundary (trim loops or
    /// parameter domain sides) count as on it, mm: where the curve runs
    /// along the boundary (a face split in the section plane) it is kept,
    /// once for the faces that share that edge.
    pub edge_tol_mm: f64,
    /// Residual `|g|` at which a section point counts as on the plane, mm.
    pub plane_tol_mm: f64,
    /// Grid nodes closer to the plane than this count as on it (so that a
    /// plane along a parameter line is traced along that line), mm.
    pub snap_tol_mm: f64,
}

impl Default for SectionOptions {
    fn default() -> Self {
        SectionOptions {
            chord_tol_mm: 1e-3,
            cells_per_span: 8,
            min_cells: 32,
            max_refine_depth: 24,
            join_tol_mm: 1e-6,
            gap_tol_mm: 2e-3,
            edge_tol_mm: 1e-6,
            plane_tol_mm: 1e-11,
            snap_tol_mm: 1e-10,
        }
    }
}

/// A point of a section curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionPoint {
    /// Index of the face (0 for a lone surface).
    pub face: usize,
    /// Surface parameters.
    pub uv: Vec2,
    /// The point (on the plane and the surface).
    pub point: Point3,
    /// Unit outward surface normal.
    pub normal: Vec3,
}

/// One connected section curve, ordered so that its tangent runs along
/// `plane_normal x surface_normal` (counter-clockwise around material seen
/// from the plane normal's side).
#[derive(Debug, Clone, PartialEq)]
pub struct SectionCurve {
    /// Ordered points (a closed curve does not repeat its first point).
    pub points: Vec<SectionPoint>,
    /// Whether the curve closes on itself.
    pub closed: bool,
}

impl SectionCurve {
    /// Polyline length, including the closing segment of a closed curve, mm.
    pub fn length(&self) -> f64 {
        let open: f64 = self
            .points
            .windows(2)
            .map(|w| (w[1].point - w[0].point).norm())
            .sum();
        let closing = match (self.closed, self.points.first(), self.points.last()) {
            (true, Some(a), Some(b)) => (a.point - b.point).norm(),
            _ => 0.0,
        };
        open + closing
    }
}

/// Section of one surface (face id `face` recorded in the points), as
/// oriented branches, not yet stitched across seams.
pub fn section_surface(
    surface: &NurbsSurface,
    face: usize,
    plane: &Plane,
    opts: &SectionOptions,
) -> Vec<SectionCurve> {
    march::branches(surface, plane, opts)
        .into_iter()
        .map(|uvs| refine::refine_branch(surface, face, plane, &uvs, opts))
        .filter(|c| c.points.len() >= 2)
        .map(|c| stitch::orient(c, plane))
        .collect()
}

/// A face to section: its surface, its trim and the id its curves carry.
#[derive(Debug, Clone, Copy)]
pub struct FaceRef<'a> {
    /// Id of the face (its index in the workpiece).
    pub id: usize,
    /// The face's surface.
    pub surface: &'a NurbsSurface,
    /// The face's trim, if any.
    pub trim: Option<&'a Trim>,
}

/// Section of `faces`, stitched across faces and seams into maximal curves
/// (closed where they close); a stretch along an edge that two of the faces
/// share is kept once.
pub fn section_faces(
    faces: &[FaceRef<'_>],
    plane: &Plane,
    opts: &SectionOptions,
) -> Vec<SectionCurve> {
    let pieces: Vec<clip::Piece> = faces
        .iter()
        .flat_map(|f| face_pieces(f, plane, opts))
        .collect();
    let tol = opts.gap_tol_mm + opts.chord_tol_mm;
    stitch::stitch(shared::once(pieces, tol), opts.join_tol_mm, opts.gap_tol_mm)
}

/// Section of one face: its surface's branches clipped to its trim
/// (stretches along its boundary included), split where they join or leave
/// the boundary.
pub fn section_face(face: &FaceRef<'_>, plane: &Plane, opts: &SectionOptions) -> Vec<SectionCurve> {
    face_pieces(face, plane, opts)
        .into_iter()
        .map(|p| p.curve)
        .collect()
}

fn face_pieces(face: &FaceRef<'_>, plane: &Plane, opts: &SectionOptions) -> Vec<clip::Piece> {
    section_surface(face.surface, face.id, plane, opts)
        .into_iter()
        .flat_map(|c| clip::clip(c, face.surface, face.trim, plane, opts))
        .collect()
}
