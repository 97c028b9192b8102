//! A ball pressed deep into the part stays on the face it was pressed
//! against.
//!
//! The contact model deflects the stylus by `r - s` along the push of the
//! nearest true surface point (`s` the signed distance of the undeflected
//! ball centre). Once the undeflected centre has gone into the material
//! (`s < 0`, a deflection beyond the ball's radius, as a touch trigger or
//! an overrun on a small ball does), the nearest surface point can jump to
//! another face: on a web thinner than twice the penetration, from the top
//! the ball presses on to a side wall, turning the deflection sideways and
//! shrinking it, though a real stylus has not moved round the web. The
//! held contact continues the penetration along the push it had before
//! the jump, as a plane there would give (exact for a flat face), until
//! the centre comes out of the material or back to that push.
use crate::math::{Point3, Vec3};

/// A jump of the push direction by more than this angle in one control
/// cycle, with the ball centre in the material, is a jump through it:
/// cos(60 deg). A ball rolling round an edge turns its push by a few
/// milliradians a cycle.
pub const JUMP_COS: f64 = 0.5;

/// The contact a deep ball is held to (part frame).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Held {
    /// Undeflected ball centre of the last contact before the jump, mm.
    centre: Point3,
    /// Its signed distance to the true part, mm.
    distance: f64,
    /// Its unit push direction.
    push: Vec3,
}

/// The per-cycle state of a held contact.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PressedContact {
    last: Option<Held>,
    /// Whether `last` is a held contact (the jump happened).
    holding: bool,
}

impl PressedContact {
    /// Forgets the last contact (the ball is in free air).
    pub fn release(&mut self) {
        *self = PressedContact::default();
    }

    /// The signed distance and push the deflection follows for the
    /// undeflected ball centre `centre`, whose nearest true surface point
    /// is at signed distance `distance` along unit push `push` (part
    /// frame, mm): these, or the held contact's continuation after a jump
    /// through the material.
    pub fn follow(&mut self, centre: Point3, distance: f64, push: Vec3) -> (f64, Vec3) {
        if let Some(h) = self.last.filter(|_| distance < 0.0) {
            if push.dot(&h.push) < JUMP_COS {
                self.holding = true;
                return (h.distance + (centre - h.centre).dot(&h.push), h.push);
            }
        }
        self.holding = false;
        self.last = Some(Held {
            centre,
            distance,
            push,
        });
        (distance, push)
    }

    /// The signed distance and push for an undeflected ball centre
    /// `centre` whose nearest true surface point lies beyond the contact
    /// search's reach, when the last contact had the centre in the
    /// material: the last contact's plane continued, while that keeps the
    /// centre in the material. A ball cannot come out of the material by
    /// more than the reach in one cycle, so it went deeper (a crash, the
    /// stylus given way on its protection): a stylus driven on through
    /// the part is not free, whatever lies beyond the search's reach.
    pub fn beyond_reach(&self, centre: Point3) -> Option<(f64, Vec3)> {
        let h = self.last.filter(|h| h.distance < 0.0)?;
        let s = h.distance + (centre - h.centre).dot(&h.push);
        (s < 0.0).then_some((s, h.push))
    }

    /// Whether the last contact followed was a held one.
    pub fn holding(&self) -> bool {
        self.holding
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A web 0.2 mm thick (y in [-0.1, 0.1]) with its top at z = 0: the
    /// signed distance and push of the nearest face of the material
    /// (top or a side wall) for a point inside or above it.
    fn web(p: Point3) -> (f64, Vec3) {
        if p.z >= 0.0 {
            return (p.z, Vec3::z());
        }
        let to_side = 0.1 - p.y.abs();
        let depth = -p.z;
        if to_side < depth {
            (-to_side, Vec3::y() * p.y.signum())
        } else {
            (p.z, Vec3::z())
        }
    }

    #[test]
    fn a_ball_pressed_past_the_web_s_middle_keeps_pressing_on_its_top() {
        let mut c = PressedContact::default();
        let y = 0.045;
        // Down the web from 0.1 above its top to 0.3 into it.
        for k in 0..=40 {
            let centre = Point3::new(0.0, y, 0.1 - 0.01 * k as f64);
            let (s, n) = web(centre);
            let (got, push) = c.follow(centre, s, n);
            // The top plane's signed distance all the way.
            assert!((got - centre.z).abs() < 1e-12, "{k}: {got} at {}", centre.z);
            assert!((push - Vec3::z()).norm() < 1e-12);
            assert_eq!(c.holding(), centre.z < -(0.1 - y), "{k}");
        }
        // Back up: the nearest face is the top again, no longer held.
        let centre = Point3::new(0.0, y, -0.01);
        let (s, n) = web(centre);
        assert_eq!(c.follow(centre, s, n), (s, n));
        assert!(!c.holding());
    }

    /// A ball driven 0.5 mm into a wall (top at z = 0) and on, beyond the
    /// search's reach: the wall's plane goes on (-0.5 - 3 = -3.5 mm); one
    /// that left the material (the plane says outside), or one that was
    /// outside when last found, is free.
    #[test]
    fn a_ball_driven_on_through_the_part_stays_in_it() {
        let mut c = PressedContact::default();
        c.follow(Point3::new(1.0, 0.0, -0.5), -0.5, Vec3::z());
        let deeper = c.beyond_reach(Point3::new(1.0, 2.0, -3.5));
        assert_eq!(deeper, Some((-3.5, Vec3::z())));
        assert_eq!(c.beyond_reach(Point3::new(1.0, 0.0, 4.0)), None);
        c.follow(Point3::new(1.0, 0.0, 0.1), 0.1, Vec3::z());
        assert_eq!(c.beyond_reach(Point3::new(1.0, 0.0, -3.5)), None);
    }

    #[test]
    fn a_ball_on_the_surface_follows_the_nearest_point() {
        let mut c = PressedContact::default();
        let a = c.follow(Point3::new(0.0, 0.0, 0.1), 0.1, Vec3::z());
        assert_eq!(a, (0.1, Vec3::z()));
        // Outside the material a turned push is followed (an edge).
        let b = c.follow(Point3::new(0.0, 0.3, 0.1), 0.05, Vec3::y());
        assert_eq!(b, (0.05, Vec3::y()));
        c.release();
        let d = c.follow(Point3::new(0.0, 0.0, -0.2), -0.05, -Vec3::y());
        assert_eq!(d, (-0.05, -Vec3::y()));
    }
}
