//! Speed planning against analytic speeds and times.

use cmm::host::path::{BallPath, MotionSample, PathOptions, SpeedOptions, SpeedPlan};
use cmm::math::{Point3, Vec3};

/// Relative slack on acceleration checks (rounding only).
const REL: f64 = 1e-9;

fn circle(r: f64, spacing: f64) -> Vec<(Point3, Vec3)> {
    let n = (2.0 * std::f64::consts::PI * r / spacing).ceil() as usize;
    (0..n)
        .map(|k| {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let radial = Vec3::new(phi.cos(), phi.sin(), 0.0);
            (Point3::origin() + radial * r, radial)
        })
        .collect()
}

/// Points every `spacing` mm from `a` to `b` (both included) with normal `n`.
fn line(a: Point3, b: Point3, spacing: f64, n: Vec3) -> Vec<(Point3, Vec3)> {
    let count = ((b - a).norm() / spacing).round() as usize;
    (0..=count)
        .map(|k| (a + (b - a) * (k as f64 / count as f64), n))
        .collect()
}

fn path(points: &[(Point3, Vec3)], closed: bool) -> BallPath {
    BallPath::from_section(points, closed, 0.0, PathOptions::default()).unwrap()
}

fn opts(speed: f64, a_lat: f64, a_tan: f64) -> SpeedOptions {
    SpeedOptions {
        speed_mm_s: speed,
        a_lat_mm_s2: a_lat,
        a_tan_mm_s2: a_tan,
        ..Default::default()
    }
}

/// Checks what every profile must satisfy: constant-acceleration
/// kinematics per cycle, |a| <= a_tan, v^2 kappa <= a_lat, s increasing,
/// rest at both ends, end exactly at the path length.
fn check_profile(path: &BallPath, plan: &SpeedPlan, o: &SpeedOptions) {
    let samples: Vec<MotionSample> = plan.samples().collect();
    let dt = o.cycle_s;
    let (first, last) = (samples[0], *samples.last().unwrap());
    assert_eq!((first.t, first.s, first.v), (0.0, 0.0, 0.0));
    assert_eq!((last.s, last.v), (path.length(), 0.0));
    assert!((plan.duration() - last.t).abs() < 1e-12);
    for pair in samples.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        assert!((b.t - a.t - dt).abs() < 1e-12);
        assert!(
            a.a.abs() <= o.a_tan_mm_s2 * (1.0 + REL),
            "a = {} at t = {}",
            a.a,
            a.t
        );
        assert!(
            (b.v - (a.v + a.a * dt)).abs() < 1e-8,
            "speed jump at t = {}",
            a.t
        );
        let ds = a.v * dt + 0.5 * a.a * dt * dt;
        assert!(
            (b.s - (a.s + ds)).abs() < 1e-8,
            "position jump at t = {}",
            a.t
        );
        assert!(b.s >= a.s && b.v >= 0.0);
    }
    for x in &samples {
        let lateral = x.v * x.v * path.curvature(x.s);
        assert!(
            lateral <= o.a_lat_mm_s2 * (1.0 + 1e-6),
            "v^2 k = {lateral} at s = {}",
            x.s
        );
        assert!(x.v <= o.speed_mm_s * (1.0 + REL));
    }
}

#[test]
fn circle_cruises_at_the_lateral_limit() {
    let r = 20.0;
    let p = path(&circle(r, 0.5), true);
    let o = opts(80.0, 100.0, 500.0);
    let plan = SpeedPlan::new(&p, &o).unwrap();
    check_profile(&p, &plan, &o);
    let expected = (o.a_lat_mm_s2 * r).sqrt();
    let top = plan.samples().map(|x| x.v).fold(0.0, f64::max);
    assert!(
        (top / expected - 1.0).abs() < 1e-3,
        "cruise {top} vs {expected}"
    );
    for seg in plan.segments() {
        assert!(
            (seg.r_eff_mm / r - 1.0).abs() < 1e-3,
            "R_eff {}",
            seg.r_eff_mm
        );
        assert!(
            (seg.r_angle_mm / r - 1.0).abs() < 1e-3,
            "R_angle {}",
            seg.r_angle_mm
        );
    }
    // Most of the way round the speed is the cruise speed.
    let cruising = plan
        .samples()
        .filter(|x| (x.v / expected - 1.0).abs() < 1e-3)
        .count();
    assert!(cruising as f64 > 0.8 * plan.profile().cycles() as f64);
}

#[test]
fn circle_cruises_at_the_commanded_speed_when_that_is_lower() {
    let p = path(&circle(20.0, 0.5), true);
    let o = opts(80.0, 1000.0, 500.0);
    let plan = SpeedPlan::new(&p, &o).unwrap();
    check_profile(&p, &plan, &o);
    let top = plan.samples().map(|x| x.v).fold(0.0, f64::max);
    assert!((top - 80.0).abs() < 1e-6, "cruise {top}");
}

#[test]
fn straight_line_takes_the_trapezoid_time() {
    let p = path(
        &line(
            Point3::origin(),
            Point3::new(60.0, 80.0, 0.0),
            0.5,
            Vec3::z(),
        ),
        false,
    );
    assert!((p.length() - 100.0).abs() < 1e-9);
    let o = opts(80.0, 1000.0, 500.0);
    let plan = SpeedPlan::new(&p, &o).unwrap();
    check_profile(&p, &plan, &o);
    let (v, a, len) = (80.0, 500.0, 100.0);
    let analytic = len / v + v / a;
    let got = plan.duration();
    assert!(
        (got - analytic).abs() <= o.cycle_s + 1e-12,
        "{got} vs {analytic}"
    );
}

#[test]
fn short_line_takes_the_triangle_time() {
    let p = path(
        &line(Point3::origin(), Point3::new(5.0, 0.0, 0.0), 0.5, Vec3::y()),
        false,
    );
    let o = opts(80.0, 1000.0, 500.0);
    let plan = SpeedPlan::new(&p, &o).unwrap();
    check_profile(&p, &plan, &o);
    let analytic = 2.0 * (5.0f64 / 500.0).sqrt();
    let got = plan.duration();
    assert!(
        (got - analytic).abs() <= o.cycle_s + 1e-12,
        "{got} vs {analytic}"
    );
}

#[test]
fn joint_speeds_match_and_follow_the_passes() {
    let p = path(
        &line(
            Point3::origin(),
            Point3::new(0.0, 0.0, 30.0),
            0.5,
            Vec3::x(),
        ),
        false,
    );
    let o = opts(80.0, 1000.0, 500.0);
    let plan = SpeedPlan::new(&p, &o).unwrap();
    let segs = plan.segments();
    for pair in segs.windows(2) {
        assert_eq!(pair[0].v_end_mm_s, pair[1].v_start_mm_s);
        assert_eq!(pair[0].s_end, pair[1].s_start);
    }
    assert_eq!(segs[0].v_start_mm_s, 0.0);
    assert_eq!(segs.last().unwrap().v_end_mm_s, 0.0);
    let len = p.length();
    for seg in segs {
        let x = seg.s_start;
        let expect = 80.0f64
            .min((1000.0 * x).sqrt())
            .min((1000.0 * (len - x)).sqrt());
        assert!(
            (seg.v_start_mm_s - expect).abs() < 1e-9,
            "at {x}: {}",
            seg.v_start_mm_s
        );
    }
}

/// Speed of the profile as it passes arc length `s`.
fn speed_at(plan: &SpeedPlan, s: f64) -> f64 {
    let samples: Vec<MotionSample> = plan.samples().collect();
    let k = samples.partition_point(|x| x.s <= s) - 1;
    let x = samples[k];
    (x.v * x.v + 2.0 * x.a * (s - x.s)).max(0.0).sqrt()
}

#[test]
fn sharp_corner_slows_down_to_the_chord_angle_speed() {
    let spacing = 0.5;
    let corner = Point3::new(20.0, 0.0, 0.0);
    let mut pts = line(Point3::origin(), corner, spacing, Vec3::z());
    pts.pop();
    pts.extend(line(
        corner,
        Point3::new(20.0, 20.0, 0.0),
        spacing,
        Vec3::z(),
    ));
    let p = path(&pts, false);
    let o = opts(80.0, 1000.0, 500.0);
    let plan = SpeedPlan::new(&p, &o).unwrap();
    check_profile(&p, &plan, &o);
    let k = 40; // index of the corner point
    let before = plan.segments()[k - 1];
    let r_angle = spacing / (2.0 * (std::f64::consts::FRAC_PI_4).sin());
    assert!(
        (before.r_angle_mm - r_angle).abs() < 1e-9,
        "R_angle {}",
        before.r_angle_mm
    );
    let v_corner = (o.a_lat_mm_s2 * r_angle).sqrt();
    assert!(before.v_max_mm_s <= v_corner + 1e-9);
    let s_corner = p.samples()[k].s;
    let v = speed_at(&plan, s_corner);
    assert!(v <= v_corner + 1e-6, "{v} at the corner, limit {v_corner}");
    assert!(v < 0.5 * o.speed_mm_s);
    let v_mid = speed_at(&plan, 0.5 * s_corner);
    assert!((v_mid - o.speed_mm_s).abs() < 1e-6, "{v_mid} mid-leg");
}

#[test]
fn state_at_time_interpolates_within_a_cycle() {
    let p = path(
        &line(
            Point3::origin(),
            Point3::new(10.0, 0.0, 0.0),
            0.5,
            Vec3::y(),
        ),
        false,
    );
    let plan = SpeedPlan::new(&p, &SpeedOptions::default()).unwrap();
    let prof = plan.profile();
    let x = prof.state_at_cycle(10).unwrap();
    let y = prof.state_at_cycle(11).unwrap();
    let mid = prof.state_at_time(0.5 * (x.t + y.t)).unwrap();
    assert!(mid.s > x.s && mid.s < y.s);
    assert!((mid.v - 0.5 * (x.v + y.v)).abs() < 1e-9);
    assert!(prof.state_at_cycle(prof.cycles() + 1).is_none());
    assert_eq!(prof.state_at_time(1e9).unwrap().s, p.length());
}

#[test]
fn invalid_options_are_rejected() {
    let p = path(
        &line(Point3::origin(), Point3::new(1.0, 0.0, 0.0), 0.5, Vec3::y()),
        false,
    );
    let o = SpeedOptions {
        a_tan_mm_s2: 0.0,
        ..Default::default()
    };
    let err = SpeedPlan::new(&p, &o).unwrap_err();
    assert!(err.to_string().contains("a_tan_mm_s2"), "{err}");
    let o = SpeedOptions {
        cycle_s: f64::NAN,
        ..Default::default()
    };
    assert!(SpeedPlan::new(&p, &o).is_err());
}

#[test]
fn wavy_path_is_held_at_the_lateral_limit_where_it_binds() {
    let wave: Vec<_> = (0..300)
        .map(|k| {
            let x = 0.5 * k as f64;
            (
                Point3::new(x, 3.0 * (0.3 * x).sin(), 0.0),
                Vec3::new(-0.9 * (0.3 * x).cos(), 1.0, 0.0),
            )
        })
        .collect();
    let p = BallPath::from_section(&wave, false, 1.0, PathOptions::default()).unwrap();
    let o = opts(80.0, 500.0, 500.0);
    let plan = SpeedPlan::new(&p, &o).unwrap();
    check_profile(&p, &plan, &o);
    let top = plan
        .samples()
        .map(|x| x.v * x.v * p.curvature(x.s))
        .fold(0.0, f64::max);
    assert!(
        top > 0.98 * o.a_lat_mm_s2,
        "lateral limit never reached: {top}"
    );
    let slowest = plan
        .segments()
        .iter()
        .map(|s| s.v_max_mm_s)
        .fold(f64::INFINITY, f64::min);
    assert!(slowest < 0.6 * o.speed_mm_s, "{slowest}");
}
