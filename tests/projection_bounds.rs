//! Closest points near the parameter bounds of small patches whose bounds
//! do not round-trip (`x0 + (hi - x0) != hi`), such as an upper knot of
//! 1.0000000000000002 or 0.1 + 0.2, untrimmed and trimmed to rectangles,
//! against an independent reference: a dense grid of points evaluated from
//! the NURBS definition, refined by shrinking grids around the best point.
//! Warm searches (Newton from a hint) on such patches and on the small faces
//! of NIST CTC 05 must end at a local minimum over the parameter box:
//! checked by finite differences of the distance, evaluated from the
//! definition, along each parameter, and for searches whose step to an
//! upper bound rounds one unit in the last place short of it (a bound not
//! then made active, with a line search without descent taken for
//! convergence, leaves such a search off the minimum) against the least
//! distance that shrinking grids around the foot find.
mod common;

use cmm::geometry::projection::{project_from, SearchStatus};
use cmm::geometry::ProjectionOptions;
use cmm::math::{Point3, Vec2, Vec3};
use cmm::workpiece::{SurfaceSpec, TrimSpec, Workpiece, WorkpieceFile};
use common::*;

/// A small curved bicubic patch over `[u0, u1] x [v0, v1]` (one Bezier
/// span), about 4 mm across, with mild weights.
fn patch(r: &mut TestRng, (u0, u1): (f64, f64), (v0, v1): (f64, f64)) -> SurfaceSpec {
    let cps = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, y) = (i as f64 * 1.3, j as f64 * 1.3);
                    // Bent and twisted: the Newton model couples u and v.
                    let bulge = 0.35 * ((x - 2.0).powi(2) - 0.6 * (y - 2.0).powi(2))
                        + 0.5 * (x - 2.0) * (y - 2.0);
                    [
                        x + uniform(r, -0.2, 0.2),
                        y + uniform(r, -0.2, 0.2),
                        bulge + uniform(r, -0.3, 0.3),
                    ]
                })
                .collect()
        })
        .collect();
    let weights = (0..4)
        .map(|_| (0..4).map(|_| uniform(r, 0.7, 1.4)).collect())
        .collect();
    SurfaceSpec {
        name: "patch".into(),
        degree: [3, 3],
        knots_u: vec![u0, u0, u0, u0, u1, u1, u1, u1],
        knots_v: vec![v0, v0, v0, v0, v1, v1, v1, v1],
        control_points: cps,
        weights: Some(weights),
        reversed: false,
        trim: None,
    }
}

/// Least distance from `p` to the patch over the parameter rectangle
/// `[lo, hi]`: an 81 x 81 grid, then 9 x 9 grids shrinking by 4 around the
/// best point, clamped to the rectangle, with the points evaluated from
/// the definition.
fn reference(spec: &SurfaceSpec, p: Point3, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let dist = |u: f64, v: f64| (Point3::from(reference_point(spec, u, v)) - p).norm();
    let grid = |c: [f64; 2], half: [f64; 2], n: usize, best: &mut (f64, [f64; 2])| {
        for i in 0..=n {
            for j in 0..=n {
                let t = |k: usize, a: usize| {
                    let x = c[a] - half[a] + 2.0 * half[a] * k as f64 / n as f64;
                    x.clamp(lo[a], hi[a])
                };
                let (u, v) = (t(i, 0), t(j, 1));
                let d = dist(u, v);
                if d < best.0 {
                    *best = (d, [u, v]);
                }
            }
        }
    };
    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let mut half = [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])];
    let mut best = (f64::INFINITY, mid);
    grid(mid, half, 80, &mut best);
    half = half.map(|h| h * 2.0 / 80.0 * 2.0);
    for _ in 0..40 {
        let c = best.1;
        grid(c, half, 8, &mut best);
        half = half.map(|h| h * 0.25);
    }
    best.0
}

fn workpiece(spec: SurfaceSpec) -> Workpiece {
    from_file(&WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: "bounds".into(),
        units: "mm".into(),
        surfaces: vec![spec],
    })
}

/// Query points near the patch, most of them beyond an edge or a corner
/// (feet on the bounds).
fn queries(r: &mut TestRng, n: usize) -> Vec<Point3> {
    (0..n)
        .map(|_| {
            Point3::new(
                uniform(r, -4.0, 8.0),
                uniform(r, -4.0, 8.0),
                uniform(r, -4.0, 4.0),
            )
        })
        .collect()
}

/// Bounds whose `x0 + (hi - x0)` is one unit in the last place short of
/// `hi` for many `x0`.
const AWKWARD: [(f64, f64); 4] = [
    (0.0, 1.000_000_000_000_000_2),
    (0.1, 0.1 + 0.2),
    (-0.7, 0.9 + 1e-16),
    (2.0 / 3.0, 10.0 / 3.0),
];

/// Checks every query against the reference over `[lo, hi]`.
fn check_all(wp: &Workpiece, spec: &SurfaceSpec, lo: [f64; 2], hi: [f64; 2], r: &mut TestRng) {
    for (k, p) in queries(r, 80).into_iter().enumerate() {
        let want = reference(spec, p, lo, hi);
        let fp = cmm::evaluate::closest_point(wp, p).unwrap();
        let got = fp.projection;
        assert_eq!(got.status, SearchStatus::Confirmed, "query {k} at {p}");
        assert!(
            (got.distance - want).abs() < 1e-9,
            "query {k} at {p}: {} vs reference {want} (foot {:?}, bounds {lo:?} {hi:?})",
            got.distance,
            got.uv
        );
    }
}

#[test]
fn untrimmed_patches_with_awkward_bounds_match_the_reference() {
    let mut r = rng(71);
    for &(u0, u1) in &AWKWARD {
        for &(v0, v1) in &AWKWARD {
            let spec = patch(&mut r, (u0, u1), (v0, v1));
            let wp = workpiece(spec.clone());
            check_all(&wp, &spec, [u0, v0], [u1, v1], &mut r);
        }
    }
}

#[test]
fn rectangular_trims_with_awkward_bounds_match_the_reference() {
    let mut r = rng(72);
    for &(u0, u1) in &AWKWARD {
        let (v0, v1) = (0.0, 1.0);
        let mut spec = patch(&mut r, (u0, u1), (v0, v1));
        // A rectangle reaching the upper u bound, its v range inside.
        let (tu0, tv0, tv1) = (u0 + 0.3 * (u1 - u0), 0.1 + 0.2, 0.7 + 0.1);
        spec.trim = Some(TrimSpec {
            outer: vec![[tu0, tv0], [u1, tv0], [u1, tv1], [tu0, tv1]],
            holes: vec![],
        });
        let wp = workpiece(spec.clone());
        check_all(&wp, &spec, [tu0, tv0], [u1, tv1], &mut r);
    }
}

/// Bounds of the warm searches: thirds and tenths, whose `x0 + (b - x0)`
/// often rounds to a neighbour of `b`, and domains far from 0.
const ROUNDING: [(f64, f64); 6] = [
    (0.0, 1.0 / 3.0),
    (0.1, 0.7),
    (0.1, 0.1 + 0.2),
    (2.0 / 3.0, 10.0 / 3.0),
    (1000.1, 1000.7),
    (123.456, 123.456 + 1.0 / 3.0),
];

/// Faces of CTC 05 whose domain corners are at most this far apart (mm)
/// are searched.
const SMALL_FACE_MM: f64 = 30.0;

/// Finite-difference step along a parameter, relative to its range.
const FD_STEP_REL: f64 = 1e-6;
/// A move of one finite-difference step may lower the distance by at most
/// this (mm) at a local minimum (rounding of the evaluation and the
/// stationarity tolerance of the search times the step).
const FD_DESCENT_TOL_MM: f64 = 1e-10;

/// The largest decrease of the distance from `p` (mm, evaluated from the
/// definition) that one finite-difference step from `uv` along either
/// parameter, clamped into `[lo, hi]`, achieves; `<= 0` at a local minimum
/// over the box.
fn fd_descent(spec: &SurfaceSpec, p: Point3, uv: Vec2, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let dist = |x: [f64; 2]| (Point3::from(reference_point(spec, x[0], x[1])) - p).norm();
    let at = [uv.x, uv.y];
    let here = dist(at);
    let mut best = f64::NEG_INFINITY;
    for k in 0..2 {
        let h = FD_STEP_REL * (hi[k] - lo[k]);
        for sign in [-1.0, 1.0] {
            let mut x = at;
            x[k] = (x[k] + sign * h).clamp(lo[k], hi[k]);
            best = best.max(here - dist(x));
        }
    }
    best
}

/// Warm searches of a sweep: how many ran, how many confirmed their foot,
/// and the confirmed feet that are not local minima, described.
#[derive(Default)]
struct Tally {
    total: usize,
    confirmed: usize,
    misses: Vec<String>,
}

/// Least share of a sweep's warm searches that must confirm their foot, so
/// that the check of the confirmed ones covers the sweep (an unconfirmed
/// search, an error, claims no minimum).
const MIN_CONFIRMED_SHARE: f64 = 0.98;

impl Tally {
    /// Warm searches from `hints` towards `p` on `spec` over `[lo, hi]`.
    fn run(&mut self, spec: &SurfaceSpec, p: Point3, hints: &[Vec2], lo: [f64; 2], hi: [f64; 2]) {
        let s = spec.to_surface().expect("surface");
        let opts = ProjectionOptions::default();
        for hint in hints {
            self.total += 1;
            let Ok(w) = project_from(&s, p, *hint, &opts) else {
                continue;
            };
            self.confirmed += 1;
            let down = fd_descent(spec, p, w.uv, lo, hi);
            if down > FD_DESCENT_TOL_MM {
                self.misses.push(format!(
                    "p {p} from {hint:?}: foot {:?} in [{lo:?}, {hi:?}], a step lowers the distance by {down:e} mm",
                    w.uv
                ));
            }
        }
    }

    /// Fails with the first few misses, or when too few searches confirmed.
    fn check(&self) {
        println!(
            "{} of {} warm searches confirmed, {} of them off a minimum",
            self.confirmed,
            self.total,
            self.misses.len()
        );
        let first: Vec<&str> = self.misses.iter().take(5).map(String::as_str).collect();
        assert!(
            self.misses.is_empty(),
            "{} of {} confirmed warm searches end off a minimum:\n{}",
            self.misses.len(),
            self.confirmed,
            first.join("\n")
        );
        assert!(
            self.confirmed as f64 >= MIN_CONFIRMED_SHARE * self.total as f64,
            "only {} of {} warm searches confirmed",
            self.confirmed,
            self.total
        );
    }
}

/// Hints spread over the box, half of them in its upper corner.
fn hints(r: &mut TestRng, lo: [f64; 2], hi: [f64; 2], n: usize) -> Vec<Vec2> {
    (0..n)
        .map(|k| {
            let from = if k % 2 == 0 { 0.0 } else { 0.8 };
            let t = |a: usize, r: &mut TestRng| lo[a] + (hi[a] - lo[a]) * uniform(r, from, 1.0);
            let u = t(0, r);
            Vec2::new(u, t(1, r))
        })
        .collect()
}

#[test]
fn warm_searches_reaching_rounding_bounds_end_at_minima() {
    let mut r = rng(73);
    let mut tally = Tally::default();
    for &(u0, u1) in &ROUNDING {
        for &(v0, v1) in &ROUNDING {
            let spec = patch(&mut r, (u0, u1), (v0, v1));
            for _ in 0..40 {
                // Mostly beyond the upper u or v edge: feet on those bounds.
                let p = Point3::new(
                    uniform(&mut r, 1.0, 7.0),
                    uniform(&mut r, 1.0, 7.0),
                    uniform(&mut r, -3.0, 3.0),
                );
                let hs = hints(&mut r, [u0, v0], [u1, v1], 6);
                tally.run(&spec, p, &hs, [u0, v0], [u1, v1]);
            }
        }
    }
    tally.check();
}

#[test]
fn warm_searches_near_the_edges_of_small_cad_faces_end_at_minima() {
    let imp = cmm::cad::import(repo("workpieces/nist-ctc05.stp")).expect("CTC 05 imports");
    let mut r = rng(74);
    let mut tally = Tally::default();
    for spec in &imp.workpiece.surfaces {
        let s = spec.to_surface().expect("surface");
        let ((u0, u1), (v0, v1)) = s.domain();
        let (lo, hi) = ([u0, v0], [u1, v1]);
        let size = (s.point(u0, v0) - s.point(u1, v1)).norm();
        if size > SMALL_FACE_MM {
            continue;
        }
        for k in 0..12 {
            // A point of an upper edge (or the corner), moved out along the
            // surface and off it.
            let (u, v) = match k % 3 {
                0 => (u1, uniform(&mut r, v0, v1)),
                1 => (uniform(&mut r, u0, u1), v1),
                _ => (u1, v1),
            };
            let d = s.derivs(u, v, 1);
            let out = d.su() * f64::from(k % 3 != 1) + d.sv() * f64::from(k % 3 != 0);
            let unit = |x: Vec3| x.try_normalize(0.0).unwrap_or_else(Vec3::zeros);
            let n = unit(d.su().cross(&d.sv()));
            let p = d.point()
                + unit(out) * (size * uniform(&mut r, 0.0, 0.3))
                + n * (size * uniform(&mut r, -0.3, 0.3));
            let hs = hints(&mut r, lo, hi, 6);
            tally.run(spec, p, &hs, lo, hi);
        }
    }
    tally.check();
}

/// Warm searches whose Newton step reaches an upper bound of 1/3 or 10/3
/// from a point where `x0 + (hi - x0)` rounds below `hi` (a search that
/// stops there ends 0.8 to 65 um farther than points near it): patch seed,
/// u and v ranges, query, hint.
#[allow(clippy::type_complexity)]
const ULP_SHORT: [(u64, (f64, f64), (f64, f64), [f64; 3], [f64; 2]); 4] = [
    (
        3,
        (0.0, 1.0 / 3.0),
        (0.0, 1.0 / 3.0),
        [1.5258506972900001, 6.3692302692674625, 0.028011790848156082],
        [0.18084302584500425, 0.08195210094900376],
    ),
    (
        5,
        (0.0, 1.0 / 3.0),
        (2.0 / 3.0, 10.0 / 3.0),
        [3.563699510302638, 5.806985532959352, -0.6697240083344651],
        [0.16127709848332683, 0.7382640673893726],
    ),
    (
        8,
        (0.0, 1.0 / 3.0),
        (0.0, 1.0 / 3.0),
        [5.91191570312785, 3.4893346809546006, 2.8121823069838143],
        [0.07768507421767248, 0.1741497347419642],
    ),
    (
        15,
        (2.0 / 3.0, 10.0 / 3.0),
        (0.0, 1.0 / 3.0),
        [6.471215982575371, 1.7379255254548018, -1.2750290232760393],
        [0.977133253975236, 0.12389504164773853],
    ),
];

/// The same on CTC 05's `face131`, half a conical chamfer (57 mm across)
/// whose upper u bound 1.5742958893526258 is such a bound (0.3 to 100 um):
/// query, hint.
const ULP_SHORT_CTC05: [([f64; 3], [f64; 2]); 4] = [
    (
        [-37.30420565967034, 15.460269835144526, 491.5215246231957],
        [-1.0103365156981408, -0.17240896659463623],
    ),
    (
        [-34.50227175022165, 9.997561467261516, 491.1740472928593],
        [-1.1678108847447621, 1.8879198195201323],
    ),
    (
        [-31.180041981449104, 14.29281616685928, 486.9853452963189],
        [-1.030767674524892, -2.6844892527408373],
    ),
    (
        [-35.84786678206521, 13.664912466259064, 488.88776183498663],
        [-0.939490989335026, 0.322748579303604],
    ),
];

/// Least distance from `p` (mm) that grids of 9 x 9 points around `c`,
/// clamped to `[lo, hi]` and halving 45 times from a tenth of the box,
/// find, the points evaluated from the definition.
fn local_reference(spec: &SurfaceSpec, p: Point3, c: Vec2, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let dist = |x: [f64; 2]| (Point3::from(reference_point(spec, x[0], x[1])) - p).norm();
    let mut best = (dist([c.x, c.y]), [c.x, c.y]);
    let mut half = [0.05 * (hi[0] - lo[0]), 0.05 * (hi[1] - lo[1])];
    for _ in 0..45 {
        let c = best.1;
        for i in 0..=8 {
            for j in 0..=8 {
                let at = |k: usize, a: usize| {
                    (c[a] - half[a] + 2.0 * half[a] * k as f64 / 8.0).clamp(lo[a], hi[a])
                };
                let x = [at(i, 0), at(j, 1)];
                let d = dist(x);
                if d < best.0 {
                    best = (d, x);
                }
            }
        }
        half = half.map(|h| h * 0.5);
    }
    best.0
}

/// A confirmed foot may be at most this much (mm) farther than the local
/// reference around it.
const LOCAL_TOL_MM: f64 = 1e-9;

/// The warm search from `hint` is confirmed and no farther than the local
/// reference around its foot.
fn check_at_local_minimum(spec: &SurfaceSpec, p: Point3, hint: Vec2) {
    let s = spec.to_surface().expect("surface");
    let ((u0, u1), (v0, v1)) = s.domain();
    let w = project_from(&s, p, hint, &ProjectionOptions::default()).expect("warm search");
    let want = local_reference(spec, p, w.uv, [u0, v0], [u1, v1]);
    assert_eq!(w.status, SearchStatus::Confirmed);
    assert!(
        w.distance - want <= LOCAL_TOL_MM,
        "{}: p {p} from {hint:?}: foot {:?} at {} mm, {want} mm near it",
        spec.name,
        w.uv,
        w.distance
    );
}

#[test]
fn warm_searches_whose_step_rounds_short_of_a_bound_end_at_minima() {
    for (seed, ur, vr, p, hint) in ULP_SHORT {
        let spec = patch(&mut rng(seed), ur, vr);
        check_at_local_minimum(&spec, Point3::from(p), Vec2::from(hint));
    }
    let imp = cmm::cad::import(repo("workpieces/nist-ctc05.stp")).expect("CTC 05 imports");
    let face = imp.workpiece.surfaces.iter().find(|s| s.name == "face131");
    let face = face.expect("CTC 05 has face131");
    assert_eq!(face.knots_u.last(), Some(&1.5742958893526258));
    for (p, hint) in ULP_SHORT_CTC05 {
        check_at_local_minimum(face, Point3::from(p), Vec2::from(hint));
    }
}
