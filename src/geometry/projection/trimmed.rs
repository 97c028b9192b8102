//! Closest point on the boundary of a trimmed face: each trim segment is a
//! straight line in (u, v) whose image on the surface is minimised over by a
//! bounded one-dimensional Newton iteration.
use super::{Foot, ProjectionError, ProjectionOptions, SearchStatus, UnconfirmedReason};
use crate::geometry::{Jet2, NurbsSurface, Trim};
use crate::math::{Point3, Vec2};

/// The closest boundary point closer than `sqrt(best_dist2)`, if any.
pub(crate) fn closest_on_boundary(
    surface: &NurbsSurface,
    trim: &Trim,
    p: Point3,
    best_dist2: f64,
    opts: &ProjectionOptions,
) -> Result<Option<Foot>, ProjectionError> {
    // Nearer chords first, as the trim's box tree finds them. The segment
    // holding the least distance is searched whatever the order (its
    // bound is below every other segment's least), so the answer is the
    // same as a search of every segment.
    let mut best: Option<Foot> = None;
    trim.search_chords(surface, p, best_dist2, |c| {
        let foot = minimise_on_segment(surface, c.a, c.b, p, opts);
        let closer = best.is_none_or(|b| foot.dist2 < b.dist2) && foot.dist2 < best_dist2;
        closer.then(|| {
            best = Some(foot);
            foot.dist2
        })
    });
    Ok(best)
}

fn foot_at(surface: &NurbsSurface, uv: Vec2, p: Point3) -> (Foot, Jet2) {
    let d = surface.jet2(uv.x, uv.y);
    let mut foot = Foot::unevaluated(uv);
    foot.d = d;
    foot.dist2 = (d.point() - p).norm_squared();
    (foot, d)
}

/// The segment from `a` to `b` in (u, v), its ends exact.
struct Segment {
    a: Vec2,
    b: Vec2,
}

impl Segment {
    fn at(&self, t: f64) -> Vec2 {
        if t >= 1.0 {
            self.b
        } else {
            self.a + (self.b - self.a) * t
        }
    }

    /// Foot, tangent `dS/dt` and the derivative of `|S - p|^2 / 2` in `t`.
    fn eval(&self, surface: &NurbsSurface, t: f64, p: Point3) -> Line1 {
        let e = self.b - self.a;
        let (foot, d) = foot_at(surface, self.at(t), p);
        let r = d.point() - p;
        let c1 = d.su() * e.x + d.sv() * e.y;
        let c2 = d.suu() * (e.x * e.x) + d.suv() * (2.0 * e.x * e.y) + d.svv() * (e.y * e.y);
        Line1 {
            t,
            foot,
            g: c1.dot(&r),
            h: c1.dot(&c1) + c2.dot(&r),
            speed: c1.norm(),
        }
    }
}

/// The one-dimensional problem at one `t`.
struct Line1 {
    t: f64,
    foot: Foot,
    /// First derivative of `|S - p|^2 / 2` in `t`.
    g: f64,
    /// Second derivative.
    h: f64,
    /// `|dS/dt|`, mm per unit of `t`.
    speed: f64,
}

/// Bounded Newton on `t` in [0, 1] for `|S(a + t (b - a)) - p|^2`. When no
/// step lowers the distance away from a stationary point, the sign change
/// of the derivative is bisected for instead (its sign stays reliable
/// where differences of the distance drown in rounding).
fn minimise_on_segment(
    surface: &NurbsSurface,
    a: Vec2,
    b: Vec2,
    p: Point3,
    opts: &ProjectionOptions,
) -> Foot {
    let seg = Segment { a, b };
    let dist2 = |t: f64| {
        let x = seg.at(t);
        (surface.point(x.x, x.y) - p).norm_squared()
    };
    let t0 = [0.0, 0.5, 1.0]
        .into_iter()
        .min_by(|&x, &y| dist2(x).total_cmp(&dist2(y)))
        .unwrap_or(0.0);
    let mut cur = seg.eval(surface, t0, p);
    let mut last_step = f64::INFINITY;
    for it in 1..=opts.max_iterations {
        let step = if cur.h > 0.0 {
            -cur.g / cur.h
        } else {
            -cur.g.signum() * 0.25
        };
        let next = (cur.t + step).clamp(0.0, 1.0);
        last_step = cur.speed * (next - cur.t).abs();
        cur.foot.iterations = it;
        if last_step <= opts.step_tol_mm {
            return cur.foot;
        }
        match descend(surface, &seg, &cur, next, p, opts) {
            Some(better) => cur = better,
            None => return settle(surface, &seg, cur, p, opts, last_step),
        }
        cur.foot.iterations = it;
    }
    cur.foot.status = SearchStatus::Unconfirmed {
        reason: UnconfirmedReason::IterationLimit,
        last_step_mm: last_step,
    };
    cur.foot
}

/// Backtracking from `cur` towards `next`: the first of the points at
/// `next`, halfway, ... that lowers the distance.
fn descend(
    surface: &NurbsSurface,
    seg: &Segment,
    cur: &Line1,
    next: f64,
    p: Point3,
    opts: &ProjectionOptions,
) -> Option<Line1> {
    let mut t = next;
    for _ in 0..=opts.max_halvings {
        if t == cur.t {
            return None;
        }
        let cand = seg.eval(surface, t, p);
        if cand.foot.dist2 < cur.foot.dist2 {
            return Some(cand);
        }
        t = 0.5 * (cur.t + t);
    }
    None
}

/// The end of a search where no step lowers the distance: `cur` when it
/// is stationary (or held at an end of the segment), else the sign change
/// of the derivative between `cur` and the end it points to, bisected.
fn settle(
    surface: &NurbsSurface,
    seg: &Segment,
    mut cur: Line1,
    p: Point3,
    opts: &ProjectionOptions,
    last_step: f64,
) -> Foot {
    let held = (cur.t <= 0.0 && cur.g > 0.0) || (cur.t >= 1.0 && cur.g < 0.0);
    if held || cur.g.abs() <= opts.stationary_tol_mm * cur.speed {
        return cur.foot;
    }
    let end = if cur.g < 0.0 { 1.0 } else { 0.0 };
    let far = seg.eval(surface, end, p);
    let (mut lo, mut hi) = (cur.t, end);
    if far.g.signum() == cur.g.signum() {
        // Descending all the way to the end: the end is the minimum when
        // it is no farther.
        if far.foot.dist2 <= cur.foot.dist2 {
            return far.foot;
        }
    } else {
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if mid == lo || mid == hi {
                break;
            }
            let m = seg.eval(surface, mid, p);
            if m.g.signum() == cur.g.signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let found = seg.eval(surface, lo, p);
        let slack = 1e-12 * cur.foot.dist2 + 1e-24;
        if found.foot.dist2 <= cur.foot.dist2 + slack {
            return found.foot;
        }
    }
    cur.foot.status = SearchStatus::Unconfirmed {
        reason: UnconfirmedReason::NoDescent,
        last_step_mm: last_step,
    };
    cur.foot
}
