//! Degree elevation and reweighting of NURBS curves against independent
//! references: circle arcs elevated to degrees 3 and 4 keep every point at
//! the radius, random cubics (clamped and unclamped, with double knots)
//! elevated to quintics match the original definition pointwise, and a
//! reweighted curve keeps its points while its weight function becomes
//! the product of both. Curves are evaluated from their knots and
//! homogeneous points by the Cox-de Boor recursion, not by the crate.
mod common;

use cmm::geometry::{ElevateError, NurbsCurve};
use cmm::math::{Point3, Vec3};
use common::*;

/// Relative agreement asked of exact operations (rounding only).
const REL_TOL: f64 = 1e-12;

/// `C(t)` and the weight `w(t)` of `c` from its definition.
fn reference(c: &NurbsCurve, t: f64) -> (Point3, f64) {
    let (knots, p) = (c.knots().as_slice(), c.knots().degree());
    let mut num = Vec3::zeros();
    let mut den = 0.0;
    for (i, h) in c.homogeneous_points().iter().enumerate() {
        let b = basis(knots, i, p, t);
        num += Vec3::new(h.x, h.y, h.z) * b;
        den += h.w * b;
    }
    (Point3::from(num / den), den)
}

/// `n` parameters spread over `[lo, hi)` (the domain end is excluded:
/// the half-open recursion reads an unclamped curve's end from the right).
fn params(c: &NurbsCurve, n: usize) -> Vec<f64> {
    let (lo, hi) = c.domain();
    (0..n)
        .map(|k| lo + (hi - lo) * k as f64 / n as f64)
        .collect()
}

/// The full circle of radius `r` about `centre` in the plane spanned by
/// the unit vectors `e1`, `e2`: four rational quadratic quarter arcs.
fn circle(centre: Point3, r: f64, e1: Vec3, e2: Vec3) -> NurbsCurve {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let at = |a: f64, b: f64| {
        let q = centre + (e1 * a + e2 * b) * r;
        [q.x, q.y, q.z]
    };
    let pts = vec![
        at(1.0, 0.0),
        at(1.0, 1.0),
        at(0.0, 1.0),
        at(-1.0, 1.0),
        at(-1.0, 0.0),
        at(-1.0, -1.0),
        at(0.0, -1.0),
        at(1.0, -1.0),
        at(1.0, 0.0),
    ];
    let weights = vec![1.0, w, 1.0, w, 1.0, w, 1.0, w, 1.0];
    let knots = vec![
        0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
    ];
    NurbsCurve::try_new(2, knots, pts, Some(weights)).expect("circle")
}

/// A random cubic on `knots` with control points in a 100 mm box and,
/// when `rational`, weights in `[0.5, 2]`.
fn random_cubic(r: &mut TestRng, knots: Vec<f64>, rational: bool) -> NurbsCurve {
    let n = knots.len() - 4;
    let pts = (0..n)
        .map(|_| [0, 1, 2].map(|_| uniform(r, -50.0, 50.0)))
        .collect();
    let weights = rational.then(|| (0..n).map(|_| uniform(r, 0.5, 2.0)).collect());
    NurbsCurve::try_new(3, knots, pts, weights).expect("cubic")
}

/// Knot vectors of cubics: clamped with single and double interior knots
/// and an offset domain, Bezier, and unclamped at both ends.
fn cubic_knots() -> Vec<Vec<f64>> {
    vec![
        vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.45, 0.45, 0.8, 1.0, 1.0, 1.0, 1.0],
        vec![5.0, 5.0, 5.0, 5.0, 5.1, 7.0, 7.0, 7.3, 7.3, 7.3, 7.3],
        vec![-1.0, -1.0, -1.0, -1.0, 2.0, 2.0, 2.0, 2.0],
        vec![-0.3, -0.1, 0.0, 0.2, 0.5, 0.5, 0.9, 1.3, 1.4, 1.6],
    ]
}

#[test]
fn circle_elevated_to_degrees_3_and_4_keeps_the_radius() {
    let (centre, r) = (Point3::new(12.0, -3.0, 40.0), 17.5);
    let e1 = Vec3::new(1.0, 2.0, 2.0) / 3.0;
    let e2 = Vec3::new(2.0, 1.0, -2.0) / 3.0;
    let c = circle(centre, r, e1, e2);
    for t in [1, 2] {
        let e = c.elevate_degree(t).expect("elevates");
        assert_eq!(e.knots().degree(), 2 + t);
        assert_eq!(e.domain(), c.domain());
        for u in params(&e, 1000) {
            let (q, _) = reference(&e, u);
            let radius = (q - centre).norm();
            assert!(
                (radius - r).abs() <= REL_TOL * r,
                "degree {}: radius {radius} at {u}",
                2 + t
            );
            assert!((q - centre).dot(&e1.cross(&e2)).abs() <= REL_TOL * r);
            let (orig, _) = reference(&c, u);
            assert!((q - orig).norm() <= REL_TOL * r, "at {u}: {q} vs {orig}");
        }
    }
}

#[test]
fn random_cubics_elevated_to_quintics_match_pointwise() {
    let mut r = rng(41);
    for (k, knots) in cubic_knots().into_iter().enumerate() {
        for rational in [false, true] {
            let c = random_cubic(&mut r, knots.clone(), rational);
            let e = c.elevate_degree(2).expect("elevates");
            assert_eq!(e.knots().degree(), 5);
            assert_eq!(e.domain(), c.domain());
            for u in params(&c, 700) {
                let (want, _) = reference(&c, u);
                let (got, _) = reference(&e, u);
                let scale = 100.0 + want.coords.norm();
                assert!(
                    (got - want).norm() <= REL_TOL * scale,
                    "knots {k}, rational {rational}, at {u}: {got} vs {want}"
                );
                // The crate's own evaluation of the elevated curve too.
                assert!((e.point(u) - want).norm() <= REL_TOL * scale);
            }
        }
    }
}

#[test]
fn reweighting_keeps_the_points_and_multiplies_the_weights() {
    let mut r = rng(42);
    let centre = Point3::new(1.0, 2.0, 3.0);
    let arc = circle(centre, 5.0, Vec3::x(), Vec3::y());
    let factor = random_cubic(&mut r, cubic_knots()[0].clone(), true);
    let rw = arc.reweighted_by(&factor).expect("reweights");
    assert_eq!(rw.knots().degree(), 5);
    for u in params(&rw, 800) {
        let (q, w) = reference(&rw, u);
        let (orig, w_arc) = reference(&arc, u);
        let (_, w_factor) = reference(&factor, u);
        assert!(((q - centre).norm() - 5.0).abs() <= REL_TOL * 5.0, "{u}");
        assert!((q - orig).norm() <= REL_TOL * 5.0, "{u}");
        assert!((w - w_arc * w_factor).abs() <= REL_TOL * w, "{u}: {w}");
    }
}

#[test]
fn elevation_beyond_the_maximum_degree_and_foreign_domains_are_errors() {
    let mut r = rng(43);
    let c = random_cubic(&mut r, cubic_knots()[0].clone(), false);
    assert_eq!(
        c.elevate_degree(13),
        Err(ElevateError::DegreeTooHigh { degree: 16 })
    );
    let other = random_cubic(&mut r, cubic_knots()[1].clone(), true);
    assert!(matches!(
        c.reweighted_by(&other),
        Err(ElevateError::Domain { .. })
    ));
    assert_eq!(c.elevate_degree(0), Ok(c.clone()));
}
