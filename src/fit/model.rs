//! The interface between an element's parameterisation and the solvers
//! (least squares in `gauss_newton`, Chebyshev in `minimum_zone`).
use crate::math::Vec3;

/// Largest number of parameters of any model (cone: 5 shape + 1 size).
pub(crate) const MAX_PARAMS: usize = 6;

/// An element parameterised around its current value, NIST style: every
/// step is a small change `delta` of local parameters that are zero at the
/// current element, after which the local frame is rebuilt.
///
/// The residual of a point is `shape_value(p) - size`; the size (radius,
/// offset) enters linearly, so the zone solvers can leave it out.
pub(crate) trait Model: Clone {
    /// Number of shape parameters (the size parameter comes on top).
    const SHAPE: usize;
    /// Shape value of `p` and its gradient (first `SHAPE` entries of `grad`)
    /// with respect to the local parameters at zero.
    fn eval(&self, p: &Vec3, grad: &mut [f64; MAX_PARAMS]) -> f64;
    /// Shape value of `p` only.
    fn value(&self, p: &Vec3) -> f64;
    /// The model after a step: `delta[..SHAPE]` shape, `delta[SHAPE]` size.
    fn step(&self, delta: &[f64; MAX_PARAMS]) -> Self;
    /// The size parameter, mm.
    fn size(&self) -> f64;
    /// The same shape with another size.
    fn with_size(&self, size: f64) -> Self;
    /// Whether the parameters are finite (a diverged step is rejected).
    fn is_finite(&self) -> bool;
    /// Whether local parameter `k` is an angle (radians); a step of it moves
    /// the element by up to `angle * extent` within the data. None by default.
    fn angular(_k: usize) -> bool {
        false
    }
}

/// Largest movement (mm) of the element within the data that a step makes:
/// lengths as they are, angles times the data `extent`.
pub(crate) fn step_size_mm<M: Model>(delta: &[f64; MAX_PARAMS], extent: f64) -> f64 {
    delta
        .iter()
        .enumerate()
        .take(M::SHAPE + 1)
        .map(|(k, d)| {
            if M::angular(k) {
                d.abs() * extent
            } else {
                d.abs()
            }
        })
        .fold(0.0, f64::max)
}
