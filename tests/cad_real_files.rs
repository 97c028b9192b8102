//! Imports of the real CAD parts in ../shared/cad, checked against
//! independent references: face counts by surface type from a plain text
//! scan of the file, and the exact geometry of converted elementary surfaces
//! (evaluated with a local de Boor evaluator written here, not the crate's).
use cmm::cad::{import, Import};
use cmm::workpiece::format::SurfaceSpec;
use std::collections::{BTreeMap, HashMap};

/// Relative tolerance of the exactness checks.
const REL_TOL: f64 = 1e-12;

fn path(name: &str) -> Option<String> {
    // CMM_CAD_DIR overrides the directory (a checkout whose parent has no shared/).
    let dir = std::env::var("CMM_CAD_DIR")
        .unwrap_or_else(|_| format!("{}/../shared/cad", env!("CARGO_MANIFEST_DIR")));
    let p = format!("{dir}/{name}");
    if std::path::Path::new(&p).exists() {
        return Some(p);
    }
    println!("note: {p} not found; skipping");
    None
}

/// `#id -> entity text without white space`, by splitting the DATA text at ';'.
fn instances(text: &str) -> HashMap<u64, String> {
    let data = text.split("DATA;").nth(1).unwrap_or("");
    data.split(';')
        .filter_map(|chunk| {
            let s: String = chunk.split_whitespace().collect();
            let rest = s.strip_prefix('#')?;
            let (id, body) = rest.split_once('=')?;
            Some((id.parse().ok()?, body.to_string()))
        })
        .collect()
}

/// Surface type per ADVANCED_FACE, from the text alone.
fn text_face_counts(text: &str) -> BTreeMap<String, usize> {
    let all = instances(text);
    let mut counts = BTreeMap::new();
    for body in all.values().filter(|b| b.starts_with("ADVANCED_FACE(")) {
        let head = &body[..body.rfind(",.").expect("same_sense")];
        let id: u64 = head[head.rfind('#').expect("surface ref") + 1..]
            .parse()
            .expect("id");
        let surf = &all[&id];
        let name = if surf.starts_with('(') {
            if surf.contains("RATIONAL_B_SPLINE_SURFACE") {
                "RATIONAL_B_SPLINE_SURFACE"
            } else {
                "B_SPLINE_SURFACE_WITH_KNOTS"
            }
        } else {
            &surf[..surf.find('(').expect("(")]
        };
        *counts.entry(name.to_string()).or_insert(0) += 1;
    }
    counts
}

fn imported_counts(imp: &Import) -> BTreeMap<String, usize> {
    let mut counts = BTreeMap::new();
    for f in &imp.faces {
        *counts.entry(f.surface_type.clone()).or_insert(0) += 1;
    }
    counts
}

fn check_step(name: &str, expected_total: usize) -> Option<(Import, String)> {
    let p = path(name)?;
    let text = std::fs::read_to_string(&p).expect("read");
    let imp = import(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(imp.faces.len(), expected_total, "{name}");
    assert_eq!(imported_counts(&imp), text_face_counts(&text), "{name}");
    assert!(
        imp.diagnostics
            .iter()
            .all(|d| d.kind == cmm::cad::DiagnosticKind::Untrimmed),
        "{name}: no face skipped"
    );
    Some((imp, text))
}

mod cad_common;
use cad_common::eval;

fn grid(s: &SurfaceSpec, n: usize) -> Vec<[f64; 3]> {
    let (p, q) = (s.degree[0], s.degree[1]);
    let (u0, u1) = (s.knots_u[p], s.knots_u[s.knots_u.len() - p - 1]);
    let (v0, v1) = (s.knots_v[q], s.knots_v[s.knots_v.len() - q - 1]);
    let mut out = Vec::new();
    for a in 0..=n {
        for b in 0..=n {
            let u = u0 + (u1 - u0) * a as f64 / n as f64;
            let v = v0 + (v1 - v0) * b as f64 / n as f64;
            out.push(eval(s, u, v));
        }
    }
    out
}

// ---- independent reading of the analytic definitions from the text ----

fn numbers(body: &str) -> Vec<f64> {
    body.split([',', '(', ')'])
        .filter_map(|t| {
            t.parse::<f64>()
                .ok()
                .or_else(|| t.strip_suffix('.').and_then(|x| x.parse().ok()))
        })
        .collect()
}

fn refs(body: &str) -> Vec<u64> {
    body.split('#')
        .skip(1)
        .filter_map(|t| t.split(|c: char| !c.is_ascii_digit()).next()?.parse().ok())
        .collect()
}

/// (origin, axis) of the AXIS2_PLACEMENT_3D `id`, scaled to mm.
fn placement(all: &HashMap<u64, String>, id: u64, scale: f64) -> ([f64; 3], [f64; 3]) {
    let r = refs(&all[&id]);
    let o = numbers(&all[&r[0]]);
    let z = numbers(&all[&r[1]]);
    let len = (z[0] * z[0] + z[1] * z[1] + z[2] * z[2]).sqrt();
    (
        [o[0] * scale, o[1] * scale, o[2] * scale],
        [z[0] / len, z[1] / len, z[2] / len],
    )
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Axial height and distance from the axis of `p`.
fn cyl_coords(p: [f64; 3], o: [f64; 3], z: [f64; 3]) -> (f64, f64) {
    let d = sub(p, o);
    let h = dot(d, z);
    let radial = [d[0] - h * z[0], d[1] - h * z[1], d[2] - h * z[2]];
    (h, norm(radial))
}

/// Signed distance-like error of `p` from the analytic surface given by its
/// text parameters `nums` and placement `(o, z)`.
fn surface_error(
    kind: &str,
    nums: &[f64],
    (o, z): ([f64; 3], [f64; 3]),
    (scale, angle_scale): (f64, f64),
    p: [f64; 3],
) -> f64 {
    let (h, rho) = cyl_coords(p, o, z);
    match kind {
        "PLANE" => h.abs(),
        "CYLINDRICAL_SURFACE" => rho - nums[0] * scale,
        "SPHERICAL_SURFACE" => norm(sub(p, o)) - nums[0] * scale,
        "CONICAL_SURFACE" => rho - (nums[0] * scale + h * (nums[1] * angle_scale).tan()).abs(),
        "TOROIDAL_SURFACE" => (rho - nums[0] * scale).hypot(h) - nums[1] * scale,
        _ => 0.0,
    }
}

/// Checks every converted elementary surface of a file against its text definition.
fn check_exact(imp: &Import, text: &str, scale: f64, angle_scale: f64) -> usize {
    let all = instances(text);
    let mut checked = 0;
    for (face, spec) in imp.faces.iter().zip(&imp.workpiece.surfaces) {
        let body = &all[&face.entity];
        let head = &body[..body.rfind(",.").expect("same_sense")];
        let surf_id: u64 = head[head.rfind('#').expect("ref") + 1..]
            .parse()
            .expect("id");
        let surf = &all[&surf_id];
        let nums = numbers(surf);
        let (o, z) = match refs(surf).first() {
            Some(&pl) if !surf.starts_with('(') && !surf.starts_with("B_SPLINE") => {
                placement(&all, pl, scale)
            }
            _ => continue,
        };
        let size = nums.iter().map(|x| x.abs()).fold(1.0, f64::max) * scale;
        for p in grid(spec, 12) {
            let err = surface_error(&face.surface_type, &nums, (o, z), (scale, angle_scale), p);
            assert!(
                err.abs() <= REL_TOL * size.max(norm(o)).max(1.0),
                "{}: {} off by {err:e}",
                face.name,
                face.surface_type
            );
        }
        checked += 1;
    }
    checked
}

/// Every trim point maps (through the local evaluator) into the surface's
/// domain, and every vertex of a trimmed elementary face is reproduced by
/// some trim point.
fn check_trims_hit_vertices(imp: &Import, text: &str, scale: f64, angle_scale: f64) {
    let all = instances(text);
    for (face, spec) in imp.faces.iter().zip(&imp.workpiece.surfaces) {
        let Some(trim) = &spec.trim else { continue };
        let pts: Vec<[f64; 3]> = trim
            .outer
            .iter()
            .chain(trim.holes.iter().flatten())
            .map(|uv| eval(spec, uv[0], uv[1]))
            .collect();
        let nearest = |v: [f64; 3]| {
            pts.iter()
                .map(|p| norm(sub(*p, v)))
                .fold(f64::INFINITY, f64::min)
        };
        if face.surface_type.contains("B_SPLINE") {
            // PCURVE trims (accepted when their ends meet the vertices within
            // the pcurve tolerance) and projected trims (vertices projected).
            let tol = cmm::cad::ImportOptions::default().pcurve_tolerance_mm;
            let vertices = face_vertices(&all, face.entity);
            assert!(!vertices.is_empty(), "{}: vertices found", face.name);
            for v in vertices {
                let v = [v[0] * scale, v[1] * scale, v[2] * scale];
                assert!(
                    nearest(v) <= tol,
                    "{}: vertex {v:?} is {:e} from the PCURVE trim",
                    face.name,
                    nearest(v)
                );
            }
            continue;
        }
        let body = &all[&face.entity];
        let head = &body[..body.rfind(",.").expect("same_sense")];
        let surf = &all[&head[head.rfind('#').expect("ref") + 1..]
            .parse::<u64>()
            .expect("id")];
        let (o, z) = placement(&all, refs(surf)[0], scale);
        let nums = numbers(surf);
        for v in face_vertices(&all, face.entity) {
            let v = [v[0] * scale, v[1] * scale, v[2] * scale];
            let best = nearest(v);
            // The file's vertex may sit off the surface by its modelling
            // tolerance; the trim point is on the surface, so allow that gap.
            let off =
                surface_error(&face.surface_type, &nums, (o, z), (scale, angle_scale), v).abs();
            assert!(
                best <= off + 1e-6 * (1.0 + norm(v)),
                "{}: vertex {v:?} is {best:e} from the trim (off surface {off:e})",
                face.name
            );
        }
    }
}

fn face_vertices(all: &HashMap<u64, String>, face: u64) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    let mut stack = refs(&all[&face]);
    let mut seen = std::collections::HashSet::new();
    while let Some(id) = stack.pop() {
        let body = &all[&id];
        if !seen.insert(id)
            || body.contains("SURFACE") && !body.starts_with("SURFACE_CURVE")
            || body.starts_with("SEAM_CURVE")
        {
            continue;
        }
        if body.starts_with("VERTEX_POINT(") {
            let n = numbers(&all[&refs(body)[0]]);
            out.push([n[0], n[1], n[2]]);
        } else if [
            "FACE_",
            "EDGE_LOOP",
            "ORIENTED_EDGE",
            "EDGE_CURVE",
            "VERTEX_LOOP",
        ]
        .iter()
        .any(|k| body.starts_with(k))
        {
            let r = refs(body);
            let keep = if body.starts_with("EDGE_CURVE") {
                &r[..2]
            } else {
                &r[..]
            };
            stack.extend_from_slice(keep);
        }
    }
    out
}

/// Even-odd point-in-polygon test.
fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut c = false;
    for (k, a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1])
        {
            c = !c;
        }
    }
    c
}

/// Trims are consistent polygons: outer counter-clockwise with positive
/// area, holes clockwise, smaller, and inside the outer loop.
fn check_trim_shapes(imp: &Import) {
    use cmm::cad::signed_area;
    for s in &imp.workpiece.surfaces {
        let Some(t) = &s.trim else { continue };
        let outer = signed_area(&t.outer);
        assert!(
            outer > 0.0 && t.outer.len() >= 3,
            "{}: outer area {outer}",
            s.name
        );
        for h in &t.holes {
            let a = signed_area(h);
            assert!(
                a < 0.0 && -a < outer,
                "{}: hole area {a} vs outer {outer}",
                s.name
            );
            let mid = [
                h.iter().map(|p| p[0]).sum::<f64>() / h.len() as f64,
                h.iter().map(|p| p[1]).sum::<f64>() / h.len() as f64,
            ];
            assert!(
                inside(h[0], &t.outer) || inside(mid, &t.outer),
                "{}: hole outside the outer loop",
                s.name
            );
        }
    }
}

#[test]
fn trims_are_consistent_polygons() {
    for name in [
        "abc-0000.step",
        "io1-cm-214.stp",
        "linkrods.step",
        "nist_ctc_05_asme1_rd.stp",
        "bearing.iges",
    ] {
        let Some(p) = path(name) else { return };
        check_trim_shapes(&import(&p).expect("imports"));
    }
}

#[test]
fn nist_ctc_05_inch_part() {
    let Some((imp, text)) = check_step("nist_ctc_05_asme1_rd.stp", 209) else {
        return;
    };
    let checked = check_exact(&imp, &text, 25.4, std::f64::consts::PI / 180.0);
    assert_eq!(checked, 200, "all elementary faces checked");
    check_trims_hit_vertices(&imp, &text, 25.4, std::f64::consts::PI / 180.0);
    let trimmed = |spline: bool| {
        imp.faces
            .iter()
            .zip(&imp.workpiece.surfaces)
            .filter(|(f, s)| f.surface_type.contains("B_SPLINE") == spline && s.trim.is_some())
            .count()
    };
    assert_eq!(trimmed(false), 200, "elementary faces are all trimmed");
    // 9 B-spline faces have no PCURVEs: all get projected trims, three of
    // them because their edges, 1.1 um off the surface, are within the
    // file's declared uncertainty (3.67e-3 inch = 0.093 mm).
    assert_eq!(trimmed(true), 9, "projected trims");
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics);
    let strict = cmm::cad::ImportOptions {
        use_file_uncertainty: false,
        ..Default::default()
    };
    let p = path("nist_ctc_05_asme1_rd.stp").expect("found above");
    let fixed = cmm::cad::import_with(&p, &strict).expect("imports");
    assert_eq!(fixed.diagnostics.len(), 3, "with the fixed 1 um tolerance");
    for d in &fixed.diagnostics {
        assert!(
            d.message.contains("miss the surface by up to 1.1"),
            "{}",
            d.message
        );
    }
}

#[test]
fn abc_0000_metre_part() {
    let Some((imp, text)) = check_step("abc-0000.step", 25) else {
        return;
    };
    assert_eq!(check_exact(&imp, &text, 1000.0, 1.0), 23);
    check_trims_hit_vertices(&imp, &text, 1000.0, 1.0);
}

#[test]
fn io1_cm_214_mm_part() {
    let Some((imp, text)) = check_step("io1-cm-214.stp", 29) else {
        return;
    };
    assert_eq!(check_exact(&imp, &text, 1.0, 1.0), 29);
    check_trims_hit_vertices(&imp, &text, 1.0, 1.0);
    assert!(imp.diagnostics.is_empty());
}

#[test]
fn linkrods_with_pcurves() {
    let Some((imp, text)) = check_step("linkrods.step", 37) else {
        return;
    };
    assert_eq!(check_exact(&imp, &text, 1.0, 1.0), 19);
    check_trims_hit_vertices(&imp, &text, 1.0, 1.0);
    let spline_trims = imp
        .faces
        .iter()
        .zip(&imp.workpiece.surfaces)
        .filter(|(f, s)| f.surface_type.contains("B_SPLINE") && s.trim.is_some())
        .count();
    assert_eq!(
        spline_trims, 18,
        "PCURVE or projected trims on all B-spline faces"
    );
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics);
}

#[test]
fn bearing_iges() {
    let Some(p) = path("bearing.iges") else {
        return;
    };
    let imp = import(&p).expect("imports");
    assert_eq!(imp.faces.len(), 213);
    assert!(imp.diagnostics.is_empty(), "{:?}", imp.diagnostics.first());
    let text = std::fs::read_to_string(&p).expect("read");
    let d_144 = text
        .lines()
        .filter(|l| l.len() >= 80 && &l[72..73] == "D" && l[..8].trim() == "144")
        .count();
    assert_eq!(d_144, 2 * 213, "independent count of 144 directory records");
    for s in &imp.workpiece.surfaces {
        let trim = s.trim.as_ref().expect("trimmed");
        let (p, q) = (s.degree[0], s.degree[1]);
        let (u0, u1) = (s.knots_u[p], s.knots_u[s.knots_u.len() - p - 1]);
        let (v0, v1) = (s.knots_v[q], s.knots_v[s.knots_v.len() - q - 1]);
        for uv in &trim.outer {
            assert!(
                uv[0] >= u0 - 1e-9
                    && uv[0] <= u1 + 1e-9
                    && uv[1] >= v0 - 1e-9
                    && uv[1] <= v1 + 1e-9,
                "{}: {uv:?}",
                s.name
            );
        }
    }
}

#[test]
fn workpieces_serialise_and_names_are_unique() {
    for name in [
        "abc-0000.step",
        "io1-cm-214.stp",
        "nist_ctc_05_asme1_rd.stp",
    ] {
        let Some(p) = path(name) else { return };
        let imp = import(&p).expect("imports");
        let json = serde_json::to_string(&imp.workpiece).expect("json");
        let back: cmm::workpiece::format::WorkpieceFile =
            serde_json::from_str(&json).expect("reads back");
        assert_eq!(back.surfaces.len(), imp.faces.len());
        let names: std::collections::HashSet<&str> =
            imp.faces.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names.len(), imp.faces.len());
    }
}
