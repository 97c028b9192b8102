//! Least-squares sphere: centre and radius by Gauss-Newton from the Kasa
//! fit.
use crate::fit::algebraic::kasa;
use crate::fit::frame::{centre, subsample, Centred};
use crate::fit::gauss_newton::{least_squares, presolve, Solved};
use crate::fit::model::{Model, MAX_PARAMS};
use crate::fit::{FitError, FitOptions, Sphere};
use crate::math::{Point3, Vec3};

const NAME: &str = "sphere";

/// Sphere parameters in centred coordinates.
#[derive(Debug, Clone)]
pub(crate) struct SphereModel {
    /// Centre, mm.
    pub center: Vec3,
    /// Radius, mm.
    pub radius: f64,
}

impl Model for SphereModel {
    const SHAPE: usize = 3;

    fn eval(&self, p: &Vec3, grad: &mut [f64; MAX_PARAMS]) -> f64 {
        let d = p - self.center;
        let rho = d.norm();
        let inv = if rho > 0.0 { 1.0 / rho } else { 0.0 };
        (grad[0], grad[1], grad[2]) = (-d.x * inv, -d.y * inv, -d.z * inv);
        rho
    }

    fn value(&self, p: &Vec3) -> f64 {
        (p - self.center).norm()
    }

    fn step(&self, delta: &[f64; MAX_PARAMS]) -> Self {
        let center = self.center + Vec3::new(delta[0], delta[1], delta[2]);
        SphereModel {
            center,
            radius: self.radius + delta[3],
        }
    }

    fn size(&self) -> f64 {
        self.radius
    }

    fn with_size(&self, size: f64) -> Self {
        SphereModel {
            radius: size,
            ..self.clone()
        }
    }

    fn is_finite(&self) -> bool {
        self.radius.is_finite() && crate::math::all_finite(self.center.as_slice())
    }
}

/// Checks and centres the points, then fits the least-squares sphere.
pub(crate) fn lsq(
    points: &[Point3],
    opts: &FitOptions,
) -> Result<(Centred, Solved<SphereModel>), FitError> {
    let c = centre(points, NAME, 4)?;
    c.principal()
        .check_volume(NAME, c.points.len(), opts.degenerate_ratio)?;
    let sample = subsample(&c.points, opts.start_sample);
    let no_start = FitError::NoStart {
        element: NAME,
        tried: 1,
    };
    let (center, radius) = kasa(&sample, 3).ok_or(no_start)?;
    let (start, pre) = presolve(SphereModel { center, radius }, &sample, c.extent, opts);
    let solved = least_squares(start, &c.points, c.extent, opts, NAME)?;
    let iterations = solved.iterations + pre;
    Ok((
        c,
        Solved {
            iterations,
            ..solved
        },
    ))
}

/// The sphere of a model in the frame of `c`.
pub(crate) fn to_element(c: &Centred, m: &SphereModel) -> Sphere {
    Sphere {
        center: Point3::from(m.center + c.centroid),
        radius: m.radius,
    }
}
