//! Fits that fail on a perfect part: a feature whose element, fitted to
//! its own design points, already has more form error than the feature's
//! form tolerance (a circle fitted to a tilted section of a cylinder, an
//! ellipse; a plane of touch points on a curved face). `cmm check` notes
//! them: the program runs as written, and its fit fails however well the
//! part is made.
use crate::evaluate::fitted::fit_nominal;
use crate::math::{Point3, Vec3};
use crate::program::{Feature, FitElement, Program};

/// A feature whose fit fails on its own design points.
#[derive(Debug, Clone, PartialEq)]
pub struct FormOverTolerance {
    /// The feature's name.
    pub feature: String,
    /// The element fitted.
    pub element: FitElement,
    /// Form error of the element fitted to the design points, mm.
    pub nominal_form_mm: f64,
    /// The feature's form tolerance, mm.
    pub form_mm: f64,
}

/// The features of `program` whose fitted element has more form error on
/// the design's own points (every point of a section's curves, the
/// projected touch points) than the feature allows.
pub fn form_over_tolerance(program: &Program) -> Vec<FormOverTolerance> {
    program.features.iter().filter_map(over_tolerance).collect()
}

fn over_tolerance(feature: &Feature) -> Option<FormOverTolerance> {
    let spec = feature.fit()?;
    let form_mm = spec.form_mm?;
    let (points, normals) = design_points(feature);
    let fitted = fit_nominal(spec.element, &points, &normals).ok()?;
    (fitted.form_mm > form_mm).then(|| FormOverTolerance {
        feature: feature.name().to_string(),
        element: spec.element,
        nominal_form_mm: fitted.form_mm,
        form_mm,
    })
}

/// The design points of a feature and their normals.
pub fn design_points(feature: &Feature) -> (Vec<Point3>, Vec<Vec3>) {
    match feature {
        Feature::Section { curves, .. } => (curves.iter().flat_map(|c| &c.points))
            .map(|p| (p.point, p.normal))
            .unzip(),
        Feature::Touch { points, .. } => points.iter().map(|p| (p.point, p.normal)).unzip(),
    }
}
