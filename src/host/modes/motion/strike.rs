//! Which way the probe backs out of a strike of its shaft or body: away
//! from where it struck, across the stylus.
//!
//! A shaft or body strike in a scan leaves the ball where the scan had
//! it: pressed on the surface it measured, or over a hole's rim with the
//! stylus free. Backing off along the ball's deflection alone (up off a
//! floor) drags a body that struck a column along the column; backing
//! against the last motion drives a ball over a hole's rim into the far
//! side of the hole. The strike point and the stylus's axis say which
//! way the struck part comes free: straight from the strike point to the
//! axis, square to the axis (for a round shaft or body, the contact's
//! normal).
use crate::math::{Point3, Vec3};

/// The unit direction from the strike point `at` square to the stylus axis
/// (through the ball centre `ball` along the unit `up`, towards the
/// probe), or `None` when `at` lies on the axis.
pub(super) fn off_the_strike(ball: Point3, up: Vec3, at: Point3) -> Option<Vec3> {
    let to_axis = ball - at;
    (to_axis - up * to_axis.dot(&up)).try_normalize(1e-9)
}

/// The direction a struck probe backs out along: away from the strike
/// (`away`, [`off_the_strike`]) and, where the ball is pressed on the
/// part (`pressed`, the unit deflection), off that surface too (their
/// sum; the deflection alone where the two nearly cancel).
pub(super) fn out_of_strike(away: Vec3, pressed: Option<Vec3>) -> Vec3 {
    match pressed {
        Some(p) => (away + p).try_normalize(0.5).unwrap_or(p),
        None => away,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A shaft standing at x = 10 (ball at z = 0) struck at (10.75, 0,
    /// 20): out along -x, whatever the height; a body struck beside a
    /// column with the ball pressed up off a floor: out up and away, at
    /// 45 degrees.
    #[test]
    fn a_struck_shaft_or_body_comes_free_across_its_axis() {
        let (ball, up) = (Point3::new(10.0, 0.0, 0.0), Vec3::z());
        let away = off_the_strike(ball, up, Point3::new(10.75, 0.0, 20.0)).unwrap();
        assert!((away - (-Vec3::x())).norm() < 1e-12);
        assert!(off_the_strike(ball, up, Point3::new(10.0, 0.0, 30.0)).is_none());
        let out = out_of_strike(away, Some(Vec3::z()));
        let want = Vec3::new(-1.0, 0.0, 1.0).normalize();
        assert!((out - want).norm() < 1e-12);
        assert_eq!(out_of_strike(away, None), away);
        assert_eq!(out_of_strike(away, Some(-away)), -away);
    }
}
