//! The as-machined model against analytic spheres and finite differences.
mod common;

use cmm::math::{Point3, Vec2, Vec3};
use cmm::world::as_machined::{AsMachined, AsMachinedSpec, TrueWarm};
use cmm::world::cmm::contact_options;
use common::*;

fn spec(json: &str) -> AsMachinedSpec {
    serde_json::from_str(json).unwrap()
}

fn random_point_near_sphere(r: &mut TestRng, centre: Point3, radius: f64) -> Point3 {
    let dir = random_direction(r);
    centre + dir * (radius + uniform(r, -3.0, 3.0))
}

#[test]
fn offset_sphere_has_the_offset_radius() {
    let wp = example("sphere");
    let am = AsMachined::from_spec(&spec(r#"{"form":[{"kind":"offset","mm":0.4}]}"#), &wp).unwrap();
    let mut r = rng(31);
    for k in 0..500 {
        let p = random_point_near_sphere(&mut r, Point3::origin(), 12.9);
        let want = p.coords.norm() - 12.9;
        let got = am.closest_point(&wp, p).unwrap();
        assert!(
            (got.signed_distance - want).abs() < 1e-10,
            "case {k}: {} vs {want}",
            got.signed_distance
        );
        // The true deviation of a point on the true surface is the offset.
        let dev = am.true_deviation(&wp, got.point).unwrap();
        assert!((dev - 0.4).abs() < 1e-10, "case {k}: true deviation {dev}");
    }
}

#[test]
fn scaled_rotated_translated_sphere() {
    let wp = example("sphere");
    let json = r#"{"transform":{"translate_mm":[1,-2,0.5],"rotate_deg":[10,20,30],"scale":1.03,"about_mm":[5,0,0]}}"#;
    let am = AsMachined::from_spec(&spec(json), &wp).unwrap();
    // Centre: R (S (0 - c)) + c + t with S = 1.03.
    let rot = cmm::math::rotation_xyz_deg([10.0, 20.0, 30.0]);
    let c = Vec3::new(5.0, 0.0, 0.0);
    let centre = Point3::from(rot * (-c * 1.03) + c + Vec3::new(1.0, -2.0, 0.5));
    let radius = 12.5 * 1.03;
    let mut r = rng(32);
    for k in 0..500 {
        let p = random_point_near_sphere(&mut r, centre, radius);
        let want = (p - centre).norm() - radius;
        let got = am.closest_point(&wp, p).unwrap();
        assert!(
            (got.signed_distance - want).abs() < 1e-10,
            "case {k}: {} vs {want}",
            got.signed_distance
        );
    }
}

#[test]
fn per_axis_scale_maps_points_exactly() {
    let wp = example("bore");
    let am =
        AsMachined::from_spec(&spec(r#"{"transform":{"scale":[1.01,0.99,1.0]}}"#), &wp).unwrap();
    let s = &wp.faces[0].surface;
    let p = s.point(0.1, 0.3);
    let q = am.true_point(&wp, 0, Vec2::new(0.1, 0.3));
    assert!((q - Point3::new(p.x * 1.01, p.y * 0.99, p.z)).norm() < 1e-12);
}

/// Exact second derivatives of q(u, v) (which use third NURBS derivatives
/// and the derivatives of the unit normal) against finite differences.
#[test]
fn displaced_surface_derivatives_agree_with_finite_differences() {
    let wp = example("blade");
    let json = r#"{"form":[{"kind":"bump","center_mm":[30,8,50],"radius_mm":12,"height_mm":0.8},
        {"kind":"waviness","amplitude_mm":0.05,"wavelength_mm":7,"direction":[1,0.2,0.1],"phase_deg":30},
        {"kind":"offset","mm":-0.2,"surfaces":["suction"]}],
        "transform":{"rotate_deg":[0,0,2],"scale":[1.01,1.0,0.99]}}"#;
    let am = AsMachined::from_spec(&spec(json), &wp).unwrap();
    let mut r = rng(33);
    let h = 1e-6;
    for face in 0..2 {
        for _ in 0..50 {
            let uv = Vec2::new(uniform(&mut r, 0.05, 0.95), uniform(&mut r, 0.05, 0.95));
            let d = am.derivs(&wp, face, uv, 2);
            let (up, um) = (
                am.derivs(&wp, face, uv + Vec2::new(h, 0.0), 2),
                am.derivs(&wp, face, uv - Vec2::new(h, 0.0), 2),
            );
            let (vp, vm) = (
                am.derivs(&wp, face, uv + Vec2::new(0.0, h), 2),
                am.derivs(&wp, face, uv - Vec2::new(0.0, h), 2),
            );
            let scale =
                1.0 + d.d[1][0].norm() + d.d[0][1].norm() + d.d[2][0].norm() + d.d[0][2].norm();
            let checks = [
                ((up.point() - um.point()) / (2.0 * h), d.su()),
                ((vp.point() - vm.point()) / (2.0 * h), d.sv()),
                ((up.su() - um.su()) / (2.0 * h), d.suu()),
                ((vp.su() - vm.su()) / (2.0 * h), d.suv()),
                ((vp.sv() - vm.sv()) / (2.0 * h), d.svv()),
            ];
            for (k, (fd, exact)) in checks.iter().enumerate() {
                assert!(
                    (fd - exact).norm() < 2e-5 * scale,
                    "face {face} check {k} at {uv:?}: {fd} vs {exact}"
                );
            }
        }
    }
}

#[test]
fn warm_and_cold_true_distances_agree_along_a_path() {
    let wp = example("blade");
    let json = r#"{"form":[{"kind":"bump","center_mm":[30,8,50],"radius_mm":10,"height_mm":1.0}]}"#;
    let am = AsMachined::from_spec(&spec(json), &wp).unwrap();
    let s = &wp.faces[1].surface;
    let mut hint = (1usize, Vec2::new(0.2, 0.5));
    for k in 0..400 {
        let t = 0.2 + 0.6 * k as f64 / 400.0;
        let x = s.point(t, 0.5) + s.normal(t, 0.5) * 1.3;
        let warm = am.closest_point_from(&wp, x, hint.0, hint.1).unwrap();
        let cold = am.closest_point(&wp, x).unwrap();
        assert!(
            (warm.distance - cold.distance).abs() < 1e-10,
            "step {k}: {} vs {}",
            warm.distance,
            cold.distance
        );
        hint = (warm.face, warm.uv);
    }
}

/// The simulator's per-cycle contact search (cached derivatives, looser
/// last-step rule) against the cold search, 0.08 mm per cycle over a bump.
#[test]
fn contact_search_along_a_path_matches_the_cold_search() {
    let wp = example("blade");
    let json = r#"{"form":[{"kind":"bump","center_mm":[30,8,50],"radius_mm":10,"height_mm":1.0},
        {"kind":"waviness","amplitude_mm":0.05,"wavelength_mm":7,"direction":[1,0,0.3],"phase_deg":10}]}"#;
    let am = AsMachined::from_spec(&spec(json), &wp).unwrap();
    let s = &wp.faces[1].surface;
    let opts = contact_options(&wp.options);
    let first = s.point(0.2, 0.5) + s.normal(0.2, 0.5) * 1.2;
    let mut warm = TrueWarm::new(1, am.closest_point(&wp, first).unwrap().uv);
    let (mut t, mut k) = (0.2f64, 0);
    while t < 0.8 {
        let v = 0.5 + 0.2 * (5.0 * t).sin();
        let x = s.point(t, v) + s.normal(t, v) * (1.2 + 0.2 * (9.0 * t).cos());
        let along = am.closest_point_along(&wp, x, &mut warm, &opts).unwrap();
        let cold = am.closest_point(&wp, x).unwrap();
        assert!(
            (along.distance - cold.distance).abs() < 1e-7 * 1e-3,
            "cycle {k}"
        );
        assert!(
            (along.normal - cold.normal).norm() < 1e-6,
            "normal at cycle {k}"
        );
        t += 0.08 / s.derivs(t, v, 1).su().norm();
        k += 1;
    }
    assert!(k > 300, "{k} cycles");
}

#[test]
fn bump_height_is_reached_at_its_centre() {
    let wp = example("panel");
    let s = &wp.faces[0].surface;
    let c = s.point(0.5, 0.5);
    let json = format!(
        r#"{{"form":[{{"kind":"bump","center_mm":[{},{},{}],"radius_mm":8,"height_mm":0.3}}]}}"#,
        c.x, c.y, c.z
    );
    let am = AsMachined::from_spec(&spec(&json), &wp).unwrap();
    let q = am.true_point(&wp, 0, Vec2::new(0.5, 0.5));
    assert!((q - (c + s.normal(0.5, 0.5) * 0.3)).norm() < 1e-12);
    let dev = am.true_deviation(&wp, q).unwrap();
    assert!((dev - 0.3).abs() < 1e-9, "{dev}");
}

#[test]
fn invalid_specs_name_the_place() {
    let wp = example("blade");
    let cases = [
        (
            r#"{"form":[{"kind":"bump","center_mm":[0,0,0],"radius_mm":-1,"height_mm":1}]}"#,
            "form[0].radius_mm",
        ),
        (
            r#"{"form":[{"kind":"offset","mm":1},{"kind":"offset","mm":1,"surfaces":["nope"]}]}"#,
            "form[1].surfaces[0]",
        ),
        (
            r#"{"form":[{"kind":"waviness","amplitude_mm":1,"wavelength_mm":5,"direction":[0,0,0]}]}"#,
            "form[0].direction",
        ),
        (r#"{"transform":{"scale":[1,0,1]}}"#, "transform.scale"),
        (r#"{"roughness_um":-2}"#, "roughness_um"),
    ];
    for (json, path) in cases {
        let e = AsMachined::from_spec(&spec(json), &wp).unwrap_err();
        assert_eq!(e.json_path, path, "{json}");
    }
    assert!(serde_json::from_str::<AsMachinedSpec>(
        r#"{"form":[{"kind":"offset","mm":1,"extra":2}]}"#
    )
    .is_err());
    assert!(
        serde_json::from_str::<AsMachinedSpec>(r#"{"form":[{"kind":"dent","mm":1}]}"#).is_err()
    );
}

/// An oracle independent of the Newton evaluation: points set off the
/// as-machined surface along its exact normal (from the exact derivative
/// table, `Qu x Qv`) project back to where they were set off from, at that
/// distance, with the per-cycle contact search and with the cold search.
/// Large bump, waviness and a transform, so the normal's curvature terms
/// that the Newton evaluation leaves out are large.
#[test]
fn points_off_the_true_normal_project_back_to_their_foot() {
    let wp = example("blade");
    let json = r#"{"form":[{"kind":"bump","center_mm":[30,8,50],"radius_mm":10,"height_mm":1.5},
        {"kind":"waviness","amplitude_mm":0.08,"wavelength_mm":6,"direction":[1,0.2,0.1],"phase_deg":30}],
        "transform":{"rotate_deg":[0,1,2],"scale":1.01}}"#;
    let am = AsMachined::from_spec(&spec(json), &wp).unwrap();
    let opts = contact_options(&wp.options);
    let mut r = rng(17);
    for face in 0..2 {
        let sign = if wp.faces[face].surface.is_reversed() {
            -1.0
        } else {
            1.0
        };
        for _ in 0..200 {
            let uv = Vec2::new(uniform(&mut r, 0.2, 0.8), uniform(&mut r, 0.1, 0.9));
            let q = am.derivs(&wp, face, uv, 1);
            let n = q.su().cross(&q.sv()).normalize() * sign;
            let d = uniform(&mut r, -0.3, 1.5);
            let x = q.point() + n * d;
            let cold = am.closest_point(&wp, x).unwrap();
            let start = uv + Vec2::new(uniform(&mut r, -0.01, 0.01), uniform(&mut r, -0.01, 0.01));
            let mut warm = TrueWarm::new(face, start);
            let along = am.closest_point_along(&wp, x, &mut warm, &opts).unwrap();
            for (what, tp) in [("cold", cold), ("contact", along)] {
                assert!(
                    (tp.signed_distance - d).abs() < 1e-9,
                    "{what} face {face} at {uv:?}: {} vs {d}",
                    tp.signed_distance
                );
                assert!(
                    (tp.point - q.point()).norm() < 1e-6,
                    "{what} foot at {uv:?}"
                );
            }
        }
    }
}

/// Beyond a face's edge the per-cycle search falls back to the cold one,
/// with its nominal search started from the previous cycle's
/// (`closest_point_seeded`): along paths 0.5-3 mm past an edge of the
/// panel (one face) and past the blade's ends (two faces, meeting at its
/// edges), it gives the cold search's foot and distance at every cycle.
#[test]
fn seeded_search_past_an_edge_matches_the_cold_search() {
    let json = r#"{"form":[{"kind":"bump","center_mm":[30,8,50],"radius_mm":10,"height_mm":0.4},
        {"kind":"waviness","amplitude_mm":0.05,"wavelength_mm":7,"direction":[1,0,0.3],"phase_deg":10}],
        "transform":{"rotate_deg":[0.2,0.1,0.3],"scale":1.001}}"#;
    let mut fallbacks = 0;
    for (name, face, past_v) in [("panel", 0, false), ("blade", 0, true), ("blade", 1, true)] {
        let wp = example(name);
        let am = AsMachined::from_spec(&spec(json), &wp).unwrap();
        let opts = contact_options(&wp.options);
        let s = &wp.faces[face].surface;
        let ((u0, u1), (v0, v1)) = s.domain();
        // Off the edge u = u0 (panel) or v = v1 (blade), along the other
        // parameter, at a height over the surface.
        let beyond = |t: f64| {
            let (u, v) = if past_v {
                (u0 + (u1 - u0) * t, v1)
            } else {
                (u0, v0 + (v1 - v0) * t)
            };
            let d = s.derivs(u, v, 1);
            let out = if past_v { d.sv() } else { -d.su() };
            let gap = 0.5 + 2.5 * (7.0 * t).sin().abs();
            d.point() + out.normalize() * gap + s.normal(u, v) * (0.3 * (5.0 * t).cos())
        };
        let first = beyond(0.1);
        let mut warm = TrueWarm::new(face, am.closest_point(&wp, first).unwrap().uv);
        let mut seeds = None;
        let mut t = 0.1;
        while t < 0.9 {
            let x = beyond(t);
            let cold = am.closest_point(&wp, x).unwrap();
            let seeded = am.closest_point_seeded(&wp, x, &mut seeds).unwrap();
            let along = am.closest_point_along(&wp, x, &mut warm, &opts).unwrap();
            fallbacks += usize::from(warm.seeds.is_some());
            for (what, tp) in [("seeded", seeded), ("contact", along)] {
                assert!(
                    (tp.distance - cold.distance).abs() < 1e-10,
                    "{name} face {face} t {t}: {what} {} vs cold {}",
                    tp.distance,
                    cold.distance
                );
                assert!((tp.point - cold.point).norm() < 1e-6, "{what} foot at {t}");
            }
            t += 0.002;
        }
    }
    assert!(fallbacks > 500, "only {fallbacks} cycles fell back");
}
