//! The world's per-cycle contact distance on a block with a pocket made of
//! trimmed planes, against the analytic signed distance of the solid: no
//! lid over the pocket, the right sign at convex and concave edges and
//! corners, inside and outside the material, and the as-machined transform
//! and form terms applied to the trimmed faces.
mod common;

use cmm::geometry::ProjectionOptions;
use cmm::math::{Point3, Vec3};
use cmm::workpiece::Workpiece;
use cmm::world::as_machined::{AsMachined, AsMachinedSpec};
use cmm::world::cmm::contact_options;
use cmm::world::contact::{ContactOptions, ContactSearch};
use common::*;

/// The block [0, 100]^2 x [0, 50] less the pocket [25, 75]^2 x [30, 50].
const POCKET: ([f64; 2], [f64; 2]) = ([25.0, 75.0], [30.0, 50.0]);

/// Distance from `p` to the box `[lo, hi]` (zero inside).
fn box_distance(p: Point3, lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let d = Vec3::from_fn(|k, _| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0));
    d.norm()
}

/// The exact signed distance of the solid (positive outside): the solid is
/// the union of five boxes (floor slab and four walls), its complement the
/// outside of the block and the (open-topped) pocket.
fn reference(p: Point3) -> f64 {
    let ([a, b], [z0, z1]) = POCKET;
    let solid = [
        ([0., 0., 0.], [100., 100., z0]),
        ([0., 0., z0], [a, 100., z1]),
        ([b, 0., z0], [100., 100., z1]),
        ([a, 0., z0], [b, a, z1]),
        ([a, b, z0], [b, 100., z1]),
    ];
    let outside = solid
        .iter()
        .map(|(lo, hi)| box_distance(p, *lo, *hi))
        .fold(f64::INFINITY, f64::min);
    if outside > 0.0 {
        return outside;
    }
    let to_block_faces = [p.x, 100.0 - p.x, p.y, 100.0 - p.y, p.z, z1 - p.z]
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let to_pocket = box_distance(p, [a, a, z0], [b, b, 1e9]);
    -to_block_faces.min(to_pocket)
}

fn search_for(wp: &Workpiece, am: &AsMachined) -> ContactSearch {
    ContactSearch::new(wp, am, &ContactOptions::default())
}

fn opts() -> ProjectionOptions {
    contact_options(&ProjectionOptions::default())
}

/// The world's distance, or `None` beyond `reach`.
fn world(
    s: &mut ContactSearch,
    wp: &Workpiece,
    am: &AsMachined,
    p: Point3,
    reach: f64,
) -> Option<f64> {
    let found = s
        .query((wp, am), p, reach, &opts())
        .unwrap_or_else(|e| panic!("{e}"));
    found.map(|c| c.distance)
}

/// Above the pocket at the height of the top face (and anywhere in it)
/// there is no material: no lid.
#[test]
fn no_lid_over_the_pocket() {
    let wp = block_with_pocket(POCKET.0[0], POCKET.0[1], POCKET.1[0]);
    let am = AsMachined::nominal();
    let mut s = search_for(&wp, &am);
    // 17.9 mm inside the pocket's rim, at the top face's height: 17.9 mm
    // from the wall, 20 mm above the floor.
    let p = Point3::new(25.0 + 17.9, 50.0, 50.0);
    assert_eq!(world(&mut s, &wp, &am, p, 2.0), None);
    let d = world(&mut s, &wp, &am, p, 30.0).unwrap();
    assert!((d - 17.9).abs() < 1e-9, "{d}");
    // The pocket's centre line down to near the floor.
    for k in 0..40 {
        let p = Point3::new(50.0, 50.0, 60.0 - 0.7 * k as f64);
        let want = reference(p);
        match world(&mut s, &wp, &am, p, 2.0) {
            None => assert!(want >= 2.0, "{p}: {want}"),
            Some(d) => assert!((d - want).abs() < 1e-9, "{p}: {d} vs {want}"),
        }
    }
}

/// Random points within 3 mm of the surface, thick near the edges and
/// corners of the pocket and of the block, inside and outside.
#[test]
fn distances_match_the_analytic_solid() {
    let wp = block_with_pocket(POCKET.0[0], POCKET.0[1], POCKET.1[0]);
    let am = AsMachined::nominal();
    let mut s = search_for(&wp, &am);
    let mut r = rng(11);
    let corners = [
        [25.0, 25.0, 50.0],
        [75.0, 75.0, 30.0],
        [25.0, 75.0, 30.0],
        [0.0, 0.0, 50.0],
        [100.0, 0.0, 0.0],
        [75.0, 50.0, 50.0],
        [50.0, 25.0, 30.0],
        [0.0, 50.0, 50.0],
    ];
    let mut checked = (0, 0, 0);
    for k in 0..4000 {
        let c = corners[k % corners.len()];
        let p = Point3::new(
            c[0] + uniform(&mut r, -3.0, 3.0),
            c[1] + uniform(&mut r, -3.0, 3.0),
            c[2] + uniform(&mut r, -3.0, 3.0),
        );
        let want = reference(p);
        let reach = 2.5;
        match world(&mut s, &wp, &am, p, reach) {
            None => assert!(want.abs() >= reach - 1e-9, "{p}: none, want {want}"),
            Some(d) => {
                assert!((d - want).abs() < 1e-9, "{p}: {d} vs {want}");
                if want < 0.0 {
                    checked.0 += 1;
                } else {
                    checked.1 += 1;
                }
            }
        }
        checked.2 += 1;
    }
    assert!(checked.0 > 500 && checked.1 > 500, "{checked:?}");
}

/// A rigid motion with a uniform scale `T` maps the solid exactly: the
/// distance to `T(S)` at `y` is `s` times that of `T^-1(y)` to `S`.
#[test]
fn transform_moves_the_trimmed_solid() {
    let wp = block_with_pocket(POCKET.0[0], POCKET.0[1], POCKET.1[0]);
    let spec: AsMachinedSpec = serde_json::from_str(
        r#"{ "transform": { "rotate_deg": [3, -2, 10], "translate_mm": [0.5, -0.2, 0.1],
             "scale": 1.001, "about_mm": [50, 50, 25] } }"#,
    )
    .unwrap();
    let am = AsMachined::from_spec(&spec, &wp).unwrap();
    let mut s = search_for(&wp, &am);
    let mut r = rng(5);
    let scale = 1.001;
    let centre = Point3::new(50.0, 50.0, 25.0);
    let rot = nalgebra::Rotation3::from_euler_angles(
        3f64.to_radians(),
        (-2f64).to_radians(),
        10f64.to_radians(),
    );
    let t = Vec3::new(0.5, -0.2, 0.1);
    let inverse = |y: Point3| centre + (rot.inverse() * (y - centre - t)) / scale;
    let mut hits = 0;
    for k in 0..2000 {
        let c = [[25.0, 25.0, 50.0], [75.0, 75.0, 30.0], [50.0, 0.0, 50.0]][k % 3];
        let nominal = Point3::new(
            c[0] + uniform(&mut r, -3.0, 3.0),
            c[1] + uniform(&mut r, -3.0, 3.0),
            c[2] + uniform(&mut r, -3.0, 3.0),
        );
        let y = am.transform_point(nominal);
        let want = scale * reference(inverse(y));
        if let Some(d) = world(&mut s, &wp, &am, y, 2.5) {
            assert!((d - want).abs() < 1e-8, "{y}: {d} vs {want}");
            hits += 1;
        } else {
            assert!(want.abs() >= 2.5 - 1e-8, "{y}: none, want {want}");
        }
    }
    assert!(hits > 1000, "{hits}");
}

/// A bump and an offset on the trimmed top face: `q = p + h(p) n` there;
/// the distance from points above the face's interior against a dense
/// search over the displaced face (grid, then a finer grid round its best).
#[test]
fn form_terms_act_on_the_trimmed_face() {
    let wp = block_with_pocket(POCKET.0[0], POCKET.0[1], POCKET.1[0]);
    let spec: AsMachinedSpec = serde_json::from_str(
        r#"{ "form": [ { "kind": "offset", "mm": 0.02 },
                       { "kind": "bump", "center_mm": [12, 50, 50], "radius_mm": 4, "height_mm": 0.05,
                         "surfaces": ["top"] } ] }"#,
    )
    .unwrap();
    let am = AsMachined::from_spec(&spec, &wp).unwrap();
    let h = |x: f64, y: f64| {
        let d2 = (x - 12.0).powi(2) + (y - 50.0).powi(2);
        0.02 + 0.05 * (-d2 / 16.0).exp()
    };
    let dense = |p: Point3| {
        let mut best = (f64::INFINITY, p.x, p.y);
        for step in [0.05, 0.002, 0.00008, 0.0000032] {
            let (cx, cy) = (best.1, best.2);
            for i in -25..=25 {
                for j in -25..=25 {
                    let (x, y) = (cx + step * i as f64, cy + step * j as f64);
                    let q = Point3::new(x, y, 50.0 + h(x, y));
                    let d = (q - p).norm();
                    if d < best.0 {
                        best = (d, x, y);
                    }
                }
            }
        }
        best.0
    };
    let mut s = search_for(&wp, &am);
    let mut r = rng(9);
    for _ in 0..60 {
        let p = Point3::new(
            uniform(&mut r, 7.0, 17.0),
            uniform(&mut r, 45.0, 55.0),
            uniform(&mut r, 50.5, 51.8),
        );
        let d = world(&mut s, &wp, &am, p, 2.5).unwrap();
        let want = dense(p);
        assert!((d - want).abs() < 1e-8, "{p}: {d} vs {want}");
    }
}

/// The simulated machine lowers the ball into the pocket at 20 mm/s, 17.9
/// mm inside its rim: no deflection in the pocket (no lid at the top
/// face's height) until the ball meets the floor, then the deflection the
/// analytic floor gives; every cycle is checked against the analytic
/// solid (the free-air bound must never skip a contact).
#[test]
fn the_machine_feels_no_lid_and_meets_the_floor() {
    use cmm::machine::{MachineModel, MachineProfile};
    use cmm::program::Pose;
    use cmm::seam::Cmm;
    use cmm::world::cmm::{SimulatedCmm, TruePart};
    use cmm::world::probe::TrueProbe;
    let wp = block_with_pocket(POCKET.0[0], POCKET.0[1], POCKET.1[0]);
    let am = AsMachined::nominal();
    let pose = Pose {
        rotation: cmm::math::Mat3::identity(),
        translation: Vec3::new(350.0, 500.0, 20.0),
    };
    let part = TruePart {
        workpiece: &wp,
        as_machined: &am,
        pose,
    };
    let (r, pv) = (1.5, Vec3::new(0.0, 0.0, -50.0));
    let probe = TrueProbe::ideal(pv, r);
    let ball0 = Point3::new(25.0 + 17.9, 50.0, 60.0);
    let start = pose.to_machine(ball0) - pv;
    let profile = MachineProfile::default().ideal();
    let mut sim = SimulatedCmm::new(
        part,
        MachineModel::default_bridge(),
        profile,
        probe,
        1,
        start,
    )
    .unwrap();
    let mut touched = 0;
    for _ in 0..4000 {
        let readings = sim.step(Vec3::new(0.0, 0.0, -20.0));
        let ball = pose.to_part(readings.scales + pv);
        let depth = r - reference(ball);
        let d = readings.deflection.norm();
        if depth <= 0.0 {
            assert_eq!(d, 0.0, "deflection {d} at {ball} in free air");
        } else {
            assert!((d - depth).abs() < 1e-6, "{ball}: {d} vs {depth}");
            touched += 1;
            if depth > 0.5 {
                break;
            }
        }
    }
    assert!(touched > 10, "{touched}");
}
