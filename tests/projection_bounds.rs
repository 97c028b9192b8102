//! Closest points near the parameter bounds of small patches whose bounds
//! do not round-trip (`x0 + (hi - x0) != hi`), such as an upper knot of
//! 1.0000000000000002 or 0.1 + 0.2, untrimmed and trimmed to rectangles,
//! against an independent reference: a dense grid of points evaluated from
//! the NURBS definition, refined by shrinking grids around the best point.
//! Warm searches (Newton from a hint) on such patches and on the small faces
//! of NIST CTC 05 must all confirm their foot, at a local minimum over the
//! parameter box:
//! checked by finite differences of the distance, evaluated from the
//! definition, along each parameter, and for searches whose step to an
//! upper bound rounds one unit in the last place short of it (a bound not
//! then made active, with a line search without descent taken for
//! convergence, leaves such a search off the minimum) against the least
//! distance that shrinking grids around the foot find.
mod bounds_support;
mod common;

use bounds_support::{
    hints, local_reference, patch, reference, rounding_sweep, workpiece, ROUNDING_SWEEP_SEED,
};
use cmm::geometry::projection::{project_from, SearchStatus};
use cmm::geometry::ProjectionOptions;
use cmm::math::{Point3, Vec2, Vec3};
use cmm::workpiece::{SurfaceSpec, TrimSpec, Workpiece};
use common::*;

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

/// Warm searches of a sweep: how many ran, the unconfirmed ones and the
/// confirmed feet that are not local minima, described.
#[derive(Default)]
struct Tally {
    total: usize,
    unconfirmed: Vec<String>,
    misses: Vec<String>,
}

impl Tally {
    /// Warm searches from `hints` towards `p` on `spec` over `[lo, hi]`.
    fn run(&mut self, spec: &SurfaceSpec, p: Point3, hints: &[Vec2], lo: [f64; 2], hi: [f64; 2]) {
        let s = spec.to_surface().expect("surface");
        let opts = ProjectionOptions::default();
        for hint in hints {
            self.total += 1;
            let w = match project_from(&s, p, *hint, &opts) {
                Ok(w) => w,
                Err(e) => {
                    self.unconfirmed.push(format!("p {p} from {hint:?}: {e}"));
                    continue;
                }
            };
            let down = fd_descent(spec, p, w.uv, lo, hi);
            if down > FD_DESCENT_TOL_MM {
                self.misses.push(format!(
                    "p {p} from {hint:?}: foot {:?} in [{lo:?}, {hi:?}], a step lowers the distance by {down:e} mm",
                    w.uv
                ));
            }
        }
    }

    /// Fails with the first few misses or unconfirmed searches: every warm
    /// search of a sweep must confirm its foot, at a local minimum.
    fn check(&self) {
        let confirmed = self.total - self.unconfirmed.len();
        println!(
            "{confirmed} of {} warm searches confirmed, {} of them off a minimum",
            self.total,
            self.misses.len()
        );
        let first = |v: &[String]| v.iter().take(5).cloned().collect::<Vec<_>>().join("\n");
        assert!(
            self.misses.is_empty(),
            "{} of {confirmed} confirmed warm searches end off a minimum:\n{}",
            self.misses.len(),
            first(&self.misses)
        );
        assert!(
            self.unconfirmed.is_empty(),
            "{} of {} warm searches unconfirmed:\n{}",
            self.unconfirmed.len(),
            self.total,
            first(&self.unconfirmed)
        );
    }
}

#[test]
fn warm_searches_reaching_rounding_bounds_end_at_minima() {
    let mut tally = Tally::default();
    for sp in rounding_sweep(&mut rng(ROUNDING_SWEEP_SEED)) {
        for (p, hs) in &sp.queries {
            tally.run(&sp.spec, *p, hs, sp.lo, sp.hi);
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
