//! Closest point on a ball-centre path: bounded Newton on the local
//! parameter of one segment, walking to neighbouring segments when the
//! minimum lies beyond a segment end.

use super::ball_path::{BallPath, PathLocation};
use super::pcc::CubicSegment;
use super::{ClosestOptions, PathError};
use crate::math::{all_finite, Point3};

/// How a Newton run on one segment ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Exit {
    /// Converged inside the segment (or ran out of iterations).
    Inside,
    /// The distance keeps falling before the segment start.
    Before,
    /// The distance keeps falling after the segment end.
    After,
}

impl Exit {
    /// The end of the next segment a walk enters by, seen from it.
    fn opposite(self) -> Exit {
        match self {
            Exit::Before => Exit::After,
            Exit::After => Exit::Before,
            Exit::Inside => Exit::Inside,
        }
    }
}

impl BallPath {
    /// Arc length `s` of the path point closest to `point`.
    ///
    /// With `hint_s` (e.g. the previous control cycle's answer) Newton starts
    /// there and walks at most [`ClosestOptions::max_hops`] segments, so the
    /// answer is the local minimum nearest the hint. Without a hint every
    /// segment is sampled ([`ClosestOptions::cold_samples`] per segment)
    /// and Newton starts at the nearest sample.
    pub fn closest_s(&self, point: &Point3, hint_s: Option<f64>) -> Result<f64, PathError> {
        let hint_ok = hint_s.is_none_or(f64::is_finite);
        if !all_finite(point.coords.as_slice()) || !hint_ok {
            return Err(PathError::NonFiniteQuery);
        }
        let hint = hint_s.map(|s| self.location(s));
        Ok(self.closest(point, hint.as_ref())?.s)
    }

    /// [`Self::closest_s`] from a location (e.g. the previous control
    /// cycle's answer), returning the location of the closest point.
    pub fn closest(
        &self,
        point: &Point3,
        hint: Option<&PathLocation>,
    ) -> Result<PathLocation, PathError> {
        let hint_ok = hint.is_none_or(|h| h.u.is_finite() && h.segment < self.segments().len());
        if !all_finite(point.coords.as_slice()) || !hint_ok {
            return Err(PathError::NonFiniteQuery);
        }
        let (i, u) = match hint {
            Some(h) => (h.segment, h.u),
            None => self.cold_start(point),
        };
        let (segment, u) = self.walk(point, i, u);
        Ok(PathLocation {
            segment,
            u,
            s: self.wrap(self.arc_of(segment, u)),
        })
    }

    /// Segment and local parameter of the nearest of the coarse samples.
    fn cold_start(&self, point: &Point3) -> (usize, f64) {
        let k = self.options().closest.cold_samples.max(1);
        let mut best = (0, 0.0, f64::INFINITY);
        for (i, seg) in self.segments().iter().enumerate() {
            for j in 0..=k {
                let u = seg.param_len() * j as f64 / k as f64;
                let d = (seg.position(u) - point).norm_squared();
                if d < best.2 {
                    best = (i, u, d);
                }
            }
        }
        (best.0, best.1)
    }

    /// Newton on segment `i` from `u`, moving to neighbours while the
    /// minimum lies beyond a segment end (never back the way it came).
    fn walk(&self, point: &Point3, mut i: usize, mut u: f64) -> (usize, f64) {
        let opts = self.options().closest;
        let mut came_from = Exit::Inside;
        for _ in 0..=opts.max_hops {
            let seg = &self.segments()[i];
            let (u_new, exit) = newton(seg, point, u, &opts);
            let next = self.neighbour(i, exit);
            match next {
                Some(j) if exit != came_from => {
                    u = self.entry_param(j, exit);
                    came_from = exit.opposite();
                    i = j;
                }
                _ => return (i, u_new),
            }
        }
        (i, u)
    }

    /// Where a walk leaving through `exit` enters segment `j`.
    fn entry_param(&self, j: usize, exit: Exit) -> f64 {
        match exit {
            Exit::Before => self.segments()[j].param_len(),
            _ => 0.0,
        }
    }

    /// The segment beyond the end `exit` of segment `i`, if any.
    fn neighbour(&self, i: usize, exit: Exit) -> Option<usize> {
        let n = self.segments().len();
        match exit {
            Exit::Inside => None,
            Exit::Before if i > 0 => Some(i - 1),
            Exit::After if i + 1 < n => Some(i + 1),
            _ if self.is_closed() => Some(if exit == Exit::Before { n - 1 } else { 0 }),
            _ => None,
        }
    }
}

/// Bounded Newton on `g(u) = (P(u) - q) . P'(u) = 0` over `[0, h]`;
/// steps leaving the segment stop at its end, and a step pushing out from
/// an end reports that end.
fn newton(seg: &CubicSegment, q: &Point3, mut u: f64, opts: &ClosestOptions) -> (f64, Exit) {
    let h = seg.param_len();
    let max_step = opts.max_step_rel * h;
    for _ in 0..opts.max_iters {
        let step = newton_step(seg, q, u).clamp(-max_step, max_step);
        let next = (u + step).clamp(0.0, h);
        if next == u && next != u + step {
            return (u, if u == 0.0 { Exit::Before } else { Exit::After });
        }
        u = next;
        if step.abs() <= opts.step_tol_rel * h {
            break;
        }
    }
    (u, Exit::Inside)
}

/// Newton step for the distance minimum (a descent step of maximal size
/// where the distance is not locally convex).
fn newton_step(seg: &CubicSegment, q: &Point3, u: f64) -> f64 {
    let r = seg.position(u) - q;
    let d1 = seg.d1(u);
    let g = r.dot(&d1);
    let hess = d1.norm_squared() + r.dot(&seg.d2(u));
    if hess > 0.0 {
        -g / hess
    } else {
        -g.signum() * f64::INFINITY
    }
}
