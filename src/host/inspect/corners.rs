//! Concave corners of a section, from the design data: where the ball
//! touching one wall would cut into the other (the corner between two
//! faces, the end of an open section against a wall), its centre cannot
//! follow the design point. Those design points are dropped, so the ball
//! path goes straight from the last point the ball reaches on one side to
//! the first on the other: about where the ball touches both walls.
//! A stretch narrower than the ball loses all its points.
//!
//! Convex corners: where the normal turns outward between neighbouring
//! design points (a box outline's corner, a boss's edge), the ball centre
//! has to go round the edge on an arc of its offset radius, or the path
//! would cut the corner on a chord (0.29 ball radii into a right-angled
//! edge). Design points on the edge itself, with normals turning from one
//! face's to the other's in the section plane, make the path that arc.
use super::correction::DesignPoint;
use crate::geometry::section::SectionCurve;
use crate::math::{Point3, Vec3};
use crate::workpiece::Workpiece;

/// A concave stretch whose bend radius is below this many ball radii is
/// looked at point by point (the exact distance then decides): the ratio
/// leaves room for the chord's error on a coarse curve.
const TIGHT_BEND_RATIO: f64 = 1.1;

/// How the corners are found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerOptions {
    /// A design point is looked at when its normal turns from a
    /// neighbour's by more than this, degrees (a corner), or when it lies
    /// within the look-around of such a point or of an open curve's end.
    pub turn_deg: f64,
    /// How far along the curve around a corner or an end design points
    /// are looked at, in ball radii.
    pub look_around_radii: f64,
    /// A ball centre closer than the ball radius less this to the design
    /// data cuts into a wall, mm.
    pub tolerance_mm: f64,
    /// Design points on a convex edge are put this far apart in normal
    /// direction, degrees (the ball centre's arc about the edge).
    pub arc_step_deg: f64,
    /// Where the ball stops reaching between a kept design point and one
    /// left out, the last point it reaches is found to this, mm.
    pub boundary_step_mm: f64,
}

impl Default for CornerOptions {
    fn default() -> Self {
        CornerOptions {
            turn_deg: 10.0,
            look_around_radii: 2.5,
            tolerance_mm: 1e-3,
            arc_step_deg: 10.0,
            boundary_step_mm: 0.01,
        }
    }
}

/// The design points of a section curve (part coordinates) that a ball of
/// radius `r` can touch: the others (at concave corners and at ends against
/// a wall) left out, and in their place, between a point left out and its
/// kept neighbour on the same face (their normals within the corner's
/// turn), the last point of the chord between them that the ball can
/// touch ([`last_reachable`]): a coarsely sampled curve (a nearly straight
/// one, its points 1.6 mm apart) keeps what the ball reaches up to the
/// wall. Only points near corners and ends are looked at (an exact
/// distance each).
pub fn reachable_points(
    design: &[DesignPoint],
    closed: bool,
    workpiece: &Workpiece,
    r: f64,
    opts: &CornerOptions,
) -> Vec<DesignPoint> {
    let near = near_corners(design, closed, r, opts);
    let cuts = |d: &DesignPoint| {
        let ball = d.point + d.normal * r;
        workpiece
            .closest_point(ball)
            .is_ok_and(|fp| fp.projection.distance < r - opts.tolerance_mm)
    };
    let keep: Vec<bool> = (design.iter().zip(&near))
        .map(|(d, &near)| !near || !cuts(d))
        .collect();
    let n = design.len();
    let neighbour = |k: usize, step: isize| {
        let j = k as isize + step;
        if closed && n > 2 {
            Some(j.rem_euclid(n as isize) as usize)
        } else {
            usize::try_from(j).ok().filter(|&j| j < n)
        }
    };
    let mut out = Vec::with_capacity(n + 2);
    for (k, d) in design.iter().enumerate() {
        if !keep.get(k).copied().unwrap_or(false) {
            continue;
        }
        let edge = |step| {
            let j = neighbour(k, step).filter(|&j| !keep.get(j).copied().unwrap_or(true))?;
            last_reachable(d, design.get(j)?, &cuts, opts)
        };
        out.extend(edge(-1));
        out.push(*d);
        out.extend(edge(1));
    }
    out
}

/// The point of the chord from `kept` (whose ball cuts into nothing) to
/// `cut` (whose ball does) farthest from `kept` whose ball cuts into
/// nothing, to [`CornerOptions::boundary_step_mm`] (bisection, the normal
/// blended along), when the two lie on one face (normals within the
/// corner's turn) and it lies that far from `kept`.
fn last_reachable(
    kept: &DesignPoint,
    cut: &DesignPoint,
    cuts: &dyn Fn(&DesignPoint) -> bool,
    opts: &CornerOptions,
) -> Option<DesignPoint> {
    if kept.normal.dot(&cut.normal) < opts.turn_deg.to_radians().cos() {
        return None;
    }
    let len = (cut.point - kept.point).norm();
    let at = |t: f64| DesignPoint {
        point: kept.point + (cut.point - kept.point) * t,
        normal: (kept.normal * (1.0 - t) + cut.normal * t)
            .try_normalize(1e-12)
            .unwrap_or(kept.normal),
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    while (hi - lo) * len > opts.boundary_step_mm {
        let mid = 0.5 * (lo + hi);
        if cuts(&at(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (lo * len >= opts.boundary_step_mm).then(|| at(lo))
}

/// The design points of a section curve over the faces `own` that a ball
/// of radius `r` follows: [`reachable_points`] that no other face comes
/// into ([`clear_of_other_faces`]: a groove narrower than the ball, a wall
/// beside the section), with the arcs about convex corners
/// ([`round_convex_corners`]) in the plane with normal `plane_normal`.
pub fn section_design(
    (design, own): (&[DesignPoint], &[usize]),
    closed: bool,
    (workpiece, plane_normal): (&Workpiece, Vec3),
    r: f64,
    opts: &CornerOptions,
) -> Vec<DesignPoint> {
    let kept = reachable_points(design, closed, workpiece, r, opts);
    let kept = clear_of_other_faces(&kept, (workpiece, own), r, opts);
    round_convex_corners(&kept, closed, plane_normal, opts)
}

/// The faces a section curve lies on, ascending.
pub fn own_faces(curve: &SectionCurve) -> Vec<usize> {
    let mut faces: Vec<usize> = curve.points.iter().map(|p| p.face).collect();
    faces.sort_unstable();
    faces.dedup();
    faces
}

/// The design points whose ball (radius `r`, on the point's normal) no
/// face but the curve's own (`own`) comes into by more than the tolerance:
/// faces the section plane does not cut (the walls of a groove parallel
/// to it) can still stand in the ball's way.
pub fn clear_of_other_faces(
    design: &[DesignPoint],
    (workpiece, own): (&Workpiece, &[usize]),
    r: f64,
    opts: &CornerOptions,
) -> Vec<DesignPoint> {
    let others = || (0..workpiece.faces.len()).filter(|i| !own.contains(i));
    let reach = r - opts.tolerance_mm;
    design
        .iter()
        .filter(|d| {
            let ball = d.point + d.normal * r;
            !workpiece
                .comes_within(ball, others(), reach)
                .unwrap_or(true)
        })
        .copied()
        .collect()
}

/// `design` with points added on every convex corner between neighbours
/// (the normal turns by more than `turn_deg`, outward along the curve):
/// the corner is where the two neighbours' tangent lines in the plane
/// meet, and its points' normals turn from one neighbour's to the other's
/// in steps of at most `arc_step_deg`.
pub fn round_convex_corners(
    design: &[DesignPoint],
    closed: bool,
    plane_normal: Vec3,
    opts: &CornerOptions,
) -> Vec<DesignPoint> {
    let cos_turn = opts.turn_deg.to_radians().cos();
    let mut out = Vec::with_capacity(design.len());
    let n = design.len();
    let pairs = if closed { n } else { n.saturating_sub(1) };
    for (k, a) in design.iter().enumerate() {
        out.push(*a);
        let Some(b) = (k < pairs).then(|| design.get((k + 1) % n)).flatten() else {
            continue;
        };
        let convex = (b.point - a.point).dot(&(b.normal - a.normal)) > 0.0;
        if convex && a.normal.dot(&b.normal) < cos_turn {
            out.extend(corner_arc(a, b, plane_normal, opts.arc_step_deg));
        }
    }
    out
}

/// The edge points between `a` and `b` (their normals turning about
/// `axis`), none when the tangent lines do not meet near them.
fn corner_arc(a: &DesignPoint, b: &DesignPoint, axis: Vec3, step_deg: f64) -> Vec<DesignPoint> {
    let Some(c) = tangent_meet(a, b, axis) else {
        return Vec::new();
    };
    let gap = (b.point - a.point).norm();
    if (c - a.point).norm() > gap + 1e-9 || (c - b.point).norm() > gap + 1e-9 {
        return Vec::new();
    }
    let turn = a
        .normal
        .cross(&b.normal)
        .dot(&axis)
        .atan2(a.normal.dot(&b.normal));
    let steps = (turn.abs() / step_deg.max(0.1).to_radians())
        .ceil()
        .max(1.0) as usize;
    let Some(axis) = nalgebra::Unit::try_new(axis, 1e-12) else {
        return Vec::new();
    };
    let on_edge = |normal| DesignPoint { point: c, normal };
    // The ends of the arc: the edge with either face's normal, unless a
    // neighbour lies on the edge already.
    let first = ((c - a.point).norm() > EDGE_SAME_MM).then(|| on_edge(a.normal));
    let last = ((c - b.point).norm() > EDGE_SAME_MM).then(|| on_edge(b.normal));
    let inner = (1..steps).map(|i| {
        let rot = nalgebra::Rotation3::from_axis_angle(&axis, turn * i as f64 / steps as f64);
        on_edge(rot * a.normal)
    });
    first.into_iter().chain(inner).chain(last).collect()
}

/// A design point this close to a corner (mm) lies on its edge.
const EDGE_SAME_MM: f64 = 1e-6;

/// Where the tangent lines of `a` and `b` (in the plane with normal
/// `axis`, perpendicular to their normals) meet, if they are not parallel.
fn tangent_meet(a: &DesignPoint, b: &DesignPoint, axis: Vec3) -> Option<Point3> {
    // c = a + s t_a with (c - b) . n_b = 0.
    let ta = axis.cross(&a.normal);
    let denom = ta.dot(&b.normal);
    if denom.abs() < 1e-9 {
        return None;
    }
    let s = (b.point - a.point).dot(&b.normal) / denom;
    Some(a.point + ta * s)
}

/// Which design points lie within `reach` (mm, along the curve) of a
/// corner (a normal turning by more than `turn_deg` between neighbours) or
/// of an open curve's ends.
fn near_corners(design: &[DesignPoint], closed: bool, r: f64, opts: &CornerOptions) -> Vec<bool> {
    let n = design.len();
    let cos_turn = opts.turn_deg.to_radians().cos();
    let mut seeds: Vec<usize> = Vec::new();
    if !closed && n > 0 {
        seeds.extend([0, n - 1]);
    }
    let last_pair = (closed && n > 2).then(|| (n - 1, 0));
    let pairs = (0..n.saturating_sub(1))
        .map(|k| (k, k + 1))
        .chain(last_pair);
    for (i, j) in pairs {
        let (Some(a), Some(b)) = (design.get(i), design.get(j)) else {
            continue;
        };
        if a.normal.dot(&b.normal) < cos_turn || bends_tighter_than_ball(a, b, r) {
            seeds.extend([i, j]);
        }
    }
    let mut near = vec![false; n];
    for s in seeds {
        mark_around(design, closed, s, r * opts.look_around_radii, &mut near);
    }
    near
}

/// Whether the curve bends concavely between neighbours `a` and `b` on a
/// radius below [`TIGHT_BEND_RATIO`] ball radii `r` (a hole smaller than
/// the ball, a fillet the ball cannot follow, points too close together
/// for their normals' turn to count as a corner).
fn bends_tighter_than_ball(a: &DesignPoint, b: &DesignPoint, r: f64) -> bool {
    let step = b.point - a.point;
    let turn = b.normal - a.normal;
    // Normals converge along a concave stretch.
    let concave = turn.dot(&step) < 0.0;
    concave && turn.norm() * r * TIGHT_BEND_RATIO > step.norm()
}

/// Marks the points within `reach` of point `s` along the curve, both ways.
fn mark_around(design: &[DesignPoint], closed: bool, s: usize, reach: f64, near: &mut [bool]) {
    let n = design.len();
    for step in [1isize, -1] {
        let (mut k, mut walked) = (s, 0.0);
        for _ in 0..n {
            if let Some(m) = near.get_mut(k) {
                *m = true;
            }
            let next = k as isize + step;
            let next = if closed {
                next.rem_euclid(n as isize) as usize
            } else if (0..n as isize).contains(&next) {
                next as usize
            } else {
                break;
            };
            let (Some(a), Some(b)) = (design.get(k), design.get(next)) else {
                break;
            };
            walked += (b.point - a.point).norm();
            if walked > reach {
                break;
            }
            k = next;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_and_ends_are_found_along_the_curve() {
        // An L of points 0.5 mm apart: along +x with normal +y, then up
        // +y with normal -x (a concave corner at the origin's side).
        let mut d: Vec<DesignPoint> = (0..20)
            .map(|k| DesignPoint {
                point: Point3::new(10.0 - 0.5 * k as f64, 0.0, 0.0),
                normal: Vec3::y(),
            })
            .collect();
        d.extend((1..20).map(|k| DesignPoint {
            point: Point3::new(0.0, 0.5 * k as f64, 0.0),
            normal: Vec3::x(),
        }));
        let near = near_corners(&d, false, 0.8, &CornerOptions::default());
        // The two ends and the corner (indices 19, 20), 2 mm either way.
        let marked: Vec<usize> = (0..d.len()).filter(|&k| near[k]).collect();
        let want: Vec<usize> = (0..=4).chain(15..=24).chain(34..=38).collect();
        assert_eq!(marked, want);
    }

    /// Points 0.1 mm apart round a circle of radius 2 mm (their normals
    /// turn 2.9 degrees between neighbours, no corner), facing `inward`
    /// (a hole) or out (a boss).
    fn circle(inward: bool) -> Vec<DesignPoint> {
        let steps = (2.0 * std::f64::consts::PI * 2.0 / 0.1).round() as usize;
        (0..steps)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / steps as f64;
                let out = Vec3::new(a.cos(), a.sin(), 0.0);
                DesignPoint {
                    point: Point3::from(out * 2.0),
                    normal: if inward { -out } else { out },
                }
            })
            .collect()
    }

    #[test]
    fn a_hole_tighter_than_the_ball_is_looked_at_all_round() {
        let opts = CornerOptions::default();
        let all = |d: &[DesignPoint], r: f64| near_corners(d, true, r, &opts).iter().all(|&m| m);
        let none = |d: &[DesignPoint], r: f64| near_corners(d, true, r, &opts).iter().all(|&m| !m);
        // A 4 mm hole: a 5 mm ball cannot follow it, a 3 mm one can.
        assert!(all(&circle(true), 2.5));
        assert!(none(&circle(true), 1.5));
        // A 4 mm boss bends the other way: any ball follows it.
        assert!(none(&circle(false), 2.5));
    }

    #[test]
    fn convex_corners_get_an_arc_about_the_edge_and_concave_ones_none() {
        // A square outline 0.5 mm apart, counter-clockwise about +z: every
        // corner convex, its last and first points 0.25 mm from it.
        let side = |k: usize, t: f64| -> DesignPoint {
            let (dir, normal, start) = match k {
                0 => (Vec3::x(), -Vec3::y(), Point3::new(-5.0, -5.0, 0.0)),
                1 => (Vec3::y(), Vec3::x(), Point3::new(5.0, -5.0, 0.0)),
                2 => (-Vec3::x(), Vec3::y(), Point3::new(5.0, 5.0, 0.0)),
                _ => (-Vec3::y(), -Vec3::x(), Point3::new(-5.0, 5.0, 0.0)),
            };
            DesignPoint {
                point: start + dir * t,
                normal,
            }
        };
        let square: Vec<DesignPoint> = (0..4)
            .flat_map(|k| (0..20).map(move |i| side(k, 0.25 + 0.5 * i as f64)))
            .collect();
        let opts = CornerOptions::default();
        let out = round_convex_corners(&square, true, Vec3::z(), &opts);
        // Each corner: the edge with both normals and 8 between (90 deg in
        // 10 deg steps).
        assert_eq!(out.len(), square.len() + 4 * 10);
        let r = 1.5;
        let corners = [(5.0, -5.0), (5.0, 5.0), (-5.0, 5.0), (-5.0, -5.0)];
        let on_edge: Vec<&DesignPoint> = out
            .iter()
            .filter(|d| {
                corners
                    .iter()
                    .any(|c| (d.point - Point3::new(c.0, c.1, 0.0)).norm() < 1e-12)
            })
            .collect();
        assert_eq!(on_edge.len(), 40);
        // The ball centres go round each edge at the ball radius, their
        // normals turning one way by at most the step.
        for w in out.windows(2) {
            let turn = w[0].normal.angle(&w[1].normal).to_degrees();
            assert!(turn <= 10.0 + 1e-9, "{turn}");
            assert!(w[0].normal.cross(&w[1].normal).z >= -1e-12);
        }
        for d in on_edge {
            let centre = d.point + d.normal * r;
            assert!(((centre - d.point).norm() - r).abs() < 1e-12);
        }
        // The same outline run the other way round: its corners are
        // concave (the inside of a pocket), nothing added.
        let pocket: Vec<DesignPoint> = square
            .iter()
            .rev()
            .map(|d| DesignPoint {
                point: d.point,
                normal: -d.normal,
            })
            .collect();
        assert_eq!(
            round_convex_corners(&pocket, true, Vec3::z(), &opts).len(),
            pocket.len()
        );
    }
}
