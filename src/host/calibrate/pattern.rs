//! Where the reference sphere is probed: the 25-point pattern of
//! ISO 10360-5 and the circle scans of condition-dependent probe correction.
//!
//! ISO 10360-5 (probing error `P[Form.Sph.1x25]`) spreads 25 points over the
//! hemisphere facing the stylus: 1 at the pole; 4 evenly spaced at 22.5 deg
//! below the pole; 8 at 45 deg below the pole, turned 22.5 deg against the
//! previous group; 4 at 67.5 deg below the pole, turned 22.5 deg; 8 at
//! 90 deg below the pole (the equator), turned 22.5 deg. The pole is the top
//! (+z), the stylus being vertical.
use std::f64::consts::PI;

use crate::math::Vec3;

/// The coordinate planes of the circle scans.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ScanPlane {
    /// Around the z axis, on the equator.
    Xy,
    /// Around the y axis, over the pole.
    Xz,
    /// Around the x axis, over the pole.
    Yz,
}

/// Every plane, in the order of the calibration.
pub const SCAN_PLANES: [ScanPlane; 3] = [ScanPlane::Xy, ScanPlane::Xz, ScanPlane::Yz];

/// Rings of the 25-point pattern: (angle below the pole in deg, points,
/// azimuth offset in deg).
const ISO_RINGS: [(f64, usize, f64); 5] = [
    (0.0, 1, 0.0),
    (22.5, 4, 0.0),
    (45.0, 8, 22.5),
    (67.5, 4, 22.5),
    (90.0, 8, 0.0),
];

/// Outward unit directions of the 25 probing points.
pub fn iso_25_directions() -> Vec<Vec3> {
    ISO_RINGS
        .iter()
        .flat_map(|&(below, count, offset)| {
            (0..count).map(move |k| {
                let polar = below.to_radians();
                let azimuth = (offset + 360.0 * k as f64 / count as f64).to_radians();
                Vec3::new(
                    polar.sin() * azimuth.cos(),
                    polar.sin() * azimuth.sin(),
                    polar.cos(),
                )
            })
        })
        .collect()
}

/// An orthonormal frame `(u, w, pole)` around `pole` (unit), with `u`
/// pointing as far up (+z) as possible; `x` when the pole is vertical.
fn pole_frame(pole: &Vec3) -> (Vec3, Vec3) {
    let up = Vec3::z() - pole * pole.z;
    let u = up
        .try_normalize(1e-9)
        .unwrap_or_else(|| (Vec3::x() - pole * pole.x).normalize());
    (u, pole.cross(&u))
}

/// `dir` (a direction of a pattern around +z) turned so that +z goes to
/// `pole` and +x to the frame's upward direction.
fn turn_to(pole: &Vec3, dir: &Vec3) -> Vec3 {
    let (u, w) = pole_frame(pole);
    u * dir.x + w * dir.y + pole * dir.z
}

/// The 25-point pattern around `pole` (unit outward direction facing the
/// probe mount) instead of +z.
pub fn iso_25_around(pole: &Vec3) -> Vec<Vec3> {
    iso_25_directions()
        .iter()
        .map(|d| turn_to(pole, d))
        .collect()
}

/// `count` probing directions for a quick sphere measurement (JP2902285B2
/// uses 4): the pole, then `count - 1` points at `polar_deg` from it. They
/// are spread evenly around the pole, starting upwards, over no more of the
/// ring than keeps every point at least `min_elevation_deg` above the
/// horizontal (points low under the sphere cannot be reached by the moves
/// through the clearance height above it).
pub fn cap_around(pole: &Vec3, count: usize, polar_deg: f64, min_elevation_deg: f64) -> Vec<Vec3> {
    let ring = count.max(2) - 1;
    let polar = polar_deg.to_radians();
    let spread = ring_spread(pole, polar, min_elevation_deg.to_radians(), ring);
    let on_ring = (0..ring).map(|k| {
        let azimuth = if ring == 1 {
            0.0
        } else {
            -spread + 2.0 * spread * k as f64 / (ring - 1) as f64
        };
        let local = Vec3::new(
            polar.sin() * azimuth.cos(),
            polar.sin() * azimuth.sin(),
            polar.cos(),
        );
        turn_to(pole, &local)
    });
    std::iter::once(*pole).chain(on_ring).collect()
}

/// Half the azimuth range (rad, from the upward direction) that `ring`
/// evenly spread points may use: a full even ring when every point of it is
/// high enough, otherwise only the part at or above the lowest elevation.
fn ring_spread(pole: &Vec3, polar: f64, min_elevation: f64, ring: usize) -> f64 {
    let full = PI * (ring as f64 - 1.0) / ring as f64;
    let (sin_p, cos_p) = (pole.z.clamp(-1.0, 1.0), pole.xy().norm());
    let across = cos_p * polar.sin();
    if across < 1e-9 {
        return full;
    }
    let limit = ((min_elevation.sin() - sin_p * polar.cos()) / across).clamp(-1.0, 1.0);
    full.min(limit.acos())
}

/// Outward unit directions of a circle scan in `plane`, `count` + 1 points in
/// scanning order. The XY circle is closed (full turn) at elevation
/// `xy_elevation_deg` above the equator; the XZ and YZ arcs run from
/// `below_deg` under the equator on one side over the pole to the same
/// height on the other side. `ccw` = positive rotation about the plane's
/// normal axis (z, y, x).
pub fn circle_directions(
    plane: ScanPlane,
    count: usize,
    (below_deg, xy_elevation_deg): (f64, f64),
    ccw: bool,
) -> Vec<Vec3> {
    let (start, span) = match plane {
        ScanPlane::Xy => (0.0, 2.0 * PI),
        _ => (-below_deg.to_radians(), PI + 2.0 * below_deg.to_radians()),
    };
    let n = count.max(2);
    let mut dirs: Vec<Vec3> = (0..=n)
        .map(|k| on_circle(plane, start + span * k as f64 / n as f64, xy_elevation_deg))
        .collect();
    if plane == ScanPlane::Xy {
        dirs.pop();
    }
    // The angle increases towards +z from +x (XZ) and +y (YZ): that is a
    // negative rotation about +y for XZ and a positive one about +x for YZ.
    let increasing_is_ccw = plane != ScanPlane::Xz;
    if ccw != increasing_is_ccw {
        dirs.reverse();
    }
    dirs
}

fn on_circle(plane: ScanPlane, a: f64, xy_elevation_deg: f64) -> Vec3 {
    let (c, s) = (a.cos(), a.sin());
    let e = xy_elevation_deg.to_radians();
    match plane {
        ScanPlane::Xy => Vec3::new(c * e.cos(), s * e.cos(), e.sin()),
        ScanPlane::Xz => Vec3::new(c, 0.0, s),
        ScanPlane::Yz => Vec3::new(0.0, c, s),
    }
}
