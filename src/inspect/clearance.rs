//! Free space around the nominal part for direct moves between
//! measurements ([`crate::host::modes::direct_move`]).
//!
//! A straight move is clear when every sampled position of the ball and of
//! the stylus shaft along it keeps the ball radius plus a margin from every
//! nominal surface. The move's two ends lie outside the material, so the
//! line can only enter it by crossing a surface, which the samples would
//! come too close to (their spacing is below the required distance). Only
//! the design data's surfaces are obstacles: fixtures and faces missing
//! from the design data are not known to the software.
use crate::host::modes::FreeSpace;
use crate::math::{Point3, Vec3};
use crate::program::Pose;
use crate::workpiece::Workpiece;

/// Margins of the direct-move check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceOptions {
    /// Free distance kept between the ball (or stylus) and the nominal
    /// surfaces, mm. Covers the as-machined part's deviation from the
    /// design data (the trajectory tolerance and more).
    pub margin_mm: f64,
    /// Spacing of the samples along the move and along the stylus, mm
    /// (must stay below the ball radius plus the margin).
    pub step_mm: f64,
}

impl Default for ClearanceOptions {
    fn default() -> Self {
        ClearanceOptions {
            margin_mm: 4.0,
            step_mm: 2.0,
        }
    }
}

/// The nominal part on the machine, with the probe's ball and stylus.
pub struct PartClearance<'w> {
    /// Design data.
    pub workpiece: &'w Workpiece,
    /// Part to machine.
    pub pose: Pose,
    /// Ball centre to probe mount along the stylus, machine coordinates, mm.
    pub stylus: Vec3,
    /// Ball radius, mm.
    pub tip_radius_mm: f64,
    /// Margins.
    pub opts: ClearanceOptions,
}

impl PartClearance<'_> {
    /// Whether the ball centre at `p` (machine) keeps the required
    /// distance from the part; projection failures count as not clear.
    fn point_clear(&self, p: Point3, need: f64) -> bool {
        let q = self.pose.to_part(p);
        let far = self
            .workpiece
            .faces
            .iter()
            .all(|f| f.index.lower_bound(q) >= need);
        far || self
            .workpiece
            .closest_point(q)
            .is_ok_and(|fp| fp.projection.distance >= need)
    }
}

impl FreeSpace for PartClearance<'_> {
    fn segment_clear(&self, from: Point3, to: Point3) -> bool {
        let step = self.opts.step_mm.max(1e-3);
        let need = self.tip_radius_mm + self.opts.margin_mm;
        let along = ((to - from).norm() / step).ceil().max(1.0) as usize;
        let up = (self.stylus.norm() / step).ceil() as usize;
        (0..=along).all(|i| {
            let ball = from + (to - from) * (i as f64 / along as f64);
            (0..=up).all(|j| {
                let shaft = if up == 0 { 0.0 } else { j as f64 / up as f64 };
                self.point_clear(ball + self.stylus * shaft, need)
            })
        })
    }
}
