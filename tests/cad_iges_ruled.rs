//! IGES 118 ruled surfaces between 126 B-spline rails of different degree
//! and knots, polynomial and rational (weights not proportional), against
//! `(1 - v) C1(u) + v C2(u)` with each rail evaluated from the numbers
//! written into the file (Cox-de Boor recursion) and the imported surface
//! evaluated from its own definition.
mod cad_iges_support;
mod common;

use cad_iges_support::{run, Iges};
use cmm::workpiece::format::SurfaceSpec;
use common::{basis, reference_point};

/// Agreement asked of an exact construction, relative to the part size.
const REL_TOL: f64 = 1e-12;

/// A 126 rail: degree, knots, control points and weights.
struct Rail {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<[f64; 3]>,
    weights: Vec<f64>,
}

impl Rail {
    /// Parameter data of entity 126 over the whole domain.
    fn params(&self) -> String {
        let real = |x: &f64| format!("{x:?}");
        let polynomial = i32::from(self.weights.iter().all(|w| *w == 1.0));
        let mut f = vec![
            (self.points.len() - 1).to_string(),
            self.degree.to_string(),
            "0".into(),
            "0".into(),
            polynomial.to_string(),
            "0".into(),
        ];
        f.extend(self.knots.iter().map(real));
        f.extend(self.weights.iter().map(real));
        f.extend(self.points.iter().flatten().map(real));
        let (lo, hi) = self.domain();
        f.extend([real(&lo), real(&hi), "0.".into(), "0.".into(), "1.".into()]);
        f.join(",")
    }

    fn domain(&self) -> (f64, f64) {
        let p = self.degree;
        (self.knots[p], self.knots[self.knots.len() - p - 1])
    }

    /// The rail at relative parameter `s` in `[0, 1]` of its domain.
    fn at(&self, s: f64) -> [f64; 3] {
        let (lo, hi) = self.domain();
        let t = lo + (hi - lo) * s;
        let (mut num, mut den) = ([0.0; 3], 0.0);
        for (i, (p, w)) in self.points.iter().zip(&self.weights).enumerate() {
            let b = basis(&self.knots, i, self.degree, t) * w;
            for k in 0..3 {
                num[k] += b * p[k];
            }
            den += b;
        }
        num.map(|c| c / den)
    }
}

/// Imports a 118 between `a` and `b` (`reversed`: `b` runs backwards) and
/// compares its surface with the ruling of the rails on a 40 x 8 grid;
/// returns the surface.
fn check_ruled(a: &Rail, b: &Rail, reversed: bool, scale: f64) -> SurfaceSpec {
    let mut g = Iges::default();
    let ea = g.add(126, 0, &a.params());
    let eb = g.add(126, 0, &b.params());
    g.add(118, 1, &format!("{ea},{eb},{},0", i32::from(reversed)));
    let imp = run(&g.text()).expect("imports");
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics);
    assert_eq!(imp.workpiece.surfaces.len(), 1);
    let spec = imp.workpiece.surfaces[0].clone();
    let surf = spec.to_surface().expect("valid surface");
    for i in 0..=40 {
        let u = i as f64 / 40.0;
        let (c1, c2) = (a.at(u), b.at(if reversed { 1.0 - u } else { u }));
        for j in 0..=8 {
            let v = j as f64 / 8.0;
            let want: [f64; 3] = std::array::from_fn(|k| (1.0 - v) * c1[k] + v * c2[k]);
            let got = reference_point(&spec, u, v);
            let fast = surf.point(u, v);
            for k in 0..3 {
                assert!(
                    (got[k] - want[k]).abs() <= REL_TOL * scale,
                    "({u}, {v}): {got:?} vs {want:?}"
                );
                assert!((fast[k] - want[k]).abs() <= REL_TOL * scale);
            }
        }
    }
    spec
}

#[test]
fn ruled_118_between_a_quadratic_and_a_cubic_b_spline() {
    // Degree 2 on [0, 2] and degree 3 on [1, 4], no knot in common
    // (relative to their domains).
    let a = Rail {
        degree: 2,
        knots: vec![0.0, 0.0, 0.0, 0.5, 1.2, 2.0, 2.0, 2.0],
        points: vec![
            [0.0, 0.0, 0.0],
            [3.0, 2.0, 0.5],
            [6.0, -1.0, 0.0],
            [9.0, 1.5, -0.5],
            [12.0, 0.0, 0.0],
        ],
        weights: vec![1.0; 5],
    };
    let b = Rail {
        degree: 3,
        knots: vec![1.0, 1.0, 1.0, 1.0, 2.5, 3.0, 4.0, 4.0, 4.0, 4.0],
        points: vec![
            [0.0, 1.0, 6.0],
            [2.0, 4.0, 7.0],
            [5.0, 2.0, 6.5],
            [7.0, -2.0, 6.0],
            [10.0, 3.0, 5.0],
            [12.5, 1.0, 6.0],
        ],
        weights: vec![1.0; 6],
    };
    check_ruled(&a, &b, false, 12.5);
    check_ruled(&b, &a, true, 12.5);
}

#[test]
fn ruled_118_between_a_circular_arc_and_a_rational_cubic() {
    // A quarter circle of radius 5 (rational quadratic) and a cubic whose
    // weights are not proportional to the arc's.
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let a = Rail {
        degree: 2,
        knots: vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        points: vec![[5.0, 0.0, 0.0], [5.0, 5.0, 0.0], [0.0, 5.0, 0.0]],
        weights: vec![1.0, w, 1.0],
    };
    let b = Rail {
        degree: 3,
        knots: vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0],
        points: vec![
            [8.0, 0.0, 4.0],
            [8.0, 3.0, 4.5],
            [6.0, 6.0, 4.0],
            [3.0, 8.0, 3.5],
            [0.0, 8.0, 4.0],
        ],
        weights: vec![1.0, 1.7, 0.6, 1.3, 1.0],
    };
    check_ruled(&a, &b, false, 8.0);
    let spec = check_ruled(&a, &b, true, 8.0);
    // The v = 0 edge is the circle itself.
    for k in 0..=200 {
        let p = reference_point(&spec, k as f64 / 200.0, 0.0);
        assert!((p[0].hypot(p[1]) - 5.0).abs() <= REL_TOL * 5.0, "{p:?}");
        assert!(p[2].abs() <= REL_TOL * 5.0);
    }
}
