//! Positioning moves and the bookkeeping every mode shares.
//!
//! Moves run at the positioning speed and acceleration of [`ModeOptions`].
//! A move through several waypoints does not stop at the intermediate ones:
//! it slows to a corner speed that keeps each corner's rounding within
//! [`CORNER_BLEND_MM`] and brakes as late as the acceleration allows. A
//! move to a probing start point ends moving towards the surface at the
//! approach speed, so the approach follows without a stop.
use super::{
    approach_standoff, route, Collision, FreeSpace, HostProbe, Measured, ModeOptions, Outcome,
};
use crate::host::observe::{Machine, Phase};
use crate::host::probe_correction::DeflectionCorrection;
use crate::math::{Point3, Vec3};
use crate::seam::{Cmm, MachineStatus, ProbePart, Readings};

mod strike;
mod trail;

/// Follows the machine cycle by cycle: ball centre, deflection, time, and
/// points taken at a pitch.
pub struct Tracker<'f> {
    /// What the host knows about the probe (fixed for the tracker's life).
    probe: HostProbe,
    /// Latest readings.
    pub now: Readings,
    /// Machine time at the start, s.
    pub t0: f64,
    /// Measured points so far.
    pub points: Vec<Measured>,
    /// Ball-centre velocity commanded in the last cycle, mm/s.
    pub command: Vec3,
    /// Velocity the scales moved with in the last cycle, mm/s.
    pub moving: Vec3,
    /// The measured point of the previous cycle sampled.
    prev_point: Option<Point3>,
    /// Length of the measured path since the first point, mm.
    travel: f64,
    /// Where along it the next point is due, mm.
    next_mark: f64,
    /// Whether the probe's deflection correction is not the identity.
    corrected: bool,
    /// What the software is doing (the phase last entered).
    pub phase: Phase,
    /// Where the probe struck the part, once it has.
    pub collision: Option<Collision>,
    /// Free space around the part: repositioning routes around the part
    /// (`None`: over the clearance height unchecked).
    free: Option<&'f dyn FreeSpace>,
    /// How the probe backs out after a collision
    /// ([`ModeOptions::escape`]), below which deflection the stylus is
    /// free ([`ModeOptions::free_mm`]), and the options the way back
    /// after a collision moves with.
    modes: ModeOptions,
    /// The ball's path since the measuring move left free air
    /// ([`trail`]).
    trail: Vec<Point3>,
    /// A retract asked for while the ball still touched the surface it
    /// measured: the phase turns to retract once the stylus is free.
    lift_off: bool,
    /// The measuring move an approach starts ([`Self::enter_approach`]):
    /// the phase turns to it at the cycle that reads the ball on the
    /// surface.
    touch_down: Option<Phase>,
}

impl<'f> Tracker<'f> {
    /// Starts tracking from the machine's current readings.
    pub fn new(cmm: &dyn Cmm, probe: HostProbe) -> Tracker<'f> {
        let now = cmm.readings();
        Tracker {
            probe,
            t0: now.time_s,
            now,
            points: Vec::new(),
            command: Vec3::zeros(),
            moving: Vec3::zeros(),
            prev_point: None,
            travel: 0.0,
            next_mark: 0.0,
            corrected: probe.correction != DeflectionCorrection::identity(),
            phase: Phase::Idle,
            collision: None,
            free: None,
            modes: ModeOptions::default(),
            trail: Vec::new(),
            lift_off: false,
            touch_down: None,
        }
    }

    /// The same, backing out of a collision as `opts` say.
    pub fn escaping(self, opts: &ModeOptions) -> Tracker<'f> {
        Tracker {
            modes: *opts,
            ..self
        }
    }

    /// The same, routing its repositioning moves clear of the part that
    /// `free` describes.
    pub fn avoiding(self, free: Option<&'f dyn FreeSpace>) -> Tracker<'f> {
        Tracker { free, ..self }
    }

    /// The free space the tracker's moves avoid, if any.
    pub fn free(&self) -> Option<&'f dyn FreeSpace> {
        self.free
    }

    /// Enters `phase`: tells the machine's observer and remembers it.
    pub fn enter(&mut self, cmm: &mut dyn Machine, phase: Phase) {
        self.lift_off = false;
        self.touch_down = None;
        match phase {
            // A measuring move leaves free air (one that starts on the
            // surface goes on with the trail it has).
            Phase::Approach | Phase::Touch
                if self.phase != phase && self.deflection() < self.modes.free_mm =>
            {
                self.start_trail(true)
            }
            Phase::Idle | Phase::Position => self.start_trail(false),
            _ => {}
        }
        self.phase = phase;
        cmm.note_phase(phase);
    }

    /// Enters the approach of the measuring move `then` (a scan): from the
    /// cycle that reads the ball on the surface (a deflection of
    /// [`ModeOptions::strike_mm`], as a move between measurements would
    /// call a strike) the phase is `then`, and the approach's cycles since
    /// the ball first read a deflection are its first (a touch's approach
    /// is phase `touch` throughout): an approach's cycles read none.
    pub fn enter_approach(&mut self, cmm: &mut dyn Machine, then: Phase) {
        self.enter(cmm, Phase::Approach);
        self.touch_down = Some(then);
    }

    /// Ends a measuring move: the phase turns to retract once the stylus
    /// is free. The ball's stop on the surface (the axes brake after a
    /// touch's trigger, pressing the stylus on by a few hundredths) and its
    /// lift off it belong to the measuring move; the retract is the move
    /// away in free air.
    pub fn retract_from_surface(&mut self, cmm: &mut dyn Machine) {
        // A tracker that starts on the surface (idle) took over from the
        // measuring move that put the ball there.
        let measuring = !matches!(self.phase, Phase::Position | Phase::Retract);
        if measuring && self.deflection() >= self.modes.free_mm {
            self.lift_off = true;
        } else {
            self.enter(cmm, Phase::Retract);
        }
    }

    /// Records a collision of `probe_part` at `at` (machine, mm) in the
    /// current phase and returns its outcome.
    pub fn struck(&mut self, probe_part: ProbePart, at: Point3, speed_mm_s: f64) -> Outcome {
        let phase = self.phase;
        // The first strike is the one reported (a retrace that runs into
        // the part again stops there).
        if self.collision.is_some() {
            return Outcome::Collision;
        }
        self.collision = Some(Collision {
            probe_part,
            at,
            speed_mm_s,
            phase,
        });
        Outcome::Collision
    }

    /// Undeflected ball centre from the scales, machine coordinates.
    pub fn ball_undeflected(&self) -> Point3 {
        self.now.scales + self.probe.probe_vector
    }

    /// The ball radius the host knows, mm.
    pub fn probe_radius(&self) -> f64 {
        self.probe.tip_radius_mm
    }

    /// Deflection magnitude, mm.
    pub fn deflection(&self) -> f64 {
        self.now.deflection.norm()
    }

    /// The measured point now, if the stylus is deflected.
    /// Ball and normal use the probe's deflection correction.
    pub fn measured(&self) -> Option<Measured> {
        let (scales, reading, motion) = (self.now.scales, self.now.deflection, self.command);
        if self.corrected {
            self.probe.locate(scales, reading, motion)
        } else {
            self.probe.locate_uncorrected(scales, reading, motion)
        }
    }

    /// Steps the machine and returns an outcome if it halted. A collision
    /// the machine reports is recorded and the probe backed out of the
    /// part ([`Self::escape`]).
    pub fn step(&mut self, cmm: &mut dyn Machine, v: Vec3) -> Option<Outcome> {
        let before = self.now.scales;
        self.now = cmm.step(v);
        self.command = v;
        self.moving = (self.now.scales - before) / cmm.cycle_s();
        if !self.trail.is_empty() {
            self.extend_trail();
        }
        if self.lift_off && self.deflection() < self.modes.free_mm {
            self.enter(cmm, Phase::Retract);
        }
        if let Some(then) = (self.touch_down).filter(|_| self.deflection() >= self.modes.strike_mm)
        {
            self.touch_down = None;
            self.phase = then;
            cmm.note_contact(then);
        }
        match self.now.status {
            MachineStatus::Ok => None,
            MachineStatus::AxisLimit { .. } => Some(Outcome::AxisLimit),
            MachineStatus::ProbeOverrange { .. } => Some(Outcome::OverDeflection),
            MachineStatus::Collision {
                probe_part,
                at,
                speed_mm_s,
            } => {
                let outcome = self.struck(probe_part, at, speed_mm_s);
                let strike = (probe_part != ProbePart::Ball).then_some(at);
                self.escape(cmm, self.moving, strike);
                self.retrace(cmm);
                Some(outcome)
            }
        }
    }

    /// After a measuring move that stopped short with the ball in the
    /// design's material (its centre inside, or nearer the design's
    /// surface than its radius: the true part lies off the design, and
    /// the move went on through where the design has material, as an
    /// approach that finds no surface does), backs out the way it came:
    /// off the surface it touches, if it still does ([`Self::escape`]),
    /// then back along its path to where it left free air (a free ball,
    /// as after a scan that lost its surface and ran on, goes straight
    /// back along the path: an escape would head back the way it came
    /// unlifted, into the surface it lost). Routes start there; from inside
    /// the design none would.
    pub fn back_out_of_design(&mut self, cmm: &mut dyn Machine) {
        let (b, r) = (self.ball_undeflected(), self.probe_radius());
        let inside = self
            .free
            .is_some_and(|f| f.in_material(b) || f.design_foot(b).is_some_and(|(s, _)| s < r));
        if inside && self.has_trail() {
            if self.deflection() >= self.modes.free_mm {
                let moving = self.moving;
                self.escape(cmm, moving, None);
            }
            self.retrace(cmm);
        }
    }

    /// Backs the probe out of the part after a collision: along the
    /// stylus's deflection when it is pressed against the part (away from
    /// the surface the ball struck), else against `moving` (the machine's
    /// velocity when it struck, mm/s; up the stylus when it stood still);
    /// after a strike of the shaft or the body at `strike` (machine
    /// coordinates) in a scan, away from it across the stylus as well
    /// ([`strike::out_of_strike`]). At
    /// [`EscapeOptions::speed_mm_s`](super::EscapeOptions::speed_mm_s),
    /// whatever the machine reports on the way (but a ball pressed
    /// [`EscapeOptions::press_mm`](super::EscapeOptions::press_mm) harder
    /// than when the move out began, once the machine no longer runs on
    /// from the strike, backs off along its deflection instead: the way
    /// out ran into the part), until it reports the probe
    /// clear with the stylus free, [`EscapeOptions::clear_mm`](super::EscapeOptions::clear_mm) further and
    /// (with free space to ask) the tight clearance margin from the design
    /// data, then to rest; during a measuring move, only
    /// [`EscapeOptions::retrace_clear_mm`](super::EscapeOptions::retrace_clear_mm) further, and then back along the
    /// move's path to where it left free air ([`trail`]). A stylus pressed
    /// against the part in a move that does not measure comes free along
    /// its deflection, [`EscapeOptions::retrace_clear_mm`](super::EscapeOptions::retrace_clear_mm) further, and
    /// then backs out up the stylus (routes come in from above). Gives up
    /// after [`EscapeOptions::max_mm`](super::EscapeOptions::max_mm), and
    /// stops where the stylus, once free, touches the part again (backing
    /// out of a small hole towards its far wall): the probe is not driven
    /// on through the part.
    pub fn escape(&mut self, cmm: &mut dyn Machine, moving: Vec3, strike: Option<Point3>) {
        // Off the surface the stylus is pressed against, if it is; else
        // back the way it came; off a struck shaft or body, away from it.
        let up = (-self.probe.probe_vector).try_normalize(1e-9);
        let pressed = (self.now.deflection.try_normalize(1e-9))
            .filter(|_| self.deflection() >= self.modes.free_mm);
        // A scan runs along the part, so back the way it came runs along
        // it too; any other move came from free air the way it leads back.
        let scanning = matches!(self.phase, Phase::Scan | Phase::Autonomous);
        let away = (strike.filter(|_| scanning).zip(up))
            .and_then(|(at, up)| strike::off_the_strike(self.ball_undeflected(), up, at));
        let dir = match away {
            Some(a) => Some(strike::out_of_strike(a, pressed)),
            None => pressed.or((-moving).try_normalize(1e-9)).or(up),
        };
        let Some(dir) = dir else {
            return;
        };
        // Coming free off the surface the ball was measuring belongs to the
        // measuring move (as its lift-off does); the retract starts free.
        let measuring = !matches!(self.phase, Phase::Position | Phase::Retract);
        let mut lifting = measuring && pressed.is_some();
        if !lifting {
            self.enter(cmm, Phase::Retract);
        }
        let mut v = dir * self.modes.escape.speed_mm_s;
        // Once free off a pressed stylus, up the stylus (out of a hole the
        // way routes come in, from above): on along the deflection, or back
        // along a move inside a small hole, its far wall is near.
        let back = up
            .or((-moving).try_normalize(1e-9))
            .filter(|_| pressed.is_some());
        let mut turned = false;
        let start = self.ball_undeflected();
        let mut clear_since: Option<Point3> = None;
        let mut pressed_at = self.deflection().max(self.modes.free_mm);
        // Twice the cycles the longest move out takes at its speed.
        let cycles =
            2.0 * self.modes.escape.max_mm / (self.modes.escape.speed_mm_s * cmm.cycle_s());
        for _ in 0..(cycles.min(1e7) as usize) {
            if (self.ball_undeflected() - start).norm() >= self.modes.escape.max_mm {
                break;
            }
            let before = self.ball_undeflected();
            self.now = cmm.step(v);
            self.command = v;
            if lifting && self.deflection() < self.modes.free_mm {
                lifting = false;
                self.enter(cmm, Phase::Retract);
            }
            let here = self.ball_undeflected();
            if !scanning && (here - before).dot(&v) <= 0.0 {
                // Still carried on into the part by the move that struck:
                // pressing harder is its run-on, not the way out.
                pressed_at = pressed_at.max(self.deflection());
            }
            let pressing = self.deflection() > pressed_at + self.modes.escape.press_mm;
            if clear_since.is_none() && pressing {
                // The way out runs into the part (along a scanned surface,
                // or across a hole the ball all but fills to its far
                // wall): off it instead.
                pressed_at = self.deflection();
                if let Some(d) = self.now.deflection.try_normalize(1e-9) {
                    v = d * self.modes.escape.speed_mm_s;
                }
            }
            match self.now.status {
                MachineStatus::AxisLimit { .. } => break,
                MachineStatus::Ok if self.deflection() < self.modes.free_mm => {
                    let since = *clear_since.get_or_insert(here);
                    let gone = (here - since).norm();
                    // With a trail to go back along, just off the surface
                    // (across a small hole the far wall is near).
                    if self.has_trail() && gone >= self.modes.escape.retrace_clear_mm {
                        break;
                    }
                    if let Some(b) =
                        back.filter(|_| !turned && gone >= self.modes.escape.retrace_clear_mm)
                    {
                        (v, turned) = (b * self.modes.escape.speed_mm_s, true);
                        clear_since = Some(here);
                        continue;
                    }
                    if gone >= self.modes.escape.clear_mm && self.roomy(here) {
                        break;
                    }
                }
                _ if clear_since.is_some() => break,
                _ => {}
            }
        }
        self.come_to_rest(cmm);
    }

    /// Whether the probe with its ball centre at `here` keeps the tight
    /// clearance margin from the part (the design data's free space; true
    /// without one), so that routes from here can be planned.
    fn roomy(&self, here: Point3) -> bool {
        self.free
            .is_none_or(|f| f.segment_clear_with(here, here, true))
    }

    /// Commands zero velocity until the scales stop moving (at most
    /// [`REST_CYCLES`] cycles).
    pub(crate) fn come_to_rest(&mut self, cmm: &mut dyn Machine) {
        for _ in 0..REST_CYCLES {
            let before = self.now.scales;
            self.now = cmm.step(Vec3::zeros());
            self.command = Vec3::zeros();
            if (self.now.scales - before).norm() < ARRIVED_SPEED_MM_S * cmm.cycle_s() {
                break;
            }
        }
    }

    /// Records the current point when its cycle is the one nearest to the
    /// next multiple of `pitch` along the measured path (the sum of the
    /// measured point's moves from cycle to cycle since the first point):
    /// points lie `pitch` apart on average, each within half a cycle's
    /// travel of it.
    pub fn sample(&mut self, pitch: f64) {
        let Some(m) = self.measured() else {
            self.prev_point = None;
            return;
        };
        let step = self
            .prev_point
            .replace(m.point)
            .map_or(0.0, |q| (m.point - q).norm());
        self.travel += step;
        // How far the next mark lies ahead; the next cycle (one more step
        // like this one) would overshoot it by `step - ahead`.
        let ahead = self.next_mark - self.travel;
        if self.points.is_empty() || ahead <= 0.5 * step {
            self.points.push(m);
            self.next_mark = (self.next_mark + pitch).max(self.travel + 0.5 * pitch);
        }
    }

    /// Machine time since the start, s.
    pub fn elapsed(&self) -> f64 {
        self.now.time_s - self.t0
    }
}

/// Proportional gain of the last millimetre of a positioning move, 1/s
/// (below `1 / (4 lag)`, the critical gain of a 5 ms servo lag).
const POSITION_GAIN: f64 = 50.0;

/// Share of the positioning acceleration used for planned braking; the
/// rest is margin for the servo lag.
const BRAKE_SHARE: f64 = 0.8;

/// Largest distance by which a blended move cuts a corner, mm.
const CORNER_BLEND_MM: f64 = 1.0;

/// The clearance margin a blended route needs, mm: the corner it cuts
/// ([`CORNER_BLEND_MM`]) and the servo's following error carrying a fast
/// move on past it (under a millimetre at the rapid speed). A route
/// checked with a smaller margin (a small part's program) stops at each
/// of its corners instead.
const BLEND_ROOM_MM: f64 = 2.0;

/// Within this distance of a waypoint the move turns to the next one, mm.
const WAYPOINT_PASS_MM: f64 = 1.0;

/// Below this commanded speed a move that ends at rest has arrived, mm/s.
const ARRIVED_SPEED_MM_S: f64 = 1.0;

/// Most cycles [`Tracker::come_to_rest`] waits for the machine to stop.
const REST_CYCLES: usize = 2000;

/// How far outside the target point a repositioning move comes down, mm.
const REPOSITION_OUTSIDE_MM: f64 = 15.0;

/// Moves the undeflected ball centre to `target` in a straight line at up
/// to `speed`, stopping at rest within [`ModeOptions::arrive_tol_mm`].
pub fn move_to(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    target: Point3,
    speed: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    straight(cmm, tr, (target, speed), Phase::Position, opts)
}

/// A straight move to `target` at up to `speed`, ending at rest, in `phase`.
fn straight(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    (target, speed): (Point3, f64),
    phase: Phase,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    tr.enter(cmm, phase);
    travel(cmm, tr, &[target], speed, 0.0, opts)
}

/// Moves through `waypoints` without stopping at the intermediate ones
/// (corner speeds limited, braking only where needed), ending at rest on
/// the last.
pub fn move_through(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    waypoints: &[Point3],
    speed: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    tr.enter(cmm, Phase::Position);
    travel(cmm, tr, waypoints, speed, 0.0, opts)
}

/// Moves to `target` between measurements, arriving along `approach`
/// (the outward direction at the target) and still moving towards the
/// surface at the approach speed, so the caller's approach follows
/// without a stop: first free the stylus if it is touching, then up to the
/// clearance height, across to a point outside the target, down, and in
/// (straight when no clearance height is set or the target is near), all
/// in one blended move.
pub fn reposition(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    target: Point3,
    approach: Vec3,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let from = tr.ball_undeflected();
    let away = free_stylus(cmm, tr, opts)?;
    tr.enter(cmm, Phase::Position);
    let here = away.unwrap_or_else(|| tr.ball_undeflected());
    let mut waypoints: Vec<Point3> = away.into_iter().collect();
    // Backed off by less than the standoff (a small hole): no room to
    // blend the turn, so the probe stops there first.
    let tight = away.is_some_and(|a| (a - from).norm() < opts.standoff_mm - opts.arrive_tol_mm);
    if tight {
        travel(cmm, tr, &waypoints, opts.rapid_speed_mm_s, 0.0, opts)?;
    }
    match tr.free {
        Some(free) => {
            let route =
                route::plan_route_from(free, (here, tr.probe.probe_vector), target, approach, opts);
            let route = route.ok_or(Outcome::Blocked)?;
            free.note_way(here, &route.waypoints);
            waypoints.extend(route.waypoints);
            let roomy = free.margin_mm().is_none_or(|m| m >= BLEND_ROOM_MM);
            if route.tight || !roomy {
                return travel_stopping(cmm, tr, &waypoints, opts);
            }
        }
        None => {
            waypoints.extend(detour(here, target, approach, opts));
            waypoints.push(target);
        }
    }
    let end_speed = if comes_in_along(here, &waypoints, approach) {
        opts.approach_speed_mm_s
    } else {
        0.0
    };
    travel(cmm, tr, &waypoints, opts.rapid_speed_mm_s, end_speed, opts)
}

/// A move may run on into the approach only when its last leg comes in
/// along the approach: cos(10 deg). Arriving sideways at the approach
/// speed, the servo's following error and braking would carry the ball
/// sideways past the start of the approach (by about 0.1 mm at 10 mm/s),
/// off a small face or over its edge; such a move ends at rest.
const ALONG_APPROACH_COS: f64 = 0.984_807_753_012_208;

/// Whether the last leg of the move from `here` through `waypoints` comes
/// in along `-approach`.
fn comes_in_along(here: Point3, waypoints: &[Point3], approach: Vec3) -> bool {
    let (from, to) = match waypoints {
        [.., a, b] => (*a, *b),
        [b] => (here, *b),
        [] => return true,
    };
    (to - from)
        .try_normalize(1e-9)
        .is_none_or(|d| d.dot(&-approach) >= ALONG_APPROACH_COS)
}

/// A route whose legs are clear with the tight margin only: each leg to
/// rest at its end (a blended corner cuts up to [`CORNER_BLEND_MM`] and
/// the servo lag carries a fast move further past it, more than that
/// margin allows), the last one ending towards the surface at the approach
/// speed.
fn travel_stopping(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    waypoints: &[Point3],
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let Some((last, legs)) = waypoints.split_last() else {
        return Ok(());
    };
    for w in legs {
        travel(cmm, tr, &[*w], opts.rapid_speed_mm_s, 0.0, opts)?;
    }
    let approach = opts.approach_speed_mm_s;
    travel(cmm, tr, &[*last], opts.rapid_speed_mm_s, approach, opts)
}

/// Moves the undeflected ball centre to `target` in a straight line at up
/// to `speed` as part of an approach: contact on the way is expected (a
/// passive scan's start lies inside the surface by the deflection).
pub fn approach_to(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    target: Point3,
    speed: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    tr.enter_approach(cmm, Phase::Scan);
    travel(cmm, tr, &[target], speed, 0.0, opts)
}

/// Waypoints over the clearance height from `here` to the point outside
/// `target` (none when no clearance height is set or `target` is near).
fn detour(here: Point3, target: Point3, approach: Vec3, opts: &ModeOptions) -> Vec<Point3> {
    let Some(z) = opts.clearance_z_mm else {
        return Vec::new();
    };
    if (here - target).norm() <= opts.standoff_mm {
        return Vec::new();
    }
    let outside = target + approach * REPOSITION_OUTSIDE_MM;
    let top = z.max(here.z);
    let mut out = Vec::new();
    if (here.xy() - outside.xy()).norm() > opts.arrive_tol_mm {
        out.push(Point3::new(here.x, here.y, top));
        out.push(Point3::new(outside.x, outside.y, top));
    }
    out.push(outside);
    out
}

/// Backs the stylus off the part along its deflection until it is free,
/// then by the standoff at positioning speed.
pub fn recover(cmm: &mut dyn Machine, tr: &mut Tracker, opts: &ModeOptions) -> Result<(), Outcome> {
    match free_stylus(cmm, tr, opts)? {
        Some(away) => move_to(cmm, tr, away, opts.rapid_speed_mm_s, opts),
        None => Ok(()),
    }
}

/// Backs the stylus off along its deflection at the approach speed until
/// it is free; returns the point one standoff further out, or less where
/// the probe would not fit ([`approach_standoff`]: a small hole), `None`
/// when it was free already. The direction follows the deflection once
/// that turns from it by more than [`FREE_TURN_COS`]: a ball held in a
/// corner, leaving one face, then backs off the other rather than sliding
/// along it, and the standoff runs along the sum of the directions
/// followed. Gives up ([`Outcome::Aborted`]) after
/// [`ModeOptions::free_travel_mm`] without coming free.
pub(super) fn free_stylus(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    opts: &ModeOptions,
) -> Result<Option<Point3>, Outcome> {
    let Some(mut dir) = tr.now.deflection.try_normalize(1e-9) else {
        return Ok(None);
    };
    tr.retract_from_surface(cmm);
    let start = tr.ball_undeflected();
    // The directions followed, summed: out of a corner the standoff runs
    // between the faces' normals.
    let mut followed = dir;
    for _ in 0..opts.max_cycles {
        let here = tr.ball_undeflected();
        if tr.deflection() < opts.free_mm {
            dir = followed.try_normalize(1e-9).unwrap_or(dir);
            return Ok(Some(
                here + dir * approach_standoff(tr.free, here, dir, opts),
            ));
        }
        if (here - start).norm() > opts.free_travel_mm {
            return Err(Outcome::Aborted);
        }
        if let Some(now) = tr.now.deflection.try_normalize(1e-9) {
            if now.dot(&dir) < FREE_TURN_COS {
                dir = now;
                followed += now;
            }
        }
        if let Some(o) = tr.step(cmm, dir * opts.approach_speed_mm_s) {
            if o != Outcome::OverDeflection {
                return Err(o);
            }
        }
    }
    Err(Outcome::Aborted)
}

/// The deflection turned from the direction a stylus is backed off along
/// by more than this (cos 30 degrees) is followed instead.
const FREE_TURN_COS: f64 = 0.866_025_403_784_438_6;

/// The blended move behind [`move_through`] and [`reposition`]: through
/// `waypoints` at up to `speed`, ending on the last at `end_speed` (at rest
/// within the arrival tolerance when 0; otherwise still moving along the
/// last leg). Starts from the velocity last commanded through `tr`.
pub(super) fn travel(
    cmm: &mut dyn Machine,
    tr: &mut Tracker,
    waypoints: &[Point3],
    speed: f64,
    end_speed: f64,
    opts: &ModeOptions,
) -> Result<(), Outcome> {
    let a = opts.rapid_accel_mm_s2;
    let pv = tr.probe.probe_vector;
    let inside: Vec<Point3> = (waypoints.iter())
        .map(|&w| inside_travel(w - pv, opts) + pv)
        .collect();
    let waypoints = inside.as_slice();
    let start = tr.ball_undeflected();
    let corners = corner_speeds(start, waypoints, speed, end_speed, a);
    let max_dv = a * cmm.cycle_s();
    let mut v_prev = tr.command;
    let mut k = 0;
    let mut guard = Guard::new(tr, opts);
    for _ in 0..opts.max_cycles {
        let here = tr.ball_undeflected();
        while k + 1 < waypoints.len() && passed(here, start, waypoints, k) {
            k += 1;
        }
        let (Some(&w), Some(ahead)) = (waypoints.get(k), waypoints.get(k..)) else {
            return Ok(());
        };
        let err = w - here;
        let leg = leg_direction(start, waypoints, k).unwrap_or(err);
        if k + 1 == waypoints.len() && arrived(err, (v_prev, leg), end_speed, cmm.cycle_s(), opts) {
            return Ok(());
        }
        let limit = speed_limit(here, ahead, corners.get(k..).unwrap_or(&[]), speed, a);
        let want = along_leg(err, leg, limit.max(end_speed), a);
        let want = within_travel(want, tr.now.scales, v_prev, opts);
        // The travel's envelope holds whatever the acceleration budget
        // left for each axis (a blended corner spends it sideways).
        let v = v_prev + budgeted(want - v_prev, leg, max_dv);
        let v = within_travel(v, tr.now.scales, v_prev, opts);
        if let Some(o) = tr.step(cmm, v) {
            return Err(o);
        }
        guard.check(cmm, tr, opts)?;
        v_prev = v;
    }
    Err(Outcome::Aborted)
}

/// Whether the move at `here` is done with waypoint `k` (of the move from
/// `start` through `waypoints`): within [`WAYPOINT_PASS_MM`] of it, or
/// past it along its leg (a blended corner that swung wide of it).
fn passed(here: Point3, start: Point3, waypoints: &[Point3], k: usize) -> bool {
    let Some(w) = waypoints.get(k) else {
        return true;
    };
    let beyond = leg_direction(start, waypoints, k).is_some_and(|d| (here - w).dot(&d) >= 0.0);
    (w - here).norm() <= WAYPOINT_PASS_MM || beyond
}

/// The unit direction of the leg that ends at waypoint `k` (from `start`
/// for the first), `None` for a leg of no length.
fn leg_direction(start: Point3, waypoints: &[Point3], k: usize) -> Option<Vec3> {
    let from = match k {
        0 => start,
        _ => *waypoints.get(k - 1)?,
    };
    (waypoints.get(k)? - from).try_normalize(1e-9)
}

/// The velocity wanted `err` before the end of a leg running along the
/// unit `leg`: `speed` along the leg towards its end, and back onto the
/// leg's line across it (at the proportional gain, no faster than the
/// acceleration `a` can stop over the distance), so that the ball follows
/// the route the clearance checks passed rather than swinging round the
/// waypoint it aims at.
fn along_leg(err: Vec3, leg: Vec3, speed: f64, a: f64) -> Vec3 {
    let Some(leg) = leg.try_normalize(1e-12) else {
        return Vec3::zeros();
    };
    let along = err.dot(&leg);
    let across = err - leg * along;
    let off = across.norm();
    let back = (POSITION_GAIN * off).min((2.0 * BRAKE_SHARE * a * off).sqrt());
    let sideways = across
        .try_normalize(1e-12)
        .map_or(Vec3::zeros(), |u| u * back);
    leg * (speed * along.signum()) + sideways
}

/// The velocity change `dv` within the budget `max_dv` (mm/s a cycle),
/// its part across the unit `leg` first: the speed that would carry the
/// ball off the leg's line goes before any gain along it.
fn budgeted(dv: Vec3, leg: Vec3, max_dv: f64) -> Vec3 {
    let Some(leg) = leg.try_normalize(1e-12) else {
        return dv * (max_dv / dv.norm().max(max_dv));
    };
    let along = leg * dv.dot(&leg);
    let across = dv - along;
    let n = across.norm();
    if n >= max_dv {
        return across * (max_dv / n);
    }
    let left = (max_dv * max_dv - n * n).sqrt();
    across + along * (left / along.norm().max(left))
}

/// How long the machine's axes may lag behind the commanded positions,
/// s: the distance they still travel at a speed `v` after the command
/// stops is taken as `v` times this on top of the braking distance (a
/// servo's following error; the simulated servo's lag is 5 ms).
const FOLLOWING_ALLOWANCE_S: f64 = 0.01;

/// `want` with each axis's speed towards an end of the travel
/// ([`ModeOptions::travel_mm`]) no more than the positioning
/// acceleration can stop before it: a move to a clearance height near the
/// top of the travel, blended into the next leg, does not overshoot into
/// the limit. `scales` are the axes' readings, `v` the velocity last
/// commanded.
fn within_travel(want: Vec3, scales: Point3, v: Vec3, opts: &ModeOptions) -> Vec3 {
    let Some((lo, hi)) = soft_travel(opts) else {
        return want;
    };
    let a = BRAKE_SHARE * opts.rapid_accel_mm_s2;
    let mut out = want;
    for k in 0..3 {
        let lag = v[k].abs() * FOLLOWING_ALLOWANCE_S;
        let up = (2.0 * a * (hi[k] - scales[k] - lag).max(0.0)).sqrt();
        let down = (2.0 * a * (scales[k] - lo[k] - lag).max(0.0)).sqrt();
        out[k] = want[k].clamp(-down, up);
    }
    out
}

/// The travel less [`ModeOptions::soft_limit_mm`] at each end, if known.
fn soft_travel(opts: &ModeOptions) -> Option<([f64; 3], [f64; 3])> {
    let m = opts.soft_limit_mm;
    opts.travel_mm
        .map(|(lo, hi)| (lo.map(|x| x + m), hi.map(|x| x - m)))
}

/// `mount` (the axes' position, machine coordinates) moved inside the
/// soft travel: a waypoint the braking would never let the axes reach
/// (a clearance height at the very top of the travel) is reached where
/// they stop.
fn inside_travel(mount: Point3, opts: &ModeOptions) -> Point3 {
    let Some((lo, hi)) = soft_travel(opts) else {
        return mount;
    };
    Point3::from(Vec3::from_fn(|k, _| {
        mount[k].clamp(lo[k], hi[k].max(lo[k]))
    }))
}

/// The ball's collision watch of a move that does not measure: once the
/// stylus is free (at the start, or after backing off a surface), any
/// deflection above [`ModeOptions::strike_mm`] is a collision of the ball.
/// Approaches (contact expected) are not watched.
struct Guard {
    free: bool,
}

impl Guard {
    fn new(tr: &Tracker, opts: &ModeOptions) -> Guard {
        Guard {
            free: tr.deflection() < opts.strike_mm,
        }
    }

    fn check(
        &mut self,
        cmm: &mut dyn Machine,
        tr: &mut Tracker,
        opts: &ModeOptions,
    ) -> Result<(), Outcome> {
        let touching = tr.deflection() >= opts.strike_mm;
        // Watched from the cycle a lift-off turns into a retract.
        let watching = matches!(tr.phase, Phase::Position | Phase::Retract);
        if watching && self.free && touching {
            let at = tr.measured().map_or(tr.ball_undeflected(), |m| m.point);
            // The speed the axes struck with (the scales' move over the
            // last cycle), not the one commanded.
            let moving = tr.moving;
            let outcome = tr.struck(ProbePart::Ball, at, moving.norm());
            tr.escape(cmm, moving, None);
            return Err(outcome);
        }
        self.free |= !touching;
        Ok(())
    }
}

/// Whether a move with the last waypoint `err` away, the velocity `v`
/// last commanded and the last leg's direction `leg`, has ended: one that
/// ends moving, within a cycle's travel of it or past it along the leg
/// (not against the velocity, which at the start of a leg is what is
/// left of the leg before, turned away from it).
fn arrived(err: Vec3, (v, leg): (Vec3, Vec3), end_speed: f64, dt: f64, opts: &ModeOptions) -> bool {
    if end_speed > 0.0 {
        let passed = err.norm() <= WAYPOINT_PASS_MM && err.dot(&leg) < 0.0;
        err.norm() <= (end_speed * dt).max(opts.arrive_tol_mm) || passed
    } else {
        err.norm() <= opts.arrive_tol_mm && v.norm() < ARRIVED_SPEED_MM_S
    }
}

/// Speed allowed now: the braking curves to every corner ahead and to the
/// end, and a proportional approach to the end.
fn speed_limit(here: Point3, ahead: &[Point3], corners: &[f64], speed: f64, a: f64) -> f64 {
    let a_brake = BRAKE_SHARE * a;
    let mut dist = 0.0;
    let mut prev = here;
    let mut limit = speed;
    for (w, &vc) in ahead.iter().zip(corners) {
        dist += (w - prev).norm();
        prev = *w;
        limit = limit.min((vc * vc + 2.0 * a_brake * dist).sqrt());
    }
    let end = corners.last().copied().unwrap_or(0.0);
    limit.min(end + POSITION_GAIN * dist)
}

/// Speed at each waypoint: limited by the turn there (the corner is cut by
/// at most [`CORNER_BLEND_MM`]), `end_speed` at the last.
fn corner_speeds(
    start: Point3,
    waypoints: &[Point3],
    speed: f64,
    end_speed: f64,
    a: f64,
) -> Vec<f64> {
    let n = waypoints.len();
    (0..n)
        .map(|k| {
            if k + 1 == n {
                return end_speed;
            }
            let before = if k == 0 {
                Some(&start)
            } else {
                waypoints.get(k - 1)
            };
            let turn = match (before, waypoints.get(k), waypoints.get(k + 1)) {
                (Some(b), Some(w), Some(c)) => {
                    let (u, v) = (w - b, c - w);
                    u.try_normalize(1e-9).zip(v.try_normalize(1e-9))
                }
                _ => None,
            };
            match turn {
                Some((u, v)) => {
                    let half_sin = ((u - v).norm() / 2.0).max(1e-9);
                    // The turn shares the acceleration between braking the
                    // old direction and speeding up in the new one.
                    speed.min((a * CORNER_BLEND_MM / (2.0 * half_sin)).sqrt())
                }
                None => speed,
            }
        })
        .collect()
}
