//! Measuring modes (JP6484108B2): touch points, passive and active
//! design-value scanning, autonomous scanning, and the moves between them.
//! Every attempt ends with exactly one [`Outcome`] and its machine time.

mod autonomous;
mod direct;
mod motion;
mod park;
mod route;
mod scan;
mod touch;

pub use autonomous::{
    autonomous_scan, autonomous_start, AutonomousTask, EndPath, STALL_MOVE_SHARE,
};
pub use direct::{approach_standoff, direct_move, FreeSpace, MoveStop};
pub use motion::{approach_to, move_through, move_to, recover, reposition, Tracker};
pub use park::park;
pub use route::{mount_reachable, route_from_above};
pub use scan::{design_value_scan, scan_start, ScanKind, ScanPlan, ScanTargets};
pub use touch::{touch_point, touch_start};

use crate::host::observe::Phase;
use crate::host::probe_correction::DeflectionCorrection;
use crate::math::{Point3, Vec3};
use crate::seam::ProbePart;

/// How a measuring attempt ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Measured to the end.
    Completed,
    /// Active scanning left its trajectory tolerance.
    TrajectoryError,
    /// The stylus lost contact with the part.
    LostContact,
    /// The stylus was pushed past its range.
    OverDeflection,
    /// An axis reached its travel limit.
    AxisLimit,
    /// The probe struck the part: the shaft or the body at any time, or
    /// the ball during a move that does not measure ([`Collision`] says
    /// where).
    Collision,
    /// Stopped for another reason (cycle budget exhausted).
    Aborted,
    /// Not started: no route to the start point is clear of the part (as
    /// the design data knows it). Reported as `aborted`.
    #[serde(rename = "aborted")]
    Blocked,
}

/// Where and how the probe struck the part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collision {
    /// Which part of the probe.
    pub probe_part: ProbePart,
    /// Where, machine coordinates, mm.
    pub at: Point3,
    /// Speed when it struck, mm/s.
    pub speed_mm_s: f64,
    /// What the software was doing.
    pub phase: Phase,
}

/// What the host knows about its probe (nominal or calibrated).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HostProbe {
    /// Probe mount to ball centre, machine coordinates, mm.
    pub probe_vector: Vec3,
    /// Tip radius, mm.
    pub tip_radius_mm: f64,
    /// Correction of the deflection readings (identity when uncalibrated).
    pub correction: DeflectionCorrection,
}

impl HostProbe {
    /// Nominal probe values without any deflection correction.
    pub fn nominal(probe_vector: Vec3, tip_radius_mm: f64) -> HostProbe {
        HostProbe {
            probe_vector,
            tip_radius_mm,
            correction: DeflectionCorrection::identity(),
        }
    }

    /// The measurement of one reading: scales, raw deflection reading and
    /// the commanded ball-centre velocity of that cycle (for the scanning
    /// direction); `None` when the stylus is not deflected.
    pub fn locate(&self, scales: Point3, reading: Vec3, motion: Vec3) -> Option<Measured> {
        let d = self.correction.deflection(reading);
        let normal = self.correction.normal(d, reading, motion)?;
        Some(self.measured(scales, reading, motion, d, normal))
    }

    /// [`Self::locate`] for a probe whose correction is the identity (not
    /// calibrated): the same result without evaluating the correction
    /// (whose terms are all zero, so the deflection is the reading and the
    /// normal its direction).
    pub fn locate_uncorrected(
        &self,
        scales: Point3,
        reading: Vec3,
        motion: Vec3,
    ) -> Option<Measured> {
        let normal = reading.try_normalize(1e-12)?;
        Some(self.measured(scales, reading, motion, reading, normal))
    }

    fn measured(
        &self,
        scales: Point3,
        reading: Vec3,
        motion: Vec3,
        d: Vec3,
        normal: Vec3,
    ) -> Measured {
        let ball = scales + self.probe_vector + d;
        Measured {
            point: ball - normal * self.tip_radius_mm,
            normal,
            ball,
            scales,
            reading,
            motion,
        }
    }
}

/// A measured surface point (machine coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// Surface point: ball centre minus the radius along the measured normal.
    pub point: Point3,
    /// Measured surface normal (the deflection direction).
    pub normal: Vec3,
    /// Ball centre.
    pub ball: Point3,
    /// Raw scale readings (probe mount), machine coordinates.
    pub scales: Point3,
    /// Raw deflection reading, mm.
    pub reading: Vec3,
    /// Ball-centre velocity commanded in the cycle of the reading, mm/s.
    pub motion: Vec3,
}

/// Result of one measuring attempt.
#[derive(Debug, Clone, PartialEq)]
pub struct Attempt {
    /// How it ended.
    pub outcome: Outcome,
    /// Points measured before it ended.
    pub points: Vec<Measured>,
    /// Machine time spent, s.
    pub machine_time_s: f64,
    /// Largest |trajectory error| seen, mm (0 for modes without a path).
    pub max_trajectory_error_mm: f64,
    /// Where the probe struck the part, when the outcome is a collision.
    pub collision: Option<Collision>,
}

/// Gains, speeds and thresholds of the measuring modes (mm, s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeOptions {
    /// Positioning speed in free air, mm/s (bridge CMMs position at several
    /// hundred mm/s; the default machine profile allows 500 per axis).
    pub rapid_speed_mm_s: f64,
    /// Positioning acceleration, mm/s^2 (the default machine profile
    /// allows 2000 per axis; the rest is margin for path corrections).
    pub rapid_accel_mm_s2: f64,
    /// Approach speed towards the surface, mm/s.
    pub approach_speed_mm_s: f64,
    /// Clearance of approach start points from the surface, mm.
    pub standoff_mm: f64,
    /// The shortest standoff an approach into a hole too small for the
    /// halves of [`Self::standoff_mm`] down to a sixteenth is started at,
    /// mm (a 0.3 mm ball in a 0.44 mm bore has 0.14 mm of room).
    pub min_standoff_mm: f64,
    /// Deflection at which a touch point triggers, mm.
    pub trigger_mm: f64,
    /// Below this deflection the stylus counts as out of contact, mm.
    pub contact_mm: f64,
    /// In a move that does not measure (positioning, retract), a
    /// deflection above this is the ball striking the part, mm: about 20
    /// times what a free probe reads (its noise, about 0.1 um), so a ball
    /// that grazes a wall by a few micrometres is reported as a collision,
    /// as a controller's unexpected-contact check does.
    pub strike_mm: f64,
    /// A retract off the surface ends once the deflection reads below
    /// this, mm: the stylus has left the surface (a free probe reads its
    /// noise only, about 0.1 um), so the move that follows starts clear.
    pub free_mm: f64,
    /// Backing the stylus off the part gives up (the move stops there,
    /// aborted) once the ball has gone this far without the stylus coming
    /// free, mm: a few times the stylus's range, so a stylus held on a
    /// surface it is not backing off is never dragged along it.
    pub free_travel_mm: f64,
    /// Passive scanning fails above this deflection, mm.
    pub over_deflection_mm: f64,
    /// Consecutive cycles out of contact before passive scanning, touch
    /// points and autonomous scanning report lost contact.
    pub lost_contact_cycles: usize,
    /// The same for active scanning, which searches for the surface along
    /// its normal and normally reports a trajectory error first.
    pub active_lost_contact_cycles: usize,
    /// An active scan that goes this far along its path without contact
    /// reports lost contact, mm: the stretch it passed unmeasured (a tight
    /// curve the deflection loop could not follow, a surface fallen away
    /// beyond the trajectory tolerance's reach) is not a completed scan,
    /// however few cycles it took.
    pub active_lost_contact_mm: f64,
    /// Gain of the path-following velocity `Gf` (dimensionless).
    pub gain_follow: f64,
    /// Gain of the deflection loop `Ge`, 1/s.
    pub gain_deflection: f64,
    /// Gain of the sideways path correction `Gc`, 1/s.
    pub gain_correction: f64,
    /// Autonomous scanning speed, mm/s.
    pub autonomous_speed_mm_s: f64,
    /// An autonomous scan of an open section also ends where the ball
    /// rolls over the part's end within this distance of the section's
    /// nominal end (mm): the surface it follows then faces the way the
    /// section ran out (a part shifted back along the section ends before
    /// its design does, and the scan would follow its end face down and
    /// under it).
    pub autonomous_end_reach_mm: f64,
    /// An autonomous scan whose ball centre stays within a tenth of this
    /// (mm) of where it was while it is driven this far along has stalled
    /// (held in a corner it cannot turn, its deflection switching between
    /// the walls) and ends `aborted`.
    pub autonomous_stall_mm: f64,
    /// Lateral acceleration limit used in speed planning, mm/s^2.
    pub lateral_accel_mm_s2: f64,
    /// Tangential acceleration limit used in speed planning, mm/s^2.
    pub tangential_accel_mm_s2: f64,
    /// Safety cap on the cycles of one attempt.
    pub max_cycles: usize,
    /// An active scan that gets less than `stall_mm` further along its
    /// path within this much machine time ends with a trajectory error
    /// (the probe cannot follow the path: the part stands in its way), s.
    pub stall_s: f64,
    /// See [`Self::stall_s`], mm.
    pub stall_mm: f64,
    /// Position tolerance ending a positioning move at rest, mm (moves end
    /// in free air before a probing approach, so micrometres are not
    /// needed; a tighter tolerance only lengthens the settling tail).
    pub arrive_tol_mm: f64,
    /// Height (machine z of the ball centre) above the part for moves
    /// between measurements; `None` moves in a straight line.
    pub clearance_z_mm: Option<f64>,
    /// The box the machine's linear axes (the scales' readings) may move
    /// in, `(lo, hi)`, machine coordinates, mm: positioning moves brake so
    /// that they stop inside it (the controller's soft limits; `None`:
    /// not known, no braking).
    pub travel_mm: Option<([f64; 3], [f64; 3])>,
    /// How far inside each end of [`Self::travel_mm`] positioning moves
    /// stop, mm: the axes lag the commands, and the braking that aims at
    /// the very end would touch the hard limit.
    pub soft_limit_mm: f64,
    /// Spacing of the grid that moves between measurements are planned
    /// from, mm: a route starts with a short leg from where the probe
    /// came free (which the measurement decides) to the nearest grid
    /// point, and is planned from there, so that a batch's parts, each
    /// freeing the probe micrometres from the others, share their routes'
    /// checks (a route is planned from the probe's own position when the
    /// grid point gives none). 0: from the probe's own position.
    pub plan_grid_mm: f64,
    /// How the probe backs out after it struck the part.
    pub escape: EscapeOptions,
}

/// The move out of the part after a collision: the machine does not stop
/// by itself when the stylus shaft or the probe body strikes the part (nor
/// when the ball runs into it during a move that does not measure), so the
/// software backs the probe out the way it came, at this speed, until the
/// machine reports it clear and the stylus free, then this much further,
/// and stops there. Later moves then start in free air instead of inside
/// the part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EscapeOptions {
    /// Speed of the move out, mm/s.
    pub speed_mm_s: f64,
    /// How far the move goes on once the probe is clear, mm.
    pub clear_mm: f64,
    /// The move out gives up after this distance, mm (the probe then stays
    /// where it is and the next move reports the collision again).
    pub max_mm: f64,
    /// Once out, the probe goes back along the path of the measuring move
    /// to where it left free air (a scan that ran in under an overhang has
    /// no route out where it struck): the path's points are kept this far
    /// apart, mm (less for a small ball, see `Tracker::trail_step_squared`).
    pub trail_step_mm: f64,
    /// The ball goes back this far (mm) off the surface it followed, on
    /// top of the deflection it had there.
    pub retrace_clear_mm: f64,
    /// Speed of the way back, mm/s.
    pub retrace_speed_mm_s: f64,
    /// A ball pressed this much harder (mm of deflection) than when the
    /// move out began has run into the part on the way out, and backs off
    /// along its deflection instead.
    pub press_mm: f64,
}

impl Default for EscapeOptions {
    fn default() -> Self {
        EscapeOptions {
            speed_mm_s: 10.0,
            clear_mm: 2.0,
            max_mm: 30.0,
            trail_step_mm: 2.0,
            retrace_clear_mm: 0.5,
            retrace_speed_mm_s: 30.0,
            press_mm: 0.1,
        }
    }
}

impl Default for ModeOptions {
    fn default() -> Self {
        ModeOptions {
            rapid_speed_mm_s: 400.0,
            rapid_accel_mm_s2: 1500.0,
            approach_speed_mm_s: 10.0,
            standoff_mm: 5.0,
            min_standoff_mm: 0.01,
            trigger_mm: 0.3,
            contact_mm: 0.02,
            strike_mm: 0.002,
            free_mm: 5e-4,
            free_travel_mm: 5.0,
            over_deflection_mm: 0.8,
            lost_contact_cycles: 40,
            active_lost_contact_cycles: 1000,
            active_lost_contact_mm: 1.0,
            gain_follow: 1.0,
            gain_deflection: 40.0,
            gain_correction: 40.0,
            autonomous_speed_mm_s: 12.0,
            autonomous_end_reach_mm: 5.0,
            autonomous_stall_mm: 10.0,
            lateral_accel_mm_s2: 1000.0,
            tangential_accel_mm_s2: 500.0,
            max_cycles: 3_000_000,
            stall_s: 2.0,
            stall_mm: 0.1,
            arrive_tol_mm: 0.01,
            clearance_z_mm: None,
            travel_mm: None,
            soft_limit_mm: 0.1,
            plan_grid_mm: 1.0,
            escape: EscapeOptions::default(),
        }
    }
}
