//! Analytic test shapes for the fitting tests: points on exact elements in a
//! generic pose, with offsets whose effect on the fit is known by symmetry.
#![allow(dead_code)]
use cmm::math::{rotation_xyz_deg, Mat3, Point3, Vec3};

/// A generic pose: rotation and translation applied to local constructions.
pub struct Pose {
    /// Rotation local -> world.
    pub rot: Mat3,
    /// Translation, mm.
    pub shift: Vec3,
}

impl Pose {
    /// A tilted pose far from the origin.
    pub fn generic() -> Self {
        Pose {
            rot: rotation_xyz_deg([17.0, -33.0, 51.0]),
            shift: Vec3::new(120.5, -48.25, 310.125),
        }
    }

    /// Maps a local point to the world.
    pub fn point(&self, x: f64, y: f64, z: f64) -> Point3 {
        Point3::from(self.rot * Vec3::new(x, y, z) + self.shift)
    }

    /// Maps a local direction to the world.
    pub fn dir(&self, v: Vec3) -> Vec3 {
        self.rot * v
    }

    /// The local origin in the world.
    pub fn origin(&self) -> Point3 {
        Point3::from(self.shift)
    }
}

/// `+1` for even `i`, `-1` for odd.
pub fn alt(i: usize) -> f64 {
    if i.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    }
}

/// Angle `i / n` of a full turn, radians.
pub fn turn(i: usize, n: usize) -> f64 {
    std::f64::consts::TAU * i as f64 / n as f64
}

/// `|a - b|` for unit directions up to sign: the sine of the angle between them.
pub fn dir_error(a: &Vec3, b: &Vec3) -> f64 {
    a.normalize().cross(&b.normalize()).norm()
}

/// Distance of point `p` from the line through `q` along `d`.
pub fn line_distance(p: &Point3, q: &Point3, d: &Vec3) -> f64 {
    (p - q).cross(&d.normalize()).norm()
}

/// Asserts `|a - b| <= tol` with a readable message.
#[track_caller]
pub fn close(what: &str, a: f64, b: f64, tol: f64) {
    assert!(
        (a - b).abs() <= tol,
        "{what}: got {a:.17e}, want {b:.17e} (tolerance {tol:e})"
    );
}

/// Asserts two points agree within `tol`.
#[track_caller]
pub fn close_pt(what: &str, a: &Point3, b: &Point3, tol: f64) {
    assert!(
        (a - b).norm() <= tol,
        "{what}: got {a:?}, want {b:?} (tolerance {tol:e})"
    );
}

/// Points on a cylinder of radius `r` about the local z axis: `rings` rings
/// of `per_ring` points over heights `z0..z1` and angles `a0..a0+span`, each
/// point moved radially by `offset(ring, k)`.
pub fn cylinder_points(
    pose: &Pose,
    r: f64,
    (z0, z1): (f64, f64),
    (a0, span): (f64, f64),
    (rings, per_ring): (usize, usize),
    offset: impl Fn(usize, usize) -> f64,
) -> Vec<Point3> {
    let mut pts = Vec::new();
    for ring in 0..rings {
        let z = z0 + (z1 - z0) * ring as f64 / (rings - 1).max(1) as f64;
        for k in 0..per_ring {
            let full = (span - std::f64::consts::TAU).abs() < 1e-12;
            let denom = if full { per_ring } else { per_ring - 1 };
            let a = a0 + span * k as f64 / denom as f64;
            let rr = r + offset(ring, k);
            pts.push(pose.point(rr * a.cos(), rr * a.sin(), z));
        }
    }
    pts
}

/// Points on a cone with apex at the local origin, axis +z, half angle
/// `psi`, at heights `zs`, `per_ring` points over `a0..a0+span` per height,
/// each moved along the surface normal by `offset(ring, k)`.
pub fn cone_points(
    pose: &Pose,
    psi: f64,
    zs: &[f64],
    (a0, span): (f64, f64),
    per_ring: usize,
    offset: impl Fn(usize, usize) -> f64,
) -> Vec<Point3> {
    let mut pts = Vec::new();
    for (ring, z) in zs.iter().enumerate() {
        for k in 0..per_ring {
            let a = a0 + span * k as f64 / per_ring as f64;
            let (rho, h) = (z * psi.tan(), *z);
            let e = offset(ring, k);
            let (rho, h) = (rho + e * psi.cos(), h - e * psi.sin());
            pts.push(pose.point(rho * a.cos(), rho * a.sin(), h));
        }
    }
    pts
}
