//! Options of path construction and closest-point queries.

/// End condition of an open spline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EndCondition {
    /// Zero second derivative at both ends.
    Natural,
    /// Third derivative continuous at the second and the second-to-last
    /// point (falls back to [`EndCondition::Natural`] below 4 points).
    #[default]
    NotAKnot,
}

/// Tolerances of [`BallPath::closest_s`](super::BallPath::closest_s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestOptions {
    /// Newton iterations per segment visit.
    pub max_iters: usize,
    /// Converged when a Newton step is below this fraction of the segment's
    /// parameter length (dimensionless). Newton converges quadratically
    /// here (the ball centre is far inside the path's curvature radius), so
    /// the error left after such a step is of the order of its square:
    /// 1e-8 of a 0.5 mm segment leaves ~1e-17 mm.
    pub step_tol_rel: f64,
    /// Largest Newton step as a fraction of the segment's parameter length
    /// (dimensionless), so that a step cannot jump far along the path.
    pub max_step_rel: f64,
    /// Most moves to a neighbouring segment in one query.
    pub max_hops: usize,
    /// Evaluations per segment when searching without a hint.
    pub cold_samples: usize,
}

impl Default for ClosestOptions {
    fn default() -> Self {
        ClosestOptions {
            max_iters: 30,
            step_tol_rel: 1e-8,
            max_step_rel: 0.5,
            max_hops: 16,
            cold_samples: 4,
        }
    }
}

/// Options of [`BallPath::from_section`](super::BallPath::from_section).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathOptions {
    /// End condition of open paths.
    pub end: EndCondition,
    /// Consecutive offset points closer than this are rejected, mm.
    pub min_chord_mm: f64,
    /// Normals shorter than this are rejected (normals are normalised).
    pub min_normal_norm: f64,
    /// Gauss-Legendre panels (5 nodes each) per segment for arc lengths
    /// (1 to [`MAX_QUAD_PANELS`](super::MAX_QUAD_PANELS)).
    pub quad_panels: usize,
    /// Accuracy of the arc length to parameter inversion, mm.
    pub arc_tol_mm: f64,
    /// Iterations of the arc length to parameter inversion.
    pub arc_max_iters: usize,
    /// Closest-point query tolerances.
    pub closest: ClosestOptions,
}

impl Default for PathOptions {
    fn default() -> Self {
        PathOptions {
            end: EndCondition::NotAKnot,
            min_chord_mm: 1e-9,
            min_normal_norm: 1e-12,
            quad_panels: 2,
            arc_tol_mm: 1e-13,
            arc_max_iters: 60,
            closest: ClosestOptions::default(),
        }
    }
}
