//! Workpiece files: shipped examples regenerate byte for byte; every kind of
//! invalid file is rejected with the file, the JSON path and the reason.
mod common;

use std::path::Path;

use cmm::workpiece::{Workpiece, WorkpieceError};
use common::*;

#[test]
fn shipped_examples_are_what_the_generator_writes() {
    for (stem, wp) in cmm::workpiece::examples::all() {
        let shipped = std::fs::read_to_string(repo(&format!("workpieces/{stem}.json"))).unwrap();
        assert_eq!(
            shipped,
            cmm::workpiece::examples::to_json(&wp),
            "workpieces/{stem}.json is stale: run `cmm example-workpieces`"
        );
        let loaded = example(stem);
        assert_eq!(loaded.faces.len(), wp.surfaces.len());
    }
    let shipped = std::fs::read_to_string(repo("workpieces/blade-points.csv")).unwrap();
    assert_eq!(shipped, cmm::workpiece::examples::blade_points_csv());
    assert_eq!(shipped.lines().count(), 37);
}

const GOOD: &str = r#"{"format":"cmm-workpiece/1","name":"t","units":"mm","surfaces":[
 {"name":"a","degree":[1,1],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],
  "control_points":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,0]]],
  "weights":[[1,1],[1,1]]}]}"#;

fn load(text: &str) -> Result<Workpiece, WorkpieceError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wp.json");
    std::fs::write(&path, text).unwrap();
    Workpiece::from_path(&path)
}

fn error_for(edit: impl Fn(&mut serde_json::Value)) -> String {
    let mut v: serde_json::Value = serde_json::from_str(GOOD).unwrap();
    edit(&mut v);
    load(&v.to_string()).map(|_| ()).unwrap_err().to_string()
}

#[test]
fn the_good_file_loads() {
    let wp = load(GOOD).unwrap();
    assert_eq!(wp.faces[0].name, "a");
}

#[test]
fn invalid_files_name_file_path_and_reason() {
    use serde_json::json;
    let s = "/surfaces/0";
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|v| v["format"] = json!("cmm-workpiece/2")),
            "$.format",
        ),
        (Box::new(|v| v["units"] = json!("inch")), "$.units"),
        (Box::new(|v| v["surfaces"] = json!([])), "$.surfaces"),
        (Box::new(|v| v["extra"] = json!(1)), "extra"),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["colour"] = json!("red")),
            "colour",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["knots_u"] = json!([0, 0, 1, 0.5])),
            "$.surfaces[0].knots_u[3]",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["knots_u"] = json!([0, 1, 1])),
            "$.surfaces[0].knots_u",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["degree"] = json!([3, 1])),
            "$.surfaces[0].knots_u",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["degree"] = json!([0, 1])),
            "$.surfaces[0].degree[0]",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["weights"] = json!([[1, 1], [1, -2]])),
            "$.surfaces[0].weights[1][1]",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["weights"] = json!([[1, 1], [1]])),
            "$.surfaces[0].weights[1]",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["weights"] = json!([[1, 1], [1, null]])),
            "$.surfaces[0].weights[1][1]",
        ),
        (
            Box::new(move |v| {
                v.pointer_mut(s).unwrap()["control_points"] = json!([[[0, 0, 0], [0, 1, 0]]])
            }),
            "$.surfaces[0].control_points",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["control_points"][1][0] = json!([1, 0])),
            "$.surfaces[0].control_points[1][0]",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["control_points"][1][0] = json!(null)),
            "$.surfaces[0].control_points[1][0]",
        ),
        (
            Box::new(move |v| v.pointer_mut(s).unwrap()["control_points"][1][0][2] = json!("x")),
            "$.surfaces[0].control_points[1][0][2]",
        ),
        (
            Box::new(|v| {
                let a = v["surfaces"][0].clone();
                v["surfaces"].as_array_mut().unwrap().push(a);
            }),
            "$.surfaces[1].name",
        ),
        (
            Box::new(move |v| {
                v.pointer_mut(s).unwrap()["trim"] = json!({"outer": [[0, 0], [2, 0], [1, 1]]})
            }),
            "$.surfaces[0].trim.outer[1]",
        ),
        (
            Box::new(|v| {
                v.as_object_mut().unwrap().remove("surfaces");
            }),
            "surfaces",
        ),
    ];
    for (k, (edit, path)) in cases.iter().enumerate() {
        let msg = error_for(edit);
        assert!(msg.contains("wp.json"), "case {k}: no file in '{msg}'");
        assert!(msg.contains(path), "case {k}: expected '{path}' in '{msg}'");
    }
}

#[test]
fn syntax_errors_carry_line_and_column() {
    let msg = load("{\n \"format\": \"cmm-workpiece/1\",\n \"name\": NaN\n}")
        .unwrap_err()
        .to_string();
    assert!(msg.contains("wp.json:3:"), "{msg}");
    let missing = Workpiece::from_path(Path::new("/nonexistent/wp.json"))
        .unwrap_err()
        .to_string();
    assert!(missing.contains("/nonexistent/wp.json"), "{missing}");
}
