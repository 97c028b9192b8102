//! Geometry kernel benchmarks: evaluation, warm and cold projection, and
//! `cmm evaluate` per point near a real trimmed part.
//!
//! `cargo bench --bench geometry` (`-- evaluate` for the last alone)
use std::hint::black_box;
use std::path::Path;

use cmm::geometry::projection::{project_from, project_warm, WarmStart};
use cmm::math::{Point3, Vec2};
use cmm::workpiece::Workpiece;
use criterion::{criterion_group, criterion_main, Criterion};

fn load(stem: &str) -> Workpiece {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("workpieces/{stem}.json"));
    match Workpiece::from_path(&path) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    }
}

/// Query points 1.2 mm off the surface along a path, 0.05 mm apart, with
/// the parameters of the previous foot as the warm hint.
fn path(wp: &Workpiece, n: usize) -> Vec<(Point3, Vec2)> {
    let s = &wp.faces[0].surface;
    let ((u0, u1), (v0, v1)) = s.domain();
    let v = 0.5 * (v0 + v1);
    let mut out = Vec::with_capacity(n);
    let mut t = u0 + 0.1 * (u1 - u0);
    let mut prev = Vec2::new(t, v);
    while out.len() < n {
        let d = s.derivs(t, v, 1);
        let p = d.point() + s.normal(t, v) * 1.2;
        out.push((p, prev));
        prev = Vec2::new(t, v);
        t += 0.05 / d.su().norm().max(1e-9);
        if t > u0 + 0.9 * (u1 - u0) {
            t = u0 + 0.1 * (u1 - u0);
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    for stem in ["panel", "blade", "sphere"] {
        let wp = load(stem);
        let face = &wp.faces[0];
        let queries = path(&wp, 1000);
        c.bench_function(&format!("derivs2/{stem}"), |b| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % queries.len();
                let uv = queries[k].1;
                black_box(face.surface.derivs(uv.x, uv.y, 2))
            })
        });
        c.bench_function(&format!("project_warm/{stem}"), |b| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % queries.len();
                let (p, hint) = queries[k];
                black_box(project_from(&face.surface, p, hint, &wp.options).ok())
            })
        });
        c.bench_function(&format!("project_warm_path/{stem}"), |b| {
            let mut k = 0;
            let mut warm = WarmStart::new(queries[0].1);
            b.iter(|| {
                k = (k + 1) % queries.len();
                let p = queries[k].0;
                black_box(project_warm(&face.surface, p, &mut warm, &wp.options).ok())
            })
        });
        c.bench_function(&format!("project_cold/{stem}"), |b| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % queries.len();
                black_box(face.index().project(&face.surface, queries[k].0).ok())
            })
        });
    }
}

/// The NIST test part (about 200 trimmed faces), when the shared CAD
/// files sit beside the repository.
fn nist() -> Option<Workpiece> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/cad/nist_ctc_05_asme1_rd.stp");
    Workpiece::from_path(&path).ok()
}

/// Points 0.5 mm off the faces of `wp` (along the normal, at random
/// parameters inside each face's trim), seeded.
fn near_points(wp: &Workpiece, n: usize) -> Vec<Point3> {
    let mut out = Vec::with_capacity(n);
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut tries = 0;
    while out.len() < n && tries < 100 * n {
        tries += 1;
        let Some(face) = wp.faces.get((next() * wp.faces.len() as f64) as usize) else {
            continue;
        };
        let ((u0, u1), (v0, v1)) = face.surface.domain();
        let uv = Vec2::new(u0 + (u1 - u0) * next(), v0 + (v1 - v0) * next());
        if face.contains(uv) {
            let off = if next() < 0.5 { 0.5 } else { -0.5 };
            out.push(face.surface.point(uv.x, uv.y) + face.surface.normal(uv.x, uv.y) * off);
        }
    }
    out
}

fn bench_evaluate(c: &mut Criterion) {
    let Some(wp) = nist() else {
        eprintln!("evaluate: nist_ctc_05 not found beside the repository, skipped");
        return;
    };
    let points = near_points(&wp, 500);
    c.bench_function(
        &format!("evaluate/nist_ctc_05 ({} faces, per point)", wp.faces.len()),
        |b| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % points.len();
                black_box(cmm::evaluate::evaluate_point(&wp, points[k]).ok())
            })
        },
    );
}

/// A real part's high-degree blend (linkrods.step, a rational face of
/// degrees 6 by 10): the power-basis evaluation against the basis
/// recursion it replaces.
fn bench_high_degree(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/linkrods.step");
    let wp = match Workpiece::from_path(&path) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    };
    let degree =
        |f: &&cmm::workpiece::Face| (f.surface.knots_u().degree(), f.surface.knots_v().degree());
    let Some(face) = wp.faces.iter().find(|f| degree(f) == (6, 10)) else {
        panic!("linkrods.step has no face of degrees 6 by 10");
    };
    let s = &face.surface;
    let ((u0, u1), (v0, v1)) = s.domain();
    let uv: Vec<(f64, f64)> = (0..1000)
        .map(|k| {
            let (a, b) = ((k % 37) as f64 / 37.0, (k % 41) as f64 / 41.0);
            (u0 + a * (u1 - u0), v0 + b * (v1 - v0))
        })
        .collect();
    for (name, fast) in [("power basis", true), ("basis recursion", false)] {
        c.bench_function(&format!("derivs2_degree_6x10/{name}"), |b| {
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % uv.len();
                let (u, v) = uv[k];
                if fast {
                    black_box(s.derivs(u, v, 2))
                } else {
                    black_box(s.derivs_de_boor(u, v, 2))
                }
            })
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = bench, bench_evaluate, bench_high_degree
}
criterion_main!(benches);
