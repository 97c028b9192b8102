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
        }
    }
}
