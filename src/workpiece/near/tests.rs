//! The queries started from an earlier foot against independent
//! references: the analytic sphere, and on the blade a brute-force search
//! (a dense parameter grid, denser towards the edges where the blade turns
//! sharply, with Newton from every grid point no farther than its
//! neighbours). Seeded random walks over the faces, on both sides of the
//! surface, across leaf boundaries, round the blade's edges from one face
//! to the other, and jumping to random places.
use super::walk::*;
use crate::geometry::Projection;
use crate::math::{Point3, Vec3};
use crate::workpiece::examples;
use rand::rngs::ChaCha8Rng;
use rand::SeedableRng;

#[test]
fn blade_walks_find_the_brute_force_distance() {
    let wp = load(&examples::blade());
    let all: Vec<usize> = (0..wp.faces.len()).collect();
    let mut r = ChaCha8Rng::seed_from_u64(71);
    let mut checked = 0;
    for _ in 0..3 {
        let mut hints = [None; 3];
        for (k, place) in walk(&mut r, wp.faces.len(), 60, 3.0).iter().enumerate() {
            let p = place.point(&wp);
            let per_face: Vec<Projection> = all.iter().map(|&i| brute_face(&wp, i, p)).collect();
            for (q, faces) in [all.clone(), vec![0], vec![1]].iter().enumerate() {
                let (near, next) = wp.closest_point_near(p, faces, hints[q]).unwrap();
                hints[q] = next;
                let want = faces
                    .iter()
                    .map(|&i| per_face[i].distance)
                    .fold(f64::INFINITY, f64::min);
                let got = near.projection;
                assert!(
                    (got.distance - want).abs() <= SAME_MM,
                    "step {k} faces {faces:?} at {place:?}: {} vs {want}",
                    got.distance
                );
                assert!(
                    ((got.point - p).norm() - want).abs() <= 1e-8,
                    "step {k}: foot"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 3 * 60 * 3);
}

/// Queries without a hint (the first of a chunk of measured points):
/// random points up to 3 mm off either side of the blade, over all faces
/// and over each face alone, find the brute-force distance.
#[test]
fn blade_queries_without_a_hint_find_the_brute_force_distance() {
    let wp = load(&examples::blade());
    let all: Vec<usize> = (0..wp.faces.len()).collect();
    let mut r = ChaCha8Rng::seed_from_u64(74);
    for k in 0..60 {
        let place = Place::random(&mut r, wp.faces.len(), 3.0);
        let p = place.point(&wp);
        let per_face: Vec<Projection> = all.iter().map(|&i| brute_face(&wp, i, p)).collect();
        for faces in [all.clone(), vec![0], vec![1]] {
            let (got, hint) = wp.closest_point_near(p, &faces, None).unwrap();
            let want = (faces.iter().map(|&i| per_face[i].distance)).fold(f64::INFINITY, f64::min);
            assert!(
                (got.projection.distance - want).abs() <= SAME_MM,
                "case {k} faces {faces:?} at {place:?}: {} vs {want}",
                got.projection.distance
            );
            assert!(hint.is_some_and(|h| h.face == got.face), "case {k}: hint");
        }
    }
}

/// The d25 sphere at the origin: the closest point of `p` is `12.5 p /
/// |p|`, at `| |p| - 12.5 |`, signed positive outside. Walks along great
/// circles through the poles and across the seam, inside and outside.
#[test]
fn sphere_walks_find_the_analytic_foot() {
    let wp = load(&examples::reference_sphere(25.0));
    let all = [0];
    let mut r = ChaCha8Rng::seed_from_u64(72);
    for walk in 0..6 {
        let (a, b) = (random_unit(&mut r), random_unit(&mut r));
        let axis = a.cross(&b).normalize();
        let start = axis.cross(&random_unit(&mut r)).normalize();
        let mut hint = None;
        for k in 0..200 {
            let angle = 0.04 * k as f64;
            let dir = rotate(start, axis, angle);
            let radius = 12.5 + 2.0 * (0.37 * k as f64 + walk as f64).sin();
            let p = Point3::from(dir * radius);
            let (near, next) = wp.closest_point_near(p, &all, hint).unwrap();
            hint = next;
            let got = near.projection;
            assert!(
                (got.signed_distance - (radius - 12.5)).abs() <= SAME_MM,
                "walk {walk} step {k}"
            );
            assert!(
                (got.point.coords - dir * 12.5).norm() <= 1e-8,
                "walk {walk} step {k}: foot"
            );
        }
    }
}

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
