//! Test support for closest-point queries near earlier ones: a brute-force
//! reference search (a dense parameter grid, denser towards the edges,
//! with Newton from every grid point no farther than its neighbours) and
//! seeded random walks over a workpiece's faces. Used by the nominal
//! near-query tests and by the true part's walk tests.
use crate::geometry::projection::project_from;
use crate::geometry::Projection;
use crate::math::{Point3, Vec2};
use crate::workpiece::Workpiece;
use rand::rngs::ChaCha8Rng;
use rand::RngExt;
use std::path::Path;

/// Largest difference allowed from a reference distance, mm.
pub(crate) const SAME_MM: f64 = 1e-9;

pub(crate) fn load(file: &crate::workpiece::WorkpieceFile) -> Workpiece {
    match Workpiece::from_file(file, Path::new("example.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    }
}

pub(crate) fn uniform(r: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * r.random::<f64>()
}

/// Grid parameters on [0, 1]: uniform, plus a geometric run towards each
/// end.
pub(crate) fn grid_params() -> Vec<f64> {
    let mut t: Vec<f64> = (0..=48).map(|k| k as f64 / 48.0).collect();
    for e in [1e-4, 3e-4, 1e-3, 2e-3, 4e-3, 7e-3, 1.2e-2] {
        t.extend([e, 1.0 - e]);
    }
    t.sort_by(f64::total_cmp);
    t
}

/// The brute-force closest point of face `i` to `p`.
pub(crate) fn brute_face(wp: &Workpiece, i: usize, p: Point3) -> Projection {
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
pub(crate) fn grid_minima(d: &[Vec<f64>]) -> Vec<(usize, usize)> {
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
pub(crate) struct Place {
    face: usize,
    u: f64,
    v: f64,
    offset: f64,
}

impl Place {
    pub(crate) fn random(r: &mut ChaCha8Rng, faces: usize, reach: f64) -> Place {
        Place {
            face: (uniform(r, 0.0, faces as f64) as usize).min(faces - 1),
            u: uniform(r, 0.0, 1.0),
            v: uniform(r, 0.0, 1.0),
            offset: uniform(r, -reach, reach),
        }
    }

    pub(crate) fn point(&self, wp: &Workpiece) -> Point3 {
        let s = &wp.faces[self.face].surface;
        let ((u0, u1), (v0, v1)) = s.domain();
        let (u, v) = (u0 + (u1 - u0) * self.u, v0 + (v1 - v0) * self.v);
        s.point(u, v) + s.normal(u, v) * self.offset
    }
}

/// A random walk: small steps in u (past an end of u onto the other
/// face, round the blade's edge), drifting v and offset (through zero to
/// the other side), and now and then a jump anywhere within `reach`.
pub(crate) fn walk(r: &mut ChaCha8Rng, faces: usize, steps: usize, reach: f64) -> Vec<Place> {
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
/// The brute-force closest point over `faces`, with its face.
pub(crate) fn brute(wp: &Workpiece, faces: &[usize], p: Point3) -> (usize, Projection) {
    faces
        .iter()
        .map(|&i| (i, brute_face(wp, i, p)))
        .min_by(|a, b| a.1.distance.total_cmp(&b.1.distance))
        .unwrap()
}
