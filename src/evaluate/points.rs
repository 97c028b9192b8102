//! Deviation of points from the nominal surfaces (`cmm evaluate`,
//! DESIGN.md 6.5): global closest point over all faces and the signed
//! distance, positive where material lies outside the design.
use serde::Serialize;

use crate::geometry::ProjectionError;
use crate::math::Point3;
use crate::workpiece::Workpiece;

/// Format tag of `cmm evaluate --json` output.
pub const EVALUATE_FORMAT: &str = "cmm-evaluate/1";

/// One evaluated point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvaluatedPoint {
    /// The input point.
    pub input: [f64; 3],
    /// Name of the surface holding the closest point.
    pub surface: String,
    /// Surface parameter u of the closest point.
    pub u: f64,
    /// Surface parameter v of the closest point.
    pub v: f64,
    /// The closest nominal point.
    pub nominal: [f64; 3],
    /// Unit outward normal there.
    pub normal: [f64; 3],
    /// Signed distance, mm.
    pub deviation_mm: f64,
}

/// The `cmm-evaluate/1` document.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvaluateReport {
    /// Always [`EVALUATE_FORMAT`].
    pub format: &'static str,
    /// One entry per input point, in input order.
    pub points: Vec<EvaluatedPoint>,
}

/// Evaluates every point against the workpiece.
pub fn evaluate(wp: &Workpiece, points: &[Point3]) -> Result<EvaluateReport, ProjectionError> {
    let points = points
        .iter()
        .map(|&p| evaluate_point(wp, p))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(EvaluateReport {
        format: EVALUATE_FORMAT,
        points,
    })
}

/// Evaluates one point.
pub fn evaluate_point(wp: &Workpiece, p: Point3) -> Result<EvaluatedPoint, ProjectionError> {
    let fp = wp.closest_point(p)?;
    let pr = fp.projection;
    Ok(EvaluatedPoint {
        input: p.into(),
        surface: wp
            .faces
            .get(fp.face)
            .map(|f| f.name.clone())
            .unwrap_or_default(),
        u: pr.uv.x,
        v: pr.uv.y,
        nominal: pr.point.into(),
        normal: pr.normal.into(),
        deviation_mm: pr.signed_distance,
    })
}

impl EvaluateReport {
    /// CSV rendering: a header, then one line per point.
    pub fn to_csv(&self) -> String {
        let mut out = String::from("x,y,z,surface,u,v,nominal_x,nominal_y,nominal_z,normal_i,normal_j,normal_k,deviation_mm\n");
        for p in &self.points {
            let nums = |v: &[f64]| {
                v.iter()
                    .map(|x| format!("{x}"))
                    .collect::<Vec<_>>()
                    .join(",")
            };
            out.push_str(&format!(
                "{},{},{},{},{},{},{}\n",
                nums(&p.input),
                p.surface,
                p.u,
                p.v,
                nums(&p.nominal),
                nums(&p.normal),
                p.deviation_mm
            ));
        }
        out
    }
}
