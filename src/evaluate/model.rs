//! The evaluated results of a part's features: points with their
//! deviations, statistics, tolerances and verdicts.
use serde::Serialize;

use crate::host::inspect::record::{AttemptReport, CorrectionReport, FeatureKind};

/// Pass, fail or incomplete (a part, a feature).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Everything measured and in tolerance.
    Pass,
    /// Measured, some deviation out of tolerance.
    Fail,
    /// A measurement could not be completed even after all fallbacks.
    Incomplete,
}

/// Deviation statistics, mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stats {
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
    /// Mean.
    pub mean: f64,
    /// Root mean square.
    pub rms: f64,
}

/// Allowed deviation band, mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    /// Lower limit.
    pub lower: f64,
    /// Upper limit.
    pub upper: f64,
}

/// One reported point (part coordinates).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointReport {
    /// Measured surface point.
    pub measured: [f64; 3],
    /// Closest nominal point.
    pub nominal: [f64; 3],
    /// Outward unit normal there.
    pub normal: [f64; 3],
    /// Signed distance measured - nominal along the normal, mm.
    pub deviation_mm: f64,
    /// The same for the true surface point nearest the measured one, mm.
    pub true_deviation_mm: f64,
    /// Measured while the ball rolled over an edge of the design (the
    /// measured normal far from the design's at the nominal point): left
    /// out of the feature's deviations, verdict and fit.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub edge: bool,
    /// A section scan's point that lies off the section plane by more than
    /// [`super::nominal::OFF_SECTION_MM`]: a point of the surface, but not
    /// of the section (the ball touching a wall beyond a concave corner
    /// it could not reach in the plane, or where the stylus could not
    /// hold its contact in the plane): its deviation is the surface's
    /// there and counts, but it is left out of the feature's fit.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub off_section: bool,
    /// For a section scan's point, the design section's point next to
    /// `nominal` (in the section plane, [`super::section_point`]): the
    /// fitted element's nominal is fitted to these. Not reported.
    #[serde(skip)]
    pub in_section: Option<[f64; 3]>,
    /// For a section scan's point, `measured` taken along the surface
    /// into the section plane ([`super::section_point::slide_into`]): the
    /// measured element is fitted to these. Not reported.
    #[serde(skip)]
    pub measured_in_section: Option<[f64; 3]>,
}

impl PointReport {
    /// Whether the point counts for the feature's deviations and fit.
    pub fn on_surface(&self) -> bool {
        !self.edge
    }

    /// Whether the point takes part in the feature's fit: on the surface
    /// and, for a section scan, in the section.
    pub fn in_fit(&self) -> bool {
        self.on_surface() && !self.off_section
    }
}

/// One feature's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FeatureReport {
    /// Name.
    pub name: String,
    /// What kind of feature it is.
    #[serde(rename = "type")]
    pub kind: FeatureKind,
    /// Verdict.
    pub status: Verdict,
    /// Attempts in order.
    pub attempts: Vec<AttemptReport>,
    /// Corrections in order.
    pub corrections: Vec<CorrectionReport>,
    /// Statistics of `deviation_mm` over the points (zeros when none).
    pub deviation_mm: Stats,
    /// The tolerance band.
    pub tolerance_mm: Tolerance,
    /// Human-readable notes (why incomplete, what was corrected).
    pub notes: Vec<String>,
    /// The fitted element, when the feature asks for one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit: Option<super::fitted::FitResult>,
    /// The points.
    pub points: Vec<PointReport>,
}

impl Stats {
    /// Statistics of a set of values (zeros for none).
    pub fn of(values: impl Iterator<Item = f64> + Clone) -> Stats {
        let n = values.clone().count();
        if n == 0 {
            return Stats {
                min: 0.0,
                max: 0.0,
                mean: 0.0,
                rms: 0.0,
            };
        }
        let min = values.clone().fold(f64::INFINITY, f64::min);
        let max = values.clone().fold(f64::NEG_INFINITY, f64::max);
        let mean = values.clone().sum::<f64>() / n as f64;
        let rms = (values.map(|v| v * v).sum::<f64>() / n as f64).sqrt();
        Stats {
            min,
            max,
            mean,
            rms,
        }
    }
}
