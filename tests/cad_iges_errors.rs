//! Malformed IGES gives typed errors with file, line and column: 124
//! cycles, 308/408 cycles, dangling DE pointers in the directory and in
//! parameter fields, bad section letters, truncation, missing units; and a
//! face that cannot be converted is listed with its DE number, type and line.
mod cad_iges_support;
use cad_iges_support::{run, Iges};
use cmm::cad::{CadError, DiagnosticKind};

fn sphere(g: &mut Iges) -> usize {
    let c = g.add(116, 0, "0.,0.,0.,0");
    g.dependent(c);
    g.add(196, 0, &format!("{c},1."))
}

/// Physical line of the first D record of entity `de` (S: 1 line, G: 2 lines).
fn d_line(de: usize) -> usize {
    3 + de
}

#[test]
fn cyclic_124_chain() {
    let mut g = Iges::default();
    let a = g.add(124, 0, "1.,0.,0.,0.,0.,1.,0.,0.,0.,0.,1.,0.");
    let b = g.add_t(124, 0, "1.,0.,0.,1.,0.,1.,0.,0.,0.,0.,1.,0.", a);
    g.set_transform(a, b);
    let s = sphere(&mut g);
    g.set_transform(s, a);
    match run(&g.text()).expect_err("cycle") {
        CadError::CyclicReference {
            file, line, reason, ..
        } => {
            assert_eq!(file, "t.iges");
            assert!(line == d_line(a) || line == d_line(b), "{line}");
            assert!(
                reason.contains(&format!("#{a}")) && reason.contains(&format!("#{b}")),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn self_referencing_124() {
    let mut g = Iges::default();
    let a = g.add(124, 0, "1.,0.,0.,0.,0.,1.,0.,0.,0.,0.,1.,0.");
    g.set_transform(a, a);
    sphere(&mut g);
    assert!(matches!(
        run(&g.text()),
        Err(CadError::CyclicReference { line, .. }) if line == d_line(a)
    ));
}

#[test]
fn cyclic_subfigures() {
    let mut g = Iges::default();
    let s = sphere(&mut g);
    g.dependent(s);
    // 308 #def holds the sphere and instance #inst, which instances #def again.
    let def = 2 * 3 + 1;
    let inst = g.add(408, 0, &format!("{def},0.,0.,0.,1."));
    g.dependent(inst);
    assert_eq!(g.add(308, 0, &format!("0,1Ha,2,{s},{inst}")), def);
    g.add(408, 0, &format!("{def},1.,0.,0.,1."));
    match run(&g.text()).expect_err("cycle") {
        CadError::CyclicReference { reason, line, .. } => {
            assert!(reason.contains(&format!("#{def}")), "{reason}");
            assert_eq!(line, d_line(def));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn dangling_transform_pointer_in_the_directory() {
    let mut g = Iges::default();
    let s = sphere(&mut g);
    g.set_transform(s, 99);
    match run(&g.text()).expect_err("dangling") {
        CadError::UnknownReference {
            line,
            column,
            entity,
            target,
            ..
        } => {
            assert_eq!(
                (line, column, entity, target),
                (d_line(s), 49, s as u64, 99)
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn dangling_pointer_in_a_parameter_field() {
    let mut g = Iges::default();
    let s = g.add(196, 0, "41,1.");
    match run(&g.text()).expect_err("dangling") {
        CadError::UnknownReference {
            line,
            column,
            entity,
            target,
            ..
        } => {
            // P section starts after S (1), G (2) and D (2) lines: line 6;
            // "196," is 4 characters, so the pointer is in column 5.
            assert_eq!((line, column, entity, target), (6, 5, s as u64, 41));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_section_letter_and_truncation() {
    let mut g = Iges::default();
    sphere(&mut g);
    let text = g.text();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[3].replace_range(72..73, "X");
    match run(&lines.join("\n")).expect_err("letter") {
        CadError::Syntax {
            line,
            column,
            reason,
            ..
        } => {
            assert_eq!((line, column), (4, 73));
            assert!(reason.contains("section letter"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let cut: Vec<&str> = text.lines().take(6).collect();
    assert!(matches!(
        run(&cut.join("\n")),
        Err(CadError::Syntax { line: 6, .. })
    ));
    // Parameter records cut off: the directory points past the P section.
    let cut: Vec<&str> = text.lines().take(8).collect();
    let e = run(&cut.join("\n")).expect_err("truncated P");
    assert!(matches!(e, CadError::NoFaces { .. }), "{e:?}");
}

#[test]
fn missing_units() {
    let mut g = Iges::default();
    g.units = "3,0H".into();
    sphere(&mut g);
    assert!(matches!(
        run(&g.text()),
        Err(CadError::MissingUnits { line: 2, .. })
    ));
}

#[test]
fn unconvertible_face_is_listed_with_its_entity() {
    let mut g = Iges::default();
    sphere(&mut g);
    let loc = g.add(116, 0, "0.,0.,0.,0");
    let axis = g.add(123, 0, "0.,0.,1.");
    // A free cylinder has no boundary: skipped with a diagnostic.
    let cyl = g.add(192, 0, &format!("{loc},{axis},2."));
    let imp = run(&g.text()).expect("the sphere imports");
    assert_eq!(imp.faces.len(), 1);
    let d = imp.diagnostics.first().expect("diagnostic");
    assert_eq!((d.entity, d.kind), (cyl as u64, DiagnosticKind::Skipped));
    assert_eq!((d.entity_type.as_str(), d.line), ("IGES 192", d_line(cyl)));
    assert!(d.message.contains("unbounded"), "{}", d.message);
}
