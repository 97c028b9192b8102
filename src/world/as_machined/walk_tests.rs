//! True deviations along seeded random walks on the blade (the walks of
//! the nominal near-query tests) against a brute-force reference: a dense
//! parameter grid of the true surface with Newton from every grid minimum.
#![allow(dead_code)]
use super::{AsMachined, AsMachinedSpec};
use crate::geometry::projection::project_from;
use crate::geometry::Projection;
use crate::math::{Point3, Vec2, Vec3};
use crate::workpiece::examples;
use crate::workpiece::KnownFoot;
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

/// The brute-force closest point over `faces`, with its face.
fn brute(wp: &Workpiece, faces: &[usize], p: Point3) -> (usize, Projection) {
    faces
        .iter()
        .map(|&i| (i, brute_face(wp, i, p)))
        .min_by(|a, b| a.1.distance.total_cmp(&b.1.distance))
        .unwrap()
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

/// The true deviation along blade walks (a bump and an offset on the
/// blade, and a small rotation), each point evaluated as the report does,
/// against a brute-force search on the true part (a grid over both faces,
/// Newton from every grid point no farther than its neighbours) and then
/// on the nominal one.

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
