//! Numeric type aliases used everywhere in `cmm`.
//!
//! All lengths are `f64` millimetres; angles are radians unless a name says
//! `_deg`. Points and vectors are nalgebra types so that the geometry kernel,
//! the simulator and the fitting code share one vocabulary.

/// A point in 3-D space, mm.
pub type Point3 = nalgebra::Point3<f64>;
/// A free vector in 3-D space (direction or displacement), mm.
pub type Vec3 = nalgebra::Vector3<f64>;
/// A homogeneous (weighted) control point `[w*x, w*y, w*z, w]`.
pub type Vec4 = nalgebra::Vector4<f64>;
/// A 2-vector, e.g. a surface parameter pair `(u, v)`.
pub type Vec2 = nalgebra::Vector2<f64>;
/// A 2x2 matrix (Newton systems in the parameter domain).
pub type Mat2 = nalgebra::Matrix2<f64>;
/// A 3x3 matrix (rotations, scalings, sensor gain matrices).
pub type Mat3 = nalgebra::Matrix3<f64>;
/// A unit direction in 3-D.
pub type Dir3 = nalgebra::Unit<Vec3>;
/// A rigid transform (rotation + translation), mm.
pub type Iso3 = nalgebra::Isometry3<f64>;

/// Converts degrees to radians.
pub fn deg_to_rad(deg: f64) -> f64 {
    deg.to_radians()
}

/// Largest magnitude of a rotation angle a program or an `as_machined`
/// block may give, degrees: one full turn either way (a larger angle names
/// the same rotation less exactly, and 1e300 degrees names none).
pub const MAX_ROTATION_DEG: f64 = 360.0;

/// Rotation matrix `Rz(rz) * Ry(ry) * Rx(rx)` about the fixed axes, angles in
/// degrees, as used by placements and as-machined transforms (the as-machined format).
///
/// ```
/// let r = cmm::math::rotation_xyz_deg([0.0, 0.0, 90.0]);
/// let x = r * cmm::math::Vec3::x();
/// assert!((x - cmm::math::Vec3::y()).norm() < 1e-15);
/// ```
pub fn rotation_xyz_deg(rotate_deg: [f64; 3]) -> Mat3 {
    let [rx, ry, rz] = rotate_deg.map(deg_to_rad);
    let rot_x = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), rx);
    let rot_y = nalgebra::Rotation3::from_axis_angle(&Vec3::y_axis(), ry);
    let rot_z = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), rz);
    (rot_z * rot_y * rot_x).into_inner()
}

/// `true` when every component is finite.
pub fn all_finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}
