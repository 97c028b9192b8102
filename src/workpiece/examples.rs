//! The example workpieces shipped in `workpieces/`, generated here so they
//! can be regenerated (`cmm example-workpieces --out workpieces`) and checked
//! against the committed files by the tests.
use std::f64::consts::FRAC_1_SQRT_2;

use super::format::{SurfaceSpec, WorkpieceFile, WORKPIECE_FORMAT};

/// Every example: (file stem, content).
pub fn all() -> Vec<(&'static str, WorkpieceFile)> {
    vec![
        ("sphere", reference_sphere(25.0)),
        ("bore", bore(50.0, 20.0)),
        ("blade", blade()),
        ("panel", panel()),
    ]
}

fn file(name: &str, surfaces: Vec<SurfaceSpec>) -> WorkpieceFile {
    WorkpieceFile {
        format: WORKPIECE_FORMAT.into(),
        name: name.into(),
        units: "mm".into(),
        surfaces,
    }
}

/// Full circle of radius 1 as a 9-point rational quadratic: points `[x, y]`,
/// weights and knots.
pub fn unit_circle() -> (Vec<[f64; 2]>, Vec<f64>, Vec<f64>) {
    let pts = vec![
        [1., 0.],
        [1., 1.],
        [0., 1.],
        [-1., 1.],
        [-1., 0.],
        [-1., -1.],
        [0., -1.],
        [1., -1.],
        [1., 0.],
    ];
    let w = FRAC_1_SQRT_2;
    let weights = vec![1., w, 1., w, 1., w, 1., w, 1.];
    let knots = vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.];
    (pts, weights, knots)
}

/// Surface of revolution about z of a rational profile `[(r, z)]` with
/// weights `pw` and knots `knots_v`.
pub fn revolve(
    name: &str,
    profile: &[[f64; 2]],
    pw: &[f64],
    knots_v: Vec<f64>,
    reversed: bool,
) -> SurfaceSpec {
    let (circle, cw, knots_u) = unit_circle();
    let control_points = circle
        .iter()
        .map(|[x, y]| profile.iter().map(|[r, z]| [x * r, y * r, *z]).collect())
        .collect();
    let weights = cw
        .iter()
        .map(|wu| pw.iter().map(|wv| wu * wv).collect())
        .collect();
    SurfaceSpec {
        name: name.into(),
        degree: [2, 2],
        knots_u,
        knots_v,
        control_points,
        weights: Some(weights),
        reversed,
        trim: None,
    }
}

/// An exact rational sphere centred at the origin: u around z, v from the
/// south pole to the north pole; normal `Su x Sv` points outward.
pub fn reference_sphere(diameter: f64) -> WorkpieceFile {
    let r = 0.5 * diameter;
    let w = FRAC_1_SQRT_2;
    let profile = [[0., -r], [r, -r], [r, 0.], [r, r], [0., r]];
    let knots_v = vec![0., 0., 0., 0.5, 0.5, 1., 1., 1.];
    file(
        "reference-sphere",
        vec![revolve(
            "sphere",
            &profile,
            &[1., w, 1., w, 1.],
            knots_v,
            false,
        )],
    )
}

/// A bore: cylinder of `diameter` from z = 0 to z = `height`, axis z. Its
/// outward normal points into the hole, away from the material (`reversed`).
pub fn bore(diameter: f64, height: f64) -> WorkpieceFile {
    let r = 0.5 * diameter;
    let profile = [[r, 0.], [r, height]];
    let spec = revolve("bore", &profile, &[1., 1.], vec![0., 0., 1., 1.], true);
    file(
        "bore",
        vec![SurfaceSpec {
            degree: [2, 1],
            ..spec
        }],
    )
}

/// Section control polygons (chord x, thickness y) of the blade: suction
/// and pressure side from the leading edge (x = 0) to the trailing edge.
const SUCTION: [[f64; 2]; 8] = [
    [0., 0.],
    [0., 2.5],
    [6., 7.],
    [18., 10.5],
    [32., 10.5],
    [46., 7.],
    [60., 1.2],
    [60., 0.],
];
const PRESSURE: [[f64; 2]; 8] = [
    [0., 0.],
    [0., -2.5],
    [6., 0.5],
    [18., 3.],
    [32., 3.5],
    [46., 2.],
    [60., -1.2],
    [60., 0.],
];

/// Span stations of the blade (z, twist in degrees, chord scale). The
/// blade tapers without a twist: every section lies inside the ones below
/// it, so a vertical stylus reaches all of its surface (a twisted blade
/// overhangs its own sections near the edges and needs a tilted stylus).
const STATIONS: [(f64, f64, f64); 6] = [
    (0., 0., 1.0),
    (20., 0., 0.96),
    (40., 0., 0.92),
    (60., 0., 0.88),
    (80., 0., 0.84),
    (100., 0., 0.8),
];

/// A turbine-blade-like loft: two bicubic surfaces (pressure and suction
/// side) meeting tangentially at the leading and trailing edges, 100 mm span,
/// tapered; every z-section is a closed smooth profile.
pub fn blade() -> WorkpieceFile {
    let side = |name: &str, poly: &[[f64; 2]; 8], reversed: bool| SurfaceSpec {
        name: name.into(),
        degree: [3, 3],
        knots_u: vec![0., 0., 0., 0., 0.2, 0.4, 0.6, 0.8, 1., 1., 1., 1.],
        knots_v: vec![0., 0., 0., 0., 1. / 3., 2. / 3., 1., 1., 1., 1.],
        control_points: poly
            .iter()
            .map(|xy| STATIONS.iter().map(|st| station_point(*xy, *st)).collect())
            .collect(),
        weights: None,
        reversed,
        trim: None,
    };
    // Su runs along the chord (+x), Sv along the span (+z): Su x Sv = -y,
    // outward for the pressure side; the suction side is reversed.
    file(
        "blade",
        vec![
            side("pressure", &PRESSURE, false),
            side("suction", &SUCTION, true),
        ],
    )
}

fn station_point([x, y]: [f64; 2], (z, twist_deg, scale): (f64, f64, f64)) -> [f64; 3] {
    let (cx, cy) = (30.0, 5.0);
    let (s, c) = twist_deg.to_radians().sin_cos();
    let (dx, dy) = ((x - cx) * scale, (y - cy) * scale);
    [cx + c * dx - s * dy, cy + s * dx + c * dy, z]
}

/// A freeform panel: bicubic, 20 x 20 control points over 200 x 150 mm with
/// a smooth doubly curved height field (up to about 15 mm).
pub fn panel() -> WorkpieceFile {
    let n = 20;
    let knots = clamped_uniform(n, 3);
    let height = |x: f64, y: f64| {
        let (a, b) = (x / 200.0, y / 150.0);
        10.0 * (std::f64::consts::PI * a).sin() * (1.0 - 0.3 * b) + 4.0 * (3.0 * a + 2.0 * b).cos()
    };
    let control_points = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let (x, y) = (
                        200.0 * i as f64 / (n - 1) as f64,
                        150.0 * j as f64 / (n - 1) as f64,
                    );
                    [x, y, round6(height(x, y))]
                })
                .collect()
        })
        .collect();
    let spec = SurfaceSpec {
        name: "panel".into(),
        degree: [3, 3],
        knots_u: knots.clone(),
        knots_v: knots,
        control_points,
        weights: None,
        reversed: false,
        trim: None,
    };
    file("panel", vec![spec])
}

/// Rounds to 6 decimals so the shipped file is short and exact.
fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// Clamped uniform knot vector on [0, 1] for `n` control points.
fn clamped_uniform(n: usize, p: usize) -> Vec<f64> {
    let spans = n - p;
    let mut k = vec![0.0; p + 1];
    k.extend((1..spans).map(|i| round6(i as f64 / spans as f64)));
    k.extend(std::iter::repeat_n(1.0, p + 1));
    k
}

/// The shipped JSON text of a workpiece (pretty, with a final newline).
pub fn to_json(wp: &WorkpieceFile) -> String {
    let mut s = serde_json::to_string_pretty(wp).unwrap_or_default();
    s.push('\n');
    s
}

/// A small measured-looking point set on the blade (`blade-points.csv`):
/// 36 points around the z = 60 section, each off the nominal surface along
/// its normal by a known smooth deviation of up to 0.03 mm.
pub fn blade_points_csv() -> String {
    use crate::geometry::{Plane, SectionOptions};
    use crate::math::{Point3, Vec3};
    use crate::workpiece::section_faces;
    let mut out = String::from("id,x,y,z\n");
    let Ok(wp) = super::Workpiece::from_file(&blade(), "blade.json".as_ref()) else {
        return out;
    };
    let Ok(plane) = Plane::try_new(Point3::new(0.0, 0.0, 60.0), Vec3::z()) else {
        return out;
    };
    let faces: Vec<usize> = (0..wp.faces.len()).collect();
    let curves = section_faces(&wp, &faces, &plane, &SectionOptions::default());
    let Some(curve) = curves.first() else {
        return out;
    };
    let step = (curve.points.len() / 36).max(1);
    for (k, sp) in curve.points.iter().step_by(step).take(36).enumerate() {
        let dev = 0.03 * (k as f64 * 0.7).sin();
        let p = sp.point + sp.normal * dev;
        out.push_str(&format!("{},{:.6},{:.6},{:.6}\n", k + 1, p.x, p.y, p.z));
    }
    out
}
