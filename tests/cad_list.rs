//! `cmm import --list` names every face with where it lies: on the io1
//! flange (the shipped STEP file), each face's listed point lies on that
//! face by `cmm evaluate` (the global closest point over all faces, an
//! independent path through the projection code) with the same outward
//! normal, and each half cylinder's listed area is `pi r L`, its radius
//! and length read off its listed box.
use serde_json::Value;
use std::path::Path;
use std::process::{Command, Output};

fn cmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

/// A face line: name, type, box corners, area, point and normal.
struct Listed {
    name: String,
    kind: String,
    lo: [f64; 3],
    hi: [f64; 3],
    area: f64,
    at: [f64; 3],
    normal: [f64; 3],
}

/// The numbers of `text` in order (the listing's parenthesised triples
/// and the area).
fn numbers(text: &str) -> Vec<f64> {
    text.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter_map(|t| t.parse().ok())
        .collect()
}

fn parse(line: &str) -> Listed {
    let (head, rest) = line.split_once(": box ").unwrap();
    let words: Vec<&str> = head.split(' ').collect();
    let n = numbers(&rest.replace("mm2", ""));
    assert_eq!(n.len(), 13, "{line}");
    Listed {
        name: words[0].to_string(),
        kind: words[2].to_string(),
        lo: [n[0], n[1], n[2]],
        hi: [n[3], n[4], n[5]],
        area: n[6],
        at: [n[7], n[8], n[9]],
        normal: [n[10], n[11], n[12]],
    }
}

#[test]
fn listed_faces_lie_where_the_listing_says() {
    let part = Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/io1-flange.stp");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w.json");
    let o = cmm(&[
        "import",
        part.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--list",
    ]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let text = String::from_utf8(o.stdout).unwrap();
    let faces: Vec<Listed> = text
        .lines()
        .filter(|l| l.starts_with("face"))
        .map(parse)
        .collect();
    assert_eq!(faces.len(), 29, "{text}");
    // Every listed point lies on its face, facing the listed way.
    let csv = dir.path().join("at.csv");
    let rows: Vec<String> = faces
        .iter()
        .map(|f| format!("{},{},{}", f.at[0], f.at[1], f.at[2]))
        .collect();
    std::fs::write(&csv, format!("x,y,z\n{}\n", rows.join("\n"))).unwrap();
    let e = cmm(&[
        "evaluate",
        "--workpiece",
        out.to_str().unwrap(),
        "--points",
        csv.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(e.status.code(), Some(0), "{e:?}");
    let report: Value = serde_json::from_slice(&e.stdout).unwrap();
    for (f, p) in faces.iter().zip(report["points"].as_array().unwrap()) {
        // The listing rounds to 1 um.
        assert!(
            p["deviation_mm"].as_f64().unwrap().abs() < 2e-3,
            "{}: {p}",
            f.name
        );
        let n: Vec<f64> = (0..3).map(|k| p["normal"][k].as_f64().unwrap()).collect();
        let dot: f64 = (0..3).map(|k| n[k] * f.normal[k]).sum();
        assert!(
            dot > 0.999,
            "{}: listed normal {:?}, evaluated {n:?}",
            f.name,
            f.normal
        );
    }
    // The flange's cylinders are halves about the x axis: radius half the
    // box's extent in y, length its extent in x.
    let mut halves = 0;
    for f in faces.iter().filter(|f| f.kind == "CYLINDRICAL_SURFACE") {
        let (r, len) = ((f.hi[1] - f.lo[1]) / 2.0, f.hi[0] - f.lo[0]);
        let half = (f.hi[2] - f.lo[2] - r).abs() < 1e-3;
        if half && len > 0.5 {
            halves += 1;
            let want = std::f64::consts::PI * r * len;
            assert!(
                (f.area - want).abs() < 2e-3 * want,
                "{}: {} against {want}",
                f.name,
                f.area
            );
        }
    }
    assert!(halves >= 10, "{halves} half cylinders");
}
