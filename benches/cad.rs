//! Import speed of the largest real STEP file (linkrods.step, 1.8 MB) and
//! of the IGES part; `cargo bench --bench cad`.
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

criterion_group!(benches, bench_import);
criterion_main!(benches);
