//! The simulated CMM: servo axes, true probe and the as-machined part,
//! stepped one control cycle at a time behind the [`Cmm`] seam.
//!
//! The ball centre follows the machine's (true) URDF chain: linear axes,
//! then the probe head when there is one, whose revolute axes are indexed
//! (turned and locked) by [`Cmm::index_head`]; the 21 geometric error terms
//! act through the effective probe vector. The probe's sensor turns with
//! the head.
use rand::rngs::Xoshiro256PlusPlus;
use rand::SeedableRng;

use super::collision::{ProbeCollisions, Stylus};
use super::contact::{CollisionOptions, ContactOptions, ContactSearch};
use super::dynamics::{Servo, ServoError};
use super::noise::gaussian;
use super::pressed::PressedContact;
use super::probe::TrueProbe;
use crate::geometry::ProjectionOptions;
use crate::machine::{GeometricErrors, LinearAxes, MachineModel, MachineProfile};
use crate::math::{Iso3, Point3, Vec3};
use crate::program::Pose;
use crate::seam::{Cmm, HeadCommandError, MachineStatus, Readings};
use crate::workpiece::Workpiece;
use crate::world::as_machined::AsMachined;
use nalgebra::UnitQuaternion;

/// Contact is evaluated only when the ball may be this close to the part
/// (beyond its radius), mm; further away the contact search's free-air
/// bound rules it out (the roughness, a few micrometres at most, stays far
/// inside this margin).
const CONTACT_MARGIN_MM: f64 = 0.5;

/// The contact needs the ball's distance to the true surface to 0.1 um.
/// A foot-point error `e` changes that distance by about `e^2 / R` and the
/// contact normal by `e / R` (R the curvature radius), so the contact's
/// Newton may end once quadratic convergence predicts a foot error below
/// this, mm: for R >= 0.1 mm the distance is then exact to 1e-11 mm and the
/// deflection direction to 1e-5 rad (3e-6 mm at 0.3 mm deflection).
pub const CONTACT_FINAL_ERROR_MM: f64 = 1e-6;

/// Longest Newton step of the contact search taken as the last one (by
/// Taylor expansion), mm.
pub const CONTACT_FINAL_STEP_MAX_MM: f64 = 1e-3;

/// Projection options of the per-cycle contact: `base` with the looser
/// last-step rule above.
pub fn contact_options(base: &ProjectionOptions) -> ProjectionOptions {
    ProjectionOptions {
        final_error_mm: CONTACT_FINAL_ERROR_MM,
        final_step_max_mm: CONTACT_FINAL_STEP_MAX_MM,
        ..*base
    }
}

/// The true part on the machine table.
#[derive(Debug, Clone, Copy)]
pub struct TruePart<'a> {
    /// Nominal design data (the base of the as-machined definition).
    pub workpiece: &'a Workpiece,
    /// The machined part.
    pub as_machined: &'a AsMachined,
    /// True pose of the part frame on the machine.
    pub pose: Pose,
}

/// Why the simulator could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The start position is outside the machine's travel.
    #[error("start position outside the machine: {0}")]
    Start(#[from] ServoError),
    /// The machine has fewer than three linear axes.
    #[error("the machine needs X, Y and Z axes first in its chain, found {0} axes")]
    Axes(usize),
}

/// A simulated CMM measuring a true part.
pub struct SimulatedCmm<'a> {
    part: TruePart<'a>,
    model: MachineModel,
    /// The model's linear axes, resolved once for the per-cycle sums.
    linear: LinearAxes,
    profile: MachineProfile,
    probe: TrueProbe,
    servo: Servo,
    /// The one noise stream of the simulation: xoshiro256++, one of rand's
    /// named portable generators (reproducible across platforms and
    /// versions), several times cheaper per draw than ChaCha8; the noise
    /// needs statistical quality, not secrecy.
    rng: Xoshiro256PlusPlus,
    /// The per-cycle contact search (free-air bound, near leaves, warm
    /// feet).
    search: ContactSearch,
    last: Readings,
    /// Projection options of the contact search.
    contact: ProjectionOptions,
    /// Whether the profile has any geometric error term.
    geometric: bool,
    /// Probe mount relative to the linear axes (the locked head's turn).
    mount: Iso3,
    /// The true probe vector carried by `mount` (fixed while the head is
    /// locked), mm.
    mounted_probe: Vec3,
    /// The stylus turned by `mount` (machine coordinates).
    stylus: Stylus,
    /// The collision checks of the stylus shaft and the probe body.
    collisions: ProbeCollisions,
    /// Whether `mount` turns anything (a head indexed away from zero).
    turned: bool,
    /// The sensor's reading of the stylus at rest (a zero deflection; no
    /// noise is drawn then), computed once.
    rest_reading: Vec3,
    /// The contact a ball pressed deep into the part is held to.
    pressed: PressedContact,
    /// Reused per-cycle buffers (axis commands, scale readings).
    command: Vec<f64>,
    scales: Vec<f64>,
}

impl<'a> SimulatedCmm<'a> {
    /// A machine at rest with the probe mount at `start` (machine coordinates).
    pub fn new(
        part: TruePart<'a>,
        model: MachineModel,
        profile: MachineProfile,
        probe: TrueProbe,
        seed: u64,
        start: Point3,
    ) -> Result<SimulatedCmm<'a>, SimError> {
        let n = model.axes().len();
        if n < 3 {
            return Err(SimError::Axes(n));
        }
        let linear = LinearAxes::new(&model);
        let mut q = Vec::new();
        linear.to_axes_into(start.coords, &mut q);
        let servo = Servo::new(&model, &profile, &q)?;
        let last = Readings {
            time_s: 0.0,
            scales: start,
            deflection: Vec3::zeros(),
            status: MachineStatus::Ok,
        };
        let rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let geometric = profile.geometric != GeometricErrors::default();
        let rest_reading = probe.response(Vec3::zeros());
        let contact_opts = ContactOptions::default();
        let collisions = ProbeCollisions::new(&probe, &contact_opts, &CollisionOptions::default());
        let mut sim = SimulatedCmm {
            part,
            model,
            linear,
            profile,
            probe,
            servo,
            rng,
            search: ContactSearch::new(part.workpiece, part.as_machined, &contact_opts),
            last,
            contact: contact_options(&part.workpiece.options),
            geometric,
            mount: Iso3::identity(),
            mounted_probe: Vec3::zeros(),
            stylus: Stylus::new(Vec3::zeros()),
            collisions,
            turned: false,
            rest_reading,
            pressed: PressedContact::default(),
            command: Vec::new(),
            scales: Vec::new(),
        };
        sim.update_mount();
        sim.last = sim.observe(Vec3::zeros(), MachineStatus::Ok);
        Ok(sim)
    }

    /// True undeflected ball centre (machine coordinates) for axis positions:
    /// the stylus vector carried through the URDF chain (linear axes, then
    /// the probe head when there is one), plus the displacement of the 21
    /// geometric error terms acting through the effective probe vector
    /// (spindle reference point `B` to the ball, JP2902285B2).
    fn ball_centre(&self, q: &[f64]) -> Point3 {
        let xyz = Point3::from(self.linear.xyz(q));
        let ball = xyz + self.mounted_probe;
        if !self.geometric {
            return ball;
        }
        ball + self.profile.geometric_error(xyz.into(), &(ball - xyz))
    }

    /// Pose of the probe mount (URDF tip link) for axis positions `q`.
    fn tip_pose(&self, q: &[f64]) -> Iso3 {
        let xyz = self.model.linear_xyz(q).unwrap_or([0.0; 3]);
        self.model
            .pose(q)
            .unwrap_or_else(|_| Iso3::translation(xyz[0], xyz[1], xyz[2]))
    }

    /// The probe mount's pose relative to the linear axes' translation,
    /// fixed while the head is locked (the linear axes come first in the
    /// chain); recomputed when the head is indexed.
    fn update_mount(&mut self) {
        let q = self.servo.position();
        let xyz = self.model.linear_xyz(q).unwrap_or([0.0; 3]);
        let linear = Iso3::translation(xyz[0], xyz[1], xyz[2]);
        self.mount = linear.inverse() * self.tip_pose(q);
        self.mounted_probe = (self.mount * Point3::from(self.probe.probe_vector)).coords;
        self.stylus = Stylus::new(self.mount.rotation * self.probe.probe_vector);
        self.turned = self.mount.rotation != UnitQuaternion::identity();
    }

    /// True deflection for the current state (zero when not touching):
    /// the contact search rules out a contact in free air at the cost of
    /// one bound check.
    #[inline(always)]
    fn contact(&mut self, ball: Point3, velocity: Vec3) -> Vec3 {
        let r = self.probe.tip_radius_mm;
        let y = self.part.pose.to_part(ball);
        let (wp, am) = (self.part.workpiece, self.part.as_machined);
        let found = self
            .search
            .query((wp, am), y, r + CONTACT_MARGIN_MM, &self.contact);
        match found {
            Ok(Some(c)) => {
                let (s, push) = self.pressed.follow(y, c.distance, c.push);
                self.touch(s, push, velocity)
            }
            Ok(None) => match self.pressed.beyond_reach(y) {
                Some((s, push)) => self.touch(s, push, velocity),
                None => {
                    self.pressed.release();
                    Vec3::zeros()
                }
            },
            Err(_) => {
                self.search.reset();
                self.pressed.release();
                Vec3::zeros()
            }
        }
    }

    /// The deflection at signed distance `s` (part frame, mm) from the
    /// true part, pushed along `push` (part frame), with the roughness
    /// added to the distance.
    #[inline(never)]
    fn touch(&mut self, s: f64, push: Vec3, velocity: Vec3) -> Vec3 {
        let r = self.probe.tip_radius_mm;
        let rough = gaussian(&mut self.rng, self.part.as_machined.roughness_mm);
        let n = self.part.pose.dir_to_machine(push);
        self.probe.deflection(r - (s + rough), n, velocity)
    }

    /// Keeps `readings` as the last ones, copying the status unless both
    /// are `Ok` (a status may hold a string).
    fn remember(&mut self, readings: &Readings) {
        let last = &mut self.last;
        (last.time_s, last.scales, last.deflection) =
            (readings.time_s, readings.scales, readings.deflection);
        let both_ok = matches!(
            (&last.status, &readings.status),
            (MachineStatus::Ok, MachineStatus::Ok)
        );
        if !both_ok {
            last.status = readings.status.clone();
        }
    }

    /// The readings of the current state. The status: a collision of the
    /// shaft or the body first (the probe is striking the part whatever
    /// else happens), then the servo's own (an axis at its limit), then a
    /// stylus deflected beyond its range.
    #[inline(always)]
    fn observe(&mut self, velocity: Vec3, status: MachineStatus) -> Readings {
        let ball = self.ball_centre(self.servo.position());
        let d = self.contact(ball, velocity);
        let struck = self.collisions.check(
            (&self.search, &self.part),
            (ball, d, &self.stylus),
            &self.contact,
        );
        let status = if let Some((probe_part, strike)) = struck {
            MachineStatus::Collision {
                probe_part,
                at: self.part.pose.to_machine(strike.point),
                speed_mm_s: velocity.norm(),
            }
        } else if d.norm() > self.probe.max_deflection_mm && status == MachineStatus::Ok {
            MachineStatus::ProbeOverrange {
                deflection_mm: d.norm(),
            }
        } else {
            status
        };
        self.servo.read_scales_into(&mut self.rng, &mut self.scales);
        let d = self.probe.within_range(d);
        // The sensor turns with the head: its gain acts in the probe's frame.
        let deflection = if self.turned {
            let turn = self.mount.rotation;
            turn * self.probe.sense(turn.inverse() * d, &mut self.rng)
        } else if is_rest(d) {
            self.rest_reading
        } else {
            self.probe.sense(d, &mut self.rng)
        };
        let time_s = self.servo.time_s();
        let xyz = Point3::from(self.linear.xyz(&self.scales));
        Readings {
            time_s,
            scales: xyz,
            deflection,
            status,
        }
    }
}

/// Whether `d` is exactly the zero vector (every component `+0.0`, as
/// [`SimulatedCmm::contact`] returns when not touching): its sensor
/// reading is then [`TrueProbe::response`] of zero, without noise.
fn is_rest(d: Vec3) -> bool {
    (d.x.to_bits() | d.y.to_bits() | d.z.to_bits()) == 0
}

impl SimulatedCmm<'_> {
    /// The machine's contact search on its true part, kept after the
    /// measuring (for the true deviations, [`crate::evaluate::truth`]).
    pub fn into_contact_search(self) -> ContactSearch {
        self.search
    }

    /// Number of exact collision checks of the shaft and the body so far
    /// (the free-air bound skips the others).
    pub fn collision_checks(&self) -> u64 {
        self.collisions.exact_checks()
    }

    /// The indexing command behind [`Cmm::index_head`].
    fn index(&mut self, angles_rad: &[f64]) -> Result<Vec<f64>, HeadCommandError> {
        let head = self.model.revolute_axes();
        if head.is_empty() {
            return Err(HeadCommandError::NoHead);
        }
        if head.len() != angles_rad.len() {
            let (expected, found) = (head.len(), angles_rad.len());
            return Err(HeadCommandError::Count { expected, found });
        }
        let targets: Vec<(usize, f64)> = head
            .iter()
            .copied()
            .zip(angles_rad.iter().copied())
            .collect();
        self.servo
            .index_to(&targets)
            .map_err(|e| self.refused(e, head.len()))?;
        self.search.reset();
        self.collisions.reset();
        self.update_mount();
        self.last = self.observe(Vec3::zeros(), MachineStatus::Ok);
        let encoders = self.servo.read_scales(&mut self.rng);
        Ok(head
            .iter()
            .filter_map(|&i| encoders.get(i).copied())
            .collect())
    }
}

impl SimulatedCmm<'_> {
    /// The servo's refusal of an indexing command as the seam's error.
    fn refused(&self, e: ServoError, expected: usize) -> HeadCommandError {
        let travel = |index: usize, angle_rad: f64| {
            let axis = self.model.axes().get(index);
            HeadCommandError::Travel {
                axis: axis.map(|a| a.name.clone()).unwrap_or_default(),
                angle_rad,
                lower: axis.map_or(f64::NAN, |a| a.limits.lower),
                upper: axis.map_or(f64::NAN, |a| a.limits.upper),
            }
        };
        match e {
            ServoError::AxisLimit {
                index, position, ..
            } => travel(index, position),
            ServoError::NotFinite { index, value } => travel(index, value),
            ServoError::AxisCount { found, .. } => HeadCommandError::Count { expected, found },
        }
    }
}

impl Cmm for SimulatedCmm<'_> {
    fn head_axes(&self) -> usize {
        self.model.revolute_axes().len()
    }

    fn index_head(&mut self, angles_rad: &[f64]) -> Result<Vec<f64>, HeadCommandError> {
        self.index(angles_rad)
    }

    fn cycle_s(&self) -> f64 {
        self.servo.cycle_s()
    }

    fn readings(&self) -> Readings {
        self.last.clone()
    }

    fn step(&mut self, velocity: Vec3) -> Readings {
        self.linear.to_axes_into(velocity, &mut self.command);
        let status = match self.servo.advance(&self.command) {
            Ok(()) => MachineStatus::Ok,
            Err(ServoError::AxisLimit { axis, position, .. }) => {
                MachineStatus::AxisLimit { axis, position }
            }
            Err(e) => MachineStatus::AxisLimit {
                axis: e.to_string(),
                position: f64::NAN,
            },
        };
        let actual = self.linear.xyz(self.servo.velocity());
        let readings = self.observe(actual, status);
        self.remember(&readings);
        readings
    }
}
