//! Import speed of the largest real STEP file (linkrods.step, 1.8 MB) and
//! of the IGES part, and the closest-point evaluation of points near the
//! NIST CTC 05 part (209 trimmed faces, as `cmm evaluate` does it);
//! `cargo bench --bench cad`.
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn shared(name: &str) -> Option<String> {
    let p = format!("{}/../shared/cad/{name}", env!("CARGO_MANIFEST_DIR"));
    std::path::Path::new(&p).exists().then_some(p)
}

fn bench_import(c: &mut Criterion) {
    let mut group = c.benchmark_group("cad");
    group.sample_size(20);
    if let Some(p) = shared("linkrods.step") {
        let text = std::fs::read_to_string(&p).unwrap_or_default();
        group.bench_function("parse linkrods.step (1.8 MB)", |b| {
            b.iter(|| black_box(cmm::cad::parse_step_str(&text).is_ok()))
        });
        group.bench_function("import linkrods.step (1.8 MB)", |b| {
            b.iter(|| black_box(cmm::cad::import(&p).is_ok()))
        });
    }
    if let Some(p) = shared("nist_ctc_05_asme1_rd.stp") {
        group.bench_function("import nist_ctc_05 (0.3 MB)", |b| {
            b.iter(|| black_box(cmm::cad::import(&p).is_ok()))
        });
    }
    if let Some(p) = shared("bearing.iges") {
        group.bench_function("import bearing.iges (1.3 MB)", |b| {
            b.iter(|| black_box(cmm::cad::import(&p).is_ok()))
        });
    }
    group.finish();
}

/// Points 0.5 mm off every face of `wp` (a 3 x 3 grid of parameters on
/// each, along the normal; some lie beyond a face's trim, where another
/// face or an edge is nearest).
fn points_near(wp: &cmm::workpiece::Workpiece) -> Vec<cmm::math::Point3> {
    let mut out = Vec::new();
    for f in &wp.faces {
        let ((u0, u1), (v0, v1)) = f.surface.domain();
        for i in 1..=3 {
            for j in 1..=3 {
                let (u, v) = (
                    u0 + (u1 - u0) * i as f64 / 4.0,
                    v0 + (v1 - v0) * j as f64 / 4.0,
                );
                out.push(f.surface.point(u, v) + f.surface.normal(u, v) * 0.5);
            }
        }
    }
    out
}

fn bench_evaluate(c: &mut Criterion) {
    let path = format!("{}/workpieces/nist-ctc05.stp", env!("CARGO_MANIFEST_DIR"));
    let Ok(wp) = cmm::workpiece::Workpiece::from_path(std::path::Path::new(&path)) else {
        return;
    };
    let points = points_near(&wp);
    println!("evaluate nist-ctc05: {} points per run", points.len());
    let mut group = c.benchmark_group("cad");
    group.sample_size(10);
    group.throughput(criterion::Throughput::Elements(points.len() as u64));
    group.bench_function("evaluate points near nist-ctc05 (209 faces)", |b| {
        b.iter(|| black_box(cmm::evaluate::evaluate(&wp, &points).is_ok()))
    });
    group.finish();
}

criterion_group!(benches, bench_import, bench_evaluate);
criterion_main!(benches);
