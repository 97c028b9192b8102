//! Deviation of points from the nominal surfaces (`cmm evaluate`,
//! the cmm-evaluate/1 format): global closest point over all faces and the signed
//! distance, positive where material lies outside the design.
//!
//! Every valid point gets an answer: the best point the search found,
//! marked `unconfirmed` when Newton could not certify it as the global
//! minimum. Only invalid points (not finite, or out of range) are errors.
use serde::Serialize;

use crate::geometry::projection::{check_query, SearchStatus};
use crate::geometry::{Projection, ProjectionError};
use crate::math::Point3;
use crate::workpiece::{FaceProjection, Workpiece};

/// Format tag of `cmm evaluate --json` output.
pub const EVALUATE_FORMAT: &str = "cmm-evaluate/1";

/// Whether a point's closest point is certified (`"ok"`) or only the best
/// point found (`"unconfirmed"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PointStatus {
    /// The global minimum, confirmed.
    Ok,
    /// The best point found; the search could not confirm it.
    Unconfirmed,
}

impl PointStatus {
    /// The name used in the JSON and CSV output.
    pub fn as_str(self) -> &'static str {
        match self {
            PointStatus::Ok => "ok",
            PointStatus::Unconfirmed => "unconfirmed",
        }
    }
}

impl From<SearchStatus> for PointStatus {
    fn from(s: SearchStatus) -> Self {
        if s.is_confirmed() {
            PointStatus::Ok
        } else {
            PointStatus::Unconfirmed
        }
    }
}

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
    /// Whether the closest point is confirmed.
    pub status: PointStatus,
    /// The search's own account (why it is unconfirmed, the last step).
    #[serde(skip)]
    pub search: SearchStatus,
}

/// The `cmm-evaluate/1` document.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvaluateReport {
    /// Always [`EVALUATE_FORMAT`].
    pub format: &'static str,
    /// One entry per input point, in input order.
    pub points: Vec<EvaluatedPoint>,
}

impl EvaluateReport {
    /// Number of points whose closest point is unconfirmed.
    pub fn unconfirmed(&self) -> usize {
        (self.points.iter())
            .filter(|p| p.status == PointStatus::Unconfirmed)
            .count()
    }
}

/// Evaluates every point against the workpiece. Every point is checked
/// first: an invalid one (see [`check_query`]) is an error, and nothing is
/// evaluated; every valid one gets an answer.
pub fn evaluate(wp: &Workpiece, points: &[Point3]) -> Result<EvaluateReport, ProjectionError> {
    points.iter().try_for_each(|&p| check_query(p))?;
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
    let fp = closest_point(wp, p)?;
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
        status: pr.status.into(),
        search: pr.status,
    })
}

/// The global closest point over all faces, always the best point found;
/// its [`Projection::status`] is unconfirmed when the search of some face
/// that could hold a closer point could not be confirmed. Faces are
/// searched nearest box first; a face whose box is no nearer than the best
/// point so far is left out, and ties go to the face searched first.
pub fn closest_point(wp: &Workpiece, p: Point3) -> Result<FaceProjection, ProjectionError> {
    check_query(p)?;
    let mut order: Vec<(f64, usize)> = (wp.faces.iter().enumerate())
        .map(|(i, f)| (f.lower_bound(p), i))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut best: Option<(usize, Projection)> = None;
    let mut bound2 = f64::INFINITY;
    let mut status = SearchStatus::Confirmed;
    for (lb, i) in order {
        let Some(face) = wp.faces.get(i).filter(|_| lb * lb < bound2) else {
            break;
        };
        let (surface, trim) = (&face.surface, face.trim.as_ref());
        let searched = face
            .index()
            .search_checked(surface, trim, p, bound2, None)?;
        status = status.and(searched.status);
        if let Some((_, foot)) = searched.found {
            bound2 = foot.dist2;
            best = Some((i, foot.into_projection(surface, p)));
        }
    }
    let (face, mut projection) = best.ok_or(ProjectionError::OutOfRange {
        x: p.x,
        y: p.y,
        z: p.z,
        limit_mm: crate::geometry::projection::MAX_QUERY_MM,
    })?;
    projection.status = status;
    Ok(FaceProjection { face, projection })
}

impl EvaluateReport {
    /// CSV rendering: a header, then one line per point.
    pub fn to_csv(&self) -> String {
        let mut out = String::from("x,y,z,surface,u,v,nominal_x,nominal_y,nominal_z,normal_i,normal_j,normal_k,deviation_mm,status\n");
        for p in &self.points {
            let nums = |v: &[f64]| {
                v.iter()
                    .map(|x| format!("{x}"))
                    .collect::<Vec<_>>()
                    .join(",")
            };
            out.push_str(&format!(
                "{},{},{},{},{},{},{},{}\n",
                nums(&p.input),
                p.surface,
                p.u,
                p.v,
                nums(&p.nominal),
                nums(&p.normal),
                p.deviation_mm,
                p.status.as_str()
            ));
        }
        out
    }
}
