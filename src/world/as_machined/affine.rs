//! The affine transform `T(x) = L x + t` of the as-machined part, with what
//! the per-query code derives from it computed once.
use crate::math::{Mat3, Point3, Vec3};

/// `T(x) = L x + t` and its derived quantities.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Affine {
    /// `L`.
    linear: Mat3,
    /// `t`, mm.
    offset: Vec3,
    /// Whether `T` is the identity (`L = I`, `t = 0`): the per-cycle jets
    /// then skip the mapping.
    identity: bool,
    /// Largest factor by which `L` stretches lengths, at least 1.
    stretch: f64,
    /// `L^-1` (the identity when `L` is singular).
    inverse: Mat3,
}

impl Affine {
    /// `x -> linear x + offset`.
    pub(super) fn new(linear: Mat3, offset: Vec3) -> Affine {
        Affine {
            linear,
            offset,
            identity: linear == Mat3::identity() && offset == Vec3::zeros(),
            stretch: linear.singular_values().max().max(1.0),
            inverse: linear.try_inverse().unwrap_or_else(Mat3::identity),
        }
    }

    /// The identity.
    pub(super) fn identity() -> Affine {
        Affine::new(Mat3::identity(), Vec3::zeros())
    }

    /// The same linear part with the translation moved by `delta`.
    pub(super) fn moved(&self, delta: Vec3) -> Affine {
        Affine::new(self.linear, self.offset + delta)
    }

    /// `L`.
    pub(super) fn linear(&self) -> &Mat3 {
        &self.linear
    }

    /// `t`, mm.
    pub(super) fn offset(&self) -> Vec3 {
        self.offset
    }

    /// Whether `T` is the identity.
    pub(super) fn is_identity(&self) -> bool {
        self.identity
    }

    /// Largest factor by which `L` stretches lengths, at least 1.
    pub(super) fn stretch(&self) -> f64 {
        self.stretch
    }

    /// `T(x)`.
    pub(super) fn apply(&self, x: Point3) -> Point3 {
        Point3::from(self.linear * x.coords + self.offset)
    }

    /// `T^-1(x)` (with `L^-1` taken as the identity for a singular `L`).
    pub(super) fn inverse_point(&self, x: Point3) -> Point3 {
        Point3::from(self.inverse * (x.coords - self.offset))
    }
}
