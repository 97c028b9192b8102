//! Plane sections of a workpiece's faces.
use super::Workpiece;
use crate::geometry::section::{self, FaceRef};
use crate::geometry::{Plane, SectionCurve, SectionOptions};

/// Section of the listed faces of a workpiece (indices that name no face
/// are skipped), stitched across faces and seams into maximal curves
/// (closed where they close).
pub fn section_faces(
    wp: &Workpiece,
    faces: &[usize],
    plane: &Plane,
    opts: &SectionOptions,
) -> Vec<SectionCurve> {
    let refs: Vec<FaceRef<'_>> = (faces.iter())
        .filter_map(|&id| {
            wp.faces.get(id).map(|f| FaceRef {
                id,
                surface: &f.surface,
                trim: f.trim.as_ref(),
            })
        })
        .collect();
    section::section_faces(&refs, plane, opts)
}
