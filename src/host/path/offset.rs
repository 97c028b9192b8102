//! Offsetting nominal points along their normals (JP6484108B2: by `r - Ep`)
//! and validating the result.

use super::{PathError, PathOptions};
use crate::math::{all_finite, Point3, Vec3};

/// A nominal point with its unit normal and the ball centre offset from it.
pub(crate) struct OffsetPoint {
    pub nominal: Point3,
    pub normal: Vec3,
    pub centre: Point3,
}

/// Offsets every point by `offset_mm` along its normalised normal.
pub(crate) fn offset_points(
    points: &[(Point3, Vec3)],
    closed: bool,
    offset_mm: f64,
    opts: &PathOptions,
) -> Result<Vec<OffsetPoint>, PathError> {
    check_count(points.len(), closed)?;
    if !offset_mm.is_finite() {
        return Err(PathError::NonFiniteOffset { offset_mm });
    }
    let out = points
        .iter()
        .enumerate()
        .map(|(index, (p, n))| offset_one(index, p, n, offset_mm, opts.min_normal_norm))
        .collect::<Result<Vec<_>, _>>()?;
    check_chords(&out, closed, opts.min_chord_mm)?;
    Ok(out)
}

/// At least 2 points for an open path, 3 for a closed one.
fn check_count(count: usize, closed: bool) -> Result<(), PathError> {
    let (min, kind) = if closed { (3, "closed") } else { (2, "open") };
    if count < min {
        return Err(PathError::TooFewPoints { count, min, kind });
    }
    Ok(())
}

fn offset_one(
    index: usize,
    p: &Point3,
    n: &Vec3,
    offset_mm: f64,
    min_norm: f64,
) -> Result<OffsetPoint, PathError> {
    if !all_finite(p.coords.as_slice()) || !all_finite(n.as_slice()) {
        return Err(PathError::NonFinite { index });
    }
    let norm = n.norm();
    if norm < min_norm {
        return Err(PathError::ZeroNormal {
            index,
            norm,
            min: min_norm,
        });
    }
    let normal = n / norm;
    Ok(OffsetPoint {
        nominal: *p,
        normal,
        centre: p + normal * offset_mm,
    })
}

/// Rejects consecutive offset points closer than `min_mm` (the closing
/// chord too when `closed`).
fn check_chords(points: &[OffsetPoint], closed: bool, min_mm: f64) -> Result<(), PathError> {
    let n = points.len();
    let count = if closed { n } else { n - 1 };
    for index in 0..count {
        let next = (index + 1) % n;
        let distance_mm = (points[next].centre - points[index].centre).norm();
        if distance_mm < min_mm || !distance_mm.is_finite() {
            return Err(PathError::CoincidentPoints {
                index,
                next,
                distance_mm,
                min_mm,
            });
        }
    }
    Ok(())
}
