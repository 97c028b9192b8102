//! Probe-radius compensation: the points are stylus-ball centres, which lie
//! one ball radius off the measured surface. The element is fitted to the
//! centres and then offset by the radius; residuals and form are unchanged.
use super::element::{Cone, Element};
use super::{FitError, FitReport};

/// From which side the surface was probed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Probed from inside the material's hole (a bore): the surface lies one
    /// ball radius further out than the centres; for a plane, the material
    /// lies on the positive side of the reported normal.
    Inside,
    /// Probed from outside (a shaft): the surface lies one ball radius further
    /// in; for a plane, the material lies on the negative side of the normal.
    Outside,
}

impl Side {
    /// `+1` inside, `-1` outside: the sign of the radius change.
    fn sign(self) -> f64 {
        match self {
            Side::Inside => 1.0,
            Side::Outside => -1.0,
        }
    }

    /// The side's name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Side::Inside => "inside",
            Side::Outside => "outside",
        }
    }
}

fn sized(radius: f64, probe: f64, side: Side) -> Result<f64, FitError> {
    let compensated_mm = radius + side.sign() * probe;
    if compensated_mm > 0.0 {
        Ok(compensated_mm)
    } else {
        Err(FitError::CompensationTooLarge {
            probe_radius_mm: probe,
            radius_mm: radius,
            compensated_mm,
        })
    }
}

/// A cone offset by the probe radius keeps axis and angle; its apex moves
/// along the axis by `probe / sin(half angle)`.
fn cone(c: &Cone, probe: f64, side: Side) -> Cone {
    let shift = -side.sign() * probe / c.half_angle_rad.sin();
    Cone {
        apex: c.apex + c.axis_direction * shift,
        ..*c
    }
}

/// The surface element for a fit made to ball centres of a probe of radius
/// `probe_radius_mm`, probed from `side`.
pub fn compensate_probe(
    mut report: FitReport,
    probe_radius_mm: f64,
    side: Side,
) -> Result<FitReport, FitError> {
    let r = probe_radius_mm;
    if !(r.is_finite() && r >= 0.0) {
        return Err(FitError::BadProbeRadius { radius_mm: r });
    }
    report.element = match report.element {
        Element::Circle(mut c) => Element::Circle({
            c.radius = sized(c.radius, r, side)?;
            c
        }),
        Element::Sphere(mut s) => Element::Sphere({
            s.radius = sized(s.radius, r, side)?;
            s
        }),
        Element::Cylinder(mut c) => Element::Cylinder({
            c.radius = sized(c.radius, r, side)?;
            c
        }),
        Element::Cone(c) => Element::Cone(cone(&c, r, side)),
        Element::Plane(mut p) => Element::Plane({
            p.point += p.normal * (side.sign() * r);
            p
        }),
        Element::Line(_) | Element::Line2d(_) => {
            return Err(FitError::NoCompensation {
                element: report.kind.name(),
            })
        }
    };
    Ok(report)
}
