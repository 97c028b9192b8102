//! How a scan of a closed path starts and ends its recorded loop.
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
