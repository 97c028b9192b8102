//! When a plane section's scan starts recording: once the measured point
//! has settled in the section plane.
//!
//! An approach along the design normal ends off the plane by the true
//! surface's offset times the normal's slope across it; the plane hold
//! takes that out within a few pitches, swinging past the plane on the
//! way (a sphere 0.02 mm oversize, cut 40 degrees from its surface: 4 um
//! off, then 10 um the other side, then within 2 um). An open curve
//! records from the first cycle within [`SETTLED_MM`], so that its first
//! millimetre is measured; a closed one goes once round from where it
//! starts recording, so where the hold moves the point (a surface inclined
//! to the plane) it waits until the point has stayed within
//! [`SETTLED_CLOSED_MM`] over [`SETTLED_RUN_MM`] of its path, and loses
//! nothing. It counts only once the scan has come up to speed: while the
//! machine accelerates, its servo lag carries the ball sideways along the
//! surface faster than the hold takes it back (a 3 mm ball in a 10 mm
//! countersunk hole at 60 mm/s: 15 um across the plane over the first
//! 4 mm). On a wall square to the plane the hold does not act (the
//! offset there is the probe's error across the plane): a closed curve
//! records from the first cycle within [`SETTLED_MM`] as an open one.

/// An open curve records once the measured point has come within this of
/// the design curve across the plane, mm.
pub const SETTLED_MM: f64 = 0.005;

/// A closed curve records once the point has stayed within this across
/// the plane, mm ...
pub const SETTLED_CLOSED_MM: f64 = 0.001;

/// ... over this much of its path, mm.
pub const SETTLED_RUN_MM: f64 = 0.5;

/// ... or once the scan has gone this far along its path, mm (where the
/// point cannot be held in the plane it is recorded as it comes).
pub const SETTLE_WITHIN_MM: f64 = 2.0;

/// A closed curve, which loses nothing by waiting, gives up this far past
/// where it came up to speed, mm: the hold takes a swing of 15 um out in
/// about 4 mm at 60 mm/s (its gain of 40/s is a time constant of 1.5 mm
/// there).
pub const SETTLE_CLOSED_WITHIN_MM: f64 = 5.0;

/// The settling of one scan's measured point in its section plane.
#[derive(Debug, Clone, Copy)]
pub(super) struct Settling {
    closed: bool,
    /// How far the scan runs before it is up to speed, mm (closed curves).
    ramp_mm: f64,
    /// Where the point last came within the tolerance and has stayed.
    within_since: Option<f64>,
    /// The progress at which recording began.
    pub(super) at: Option<f64>,
}

impl Settling {
    /// A scan of a plane section (`section`) of a closed or open path that
    /// comes up to speed over its first `ramp_mm` (mm); a scan that holds
    /// no plane records from its start.
    pub(super) fn new(section: bool, closed: bool, ramp_mm: f64) -> Settling {
        Settling {
            closed,
            ramp_mm: if closed { ramp_mm.max(0.0) } else { 0.0 },
            within_since: None,
            at: (!section).then_some(0.0),
        }
    }

    /// Takes the point's offset across the plane (mm, asked only until
    /// the scan records; `None` when there is no measured point) and
    /// whether the plane hold acts there, at `progress` along the path
    /// (mm); returns whether the scan records.
    pub(super) fn update(
        &mut self,
        progress: f64,
        offset: impl FnOnce() -> Option<(f64, bool)>,
    ) -> bool {
        if self.at.is_some() {
            return true;
        }
        let offset = offset();
        let held = offset.is_some_and(|(_, held)| held);
        let (tol, run, from) = match self.closed && held {
            true => (SETTLED_CLOSED_MM, SETTLED_RUN_MM, self.ramp_mm),
            false => (SETTLED_MM, 0.0, 0.0),
        };
        let give_up = match self.closed {
            true => self.ramp_mm + SETTLE_CLOSED_WITHIN_MM,
            false => SETTLE_WITHIN_MM,
        };
        match offset {
            Some((e, _)) if e.abs() <= tol && progress >= from => {
                self.within_since.get_or_insert(progress);
            }
            _ => self.within_since = None,
        }
        let stayed = self.within_since.is_some_and(|s| progress - s >= run);
        if stayed || progress >= give_up {
            self.at = Some(progress);
        }
        self.at.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sphere's swing (4, -10, -4.4, -1.6, -0.5, ... um at 0.25 mm
    /// steps): an open curve records from the first point, a closed one
    /// from the point 0.5 mm after the first within 1 um.
    #[test]
    fn a_closed_curve_waits_for_the_swing_past_the_plane_to_die_out() {
        let swing = [
            0.0043, -0.0098, -0.0044, -0.0016, -0.0005, -0.0002, -0.0001, 0.0,
        ];
        let first = |closed: bool| {
            let mut s = Settling::new(true, closed, 0.0);
            (swing.iter().enumerate())
                .find(|&(k, &e)| s.update(0.25 * k as f64, || Some((e, true))))
                .map(|(k, _)| k)
        };
        assert_eq!(first(false), Some(0));
        assert_eq!(first(true), Some(6));
        let mut never = Settling::new(true, true, 0.0);
        assert!(!never.update(4.9, || Some((0.01, true))));
        assert!(never.update(5.0, || Some((0.01, true))));
        let mut open = Settling::new(true, false, 0.0);
        assert!(!open.update(1.9, || Some((0.01, true))));
        assert!(open.update(2.0, || Some((0.01, true))));
        assert!(Settling::new(false, true, 0.0).update(0.0, || None));
        // A wall square to the plane: within 5 um is settled.
        assert!(Settling::new(true, true, 0.0).update(0.0, || Some((0.004, false))));
    }

    /// A closed curve that comes up to speed over its first 3 mm counts
    /// nothing before: a point within 1 um during the ramp does not start
    /// the run, and it gives up 5 mm past the ramp. An open curve records
    /// as before.
    #[test]
    fn a_closed_curve_counts_only_once_up_to_speed() {
        let mut s = Settling::new(true, true, 3.0);
        assert!(!s.update(0.5, || Some((0.0, true))));
        assert!(!s.update(1.0, || Some((0.0, true))));
        assert!(!s.update(2.9, || Some((0.015, true))));
        assert!(!s.update(7.9, || Some((0.015, true))));
        assert!(s.update(8.0, || Some((0.015, true))));
        let mut t = Settling::new(true, true, 3.0);
        assert!(!t.update(3.0, || Some((0.0005, true))));
        assert!(!t.update(3.4, || Some((0.0005, true))));
        assert!(t.update(3.5, || Some((0.0005, true))));
        assert!(Settling::new(true, false, 3.0).update(0.0, || Some((0.004, true))));
    }
}
