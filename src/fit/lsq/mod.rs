//! Orthogonal-distance least-squares fits, one file per element. Each
//! works on centred points, starts from a closed-form or algebraic
//! solution and refines with [`least_squares`](super::gauss_newton).
pub(crate) mod circle;
pub(crate) mod cone;
pub(crate) mod cylinder;
pub(crate) mod line;
pub(crate) mod plane;
pub(crate) mod sphere;

use super::element::{Element, ResidualStats};
use super::gauss_newton::Solved;
use super::{ElementKind, FitError, FitOptions};
use crate::math::Point3;

/// A least-squares element, the iterations its fit took and, where the
/// solver already has them, the residual statistics.
pub(crate) struct LsqFit {
    /// The element.
    pub element: Element,
    /// Solver iterations.
    pub iterations: usize,
    /// Residual statistics from the solver's last pass.
    pub stats: Option<ResidualStats>,
}

type Fitted = Result<LsqFit, FitError>;

fn bare(element: Element, iterations: usize) -> LsqFit {
    LsqFit {
        element,
        iterations,
        stats: None,
    }
}

fn solved<M>(element: Element, s: &Solved<M>) -> LsqFit {
    LsqFit {
        element,
        iterations: s.iterations,
        stats: Some(s.stats),
    }
}

/// The least-squares fit of `kind` to `points`.
pub(crate) fn fit(kind: ElementKind, points: &[Point3], opts: &FitOptions) -> Fitted {
    match kind {
        ElementKind::Line => line_3d(points, opts),
        ElementKind::Line2d => line_2d(points, opts),
        ElementKind::Plane => plane::fit(points, opts).map(|(p, it)| bare(Element::Plane(p), it)),
        ElementKind::Circle => circle_any(points, opts, kind),
        ElementKind::Circle2d => circle_any(points, opts, kind),
        ElementKind::Sphere => sphere_fit(points, opts),
        ElementKind::Cylinder => cylinder_fit(points, opts),
        ElementKind::Cone => cone_fit(points, opts),
    }
}

/// [`fit`], started from the nominal element `near` where the points
/// may fit more than one element (a cylinder); the others as [`fit`].
pub(crate) fn fit_near(
    kind: ElementKind,
    points: &[Point3],
    opts: &FitOptions,
    near: &Element,
) -> Fitted {
    match (kind, near) {
        (ElementKind::Cylinder, Element::Cylinder(n)) => {
            let (c, s) = cylinder::lsq_near(points, opts, &n.axis_direction)?;
            Ok(solved(
                Element::Cylinder(cylinder::to_element(&c, &s.model)),
                &s,
            ))
        }
        _ => fit(kind, points, opts),
    }
}

fn line_3d(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, dir, passes) = line::lsq_3d(points, opts)?;
    Ok(bare(Element::Line(line::to_element_3d(&c, &dir)), passes))
}

fn line_2d(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = line::lsq_2d(points, opts)?;
    // Statistics are recomputed: the canonical direction may flip the sign.
    let line = line::to_element_2d(&c, &s.model);
    Ok(bare(Element::Line2d(line), s.iterations))
}

fn circle_any(points: &[Point3], opts: &FitOptions, kind: ElementKind) -> Fitted {
    let pl = circle::in_plane(points, opts, kind == ElementKind::Circle2d)?;
    let s = circle::lsq(&pl, opts, kind.name())?;
    Ok(solved(
        Element::Circle(circle::to_element(&pl, &s.model)),
        &s,
    ))
}

fn sphere_fit(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = sphere::lsq(points, opts)?;
    Ok(solved(
        Element::Sphere(sphere::to_element(&c, &s.model)),
        &s,
    ))
}

fn cylinder_fit(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = cylinder::lsq(points, opts)?;
    Ok(solved(
        Element::Cylinder(cylinder::to_element(&c, &s.model)),
        &s,
    ))
}

fn cone_fit(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = cone::lsq(points, opts)?;
    Ok(solved(Element::Cone(cone::to_element(&c, &s.model)?), &s))
}
