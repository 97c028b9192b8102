//! The io1-cm-214 part written by OpenCASCADE's IGES writer as a manifold
//! solid B-rep (186/514/510/508/504/502 on 190/192/198 surfaces), checked
//! against independent references: OpenCASCADE's face count (29, README of
//! the part files), the surface types from a plain scan of the Directory
//! section, the same part read from its STEP file (points sampled on each
//! reader's faces lie on the other's faces to 1e-6 mm, and normals agree
//! in sense), and the enclosed volume from the divergence theorem (positive
//! only when the normals point out of the material).
use cmm::cad::{import, Import};
use cmm::math::{Point3, Vec2};
use cmm::workpiece::Workpiece;
use std::collections::BTreeMap;
use std::path::Path;

/// A part file: `$CMM_SHARED_CAD/<name>` when that variable is set, else
/// `../shared/cad/<name>` beside the repository.
fn path(name: &str) -> Option<String> {
    let dir = std::env::var("CMM_SHARED_CAD")
        .unwrap_or_else(|_| format!("{}/../shared/cad", env!("CARGO_MANIFEST_DIR")));
    let p = format!("{dir}/{name}");
    if Path::new(&p).exists() {
        return Some(p);
    }
    println!("note: {p} not found; skipping");
    None
}

fn workpiece(imp: &Import) -> Workpiece {
    Workpiece::from_file(&imp.workpiece, Path::new("x")).expect("valid workpiece")
}

/// Points of each face on an `n x n` grid of its domain, inside its trim.
fn face_samples(wp: &Workpiece, n: usize) -> Vec<(usize, Point3)> {
    let mut out = Vec::new();
    for (k, f) in wp.faces.iter().enumerate() {
        let ((u0, u1), (v0, v1)) = f.surface.domain();
        for i in 0..n {
            for j in 0..n {
                let uv = Vec2::new(
                    u0 + (u1 - u0) * (i as f64 + 0.5) / n as f64,
                    v0 + (v1 - v0) * (j as f64 + 0.5) / n as f64,
                );
                if f.contains(uv) {
                    out.push((k, f.surface.point(uv.x, uv.y)));
                }
            }
        }
    }
    out
}

/// Surface type of every 510 face, from the Directory and Parameter text.
fn text_surface_types(text: &str) -> BTreeMap<String, usize> {
    let lines: Vec<&str> = text.lines().collect();
    let d: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.get(72..73) == Some("D"))
        .collect();
    let kind_of = |de: usize| d[de - 1][..8].trim().to_string();
    let mut counts = BTreeMap::new();
    for l in lines
        .iter()
        .filter(|l| l.get(72..73) == Some("P") && l.starts_with("510,"))
    {
        let surf: usize = l
            .split(',')
            .nth(1)
            .expect("surface field")
            .trim()
            .parse()
            .expect("DE");
        *counts.entry(format!("IGES {}", kind_of(surf))).or_insert(0) += 1;
    }
    counts
}

/// Volume enclosed by the faces: (1/3) sum of p . n dA over the trimmed
/// domains (midpoint rule on an `n x n` grid per face).
fn volume(wp: &Workpiece, n: usize) -> f64 {
    let mut v = 0.0;
    for f in &wp.faces {
        let ((u0, u1), (v0, v1)) = f.surface.domain();
        let (du, dv) = ((u1 - u0) / n as f64, (v1 - v0) / n as f64);
        for i in 0..n {
            for j in 0..n {
                let uv = Vec2::new(u0 + du * (i as f64 + 0.5), v0 + dv * (j as f64 + 0.5));
                if !f.contains(uv) {
                    continue;
                }
                let d = f.surface.derivs(uv.x, uv.y, 1);
                let mut normal = d.su().cross(&d.sv());
                if f.surface.is_reversed() {
                    normal = -normal;
                }
                v += d.point().coords.dot(&normal) * du * dv / 3.0;
            }
        }
    }
    v
}

fn both() -> Option<(Import, Import, String)> {
    let (Some(ig), Some(st)) = (path("io1-cm-214-brep.igs"), path("io1-cm-214.stp")) else {
        return None;
    };
    let text = std::fs::read_to_string(&ig).expect("read");
    Some((
        import(&ig).expect("IGES imports"),
        import(&st).expect("STEP imports"),
        text,
    ))
}

#[test]
fn brep_faces_counts_and_types() {
    let Some((iges, _, text)) = both() else {
        return;
    };
    assert_eq!(iges.faces.len(), 29, "OpenCASCADE's face count");
    assert!(iges.diagnostics.is_empty(), "{:?}", iges.diagnostics);
    assert!(iges.workpiece.surfaces.iter().all(|s| s.trim.is_some()));
    let mut counts = BTreeMap::new();
    for f in &iges.faces {
        *counts.entry(f.surface_type.clone()).or_insert(0) += 1;
    }
    assert_eq!(counts, text_surface_types(&text));
    assert_eq!(counts.get("IGES 192"), Some(&22));
}

#[test]
fn brep_matches_the_step_part() {
    let Some((iges, step, _)) = both() else {
        return;
    };
    let (wi, ws) = (workpiece(&iges), workpiece(&step));
    for (from, to, what) in [(&wi, &ws, "IGES on STEP"), (&ws, &wi, "STEP on IGES")] {
        let samples = face_samples(from, 12);
        assert!(samples.len() > 29 * 20, "{what}: {} samples", samples.len());
        let mut worst: f64 = 0.0;
        let mut outward_checked = 0;
        for (k, p) in &samples {
            let d = to.closest_point(*p).expect("projects").projection.distance;
            worst = worst.max(d);
            // Normal sense: a point 0.01 mm outside `from` along its normal
            // is 0.01 mm outside `to` unless another face is closer.
            let own = from
                .closest_point_among(*p, [*k])
                .expect("own face")
                .projection;
            let q = p + own.normal * 0.01;
            let other = to.closest_point(q).expect("projects").projection;
            if other.distance > 0.0099 {
                assert!(
                    other.signed_distance > 0.0,
                    "{what}: face {k} at {p:?} points inwards"
                );
                outward_checked += 1;
            }
        }
        println!(
            "{what}: {} samples, worst distance {worst:.2e} mm, {outward_checked} normal checks",
            samples.len()
        );
        assert!(worst < 1e-6, "{what}: worst distance {worst:e} mm");
        assert!(
            outward_checked > samples.len() / 2,
            "{what}: {outward_checked} normal checks"
        );
    }
}

#[test]
fn brep_normals_enclose_a_positive_volume() {
    let Some((iges, step, _)) = both() else {
        return;
    };
    let (vi, vs) = (
        volume(&workpiece(&iges), 200),
        volume(&workpiece(&step), 200),
    );
    println!("volume: IGES {vi:.3} mm^3, STEP {vs:.3} mm^3");
    assert!(vi > 0.0, "outward normals give a positive volume: {vi}");
    assert!(
        (vi - vs).abs() < 1e-3 * vs.abs(),
        "IGES {vi} vs STEP {vs} mm^3"
    );
}

#[test]
fn bearing_keeps_its_trimmed_faces() {
    let Some(p) = path("bearing.iges") else {
        return;
    };
    let imp = import(&p).expect("imports");
    assert_eq!(imp.faces.len(), 213, "OpenCASCADE's face count");
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics.first());
    assert!(imp.workpiece.surfaces.iter().all(|s| s.trim.is_some()));
    assert!(imp.faces.iter().all(|f| f.surface_type == "IGES 128"));
}
