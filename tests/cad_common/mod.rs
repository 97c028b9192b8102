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

/// A STEP file around `data` with a millimetre length unit.
pub fn wrap(data: &str) -> String {
    format!(
        "ISO-10303-21;\nHEADER;\nFILE_NAME('t','',(''),(''),'','','');\nENDSEC;\nDATA;\n{data}\
#900=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n\
#901=(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNIT_ASSIGNED_CONTEXT((#900))REPRESENTATION_CONTEXT('',''));\n\
ENDSEC;\nEND-ISO-10303-21;\n"
    )
}

/// Signed area of a closed (u, v) polyline (positive when counter-clockwise).
pub fn shoelace(pts: &[[f64; 2]]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}
