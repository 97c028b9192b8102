//! The way back out of a measuring move after a collision: the ball's path
//! since the move left free air, kept every [`super::EscapeOptions::trail_step_mm`],
//! each point lifted off the surface the ball then touched.
//!
//! A scan that runs in under an overhang (the probe body under a lamp's
//! shade, the shaft under a flange) until the probe strikes it may end
//! where no route from the design data leads out: straight up runs into
//! the overhang, and short escape legs stay under it. The path the probe
//! came in along was clear all the way until the strike (the machine
//! reported no collision on it), so after backing out of the strike the
//! probe goes back along it, the ball lifted off the surface it followed
//! by its deflection there plus [`super::EscapeOptions::retrace_clear_mm`],
//! to where the measuring move began in free air: the point the route to
//! the feature led to, from which later routes start.
use super::{travel, Tracker};
use crate::host::observe::{Machine, Phase};
use crate::math::Point3;

impl Tracker<'_> {
    /// Starts the trail at the ball's position now (a measuring move
    /// leaves free air here), or forgets it (`false`: a move that does not
    /// measure, which backs out the way it came).
    pub(super) fn start_trail(&mut self, measuring: bool) {
        self.trail.clear();
        if measuring {
            self.trail.push(self.ball_undeflected());
        }
    }

    /// Whether a trail leads back to where the measuring move left free
    /// air.
    pub(super) fn has_trail(&self) -> bool {
        !self.trail.is_empty()
    }

    /// Adds the ball's position to the trail when it has moved
    /// [`super::EscapeOptions::trail_step_mm`] from the last point kept,
    /// lifted off the surface along the stylus's deflection.
    #[inline(always)]
    pub(super) fn extend_trail(&mut self) {
        let Some(&last) = self.trail.last() else {
            return;
        };
        let here = self.ball_undeflected();
        if (here - last).norm_squared() < self.trail_step_squared() {
            return;
        }
        let d = self.now.deflection;
        let lift = match d.try_normalize(1e-9) {
            Some(u) if d.norm() >= self.modes.free_mm => {
                u * (d.norm() + self.modes.escape.retrace_clear_mm)
            }
            _ => crate::math::Vec3::zeros(),
        };
        self.trail.push(here + lift);
    }

    /// The square of how far apart the trail's points are kept, mm^2
    /// (asked every cycle, so no root): at most
    /// [`super::EscapeOptions::trail_step_mm`], and for a small ball less,
    /// so that a chord between two points of the ball centre's path (which
    /// bends round a convex edge on a radius no less than the ball's, `r`)
    /// sags from it by at most half the retrace's clearance `c`: `sqrt(4 r
    /// c)` (0.55 mm for a 0.3 mm ball; on 2 mm chords a ring of 0.75 mm
    /// radius was cut through).
    fn trail_step_squared(&self) -> f64 {
        let e = &self.modes.escape;
        let sag_bound = 4.0 * self.probe_radius() * e.retrace_clear_mm;
        e.trail_step_mm.powi(2).min(sag_bound)
    }

    /// Moves the probe back along the trail to its start (see the module
    /// docs), in phase retract; stops where the machine reports anything
    /// but a free move. The trail is used once.
    pub(super) fn retrace(&mut self, cmm: &mut dyn Machine) {
        let opts = self.modes;
        let trail = std::mem::take(&mut self.trail);
        let here = self.ball_undeflected();
        let back: Vec<Point3> = trail.iter().rev().copied().collect();
        let Some(&start) = trail.first() else {
            return;
        };
        if (here - start).norm() < 1e-6 {
            return;
        }
        self.enter(cmm, Phase::Retract);
        let speed = self.modes.escape.retrace_speed_mm_s;
        let _ = travel(cmm, self, &back, speed, 0.0, &opts);
    }
}
