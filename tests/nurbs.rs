//! NURBS evaluation against the definition, derivatives against finite
//! differences, knot insertion invariance, analytic sphere and cylinder.
mod common;

use cmm::geometry::{KnotError, KnotVector, NurbsCurve, NurbsSurface};
use cmm::math::{Point3, Vec3};
use common::*;

fn build(spec: &cmm::workpiece::SurfaceSpec) -> NurbsSurface {
    spec.to_surface().unwrap()
}

#[test]
fn evaluation_matches_the_definition_on_random_rational_surfaces() {
    let mut r = rng(11);
    for case in 0..60 {
        let spec = random_surface(&mut r, "s");
        let s = build(&spec);
        let ((u0, u1), (v0, v1)) = s.domain();
        for k in 0..20 {
            let (u, v) = match k {
                0 => (u0, v0),
                1 => (u1, v1),
                _ => (uniform(&mut r, u0, u1), uniform(&mut r, v0, v1)),
            };
            let got = s.point(u, v);
            let want = Point3::from(reference_point(&spec, u, v));
            let scale = 1.0 + want.coords.norm();
            assert!(
                (got - want).norm() <= 1e-12 * scale,
                "case {case}: {got} vs {want} at ({u}, {v})"
            );
        }
    }
}

/// Central difference of order-(k-1) derivatives checks every order-k one.
#[test]
fn derivatives_agree_with_finite_differences() {
    let mut r = rng(12);
    let mut specs: Vec<_> = (0..30).map(|_| random_surface(&mut r, "s")).collect();
    specs.extend(cmm::workpiece::examples::blade().surfaces);
    specs.extend(cmm::workpiece::examples::reference_sphere(25.0).surfaces);
    for spec in &specs {
        let s = build(spec);
        for _ in 0..10 {
            let u = param_inside_span(&mut r, s.knots_u(), 0.2);
            let v = param_inside_span(&mut r, s.knots_v(), 0.2);
            check_fd(&s, u, v);
        }
    }
}

fn check_fd(s: &NurbsSurface, u: f64, v: f64) {
    let h = 1e-6;
    let d = s.derivs(u, v, 3);
    let (du_p, du_m) = (s.derivs(u + h, v, 2), s.derivs(u - h, v, 2));
    let (dv_p, dv_m) = (s.derivs(u, v + h, 2), s.derivs(u, v - h, 2));
    let scale = 1.0
        + (0..4)
            .flat_map(|k| (0..4 - k).map(move |l| (k, l)))
            .map(|(k, l)| d.d[k][l].norm())
            .fold(0.0, f64::max);
    for k in 0..3 {
        for l in 0..3 - k {
            let fd_u = (du_p.d[k][l] - du_m.d[k][l]) / (2.0 * h);
            let fd_v = (dv_p.d[k][l] - dv_m.d[k][l]) / (2.0 * h);
            assert!(
                (fd_u - d.d[k + 1][l]).norm() <= 1e-5 * scale,
                "d[{}][{l}] at ({u},{v}): {} vs {}",
                k + 1,
                d.d[k + 1][l],
                fd_u
            );
            assert!(
                (fd_v - d.d[k][l + 1]).norm() <= 1e-5 * scale,
                "d[{k}][{}] at ({u},{v})",
                l + 1
            );
        }
    }
}

#[test]
fn knot_insertion_leaves_the_shape_unchanged() {
    let mut r = rng(13);
    for _ in 0..40 {
        let s = build(&random_surface(&mut r, "s"));
        let ((u0, u1), (v0, v1)) = s.domain();
        let (ui, vi) = (uniform(&mut r, u0, u1), uniform(&mut r, v0, v1));
        let refined = s
            .insert_knot_u(ui, 1)
            .unwrap()
            .insert_knot_v(vi, 1)
            .unwrap();
        assert_eq!(refined.counts(), (s.counts().0 + 1, s.counts().1 + 1));
        for _ in 0..20 {
            let (u, v) = (uniform(&mut r, u0, u1), uniform(&mut r, v0, v1));
            let (a, b) = (s.point(u, v), refined.point(u, v));
            assert!(
                (a - b).norm() <= 1e-12 * (1.0 + a.coords.norm()),
                "{a} vs {b}"
            );
        }
    }
}

#[test]
fn curve_knot_insertion_and_circle() {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let c = NurbsCurve::try_new(
        2,
        vec![0., 0., 0., 1., 1., 1.],
        vec![[3., 0., 0.], [3., 3., 0.], [0., 3., 0.]],
        Some(vec![1., w, 1.]),
    )
    .unwrap();
    let refined = c.insert_knot(0.3, 2).unwrap();
    for k in 0..=50 {
        let t = k as f64 / 50.0;
        let p = c.point(t);
        assert!((p.coords.norm() - 3.0).abs() < 1e-13);
        assert!((refined.point(t) - p).norm() < 1e-13);
        let d = c.derivs(t, 1);
        assert!(
            d[1].dot(&p.coords).abs() < 1e-12,
            "tangent perpendicular to radius"
        );
    }
    assert!(c.insert_knot(0.3, 3).is_err(), "multiplicity above degree");
}

#[test]
fn reference_sphere_is_exact() {
    let wp = example("sphere");
    let s = &wp.faces[0].surface;
    let mut r = rng(14);
    for _ in 0..500 {
        let (u, v) = (uniform(&mut r, 0.0, 1.0), uniform(&mut r, 0.0, 1.0));
        let p = s.point(u, v);
        assert!((p.coords.norm() - 12.5).abs() < 1e-13);
        let n = s.normal(u, v);
        assert!(
            (n - p.coords / 12.5).norm() < 1e-12,
            "outward radial normal"
        );
        let k = s.curvature(u, v);
        assert!(
            (k.k_min + 0.08).abs() < 1e-10 && (k.k_max + 0.08).abs() < 1e-10,
            "{k:?}"
        );
    }
    // Poles: the limit normal is still radial.
    for (v, z) in [(0.0, -1.0), (1.0, 1.0)] {
        let n = s.normal(0.37, v);
        assert!(
            (n - Vec3::new(0.0, 0.0, z)).norm() < 1e-12,
            "pole normal {n}"
        );
    }
}

#[test]
fn bore_is_an_exact_cylinder_with_normal_into_the_hole() {
    let wp = example("bore");
    let s = &wp.faces[0].surface;
    let mut r = rng(15);
    for _ in 0..500 {
        let (u, v) = (uniform(&mut r, 0.0, 1.0), uniform(&mut r, 0.0, 1.0));
        let p = s.point(u, v);
        let radial = Vec3::new(p.x, p.y, 0.0);
        assert!((radial.norm() - 25.0).abs() < 1e-12);
        assert!((0.0..=20.0).contains(&p.z));
        assert!(
            (s.normal(u, v) + radial / 25.0).norm() < 1e-12,
            "normal points to the axis"
        );
        let k = s.curvature(u, v);
        assert!(
            k.k_min.abs() < 1e-12 && (k.k_max - 0.04).abs() < 1e-12,
            "{k:?}"
        );
        assert!(
            k.dir_max.z.abs() < 1e-9,
            "max curvature runs around the bore"
        );
    }
}

#[test]
fn knot_vectors_check_their_invariants() {
    assert!(matches!(
        KnotVector::try_new(vec![0., 0., 1., 0.5], 1),
        Err(KnotError::Decreasing { index: 3, .. })
    ));
    assert!(matches!(
        KnotVector::try_new(vec![0., 0., 1., 1.], 2),
        Err(KnotError::TooFew { need: 6, .. })
    ));
    assert!(matches!(
        KnotVector::try_new(vec![0., 0., 0.5, 0.5, 0.5, 1., 1.], 2),
        Err(KnotError::Multiplicity { .. })
    ));
    assert!(matches!(
        KnotVector::try_new(vec![0., f64::NAN, 1., 1.], 1),
        Err(KnotError::NotFinite { index: 1 })
    ));
    assert!(KnotVector::try_new(vec![1., 1., 1., 1.], 1).is_err());
    assert!(matches!(
        KnotVector::try_new(vec![0., 1.], 0),
        Err(KnotError::DegreeZero)
    ));
    // Unclamped vectors and knots outside [0, 1] are fine.
    let k = KnotVector::try_new(vec![-3., -2., -1., 0., 1., 2.], 2).unwrap();
    assert_eq!(k.domain(), (-1.0, 0.0));
}

#[test]
fn power_basis_fast_path_agrees_with_the_basis_recursion() {
    let mut r = rng(16);
    for _ in 0..40 {
        let s = build(&random_surface(&mut r, "s"));
        let ((u0, u1), (v0, v1)) = s.domain();
        for _ in 0..20 {
            let (u, v) = (uniform(&mut r, u0, u1), uniform(&mut r, v0, v1));
            let (a, b) = (s.derivs(u, v, 3), s.derivs_de_boor(u, v, 3));
            let scale = 1.0 + b.d[0][0].norm() + b.d[1][0].norm() + b.d[0][1].norm();
            for k in 0..4 {
                for l in 0..4 - k {
                    assert!(
                        (a.d[k][l] - b.d[k][l]).norm() <= 1e-10 * scale * (1.0 + b.d[k][l].norm()),
                        "d[{k}][{l}]"
                    );
                }
            }
            assert!((a.d[0][0] - b.d[0][0]).norm() <= 1e-12 * scale);
        }
    }
}

/// The non-rational fast path (Horner kernels for bicubic patches, the
/// general kernel otherwise) and the second-order `jet2` against the basis
/// recursion, on random non-rational surfaces of degrees 1 to 4.
#[test]
fn polynomial_fast_path_and_jet2_agree_with_the_basis_recursion() {
    let mut r = rng(17);
    for case in 0..60 {
        let mut spec = random_surface(&mut r, "s");
        spec.weights = None;
        if case % 2 == 0 {
            spec.degree = [3, 3];
            let (ku, nu) = random_knots(&mut r, 3);
            let (kv, nv) = random_knots(&mut r, 3);
            spec.knots_u = ku;
            spec.knots_v = kv;
            spec.control_points = (0..nu)
                .map(|i| {
                    (0..nv)
                        .map(|j| [i as f64 * 10.0, j as f64 * 10.0, uniform(&mut r, -8.0, 8.0)])
                        .collect()
                })
                .collect();
        }
        let s = build(&spec);
        let ((u0, u1), (v0, v1)) = s.domain();
        for _ in 0..20 {
            let (u, v) = (uniform(&mut r, u0, u1), uniform(&mut r, v0, v1));
            for nd in [1, 2, 3] {
                let (a, b) = (s.derivs(u, v, nd), s.derivs_de_boor(u, v, nd));
                let scale = 1.0 + b.d[0][0].norm() + b.d[1][0].norm() + b.d[0][1].norm();
                for k in 0..=nd {
                    for l in 0..=nd - k {
                        let err = (a.d[k][l] - b.d[k][l]).norm();
                        assert!(
                            err <= 1e-10 * scale * (1.0 + b.d[k][l].norm()),
                            "case {case} nd {nd} d[{k}][{l}]"
                        );
                    }
                }
            }
            let (j, b) = (s.jet2(u, v), s.derivs_de_boor(u, v, 2));
            let want = [
                b.d[0][0], b.d[1][0], b.d[0][1], b.d[2][0], b.d[1][1], b.d[0][2],
            ];
            for (got, want) in j.d.iter().zip(want) {
                assert!(
                    (got - want).norm() <= 1e-10 * (1.0 + want.norm()),
                    "case {case} jet2"
                );
            }
        }
    }
}

/// The rational second-order `jet2` (Horner's rule on the homogeneous
/// coefficients, then the quotient rule) against the basis recursion, on
/// random rational surfaces of degrees 1 to 4 in each direction (the
/// patch shapes without a dedicated kernel take the general path).
#[test]
fn rational_jet2_agrees_with_the_basis_recursion() {
    let mut r = rng(23);
    for case in 0..80 {
        let s = build(&random_surface(&mut r, "s"));
        assert!(s.is_rational());
        let ((u0, u1), (v0, v1)) = s.domain();
        for _ in 0..20 {
            let (u, v) = (uniform(&mut r, u0, u1), uniform(&mut r, v0, v1));
            let (j, b) = (s.jet2(u, v), s.derivs_de_boor(u, v, 2));
            let want = [
                b.d[0][0], b.d[1][0], b.d[0][1], b.d[2][0], b.d[1][1], b.d[0][2],
            ];
            let scale = 1.0 + b.d[1][0].norm() + b.d[0][1].norm();
            for (k, (got, want)) in j.d.iter().zip(want).enumerate() {
                assert!(
                    (got - want).norm() <= 1e-10 * scale * (1.0 + want.norm()),
                    "case {case} degree {:?} jet2[{k}]: {got} vs {want}",
                    (s.knots_u().degree(), s.knots_v().degree())
                );
            }
        }
    }
}

/// A random rational surface of degrees `p` by `q` placed where real parts
/// sit on a machine table (coordinates of several hundred mm).
fn high_degree_surface(r: &mut TestRng, p: usize, q: usize) -> NurbsSurface {
    let (ku, nu) = random_knots(r, p);
    let (kv, nv) = random_knots(r, q);
    let at = [350.0, -500.0, 120.0];
    let cps: Vec<Vec<[f64; 3]>> = (0..nu)
        .map(|i| {
            (0..nv)
                .map(|j| {
                    [
                        at[0] + i as f64 * 4.0 + uniform(r, -1.0, 1.0),
                        at[1] + j as f64 * 4.0 + uniform(r, -1.0, 1.0),
                        at[2] + uniform(r, -5.0, 5.0),
                    ]
                })
                .collect()
        })
        .collect();
    let w: Vec<Vec<f64>> = (0..nu)
        .map(|_| (0..nv).map(|_| uniform(r, 0.5, 2.0)).collect())
        .collect();
    NurbsSurface::try_new([p, q], ku, kv, &cps, Some(&w), false).unwrap()
}

/// Degrees 5 to 11 (real parts' blends) take the power-basis path too:
/// points, derivatives to third order and the second-order jet agree with
/// the basis recursion at table coordinates, points to 1e-8 mm (the
/// contact needs 1e-4 mm).
#[test]
fn high_degree_fast_path_agrees_with_the_basis_recursion() {
    let mut r = rng(29);
    for case in 0..60 {
        let (p, q) = (5 + case % 7, 5 + (case * 3) % 7);
        let s = high_degree_surface(&mut r, p, q);
        let ((u0, u1), (v0, v1)) = s.domain();
        for _ in 0..10 {
            let (u, v) = (uniform(&mut r, u0, u1), uniform(&mut r, v0, v1));
            let (a, b) = (s.derivs(u, v, 3), s.derivs_de_boor(u, v, 3));
            let e = (a.d[0][0] - b.d[0][0]).norm();
            assert!(e <= 1e-8, "case {case} point {p} {q} err {e:e}");
            assert!((s.point(u, v).coords - b.d[0][0]).norm() <= 1e-8);
            let scale = 1.0 + b.d[1][0].norm() + b.d[0][1].norm();
            for k in 0..4 {
                for l in 0..4 - k {
                    let err = (a.d[k][l] - b.d[k][l]).norm();
                    assert!(
                        err <= 1e-8 * scale * (1.0 + b.d[k][l].norm()),
                        "case {case} d[{k}][{l}]"
                    );
                }
            }
            let j = s.jet2(u, v);
            let want = [
                b.d[0][0], b.d[1][0], b.d[0][1], b.d[2][0], b.d[1][1], b.d[0][2],
            ];
            for (got, want) in j.d.iter().zip(want) {
                assert!(
                    (got - want).norm() <= 1e-8 * scale * (1.0 + want.norm()),
                    "case {case} jet2"
                );
            }
        }
    }
}
