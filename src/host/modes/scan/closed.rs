//! How a scan of a closed path starts and ends its recorded loop.
use crate::host::modes::Measured;
use crate::host::path::SegmentSpeed;

/// How far a scan of a closed path with the segment speeds `speeds` runs
/// before it is up to speed (its first segment's top speed at the
/// tangential acceleration `a`), and how far it runs on past the end of
/// its recorded loop to brake from its top speed, mm. The servo's lag
/// while the machine accelerates or brakes carries the ball sideways
/// along a surface inclined to the section plane, off the plane, faster
/// than the plane hold takes it back: a closed scan records once up to
/// speed ([`super::settle`]) and brakes after its last point, over what it
/// measured first. An open scan records from its start to its end.
pub(super) fn closed_run(speeds: &[SegmentSpeed], a: f64) -> (f64, f64) {
    let stop = |v: f64| v * v / (2.0 * a.max(f64::MIN_POSITIVE));
    let first = speeds.first().map_or(0.0, |g| g.v_max_mm_s);
    let top = speeds.iter().map(|g| g.v_max_mm_s).fold(0.0, f64::max);
    (stop(first), stop(top))
}

/// Drops a closed scan's last point when it lies within half a `pitch`
/// (mm) of its first, all but repeating it: the loop's last point then
/// lies between half a pitch and a pitch and a half before its first. The
/// points are a pitch apart along the measured path, which differs in
/// length from the ball's (a 6 mm ball in a 10 mm bore: 2.5 times
/// longer), so where the ball's loop ends says nothing of that gap.
pub(super) fn close_the_loop(points: &mut Vec<Measured>, pitch: f64) {
    let repeats = match (points.first(), points.last()) {
        (Some(a), Some(b)) => points.len() > 2 && (b.point - a.point).norm() < 0.5 * pitch,
        _ => false,
    };
    if repeats {
        points.pop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Point3, Vec3};

    fn at(x: f64) -> Measured {
        let p = Point3::new(x.cos() * 5.0, x.sin() * 5.0, 0.0);
        Measured {
            point: p,
            normal: Vec3::z(),
            ball: p,
            scales: p,
            reading: Vec3::zeros(),
            motion: Vec3::zeros(),
        }
    }

    /// A last point 0.2 mm before the first (pitch 0.5) goes; one 0.3 mm
    /// before it stays.
    #[test]
    fn a_last_point_that_repeats_the_first_goes() {
        let step = |mm: f64| mm / 5.0;
        let mut near: Vec<Measured> = (0..3).map(|k| at(step(0.5) * k as f64)).collect();
        near.push(at(-step(0.2)));
        close_the_loop(&mut near, 0.5);
        assert_eq!(near.len(), 3);
        let mut far: Vec<Measured> = (0..3).map(|k| at(step(0.5) * k as f64)).collect();
        far.push(at(-step(0.3)));
        close_the_loop(&mut far, 0.5);
        assert_eq!(far.len(), 4);
    }
}
