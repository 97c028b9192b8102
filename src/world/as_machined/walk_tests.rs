//! True deviations along seeded random walks on the blade (the walks of
//! the nominal near-query tests) against a brute-force reference: a dense
//! parameter grid of the true surface with Newton from every grid minimum.
#![allow(dead_code)]
use super::{AsMachined, AsMachinedSpec};
use crate::math::{Point3, Vec2, Vec3};
use crate::workpiece::examples;
use crate::workpiece::walk_support::*;
use crate::workpiece::KnownFoot;
use crate::workpiece::Workpiece;
use rand::rngs::ChaCha8Rng;
use rand::SeedableRng;

/// Every query along the walks, over all faces and over each face
/// alone, finds the brute-force distance (and a foot at that distance).
/// Queries without a hint (the first of a chunk of measured points):
/// random points up to 3 mm off either side of the blade, over all faces
/// and over each face alone, find the brute-force distance.
/// The d25 sphere at the origin: the closest point of `p` is `12.5 p /
/// |p|`, at `| |p| - 12.5 |`, signed positive outside. Walks along great
/// circles through the poles and across the seam, inside and outside.
fn random_unit(r: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            uniform(r, -1.0, 1.0),
            uniform(r, -1.0, 1.0),
            uniform(r, -1.0, 1.0),
        );
        if (0.1..=1.0).contains(&v.norm()) {
            return v.normalize();
        }
    }
}

/// `v` turned by `angle` about the unit `axis` (Rodrigues).
fn rotate(v: Vec3, axis: Vec3, angle: f64) -> Vec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(&v) * s + axis * axis.dot(&v) * (1.0 - c)
}

#[test]
fn true_deviations_along_blade_walks_match_brute_force() {
    let wp = load(&examples::blade());
    let all: Vec<usize> = (0..wp.faces.len()).collect();
    let specs = [
        r#"{"form":[{"kind":"offset","mm":0.02},{"kind":"bump","center_mm":[30,12,60],"radius_mm":8,"height_mm":0.05}]}"#,
        r#"{"transform":{"translate_mm":[0.02,-0.01,0.03],"rotate_deg":[0.01,0,0.02]},
            "form":[{"kind":"waviness","amplitude_mm":0.01,"wavelength_mm":9,"direction":[1,0,0]}]}"#,
    ];
    let mut r = ChaCha8Rng::seed_from_u64(73);
    for (j, json) in specs.iter().enumerate() {
        let spec: AsMachinedSpec = serde_json::from_str(json).unwrap();
        let am = AsMachined::from_spec(&spec, &wp).unwrap();
        let mut hint = None;
        for (k, place) in walk(&mut r, wp.faces.len(), 30, 1.0).iter().enumerate() {
            let m = place.point(&wp);
            let (foot, next) = wp.closest_point_near(m, &all, hint).unwrap();
            hint = next;
            let known = KnownFoot {
                query: m,
                foot,
                hint: next,
            };
            let got = am.true_deviation_near(&wp, m, Some(&known)).unwrap();
            let want = brute_true_deviation(&wp, &am, m);
            assert!(
                (got - want).abs() <= SAME_MM,
                "spec {j} step {k} at {place:?}: {got} vs {want}"
            );
        }
    }
}

/// The nominal signed deviation of the true point nearest to `m`, both
/// found by brute force.
fn brute_true_deviation(wp: &Workpiece, am: &AsMachined, m: Point3) -> f64 {
    let t = grid_params();
    let mut best: Option<(f64, Point3)> = None;
    for face in 0..wp.faces.len() {
        let ((u0, u1), (v0, v1)) = wp.faces[face].surface.domain();
        let at = |a: usize, b: usize| Vec2::new(u0 + (u1 - u0) * t[a], v0 + (v1 - v0) * t[b]);
        let d: Vec<Vec<f64>> = (0..t.len())
            .map(|a| {
                (0..t.len())
                    .map(|b| (am.true_point(wp, face, at(a, b)) - m).norm())
                    .collect()
            })
            .collect();
        for (a, b) in grid_minima(&d) {
            let tp = am.closest_point_from(wp, m, face, at(a, b)).unwrap();
            if best.is_none_or(|b| tp.distance < b.0) {
                best = Some((tp.distance, tp.point));
            }
        }
    }
    let q = best.unwrap().1;
    let all: Vec<usize> = (0..wp.faces.len()).collect();
    brute(wp, &all, q).1.signed_distance
}
