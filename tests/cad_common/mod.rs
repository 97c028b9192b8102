//! Shared helpers of the CAD tests: a local NURBS evaluator written
//! independently of the crate (de Boor on homogeneous points).
#![allow(dead_code)]
use cmm::workpiece::format::SurfaceSpec;

fn basis_point(knots: &[f64], p: usize, cps: &[[f64; 4]], t: f64) -> [f64; 4] {
    let n = cps.len();
    let t = t.clamp(knots[p], knots[n]);
    let mut k = p;
    while k + 1 < n && knots[k + 1] <= t {
        k += 1;
    }
    let mut d: Vec<[f64; 4]> = (0..=p).map(|j| cps[j + k - p]).collect();
    for r in 1..=p {
        for j in (r..=p).rev() {
            let i = j + k - p;
            let den = knots[i + p + 1 - r] - knots[i];
            let a = if den > 0.0 { (t - knots[i]) / den } else { 0.0 };
            let prev = d[j - 1];
            for (x, p) in d[j].iter_mut().zip(prev) {
                *x = (1.0 - a) * p + a * *x;
            }
        }
    }
    d[p]
}

pub fn eval(s: &SurfaceSpec, u: f64, v: f64) -> [f64; 3] {
    let col: Vec<[f64; 4]> = s
        .control_points
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let h: Vec<[f64; 4]> = row
                .iter()
                .enumerate()
                .map(|(j, c)| {
                    let w = s.weights.as_ref().map_or(1.0, |w| w[i][j]);
                    [c[0] * w, c[1] * w, c[2] * w, w]
                })
                .collect();
            basis_point(&s.knots_v, s.degree[1], &h, v)
        })
        .collect();
    let h = basis_point(&s.knots_u, s.degree[0], &col, u);
    [h[0] / h[3], h[1] / h[3], h[2] / h[3]]
}
