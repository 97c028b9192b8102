//! Condition-dependent correction of the probe's deflection reading (seed
//! 002), applied by the host when it turns readings into points.
//!
//! Two parts, both found by `cmm calibrate-probe` on a reference sphere:
//! - **ball**: the corrected deflection vector is
//!   `d = m + (E0 + E1 |m| + E2 |m|^2) m` for the raw reading `m` (mm), with
//!   symmetric 3x3 matrices `E0` (dimensionless), `E1` (1/mm), `E2` (1/mm^2):
//!   gain, cross-talk and nonlinearity as polynomials in the deflection
//!   amount. It moves the ball centre.
//! - **normal**: while scanning, friction drags the stylus against the motion,
//!   so the deflection direction leans away from the surface normal. The
//!   measured normal is the deflection direction turned towards the motion by
//!   the angle `tilt(|m|)` (rad, a polynomial in the deflection), one
//!   polynomial per coordinate plane (XY, XZ, YZ) and scanning direction
//!   (clockwise, counter-clockwise). The plane and direction come from the
//!   rotation axis `a = normalize(d x t)` of the local motion (`t` = commanded
//!   velocity across the deflection): plane XY for axis z, XZ for y, YZ for
//!   x; counter-clockwise when `a` points along the positive axis. The three
//!   planes' tilts are blended with weights `a_k^2` (condition-dependent probe correction, equation 9,
//!   weighs by the motion's amplitude per axis in the same spirit).
use crate::math::{Mat3, Vec3};

/// Polynomial degree + 1 of every correction term in the deflection amount.
pub const CORRECTION_TERMS: usize = 3;

/// Below this commanded speed across the deflection (mm/s) the motion has no
/// direction and the normal is not tilted.
pub const MIN_SCAN_SPEED_MM_S: f64 = 0.5;

/// The motion counts as scanning only when its part across the deflection is
/// at least this fraction of the commanded speed (dimensionless); touch
/// points move along the deflection and keep the plain direction.
pub const MIN_ACROSS_FRACTION: f64 = 0.5;

/// Coordinate planes of the direction-dependent terms, by their normal axis.
pub const PLANES: [&str; 3] = ["yz", "xz", "xy"];

/// Scanning directions, clockwise first.
pub const DIRECTIONS: [&str; 2] = ["cw", "ccw"];

/// A polynomial in the deflection amount, coefficients from degree 0.
pub type DeflectionPoly = [f64; CORRECTION_TERMS];

/// The correction of deflection readings (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeflectionCorrection {
    /// `E0, E1, E2`: gain correction matrices per power of `|m|`.
    pub gain: [Mat3; CORRECTION_TERMS],
    /// Normal tilt (rad) per plane (by normal axis x, y, z = YZ, XZ, XY)
    /// and direction (cw, ccw), as polynomials in `|m|` (mm).
    pub tilt: [[DeflectionPoly; 2]; 3],
}

impl Default for DeflectionCorrection {
    fn default() -> Self {
        DeflectionCorrection::identity()
    }
}

/// Value of a polynomial at `x`.
pub fn poly_eval(p: &DeflectionPoly, x: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, c| acc * x + c)
}

/// The scanning condition of one reading: the motion's rotation axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanCondition {
    /// Unit rotation axis `normalize(d x t)`.
    pub axis: Vec3,
    /// Unit motion direction across the deflection.
    pub across: Vec3,
}

impl ScanCondition {
    /// The condition of deflection direction `d` under commanded velocity
    /// `motion`; `None` when the motion has no component across `d`.
    pub fn of(d: Vec3, motion: Vec3) -> Option<ScanCondition> {
        let u = d.try_normalize(1e-12)?;
        let t = motion - u * motion.dot(&u);
        if t.norm() < MIN_SCAN_SPEED_MM_S || t.norm() < MIN_ACROSS_FRACTION * motion.norm() {
            return None;
        }
        let across = t.normalize();
        let axis = u.cross(&across);
        Some(ScanCondition { axis, across })
    }

    /// The dominant plane (index into [`PLANES`]) and direction (index into
    /// [`DIRECTIONS`]).
    pub fn dominant(&self) -> (usize, usize) {
        let k = self.axis.iamax();
        let dir = usize::from(self.axis[k] > 0.0);
        (k, dir)
    }
}

impl DeflectionCorrection {
    /// No correction: the reading is the deflection.
    pub fn identity() -> DeflectionCorrection {
        DeflectionCorrection {
            gain: [Mat3::zeros(); CORRECTION_TERMS],
            tilt: [[[0.0; CORRECTION_TERMS]; 2]; 3],
        }
    }

    /// The gain correction matrix `E(|m|)` at deflection amount `dp` (mm).
    pub fn gain_at(&self, dp: f64) -> Mat3 {
        self.gain
            .iter()
            .rev()
            .fold(Mat3::zeros(), |acc, e| acc * dp + e)
    }

    /// The gain correction of a probe turned by `turn` (a probe head
    /// orientation relative to the one calibrated): the sensor's frame turns
    /// with the stylus, so `E_k -> R E_k R^T`. The scanning tilts belong to
    /// machine planes and are kept as they are.
    pub fn turned(&self, turn: &Mat3) -> DeflectionCorrection {
        DeflectionCorrection {
            gain: self.gain.map(|e| turn * e * turn.transpose()),
            tilt: self.tilt,
        }
    }

    /// Corrected deflection vector for the raw reading `m`, mm.
    pub fn deflection(&self, m: Vec3) -> Vec3 {
        m + self.gain_at(m.norm()) * m
    }

    /// Normal tilt (rad) at deflection amount `dp` for a condition.
    pub fn tilt_at(&self, dp: f64, c: &ScanCondition) -> f64 {
        (0..3)
            .map(|k| {
                let dir = usize::from(c.axis[k] > 0.0);
                c.axis[k].powi(2) * poly_eval(&self.tilt[k][dir], dp)
            })
            .sum()
    }

    /// Measured surface normal (unit) for the corrected deflection `d` and the
    /// raw reading `m` under commanded velocity `motion`.
    pub fn normal(&self, d: Vec3, m: Vec3, motion: Vec3) -> Option<Vec3> {
        let u = d.try_normalize(1e-12)?;
        let Some(c) = ScanCondition::of(d, motion) else {
            return Some(u);
        };
        let phi = self.tilt_at(m.norm(), &c);
        Some(u * phi.cos() + c.across * phi.sin())
    }
}
