//! Distances from points near the real STEP parts to the imported
//! workpieces agree with OpenCASCADE's (reference data in tests/cad_step_occ,
//! see its README): within 1e-6 mm where OpenCASCADE's foot lies inside a
//! face, 1e-3 mm where it lies on an edge or vertex (trims are polylines
//! sampled to the 1 um chord tolerance).
use cmm::cad::import;
use cmm::math::Point3;
use cmm::workpiece::Workpiece;

fn part(name: &str) -> Option<String> {
    let dir = std::env::var("CMM_CAD_DIR")
        .unwrap_or_else(|_| format!("{}/../shared/cad", env!("CARGO_MANIFEST_DIR")));
    let p = format!("{dir}/{name}");
    if std::path::Path::new(&p).exists() {
        return Some(p);
    }
    println!("note: {p} not found; skipping");
    None
}

struct Reference {
    p: Point3,
    distance: f64,
    on_face: bool,
}

fn references(csv: &str) -> Vec<Reference> {
    let path = format!("{}/tests/cad_step_occ/{csv}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).expect("reference file");
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let n = |k: usize| f[k].parse::<f64>().expect("number");
            Reference {
                p: Point3::new(n(0), n(1), n(2)),
                distance: n(3),
                on_face: f[4] == "face",
            }
        })
        .collect()
}

/// (points checked, worst error inside faces, worst on edges, failures).
fn compare(step: &str, csv: &str) -> Option<(usize, f64, f64, Vec<String>)> {
    let path = part(step)?;
    let imp = import(&path).expect("imports");
    let wp = Workpiece::from_file(&imp.workpiece, std::path::Path::new(&path)).expect("valid");
    let refs = references(csv);
    let (mut face_worst, mut edge_worst, mut bad) = (0.0f64, 0.0f64, Vec::new());
    for r in &refs {
        let got = cmm::evaluate::evaluate_point(&wp, r.p).expect("evaluates");
        let err = (got.deviation_mm.abs() - r.distance).abs();
        let tol = if r.on_face { 1e-6 } else { 1e-3 };
        if r.on_face {
            face_worst = face_worst.max(err);
        } else {
            edge_worst = edge_worst.max(err);
        }
        if err > tol {
            bad.push(format!(
                "{:?}: OCC {:.6} cmm {:.6} on {} ({})",
                r.p, r.distance, got.deviation_mm, got.surface, err
            ));
        }
    }
    Some((refs.len(), face_worst, edge_worst, bad))
}

fn check(step: &str, csv: &str) {
    let Some((n, fw, ew, bad)) = compare(step, csv) else {
        return;
    };
    println!("{step}: {n} points, worst {fw:e} mm inside faces, {ew:e} mm on edges");
    assert!(
        bad.is_empty(),
        "{step}: {} of {n} off:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

#[test]
fn abc_0000_agrees_with_opencascade() {
    check("abc-0000.step", "abc-0000.csv");
}

#[test]
fn io1_cm_214_agrees_with_opencascade() {
    check("io1-cm-214.stp", "io1-cm-214.csv");
}

#[test]
fn nist_ctc_05_agrees_with_opencascade() {
    check("nist_ctc_05_asme1_rd.stp", "nist_ctc_05_asme1_rd.csv");
}

#[test]
fn linkrods_agrees_with_opencascade() {
    check("linkrods.step", "linkrods.csv");
}
