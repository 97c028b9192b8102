//! Form terms as functions of a 3-D point, with gradient and Hessian (for
//! the exact Newton iteration on the as-machined surface).
use crate::math::{Mat3, Point3, Vec3};

/// A validated form term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Form {
    /// Constant `h`.
    Offset(f64),
    /// `h exp(-|p - c|^2 / rho^2)`.
    Bump {
        /// Centre.
        center: Point3,
        /// Radius rho, mm (> 0).
        radius: f64,
        /// Height, mm.
        height: f64,
    },
    /// `A sin(k (p . d) + phi)`, `k = 2 pi / L`.
    Waviness {
        /// Amplitude, mm.
        amplitude: f64,
        /// Wave number `2 pi / L`, 1/mm.
        wavenumber: f64,
        /// Unit direction.
        direction: Vec3,
        /// Phase, radians.
        phase: f64,
    },
}

/// Value, gradient and Hessian of a scalar field at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet {
    /// Value, mm.
    pub h: f64,
    /// Gradient.
    pub grad: Vec3,
    /// Hessian.
    pub hess: Mat3,
}

impl Jet {
    /// The zero field.
    pub fn zero() -> Jet {
        Jet {
            h: 0.0,
            grad: Vec3::zeros(),
            hess: Mat3::zeros(),
        }
    }
    fn add(self, o: Jet) -> Jet {
        Jet {
            h: self.h + o.h,
            grad: self.grad + o.grad,
            hess: self.hess + o.hess,
        }
    }
}

impl Form {
    /// The term's value at `p`.
    pub fn value(&self, p: Point3) -> f64 {
        self.jet(p).h
    }

    /// Value, gradient and Hessian at `p`.
    pub fn jet(&self, p: Point3) -> Jet {
        match *self {
            Form::Offset(h) => Jet { h, ..Jet::zero() },
            Form::Bump {
                center,
                radius,
                height,
            } => bump_jet(p - center, radius, height),
            Form::Waviness {
                amplitude,
                wavenumber,
                direction,
                phase,
            } => {
                let arg = wavenumber * p.coords.dot(&direction) + phase;
                let (s, c) = arg.sin_cos();
                Jet {
                    h: amplitude * s,
                    grad: direction * (amplitude * wavenumber * c),
                    hess: direction
                        * direction.transpose()
                        * (-amplitude * wavenumber * wavenumber * s),
                }
            }
        }
    }

    /// Scales the term's height or amplitude by `k`.
    pub fn scale_size(&mut self, k: f64) {
        match self {
            Form::Offset(h) => *h *= k,
            Form::Bump { height, .. } => *height *= k,
            Form::Waviness { amplitude, .. } => *amplitude *= k,
        }
    }

    /// Largest possible |h|, mm.
    pub fn amplitude(&self) -> f64 {
        match *self {
            Form::Offset(h) => h.abs(),
            Form::Bump { height, .. } => height.abs(),
            Form::Waviness { amplitude, .. } => amplitude.abs(),
        }
    }
}

/// Beyond `|p - c|^2 = BUMP_CUTOFF rho^2` a bump is taken as zero: its
/// value there is below `exp(-50)`, about 2e-22, of its height (and its
/// derivatives as small), far below the resolution of an f64 coordinate of
/// a part (1e-14 mm at 100 mm). Skipping the exponential there is exact in
/// practice and saves most of the bump's cost away from it.
const BUMP_CUTOFF: f64 = 50.0;

fn bump_jet(r: Vec3, rho: f64, height: f64) -> Jet {
    let rho2 = rho * rho;
    let q = r.norm_squared() / rho2;
    if q > BUMP_CUTOFF {
        return Jet::zero();
    }
    let h = height * (-q).exp();
    Jet {
        h,
        grad: r * (-2.0 * h / rho2),
        hess: (r * r.transpose() * (4.0 / (rho2 * rho2)) - Mat3::identity() * (2.0 / rho2)) * h,
    }
}

/// Sum of the jets of several terms.
pub fn sum_jets<'a>(terms: impl Iterator<Item = &'a Form>, p: Point3) -> Jet {
    terms.fold(Jet::zero(), |acc, t| acc.add(t.jet(p)))
}
