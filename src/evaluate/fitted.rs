//! Fitted features: a geometric element fitted (least squares) to the
//! measured points and, for the nominal, the same fit of the nominal points;
//! size, form and position are checked against the feature's tolerances.
use serde::Serialize;

use super::model::{PointReport, Verdict};
use crate::fit::{
    fit, fit_near, Cylinder, Element, ElementKind, FitError, FitOptions, FitReport, Method,
};
use crate::math::{Mat3, Point3, Vec3};
use crate::program::{FitElement, FitSpec};

/// The essentials of a fitted element, part coordinates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElementSummary {
    /// Centre (circle, sphere), axis point (cylinder) or plane point.
    pub center: [f64; 3],
    /// Normal (circle, plane) or axis direction (cylinder); zeros for a sphere.
    pub direction: [f64; 3],
    /// Diameter, mm (0 for a plane).
    pub diameter_mm: f64,
    /// Form error: range of the residuals, mm.
    pub form_mm: f64,
}

/// Result of a fitted feature (`features[].fit` in report.json).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitResult {
    /// `circle`, `plane`, `sphere` or `cylinder`.
    pub element: &'static str,
    /// Fit of the measured points (absent when the fit could not be
    /// made).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured: Option<ElementSummary>,
    /// Fit of the nominal points (absent when the fit could not be made).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nominal: Option<ElementSummary>,
    /// Measured minus nominal diameter, mm.
    pub size_deviation_mm: f64,
    /// Distance of the measured centre / axis / plane from the nominal, mm.
    pub position_deviation_mm: f64,
    /// Pass or fail against the fit tolerances; incomplete when the fit
    /// could not be made (too few points on the surface, say).
    pub status: Verdict,
    /// Why the fit could not be made, if it could not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

impl FitResult {
    /// Leaves the fit unjudged (status incomplete, with why) because the
    /// feature's measuring did not complete.
    pub fn not_judged(&mut self) {
        self.status = Verdict::Incomplete;
        self.error.get_or_insert_with(|| {
            "not judged: the feature's measuring did not complete, so the fit covers only \
             the points measured"
                .to_string()
        });
    }
}

fn kind(e: FitElement) -> (ElementKind, &'static str) {
    (e.kind(), e.name())
}

/// Fits and checks; `None` when there are no points. The nominal element
/// is fitted to the points' nominal points, or where a section scan's
/// point has one, to the design section's point next to it
/// ([`PointReport::in_section`]).
pub fn fit_feature(spec: &FitSpec, points: &[PointReport]) -> Option<FitResult> {
    let points: Vec<&PointReport> = points.iter().filter(|p| p.in_fit()).collect();
    let measured: Vec<Point3> = (points.iter())
        .map(|p| Point3::from(p.measured_in_section.unwrap_or(p.measured)))
        .collect();
    let nominal: Vec<Point3> = (points.iter())
        .map(|p| Point3::from(p.in_section.unwrap_or(p.nominal)))
        .collect();
    if measured.is_empty() {
        return None;
    }
    let (k, name) = kind(spec.element);
    let opts = FitOptions::default();
    // The measured element starts from the nominal one: points that fit
    // two elements give the one the design meant.
    let normals: Vec<Vec3> = points.iter().map(|p| Vec3::from(p.normal)).collect();
    let nominal_fit = fit_nominal(spec.element, &nominal, &normals);
    let both = nominal_fit.and_then(|n| Ok((fit_near(k, &measured, &opts, &n.element)?, n)));
    Some(match both {
        Ok((m, n)) => compare(
            spec,
            name,
            (summary(&m.element, m.form_mm), &m.element),
            summary(&n.element, n.form_mm),
            &nominal,
        ),
        Err(e) => FitResult {
            element: name,
            measured: None,
            nominal: None,
            size_deviation_mm: 0.0,
            position_deviation_mm: 0.0,
            status: Verdict::Incomplete,
            error: Some(e.to_string()),
        },
    })
}

/// The least-squares `element` of design points `nominal` with their
/// `normals`; a cylinder starts from the axis square to the normals.
pub fn fit_nominal(
    element: FitElement,
    nominal: &[Point3],
    normals: &[Vec3],
) -> Result<FitReport, FitError> {
    let (k, opts) = (element.kind(), FitOptions::default());
    match design_axis(normals) {
        Some(axis) if k == ElementKind::Cylinder => fit_near(k, nominal, &opts, &axis),
        _ => fit(k, Method::Lsq, nominal, &opts),
    }
}

/// A cylinder whose axis is the direction most nearly square to every
/// normal of `normals` (the least eigenvector of the sum of `n n^T`): a
/// cylinder's surface normals are all square to its axis. Only its axis
/// direction means anything. `None` for no normals.
fn design_axis(normals: &[Vec3]) -> Option<Element> {
    if normals.is_empty() {
        return None;
    }
    let m = normals
        .iter()
        .fold(Mat3::zeros(), |m, n| m + n * n.transpose());
    let eig = m.symmetric_eigen();
    let k = eig.eigenvalues.imin();
    let axis = eig.eigenvectors.column(k).into_owned();
    Some(Element::Cylinder(Cylinder {
        axis_point: Point3::origin(),
        axis_direction: axis.try_normalize(1e-12)?,
        radius: 0.0,
    }))
}

fn summary(e: &Element, form_mm: f64) -> ElementSummary {
    let (c, d, dia) = match e {
        Element::Circle(c) => (c.center, c.normal, 2.0 * c.radius),
        Element::Sphere(s) => (s.center, Vec3::zeros(), 2.0 * s.radius),
        Element::Cylinder(c) => (c.axis_point, c.axis_direction, 2.0 * c.radius),
        Element::Plane(p) => (p.point, p.normal, 0.0),
        _ => (Point3::origin(), Vec3::zeros(), 0.0),
    };
    ElementSummary {
        center: c.into(),
        direction: d.into(),
        diameter_mm: dia,
        form_mm,
    }
}

/// Position deviation: the centres' distance (circle, sphere), or the
/// largest distance of the measured axis or plane from the nominal one
/// over the stretch the nominal points `at` span: at the ends of their
/// extent along the nominal axis (the distance from a point moving along
/// one line to another line is convex, largest at an end), or at each of
/// them on the nominal plane (the distance between two planes is linear
/// along either). A tilted axis or plane is off by more at the ends of
/// what was measured than at its middle.
fn position(e: &Element, nominal: &ElementSummary, at: &[Point3]) -> f64 {
    let (c, dn) = (Point3::from(nominal.center), Vec3::from(nominal.direction));
    let along = |p: &Point3| (p - c).dot(&dn);
    match e {
        Element::Cylinder(m) => {
            let to_axis = |p: Point3| {
                let r = p - m.axis_point;
                (r - m.axis_direction * r.dot(&m.axis_direction)).norm()
            };
            let ts = at.iter().map(along);
            let lo = ts.clone().fold(0.0, f64::min);
            let hi = ts.fold(0.0, f64::max);
            to_axis(c + dn * lo).max(to_axis(c + dn * hi))
        }
        Element::Plane(m) => {
            let off = |q: Point3| (q - m.point).dot(&m.normal).abs();
            at.iter()
                .map(|p| off(p - dn * along(p)))
                .fold(off(c), f64::max)
        }
        other => (c - Point3::from(summary(other, 0.0).center)).norm(),
    }
}

fn compare(
    spec: &FitSpec,
    name: &'static str,
    (m, me): (ElementSummary, &Element),
    n: ElementSummary,
    at: &[Point3],
) -> FitResult {
    let size = m.diameter_mm - n.diameter_mm;
    let pos = position(me, &n, at);
    let size_ok = spec.size_mm.is_none_or(|[lo, hi]| size >= lo && size <= hi);
    let form_ok = spec.form_mm.is_none_or(|f| m.form_mm <= f);
    let pos_ok = spec.position_mm.is_none_or(|p| pos <= p);
    let status = if size_ok && form_ok && pos_ok {
        Verdict::Pass
    } else {
        Verdict::Fail
    };
    FitResult {
        element: name,
        measured: Some(m),
        nominal: Some(n),
        size_deviation_mm: size,
        position_deviation_mm: pos,
        status,
        error: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::format::{FitElement, FitSpec};

    fn point(at: [f64; 3], edge: bool) -> PointReport {
        PointReport {
            measured: at,
            nominal: at,
            normal: [0.0, 0.0, 1.0],
            deviation_mm: 0.0,
            true_deviation_mm: 0.0,
            edge,
            off_section: false,
            in_section: None,
            measured_in_section: None,
        }
    }

    /// `p` turned by `angle` (rad) about the x axis.
    fn turned(p: [f64; 3], angle: f64) -> [f64; 3] {
        let (c, s) = (angle.cos(), angle.sin());
        [p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]]
    }

    /// Points of a nominal element at `nominal` (with the design normals
    /// `normal`), measured on the element turned by `angle` about the x
    /// axis.
    fn tilted(nominal: &[([f64; 3], [f64; 3])], angle: f64) -> Vec<PointReport> {
        (nominal.iter())
            .map(|&(at, normal)| PointReport {
                measured: turned(at, angle),
                nominal: at,
                normal,
                deviation_mm: 0.0,
                true_deviation_mm: 0.0,
                edge: false,
                off_section: false,
                in_section: None,
                measured_in_section: None,
            })
            .collect()
    }

    fn spec(element: FitElement) -> FitSpec {
        FitSpec {
            element,
            size_mm: None,
            form_mm: None,
            position_mm: Some(0.05),
        }
    }

    /// A cylinder of radius 5 about the z axis touched at z = 0 and z = 20,
    /// and a plane z = 0 touched out to 10 mm from the axis, each turned
    /// by 0.2 degrees about the x axis: the axis and the plane stand off
    /// the nominal ones by 20 sin(0.2 deg) = 0.0698 mm and 10 sin(0.2 deg)
    /// = 0.0349 mm at the far ends of what was touched, 0 at the origin
    /// (the reference: the turn itself).
    #[test]
    fn a_tilted_axis_or_plane_is_off_by_its_largest_distance_over_the_points() {
        let angle = 0.2_f64.to_radians();
        let ring = |z: f64| {
            (0..4).map(move |k| {
                let a = std::f64::consts::FRAC_PI_2 * k as f64;
                ([5.0 * a.cos(), 5.0 * a.sin(), z], [a.cos(), a.sin(), 0.0])
            })
        };
        let cylinder: Vec<_> = ring(0.0).chain(ring(20.0)).collect();
        let fit = fit_feature(&spec(FitElement::Cylinder), &tilted(&cylinder, angle)).unwrap();
        let want = 20.0 * angle.sin();
        assert!((fit.position_deviation_mm - want).abs() < 1e-9, "{fit:?}");
        assert_eq!(fit.status, Verdict::Fail);
        let plane: Vec<_> = [
            [10.0, 0.0, 0.0],
            [0.0, 10.0, 0.0],
            [-10.0, 0.0, 0.0],
            [0.0, -10.0, 0.0],
        ]
        .map(|p| (p, [0.0, 0.0, 1.0]))
        .to_vec();
        let fit = fit_feature(&spec(FitElement::Plane), &tilted(&plane, angle)).unwrap();
        let want = 10.0 * angle.sin();
        assert!((fit.position_deviation_mm - want).abs() < 1e-9, "{fit:?}");
        assert_eq!(fit.status, Verdict::Pass);
    }

    /// Three touch points of a plane, one of them an edge point: two
    /// remain for the fit, which cannot be made. The fit is incomplete,
    /// with no element in it, not a failed plane at the origin.
    #[test]
    fn a_fit_left_too_few_points_is_incomplete_and_has_no_element() {
        let spec = FitSpec {
            element: FitElement::Plane,
            size_mm: None,
            form_mm: Some(0.02),
            position_mm: None,
        };
        let points = [
            point([6.0, 40.0, 0.0], false),
            point([6.0, -40.0, 0.0], false),
            point([6.0, 0.0, 41.0], true),
        ];
        let fit = fit_feature(&spec, &points).unwrap();
        assert_eq!(fit.status, Verdict::Incomplete);
        assert!(fit.measured.is_none() && fit.nominal.is_none());
        assert!(fit.error.is_some_and(|e| e.contains("got 2")));
        let all = points.map(|p| PointReport { edge: false, ..p });
        assert_eq!(fit_feature(&spec, &all).unwrap().status, Verdict::Pass);
    }
}
