//! Planes.
use crate::math::{Point3, Vec3};

/// A plane through `origin` with unit `normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    origin: Point3,
    normal: Vec3,
}

/// Why a plane could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlaneError {
    /// The normal is zero or not finite.
    #[error("plane normal {0:?} must be a finite non-zero vector")]
    BadNormal([f64; 3]),
    /// The origin is not finite.
    #[error("plane origin {0:?} must be finite")]
    BadOrigin([f64; 3]),
}

impl Plane {
    /// Builds a plane; the normal is normalised.
    ///
    /// ```
    /// let p = cmm::geometry::Plane::try_new([0., 0., 5.].into(), [0., 0., 2.].into()).unwrap();
    /// assert_eq!(p.signed_distance([1., 2., 7.].into()), 2.0);
    /// ```
    pub fn try_new(origin: Point3, normal: Vec3) -> Result<Plane, PlaneError> {
        if !origin.iter().all(|c| c.is_finite()) {
            return Err(PlaneError::BadOrigin(origin.into()));
        }
        match normal.try_normalize(1e-300) {
            Some(n) if n.iter().all(|c| c.is_finite()) => Ok(Plane { origin, normal: n }),
            _ => Err(PlaneError::BadNormal(normal.into())),
        }
    }
    /// A point on the plane.
    pub fn origin(&self) -> Point3 {
        self.origin
    }
    /// Unit normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }
    /// Signed distance of `p` from the plane (positive on the normal's side).
    pub fn signed_distance(&self, p: Point3) -> f64 {
        (p - self.origin).dot(&self.normal)
    }
}
