//! Positioning moves and the bookkeeping every mode shares.
use super::{HostProbe, Measured, ModeOptions, Outcome};
use crate::host::machine::{Cmm, MachineStatus, Readings};
use crate::math::{Point3, Vec3};

/// Follows the machine cycle by cycle: ball centre, deflection, time, and
/// points taken at a pitch.
pub struct Tracker {
    /// What the host knows about the probe.
    pub probe: HostProbe,
    /// Latest readings.
    pub now: Readings,
    /// Machine time at the start, s.
    pub t0: f64,
    /// Measured points so far.
    pub points: Vec<Measured>,
    /// Ball-centre velocity commanded in the last cycle, mm/s.
    pub command: Vec3,
    last_point: Option<Point3>,
}

impl Tracker {
    /// Starts tracking from the machine's current readings.
    pub fn new(cmm: &dyn Cmm, probe: HostProbe) -> Tracker {
        let now = cmm.readings();
        Tracker {
            probe,
            t0: now.time_s,
            now,
            points: Vec::new(),
            command: Vec3::zeros(),
            last_point: None,
        }
    }

    /// Undeflected ball centre from the scales, machine coordinates.
    pub fn ball_undeflected(&self) -> Point3 {
        self.now.scales + self.probe.probe_vector
    }

    /// Deflection magnitude, mm.
    pub fn deflection(&self) -> f64 {
        self.now.deflection.norm()
    }

    /// The measured point now, if the stylus is deflected.
    /// Ball and normal use the probe's deflection correction.
    pub fn measured(&self) -> Option<Measured> {
        self.probe
            .locate(self.now.scales, self.now.deflection, self.command)
    }

    /// Steps the machine and returns an outcome if it halted.
    pub fn step(&mut self, cmm: &mut dyn Cmm, v: Vec3) -> Option<Outcome> {
        self.now = cmm.step(v);
        self.command = v;
        match self.now.status {
            MachineStatus::Ok => None,
            MachineStatus::AxisLimit { .. } => Some(Outcome::AxisLimit),
            MachineStatus::ProbeOverrange { .. } => Some(Outcome::OverDeflection),
        }
    }

    /// Records the current point when it is at least `pitch` from the last.
    pub fn sample(&mut self, pitch: f64) {
        let Some(m) = self.measured() else { return };
        if self
            .last_point
            .is_none_or(|p| (m.point - p).norm() >= pitch)
        {
            self.points.push(m);
            self.last_point = Some(m.point);
        }
    }

    /// Machine time since the start, s.
    pub fn elapsed(&self) -> f64 {
        self.now.time_s - self.t0
    }
}

/// Proportional gain of the final approach of a positioning move, 1/s.
const POSITION_GAIN: f64 = 30.0;

/// Moves the undeflected ball centre to `target` in a straight line
/// (trapezoidal speed, proportional correction), stopping at rest.
pub fn move_to(
    cmm: &mut dyn Cmm,
    tr: &mut Tracker,
    target: Point3,
    speed: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let dt = cmm.cycle_s();
    let mut v_prev = Vec3::zeros();
    for _ in 0..opts.max_cycles {
        let err = target - tr.ball_undeflected();
        let dist = err.norm();
        if dist <= opts.arrive_tol_mm && v_prev.norm() < 1.0 {
            return Ok(());
        }
        let brake = (2.0 * opts.rapid_accel_mm_s2 * dist).sqrt();
        let dir = err.try_normalize(1e-12).unwrap_or_else(Vec3::zeros);
        let want = dir * speed.min(brake).min(POSITION_GAIN * dist);
        let dv = want - v_prev;
        let max_dv = opts.rapid_accel_mm_s2 * dt;
        let v = v_prev + dv * (max_dv / dv.norm().max(max_dv));
        if let Some(o) = tr.step(cmm, v) {
            return Err(o);
        }
        v_prev = v;
    }
    Err(Outcome::Aborted)
}

/// Moves to `target` between measurements, arriving along `approach`
/// (the outward direction at the target): first free the stylus if it is
/// touching, then up to the clearance height, across to a point `far`
/// outside the target, down, and in (straight when no clearance height is
/// set).
pub fn reposition(
    cmm: &mut dyn Cmm,
    tr: &mut Tracker,
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    recover(cmm, tr, opts)?;
    let speed = opts.rapid_speed_mm_s;
    let Some(z) = opts.clearance_z_mm else {
        return move_to(cmm, tr, target, speed, opts);
    };
    let here = tr.ball_undeflected();
    if (here - target).norm() <= opts.standoff_mm {
        return move_to(cmm, tr, target, speed, opts);
    }
    let outside = target + approach * REPOSITION_OUTSIDE_MM;
    if (here.xy() - outside.xy()).norm() > opts.arrive_tol_mm {
        move_to(
            cmm,
            tr,
            Point3::new(here.x, here.y, z.max(here.z)),
            speed,
            opts,
        )?;
        move_to(
            cmm,
            tr,
            Point3::new(outside.x, outside.y, z.max(here.z)),
            speed,
            opts,
        )?;
    }
    move_to(cmm, tr, outside, speed, opts)?;
    move_to(cmm, tr, target, speed, opts)
}

/// How far outside the target point a repositioning move comes down, mm.
const REPOSITION_OUTSIDE_MM: f64 = 15.0;

/// Backs the stylus off the part along its deflection until it is free,
/// then by the standoff.
pub fn recover(cmm: &mut dyn Cmm, tr: &mut Tracker, opts: &ModeOptions) -> Result<(), Outcome> {
    let Some(dir) = tr.now.deflection.try_normalize(1e-9) else {
        return Ok(());
    };
    for _ in 0..opts.max_cycles {
        if tr.deflection() < opts.contact_mm * 0.5 {
            let away = tr.ball_undeflected() + dir * opts.standoff_mm;
            return move_to(cmm, tr, away, opts.approach_speed_mm_s, opts);
        }
        if let (Some(o), true) = (tr.step(cmm, dir * opts.approach_speed_mm_s), true) {
            if o != Outcome::OverDeflection {
                return Err(o);
            }
        }
    }
    Err(Outcome::Aborted)
}

/// Within this distance of a waypoint the move turns to the next one, mm.
const WAYPOINT_PASS_MM: f64 = 1.0;

/// Moves through `waypoints` without stopping at the intermediate ones
/// (accelerations limited, braking only for the last), ending at rest on
/// the last.
pub fn move_through(
    cmm: &mut dyn Cmm,
    tr: &mut Tracker,
    waypoints: &[Point3],
    speed: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let Some((&last, via)) = waypoints.split_last() else {
        return Ok(());
    };
    let dt = cmm.cycle_s();
    let mut v_prev = Vec3::zeros();
    for (k, &w) in via.iter().enumerate() {
        for _ in 0..opts.max_cycles {
            let err = w - tr.ball_undeflected();
            if err.norm() <= WAYPOINT_PASS_MM {
                break;
            }
            let rest: f64 = err.norm() + polyline_length(&waypoints[k..]);
            let brake = (2.0 * opts.rapid_accel_mm_s2 * rest).sqrt();
            let want = err.normalize() * speed.min(brake);
            let dv = want - v_prev;
            let max_dv = opts.rapid_accel_mm_s2 * dt;
            let v = v_prev + dv * (max_dv / dv.norm().max(max_dv));
            if let Some(o) = tr.step(cmm, v) {
                return Err(o);
            }
            v_prev = v;
        }
    }
    move_to(cmm, tr, last, speed, opts)
}

fn polyline_length(points: &[Point3]) -> f64 {
    points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}
