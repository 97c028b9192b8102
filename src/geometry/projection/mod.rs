//! Closest-point projection of a point onto a NURBS surface.
//!
//! - **Warm** ([`project_from`]): bounded Newton from a parameter hint, as the
//!   simulator calls it every control cycle. Finds the local minimum in the
//!   basin of the hint.
//! - **Cold** ([`ProjectionIndex::project`]): the global minimum. The surface
//!   is split into near-flat rational Bezier leaves (each inside the convex hull
//!   of its control points, since weights are positive) under a bounding-box
//!   tree; a best-first search visits only leaves whose oriented box could
//!   hold a closer point than the best found so far and minimises the distance
//!   within each such leaf by bounded Newton. Poles, seams, collapsed edges,
//!   far points and points beyond the boundary (answer on the boundary) need no
//!   special cases.

mod descent;
mod index;
mod newton;
mod status;
mod trimmed;

pub use index::{HullShadows, ProjectionIndex};
pub(crate) use index::{LeafMemo, NoMemo};
pub(crate) use newton::{
    local_minimum, local_minimum_cached, minimise_cached, minimise_with, Bounds, Foot,
};
pub use status::{SearchStatus, UnconfirmedReason};
pub(crate) use trimmed::closest_on_boundary;

use crate::geometry::{Jet2, NurbsSurface};
use crate::math::{Point3, Vec2, Vec3};

/// Tolerances and limits of projection (lengths in mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProjectionOptions {
    /// Newton stops when a step would move the foot point by less than this
    /// (mm). The distance is then exact to far better than this, since it is
    /// stationary at the foot.
    pub step_tol_mm: f64,
    /// A Newton step shorter than this (mm) is the last one: it is taken
    /// without line search or another evaluation (Taylor expansion), since
    /// quadratic convergence leaves an error of the order of its square
    /// divided by the curvature radius.
    pub final_step_mm: f64,
    /// ... provided the surface bends by at most this (mm) along the step
    /// (its second-order Taylor term): near a pole a step short in mm may
    /// still be long in the parameter, and Newton's error after it is of
    /// the order of that bend.
    pub final_bend_mm: f64,
    /// A longer Newton step is also the last one when quadratic convergence,
    /// with its constant estimated from the previous full step, predicts a
    /// foot error below this (mm) after it...
    pub final_error_mm: f64,
    /// ... and the step is at most this long (mm; bounds the Taylor
    /// remainder, of the order of the step cubed over the curvature radius
    /// squared).
    pub final_step_max_mm: f64,
    /// Newton iterations allowed per start; a foot still moving after them
    /// is [`SearchStatus::Unconfirmed`].
    pub max_iterations: usize,
    /// A foot where no step lowers the distance is a minimum (confirmed)
    /// when the residual's component along each free tangent is at most
    /// this (mm), or at most what the rounding of the squared distance lets
    /// a line search see.
    pub stationary_tol_mm: f64,
    /// Further starts (the next-nearest samples of a leaf) tried when a
    /// cold search cannot confirm the foot of its first start in a leaf.
    pub max_restarts: usize,
    /// Halvings allowed in the line search of one Newton step.
    pub max_halvings: usize,
    /// A leaf of the cold-search tree is flat enough when its control points
    /// lie within this fraction of its in-plane size from its mid plane.
    pub leaf_flatness: f64,
    /// Maximum subdivision depth of one Bezier patch into leaves.
    pub max_leaf_depth: usize,
    /// A leaf is also split (to `max_leaf_depth`) while its control net's
    /// tangents turn by more than this (radians) along u or along v, such
    /// as a thin flat leaf round a sharp edge: a warm search can then
    /// certify the leaf of its foot (one minimum of the distance there)
    /// and leave out its Newton iteration.
    pub leaf_max_turn: f64,
    /// Cell size of the grid that lists the leaves near a point (for the
    /// searches that start with a tight bound), relative to the median
    /// longest side of the leaves' axis-aligned boxes.
    pub grid_cell_ratio: f64,
    /// Most cells of that grid per surface (the cells grow until they fit).
    pub grid_max_cells: usize,
    /// A search whose bound spans more cells of the grid than this goes
    /// down the box tree instead.
    pub grid_query_cells: usize,
}

impl Default for ProjectionOptions {
    fn default() -> Self {
        ProjectionOptions {
            step_tol_mm: 1e-11,
            final_step_mm: 3e-6,
            final_bend_mm: 1e-10,
            final_error_mm: 1e-12,
            final_step_max_mm: 3e-4,
            max_iterations: 60,
            stationary_tol_mm: 1e-9,
            max_restarts: 3,
            max_halvings: 40,
            leaf_flatness: 0.05,
            max_leaf_depth: 8,
            leaf_max_turn: std::f64::consts::FRAC_PI_4,
            grid_cell_ratio: 1.0,
            grid_max_cells: 1 << 12,
            grid_query_cells: 8,
        }
    }
}

/// Why a projection failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProjectionError {
    /// Newton did not settle within the iteration limit.
    #[error("closest-point search for ({x}, {y}, {z}) did not converge in {iterations} iterations (last step {last_step_mm:e} mm)")]
    NoConvergence {
        /// Query point x.
        x: f64,
        /// Query point y.
        y: f64,
        /// Query point z.
        z: f64,
        /// Iterations used.
        iterations: usize,
        /// Size of the last step, mm.
        last_step_mm: f64,
    },
    /// The query point has a NaN or infinite coordinate.
    #[error("query point ({x}, {y}, {z}) is not finite")]
    NotFinite {
        /// Query point x.
        x: f64,
        /// Query point y.
        y: f64,
        /// Query point z.
        z: f64,
    },
    /// The query point is finite but so far out that squared distances to
    /// it would overflow.
    #[error("query point ({x:e}, {y:e}, {z:e}) is out of range: coordinates must lie within +-{limit_mm:e} mm")]
    OutOfRange {
        /// Query point x.
        x: f64,
        /// Query point y.
        y: f64,
        /// Query point z.
        z: f64,
        /// Largest coordinate magnitude accepted, mm.
        limit_mm: f64,
    },
}

/// Largest coordinate magnitude of a query point, mm: squared distances
/// to the surface stay finite (the surface's own coordinates are checked
/// far tighter when it is made).
pub const MAX_QUERY_MM: f64 = 1e150;

/// The closest point found on a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Surface parameters of the foot point.
    pub uv: Vec2,
    /// The foot point `S(u, v)`.
    pub point: Point3,
    /// Unit outward normal at the foot.
    pub normal: Vec3,
    /// Unsigned distance from the query point to the foot, mm.
    pub distance: f64,
    /// Distance signed by `(query - foot) . normal` (positive outside), mm.
    pub signed_distance: f64,
    /// Newton iterations spent (all starts together for cold queries).
    pub iterations: usize,
    /// Whether the search confirmed this foot as the closest point.
    pub status: SearchStatus,
}

/// Warm projection: bounded Newton over the whole domain from `hint`.
///
/// ```
/// use cmm::geometry::{NurbsSurface, projection::project_from, ProjectionOptions};
/// use cmm::math::{Point3, Vec2};
/// // Bilinear plane z = 0 over [0, 10]^2.
/// let s = NurbsSurface::try_new([1, 1], vec![0., 0., 1., 1.], vec![0., 0., 1., 1.],
///     &[vec![[0., 0., 0.], [0., 10., 0.]], vec![[10., 0., 0.], [10., 10., 0.]]], None, false).unwrap();
/// let pr = project_from(&s, Point3::new(3., 4., 2.), Vec2::new(0.5, 0.5), &ProjectionOptions::default()).unwrap();
/// assert!((pr.uv - Vec2::new(0.3, 0.4)).norm() < 1e-12);
/// assert!((pr.signed_distance - 2.0).abs() < 1e-12);
/// ```
pub fn project_from(
    surface: &NurbsSurface,
    p: Point3,
    hint: Vec2,
    opts: &ProjectionOptions,
) -> Result<Projection, ProjectionError> {
    check_query(p)?;
    let foot = newton::minimise(surface, p, hint, &domain_bounds(surface), opts)?;
    Ok(foot.into_projection(surface, p))
}

/// Where the next warm query starts: the parameters of the previous foot
/// and, once a query has run, the derivative table there, so that the first
/// Newton step of the next query needs no evaluation of the surface. This
/// is how a query along a path (one per control cycle) costs about one
/// evaluation.
#[derive(Debug, Clone, Copy)]
pub struct WarmStart {
    /// The last foot (its table valid when `has_table`), updated in place.
    foot: Foot,
    has_table: bool,
}

impl PartialEq for WarmStart {
    fn eq(&self, other: &Self) -> bool {
        self.foot.uv == other.foot.uv
            && self.has_table == other.has_table
            && (!self.has_table || self.foot.d == other.foot.d)
    }
}

impl WarmStart {
    /// A start at parameters `uv` with no derivative table yet.
    pub fn new(uv: Vec2) -> WarmStart {
        WarmStart {
            foot: Foot::unevaluated(uv),
            has_table: false,
        }
    }

    /// Parameters of the last foot (or of the start).
    pub fn uv(&self) -> Vec2 {
        self.foot.uv
    }

    /// Runs the Newton iteration from this start and keeps the new foot
    /// (returned by reference: the per-cycle path copies no tables).
    #[inline(always)]
    pub(crate) fn run<F: Fn(Vec2, &mut Jet2)>(
        &mut self,
        eval: F,
        p: Point3,
        bounds: &Bounds,
        opts: &ProjectionOptions,
    ) -> Result<&Foot, ProjectionError> {
        if self.has_table {
            minimise_cached(eval, p, &mut self.foot, bounds, opts)?;
        } else {
            self.foot = minimise_with(eval, p, self.foot.uv, bounds, opts)?;
            self.has_table = true;
        }
        Ok(&self.foot)
    }
}

/// Warm projection along a path: like [`project_from`], starting from
/// `warm` (the previous query's foot) and updating it to the new foot.
///
/// ```
/// use cmm::geometry::{NurbsSurface, ProjectionOptions};
/// use cmm::geometry::projection::{project_warm, WarmStart};
/// use cmm::math::{Point3, Vec2};
/// let s = NurbsSurface::try_new([1, 1], vec![0., 0., 1., 1.], vec![0., 0., 1., 1.],
///     &[vec![[0., 0., 0.], [0., 10., 0.]], vec![[10., 0., 0.], [10., 10., 0.]]], None, false).unwrap();
/// let mut warm = WarmStart::new(Vec2::new(0.5, 0.5));
/// for k in 0..5 {
///     let x = 3.0 + 0.05 * k as f64;
///     let pr = project_warm(&s, Point3::new(x, 4., 2.), &mut warm, &ProjectionOptions::default()).unwrap();
///     assert!((pr.point.x - x).abs() < 1e-12 && (pr.signed_distance - 2.0).abs() < 1e-12);
/// }
/// assert!((warm.uv().x - 0.32).abs() < 1e-12);
/// ```
pub fn project_warm(
    surface: &NurbsSurface,
    p: Point3,
    warm: &mut WarmStart,
    opts: &ProjectionOptions,
) -> Result<Projection, ProjectionError> {
    check_query(p)?;
    let bounds = domain_bounds(surface);
    let eval = |x: Vec2, out: &mut Jet2| surface.jet2_into(x.x, x.y, out);
    let foot = warm.run(eval, p, &bounds, opts)?;
    Ok(foot.projection(surface, p))
}

fn domain_bounds(surface: &NurbsSurface) -> Bounds {
    let ((u0, u1), (v0, v1)) = surface.domain();
    Bounds {
        lo: Vec2::new(u0, v0),
        hi: Vec2::new(u1, v1),
    }
}

/// `Ok` for a valid query point: finite, each coordinate within
/// [`MAX_QUERY_MM`].
pub fn check_query(p: Point3) -> Result<(), ProjectionError> {
    let (x, y, z) = (p.x, p.y, p.z);
    if !p.iter().all(|c| c.is_finite()) {
        Err(ProjectionError::NotFinite { x, y, z })
    } else if !p.iter().all(|c| c.abs() <= MAX_QUERY_MM) {
        Err(ProjectionError::OutOfRange {
            x,
            y,
            z,
            limit_mm: MAX_QUERY_MM,
        })
    } else {
        Ok(())
    }
}
