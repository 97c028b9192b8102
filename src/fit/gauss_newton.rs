//! Levenberg-Marquardt (Gauss-Newton with damping) on a [`Model`].
//!
//! Hand-written rather than the `levenberg-marquardt` crate on purpose: that
//! crate wants the full N x p Jacobian, while here the normal equations
//! `J^T J` (at most 6 x 6) and `J^T r` are accumulated point by point in
//! fixed-size chunks. A million points then need no big allocation, the
//! chunks run on all cores (see `parallel`), and the sums are added in
//! chunk order so the result does not depend on the number of threads.
//! Squaring the condition number does not cost accuracy: the iteration
//! converges to the point where the accurately evaluated `J^T r` vanishes;
//! the normal-equation solve only has to point downhill.
use nalgebra::{DMatrix, DVector};

use super::model::{step_size_mm, Model, MAX_PARAMS};
use super::{FitError, FitOptions, ResidualStats};
use crate::math::Vec3;

/// Damping at which a rejected step counts as "no descent left within
/// floating-point precision": the current model is then the minimum.
const LAMBDA_MAX: f64 = 1e16;
/// First damping after a rejected undamped step.
const LAMBDA_FIRST: f64 = 1e-4;
/// Damping below this is dropped (pure Gauss-Newton).
const LAMBDA_MIN: f64 = 1e-12;

/// Normal equations of the linearised problem at one model, with the
/// residual statistics of that model (so no extra pass is needed for them).
#[derive(Debug, Clone, Copy)]
struct Normal {
    /// Upper triangle of `J^T J`.
    a: [[f64; MAX_PARAMS]; MAX_PARAMS],
    /// `J^T r`.
    g: [f64; MAX_PARAMS],
    /// Sum of squared residuals, mm^2.
    cost: f64,
    /// Smallest residual, mm.
    lo: f64,
    /// Largest residual, mm.
    hi: f64,
}

impl Default for Normal {
    fn default() -> Self {
        let (a, g) = ([[0.0; MAX_PARAMS]; MAX_PARAMS], [0.0; MAX_PARAMS]);
        Normal {
            a,
            g,
            cost: 0.0,
            lo: f64::INFINITY,
            hi: f64::NEG_INFINITY,
        }
    }
}

impl Normal {
    fn stats(&self, count: usize) -> ResidualStats {
        let rms = (self.cost / count.max(1) as f64).sqrt();
        ResidualStats {
            rms,
            min: self.lo,
            max: self.hi,
        }
    }

    fn add(mut self, other: &Normal) -> Normal {
        (self.lo, self.hi) = (self.lo.min(other.lo), self.hi.max(other.hi));
        for (row, orow) in self.a.iter_mut().zip(other.a.iter()) {
            row.iter_mut().zip(orow.iter()).for_each(|(x, y)| *x += y);
        }
        self.g
            .iter_mut()
            .zip(other.g.iter())
            .for_each(|(x, y)| *x += y);
        self.cost += other.cost;
        self
    }
}

/// A converged least-squares solution.
#[derive(Debug, Clone)]
pub(crate) struct Solved<M> {
    /// The fitted model.
    pub model: M,
    /// Iterations made.
    pub iterations: usize,
    /// RMS residual, mm.
    pub rms: f64,
    /// Residual statistics (shape value minus size) of the last evaluated
    /// iterate, within the step tolerance of `model`'s, mm.
    pub stats: ResidualStats,
}

fn accumulate_chunk<M: Model>(model: &M, points: &[Vec3]) -> Normal {
    let n = M::SHAPE + 1;
    let size = model.size();
    let mut acc = Normal::default();
    let mut row = [0.0; MAX_PARAMS];
    for p in points {
        let r = model.eval(p, &mut row) - size;
        row[M::SHAPE] = -1.0;
        for i in 0..n {
            acc.g[i] += row[i] * r;
            for j in i..n {
                acc.a[i][j] += row[i] * row[j];
            }
        }
        acc.cost += r * r;
        (acc.lo, acc.hi) = (acc.lo.min(r), acc.hi.max(r));
    }
    acc
}

fn normal_equations<M: Model + Sync>(model: &M, points: &[Vec3]) -> Normal {
    let parts = super::parallel::map_chunks(points, |c| accumulate_chunk(model, c));
    parts.iter().fold(Normal::default(), |acc, p| acc.add(p))
}

/// Solves `(J^T J + lambda D) delta = -J^T r`, `D` the diagonal of `J^T J`
/// (floored so that damping always makes the matrix positive definite).
fn solve_step(ne: &Normal, n: usize, lambda: f64) -> Option<[f64; MAX_PARAMS]> {
    let sym = |i: usize, j: usize| if i <= j { ne.a[i][j] } else { ne.a[j][i] };
    let max_diag = (0..n).map(|i| ne.a[i][i]).fold(0.0, f64::max);
    let damp = |i: usize| lambda * ne.a[i][i].max(1e-12 * max_diag);
    let m = DMatrix::from_fn(n, n, |i, j| sym(i, j) + if i == j { damp(i) } else { 0.0 });
    let rhs = DVector::from_fn(n, |i, _| -ne.g[i]);
    let x = m.cholesky()?.solve(&rhs);
    let mut delta = [0.0; MAX_PARAMS];
    delta.iter_mut().zip(x.iter()).for_each(|(d, v)| *d = *v);
    delta.iter().all(|d| d.is_finite()).then_some(delta)
}

fn raise(lambda: f64) -> f64 {
    if lambda == 0.0 {
        LAMBDA_FIRST
    } else {
        lambda * 10.0
    }
}

fn lower(lambda: f64) -> f64 {
    let l = lambda * 0.1;
    if l < LAMBDA_MIN {
        0.0
    } else {
        l
    }
}

/// Relative size of the cost's round-off: a trial whose cost exceeds the
/// current one by less than this fraction is not a worse point.
const COST_ROUND_OFF: f64 = 1e-12;
/// A Gauss-Newton step whose predicted cost reduction is below this
/// fraction of the cost cannot be checked against the evaluated cost (the
/// residuals' own round-off is larger); it is taken as it is.
const UNCHECKABLE_REDUCTION: f64 = 1e-9;

/// The tolerance in force: the option, but never below the round-off floor.
pub(crate) fn tolerance_mm(opts: &FitOptions, extent: f64) -> f64 {
    opts.step_tolerance_mm.max(64.0 * f64::EPSILON * extent)
}

/// How an iteration run ended.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Outcome {
    /// The step tolerance was met (or no descent was left).
    pub converged: bool,
    /// Size of the last step (see [`step_size_mm`]), mm.
    pub last_step_mm: f64,
}

/// State of one Levenberg-Marquardt run.
struct State<M> {
    model: M,
    ne: Normal,
    lambda: f64,
}

impl<M: Model + Sync> State<M> {
    /// One iteration: `Some((step size, converged))` after a solve, `None`
    /// when the damped system was singular (damping raised). Convergence is
    /// judged on the undamped Gauss-Newton step, never on a damped one.
    fn advance(&mut self, points: &[Vec3], extent: f64, tol: f64) -> Option<(f64, bool)> {
        // Residuals at the tolerance (the rounding floor, for data exactly
        // on the element): the model passes through the points as nearly
        // as the arithmetic tells, and no later step could be checked. A
        // layout that fixes a parameter to second order only (a cylinder
        // touched at four points of one circle and two of another, in one
        // plane) otherwise creeps on below the cost's rounding.
        if (self.ne.cost / points.len().max(1) as f64).sqrt() <= tol {
            return Some((0.0, true));
        }
        // The size reported is that of the undamped (Gauss-Newton) step,
        // the one convergence is judged on, even when a damped step is
        // taken instead.
        let mut undamped = None;
        if let Some(gn) = solve_step(&self.ne, M::SHAPE + 1, 0.0) {
            let size = step_size_mm::<M>(&gn, extent);
            undamped = Some(size);
            let reduction = -(0..=M::SHAPE).map(|k| self.ne.g[k] * gn[k]).sum::<f64>();
            let trial = self.model.step(&gn);
            if trial.is_finite() && size <= tol {
                // The last (tiny) step is taken without another pass: the
                // statistics stay those of the previous iterate, which differ
                // from the returned model's by at most `tol`.
                self.model = trial;
                return Some((size, true));
            }
            if trial.is_finite() && reduction <= UNCHECKABLE_REDUCTION * self.ne.cost {
                (self.ne, self.model, self.lambda) = (normal_equations(&trial, points), trial, 0.0);
                return Some((size, false));
            }
        }
        (self.damped(points, extent)).map(|(damped, done)| (undamped.unwrap_or(damped), done))
    }

    /// A Levenberg-Marquardt step, kept only if the cost does not rise.
    fn damped(&mut self, points: &[Vec3], extent: f64) -> Option<(f64, bool)> {
        let Some(delta) = solve_step(&self.ne, M::SHAPE + 1, self.lambda) else {
            self.lambda = raise(self.lambda);
            return None;
        };
        let trial = self.model.step(&delta);
        let trial_ne = trial.is_finite().then(|| normal_equations(&trial, points));
        match trial_ne {
            Some(t) if t.cost <= self.ne.cost * (1.0 + COST_ROUND_OFF) => {
                (self.model, self.ne, self.lambda) = (trial, t, lower(self.lambda))
            }
            _ => self.lambda = raise(self.lambda),
        }
        Some((step_size_mm::<M>(&delta, extent), self.lambda > LAMBDA_MAX))
    }
}

/// Runs at most `limit` iterations from `start`; returns the last model
/// whether or not it converged.
pub(crate) fn iterate<M: Model + Sync>(
    start: M,
    points: &[Vec3],
    extent: f64,
    opts: &FitOptions,
    limit: usize,
) -> (Solved<M>, Outcome) {
    let tol = tolerance_mm(opts, extent);
    let ne = normal_equations(&start, points);
    let mut state = State {
        model: start,
        ne,
        lambda: 0.0,
    };
    let mut outcome = Outcome {
        converged: false,
        last_step_mm: f64::INFINITY,
    };
    let mut iterations = 0;
    while iterations < limit && !outcome.converged {
        iterations += 1;
        if let Some((size, done)) = state.advance(points, extent, tol) {
            outcome = Outcome {
                converged: done,
                last_step_mm: size,
            };
        }
    }
    let stats = state.ne.stats(points.len());
    let solved = Solved {
        model: state.model,
        iterations,
        rms: stats.rms,
        stats,
    };
    (solved, outcome)
}

/// Iterations given to a starting value on a sample of the points.
pub(crate) const START_ITERATIONS: usize = 12;

/// `start` refined on `sample` (a subset of the points), and the iterations
/// used: from the sample's solution the fit on all points needs only about
/// two passes over them.
pub(crate) fn presolve<M: Model + Sync>(
    start: M,
    sample: &[Vec3],
    extent: f64,
    opts: &FitOptions,
) -> (M, usize) {
    let solved = iterate(start, sample, extent, opts, START_ITERATIONS).0;
    (solved.model, solved.iterations)
}

/// Least-squares fit of `start` to centred `points` whose largest distance
/// from the origin is `extent` mm; fails when it does not converge within
/// `opts.max_iterations`.
pub(crate) fn least_squares<M: Model + Sync>(
    start: M,
    points: &[Vec3],
    extent: f64,
    opts: &FitOptions,
    element: &'static str,
) -> Result<Solved<M>, FitError> {
    let (solved, outcome) = iterate(start, points, extent, opts, opts.max_iterations);
    if outcome.converged {
        return Ok(solved);
    }
    Err(FitError::NoConvergence {
        element,
        method: "lsq",
        iterations: solved.iterations,
        last_step_mm: outcome.last_step_mm,
        tolerance_mm: tolerance_mm(opts, extent),
    })
}
