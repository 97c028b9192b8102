//! Whether the probe can measure a feature, from the design data: standing
//! at the points of its ball path with the stylus shaft and the probe body
//! clear of the part, and with a clear route from the clearance height to
//! where its measuring starts. A curve or touch point without a route is
//! not measured; one whose probe would strike the part is noted (the
//! machine's collision stop ends its scan where it strikes); `cmm check`
//! names both.
use std::fmt;

use super::correction::DesignPoint;
use crate::host::modes::{
    approach_standoff, mount_reachable, route_from_above, FreeSpace, HostProbe, ModeOptions,
};
use crate::math::Point3;
use crate::program::Pose;
use crate::seam::ProbePart;

/// Spacing of the ball-path points whose posture is checked, mm (at
/// most: see [`POSTURE_STEP_RADII`]).
const POSTURE_STEP_MM: f64 = 2.0;

/// ... and at most this many ball radii: a small ball's path round a
/// small feature (a 0.3 mm ball in a 1.5 mm bore, its path 2.6 mm round)
/// is checked at more than its two ends.
const POSTURE_STEP_RADII: f64 = 2.0;

/// Why a feature cannot be measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Unreachable {
    /// With the ball centre at `ball` (part coordinates, mm) this part of
    /// the probe would be inside the part or too close to it.
    Strikes {
        /// The part of the probe.
        probe_part: ProbePart,
        /// Ball centre, part coordinates, mm.
        ball: Point3,
    },
    /// No route from the clearance height to the start point `start`
    /// (ball centre, part coordinates, mm) is clear of the part.
    NoRoute {
        /// Ball centre at the start, part coordinates, mm.
        start: Point3,
        /// The part of the probe that would strike the part with the ball
        /// centre at the start, when one would (a stylus too short for a
        /// deep hole: the body stands in the part there).
        blocked_by: Option<ProbePart>,
        /// Whether the probe mount would stand outside the machine's
        /// travel with the ball centre at the start (no route can reach
        /// it, whatever the part).
        out_of_travel: bool,
    },
    /// No point of the section can be touched: the stretch is narrower
    /// than the ball, or walls beside it stand in the ball's way.
    TooNarrow,
}

impl fmt::Display for Unreachable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Unreachable::Strikes { probe_part, ball } => write!(
                f,
                "the probe's {} would strike the part, or pass closer to it than the clearance's posture margin, with the ball centre at ({:.3}, {:.3}, {:.3})",
                probe_part.name(),
                ball.x,
                ball.y,
                ball.z
            ),
            Unreachable::NoRoute {
                start,
                out_of_travel: true,
                ..
            } => write!(
                f,
                "the start ({:.3}, {:.3}, {:.3}) lies outside the machine's travel (the probe mount would stand beyond it)",
                start.x, start.y, start.z
            ),
            Unreachable::NoRoute {
                start, blocked_by, ..
            } => {
                write!(
                    f,
                    "no route from the clearance height to the start ({:.3}, {:.3}, {:.3}) is clear of the part",
                    start.x, start.y, start.z
                )?;
                match blocked_by {
                    Some(p) => write!(f, " (the probe's {} would strike the part there)", p.name()),
                    None => Ok(()),
                }
            }
            Unreachable::TooNarrow => write!(f, "narrower than the ball"),
        }
    }
}

/// What the check needs.
#[derive(Clone, Copy)]
pub struct Reach<'a> {
    /// The nominal part's free space.
    pub free: &'a dyn FreeSpace,
    /// Part to machine.
    pub pose: Pose,
    /// The probe as the host knows it.
    pub probe: HostProbe,
    /// Standoff and clearance height.
    pub modes: &'a ModeOptions,
    /// How far the stylus is pressed into the surface while a curve is
    /// scanned (its deflection), mm: the ball centre stands that much
    /// nearer the part than touching, and the shaft and body with it.
    pub press_mm: f64,
}

impl Reach<'_> {
    /// Whether a scan along `design` (part coordinates) can be measured:
    /// the probe's posture every [`POSTURE_STEP_MM`] along the ball path,
    /// and the route to its start.
    pub fn curve(&self, design: &[DesignPoint]) -> Result<(), Unreachable> {
        let Some(first) = design.first() else {
            return Ok(());
        };
        self.start(first)?;
        (self.posture_samples(design).into_iter())
            .filter_map(|k| design.get(k))
            .try_for_each(|d| self.scanning_posture(d))
    }

    /// [`Reach::curve`] of a scan that may start elsewhere: an open curve
    /// whose start has no clear route (it begins in a concave corner, the
    /// ball a few tenths of a millimetre from the wall it meets) while its
    /// end has one is scanned from its end; a closed curve whose start has
    /// none (under an overhang that covers part of it) from the first of
    /// [`CLOSED_STARTS`] points evenly round it that has one. The verdict,
    /// and the design points in the order to scan them when that is not
    /// their own.
    pub fn curve_either_way(
        &self,
        design: &[DesignPoint],
        closed: bool,
    ) -> (Result<(), Unreachable>, Option<Vec<DesignPoint>>) {
        let forward = self.curve(design);
        if !matches!(forward, Err(Unreachable::NoRoute { .. })) {
            return (forward, None);
        }
        let starts = match closed {
            true => 1..CLOSED_STARTS,
            false => 0..1,
        };
        let n = design.len();
        for k in starts.filter(|&k| !closed || k * n / CLOSED_STARTS > 0) {
            let order: Vec<DesignPoint> = match closed {
                true => rotated(design, k * n / CLOSED_STARTS),
                false => design.iter().rev().copied().collect(),
            };
            match self.curve(&order) {
                Err(Unreachable::NoRoute { .. }) => continue,
                other => return (other, Some(order)),
            }
        }
        (forward, None)
    }

    /// Where a scan along `design` whose probe strikes the part somewhere
    /// on it is best started: the order of the design points (rotated, for
    /// a closed curve, to the start of its longest stretch where the probe
    /// stands clear; reversed, for an open one, when it runs clear longer
    /// from its end), so the scan measures that stretch before the
    /// machine's collision stop ends it. `None` when the design has no
    /// clear stretch or the new start has no clear route.
    pub fn clearest_order(&self, design: &[DesignPoint], closed: bool) -> Option<Vec<DesignPoint>> {
        let clear = self.clear_marks(design);
        let order: Vec<DesignPoint> = if closed {
            rotated(design, longest_circular_run(&clear)?)
        } else {
            let ahead = clear.iter().take_while(|c| **c).count();
            let back = clear.iter().rev().take_while(|c| **c).count();
            (back > ahead).then(|| design.iter().rev().copied().collect())?
        };
        self.start(order.first()?).ok().map(|()| order)
    }

    /// Whether the probe stands clear at each design point, from the
    /// checks at [`Reach::posture_samples`]: a point between two checks
    /// is clear when both are.
    fn clear_marks(&self, design: &[DesignPoint]) -> Vec<bool> {
        let verdicts: Vec<(usize, bool)> = (self.posture_samples(design).into_iter())
            .filter_map(|k| Some((k, self.scanning_posture(design.get(k)?).is_ok())))
            .collect();
        let mut marks = vec![verdicts.iter().all(|v| v.1); design.len()];
        for w in verdicts.windows(2) {
            if let [(a, true), (b, true)] = w {
                marks[*a..=*b].fill(true);
            }
        }
        marks
    }

    /// The indices of the design points whose posture is checked: the
    /// first, each one [`POSTURE_STEP_MM`] (or [`POSTURE_STEP_RADII`] ball
    /// radii, if less) along the ball path from the
    /// one checked before it, and the last.
    fn posture_samples(&self, design: &[DesignPoint]) -> Vec<usize> {
        let mut out: Vec<usize> = Vec::new();
        let mut last: Option<Point3> = None;
        let step = POSTURE_STEP_MM.min(POSTURE_STEP_RADII * self.probe.tip_radius_mm);
        for (k, d) in design.iter().enumerate() {
            let ball = self.ball(d);
            if last.is_none_or(|l| (ball - l).norm() >= step) {
                out.push(k);
                last = Some(ball);
            }
        }
        let end = design.len().checked_sub(1);
        out.extend(end.filter(|e| out.last() != Some(e)));
        out
    }

    /// Whether a touch point at `d` (part coordinates) can be measured.
    pub fn touch(&self, d: &DesignPoint) -> Result<(), Unreachable> {
        self.start(d)?;
        self.posture(self.ball(d))
    }

    /// The ball centre touching the design at `d`, part coordinates.
    fn ball(&self, d: &DesignPoint) -> Point3 {
        d.point + d.normal * self.probe.tip_radius_mm
    }

    /// The probe's posture scanning over `d`: the ball touching there
    /// and the stylus bent by [`Reach::press_mm`] from the probe mount,
    /// which stands that much nearer the part, the body with it.
    fn scanning_posture(&self, d: &DesignPoint) -> Result<(), Unreachable> {
        let ball = self.ball(d);
        self.posture(ball)?;
        // Unpressed, the posture's own body check was this one.
        if self.press_mm <= 0.0 {
            return Ok(());
        }
        let pressed = ball - d.normal * self.press_mm;
        match self.free.body_clear(self.pose.to_machine(pressed)) {
            true => Ok(()),
            false => Err(Unreachable::Strikes {
                probe_part: ProbePart::Body,
                ball,
            }),
        }
    }

    fn posture(&self, ball: Point3) -> Result<(), Unreachable> {
        match self.free.posture(self.pose.to_machine(ball)) {
            Some(probe_part) => Err(Unreachable::Strikes { probe_part, ball }),
            None => Ok(()),
        }
    }

    /// The route to the approach start outside `d`.
    fn start(&self, d: &DesignPoint) -> Result<(), Unreachable> {
        let touching = self
            .pose
            .to_machine(d.point + d.normal * self.probe.tip_radius_mm);
        let n = self.pose.dir_to_machine(d.normal);
        let at = touching + n * approach_standoff(Some(self.free), touching, n, self.modes);
        let start = self.pose.to_part(at);
        match route_from_above(self.free, (at, self.probe.probe_vector), n, self.modes) {
            true => Ok(()),
            false => Err(Unreachable::NoRoute {
                start,
                blocked_by: self.free.posture(at),
                out_of_travel: !mount_reachable(at - self.probe.probe_vector, self.modes),
            }),
        }
    }
}

/// How many starts round a closed curve are tried for one with a clear
/// route (its own first and the points dividing it into this many
/// stretches).
const CLOSED_STARTS: usize = 16;

/// The closed curve `design` started at its point `start`.
fn rotated(design: &[DesignPoint], start: usize) -> Vec<DesignPoint> {
    let (a, b) = design.split_at(start.min(design.len()));
    b.iter().chain(a).copied().collect()
}

/// The first index of the longest run of `true` in `marks` taken as a
/// circle (a run may wrap past the end), or `None` when there is none.
fn longest_circular_run(marks: &[bool]) -> Option<usize> {
    let n = marks.len();
    let first_false = marks.iter().position(|m| !m)?;
    let (mut best, mut run_start, mut run) = (None::<(usize, usize)>, 0, 0);
    for i in 1..=n {
        let k = (first_false + i) % n;
        if marks[k] {
            if run == 0 {
                run_start = k;
            }
            run += 1;
            if best.is_none_or(|(_, len)| run > len) {
                best = Some((run_start, run));
            }
        } else {
            run = 0;
        }
    }
    best.map(|(start, _)| start)
}

#[cfg(test)]
mod tests {
    use super::longest_circular_run;

    #[test]
    fn the_longest_run_may_wrap_round_the_end() {
        let m = |s: &str| s.chars().map(|c| c == '1').collect::<Vec<bool>>();
        assert_eq!(longest_circular_run(&m("1100111")), Some(4));
        assert_eq!(longest_circular_run(&m("0110")), Some(1));
        assert_eq!(longest_circular_run(&m("0000")), None);
        assert_eq!(longest_circular_run(&m("1011101")), Some(2));
    }
}
