//! The per-cycle collision check of the probe beyond the ball: the stylus
//! shaft and the probe body against the true part (see
//! [`super::contact`] for how each is checked).
//!
//! The shaft runs along the actual mount-to-ball vector (turned with a
//! probe head) from where it leaves the ball, `sqrt(r^2 - rs^2)` from the
//! ball centre, to the mount, and moves with the ball's deflection (a
//! scanning probe's stylus moves as a whole); the body runs from the
//! mount on, away from the ball, and does not. The shaft is checked
//! first.
use super::cmm::TruePart;
use super::contact::{
    CollisionOptions, ContactOptions, ContactSearch, Cylinder, PartCheck, PartIndex, Strike,
};
use super::probe::{ProbeShape, TrueProbe};
use crate::geometry::{ProjectionError, ProjectionOptions};
use crate::math::{Point3, Vec3};
use crate::seam::ProbePart;

/// The stylus as mounted (fixed while the head is locked), machine
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stylus {
    /// The mount-to-ball vector, mm.
    pub to_ball: Vec3,
    /// The unit vector from the ball to the mount.
    pub up: Vec3,
}

impl Stylus {
    /// The stylus of the mount-to-ball vector `to_ball` (along -z when it
    /// has no length).
    pub fn new(to_ball: Vec3) -> Stylus {
        Stylus {
            to_ball,
            up: (-to_ball).try_normalize(1e-12).unwrap_or(Vec3::z()),
        }
    }
}

/// The collision checks of one simulated probe.
#[derive(Debug, Clone)]
pub struct ProbeCollisions {
    shape: ProbeShape,
    /// How far from the ball centre the shaft leaves the ball, mm.
    lift_mm: f64,
    shaft: PartCheck,
    body: PartCheck,
}

impl ProbeCollisions {
    /// The checks of `probe`'s shaft and body.
    pub fn new(
        probe: &TrueProbe,
        contact: &ContactOptions,
        opts: &CollisionOptions,
    ) -> ProbeCollisions {
        let (r, rs) = (probe.tip_radius_mm, probe.shape.shaft_radius_mm);
        ProbeCollisions {
            shape: probe.shape,
            lift_mm: (r * r - rs * rs).max(0.0).sqrt(),
            shaft: PartCheck::new(contact, opts),
            body: PartCheck::new(contact, opts).with_caps(),
        }
    }

    /// Forgets what earlier checks learnt (after the head turned).
    pub fn reset(&mut self) {
        self.shaft.reset();
        self.body.reset();
    }

    /// Number of exact checks run so far (shaft and body).
    pub fn exact_checks(&self) -> u64 {
        self.shaft.exact_checks() + self.body.exact_checks()
    }

    /// The probe part in the material and where it strikes (part frame),
    /// for the undeflected ball centre `ball`, the true deflection `d` and
    /// the stylus (machine coordinates, mm).
    #[inline(always)]
    pub fn check(
        &mut self,
        (search, part): (&ContactSearch, &TruePart<'_>),
        (ball, d, stylus): (Point3, Vec3, &Stylus),
        opts: &ProjectionOptions,
    ) -> Option<(ProbePart, Strike)> {
        let (mount, up) = (ball - stylus.to_ball, stylus.up);
        let shaft = (ball + d + up * self.lift_mm, mount + d);
        let body = (mount, mount + up * self.shape.body_length_mm);
        let (rs, rb) = (self.shape.shaft_radius_mm, self.shape.body_radius_mm);
        let shaft_may = self.shaft.may_touch(shaft.0, shaft.1);
        let body_may = self.body.may_touch(body.0, body.1);
        if !(shaft_may || body_may) {
            return None;
        }
        let ix = search.index();
        if shaft_may {
            let hit = run(&mut self.shaft, (ix, part), shaft, rs, opts);
            if let Ok(Some(s)) = hit {
                return Some((ProbePart::Shaft, s));
            }
        }
        if body_may {
            let hit = run(&mut self.body, (ix, part), body, rb, opts);
            if let Ok(Some(s)) = hit {
                return Some((ProbePart::Body, s));
            }
        }
        None
    }
}

/// The exact check of the cylinder of `radius` round `ends` (machine
/// coordinates) on the part.
#[inline(never)]
fn run(
    check: &mut PartCheck,
    (ix, part): (&PartIndex, &TruePart<'_>),
    ends: (Point3, Point3),
    radius: f64,
    opts: &ProjectionOptions,
) -> Result<Option<Strike>, ProjectionError> {
    let (a, b) = (part.pose.to_part(ends.0), part.pose.to_part(ends.1));
    let Some(cyl) = Cylinder::between(a, b, radius) else {
        return Ok(None);
    };
    let wp = (part.workpiece, part.as_machined);
    check.check((ix, wp), &cyl, ends, opts)
}
