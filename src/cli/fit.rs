//! `cmm fit`: fit a geometric element to a point CSV file and print the
//! parameters, residual statistics and form error (text, or JSON as in
//! the cmm-fit/1 format).
use std::path::PathBuf;

use serde_json::{json, Map, Value};

use super::{emit, CliError, Status};
use crate::fit::{self, Element, ElementKind, FitOptions, FitReport, Method, Side};
use crate::math::{Point3, Vec3};

/// Element kinds on the command line.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum KindArg {
    /// 3-D line.
    Line,
    /// Line in the xy plane.
    Line2d,
    /// Plane.
    Plane,
    /// 3-D circle.
    Circle,
    /// Circle in the xy plane.
    Circle2d,
    /// Sphere.
    Sphere,
    /// Cylinder.
    Cylinder,
    /// Cone.
    Cone,
}

/// Fitting methods on the command line.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum MethodArg {
    /// Orthogonal least squares.
    Lsq,
    /// Minimum zone (Chebyshev).
    MinimumZone,
    /// Minimum circumscribed (circle, sphere, cylinder).
    MinCircumscribed,
    /// Maximum inscribed (circle, sphere, cylinder).
    MaxInscribed,
}

/// Probing side on the command line.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum SideArg {
    /// A bore probed from inside: the surface lies one ball radius further out.
    Inside,
    /// A shaft probed from outside: the surface lies one ball radius further in.
    Outside,
}

/// Conventions printed under `cmm fit --help`.
const CONVENTIONS: &str = "\
Conventions (all lengths mm):
  Least squares minimises orthogonal distances; a 3-D circle is the circle in
  the least-squares plane of its points; line2d/circle2d use x and y only.
  Directions (line direction, plane/circle normal, cylinder axis) have their
  largest-magnitude component positive; a cone axis points towards growing
  radius; apex_angle_deg is the full angle.
  point / axis_point: the foot of the points' centroid on the line or axis.
  Residuals are signed: positive outside the material for circle, sphere,
  cylinder and cone, along the normal for a plane, left of the direction for
  line2d; unsigned distances for a 3-D line.
  form_mm: max - min residual (minimum zone: the zone width); for a 3-D line
  the diameter 2 * max of the cylinder about it holding all points.
  Probe compensation (--probe-radius R --side S): the points are ball centres;
  inside (bore) adds R to the radius, outside (shaft) subtracts it; a cone's
  apex moves along the axis by R / sin(half angle); for a plane, outside
  means the material lies behind the normal (surface at point - R * normal).";

/// Arguments of `cmm fit`.
#[derive(Debug, clap::Args)]
#[command(after_long_help = CONVENTIONS)]
pub struct FitArgs {
    /// Element kind.
    #[arg(long, value_enum)]
    pub element: KindArg,
    /// Point CSV file (header naming x,y,z; one point per line).
    pub points: PathBuf,
    /// Fitting criterion.
    #[arg(long, value_enum, default_value = "lsq")]
    pub method: MethodArg,
    /// Stylus ball radius, mm: the points are ball centres; the result is
    /// compensated to the surface. Needs --side.
    #[arg(long, requires = "side")]
    pub probe_radius: Option<f64>,
    /// From which side the surface was probed (with --probe-radius).
    #[arg(long, value_enum, requires = "probe_radius")]
    pub side: Option<SideArg>,
    /// Machine-readable JSON output (format cmm-fit/1).
    #[arg(long)]
    pub json: bool,
    /// Write the output to this file (atomically) instead of stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

fn kind(k: KindArg) -> ElementKind {
    match k {
        KindArg::Line => ElementKind::Line,
        KindArg::Line2d => ElementKind::Line2d,
        KindArg::Plane => ElementKind::Plane,
        KindArg::Circle => ElementKind::Circle,
        KindArg::Circle2d => ElementKind::Circle2d,
        KindArg::Sphere => ElementKind::Sphere,
        KindArg::Cylinder => ElementKind::Cylinder,
        KindArg::Cone => ElementKind::Cone,
    }
}

fn method(m: MethodArg) -> Method {
    match m {
        MethodArg::Lsq => Method::Lsq,
        MethodArg::MinimumZone => Method::MinimumZone,
        MethodArg::MinCircumscribed => Method::MinCircumscribed,
        MethodArg::MaxInscribed => Method::MaxInscribed,
    }
}

fn side(s: SideArg) -> Side {
    match s {
        SideArg::Inside => Side::Inside,
        SideArg::Outside => Side::Outside,
    }
}

/// Runs `cmm fit`.
pub fn run(args: &FitArgs) -> Result<Status, CliError> {
    if let Some(r) = args.probe_radius {
        check_probe_radius(r)?;
    }
    let points = crate::pointfile::read_points_csv(&args.points)?;
    let opts = FitOptions::default();
    let in_file = |source| CliError::FitPoints {
        file: args.points.clone(),
        source,
    };
    let mut report =
        fit::fit(kind(args.element), method(args.method), &points, &opts).map_err(in_file)?;
    let probe = args.probe_radius.zip(args.side.map(side));
    if let Some((radius, s)) = probe {
        report = fit::compensate_probe(report, radius, s).map_err(in_file)?;
    }
    let text = if args.json {
        json_text(&report, probe)
    } else {
        human_text(&report, probe)
    };
    emit(&text, args.out.as_deref())?;
    Ok(Status::Pass)
}

/// Largest stylus ball radius accepted by `--probe-radius`, mm (the
/// largest styli balls are 30 mm across).
pub const MAX_PROBE_RADIUS_MM: f64 = 50.0;

fn check_probe_radius(r: f64) -> Result<(), CliError> {
    if r.is_finite() && r > 0.0 && r <= MAX_PROBE_RADIUS_MM {
        return Ok(());
    }
    Err(CliError::Value {
        option: "--probe-radius",
        value: r.to_string(),
        reason: format!("a ball radius must lie in (0, {MAX_PROBE_RADIUS_MM}] mm"),
    })
}

fn pt(p: &Point3) -> Value {
    json!([p.x, p.y, p.z])
}

fn vec(v: &Vec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// The element's parameters under the the cmm-fit/1 format keys.
fn element_fields(e: &Element) -> Vec<(&'static str, Value)> {
    match e {
        Element::Line(l) | Element::Line2d(l) => {
            vec![("point", pt(&l.point)), ("direction", vec(&l.direction))]
        }
        Element::Plane(p) => vec![("point", pt(&p.point)), ("normal", vec(&p.normal))],
        Element::Circle(c) => vec![
            ("center", pt(&c.center)),
            ("normal", vec(&c.normal)),
            ("radius", json!(c.radius)),
            ("diameter", json!(2.0 * c.radius)),
        ],
        Element::Sphere(s) => vec![
            ("center", pt(&s.center)),
            ("radius", json!(s.radius)),
            ("diameter", json!(2.0 * s.radius)),
        ],
        Element::Cylinder(c) => vec![
            ("axis_point", pt(&c.axis_point)),
            ("axis_direction", vec(&c.axis_direction)),
            ("radius", json!(c.radius)),
            ("diameter", json!(2.0 * c.radius)),
        ],
        Element::Cone(c) => vec![
            ("apex", pt(&c.apex)),
            ("axis_direction", vec(&c.axis_direction)),
            ("apex_angle_deg", json!(2.0 * c.half_angle_rad.to_degrees())),
        ],
    }
}

fn json_text(r: &FitReport, probe: Option<(f64, Side)>) -> String {
    let mut m = Map::new();
    m.insert("format".into(), json!("cmm-fit/1"));
    m.insert("element".into(), json!(r.kind.name()));
    m.insert("method".into(), json!(r.method.name()));
    for (k, v) in element_fields(&r.element) {
        m.insert(k.into(), v);
    }
    let res = &r.residuals;
    m.insert(
        "residuals_mm".into(),
        json!({ "rms": res.rms, "min": res.min, "max": res.max }),
    );
    m.insert("form_mm".into(), json!(r.form_mm));
    m.insert("point_count".into(), json!(r.point_count));
    m.insert("iterations".into(), json!(r.iterations));
    m.insert("converged".into(), json!(true));
    if let Some((radius, s)) = probe {
        m.insert(
            "probe_compensation".into(),
            json!({ "radius_mm": radius, "side": s.name() }),
        );
    }
    format!("{}\n", Value::Object(m))
}

fn human_value(v: &Value) -> String {
    match v {
        Value::Array(items) => items.iter().map(human_value).collect::<Vec<_>>().join(" "),
        Value::Number(n) => n
            .as_f64()
            .map_or_else(|| n.to_string(), |x| format!("{x:.9}")),
        other => other.to_string(),
    }
}

fn human_text(r: &FitReport, probe: Option<(f64, Side)>) -> String {
    let mut out = format!(
        "{} fit ({}), {} points, {} iterations, converged\n",
        r.kind.name(),
        r.method.name(),
        r.point_count,
        r.iterations
    );
    if let Some((radius, s)) = probe {
        out += &format!(
            "probe compensation: ball radius {radius} mm, probed from {}\n",
            s.name()
        );
    }
    for (k, v) in element_fields(&r.element) {
        out += &format!("  {k:<15} {}\n", human_value(&v));
    }
    let res = &r.residuals;
    out += &format!(
        "residuals (mm): rms {:.9}  min {:.9}  max {:.9}\n",
        res.rms, res.min, res.max
    );
    out += &format!("form error (mm): {:.9}\n", r.form_mm);
    out
}
