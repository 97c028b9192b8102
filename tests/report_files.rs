//! report.json, points.csv, junit.xml and write_reports on a hand-built report.
mod report_common;

use cmm::report::*;
use report_common::*;
use serde_json::Value;

fn json() -> Value {
    serde_json::from_str(&to_json(&report())).unwrap()
}

fn get<'a>(value: &'a Value, key: &str) -> &'a Value {
    value
        .get(key)
        .unwrap_or_else(|| panic!("missing key {key} in {value}"))
}

fn number(value: &Value, key: &str) {
    assert!(
        get(value, key).is_f64() || get(value, key).is_u64(),
        "{key}"
    );
}

fn triple(value: &Value, key: &str) {
    let items = get(value, key).as_array().unwrap();
    assert_eq!(items.len(), 3, "{key}");
    assert!(items.iter().all(Value::is_number), "{key}");
}

#[test]
fn json_has_the_required_keys_of_design_6_3() {
    let root = json();
    assert_eq!(get(&root, "format"), "cmm-report/1");
    assert_eq!(get(&root, "program"), "blade-7 <demo>");
    assert_eq!(get(&root, "seed"), 42);
    assert_eq!(get(&root, "status"), "incomplete");
    number(&root, "machine_time_s");
    number(&root, "wall_time_s");
    let placement = get(&root, "part_to_machine");
    let rotation = get(placement, "rotation").as_array().unwrap();
    assert_eq!(rotation.len(), 3);
    for row in rotation {
        assert_eq!(row.as_array().unwrap().len(), 3);
    }
    triple(placement, "translation_mm");
    let features = get(&root, "features").as_array().unwrap();
    let statuses: Vec<&str> = features
        .iter()
        .map(|f| get(f, "status").as_str().unwrap())
        .collect();
    assert_eq!(statuses, ["pass", "fail", "incomplete"]);
    for feature in features {
        check_feature(feature);
    }
}

fn check_feature(feature: &Value) {
    assert!(get(feature, "name").is_string());
    for attempt in get(feature, "attempts").as_array().unwrap() {
        let mode = get(attempt, "mode").as_str().unwrap();
        assert!(["active", "passive", "autonomous", "points"].contains(&mode));
        assert!(get(attempt, "outcome").is_string());
        number(attempt, "machine_time_s");
    }
    for correction in get(feature, "corrections").as_array().unwrap() {
        let kind = get(correction, "kind").as_str().unwrap();
        if kind == "geometric" {
            assert!(get(correction, "model").is_string());
            number(correction, "max_residual_mm");
        } else {
            assert_eq!(kind, "autonomous");
        }
    }
    let stats = get(feature, "deviation_mm");
    for key in ["min", "max", "mean", "rms"] {
        number(stats, key);
    }
    let tol = get(feature, "tolerance_mm");
    for key in ["lower", "upper"] {
        number(tol, key);
    }
    for point in get(feature, "points").as_array().unwrap() {
        for key in ["measured", "nominal", "normal"] {
            triple(point, key);
        }
        number(point, "deviation_mm");
        number(point, "true_deviation_mm");
    }
}

#[test]
fn json_is_pretty_deterministic_and_ends_with_a_newline() {
    let text = to_json(&report());
    assert_eq!(text, to_json(&report()));
    assert!(text.starts_with("{\n  \"format\": \"cmm-report/1\",\n"));
    assert!(text.ends_with("}\n"));
    let outcome = &json()["features"][2]["attempts"][0]["outcome"];
    assert_eq!(outcome, "lost_contact");
}

/// Splits one CSV line (RFC 4180 quoting, no embedded newlines).
fn csv_fields(line: &str) -> Vec<String> {
    let (mut fields, mut field, mut quoted) = (vec![], String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut field)),
            _ => field.push(c),
        }
    }
    fields.push(field);
    fields
}

/// The number tokens inside every `"points"` array of the JSON text,
/// in order, exactly as written (serde_json's default parser may be one ulp
/// off, so the text is compared rather than parsed values).
fn point_number_tokens(json: &str) -> Vec<String> {
    let mut tokens = vec![];
    let mut points_indent = None;
    for line in json.lines() {
        let indent = line.len() - line.trim_start().len();
        let item = line.trim().trim_end_matches(',');
        match points_indent {
            None if item == "\"points\": [" => points_indent = Some(indent),
            Some(i) if indent == i && item.starts_with(']') => points_indent = None,
            Some(_) => {
                // `"key": 1.5` or `"key": [1.5, -2.0, 3.0]` (arrays of
                // numbers stand on one line).
                let value = item.split_once(": ").map_or(item, |(_, v)| v);
                let inner = value.trim_start_matches('[').trim_end_matches(']');
                for token in inner.split(", ") {
                    if token.parse::<f64>().is_ok() {
                        tokens.push(token.to_string());
                    }
                }
            }
            None => {}
        }
    }
    tokens
}

#[test]
fn csv_holds_exactly_the_points_of_the_json_with_identical_numbers() {
    let report = report();
    let csv = points_csv(&report);
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), POINTS_CSV_HEADER);
    assert_eq!(
        POINTS_CSV_HEADER,
        "feature,index,x,y,z,nominal_x,nominal_y,nominal_z,normal_i,normal_j,normal_k,deviation_mm,true_deviation_mm"
    );
    let rows: Vec<Vec<String>> = lines.map(csv_fields).collect();
    let root = json();
    let mut expected = vec![];
    for feature in root["features"].as_array().unwrap() {
        let count = feature["points"].as_array().unwrap().len();
        let name = feature["name"].as_str().unwrap().to_string();
        expected.extend((0..count).map(|i| (name.clone(), i.to_string())));
    }
    let labels: Vec<(String, String)> = rows.iter().map(|r| (r[0].clone(), r[1].clone())).collect();
    assert_eq!(labels, expected);
    assert_eq!(rows.len(), 72 + 40);
    assert!(rows.iter().all(|r| r.len() == 13));
    let csv_numbers: Vec<String> = rows.iter().flat_map(|r| r[2..].to_vec()).collect();
    assert_eq!(csv_numbers, point_number_tokens(&to_json(&report)));
    let model_numbers = report
        .features
        .iter()
        .flat_map(|f| &f.points)
        .flat_map(|p| {
            let scalars = [p.deviation_mm, p.true_deviation_mm];
            [p.measured, p.nominal, p.normal]
                .concat()
                .into_iter()
                .chain(scalars)
        });
    for (text, value) in csv_numbers.iter().zip(model_numbers) {
        assert_eq!(
            text.parse::<f64>().unwrap().to_bits(),
            value.to_bits(),
            "{text}"
        );
    }
}

#[test]
fn junit_is_well_formed_with_the_right_counts() {
    let xml = junit_xml(&report());
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "testsuites");
    let suites: Vec<_> = root
        .children()
        .filter(|n| n.has_tag_name("testsuite"))
        .collect();
    assert_eq!(suites.len(), 1);
    let suite = suites[0];
    assert_eq!(suite.attribute("name"), Some("blade-7 <demo>"));
    assert_eq!(suite.attribute("tests"), Some("3"));
    assert_eq!(suite.attribute("failures"), Some("1"));
    assert_eq!(suite.attribute("errors"), Some("1"));
    assert_eq!(suite.attribute("time"), Some("18.375"));
    let cases: Vec<_> = suite
        .children()
        .filter(|n| n.has_tag_name("testcase"))
        .collect();
    let names: Vec<_> = cases.iter().map(|c| c.attribute("name").unwrap()).collect();
    assert_eq!(names, ["ring", FAIL_NAME, "pocket"]);
    assert!(cases
        .iter()
        .all(|c| c.attribute("classname") == Some("blade-7 <demo>")));
    assert_eq!(cases[0].attribute("time"), Some("9.750"));
    assert_eq!(cases[0].children().filter(|n| n.is_element()).count(), 0);
    let failure = cases[1]
        .children()
        .find(|n| n.has_tag_name("failure"))
        .unwrap();
    let message = failure.attribute("message").unwrap();
    assert!(
        message.contains("outside tolerance -0.0500..0.0500 mm"),
        "{message}"
    );
    let error = cases[2]
        .children()
        .find(|n| n.has_tag_name("error"))
        .unwrap();
    let message = error.attribute("message").unwrap();
    assert!(
        message.contains("last attempt autonomous ended aborted"),
        "{message}"
    );
    assert!(message.contains("stylus lost contact"), "{message}");
}

#[test]
fn junit_batch_has_one_suite_per_part() {
    let parts = vec![
        ("part-1".to_string(), report()),
        ("part-2".to_string(), report()),
    ];
    let xml = junit_batch(&parts);
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let root = doc.root_element();
    assert_eq!(root.attribute("tests"), Some("6"));
    assert_eq!(root.attribute("failures"), Some("2"));
    assert_eq!(root.attribute("errors"), Some("2"));
    let names: Vec<_> = root
        .children()
        .filter(|n| n.has_tag_name("testsuite"))
        .map(|n| n.attribute("name").unwrap())
        .collect();
    assert_eq!(names, ["part-1", "part-2"]);
}

#[test]
fn write_reports_creates_the_directory_and_all_four_files() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out/part-1");
    let report = report();
    write_reports(&dir, &report).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["junit.xml", "points.csv", "report.html", "report.json"]
    );
    let json = std::fs::read_to_string(dir.join("report.json")).unwrap();
    assert_eq!(json, to_json(&report));
}

#[test]
fn write_reports_reports_the_path_when_the_directory_cannot_be_made() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let err = write_reports(&file.join("sub"), &report()).unwrap_err();
    assert!(err.to_string().contains("a-file"), "{err}");
}
