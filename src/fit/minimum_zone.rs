//! Chebyshev fits by sequential linear programming (SLP) with a trust
//! region: minimum zone (smallest `max - min` of the shape values), minimum
//! circumscribed (smallest max) and maximum inscribed (largest min).
//!
//! Each iteration linearises the shape values of the points near the
//! extremes around the current element and solves a small linear program
//! (with `microlp`, a pure-Rust simplex: small, no native code) for the
//! step within the trust region; the step is kept only if the exact
//! objective improves. The LP is scaled by the trust-region radius, so its
//! own absolute tolerance shrinks with the steps. Only points that can
//! reach an extreme within the trust region enter the LP (at most
//! [`MAX_CANDIDATES`] per side), which keeps it small for large data.
use microlp::{ComparisonOp, OptimizationDirection, Problem, Variable};

use super::model::{Model, MAX_PARAMS};
use super::{FitError, FitOptions};
use crate::math::Vec3;

/// Most points per side (upper, lower) in one linear program.
pub const MAX_CANDIDATES: usize = 1500;
/// Trust region growth on a good step.
const GROW: f64 = 2.0;
/// Trust region shrink on a poor or rejected step.
const SHRINK: f64 = 0.25;

/// What a Chebyshev fit minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Objective {
    /// Zone width `max - min` (minimum zone).
    Zone,
    /// `max` (minimum circumscribed).
    Circumscribed,
    /// `-min` (maximum inscribed).
    Inscribed,
}

impl Objective {
    fn value(self, lo: f64, hi: f64) -> f64 {
        match self {
            Objective::Zone => hi - lo,
            Objective::Circumscribed => hi,
            Objective::Inscribed => -lo,
        }
    }

    fn size(self, lo: f64, hi: f64) -> f64 {
        match self {
            Objective::Zone => 0.5 * (lo + hi),
            Objective::Circumscribed => hi,
            Objective::Inscribed => lo,
        }
    }

    fn uses_top(self) -> bool {
        self != Objective::Inscribed
    }

    fn uses_bottom(self) -> bool {
        self != Objective::Circumscribed
    }
}

/// Names for messages.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Names {
    /// Element kind.
    pub element: &'static str,
    /// Method.
    pub method: &'static str,
}

impl Names {
    fn lp_error(self, iteration: usize, reason: String) -> FitError {
        let (element, method) = (self.element, self.method);
        FitError::LinearProgram {
            element,
            method,
            iteration,
            reason,
        }
    }

    fn no_convergence(self, iterations: usize, last_step_mm: f64, tolerance_mm: f64) -> FitError {
        let (element, method) = (self.element, self.method);
        FitError::NoConvergence {
            element,
            method,
            iterations,
            last_step_mm,
            tolerance_mm,
        }
    }
}

fn min_max<M: Model>(model: &M, points: &[Vec3]) -> (Vec<f64>, f64, f64) {
    let values: Vec<f64> = points.iter().map(|p| model.value(p)).collect();
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (values, lo, hi)
}

/// Indices of the values within `band` of the extreme (at most
/// `MAX_CANDIDATES`, the most extreme ones).
fn candidates(values: &[f64], extreme: f64, band: f64, top: bool) -> Vec<usize> {
    let dist = |v: f64| if top { extreme - v } else { v - extreme };
    let mut idx: Vec<usize> = (0..values.len())
        .filter(|&i| values.get(i).is_some_and(|&v| dist(v) <= band))
        .collect();
    if idx.len() > MAX_CANDIDATES {
        let key = |i: &usize| values.get(*i).map_or(f64::INFINITY, |&v| dist(v));
        idx.select_nth_unstable_by(MAX_CANDIDATES, |a, b| key(a).total_cmp(&key(b)));
        idx.truncate(MAX_CANDIDATES);
    }
    idx
}

/// One linearised row: scaled value offset and gradient.
struct Row {
    offset: f64,
    grad: [f64; MAX_PARAMS],
}

fn rows<M: Model>(
    model: &M,
    points: &[Vec3],
    idx: &[usize],
    extreme: f64,
    radius: f64,
) -> Vec<Row> {
    let mut grad = [0.0; MAX_PARAMS];
    idx.iter()
        .filter_map(|&i| points.get(i))
        .map(|p| {
            let v = model.eval(p, &mut grad);
            Row {
                offset: (v - extreme) / radius,
                grad,
            }
        })
        .collect()
}

/// Parameter scales: largest finite gradient magnitude of each parameter.
fn scales(rows: &[&[Row]], n: usize) -> [f64; MAX_PARAMS] {
    let mut sc = [0.0f64; MAX_PARAMS];
    for row in rows.iter().flat_map(|r| r.iter()) {
        sc.iter_mut()
            .zip(row.grad.iter())
            .take(n)
            .filter(|(_, g)| g.is_finite())
            .for_each(|(s, g)| *s = s.max(g.abs()));
    }
    sc
}

/// The LP's answer: parameter step (model units) and predicted change of
/// the objective, mm.
struct LpStep {
    delta: [f64; MAX_PARAMS],
    predicted: f64,
}

struct Lp {
    problem: Problem,
    ys: Vec<Variable>,
    upper: Variable,
    lower: Variable,
}

fn new_lp(obj: Objective, sc: &[f64; MAX_PARAMS], n: usize) -> Lp {
    let mut problem = Problem::new(OptimizationDirection::Minimize);
    let ys = (0..n)
        .map(|k| {
            let b = if sc.get(k).is_some_and(|&s| s > 0.0) {
                1.0
            } else {
                0.0
            };
            problem.add_var(0.0, (-b, b))
        })
        .collect();
    let cu = if obj.uses_top() { 1.0 } else { 0.0 };
    let cl = if obj.uses_bottom() { -1.0 } else { 0.0 };
    let free = (f64::NEG_INFINITY, f64::INFINITY);
    let upper = problem.add_var(cu, free);
    let lower = problem.add_var(cl, free);
    Lp {
        problem,
        ys,
        upper,
        lower,
    }
}

fn add_rows(lp: &mut Lp, rows: &[Row], sc: &[f64; MAX_PARAMS], top: bool) {
    let bound = if top { lp.upper } else { lp.lower };
    for row in rows {
        let mut terms: Vec<(Variable, f64)> = lp
            .ys
            .iter()
            .zip(row.grad.iter().zip(sc.iter()))
            .filter(|(_, (_, s))| **s > 0.0)
            .map(|(y, (g, s))| (*y, g / s))
            .collect();
        terms.push((bound, -1.0));
        // microlp refuses non-finite data by panicking: never hand it any.
        if !row.offset.is_finite() || terms.iter().any(|(_, c)| !c.is_finite()) {
            continue;
        }
        let op = if top {
            ComparisonOp::Le
        } else {
            ComparisonOp::Ge
        };
        lp.problem.add_constraint(terms, op, -row.offset);
    }
}

/// Everything one LP needs.
struct Linearised {
    top: Vec<Row>,
    bottom: Vec<Row>,
}

fn solve_lp(lin: &Linearised, obj: Objective, n: usize, radius: f64) -> Result<LpStep, String> {
    let sc = scales(&[&lin.top, &lin.bottom], n);
    let mut lp = new_lp(obj, &sc, n);
    add_rows(&mut lp, &lin.top, &sc, true);
    add_rows(&mut lp, &lin.bottom, &sc, false);
    let solution = lp.problem.solve().map_err(|e| e.to_string())?;
    let solution = solution
        .into_solution()
        .map_err(|_| "interrupted".to_string())?;
    let mut delta = [0.0; MAX_PARAMS];
    for (k, y) in lp.ys.iter().enumerate().take(n) {
        let s = sc.get(k).copied().unwrap_or(0.0);
        if let Some(d) = delta.get_mut(k) {
            *d = if s > 0.0 {
                solution.var_value(*y) * radius / s
            } else {
                0.0
            };
        }
    }
    Ok(LpStep {
        delta,
        predicted: solution.objective() * radius,
    })
}

fn linearise<M: Model>(model: &M, points: &[Vec3], obj: Objective, radius: f64) -> Linearised {
    let (values, lo, hi) = min_max(model, points);
    let band = 2.0 * M::SHAPE as f64 * radius;
    let pick = |use_it: bool, extreme: f64, top: bool| {
        if !use_it {
            return Vec::new();
        }
        let idx = candidates(&values, extreme, band, top);
        rows(model, points, &idx, extreme, radius)
    };
    let top = pick(obj.uses_top(), hi, true);
    let bottom = pick(obj.uses_bottom(), lo, false);
    Linearised { top, bottom }
}

fn objective_of<M: Model>(model: &M, points: &[Vec3], obj: Objective) -> (f64, f64, f64) {
    let (_, lo, hi) = min_max(model, points);
    (obj.value(lo, hi), lo, hi)
}

/// A converged Chebyshev fit: the model with its size set, and iterations.
pub(crate) struct ZoneFit<M> {
    /// The model, size = mid-zone / max / min for the three objectives.
    pub model: M,
    /// Iterations made.
    pub iterations: usize,
}

/// Trust-region radius factor after a step whose actual over predicted
/// improvement is `ratio`.
fn radius_factor(ratio: f64) -> f64 {
    if ratio > 0.75 {
        GROW
    } else if ratio > 0.25 {
        1.0
    } else {
        SHRINK
    }
}

/// The current iterate: model, objective and extreme shape values.
struct Iterate<M> {
    model: M,
    f: f64,
    lo: f64,
    hi: f64,
}

impl<M: Model> Iterate<M> {
    fn new(model: M, points: &[Vec3], obj: Objective) -> Self {
        let (f, lo, hi) = objective_of(&model, points, obj);
        Iterate { model, f, lo, hi }
    }

    /// Tries `step`; keeps it if the objective improves. Returns the ratio
    /// of actual to predicted improvement.
    fn try_step(&mut self, step: &LpStep, points: &[Vec3], obj: Objective) -> f64 {
        let trial = Iterate::new(self.model.step(&step.delta), points, obj);
        let ratio = (self.f - trial.f) / -step.predicted;
        if trial.model.is_finite() && trial.f < self.f {
            *self = trial;
        }
        ratio
    }
}

/// Chebyshev fit of `start` (usually the least-squares solution) to
/// centred `points`.
pub(crate) fn chebyshev<M: Model>(
    start: M,
    points: &[Vec3],
    obj: Objective,
    opts: &FitOptions,
    names: Names,
) -> Result<ZoneFit<M>, FitError> {
    let tol = opts.zone_tolerance_mm;
    let mut it = Iterate::new(start, points, obj);
    let max_radius = 4.0 * (it.hi - it.lo).max(1e3 * tol);
    let mut radius = max_radius / 4.0;
    let start_size = obj.size(it.lo, it.hi);
    for iteration in 1..=opts.max_zone_iterations {
        let lin = linearise(&it.model, points, obj, radius);
        let step = solve_lp(&lin, obj, M::SHAPE, radius)
            .map_err(|reason| names.lp_error(iteration, reason))?;
        if -step.predicted <= tol || radius <= tol {
            let model = it.model.with_size(obj.size(it.lo, it.hi));
            return Ok(ZoneFit {
                model,
                iterations: iteration,
            });
        }
        let ratio = it.try_step(&step, points, obj);
        radius = (radius * radius_factor(ratio)).min(max_radius);
    }
    let growth_mm = obj.size(it.lo, it.hi) - start_size;
    if obj == Objective::Inscribed && growth_mm > max_radius {
        let (element, method, iterations) = (names.element, names.method, opts.max_zone_iterations);
        return Err(FitError::Unbounded {
            element,
            method,
            iterations,
            growth_mm,
        });
    }
    Err(names.no_convergence(opts.max_zone_iterations, radius, tol))
}
