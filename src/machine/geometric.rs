//! The 21 geometric error terms of a three-axis machine (JP2902285B2) and their
//! effect at the stylus tip.
//!
//! Per linear axis X, Y, Z: a scale error (along the axis), two
//! straightnesses (along the two other axes), and three small rotations —
//! roll about the axis itself, pitch about the first of the two other axes
//! and yaw about the second (x, y, z order: X pitches about Y and yaws about
//! Z; Y pitches about X and yaws about Z; Z pitches about X and yaws about
//! Y). Each is a polynomial in that axis's own position. Plus three
//! squareness angles. 6 x 3 + 3 = 21.
//!
//! Effect at the tip (JP2902285B2, equation 1): `delta = sum_i (e_i + theta_i x
//! C_iA)`, with `e_i` the translation error and `theta_i` the rotation
//! error of axis `i`, and `C_iA = C_iB + P` the lever arm from the axis's
//! fulcrum `C_i` to the tip `A` (via the spindle reference point `B` and the
//! probe vector `P`). Model choice: a rotation error of a carriage tilts
//! everything that carriage carries, about the carriage's own reference
//! point, so `C_iB` is the displacement of the axes stacked on axis `i`
//! ([`Stacking`]; for the bridge, Y carries X carries Z: the bridge's errors
//! act through `(x, 0, z)`, the carriage's through `(0, 0, z)`, the ram's
//! only through the probe vector).
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::math::Vec3;

/// A polynomial `c0 + c1 p + c2 p^2 + ...` in an axis position `p` (mm),
/// written as the list of coefficients `[c0, c1, ...]`. Coefficient `k` is in
/// mm/mm^k for translations and rad/mm^k for rotations; empty means zero.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(transparent)]
pub struct ErrorPolynomial(pub Vec<f64>);

impl ErrorPolynomial {
    /// Value at axis position `p` (mm), by Horner's rule.
    pub fn eval(&self, p: f64) -> f64 {
        self.0.iter().rev().fold(0.0, |acc, c| acc * p + c)
    }
}

/// The six error terms of one linear axis, each a polynomial in that
/// axis's position.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct LinearAxisErrors {
    /// Position error along the axis itself, mm (e.g. `[0, 5e-6]` = 5 ppm).
    pub scale_mm: ErrorPolynomial,
    /// Straightness along the first other axis (x, y, z order), mm.
    pub straightness_1_mm: ErrorPolynomial,
    /// Straightness along the second other axis, mm.
    pub straightness_2_mm: ErrorPolynomial,
    /// Rotation about the first other axis, rad.
    pub pitch_rad: ErrorPolynomial,
    /// Rotation about the second other axis, rad.
    pub yaw_rad: ErrorPolynomial,
    /// Rotation about the axis itself, rad.
    pub roll_rad: ErrorPolynomial,
}

impl LinearAxisErrors {
    /// All six polynomials with their JSON field names.
    pub fn terms(&self) -> [(&'static str, &ErrorPolynomial); 6] {
        [
            ("scale_mm", &self.scale_mm),
            ("straightness_1_mm", &self.straightness_1_mm),
            ("straightness_2_mm", &self.straightness_2_mm),
            ("pitch_rad", &self.pitch_rad),
            ("yaw_rad", &self.yaw_rad),
            ("roll_rad", &self.roll_rad),
        ]
    }

    /// Translation error (mm) and rotation error (rad) of axis `axis`
    /// (0 = X, 1 = Y, 2 = Z) at position `p` (mm), in machine coordinates.
    fn errors_at(&self, axis: usize, p: f64) -> (Vec3, Vec3) {
        let [first, second] = other_axes(axis);
        let mut translation = Vec3::zeros();
        let mut rotation = Vec3::zeros();
        for (index, t, r) in [
            (axis, &self.scale_mm, &self.roll_rad),
            (first, &self.straightness_1_mm, &self.pitch_rad),
            (second, &self.straightness_2_mm, &self.yaw_rad),
        ] {
            translation[index] = t.eval(p);
            rotation[index] = r.eval(p);
        }
        (translation, rotation)
    }
}

/// The two other axes of `axis`, in x, y, z order.
fn other_axes(axis: usize) -> [usize; 2] {
    match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

/// Out-of-squareness angles (rad); positive means the second axis leans
/// towards the positive direction of the first.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Squareness {
    /// Y leans towards +X: a Y move of `y` also moves X by `y * xy_rad`.
    pub xy_rad: f64,
    /// Z leans towards +X: a Z move of `z` also moves X by `z * xz_rad`.
    pub xz_rad: f64,
    /// Z leans towards +Y: a Z move of `z` also moves Y by `z * yz_rad`.
    pub yz_rad: f64,
}

/// Which linear axis carries which, from the base up: `yxz` (the default,
/// a bridge CMM) means Y carries X, which carries Z.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Stacking {
    /// X carries Y carries Z.
    Xyz,
    /// X carries Z carries Y.
    Xzy,
    /// Y carries X carries Z (bridge CMM).
    #[default]
    Yxz,
    /// Y carries Z carries X.
    Yzx,
    /// Z carries X carries Y.
    Zxy,
    /// Z carries Y carries X.
    Zyx,
}

impl Stacking {
    /// Axis indices (0 = X, 1 = Y, 2 = Z) from the base up.
    pub fn order(self) -> [usize; 3] {
        match self {
            Stacking::Xyz => [0, 1, 2],
            Stacking::Xzy => [0, 2, 1],
            Stacking::Yxz => [1, 0, 2],
            Stacking::Yzx => [1, 2, 0],
            Stacking::Zxy => [2, 0, 1],
            Stacking::Zyx => [2, 1, 0],
        }
    }

    /// Lever arm of axis `axis` without the probe vector: the positions of
    /// the axes it carries (mm).
    fn carried(self, axis: usize, b: &Vec3) -> Vec3 {
        let order = self.order();
        let above = order.iter().skip_while(|&&a| a != axis).skip(1);
        above.fold(Vec3::zeros(), |mut lever, &a| {
            lever[a] = b[a];
            lever
        })
    }
}

/// The 21 geometric error terms; all zero by default (a perfect machine).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct GeometricErrors {
    /// Errors of the X axis (polynomials in x).
    pub x: LinearAxisErrors,
    /// Errors of the Y axis (polynomials in y).
    pub y: LinearAxisErrors,
    /// Errors of the Z axis (polynomials in z).
    pub z: LinearAxisErrors,
    /// The three squareness angles.
    pub squareness: Squareness,
    /// Which axis carries which (sets the lever arms of rotation errors).
    pub stacking: Stacking,
}

impl GeometricErrors {
    /// The three axes with their JSON names.
    pub fn axes(&self) -> [(&'static str, &LinearAxisErrors); 3] {
        [("x", &self.x), ("y", &self.y), ("z", &self.z)]
    }

    /// Displacement (mm) of the stylus tip caused by the error terms, for
    /// the nominal axis positions `xyz` (mm, the spindle reference point
    /// `B`) and the probe vector `probe_vector` (mm, from `B` to the tip).
    pub fn displacement(&self, xyz: [f64; 3], probe_vector: &Vec3) -> Vec3 {
        let b = Vec3::from(xyz);
        let per_axis = self.axes().into_iter().enumerate().map(|(i, (_, errors))| {
            let (translation, rotation) = errors.errors_at(i, b[i]);
            let lever = self.stacking.carried(i, &b) + probe_vector;
            translation + rotation.cross(&lever)
        });
        per_axis.sum::<Vec3>() + self.squareness_displacement(&b)
    }

    fn squareness_displacement(&self, b: &Vec3) -> Vec3 {
        let s = &self.squareness;
        Vec3::new(b.y * s.xy_rad + b.z * s.xz_rad, b.z * s.yz_rad, 0.0)
    }
}
