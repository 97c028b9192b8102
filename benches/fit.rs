//! Least-squares cylinder and sphere on one million points.
//!
//! Run: `cargo bench --bench fit` (small sample size, a few seconds).
use std::hint::black_box;
use std::time::Duration;

use cmm::fit::{fit, ElementKind, FitOptions, Method};
use cmm::math::{rotation_xyz_deg, Point3, Vec3};
use criterion::{criterion_group, criterion_main, Criterion};

const N: usize = 1_000_000;

/// Deterministic form error of a few micrometres (no RNG needed).
fn wobble(i: usize) -> f64 {
    let t = i as f64;
    0.002 * (t * 0.618_033_988_7).sin() + 0.001 * (t * 1.732_05).cos()
}

fn cylinder_points() -> Vec<Point3> {
    let rot = rotation_xyz_deg([10.0, 20.0, 30.0]);
    let shift = Vec3::new(100.0, 200.0, 50.0);
    (0..N)
        .map(|i| {
            let a = std::f64::consts::TAU * (i % 1000) as f64 / 1000.0;
            let (z, r) = ((i / 1000) as f64 * 0.1, 25.0 + wobble(i));
            Point3::from(rot * Vec3::new(r * a.cos(), r * a.sin(), z) + shift)
        })
        .collect()
}

fn sphere_points() -> Vec<Point3> {
    let centre = Vec3::new(-40.0, 12.0, 300.0);
    (0..N)
        .map(|i| {
            let az = std::f64::consts::TAU * (i % 1000) as f64 / 1000.0;
            let pol = 0.05 + 1.5 * (i / 1000) as f64 / 1000.0;
            let r = 12.5 + wobble(i);
            Point3::from(
                centre + Vec3::new(pol.sin() * az.cos(), pol.sin() * az.sin(), pol.cos()) * r,
            )
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let opts = FitOptions::default();
    let mut group = c.benchmark_group("lsq_1e6_points");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    let cyl = cylinder_points();
    group.bench_function("cylinder", |b| {
        b.iter(|| {
            fit(ElementKind::Cylinder, Method::Lsq, black_box(&cyl), &opts).map(|r| r.form_mm)
        })
    });
    let sph = sphere_points();
    group.bench_function("sphere", |b| {
        b.iter(|| fit(ElementKind::Sphere, Method::Lsq, black_box(&sph), &opts).map(|r| r.form_mm))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
