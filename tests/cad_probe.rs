#[test]
fn probe() {
    for f in [
        "abc-0000.step",
        "io1-cm-214.stp",
        "linkrods.step",
        "nist_ctc_05_asme1_rd.stp",
        "bearing.iges",
    ] {
        let path = format!("{}/../shared/cad/{f}", env!("CARGO_MANIFEST_DIR"));
        let t = std::time::Instant::now();
        match cmm::cad::import(&path) {
            Ok(imp) => {
                let mut counts = std::collections::BTreeMap::new();
                for fr in &imp.faces {
                    *counts.entry(fr.surface_type.clone()).or_insert(0) += 1;
                }
                println!(
                    "{f}: {} faces {:?} in {:?}",
                    imp.faces.len(),
                    counts,
                    t.elapsed()
                );
                for d in imp.diagnostics.iter().take(8) {
                    println!("   #{} {:?} {}", d.entity, d.kind, d.message);
                }
                println!("   diagnostics: {}", imp.diagnostics.len());
            }
            Err(e) => println!("{f}: ERROR {e}"),
        }
    }
}
#[test]
fn probe_face() {
    let path = format!(
        "{}/../shared/cad/nist_ctc_05_asme1_rd.stp",
        env!("CARGO_MANIFEST_DIR")
    );
    let imp = cmm::cad::import(&path).unwrap();
    for (f, s) in imp.faces.iter().zip(&imp.workpiece.surfaces) {
        if f.name == "face190" || f.name == "face189" {
            println!("{:?} knots_u {:?} knots_v {:?}", f, s.knots_u, s.knots_v);
            println!("cps {:?}", s.control_points);
        }
    }
}
