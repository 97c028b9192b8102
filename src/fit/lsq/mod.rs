//! Orthogonal-distance least-squares fits, one file per element. Each
//! works on centred points, starts from a closed-form or algebraic
//! solution and refines with [`least_squares`](super::gauss_newton).
pub(crate) mod circle;
pub(crate) mod cone;
pub(crate) mod cylinder;
pub(crate) mod line;
pub(crate) mod plane;
pub(crate) mod sphere;
