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
}

impl Form {
    /// The term's value at `p`.
    pub fn value(&self, p: Point3) -> f64 {
        self.jet(p).h
    }

    /// Adds the term's value, gradient and Hessian at `p` to `acc` (the
    /// same numbers as [`Self::jet`], without a temporary jet).
    pub fn add_to(&self, p: Point3, acc: &mut Jet) {
        match *self {
            Form::Offset(h) => acc.h += h,
            Form::Bump {
                center,
                radius,
                height,
            } => add_bump(p - center, radius, height, acc),
            Form::Waviness { .. } => {
                let j = self.jet(p);
                acc.h += j.h;
                acc.grad += j.grad;
                acc.hess += j.hess;
            }
        }
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

    /// Largest |h| at the points of the box `lo..hi`, mm: a bump's height
    /// times its value at the box's point nearest to its centre, else the
    /// amplitude.
    pub fn amplitude_over(&self, lo: Point3, hi: Point3) -> f64 {
        match *self {
            Form::Bump {
                center,
                radius,
                height,
            } => {
                let gap = (lo - center).sup(&(center - hi)).sup(&Vec3::zeros());
                let fall = (-gap.norm_squared() / (radius * radius)).exp();
                if fall.is_finite() {
                    height.abs() * fall
                } else {
                    height.abs()
                }
            }
            _ => self.amplitude(),
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
    let mut jet = Jet::zero();
    add_bump(r, rho, height, &mut jet);
    jet
}

/// Adds the bump's jet at `r = p - c` to `acc`: `h = height exp(-|r|^2 /
/// rho^2)`, gradient `-2 h r / rho^2`, Hessian `h (4 r r^T / rho^4 - 2 I /
/// rho^2)`.
fn add_bump(r: Vec3, rho: f64, height: f64, acc: &mut Jet) {
    let rho2 = rho * rho;
    let q = r.norm_squared() / rho2;
    if q > BUMP_CUTOFF {
        return;
    }
    let h = height * (-q).exp();
    acc.h += h;
    acc.grad += r * (-2.0 * h / rho2);
    acc.hess.ger(4.0 * h / (rho2 * rho2), &r, &r, 1.0);
    let diagonal = 2.0 * h / rho2;
    for k in 0..3 {
        acc.hess[(k, k)] -= diagonal;
    }
}

/// Sum of the jets of several terms (each added in place, without
/// building its own jet).
#[inline]
pub fn sum_jets<'a>(terms: impl Iterator<Item = &'a Form>, p: Point3) -> Jet {
    let mut acc = Jet::zero();
    for t in terms {
        match *t {
            // A constant adds its value only: no call for it.
            Form::Offset(h) => acc.h += h,
            _ => t.add_to(p, &mut acc),
        }
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bump's bound over a box against a dense grid of the box's points:
    /// never below the largest value there, and equal to it (the box's
    /// point nearest to the centre is a grid point in each case).
    #[test]
    fn bump_bound_over_a_box_is_its_largest_value_there() {
        let bump = Form::Bump {
            center: Point3::new(1.0, -2.0, 0.5),
            radius: 1.5,
            height: -0.6,
        };
        let boxes = [
            ([2.0, -1.0, 0.0], [4.0, 1.0, 4.0]),
            ([-3.0, -5.0, -1.0], [-1.0, -2.5, 0.5]),
            ([0.0, -4.0, 0.0], [2.0, 0.0, 1.0]),
            ([10.0, 10.0, 10.0], [11.0, 12.0, 13.0]),
        ];
        for (lo, hi) in boxes {
            let (lo, hi) = (Point3::from(lo), Point3::from(hi));
            let n = 40;
            let mut largest: f64 = 0.0;
            for i in 0..=n {
                for j in 0..=n {
                    for k in 0..=n {
                        let t = Vec3::new(i as f64, j as f64, k as f64) / n as f64;
                        let p = lo + (hi - lo).component_mul(&t);
                        largest = largest.max(bump.value(p).abs());
                    }
                }
            }
            let bound = bump.amplitude_over(lo, hi);
            assert!(bound >= largest - 1e-15, "{lo} {hi}: {bound} < {largest}");
            assert!(
                bound - largest <= 1e-12 + 1e-9 * largest,
                "{lo} {hi}: {bound} vs {largest}"
            );
        }
        let offset = Form::Offset(-0.02);
        assert_eq!(
            offset.amplitude_over(Point3::origin(), Point3::origin()),
            0.02
        );
    }
}
