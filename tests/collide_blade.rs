//! The stylus shaft's collision check on the blade's two NURBS faces
//! against an independent reference: the distance from the shaft's axis
//! to the faces by a dense grid of points evaluated from the definition,
//! refined round its best. The blade's pressure side leans over a vertical
//! stylus touching it halfway up, so both outcomes occur.
mod common;

use cmm::geometry::ProjectionOptions;
use cmm::math::{Mat3, Point3, Vec3};
use cmm::program::Pose;
use cmm::seam::ProbePart;
use cmm::workpiece::{SurfaceSpec, WorkpieceFile};
use cmm::world::as_machined::AsMachined;
use cmm::world::cmm::{contact_options, TruePart};
use cmm::world::collision::{ProbeCollisions, Stylus};
use cmm::world::contact::{CollisionOptions, ContactOptions, ContactSearch};
use cmm::world::probe::{ProbeShape, TrueProbe};
use common::*;

const R: f64 = 1.5;
const RS: f64 = 0.5;
const STYLUS: f64 = 50.0;

/// Points of a face on an `n` x `n` parameter grid, with their parameters.
fn grid(s: &SurfaceSpec, n: usize) -> Vec<(f64, f64, Point3)> {
    let (u0, u1) = (s.knots_u[0], *s.knots_u.last().unwrap());
    let (v0, v1) = (s.knots_v[0], *s.knots_v.last().unwrap());
    let mut out = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let u = u0 + (u1 - u0) * i as f64 / n as f64;
            let v = v0 + (v1 - v0) * j as f64 / n as f64;
            out.push((u, v, Point3::from(reference_point(s, u, v))));
        }
    }
    out
}

fn segment_distance(a: Point3, b: Point3, q: Point3) -> f64 {
    let d = b - a;
    let t = ((q - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (q - (a + d * t)).norm()
}

/// The least distance from the segment `a..b` to the face `s`: the best
/// of the grid, then finer grids round the best.
fn reference(
    s: &SurfaceSpec,
    points: &[(f64, f64, Point3)],
    a: Point3,
    b: Point3,
    n: usize,
) -> f64 {
    let (u0, u1) = (s.knots_u[0], *s.knots_u.last().unwrap());
    let (v0, v1) = (s.knots_v[0], *s.knots_v.last().unwrap());
    let mut best = points
        .iter()
        .map(|&(u, v, q)| (segment_distance(a, b, q), u, v))
        .fold(
            (f64::INFINITY, 0.0, 0.0),
            |x, y| if y.0 < x.0 { y } else { x },
        );
    let (mut du, mut dv) = ((u1 - u0) / n as f64, (v1 - v0) / n as f64);
    for _ in 0..6 {
        let (cu, cv) = (best.1, best.2);
        for i in -10..=10 {
            for j in -10..=10 {
                let u = (cu + du * i as f64 / 10.0).clamp(u0, u1);
                let v = (cv + dv * j as f64 / 10.0).clamp(v0, v1);
                let q = Point3::from(reference_point(s, u, v));
                let d = segment_distance(a, b, q);
                if d < best.0 {
                    best = (d, u, v);
                }
            }
        }
        (du, dv) = (du / 5.0, dv / 5.0);
    }
    best.0
}

/// The shipped blade tapers without a twist (a vertical stylus reaches all
/// of it). Twisted here by 3 degrees per 20 mm of span about the profile's
/// centre (30, 5), control point by control point (a rotation about a
/// vertical axis maps the B-spline exactly), it overhangs its own sections
/// near the edges, where a vertical shaft strikes it.
fn twist(file: &mut WorkpieceFile) {
    for s in &mut file.surfaces {
        for row in &mut s.control_points {
            for p in row.iter_mut() {
                let (sin, cos) = (3.0 * p[2] / 20.0f64).to_radians().sin_cos();
                let (dx, dy) = (p[0] - 30.0, p[1] - 5.0);
                (p[0], p[1]) = (30.0 + cos * dx - sin * dy, 5.0 + sin * dx + cos * dy);
            }
        }
    }
}

/// Vertical styli whose ball sits 0.05-1 mm off a random point of either
/// face between z = 55 and 65 (the mount above the blade's top, z = 100):
/// a shaft collision exactly where the reference puts the shaft's axis
/// within its radius of a face.
#[test]
fn shaft_collisions_on_the_blade_match_a_dense_search() {
    let path = repo("workpieces/blade.json");
    let mut file: WorkpieceFile =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    twist(&mut file);
    let wp = common::from_file(&file);
    let am = AsMachined::nominal();
    let search = ContactSearch::new(&wp, &am, &ContactOptions::default());
    let mut ball_search = ContactSearch::new(&wp, &am, &ContactOptions::default());
    let part = TruePart {
        workpiece: &wp,
        as_machined: &am,
        pose: Pose {
            rotation: Mat3::identity(),
            translation: Vec3::zeros(),
        },
    };
    let pv = Vec3::new(0.0, 0.0, -STYLUS);
    let mut probe = TrueProbe::ideal(pv, R);
    probe.shape = ProbeShape {
        shaft_radius_mm: RS,
        ..ProbeShape::common(R)
    };
    let copts = CollisionOptions::default();
    let mut checks = ProbeCollisions::new(&probe, &ContactOptions::default(), &copts);
    let opts = contact_options(&ProjectionOptions::default());
    let n = 150;
    let grids: Vec<_> = file.surfaces.iter().map(|s| grid(s, n)).collect();
    let lift = (R * R - RS * RS).sqrt();
    let mut r = rng(17);
    let (mut struck, mut clear) = (0, 0);
    while struck + clear < 80 {
        let s = &file.surfaces[(struck + clear) % 2];
        let (u, v) = (uniform(&mut r, 0.02, 0.98), uniform(&mut r, 0.0, 1.0));
        let q = Point3::from(reference_point(s, u, v));
        if !(55.0..=65.0).contains(&q.z) {
            continue;
        }
        let h = 1e-6;
        let qu = Point3::from(reference_point(s, u + h, v)) - q;
        let qv = Point3::from(reference_point(s, u, v + h)) - q;
        let normal = qu.cross(&qv).normalize();
        let off = R + uniform(&mut r, 0.05, 1.0);
        // The side of the face outside the material (the ball contact's
        // sign), the ball clear of both faces.
        let outside = [normal, -normal].into_iter().find(|&nn| {
            let c = q + nn * off;
            let found = ball_search.query((&wp, &am), c, 3.0, &opts).unwrap();
            found.is_some_and(|t| t.distance > R)
        });
        let Some(nn) = outside else { continue };
        let ball = q + nn * off;
        let (a, b) = (ball + Vec3::z() * lift, ball + Vec3::z() * STYLUS);
        let want = file
            .surfaces
            .iter()
            .zip(&grids)
            .map(|(s, g)| reference(s, g, a, b, n))
            .fold(f64::INFINITY, f64::min)
            - RS;
        let got = checks.check(
            (&search, &part),
            (ball, Vec3::zeros(), &Stylus::new(pv)),
            &opts,
        );
        let pen = copts.penetration_mm;
        if want < -2.0 * pen {
            let (which, strike) = got.unwrap_or_else(|| panic!("{ball}: no strike at {want}"));
            assert_eq!(which, ProbePart::Shaft);
            let off_axis = segment_distance(a, b, strike.point);
            // The foot of a point of the shaft inside the material, as deep.
            assert!(
                off_axis < RS + strike.depth_mm + 1e-9,
                "{ball}: strike {strike:?}"
            );
            struck += 1;
        } else if want > pen {
            assert!(got.is_none(), "{ball}: {got:?} at clearance {want}");
            clear += 1;
        }
    }
    eprintln!("{struck} struck, {clear} clear");
    assert!(struck > 5 && clear > 5, "{struck} struck, {clear} clear");
}
