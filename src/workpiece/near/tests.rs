//! The queries started from an earlier foot against independent
//! references: the analytic sphere, and on the blade a brute-force search
//! (a dense parameter grid, denser towards the edges where the blade turns
//! sharply, with Newton from every grid point no farther than its
//! neighbours). Seeded random walks over the faces, on both sides of the
//! surface, across leaf boundaries, round the blade's edges from one face
//! to the other, and jumping to random places.
use crate::geometry::projection::project_from;
use crate::geometry::Projection;
use crate::math::{Point3, Vec2, Vec3};
use crate::workpiece::examples;
use crate::workpiece::Workpiece;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::path::Path;

/// Largest difference allowed from a reference distance, mm.
const SAME_MM: f64 = 1e-9;

fn load(file: &crate::workpiece::WorkpieceFile) -> Workpiece {
    match Workpiece::from_file(file, Path::new("example.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    }
}

fn uniform(r: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * r.random::<f64>()
}

/// Grid parameters on [0, 1]: uniform, plus a geometric run towards each
/// end.
fn grid_params() -> Vec<f64> {
    let mut t: Vec<f64> = (0..=48).map(|k| k as f64 / 48.0).collect();
    for e in [1e-4, 3e-4, 1e-3, 2e-3, 4e-3, 7e-3, 1.2e-2] {
        t.extend([e, 1.0 - e]);
    }
    t.sort_by(f64::total_cmp);
    t
}

/// The brute-force closest point of face `i` to `p`.
fn brute_face(wp: &Workpiece, i: usize, p: Point3) -> Projection {
    let s = &wp.faces[i].surface;
    let ((u0, u1), (v0, v1)) = s.domain();
    let t = grid_params();
    let at = |a: usize, b: usize| Vec2::new(u0 + (u1 - u0) * t[a], v0 + (v1 - v0) * t[b]);
    let d: Vec<Vec<f64>> = (0..t.len())
        .map(|a| {
            (0..t.len())
                .map(|b| (s.point(at(a, b).x, at(a, b).y) - p).norm())
                .collect()
        })
        .collect();
    let mut best: Option<Projection> = None;
    for (a, b) in grid_minima(&d) {
        let pr = project_from(s, p, at(a, b), &wp.options).unwrap();
        if best.is_none_or(|b| pr.distance < b.distance) {
            best = Some(pr);
        }
    }
    best.unwrap()
}

/// The grid nodes `(a, b)` whose distance in `d` is no larger than any of
/// their (up to 8) neighbours': the starts of the Newton polish.
fn grid_minima(d: &[Vec<f64>]) -> Vec<(usize, usize)> {
    let n = d.len() as isize;
    let lowest = |a: usize, b: usize| {
        (-1..=1).all(|da: isize| {
            (-1..=1).all(|db: isize| {
                let (x, y) = (a as isize + da, b as isize + db);
                !(0..n).contains(&x) || !(0..n).contains(&y) || d[a][b] <= d[x as usize][y as usize]
            })
        })
    };
    (0..d.len())
        .flat_map(|a| (0..d.len()).map(move |b| (a, b)))
        .filter(|&(a, b)| lowest(a, b))
        .collect()
}

/// A place on the part: face, parameters on [0, 1]^2 and the offset along
/// the normal (mm, both sides).
#[derive(Debug, Clone, Copy)]
struct Place {
    face: usize,
    u: f64,
    v: f64,
    offset: f64,
}

impl Place {
    fn random(r: &mut ChaCha8Rng, faces: usize, reach: f64) -> Place {
        Place {
            face: (uniform(r, 0.0, faces as f64) as usize).min(faces - 1),
            u: uniform(r, 0.0, 1.0),
            v: uniform(r, 0.0, 1.0),
            offset: uniform(r, -reach, reach),
        }
    }

    fn point(&self, wp: &Workpiece) -> Point3 {
        let s = &wp.faces[self.face].surface;
        let ((u0, u1), (v0, v1)) = s.domain();
        let (u, v) = (u0 + (u1 - u0) * self.u, v0 + (v1 - v0) * self.v);
        s.point(u, v) + s.normal(u, v) * self.offset
    }
}

/// A random walk: small steps in u (past an end of u onto the other
/// face, round the blade's edge), drifting v and offset (through zero to
/// the other side), and now and then a jump anywhere within `reach`.
fn walk(r: &mut ChaCha8Rng, faces: usize, steps: usize, reach: f64) -> Vec<Place> {
    let mut at = Place::random(r, faces, 0.3);
    let mut du = 0.012;
    let mut out = Vec::with_capacity(steps);
    for _ in 0..steps {
        out.push(at);
        if r.random::<f64>() < 0.08 {
            at = Place::random(r, faces, reach);
            continue;
        }
        at.u += du;
        if !(0.0..=1.0).contains(&at.u) {
            at.u = at.u.clamp(0.0, 1.0);
            at.face = (at.face + 1) % faces;
            du = -du;
        }
        at.v = (at.v + uniform(r, -0.01, 0.01)).clamp(0.0, 1.0);
        at.offset = (at.offset + uniform(r, -0.08, 0.08)).clamp(-reach, reach);
    }
    out
}

/// Every query along the walks, over all faces and over each face
/// alone, finds the brute-force distance (and a foot at that distance).
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
