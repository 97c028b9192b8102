//! Tests of the direct-move check against an analytic sphere, the part
//! programs' moves and a dense reference on random moves.
use super::*;
use crate::math::{rotation_xyz_deg, Mat3};
use crate::program::load;
use crate::workpiece::examples::reference_sphere;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use std::path::Path;

/// The d25 sphere at the origin, ball radius 1.5 mm, margin 4 mm, a
/// 10 mm stylus pointing up: a move along x at height 0 and offset `y0`
/// keeps `y0 - 12.5` from the sphere (closest at x = 0, at the ball),
/// so it is clear exactly when `y0 >= 18`.
pub(super) fn sphere_clearance(wp: &Workpiece) -> PartClearance<'_> {
    PartClearance {
        workpiece: wp,
        pose: Pose {
            rotation: Mat3::identity(),
            translation: Vec3::zeros(),
        },
        stylus: Vec3::new(0.0, 0.0, 10.0),
        tip_radius_mm: 1.5,
        shaft_radius_mm: 1.0,
        body: None,
        opts: ClearanceOptions::default(),
    }
}

#[test]
fn moves_past_a_sphere_are_clear_exactly_beyond_the_margin() {
    let wp = match Workpiece::from_file(&reference_sphere(25.0), Path::new("sphere.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    };
    let c = sphere_clearance(&wp);
    for (y0, clear) in [(18.2, true), (17.8, false), (30.0, true), (0.0, false)] {
        let (a, b) = (Point3::new(-60.0, y0, 0.0), Point3::new(60.0, y0, 0.0));
        assert_eq!(c.segment_clear(a, b), clear, "y0 = {y0}");
    }
    // A move that ends far away but dips past the sphere's side.
    let (a, b) = (Point3::new(-40.0, 40.0, 0.0), Point3::new(40.0, -40.0, 0.0));
    assert!(!c.segment_clear(a, b), "diagonal through the centre");
    // Only the stylus comes close: the ball passes 20 mm below the
    // sphere's bottom, the shaft's top 10 mm higher is 15 mm from it.
    let (a, b) = (
        Point3::new(-60.0, 0.0, -32.5),
        Point3::new(60.0, 0.0, -32.5),
    );
    assert!(c.segment_clear(a, b));
    let (a, b) = (
        Point3::new(-60.0, 0.0, -25.0),
        Point3::new(60.0, 0.0, -25.0),
    );
    assert!(
        !c.segment_clear(a, b),
        "the shaft's top passes 2.5 mm from the sphere"
    );
}

/// Moves along x past the sphere of [`sphere_clearance`] at 0.1 mm
/// closer than required (y0 = 17.9) are never clear, wherever they start
/// and end: the ball's path dips below the required distance over
/// +-1.9 mm only, and the path is sampled at most `2 step_mm / sqrt(2)`
/// apart. At 0.1 mm farther (y0 = 18.1) they are always clear.
#[test]
fn grazing_moves_past_a_sphere_are_judged_on_the_path() {
    let wp = match Workpiece::from_file(&reference_sphere(25.0), Path::new("sphere.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    };
    let c = sphere_clearance(&wp);
    for k in 0..40 {
        let (x0, x1) = (-60.0 + 0.37 * k as f64, 45.0 + 0.23 * k as f64);
        for (y0, clear) in [(17.9, false), (18.1, true)] {
            let (a, b) = (Point3::new(x0, y0, 0.0), Point3::new(x1, y0, 0.0));
            assert_eq!(c.segment_clear(a, b), clear, "{a} -> {b}");
        }
    }
}

/// A move of no length checks the stylus alone (its foot 20 mm, then
/// 17 mm from the sphere's centre: 7.5 and 4.5 mm from the surface);
/// a move to a point at infinity is never clear.
#[test]
fn degenerate_moves() {
    let wp = match Workpiece::from_file(&reference_sphere(25.0), Path::new("sphere.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    };
    let c = sphere_clearance(&wp);
    let p = Point3::new(0.0, 20.0, 0.0);
    assert!(c.segment_clear(p, p));
    let p = Point3::new(0.0, 17.0, 0.0);
    assert!(!c.segment_clear(p, p));
    let far = Point3::new(f64::INFINITY, 40.0, 0.0);
    assert!(!c.segment_clear(Point3::new(0.0, 40.0, 0.0), far));
    let nan = Point3::new(f64::NAN, 40.0, 0.0);
    assert!(!c.segment_clear(nan, Point3::new(0.0, 40.0, 0.0)));
}

/// The blade from its file, the probe of `part-programs/blade-z60.json`
/// (ball radius 1.5 mm, 50 mm stylus straight up) and `pose`.
fn blade_clearance(wp: &Workpiece, pose: Pose) -> PartClearance<'_> {
    PartClearance {
        workpiece: wp,
        pose,
        stylus: Vec3::new(0.0, 0.0, 50.0),
        tip_radius_mm: 1.5,
        shaft_radius_mm: 1.0,
        body: None,
        opts: ClearanceOptions::default(),
    }
}

fn blade() -> Workpiece {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("workpieces/blade.json");
    match Workpiece::from_path(&path) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    }
}

/// The checker for the part program `name` (its workpiece, nominal
/// placement and nominal probe).
fn with_program<T>(name: &str, check: impl FnOnce(&PartClearance) -> T) -> T {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("part-programs");
    let program = match load(&dir.join(format!("{name}.json"))) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    check(&PartClearance {
        workpiece: &program.workpiece,
        pose: program.placement,
        stylus: Vec3::new(0.0, 0.0, program.probe.stylus_length_mm),
        tip_radius_mm: program.probe.tip_radius_mm,
        shaft_radius_mm: 1.0,
        body: None,
        opts: ClearanceOptions::default(),
    })
}

/// The direct moves of runs of the part programs (machine coordinates,
/// as `cmm scan` asks them; the nominal placement and probe here), with
/// the decisions those runs take (for the blade, judged against the dense
/// reference, see [`agrees_with_dense`]). The second `sphere` move's ball path dips about 0.14 mm closer
/// than required between its ends (so it is not clear, although pieces
/// judged by their centres would miss that).
#[test]
fn the_part_programs_moves_keep_their_decisions() {
    type Move = ([f64; 3], [f64; 3], bool);
    let runs: [(&str, &[Move]); 5] = [
        (
            "blade-z60",
            &[
                (
                    [378.2482, 502.7489, 261.5],
                    [348.2147, 495.5455, 210.4640],
                    false,
                ),
                (
                    [348.1909, 495.6603, 210.4604],
                    [345.8014, 497.6292, 180.4680],
                    true,
                ),
            ],
        ),
        (
            "blade-gouge",
            &[
                (
                    [377.1493, 514.2580, 210.0642],
                    [360.3762, 490.3207, 209.5637],
                    false,
                ),
                (
                    [350.4779, 503.5747, 210.5595],
                    [348.2147, 495.5455, 210.4640],
                    true,
                ),
                (
                    [348.1099, 496.8216, 210.3967],
                    [348.2215, 495.5976, 210.6645],
                    true,
                ),
            ],
        ),
        (
            "sphere",
            &[
                ([500.8333, 700.0, 124.0], [519.0, 700.0, 100.0], false),
                (
                    [518.9912, 699.8931, 100.0073],
                    [514.5991, 700.0, 112.16],
                    false,
                ),
            ],
        ),
        (
            "panel-lines",
            &[
                (
                    [300.0, 375.0, 122.9533],
                    [199.3029, 350.2292, 110.0992],
                    true,
                ),
                (
                    [400.7924, 349.8226, 103.4725],
                    [319.9809, 449.9210, 110.4759],
                    false,
                ),
            ],
        ),
        (
            "bore-circles",
            &[
                ([302.4056, 401.3889, 131.0], [316.4545, 409.5, 105.0], true),
                (
                    [316.4101, 409.6407, 104.9982],
                    [316.4545, 409.5, 115.0],
                    true,
                ),
            ],
        ),
    ];
    for (name, moves) in runs {
        with_program(name, |c| {
            for &(from, to, clear) in moves {
                let (from, to) = (Point3::from(from), Point3::from(to));
                if name.starts_with("blade") {
                    agrees_with_dense(c, from, to);
                } else {
                    assert_eq!(c.segment_clear(from, to), clear, "{name}: {from} -> {to}");
                }
            }
        });
    }
}

/// The blade's moves were recorded on an earlier (twisted) blade: they
/// still pass close by the blade, and the decision is judged against the
/// dense reference: a clear move keeps the required distance to the
/// sampling step, a refused one comes within the reference's grid of it.
fn agrees_with_dense(c: &PartClearance, from: Point3, to: Point3) {
    let need = c.tip_radius_mm + c.opts.margin_mm;
    let tol = c.opts.step_mm * std::f64::consts::FRAC_1_SQRT_2;
    let grid = REF_SPACING_MM * std::f64::consts::FRAC_1_SQRT_2;
    let clear = c.segment_clear(from, to);
    let min = dense_min_distance(c, from, to, if clear { 0.0 } else { need });
    assert!(
        !clear || min >= need - tol,
        "{from} -> {to}: clear at {min} mm"
    );
    assert!(
        clear || min < need + grid,
        "{from} -> {to}: not clear at {min} mm"
    );
}

/// Grid spacing of the dense reference over the swept area, mm.
const REF_SPACING_MM: f64 = 1.0;

/// Random moves per workpiece.
const MOVES: usize = 200;

/// Offsets of the further tries of a reference projection that failed,
/// mm.
const RETRY_MM: [f64; 3] = [0.01, 0.1, 1.0];

/// The exact distance from `p` (machine) to the part for the reference:
/// a projection that fails (as some do right over the sphere's poles) is
/// tried again from each of `RETRY_MM` away in turn, whose distance less
/// that offset bounds the distance from below; if all fail, 0.
fn reference_distance(c: &PartClearance, p: Point3) -> f64 {
    let distance =
        |p: Point3| (c.workpiece.closest_point(c.pose.to_part(p))).map(|fp| fp.projection.distance);
    let away = Vec3::new(1.0, 2.0, 3.0).normalize();
    let retries = RETRY_MM
        .iter()
        .map(|off| distance(p + away * *off).map(|d| d - off));
    (std::iter::once(distance(p)).chain(retries))
        .find_map(Result::ok)
        .unwrap_or(0.0)
}

/// The smallest exact distance from the part over a grid of the area
/// the stylus sweeps (spacing at most [`REF_SPACING_MM`]); stops early
/// below `stop`.
fn dense_min_distance(c: &PartClearance, from: Point3, to: Point3, stop: f64) -> f64 {
    let (a, b) = (to - from, c.stylus);
    let n = (a.norm() / REF_SPACING_MM).ceil().max(1.0) as usize;
    let m = (b.norm() / REF_SPACING_MM).ceil().max(1.0) as usize;
    let mut min = f64::INFINITY;
    for i in 0..=n {
        for j in 0..=m {
            let p = from + a * (i as f64 / n as f64) + b * (j as f64 / m as f64);
            min = min.min(reference_distance(c, p));
            if min < stop {
                return min;
            }
        }
    }
    min
}

/// A uniform random point of the box `lo..hi` grown by `grow` mm.
fn in_box(rng: &mut ChaCha8Rng, (lo, hi): (Point3, Point3), grow: f64) -> Point3 {
    Point3::from(Vec3::from_fn(|k, _| {
        lo[k] - grow + (hi[k] - lo[k] + 2.0 * grow) * rng.random::<f64>()
    }))
}

/// A random point of the grown box pushed outside the surface along
/// the normal at its foot, to between `near.0` and `near.1` mm.
fn near_surface(
    rng: &mut ChaCha8Rng,
    wp: &Workpiece,
    bounds: (Point3, Point3),
    near: (f64, f64),
) -> Point3 {
    let p = in_box(rng, bounds, 10.0);
    let off = near.0 + (near.1 - near.0) * rng.random::<f64>();
    match wp.closest_point(p) {
        Ok(fp) => fp.projection.point + fp.projection.normal * off,
        Err(_) => p,
    }
}

/// A random direction, between `len.0` and `len.1` mm long.
pub(super) fn direction(rng: &mut ChaCha8Rng, len: (f64, f64)) -> Vec3 {
    let len = len.0 + (len.1 - len.0) * rng.random::<f64>();
    loop {
        let v = Vec3::from_fn(|_, _| 2.0 * rng.random::<f64>() - 1.0);
        if let Some(u) = v.try_normalize(0.1).filter(|_| v.norm() <= 1.0) {
            return u * len;
        }
    }
}

/// A move grazing the surface (part coordinates: from, to, stylus): its
/// path passes `off` mm outside a random surface point along the normal
/// there, tangent to the surface, 5 to 20 mm on either side; the stylus
/// points away from the surface (within about 45 degrees of the normal).
fn grazing(
    rng: &mut ChaCha8Rng,
    wp: &Workpiece,
    bounds: (Point3, Point3),
    off: f64,
) -> (Point3, Point3, Vec3) {
    let p = in_box(rng, bounds, 10.0);
    let Ok(fp) = wp.closest_point(p) else {
        return (p, p, Vec3::z() * 10.0);
    };
    let (foot, n) = (
        fp.projection.point + fp.projection.normal * off,
        fp.projection.normal,
    );
    let side = direction(rng, (1.0, 1.0));
    let along = (side - n * side.dot(&n))
        .try_normalize(1e-3)
        .unwrap_or_else(|| n.cross(&Vec3::x()));
    let mut len = || 5.0 + 15.0 * rng.random::<f64>();
    let (from, to) = (foot - along * len(), foot + along * len());
    let up = (n + direction(rng, (0.0, 1.0)))
        .try_normalize(1e-3)
        .unwrap_or(n);
    (from, to, up * (5.0 + 45.0 * rng.random::<f64>()))
}

/// A random move around a part of bounds `bounds` (part coordinates:
/// from, to, stylus), of the kind `k % 5`: ends anywhere in the bounds
/// grown by 40 mm or 4.5 to 9.5 mm outside the surface (as probing starts
/// are), in the four pairings, with a random stylus; or grazing the
/// surface 2 mm closer to 1 mm farther than `need`.
fn random_move(
    rng: &mut ChaCha8Rng,
    wp: &Workpiece,
    bounds: (Point3, Point3),
    (k, need): (usize, f64),
) -> (Point3, Point3, Vec3) {
    if k % 5 == 4 {
        let off = need - 2.0 + 3.0 * rng.random::<f64>();
        return grazing(rng, wp, bounds, off);
    }
    let mut end = |near: bool| match near {
        false => in_box(rng, bounds, 40.0),
        true => near_surface(rng, wp, bounds, (need - 1.0, need + 4.0)),
    };
    let (a, b) = (end(k & 1 == 1), end(k & 2 == 2));
    (a, b, direction(rng, (5.0, 50.0)))
}

/// Decisions on random moves compared with the dense reference.
#[derive(Debug, Default)]
pub(super) struct Tally {
    pub(super) clear: usize,
    pub(super) touching: usize,
    /// Called clear, the reference closer than needed (within the
    /// sampling step's tolerance).
    pub(super) clear_within_tolerance: usize,
    /// Called not clear, the reference keeping the distance.
    pub(super) conservative: usize,
}

impl Tally {
    /// Counts a move called `clear` whose reference distance is `min`,
    /// the required one `need`.
    pub(super) fn add(&mut self, clear: bool, min: f64, need: f64) {
        self.clear += usize::from(clear);
        self.touching += usize::from(!clear);
        self.clear_within_tolerance += usize::from(clear && min < need);
        self.conservative += usize::from(!clear && min >= need);
    }

    /// Both decisions come often, and moves called clear although the
    /// reference comes closer than required (within the tolerance) stay
    /// rare: the rim's samples find the ball's path and the stylus at the
    /// ends too close as the old line sampling did (which called none of
    /// these moves clear either).
    fn check(&self) {
        assert!(
            self.clear > MOVES / 5 && self.touching > MOVES / 5,
            "{self:?}"
        );
        assert!(self.clear_within_tolerance <= MOVES / 100, "{self:?}");
    }
}

/// Random moves ([`random_move`]) placed by a rotated pose: none called
/// clear where the dense reference comes closer than required by more
/// than the sampling step allows, all called clear where the reference
/// keeps the distance by more than its own grid could miss.
fn compare_with_dense(wp: &Workpiece, bounds: (Point3, Point3), seed: u64) -> Tally {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let pose = Pose {
        rotation: rotation_xyz_deg([10.0, -5.0, 30.0]),
        translation: Vec3::new(350.0, 500.0, 150.0),
    };
    let mut c = blade_clearance(wp, pose);
    let need = c.tip_radius_mm + c.opts.margin_mm;
    let tol = c.opts.step_mm * std::f64::consts::FRAC_1_SQRT_2;
    let grid = REF_SPACING_MM * std::f64::consts::FRAC_1_SQRT_2;
    let mut tally = Tally::default();
    for k in 0..MOVES {
        let (a, b, stylus) = random_move(&mut rng, wp, bounds, (k, need));
        c.stylus = pose.dir_to_machine(stylus);
        let (from, to) = (pose.to_machine(a), pose.to_machine(b));
        let clear = c.segment_clear(from, to);
        let min = dense_min_distance(&c, from, to, if clear { 0.0 } else { need });
        assert!(!clear || min >= need - tol, "{a} -> {b}: clear at {min} mm");
        assert!(
            clear || min < need + grid,
            "{a} -> {b}: not clear at {min} mm"
        );
        tally.add(clear, min, need);
    }
    tally
}

#[test]
fn random_moves_agree_with_dense_sampling_on_the_blade() {
    let bounds = (Point3::new(0.0, -7.0, 0.0), Point3::new(60.0, 10.5, 100.0));
    let tally = compare_with_dense(&blade(), bounds, 21);
    eprintln!("blade: {tally:?}");
    tally.check();
}

#[test]
fn random_moves_agree_with_dense_sampling_on_the_sphere() {
    let wp = match Workpiece::from_file(&reference_sphere(25.0), Path::new("sphere.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    };
    let bounds = (
        Point3::new(-12.5, -12.5, -12.5),
        Point3::new(12.5, 12.5, 12.5),
    );
    let tally = compare_with_dense(&wp, bounds, 22);
    eprintln!("sphere: {tally:?}");
    tally.check();
}

/// A 0.3 mm ball (shaft 0.15 mm across, a 10 mm stylus pointing up) on the
/// d25 sphere: touching it at its equator, the shaft leaves the ball
/// 0.13 mm above its centre and keeps 0.075 mm (the ball radius less the
/// shaft's) from the sphere there: with the margin a program gets by
/// default for that probe (half of it) the posture is clear, with a 0.1 mm
/// margin the shaft strikes. Touching the sphere's bottom, or leaning in
/// under its equator, the shaft runs into it.
#[test]
fn a_small_balls_shaft_beside_the_surface_it_touches_is_clear() {
    let wp = match Workpiece::from_file(&reference_sphere(25.0), Path::new("sphere.json")) {
        Ok(wp) => wp,
        Err(e) => panic!("{e}"),
    };
    let small = |margin: f64| PartClearance {
        tip_radius_mm: 0.15,
        shaft_radius_mm: 0.075,
        opts: ClearanceOptions {
            posture_margin_mm: margin,
            ..ClearanceOptions::default()
        },
        ..sphere_clearance(&wp)
    };
    let c = small(0.0375);
    assert_eq!(c.posture(Point3::new(12.65, 0.0, 0.0)), None);
    assert_eq!(c.posture(Point3::new(0.0, 12.65, 0.0)), None);
    assert_eq!(
        small(0.1).posture(Point3::new(12.65, 0.0, 0.0)),
        Some(ProbePart::Shaft)
    );
    assert_eq!(
        c.posture(Point3::new(0.0, 0.0, -12.65)),
        Some(ProbePart::Shaft)
    );
    assert_eq!(
        c.posture(Point3::new(12.0, 0.0, -4.0)),
        Some(ProbePart::Shaft)
    );
}
