//! IGES reader on a small hand-made file: custom delimiters, Hollerith
//! strings, D exponents, 124 transforms, inch units, and error places.
use cmm::cad::{iges::import_iges, CadError, DiagnosticKind, ImportOptions};

fn section(letter: char, lines: &[String]) -> Vec<String> {
    lines
        .iter()
        .enumerate()
        .map(|(k, l)| format!("{l:<72}{letter}{:>7}", k + 1))
        .collect()
}

/// Parameter records of one entity (`data` split into 64-column pieces).
fn p_lines(data: &str, de: usize, first_seq: usize) -> Vec<String> {
    let chunks: Vec<String> = data
        .as_bytes()
        .chunks(60)
        .map(|c| String::from_utf8_lossy(c).into_owned())
        .collect();
    chunks
        .iter()
        .enumerate()
        .map(|(k, c)| format!("{c:<64} {de:>7}P{:>7}", first_seq + k))
        .collect()
}

fn d_pair(kind: i32, pstart: usize, pcount: usize, transform: usize) -> [String; 2] {
    [
        format!(
            "{kind:>8}{pstart:>8}{:>8}{:>8}{:>8}{:>8}{transform:>8}{:>8}{:>8}",
            0, 0, 0, 0, 0, "00000000"
        ),
        format!(
            "{kind:>8}{:>8}{:>8}{pcount:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            0, 0, 0, "", "", "", 0
        ),
    ]
}

/// A unit square patch (translated by 10 in x by a 124) trimmed by a square in (u, v).
fn sample(global_units: &str, line_param: &str) -> String {
    let params = [
        (124, "124;1.;0.;0.;10.;0.;1.;0.;0.;0.;0.;1.;0./", 0),
        (128, "128;1;1;1;1;0;0;1;0;0;0.;0.;1.;1.;0.;0.;1.;1.;1.;1.;1.;1.;0.;0.;0.;1.;0.;0.;0.;1.;0.;1.;1.;0.;0.;1.;0.;1./", 1),
        (110, line_param, 0),
        (110, "110;1.;0.;0.;1.;1.;0./", 0),
        (110, "110;1.;1.;0.;0.;1.;0./", 0),
        (110, "110;0.;1.;0.;0.;0.;0./", 0),
        (102, "102;4;5;7;9;11/", 0),
        (142, "142;0;3;13;0;1/", 0),
        (144, "144;3;1;0;15/", 0),
    ];
    let (mut d, mut p) = (Vec::new(), Vec::new());
    for (k, (kind, data, tr)) in params.iter().enumerate() {
        let de = 2 * k + 1;
        let lines = p_lines(data, de, p.len() + 1);
        d.extend(d_pair(*kind, p.len() + 1, lines.len(), *tr));
        p.extend(lines);
    }
    let s = section('S', &["hand-made test part".to_string()]);
    let g = section(
        'G',
        &[format!(
            "1H;;1H/;4Htest;6Ht.iges;1Hs;1Hp;32;38;6;308;15;4Htest;1.0D0;{global_units}/"
        )],
    );
    let d = section('D', &d);
    let t = format!(
        "{:<72}T{:>7}",
        format!("S{:>7}G{:>7}D{:>7}P{:>7}", 1, 1, d.len(), p.len()),
        1
    );
    [s, g, d, p, vec![t]].concat().join("\n") + "\n"
}

fn run(text: &str) -> Result<cmm::cad::Import, CadError> {
    import_iges(text, "t.iges", "t", &ImportOptions::default())
}

#[test]
fn square_patch_in_inches_with_transform() {
    let imp = run(&sample("1;2HIN", "110;0.;0.;0.;0.1D1;0.;0./")).expect("imports");
    assert_eq!(imp.faces.len(), 1);
    let s = &imp.workpiece.surfaces[0];
    assert_eq!(s.name, "face1");
    assert_eq!(s.control_points[0][0], [254.0, 0.0, 0.0]);
    assert_eq!(
        s.control_points[1][0],
        [279.4, 0.0, 0.0],
        "i runs along u (first IGES index)"
    );
    assert_eq!(s.control_points[0][1], [254.0, 25.4, 0.0]);
    let trim = s.trim.as_ref().expect("trim");
    assert_eq!(
        trim.outer,
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    );
}

#[test]
fn unit_name_is_used_when_flag_is_3() {
    let imp = run(&sample("3;2HMM", "110;0.;0.;0.;1.;0.;0./")).expect("imports");
    assert_eq!(
        imp.workpiece.surfaces[0].control_points[0][0],
        [10.0, 0.0, 0.0]
    );
}

#[test]
fn unknown_units_are_an_error() {
    match run(&sample("3;4HFURL", "110;0.;0.;0.;1.;0.;0./")).expect_err("units") {
        CadError::MissingUnits { line, .. } => assert_eq!(line, 2),
        other => panic!("{other:?}"),
    }
}

#[test]
fn malformed_number_is_reported_with_its_place() {
    let imp = run(&sample("2;2HMM", "110;0.;0.;0.;1.2.3;0.;0./")).expect("other faces still fine");
    assert!(imp.faces.is_empty() || imp.workpiece.surfaces[0].trim.is_none());
    let d = imp.diagnostics.first().expect("diagnostic");
    assert_eq!(d.kind, DiagnosticKind::Untrimmed);
    // Lines: S 1, G 2, D 3..=20, P of DE 1 on 21, DE 3 on 22-23, DE 5 on 24;
    // "110;0.;0.;0.;" is 13 characters, so "1.2.3" starts in column 14.
    assert!(
        d.message
            .contains("t.iges:24:14: syntax error: malformed number"),
        "{}",
        d.message
    );
}

#[test]
fn short_record_and_bad_directory_field() {
    let text = sample("2;2HMM", "110;0.;0.;0.;1.;0.;0./");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[4].truncate(40);
    match run(&lines.join("\n")).expect_err("short") {
        CadError::Syntax { line, column, .. } => assert_eq!((line, column), (5, 41)),
        other => panic!("{other:?}"),
    }
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    lines[2].replace_range(8..16, "     x12");
    match run(&lines.join("\n")).expect_err("bad field") {
        CadError::Syntax { line, column, .. } => assert_eq!((line, column), (3, 9)),
        other => panic!("{other:?}"),
    }
}

#[test]
fn truncated_directory_is_an_error() {
    let text = sample("2;2HMM", "110;0.;0.;0.;1.;0.;0./");
    let lines: Vec<&str> = text.lines().take(5).collect();
    assert!(matches!(
        run(&lines.join("\n")),
        Err(CadError::Syntax { line: 5, .. })
    ));
}
