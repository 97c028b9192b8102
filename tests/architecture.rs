//! The world/host seam, enforced: the measuring software (the host) never
//! reads the simulated truth, the simulated world never reads the host, only
//! the application layer (and the one truth step of the evaluation) builds
//! or reads a world, and the top-level modules form no cycle.
//!
//! The checker reads every file under `src/` and collects the top-level
//! modules it names (`crate::x`, `use crate::{x, y}`, and `super::` paths
//! that climb to the crate root). It is checked itself on made-up trees
//! that break each rule.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Files (paths under `src/`, `/`-separated) and the top-level modules each
/// names.
type Refs = BTreeMap<String, BTreeSet<String>>;

/// Files outside the world that may name it: the application layer and
/// the truth step of the evaluation.
const MAY_READ_WORLD: [&str; 2] = ["app/", "evaluate/truth.rs"];
/// What the world must not name.
const WORLD_MUST_NOT: [&str; 5] = ["host", "evaluate", "report", "app", "cli"];
/// What the host must not name.
const HOST_MUST_NOT: [&str; 5] = ["world", "evaluate", "report", "app", "cli"];
/// Scenario types under `formats` that the host must not name.
const SCENARIO_PATHS: [&str; 1] = ["crate::formats::as_machined"];
/// What the seam may name besides itself.
const SEAM_MAY: [&str; 1] = ["math"];
/// What the neutral machine model must not name.
const MACHINE_MUST_NOT: [&str; 3] = ["world", "host", "app"];

fn top(file: &str) -> &str {
    let first = file.split('/').next().unwrap_or(file);
    first.strip_suffix(".rs").unwrap_or(first)
}

/// The module path of a file (`host/inspect/mod.rs` -> `[host, inspect]`).
fn module_path(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file.split('/').map(str::to_string).collect();
    if let Some(last) = parts.pop() {
        let stem = last.trim_end_matches(".rs");
        if stem != "mod" {
            parts.push(stem.to_string());
        }
    }
    parts
}

/// The source without comments (line comments, doc comments).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

fn ident_at(s: &str) -> String {
    s.chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect()
}

/// Top-level modules named by `text` of the file `file`.
fn named(file: &str, text: &str) -> BTreeSet<String> {
    let code = code(text);
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name = ident_at(item.trim());
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        } else {
            out.insert(ident_at(rest));
        }
    }
    let path = module_path(file);
    for (i, _) in code.match_indices("super::") {
        // Only the first `super` of a chain.
        if code[..i].ends_with("super::") {
            continue;
        }
        let mut rest = &code[i..];
        let mut up = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            up += 1;
            rest = r;
        }
        if up >= path.len() {
            out.insert(ident_at(rest));
        }
    }
    out.retain(|m| !m.is_empty() && m != "self" && m != "super");
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// Every file under `src/` (but the crate root and `main.rs`) and what it
/// names.
fn source_refs() -> Refs {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut refs = Refs::new();
    for f in files {
        let rel = f
            .strip_prefix(&src)
            .unwrap_or(&f)
            .to_string_lossy()
            .replace('\\', "/");
        if rel == "lib.rs" || rel == "main.rs" {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap_or_else(|e| panic!("{rel}: {e}"));
        let mut names = named(&rel, &text);
        names.remove(top(&rel));
        if SCENARIO_PATHS.iter().any(|p| code(&text).contains(p)) {
            names.insert("formats::as_machined".into());
        }
        refs.insert(rel, names);
    }
    refs
}

/// Every rule broken by `refs`, as readable lines.
fn violations(refs: &Refs) -> Vec<String> {
    let mut out = Vec::new();
    for (file, names) in refs {
        let module = top(file);
        let may_read_world =
            module == "world" || MAY_READ_WORLD.iter().any(|p| file.starts_with(p));
        if names.contains("world") && !may_read_world {
            out.push(format!("{file} names the world"));
        }
        let forbidden: &[&str] = match module {
            "world" => &WORLD_MUST_NOT,
            "host" => &HOST_MUST_NOT,
            "machine" => &MACHINE_MUST_NOT,
            _ => &[],
        };
        for f in forbidden {
            if names.contains(*f) {
                out.push(format!("{file} ({module}) names {f}"));
            }
        }
        if module == "host" && names.contains("formats::as_machined") {
            out.push(format!(
                "{file} (host) names the scenario's as-machined types"
            ));
        }
        if module == "seam" {
            for n in names.iter().filter(|n| !SEAM_MAY.contains(&n.as_str())) {
                out.push(format!("{file} (seam) names {n}"));
            }
        }
    }
    out.extend(cycles(refs));
    out
}

/// Whether a file holds unit tests only (`tests.rs`, or under a `tests/`
/// folder of a module): such a file may use a later module for its
/// fixtures (an example workpiece in a geometry test) without making the
/// product's modules depend on each other. The world rules hold for it all
/// the same.
fn is_unit_test(file: &str) -> bool {
    file.ends_with("/tests.rs") || file.contains("/tests/")
}

/// The top-level module graph's cycles (one line per strongly connected
/// set of two or more modules); unit-test files are left out.
fn cycles(refs: &Refs) -> Vec<String> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (file, names) in refs.iter().filter(|(f, _)| !is_unit_test(f)) {
        let from = top(file).to_string();
        let to: Vec<String> = (names.iter())
            .filter(|n| !n.contains("::") && **n != from)
            .cloned()
            .collect();
        graph.entry(from).or_default().extend(to);
    }
    let reach = |start: &str| -> BTreeSet<String> {
        let mut seen = BTreeSet::new();
        let mut stack = vec![start.to_string()];
        while let Some(m) = stack.pop() {
            for n in graph.get(&m).into_iter().flatten() {
                if seen.insert(n.clone()) {
                    stack.push(n.clone());
                }
            }
        }
        seen
    };
    let mut reported = BTreeSet::new();
    let mut out = Vec::new();
    for m in graph.keys() {
        let from_m = reach(m);
        if !from_m.contains(m) || reported.contains(m) {
            continue;
        }
        let set: BTreeSet<String> = (from_m.iter())
            .filter(|n| reach(n).contains(m))
            .cloned()
            .collect();
        reported.extend(set.iter().cloned());
        let names: Vec<&str> = set.iter().map(String::as_str).collect();
        out.push(format!("modules in a cycle: {}", names.join(", ")));
    }
    out
}

#[test]
fn the_source_keeps_the_seam_and_has_no_module_cycle() {
    let refs = source_refs();
    assert!(refs.len() > 100, "only {} source files found", refs.len());
    let v = violations(&refs);
    assert!(v.is_empty(), "architecture rules broken:\n{}", v.join("\n"));
}

fn tree(files: &[(&str, &str)]) -> Refs {
    files
        .iter()
        .map(|(f, text)| {
            let mut n = named(f, text);
            n.remove(top(f));
            if SCENARIO_PATHS.iter().any(|p| text.contains(p)) {
                n.insert("formats::as_machined".into());
            }
            (f.to_string(), n)
        })
        .collect()
}

#[test]
fn the_checker_sees_each_kind_of_broken_rule() {
    let ok = [
        (
            "host/modes/scan.rs",
            "use crate::seam::Cmm;\nuse super::Tracker;",
        ),
        (
            "world/cmm.rs",
            "use crate::seam::Cmm; use crate::workpiece::Workpiece;",
        ),
        (
            "app/run.rs",
            "use crate::world::cmm::SimulatedCmm; use crate::host::modes;",
        ),
        (
            "evaluate/truth.rs",
            "use crate::world::as_machined::AsMachined;",
        ),
        (
            "seam/mod.rs",
            "use crate::math::Vec3; // crate::world in a comment",
        ),
    ];
    assert_eq!(violations(&tree(&ok)), Vec::<String>::new());
    let fixture = [
        ("workpiece/mod.rs", "use crate::geometry::Plane;"),
        (
            "geometry/projection/tests.rs",
            "use crate::workpiece::examples;",
        ),
    ];
    assert_eq!(violations(&tree(&fixture)), Vec::<String>::new());
    let broken: [(&str, &str, &str); 8] = [
        (
            "host/inspect/run.rs",
            "use crate::world::cmm::SimulatedCmm;",
            "names the world",
        ),
        (
            "cli/scan.rs",
            "use crate::{app, world::as_machined};",
            "names the world",
        ),
        (
            "world/cmm.rs",
            "fn f() { crate::host::modes::x() }",
            "names host",
        ),
        (
            "host/path/x.rs",
            "use crate::formats::as_machined::AsMachinedSpec;",
            "scenario",
        ),
        (
            "seam/mod.rs",
            "use crate::host::modes::Measured;",
            "(seam) names host",
        ),
        (
            "machine/mod.rs",
            "use super::world::dynamics::Servo;",
            "names world",
        ),
        ("geometry/a.rs", "use crate::workpiece::Face;", "cycle"),
        (
            "workpiece/near/tests.rs",
            "use crate::world::as_machined::X;",
            "names the world",
        ),
    ];
    for (file, text, expect) in broken {
        let mut files = ok.to_vec();
        files.push(("workpiece/mod.rs", "use crate::geometry::Plane;"));
        files.push((file, text));
        let v = violations(&tree(&files));
        assert!(
            v.iter().any(|l| l.contains(expect)),
            "{file}: {text}: expected '{expect}', got {v:?}"
        );
    }
}

#[test]
fn super_paths_that_climb_to_the_crate_root_count() {
    let n = named("host/modes/scan.rs", "use super::super::super::world::x;");
    assert!(n.contains("world"), "{n:?}");
    let n = named("host/modes/scan.rs", "use super::super::trace::x;");
    assert!(!n.contains("trace"), "{n:?}");
}
