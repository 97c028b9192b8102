//! Geometric error compensation at the stylus tip (JP2902285B2), host side.
//!
//! The host is given the machine's error map — the 21 geometric error terms
//! from the machine's own calibration (laser interferometer, squares,
//! straightedges) — and corrects every position with it:
//! `ball = s + P + delta(s, P)` for scale readings `s` (mm) and probe vector
//! `P` (mm, spindle reference point to ball centre), where
//! `delta = sum_i (e_i + theta_i x C_iA)` acts through the probe vector
//! (see [`GeometricErrors::displacement`]; the host evaluates the same
//! published formula on its own copy of the coefficients).
//!
//! In the simulation the map is the machine profile's error terms, i.e. the
//! machine's error map is assumed to be exactly right; a real map has its
//! own uncertainty, which this does not model.
//!
//! The **iterative inverse** (JP2902285B2, figure 3) finds the scale position
//! `s` at which the ball of probe vector `P` sits at a wanted (corrected)
//! position `t`: start with `y = t`, evaluate `c = y + delta(y - P, P)`,
//! step `y += t - c`, until every component of the step is at most
//! [`InverseOptions::step_tolerance_mm`]. It converges because `delta`
//! changes by far less than the position does (its gradient is of the order
//! of the error terms, 1e-5). [`ErrorMap::recompensate`] uses it as the seed
//! does: positions corrected with an old probe vector are turned into the
//! positions the new probe vector gives, without measuring again.
use crate::machine::GeometricErrors;
use crate::math::{Point3, Vec3};

/// Limits of the iterative inverse correction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InverseOptions {
    /// Converged when no component of the step exceeds this, mm.
    pub step_tolerance_mm: f64,
    /// Most iterations before giving up.
    pub max_iterations: usize,
}

impl Default for InverseOptions {
    fn default() -> Self {
        InverseOptions {
            step_tolerance_mm: 1e-9,
            max_iterations: 20,
        }
    }
}

/// Why the iterative inverse failed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum InverseError {
    /// The step did not fall below the tolerance.
    #[error(
        "iterative inverse correction did not converge in {iterations} iterations: last step \
         {last_step_mm} mm, tolerance {tolerance_mm} mm"
    )]
    NotConverged {
        /// Iterations made.
        iterations: usize,
        /// Largest component of the last step, mm.
        last_step_mm: f64,
        /// The tolerance, mm.
        tolerance_mm: f64,
    },
}

/// A solved inverse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inverse {
    /// Scale position (probe mount) that puts the ball at the target, mm.
    pub scales: Point3,
    /// Iterations used.
    pub iterations: usize,
    /// Largest component of the last step, mm.
    pub last_step_mm: f64,
}

/// The host's error map (a copy of the 21 terms it was given).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ErrorMap {
    terms: GeometricErrors,
}

impl ErrorMap {
    /// A map of the given error terms.
    pub fn new(terms: GeometricErrors) -> ErrorMap {
        ErrorMap { terms }
    }

    /// No compensation (a perfect machine, or none known).
    pub fn none() -> ErrorMap {
        ErrorMap::default()
    }

    /// `true` when the map corrects nothing.
    pub fn is_zero(&self) -> bool {
        self.terms == GeometricErrors::default()
    }

    /// Displacement of the ball for scale readings `scales` and probe vector
    /// `p`, mm.
    pub fn error(&self, scales: Point3, p: &Vec3) -> Vec3 {
        self.terms.displacement(scales.coords.into(), p)
    }

    /// The corrected ball centre for scale readings and probe vector, mm.
    pub fn forward(&self, scales: Point3, p: &Vec3) -> Point3 {
        scales + p + self.error(scales, p)
    }

    /// Scale readings moved by the error, so that `compensated + P` is the
    /// corrected undeflected ball centre.
    pub fn compensate(&self, scales: Point3, p: &Vec3) -> Point3 {
        scales + self.error(scales, p)
    }

    /// The scale position putting the ball of probe vector `p` at `target`
    /// (the seed's iterative inverse correction).
    pub fn inverse(
        &self,
        target: Point3,
        p: &Vec3,
        opts: &InverseOptions,
    ) -> Result<Inverse, InverseError> {
        let mut y = target;
        let mut last_step_mm = f64::INFINITY;
        for iterations in 1..=opts.max_iterations {
            let corrected = y + self.error(y - p, p);
            let step = target - corrected;
            last_step_mm = step.amax();
            y += step;
            if last_step_mm <= opts.step_tolerance_mm {
                return Ok(Inverse {
                    scales: y - p,
                    iterations,
                    last_step_mm,
                });
            }
        }
        Err(InverseError::NotConverged {
            iterations: opts.max_iterations,
            last_step_mm,
            tolerance_mm: opts.step_tolerance_mm,
        })
    }

    /// A ball position corrected with probe vector `old` turned into the one
    /// the same scale readings give with `new` (JP2902285B2: undo the old
    /// correction by the iterative inverse, apply the new one).
    pub fn recompensate(
        &self,
        corrected: Point3,
        old: &Vec3,
        new: &Vec3,
        opts: &InverseOptions,
    ) -> Result<Point3, InverseError> {
        let raw = self.inverse(corrected, old, opts)?;
        Ok(self.forward(raw.scales, new))
    }
}
