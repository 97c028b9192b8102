//! Minimum-zone, minimum-circumscribed and maximum-inscribed fits per
//! element, each started from the least-squares solution.
use super::element::Element;
use super::lsq::{circle, cone, cylinder, line, plane, sphere};
use super::minimum_zone::{chebyshev, Names, Objective};
use super::{ElementKind, FitError, FitOptions, Method};
use crate::math::Point3;

/// A Chebyshev fit's element and iteration count.
pub(crate) type Fitted = (Element, usize);

fn unsupported(kind: ElementKind, method: Method, available: &'static str) -> FitError {
    FitError::UnsupportedMethod {
        element: kind.name(),
        method: method.name(),
        available,
    }
}

fn objective(kind: ElementKind, method: Method) -> Result<Objective, FitError> {
    let sized = matches!(
        kind,
        ElementKind::Circle | ElementKind::Circle2d | ElementKind::Sphere | ElementKind::Cylinder
    );
    match method {
        Method::MinimumZone => Ok(Objective::Zone),
        Method::MinCircumscribed if sized => Ok(Objective::Circumscribed),
        Method::MaxInscribed if sized => Ok(Objective::Inscribed),
        _ => Err(unsupported(kind, method, "lsq, minimum-zone")),
    }
}

/// The Chebyshev fit of `kind` by `method` (not `Lsq`).
pub(crate) fn fit(
    kind: ElementKind,
    method: Method,
    points: &[Point3],
    opts: &FitOptions,
) -> Result<Fitted, FitError> {
    let obj = objective(kind, method)?;
    let names = Names {
        element: kind.name(),
        method: method.name(),
    };
    match kind {
        ElementKind::Line => line_3d(points, opts, names),
        ElementKind::Line2d => line_2d(points, obj, opts, names),
        ElementKind::Plane => plane_zone(points, obj, opts, names),
        ElementKind::Circle => circle_zone(points, obj, opts, names, false),
        ElementKind::Circle2d => circle_zone(points, obj, opts, names, true),
        ElementKind::Sphere => sphere_zone(points, obj, opts, names),
        ElementKind::Cylinder => cylinder_zone(points, obj, opts, names),
        ElementKind::Cone => cone_zone(points, obj, opts, names),
    }
}

/// Straightness of a 3-D line: the smallest cylinder holding all points.
fn line_3d(points: &[Point3], opts: &FitOptions, names: Names) -> Result<Fitted, FitError> {
    let (c, dir, _) = line::lsq_3d(points, opts)?;
    let start = cylinder::CylinderModel::new(&dir, crate::math::Vec3::zeros(), 0.0);
    let z = chebyshev(start, &c.points, Objective::Circumscribed, opts, names)?;
    let cyl = cylinder::to_element(&c, &z.model);
    let line = super::Line {
        point: cyl.axis_point,
        direction: cyl.axis_direction,
    };
    Ok((Element::Line(line), z.iterations))
}

fn line_2d(
    points: &[Point3],
    obj: Objective,
    opts: &FitOptions,
    names: Names,
) -> Result<Fitted, FitError> {
    let (c, solved) = line::lsq_2d(points, opts)?;
    let z = chebyshev(solved.model, &c.points, obj, opts, names)?;
    Ok((
        Element::Line2d(line::to_element_2d(&c, &z.model)),
        z.iterations,
    ))
}

fn plane_zone(
    points: &[Point3],
    obj: Objective,
    opts: &FitOptions,
    names: Names,
) -> Result<Fitted, FitError> {
    let (c, solved) = plane::lsq(points, opts, names.element)?;
    let z = chebyshev(solved.model, &c.points, obj, opts, names)?;
    Ok((
        Element::Plane(plane::to_element(&c, &z.model)),
        z.iterations,
    ))
}

fn circle_zone(
    points: &[Point3],
    obj: Objective,
    opts: &FitOptions,
    names: Names,
    flat: bool,
) -> Result<Fitted, FitError> {
    let pl = circle::in_plane(points, opts, flat)?;
    let solved = circle::lsq(&pl, opts, names.element)?;
    let z = chebyshev(solved.model, &pl.local, obj, opts, names)?;
    Ok((
        Element::Circle(circle::to_element(&pl, &z.model)),
        z.iterations,
    ))
}

fn sphere_zone(
    points: &[Point3],
    obj: Objective,
    opts: &FitOptions,
    names: Names,
) -> Result<Fitted, FitError> {
    let (c, solved) = sphere::lsq(points, opts)?;
    let z = chebyshev(solved.model, &c.points, obj, opts, names)?;
    Ok((
        Element::Sphere(sphere::to_element(&c, &z.model)),
        z.iterations,
    ))
}

fn cylinder_zone(
    points: &[Point3],
    obj: Objective,
    opts: &FitOptions,
    names: Names,
) -> Result<Fitted, FitError> {
    let (c, solved) = cylinder::lsq(points, opts)?;
    let z = chebyshev(solved.model, &c.points, obj, opts, names)?;
    Ok((
        Element::Cylinder(cylinder::to_element(&c, &z.model)),
        z.iterations,
    ))
}

fn cone_zone(
    points: &[Point3],
    obj: Objective,
    opts: &FitOptions,
    names: Names,
) -> Result<Fitted, FitError> {
    let (c, solved) = cone::lsq(points, opts)?;
    let z = chebyshev(solved.model, &c.points, obj, opts, names)?;
    Ok((Element::Cone(cone::to_element(&c, &z.model)?), z.iterations))
}
