//! Concave corners of a section, from the design data: where the ball
//! touching one wall would cut into the other (the corner between two
//! faces, the end of an open section against a wall), its centre cannot
//! follow the design point. Those design points are dropped, so the ball
//! path goes straight from the last point the ball reaches on one side to
//! the first on the other: about where the ball touches both walls.
//! A stretch narrower than the ball loses all its points.
use super::correction::DesignPoint;
use crate::workpiece::Workpiece;

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
}

impl Default for CornerOptions {
    fn default() -> Self {
        CornerOptions {
            turn_deg: 10.0,
            look_around_radii: 2.5,
            tolerance_mm: 1e-3,
        }
    }
}

/// The design points of a section curve (part coordinates) that a ball of
/// radius `r` can touch: the others (at concave corners and at ends against
/// a wall) left out. Only points near corners and ends are looked at (an
/// exact distance each).
pub fn reachable_points(
    design: &[DesignPoint],
    closed: bool,
    workpiece: &Workpiece,
    r: f64,
    opts: &CornerOptions,
) -> Vec<DesignPoint> {
    let near = near_corners(design, closed, r * opts.look_around_radii, opts.turn_deg);
    let cuts = |d: &DesignPoint| {
        let ball = d.point + d.normal * r;
        workpiece
            .closest_point(ball)
            .is_ok_and(|fp| fp.projection.distance < r - opts.tolerance_mm)
    };
    design
        .iter()
        .zip(near)
        .filter(|(d, near)| !*near || !cuts(d))
        .map(|(d, _)| *d)
        .collect()
}

/// Which design points lie within `reach` (mm, along the curve) of a
/// corner (a normal turning by more than `turn_deg` between neighbours) or
/// of an open curve's ends.
fn near_corners(design: &[DesignPoint], closed: bool, reach: f64, turn_deg: f64) -> Vec<bool> {
    let n = design.len();
    let cos_turn = turn_deg.to_radians().cos();
    let mut seeds: Vec<usize> = Vec::new();
    if !closed && n > 0 {
        seeds.extend([0, n - 1]);
    }
    for (k, w) in design.windows(2).enumerate() {
        if w[0].normal.dot(&w[1].normal) < cos_turn {
            seeds.extend([k, k + 1]);
        }
    }
    if closed && n > 1 {
        if let (Some(a), Some(b)) = (design.last(), design.first()) {
            if a.normal.dot(&b.normal) < cos_turn {
                seeds.extend([n - 1, 0]);
            }
        }
    }
    let mut near = vec![false; n];
    for s in seeds {
        mark_around(design, closed, s, reach, &mut near);
    }
    near
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
    use crate::math::{Point3, Vec3};

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
        let near = near_corners(&d, false, 2.0, 10.0);
        // The two ends and the corner (indices 19, 20), 2 mm either way.
        let marked: Vec<usize> = (0..d.len()).filter(|&k| near[k]).collect();
        let want: Vec<usize> = (0..=4).chain(15..=24).chain(34..=38).collect();
        assert_eq!(marked, want);
    }
}
