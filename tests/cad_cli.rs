//! `cmm import` and `cmm evaluate --workpiece PART.step` on the real CAD
//! parts in ../shared/cad (skipped with a note when absent), checked against
//! independent references: points built as `S(u, v) + d n` with the local
//! evaluator of `cad_common` must come back with deviation `d`, and a point
//! beyond a face's boundary must come back with its distance to the face's
//! 3-D edges (sampled by the reader, not taken from the trim).
mod cad_common;

use cad_common::eval;
use cmm::cad::step::{access::Ctx, parse_step, topology, topology::EdgeSampler, units};
use cmm::cad::{import, ImportOptions};
use cmm::workpiece::format::{SurfaceSpec, WorkpieceFile};
use cmm::workpiece::Workpiece;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Agreement of evaluated deviations with the constructed offsets, mm.
const DEVIATION_TOL_MM: f64 = 1e-6;
/// Agreement of a boundary distance with the 3-D edge polylines, mm.
const BOUNDARY_TOL_MM: f64 = 1e-3;
/// Largest offset of a generated point from its face, mm; offsets are also
/// at most half the foot's distance from the face's boundary (small faces).
const MAX_OFFSET_MM: f64 = 1.0;
/// Feet of generated points keep this far from their face's boundary, mm.
const MIN_CLEARANCE_MM: f64 = 0.02;
/// Generated points are at least this much closer to their face than to
/// any other face, mm.
const OTHER_FACE_MARGIN_MM: f64 = 0.05;

const FILES: [&str; 5] = [
    "abc-0000.step",
    "bearing.iges",
    "io1-cm-214.stp",
    "linkrods.step",
    "nist_ctc_05_asme1_rd.stp",
];

fn shared(name: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/cad")
        .join(name);
    if p.exists() {
        return Some(p);
    }
    println!("note: {} not found; skipping", p.display());
    None
}

fn cmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn import_writes_a_workpiece_that_loads_back_with_the_same_faces() {
    let dir = tempfile::tempdir().unwrap();
    for name in FILES {
        let Some(src) = shared(name) else { return };
        let out = dir.path().join(format!("{name}.json"));
        let run = cmm(&["import", s(&src), "--out", s(&out)]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(0), "{name}: {stderr}");
        let direct = import(&src).unwrap();
        // Notes (a part too small for its units) come after the summary.
        let lines: Vec<&str> = stderr
            .lines()
            .filter(|l| !l.starts_with("note: "))
            .collect();
        assert_eq!(lines.len(), direct.diagnostics.len() + 1, "{stderr}");
        assert!(lines
            .last()
            .unwrap()
            .starts_with(&format!("imported {} faces (", direct.faces.len())));
        let back = Workpiece::from_path(&out).unwrap();
        let cad = Workpiece::from_path(&src).unwrap();
        assert_eq!(back.faces.len(), cad.faces.len(), "{name}");
        for (a, b) in back.faces.iter().zip(&cad.faces) {
            assert_eq!(a.name, b.name);
            assert_eq!(a.trim.is_some(), b.trim.is_some(), "{}", a.name);
            let ((u0, u1), (v0, v1)) = b.surface.domain();
            let (u, v) = (0.3 * u0 + 0.7 * u1, 0.6 * v0 + 0.4 * v1);
            assert!((a.surface.point(u, v) - b.surface.point(u, v)).norm() < 1e-9);
        }
        let file: WorkpieceFile =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let names: Vec<&str> = file.surfaces.iter().map(|s| s.name.as_str()).collect();
        let want: Vec<&str> = direct.faces.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, want, "{name}");
    }
}

/// Even-odd point-in-polygon test (independent of the crate's trims).
fn inside(poly: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut odd = false;
    for (i, a) in poly.iter().enumerate() {
        let b = poly[(i + 1) % poly.len()];
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            odd ^= p[0] < x;
        }
    }
    odd
}

fn on_face(spec: &SurfaceSpec, uv: [f64; 2]) -> bool {
    let t = spec.trim.as_ref().unwrap();
    inside(&t.outer, uv) && !t.holes.iter().any(|h| inside(h, uv))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Outward unit normal by central differences of the local evaluator.
fn normal(spec: &SurfaceSpec, u: f64, v: f64) -> [f64; 3] {
    let h = 1e-6;
    let su = sub(eval(spec, u + h, v), eval(spec, u - h, v));
    let sv = sub(eval(spec, u, v + h), eval(spec, u, v - h));
    let c = [
        su[1] * sv[2] - su[2] * sv[1],
        su[2] * sv[0] - su[0] * sv[2],
        su[0] * sv[1] - su[1] * sv[0],
    ];
    let k = if spec.reversed { -1.0 } else { 1.0 } / norm(c);
    [c[0] * k, c[1] * k, c[2] * k]
}

fn segment_distance(q: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let aq = sub(q, a);
    let len2 = ab.iter().map(|x| x * x).sum::<f64>();
    let t = if len2 > 0.0 {
        (aq.iter().zip(ab).map(|(x, y)| x * y).sum::<f64>() / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(sub(
        q,
        [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]],
    ))
}

fn polyline_distance(q: [f64; 3], loops: &[Vec<[f64; 3]>]) -> f64 {
    loops
        .iter()
        .flat_map(|l| (0..l.len()).map(move |i| (l[i], l[(i + 1) % l.len()])))
        .map(|(a, b)| segment_distance(q, a, b))
        .fold(f64::INFINITY, f64::min)
}

/// The trim loops of a face mapped to 3-D (for keeping away from edges).
fn trim_3d(spec: &SurfaceSpec) -> Vec<Vec<[f64; 3]>> {
    let t = spec.trim.as_ref().unwrap();
    std::iter::once(&t.outer)
        .chain(&t.holes)
        .map(|l| l.iter().map(|uv| eval(spec, uv[0], uv[1])).collect())
        .collect()
}

/// Points `S(u, v) + d n` on trimmed faces, away from edges and other faces.
fn generate(wp: &Workpiece, specs: &[SurfaceSpec], per_face: usize) -> Vec<([f64; 3], f64)> {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let mut out = Vec::new();
    for (k, spec) in specs.iter().enumerate() {
        let Some(t) = &spec.trim else { continue };
        let edges = trim_3d(spec);
        let (lo, hi) = t.outer.iter().fold(
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
            |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1])],
                    [hi[0].max(p[0]), hi[1].max(p[1])],
                )
            },
        );
        let mut found = 0;
        for _ in 0..200 {
            let uv = [
                rng.random_range(lo[0]..=hi[0]),
                rng.random_range(lo[1]..=hi[1]),
            ];
            if found == per_face || !on_face(spec, uv) {
                continue;
            }
            let foot = eval(spec, uv[0], uv[1]);
            let clearance = polyline_distance(foot, &edges);
            if clearance < MIN_CLEARANCE_MM {
                continue;
            }
            let max = MAX_OFFSET_MM.min(0.5 * clearance);
            let d = rng.random_range(-max..max);
            let n = normal(spec, uv[0], uv[1]);
            let p = [foot[0] + d * n[0], foot[1] + d * n[1], foot[2] + d * n[2]];
            let others = (0..specs.len()).filter(|&i| i != k);
            let q = cmm::math::Point3::new(p[0], p[1], p[2]);
            let other = wp.closest_point_among(q, others).unwrap();
            if other.projection.distance > d.abs() + OTHER_FACE_MARGIN_MM {
                out.push((p, d));
                found += 1;
            }
        }
    }
    out
}

fn write_points(path: &Path, pts: &[[f64; 3]]) {
    let mut text = String::from("x,y,z\n");
    for p in pts {
        text.push_str(&format!("{:.17e},{:.17e},{:.17e}\n", p[0], p[1], p[2]));
    }
    std::fs::write(path, text).unwrap();
}

fn deviations(workpiece: &Path, points: &Path) -> Vec<f64> {
    let run = cmm(&[
        "evaluate",
        "--workpiece",
        s(workpiece),
        "--points",
        s(points),
        "--json",
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{stderr}");
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let pts = v["points"].as_array().unwrap();
    pts.iter()
        .map(|p| p["deviation_mm"].as_f64().unwrap())
        .collect()
}

#[test]
fn evaluate_on_a_step_part_recovers_constructed_offsets() {
    let dir = tempfile::tempdir().unwrap();
    for (name, per_face) in [("linkrods.step", 3), ("nist_ctc_05_asme1_rd.stp", 1)] {
        let Some(src) = shared(name) else { return };
        let specs = import(&src).unwrap().workpiece.surfaces;
        let wp = Workpiece::from_path(&src).unwrap();
        let pts = generate(&wp, &specs, per_face);
        println!("{name}: {} points", pts.len());
        assert!(pts.len() >= specs.len() / 2, "{name}: {} points", pts.len());
        let csv = dir.path().join("p.csv");
        write_points(&csv, &pts.iter().map(|p| p.0).collect::<Vec<_>>());
        let got = deviations(&src, &csv);
        assert_eq!(got.len(), pts.len());
        for ((p, d), dev) in pts.iter().zip(got) {
            assert!(
                (dev - d).abs() < DEVIATION_TOL_MM,
                "{name}: {p:?}: deviation {dev}, constructed {d}"
            );
        }
    }
}

/// The reader's 3-D polylines of a STEP face's bounds (chord error < 1 um).
fn edge_loops(src: &Path, face_entity: u64) -> Vec<Vec<[f64; 3]>> {
    let text = std::fs::read_to_string(src).unwrap();
    let step = parse_step(&text, "f").unwrap();
    let u = units::find_units(&step, "f").unwrap();
    let ctx = Ctx {
        step: &step,
        file: "f",
        length_mm: u.length_mm,
        angle_rad: u.angle_rad,
    };
    let face = topology::face(&ctx, face_entity, "ADVANCED_FACE").unwrap();
    let mut sampler = EdgeSampler::new(ctx, ImportOptions::default());
    face.bounds
        .iter()
        .map(|b| {
            let pts = sampler.bound_points(b).unwrap();
            pts.iter().map(|p| [p.x, p.y, p.z]).collect()
        })
        .collect()
}

#[test]
fn point_beyond_a_projected_trim_reports_the_edge_distance() {
    let Some(src) = shared("linkrods.step") else {
        return;
    };
    let imp = import(&src).unwrap();
    // A B-spline face whose PCURVEs miss its vertices: its trim is projected.
    let k = imp.faces.iter().position(|f| f.entity == 7998).unwrap();
    let spec = imp.workpiece.surfaces[k].clone();
    let edges = edge_loops(&src, 7998);
    let all: Vec<[f64; 3]> = edges.iter().flatten().copied().collect();
    let c = all.iter().fold([0.0; 3], |a, p| {
        let n = all.len() as f64;
        [a[0] + p[0] / n, a[1] + p[1] / n, a[2] + p[2] / n]
    });
    let dir = tempfile::tempdir().unwrap();
    let one = WorkpieceFile {
        surfaces: vec![spec],
        ..imp.workpiece.clone()
    };
    let wp_path = dir.path().join("one.json");
    std::fs::write(&wp_path, serde_json::to_string(&one).unwrap()).unwrap();
    // Points pushed out from the face's centre through a few edge points.
    let queries: Vec<[f64; 3]> = (0..4)
        .map(|i| {
            let b = all[i * all.len() / 4];
            let out = sub(b, c);
            let k = 3.0 / norm(out);
            [b[0] + k * out[0], b[1] + k * out[1], b[2] + k * out[2]]
        })
        .collect();
    let csv = dir.path().join("q.csv");
    write_points(&csv, &queries);
    for (q, dev) in queries.iter().zip(deviations(&wp_path, &csv)) {
        let want = polyline_distance(*q, &edges);
        assert!(want > 1.0, "{q:?} is beyond the boundary");
        assert!(
            (dev.abs() - want).abs() < BOUNDARY_TOL_MM,
            "{q:?}: deviation {dev}, edge distance {want}"
        );
    }
}

const MALFORMED: &str = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.);\nENDSEC;\nEND-ISO-10303-21;\n";

#[test]
fn malformed_step_exits_2_with_its_place() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.STEP");
    std::fs::write(&bad, MALFORMED).unwrap();
    let csv = dir.path().join("p.csv");
    write_points(&csv, &[[0.0, 0.0, 0.0]]);
    let run = cmm(&["evaluate", "--workpiece", s(&bad), "--points", s(&csv)]);
    assert_eq!(run.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains(&format!("{}:5:", bad.display())),
        "{stderr}"
    );
    let out = dir.path().join("w.json");
    let run = cmm(&["import", s(&bad), "--out", s(&out)]);
    assert_eq!(run.status.code(), Some(2));
    assert!(!out.exists(), "nothing written");
}

#[test]
fn step_without_faces_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path().join("empty.stp");
    let text = MALFORMED.replace("0.,0.,0.);", "0.,0.,0.));");
    std::fs::write(&empty, text).unwrap();
    let err = Workpiece::from_path(&empty).unwrap_err().to_string();
    assert!(err.contains("empty.stp:"), "{err}");
}

#[test]
fn part_program_may_name_a_step_workpiece() {
    let Some(src) = shared("io1-cm-214.stp") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let prog = dir.path().join("p.json");
    let text = serde_json::json!({
        "format": "cmm-program/1", "name": "io1", "workpiece": s(&src),
        "placement": { "translate_mm": [350, 500, 150], "rotate_deg": [0, 0, 0] },
        "probe": { "tip_diameter_mm": 3.0, "stylus_length_mm": 50 },
        // The flange's outer cylinder (its two halves, by the names
        // `cmm import` gives) where the plane z = 40 cuts it.
        "features": [ { "name": "flange", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 40], "normal": [0, 0, 1] },
            "surfaces": ["face1", "face20"], "tolerance_mm": [-0.1, 0.1] },
          // The part is a flanged ring lying on its side (axis along x):
          // at z = 5 the plane cuts its bore, which a vertical stylus
          // cannot enter.
          { "name": "low", "type": "section_scan",
            "plane": { "origin_mm": [0, 0, 5], "normal": [0, 0, 1] },
            "tolerance_mm": [-0.1, 0.1] } ]
    });
    std::fs::write(&prog, text.to_string()).unwrap();
    let run = cmm(&["check", s(&prog)]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert_eq!(run.status.code(), Some(3), "{stdout}");
    assert!(stdout.contains("(29 surfaces)"), "{stdout}");
    assert!(!stdout.contains("flange ["), "{stdout}");
    assert!(
        stdout.contains("low [") && stdout.contains("not reachable"),
        "{stdout}"
    );
}

/// A part a fraction of a millimetre across (bearing.iges states
/// millimetres for a part 0.16 mm across) gets a note on its units; a
/// part of ordinary size none.
#[test]
fn import_notes_a_part_too_small_for_its_units() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w.json");
    let flange = Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/io1-flange.stp");
    let o = cmm(&["import", s(&flange), "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("note:"),
        "{o:?}"
    );
    let Some(bearing) = shared("bearing.iges") else {
        return;
    };
    let o = cmm(&["import", s(&bearing), "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("note: the part is 0.16"), "{err}");
}
