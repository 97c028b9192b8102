//! Orthogonal-distance least-squares fits, one file per element. Each
//! works on centred points, starts from a closed-form or algebraic
//! solution and refines with [`least_squares`](super::gauss_newton).
pub(crate) mod circle;
pub(crate) mod cone;
pub(crate) mod cylinder;
pub(crate) mod line;
pub(crate) mod plane;
pub(crate) mod sphere;

use super::element::Element;
use super::{ElementKind, FitError, FitOptions};
use crate::math::Point3;

/// An element and the iterations its fit took.
type Fitted = Result<(Element, usize), FitError>;

/// The least-squares fit of `kind` to `points`.
pub(crate) fn fit(kind: ElementKind, points: &[Point3], opts: &FitOptions) -> Fitted {
    match kind {
        ElementKind::Line => line_3d(points, opts),
        ElementKind::Line2d => line_2d(points, opts),
        ElementKind::Plane => plane::fit(points, opts).map(|(p, it)| (Element::Plane(p), it)),
        ElementKind::Circle => circle_any(points, opts, kind),
        ElementKind::Circle2d => circle_any(points, opts, kind),
        ElementKind::Sphere => sphere_fit(points, opts),
        ElementKind::Cylinder => cylinder_fit(points, opts),
        ElementKind::Cone => cone_fit(points, opts),
    }
}

fn line_3d(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, dir, passes) = line::lsq_3d(points, opts)?;
    Ok((Element::Line(line::to_element_3d(&c, &dir)), passes))
}

fn line_2d(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = line::lsq_2d(points, opts)?;
    Ok((
        Element::Line2d(line::to_element_2d(&c, &s.model)),
        s.iterations,
    ))
}

fn circle_any(points: &[Point3], opts: &FitOptions, kind: ElementKind) -> Fitted {
    let pl = circle::in_plane(points, opts, kind == ElementKind::Circle2d)?;
    let s = circle::lsq(&pl, opts, kind.name())?;
    Ok((
        Element::Circle(circle::to_element(&pl, &s.model)),
        s.iterations,
    ))
}

fn sphere_fit(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = sphere::lsq(points, opts)?;
    Ok((
        Element::Sphere(sphere::to_element(&c, &s.model)),
        s.iterations,
    ))
}

fn cylinder_fit(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = cylinder::lsq(points, opts)?;
    Ok((
        Element::Cylinder(cylinder::to_element(&c, &s.model)),
        s.iterations,
    ))
}

fn cone_fit(points: &[Point3], opts: &FitOptions) -> Fitted {
    let (c, s) = cone::lsq(points, opts)?;
    Ok((Element::Cone(cone::to_element(&c, &s.model)?), s.iterations))
}
