//! Tolerances of the CAD import (all lengths in mm).

/// Tolerances and limits used while converting CAD faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImportOptions {
    /// Maximum chord error of sampled edge polylines (trims), mm. Default 1 um.
    pub chord_tolerance_mm: f64,
    /// Margin added around a face's extent when bounding an unbounded
    /// analytic surface (plane, cylinder, cone), mm. Default 0.1 mm.
    pub extent_margin_mm: f64,
    /// Distance below which two vertices coincide (closed edges) and below
    /// which a point lies on an axis (cone apex, sphere pole), mm. Default 1e-6 mm.
    pub point_tolerance_mm: f64,
    /// Largest allowed gap between a vertex and the surface point of its
    /// pcurve end, mm; beyond it the pcurve is not trusted. Default 0.01 mm.
    pub pcurve_tolerance_mm: f64,
    /// Largest allowed distance between an edge sample and the surface point
    /// of its projected (u, v) for projection-based trims, mm. Default 1 um.
    pub projection_tolerance_mm: f64,
    /// Largest gap between opposite boundary curves of a B-spline surface
    /// for it to count as closed (a seam) in that direction, mm. Default 1 um.
    pub seam_tolerance_mm: f64,
    /// Upper bound on the samples of one edge (guards hostile input).
    pub max_edge_samples: usize,
    /// Take the edge-on-surface tolerance (used in place of
    /// `projection_tolerance_mm`) from the file's declared length
    /// uncertainty (STEP UNCERTAINTY_MEASURE_WITH_UNIT, converted to mm),
    /// bounded to `uncertainty_range_mm`. Default true.
    pub use_file_uncertainty: bool,
    /// Lower and upper bound applied to a file's declared uncertainty, mm.
    /// Default [1e-3, 0.1] mm: a declared uncertainty only ever loosens the
    /// 1 um default, because files declare their modeller's confusion
    /// distance, not how far their edges stray (a part declaring 2e-5 mm
    /// has edges up to 2.4e-4 mm off their surfaces).
    pub uncertainty_range_mm: [f64; 2],
}

impl ImportOptions {
    /// The options with the edge-on-surface tolerance taken from a file's
    /// declared uncertainty `declared_mm` (when enabled, finite and
    /// positive), bounded to [`ImportOptions::uncertainty_range_mm`].
    pub fn with_file_uncertainty(mut self, declared_mm: Option<f64>) -> ImportOptions {
        let [lo, hi] = self.uncertainty_range_mm;
        let usable = declared_mm.filter(|d| d.is_finite() && *d > 0.0 && lo <= hi);
        if let (true, Some(d)) = (self.use_file_uncertainty, usable) {
            self.projection_tolerance_mm = d.clamp(lo, hi);
        }
        self
    }
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            chord_tolerance_mm: 1e-3,
            extent_margin_mm: 0.1,
            point_tolerance_mm: 1e-6,
            pcurve_tolerance_mm: 0.01,
            projection_tolerance_mm: 1e-3,
            seam_tolerance_mm: 1e-3,
            max_edge_samples: 20_000,
            use_file_uncertainty: true,
            uncertainty_range_mm: [1e-3, 0.1],
        }
    }
}
