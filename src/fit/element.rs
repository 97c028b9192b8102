//! Fitted elements and their signed residuals.
//!
//! Sign rules: line directions, plane and circle normals and cylinder axes
//! have their largest-magnitude component positive (see
//! [`canonical_sign`](super::canonical_sign)); a cone axis points towards
//! growing radius. Residuals are orthogonal distances, positive outside the
//! material for circle, sphere, cylinder and cone, along the normal for a
//! plane, to the left of the direction (in xy) for a 2-D line, and unsigned
//! for a 3-D line.
use crate::math::{Point3, Vec3};

/// A straight line through `point` along the unit vector `direction`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// The centroid of the points (lies on the least-squares line), mm.
    pub point: Point3,
    /// Unit direction.
    pub direction: Vec3,
}

/// A plane through `point` with unit `normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// A point of the plane (the centroid's foot), mm.
    pub point: Point3,
    /// Unit normal.
    pub normal: Vec3,
}

/// A circle in 3-D.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    /// Centre, mm.
    pub center: Point3,
    /// Unit normal of the circle's plane.
    pub normal: Vec3,
    /// Radius, mm.
    pub radius: f64,
}

/// A sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Centre, mm.
    pub center: Point3,
    /// Radius, mm.
    pub radius: f64,
}

/// A circular cylinder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// The point of the axis nearest the centroid of the points, mm.
    pub axis_point: Point3,
    /// Unit axis direction.
    pub axis_direction: Vec3,
    /// Radius, mm.
    pub radius: f64,
}

/// A circular cone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    /// Apex, mm.
    pub apex: Point3,
    /// Unit axis direction, towards growing radius.
    pub axis_direction: Vec3,
    /// Half the apex angle, radians, in (0, pi/2).
    pub half_angle_rad: f64,
}

/// A fitted element of any kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Element {
    /// 3-D line (unsigned residuals).
    Line(Line),
    /// Line in the xy plane (z ignored; residuals signed, left positive).
    Line2d(Line),
    /// Plane.
    Plane(Plane),
    /// Circle (also the 2-D circle, with normal +z).
    Circle(Circle),
    /// Sphere.
    Sphere(Sphere),
    /// Cylinder.
    Cylinder(Cylinder),
    /// Cone.
    Cone(Cone),
}

impl Element {
    /// Signed orthogonal distance of `p` from the element, mm.
    pub fn residual(&self, p: &Point3) -> f64 {
        match self {
            Element::Line(l) => off_axis(p - l.point, &l.direction).norm(),
            Element::Line2d(l) => line2d_residual(l, p),
            Element::Plane(pl) => (p - pl.point).dot(&pl.normal),
            Element::Circle(c) => off_axis(p - c.center, &c.normal).norm() - c.radius,
            Element::Sphere(s) => (p - s.center).norm() - s.radius,
            Element::Cylinder(c) => off_axis(p - c.axis_point, &c.axis_direction).norm() - c.radius,
            Element::Cone(c) => cone_residual(c, p),
        }
    }
}

fn off_axis(v: Vec3, axis: &Vec3) -> Vec3 {
    v - axis * v.dot(axis)
}

fn line2d_residual(l: &Line, p: &Point3) -> f64 {
    let left = Vec3::new(-l.direction.y, l.direction.x, 0.0);
    let v = p - l.point;
    left.dot(&Vec3::new(v.x, v.y, 0.0))
}

fn cone_residual(c: &Cone, p: &Point3) -> f64 {
    let v = p - c.apex;
    let along = v.dot(&c.axis_direction);
    let radial = off_axis(v, &c.axis_direction).norm();
    radial * c.half_angle_rad.cos() - along * c.half_angle_rad.sin()
}

/// Signed residual statistics, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResidualStats {
    /// Root mean square.
    pub rms: f64,
    /// Smallest (most negative).
    pub min: f64,
    /// Largest.
    pub max: f64,
}

/// Statistics of the residuals of `points` from `element`.
pub fn residual_stats(element: &Element, points: &[Point3]) -> ResidualStats {
    let init = (0.0, f64::INFINITY, f64::NEG_INFINITY);
    let parts = super::parallel::map_chunks(points, |c| {
        c.iter()
            .map(|p| element.residual(p))
            .fold(init, |(s, lo, hi), r| (s + r * r, lo.min(r), hi.max(r)))
    });
    let (sq, min, max) = parts
        .iter()
        .fold(init, |(s, lo, hi), p| (s + p.0, lo.min(p.1), hi.max(p.2)));
    let rms = (sq / points.len().max(1) as f64).sqrt();
    ResidualStats { rms, min, max }
}

/// Form error from the residual statistics: peak to valley `max - min`,
/// except for a 3-D line, where it is the diameter `2 * max` of the
/// cylinder about the line that holds all points (straightness).
pub fn form_error(element: &Element, stats: &ResidualStats) -> f64 {
    match element {
        Element::Line(_) => 2.0 * stats.max,
        _ => stats.max - stats.min,
    }
}
