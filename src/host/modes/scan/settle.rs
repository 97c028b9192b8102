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
//! nothing. On a wall square to the plane the hold does not act (the
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

/// The settling of one scan's measured point in its section plane.
#[derive(Debug, Clone, Copy)]
pub(super) struct Settling {
    closed: bool,
    /// Where the point last came within the tolerance and has stayed.
    within_since: Option<f64>,
    /// The progress at which recording began.
    pub(super) at: Option<f64>,
}

impl Settling {
    /// A scan of a plane section (`section`) of a closed or open path; a
    /// scan that holds no plane records from its start.
    pub(super) fn new(section: bool, closed: bool) -> Settling {
        Settling {
            closed,
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
        let (tol, run) = match self.closed && held {
            true => (SETTLED_CLOSED_MM, SETTLED_RUN_MM),
            false => (SETTLED_MM, 0.0),
        };
        match offset {
            Some((e, _)) if e.abs() <= tol => {
                self.within_since.get_or_insert(progress);
            }
            _ => self.within_since = None,
        }
        let stayed = self.within_since.is_some_and(|s| progress - s >= run);
        if stayed || progress >= SETTLE_WITHIN_MM {
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
            let mut s = Settling::new(true, closed);
            (swing.iter().enumerate())
                .find(|&(k, &e)| s.update(0.25 * k as f64, || Some((e, true))))
                .map(|(k, _)| k)
        };
        assert_eq!(first(false), Some(0));
        assert_eq!(first(true), Some(6));
        let mut never = Settling::new(true, true);
        assert!(!never.update(1.9, || Some((0.01, true))));
        assert!(never.update(2.0, || Some((0.01, true))));
        assert!(Settling::new(false, true).update(0.0, || None));
        // A wall square to the plane: within 5 um is settled.
        assert!(Settling::new(true, true).update(0.0, || Some((0.004, false))));
    }
}
