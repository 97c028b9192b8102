#![allow(dead_code)]
//! Shared test helpers: seeded randomness, example workpieces and an
//! independent NURBS evaluator written straight from the definition.
use std::path::PathBuf;

use cmm::workpiece::{SurfaceSpec, TrimSpec, Workpiece, WorkpieceFile};
use rand::SeedableRng;

pub type TestRng = rand::rngs::ChaCha8Rng;

pub fn rng(seed: u64) -> TestRng {
    TestRng::seed_from_u64(seed)
}

pub fn uniform(rng: &mut TestRng, lo: f64, hi: f64) -> f64 {
    use rand::RngExt;
    lo + (hi - lo) * rng.random::<f64>()
}

/// A uniformly random unit vector (rejection from the unit ball).
pub fn random_direction(rng: &mut TestRng) -> cmm::math::Vec3 {
    loop {
        let v = cmm::math::Vec3::new(
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
            uniform(rng, -1.0, 1.0),
        );
        if v.norm() > 0.1 && v.norm() <= 1.0 {
            return v.normalize();
        }
    }
}

pub fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// Runs the `cmm` binary with `args`.
pub fn cmm(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_cmm"))
        .args(args)
        .output()
        .unwrap()
}

/// A path as a command-line argument.
pub fn arg(p: &std::path::Path) -> String {
    p.to_string_lossy().into_owned()
}

pub fn example(stem: &str) -> Workpiece {
    let path = repo(&format!("workpieces/{stem}.json"));
    Workpiece::from_path(&path).unwrap_or_else(|e| panic!("{e}"))
}

pub fn from_file(file: &WorkpieceFile) -> Workpiece {
    Workpiece::from_file(file, "test.json".as_ref()).unwrap_or_else(|e| panic!("{e}"))
}

/// B-spline basis N_{i,p}(u) by the Cox-de Boor recursion, straight from the
/// definition (half-open spans; the domain end is taken from the left).
pub fn basis(knots: &[f64], i: usize, p: usize, u: f64) -> f64 {
    if p == 0 {
        let end = knots[knots.len() - 1];
        let last_nonempty = knots[i] < knots[i + 1] && knots[i + 1] == end && u == end;
        return if (knots[i] <= u && u < knots[i + 1]) || last_nonempty {
            1.0
        } else {
            0.0
        };
    }
    let mut out = 0.0;
    let d1 = knots[i + p] - knots[i];
    if d1 > 0.0 {
        out += (u - knots[i]) / d1 * basis(knots, i, p - 1, u);
    }
    let d2 = knots[i + p + 1] - knots[i + 1];
    if d2 > 0.0 {
        out += (knots[i + p + 1] - u) / d2 * basis(knots, i + 1, p - 1, u);
    }
    out
}

/// Surface point from a spec by the definition (rational sum).
pub fn reference_point(s: &cmm::workpiece::SurfaceSpec, u: f64, v: f64) -> [f64; 3] {
    let [p, q] = s.degree;
    let mut num = [0.0; 3];
    let mut den = 0.0;
    for (i, row) in s.control_points.iter().enumerate() {
        let bu = basis(&s.knots_u, i, p, u);
        if bu == 0.0 {
            continue;
        }
        for (j, cp) in row.iter().enumerate() {
            let w = s.weights.as_ref().map_or(1.0, |w| w[i][j]);
            let b = bu * basis(&s.knots_v, j, q, v) * w;
            for k in 0..3 {
                num[k] += b * cp[k];
            }
            den += b;
        }
    }
    num.map(|c| c / den)
}

/// A random rational surface: degrees 1-4, random interior knots (some
/// repeated), control points in a 100 mm box, weights in [0.5, 2].
pub fn random_surface(rng: &mut TestRng, name: &str) -> cmm::workpiece::SurfaceSpec {
    use rand::RngExt;
    let p = rng.random_range(1..=4usize);
    let q = rng.random_range(1..=4usize);
    let (ku, nu) = random_knots(rng, p);
    let (kv, nv) = random_knots(rng, q);
    let cps = (0..nu)
        .map(|i| {
            (0..nv)
                .map(|j| {
                    [
                        i as f64 * 10.0 + uniform(rng, -3.0, 3.0),
                        j as f64 * 10.0 + uniform(rng, -3.0, 3.0),
                        uniform(rng, -8.0, 8.0),
                    ]
                })
                .collect()
        })
        .collect();
    let weights = (0..nu)
        .map(|_| (0..nv).map(|_| uniform(rng, 0.5, 2.0)).collect())
        .collect();
    cmm::workpiece::SurfaceSpec {
        name: name.into(),
        degree: [p, q],
        knots_u: ku,
        knots_v: kv,
        control_points: cps,
        weights: Some(weights),
        reversed: false,
        trim: None,
    }
}

pub fn random_knots(rng: &mut TestRng, p: usize) -> (Vec<f64>, usize) {
    use rand::RngExt;
    let lo = uniform(rng, -2.0, 2.0);
    let spans = rng.random_range(1..=4usize);
    let mut k = vec![lo; p + 1];
    let mut x = lo;
    for _ in 1..spans {
        x += uniform(rng, 0.3, 1.5);
        let mult = if p > 1 && rng.random_range(0..4) == 0 {
            2.min(p)
        } else {
            1
        };
        k.extend(std::iter::repeat_n(x, mult));
    }
    x += uniform(rng, 0.3, 1.5);
    k.extend(std::iter::repeat_n(x, p + 1));
    let n = k.len() - p - 1;
    (k, n)
}

/// Random parameter strictly inside a random knot span (away from knots by
/// `margin` of the span), for derivative checks that must not straddle knots.
pub fn param_inside_span(rng: &mut TestRng, knots: &cmm::geometry::KnotVector, margin: f64) -> f64 {
    use rand::RngExt;
    let b = knots.breakpoints();
    let s = rng.random_range(0..b.len() - 1);
    b[s] + (b[s + 1] - b[s]) * uniform(rng, margin, 1.0 - margin)
}

/// A plane face `o + u a + v b`, (u, v) in [0, 1]^2, normal `a x b`.
pub fn plane(
    name: &str,
    o: [f64; 3],
    a: [f64; 3],
    b: [f64; 3],
    trim: Option<TrimSpec>,
) -> SurfaceSpec {
    let at = |s: f64, t: f64| [0, 1, 2].map(|k| o[k] + s * a[k] + t * b[k]);
    SurfaceSpec {
        name: name.into(),
        degree: [1, 1],
        knots_u: vec![0.0, 0.0, 1.0, 1.0],
        knots_v: vec![0.0, 0.0, 1.0, 1.0],
        control_points: vec![
            vec![at(0.0, 0.0), at(0.0, 1.0)],
            vec![at(1.0, 0.0), at(1.0, 1.0)],
        ],
        weights: None,
        reversed: false,
        trim,
    }
}

/// The square loop `[lo, hi]^2` in (u, v), counter-clockwise.
pub fn square(lo: f64, hi: f64) -> Vec<[f64; 2]> {
    vec![[lo, lo], [hi, lo], [hi, hi], [lo, hi]]
}

/// The block [0, 100]^2 x [0, 50] less the pocket [a, b]^2 x [z0, 50].
pub fn block_with_pocket(a: f64, b: f64, z0: f64) -> Workpiece {
    let top_trim = TrimSpec {
        outer: square(0.0, 1.0),
        holes: vec![square(a / 100.0, b / 100.0)],
    };
    let (w, h) = (b - a, 50.0 - z0);
    let surfaces = vec![
        plane(
            "top",
            [0., 0., 50.],
            [100., 0., 0.],
            [0., 100., 0.],
            Some(top_trim),
        ),
        plane("bottom", [0., 0., 0.], [0., 100., 0.], [100., 0., 0.], None),
        plane("x0", [0., 0., 0.], [0., 0., 50.], [0., 100., 0.], None),
        plane("x1", [100., 0., 0.], [0., 100., 0.], [0., 0., 50.], None),
        plane("y0", [0., 0., 0.], [100., 0., 0.], [0., 0., 50.], None),
        plane("y1", [0., 100., 0.], [0., 0., 50.], [100., 0., 0.], None),
        plane("floor", [a, a, z0], [w, 0., 0.], [0., w, 0.], None),
        plane("wall-xa", [a, a, z0], [0., w, 0.], [0., 0., h], None),
        plane("wall-xb", [b, a, z0], [0., 0., h], [0., w, 0.], None),
        plane("wall-ya", [a, a, z0], [0., 0., h], [w, 0., 0.], None),
        plane("wall-yb", [a, b, z0], [w, 0., 0.], [0., 0., h], None),
    ];
    from_file(&WorkpieceFile {
        format: "cmm-workpiece/1".into(),
        name: "block-pocket".into(),
        units: "mm".into(),
        surfaces,
    })
}

/// Pose of the block with a pocket on the machine table in the collision
/// tests.
pub const POCKET_POSE: cmm::program::Pose = cmm::program::Pose {
    rotation: cmm::math::Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
    translation: cmm::math::Vec3::new(350.0, 500.0, 20.0),
};

/// An ideal machine over `wp` as machined by `am` at [`POCKET_POSE`], with
/// the probe `pv` (mount to ball), ball radius `r`, shaft radius `rs`
/// (body 25 mm across, 80 mm long) and the ball centre at `ball` (part
/// frame).
pub fn pocket_machine<'a>(
    (wp, am): (&'a Workpiece, &'a cmm::world::as_machined::AsMachined),
    (pv, r, rs): (cmm::math::Vec3, f64, f64),
    ball: cmm::math::Point3,
) -> cmm::world::cmm::SimulatedCmm<'a> {
    use cmm::world::probe::{ProbeShape, TrueProbe};
    let part = cmm::world::cmm::TruePart {
        workpiece: wp,
        as_machined: am,
        pose: POCKET_POSE,
    };
    let mut probe = TrueProbe::ideal(pv, r);
    probe.shape = ProbeShape {
        shaft_radius_mm: rs,
        body_radius_mm: 12.5,
        body_length_mm: 80.0,
    };
    let start = POCKET_POSE.to_machine(ball) - pv;
    let profile = cmm::machine::MachineProfile::default().ideal();
    let model = cmm::machine::MachineModel::default_bridge();
    cmm::world::cmm::SimulatedCmm::new(part, model, profile, probe, 1, start).unwrap()
}

/// Writes the part program `program` to `dir/name`.
pub fn write_program(dir: &std::path::Path, name: &str, program: &serde_json::Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_string_pretty(program).unwrap()).unwrap();
    path
}

/// `cmm scan PROGRAM --ideal --quiet --out DIR/out --trace DIR/trace.csv`:
/// its exit code, the report and the trace it wrote.
pub fn scan_ideal_traced(
    program: &std::path::Path,
    dir: &std::path::Path,
) -> (Option<i32>, serde_json::Value, String) {
    let trace = dir.join("trace.csv");
    let (code, report) = scan_ideal_with(program, &dir.join("out"), &["--trace", &arg(&trace)]);
    let text = std::fs::read_to_string(&trace).unwrap_or_else(|e| panic!("{e}: {report}"));
    (code, report, text)
}

/// `cmm scan PROGRAM --ideal --quiet --out OUT`: its exit code and the
/// report it wrote.
pub fn scan_ideal(
    program: &std::path::Path,
    out: &std::path::Path,
) -> (Option<i32>, serde_json::Value) {
    scan_ideal_with(program, out, &[])
}

/// [`scan_ideal`] with `more` arguments.
fn scan_ideal_with(
    program: &std::path::Path,
    out: &std::path::Path,
    more: &[&str],
) -> (Option<i32>, serde_json::Value) {
    let (program, out) = (arg(program), arg(out));
    let mut args = vec!["scan", &program, "--ideal", "--quiet", "--out", &out];
    args.extend_from_slice(more);
    let o = cmm(&args);
    let text = std::fs::read_to_string(std::path::Path::new(&out).join("report.json"))
        .unwrap_or_else(|e| panic!("{e}: {o:?}"));
    (o.status.code(), serde_json::from_str(&text).unwrap())
}

/// A trace's rows as (phase, deflection magnitude in mm).
pub fn trace_deflections(trace: &str) -> Vec<(String, f64)> {
    let mut lines = trace.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (phase, dx, dy, dz) = (col("phase"), col("dx_mm"), col("dy_mm"), col("dz_mm"));
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let d: f64 = [dx, dy, dz]
                .iter()
                .map(|&k| f[k].parse::<f64>().unwrap().powi(2))
                .sum();
            (f[phase].to_string(), d.sqrt())
        })
        .collect()
}

/// The bearing housing of the shared CAD files (`../shared/cad`), whose
/// IGES file is 0.16 mm across (its units are wrong by a factor of 1000),
/// imported and scaled to millimetres into `dir`; `None` (with a note)
/// when the file is not there.
pub fn bearing_in_mm(dir: &std::path::Path) -> Option<PathBuf> {
    let iges = repo("../shared/cad/bearing.iges");
    if !iges.exists() {
        println!("note: {} not found; skipping", iges.display());
        return None;
    }
    let imported = dir.join("bearing-raw.json");
    let out = cmm(&["import", &arg(&iges), "--out", &arg(&imported)]);
    assert!(out.status.success(), "{out:?}");
    let mut w: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&imported).unwrap()).unwrap();
    // Trims lie in the surfaces' parameters and stay as they are.
    for s in w["surfaces"].as_array_mut().unwrap() {
        for row in s["control_points"].as_array_mut().unwrap() {
            for p in row.as_array_mut().unwrap() {
                for c in p.as_array_mut().unwrap().iter_mut().take(3) {
                    *c = serde_json::json!(c.as_f64().unwrap() * 1000.0);
                }
            }
        }
    }
    let path = dir.join("bearing-mm.json");
    std::fs::write(&path, w.to_string()).unwrap();
    Some(path)
}
