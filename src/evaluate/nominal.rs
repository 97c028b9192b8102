//! Measured points to their deviations from the design: the nominal foot
//! over the feature's faces and the signed distance (the cmm-report/1 format). Needs
//! the design data only, so it works the same for a simulated and a real
//! machine; `true_deviation_mm` is filled in afterwards by [`super::truth`]
//! in a simulated run (NaN until then).
//!
//! Consecutive measured points lie close together, so each point's
//! closest-point searches start where the previous point's foot lies
//! ([`crate::workpiece::Workpiece::closest_point_tracked`]); the answers
//! are the global closest points all the same. Points are evaluated in
//! fixed chunks ([`CHUNK_POINTS`]) in parallel; each chunk's first search
//! starts cold, so the results do not depend on the number of threads.
use rayon::prelude::*;

use super::model::PointReport;
use super::section_point::{onto_section, slide_error, slide_into, SLIDE_ERROR_MM};
use crate::geometry::Plane;
use crate::host::modes::Measured;
use crate::math::{Point3, Vec3};
use crate::program::Pose;
use crate::workpiece::{FaceProjection, FootHint, Workpiece};

/// Measured points per evaluation chunk: large enough that the cold start
/// of each chunk's first search costs little, small enough to share the
/// points of one scan between threads.
pub const CHUNK_POINTS: usize = 32;

/// A section scan's point farther than this (mm) from the section plane,
/// whose slide along the surface into the plane would leave the surface
/// by more than [`SLIDE_ERROR_MM`], is not a point of the section
/// ([`PointReport::off_section`], left out of the fit; its deviation is
/// the surface's there and counts): the plane hold keeps a scanning
/// contact within a few micrometres of the plane, swinging up to 10 um
/// past it as it takes over. A wall square to the plane of a part set up
/// off its design is touched off the plane by the ball's radius times
/// the tilt, and slides into it along the design's wall (off the true
/// section by that offset times the tilt).
pub const OFF_SECTION_MM: f64 = 0.01;

/// A point whose nominal point lies on an edge of its face (the trim or
/// the surface's boundary) and whose measured normal (the ball's
/// deflection, part frame) turns from the face's normal there by more than
/// 10 degrees was measured with the ball rolling over the edge: its
/// deviation says nothing of either face. A surface keeps the two within a
/// few degrees (the probe's friction leans the deflection by about 2), and
/// a deformed part's slopes away from the edges do not count.
const EDGE_COS: f64 = 0.984_807_753_012_208; // cos(10 deg)

/// How close (in the surface's parameters) a foot lies to its face's
/// boundary to count as on it: the boundary searches put their feet on it.
const ON_BOUNDARY_UV: f64 = 1e-9;

/// A point whose nominal point lies on an edge of its face and which lies
/// beyond that edge, its offset from the nominal point leaving the normal
/// there by more than this (mm), was measured past the end of the
/// feature's faces (on a face the feature does not name, or where the
/// part's as-machined edge lies further out): its distance to the edge is
/// not a deviation of the face, and it is reported as an edge point. Its
/// reported deviation would exceed the normal one by up to this.
const BEYOND_EDGE_MM: f64 = 1e-4;

/// How near (mm) to its face's edge the nominal point of a point whose
/// measured normal turns by more than 10 degrees may lie and still count
/// as rolled over the edge: the ball touching the edge itself puts the
/// measured point on the edge only to within the probe's errors (its
/// radius and the direction of its deflection, a few tens of
/// micrometres), often just inside the face.
const EDGE_NEAR_MM: f64 = 0.1;

fn rolled_over_edge(wp: &Workpiece, nominal: &FaceProjection, measured_normal: Vec3) -> bool {
    measured_normal.dot(&nominal.projection.normal) < EDGE_COS
        && (on_boundary(wp, nominal) || within_edge_mm(wp, nominal, EDGE_NEAR_MM))
}

/// Whether the ball stood on an edge of the design: the ball centre's
/// nominal foot on the face of the point's own foot lies on the face's
/// edge and the ball centre stands off it turned by more than 10 degrees
/// from the face's normal line there, as it does only over an edge (a
/// ball touching a face has its centre along the face's normal; where the
/// part carries more material than the ball's radius, behind the face,
/// against the normal: at a seam between two faces that continue each
/// other, a cylinder's halves, the centre's foot on the point's own face
/// lies on that face's edge, and the point is on the surface all the
/// same). This needs
/// the ball centre alone, which the scales and the probe vector give to
/// micrometres, not the deflection's direction, which lags while the ball
/// rolls round a corner: a point measured there can carry a measured
/// normal within a few degrees of one face's while the ball is still well
/// round the edge, tens of micrometres off either face. Looked at only
/// for a point whose own foot lies within `reach` of its face's edge (a
/// ball on an edge measures a point at most its radius from the edge).
/// The ball centre's foot on that edge, when it stands on one.
fn ball_on_edge(
    wp: &Workpiece,
    (nominal, ball, reach): (&FaceProjection, Point3, f64),
    hint: &mut Option<FootHint>,
) -> Option<FaceProjection> {
    if !within_edge_mm(wp, nominal, reach) {
        return None;
    }
    let face = [nominal.face];
    let foot = wp
        .closest_point_tracked(ball, face.iter().copied(), hint)
        .ok()?;
    let off = (ball - foot.projection.point).try_normalize(0.0);
    let turned = off.is_some_and(|u| u.dot(&foot.projection.normal).abs() < EDGE_COS);
    (turned && on_boundary(wp, &foot)).then_some(foot)
}

/// Whether the ball centre stands on the design's normal line at its
/// nearest point of the whole design (within 10 degrees): the ball
/// stands over a smooth stretch of the design, whatever its own face's
/// edge (the seam of two half cylinders that continue each other, where
/// the centre of a ball in a hole moved by more than the ball's radius
/// comes nearer the other half or the seam itself). Over an edge the
/// centre stands off the edge between the two faces' normals.
fn over_a_face(wp: &Workpiece, ball: Point3) -> bool {
    let Ok(foot) = wp.closest_point(ball) else {
        return false;
    };
    let off = (ball - foot.projection.point).try_normalize(0.0);
    off.is_some_and(|u| u.dot(&foot.projection.normal).abs() >= EDGE_COS)
}

/// Whether the face of the foot `nominal` (on or near its face's edge)
/// continues smoothly into the face nearest to it beside its own (within [`EDGE_NEAR_MM`], their
/// normals within 10 degrees): a seam between two faces that continue
/// each other (a cylinder's halves), not an edge the ball rolls over. A
/// ball standing over a face next to a sharp edge, its deflection still
/// turned from rolling round the edge, measures its point tens of
/// micrometres off (the lag of the deflection's direction), and that
/// point is an edge point.
fn continues_smoothly(wp: &Workpiece, nominal: &FaceProjection) -> bool {
    let q = nominal.projection.point;
    let mut near = Vec::new();
    wp.faces_within(q, EDGE_NEAR_MM, &mut near);
    let others = near.into_iter().filter(|&f| f != nominal.face);
    let Ok(other) = wp.closest_point_among(q, others) else {
        return false;
    };
    let normals = other.projection.normal.dot(&nominal.projection.normal);
    other.projection.distance <= EDGE_NEAR_MM && normals >= EDGE_COS
}

/// Whether the foot lies within `d` (mm) of its face's edge (the trim,
/// else the surface's boundary), the distance in the parameters taken
/// times the larger of the surface's first derivatives there (exact to
/// first order on a face whose parameters stretch alike both ways).
fn within_edge_mm(wp: &Workpiece, nominal: &FaceProjection, d: f64) -> bool {
    let Some(face) = wp.faces.get(nominal.face) else {
        return true;
    };
    let uv = nominal.projection.uv;
    let derivs = face.surface.derivs(uv.x, uv.y, 1);
    let (su, sv) = (derivs.su().norm(), derivs.sv().norm());
    let ((u0, u1), (v0, v1)) = face.surface.domain();
    let sides = [
        (uv.x - u0) * su,
        (u1 - uv.x) * su,
        (uv.y - v0) * sv,
        (v1 - uv.y) * sv,
    ];
    let stretch = su.max(sv);
    sides.iter().any(|x| x.abs() <= d)
        || (face.trim.as_ref()).is_some_and(|t| stretch <= 0.0 || t.comes_within(uv, d / stretch))
}

fn beyond_edge(wp: &Workpiece, nominal: &FaceProjection, p: Point3) -> bool {
    let (off, n) = (p - nominal.projection.point, nominal.projection.normal);
    (off - n * off.dot(&n)).norm() > BEYOND_EDGE_MM && on_boundary(wp, nominal)
}

/// Whether the foot lies on its face's trim or its surface's boundary.
fn on_boundary(wp: &Workpiece, nominal: &FaceProjection) -> bool {
    let Some(face) = wp.faces.get(nominal.face) else {
        return false;
    };
    let uv = nominal.projection.uv;
    let ((u0, u1), (v0, v1)) = face.surface.domain();
    let on_domain = [uv.x - u0, u1 - uv.x, uv.y - v0, v1 - uv.y]
        .iter()
        .any(|d| d.abs() <= ON_BOUNDARY_UV);
    on_domain
        || face
            .trim
            .as_ref()
            .is_some_and(|t| t.distance(uv) <= ON_BOUNDARY_UV)
}

/// Deviation of every measured point (machine frame, `pose` maps the part
/// to the machine) from the nominal surfaces `faces`; for a section scan
/// (`section`), which points lie off its plane and, when the feature fits
/// an element, each point's design and measured section points. A point
/// whose foot cannot be found is left out.
pub fn point_reports(
    workpiece: &Workpiece,
    pose: &Pose,
    (faces, section): (&[usize], Option<Section>),
    points: &[Measured],
) -> Vec<PointReport> {
    let faces = FeatureFaces::new(workpiece, faces);
    let chunks: Vec<Vec<PointReport>> = points
        .par_chunks(CHUNK_POINTS)
        .map(|chunk| {
            let mut hints = (Hints::default(), None);
            (chunk.iter())
                .filter_map(|m| point_report(workpiece, pose, (faces, section), m, &mut hints))
                .collect()
        })
        .collect();
    chunks.concat()
}

/// The plane of a section scan's points (part frame), and whether the
/// feature fits an element to them (its points then get their design
/// section points, [`PointReport::in_section`]).
#[derive(Debug, Clone, Copy)]
pub struct Section<'a> {
    /// The section plane.
    pub plane: &'a Plane,
    /// Whether the feature fits an element.
    pub fitted: bool,
}

/// The faces a feature's points are measured against.
#[derive(Debug, Clone, Copy)]
pub struct FeatureFaces<'a> {
    list: &'a [usize],
    /// Whether `list` names every face of the workpiece.
    all: bool,
}

impl<'a> FeatureFaces<'a> {
    /// The faces `list` (indices into `workpiece`'s faces).
    pub fn new(workpiece: &Workpiece, list: &'a [usize]) -> FeatureFaces<'a> {
        let mut listed = list.to_vec();
        listed.sort_unstable();
        listed.dedup();
        let all = listed.iter().copied().eq(0..workpiece.faces.len());
        FeatureFaces { list, all }
    }
}

/// Where the previous point's nominal feet lie.
#[derive(Debug, Default)]
pub struct Hints {
    /// Foot over all faces.
    all: Option<FootHint>,
    /// Foot over the feature's faces.
    faces: Option<FootHint>,
}

/// The nominal foot of part point `p` over the feature's `faces`, as
/// every reported deviation is measured (the measured point's and the
/// true point's alike): the closest point over all faces when it lies on
/// one of them, else the closest over theirs.
pub fn feature_foot(
    wp: &Workpiece,
    p: Point3,
    faces: FeatureFaces,
    hints: &mut Hints,
) -> Option<FaceProjection> {
    let foot = wp
        .closest_point_tracked(p, 0..wp.faces.len(), &mut hints.all)
        .ok()?;
    if faces.all || faces.list.contains(&foot.face) {
        return Some(foot);
    }
    let listed = faces.list.iter().copied();
    wp.closest_point_tracked(p, listed, &mut hints.faces).ok()
}

/// Whether the section scan's point `p` (part frame, its nominal point
/// `nominal`) lies off `plane` farther than [`OFF_SECTION_MM`] and than
/// its slide along the surface into the plane can take it.
fn off_the_section(wp: &Workpiece, nominal: &FaceProjection, p: Point3, plane: &Plane) -> bool {
    let e = plane.signed_distance(p);
    if e.abs() <= OFF_SECTION_MM {
        return false;
    }
    let Some(face) = wp.faces.get(nominal.face) else {
        return true;
    };
    let at = (nominal.projection.uv, nominal.projection.normal);
    slide_error(&face.surface, at.0, at.1, (plane, e)).is_none_or(|err| err > SLIDE_ERROR_MM)
}

fn point_report(
    wp: &Workpiece,
    pose: &Pose,
    (faces, section): (FeatureFaces, Option<Section>),
    m: &Measured,
    (hints, ball_hint): &mut (Hints, Option<FootHint>),
) -> Option<PointReport> {
    let p = pose.to_part(m.point);
    let nominal = feature_foot(wp, p, faces, hints)?;
    let reach = 2.0 * (m.ball - m.point).norm() + EDGE_NEAR_MM;
    let ball = (&nominal, pose.to_part(m.ball), reach);
    let on_edge = ball_on_edge(wp, ball, ball_hint);
    let turned =
        on_edge.is_some() || rolled_over_edge(wp, &nominal, pose.rotation.transpose() * m.normal);
    // Where the ball stands over an edge, that edge (else the point's own
    // foot's) decides whether it is a seam.
    let at = on_edge.as_ref().unwrap_or(&nominal);
    let seam = || over_a_face(wp, ball.1) && continues_smoothly(wp, at);
    let edge = beyond_edge(wp, &nominal, p) || (turned && !seam());
    let off_section = section.is_some_and(|s| off_the_section(wp, &nominal, p, s.plane));
    // Only points on the surface take part in the fit.
    let fitted = section.filter(|s| s.fitted && !edge && !off_section);
    let in_section = fitted.and_then(|s| {
        let face = wp.faces.get(nominal.face)?;
        onto_section(&face.surface, nominal.projection.uv, s.plane).map(Into::into)
    });
    let measured_in_section = fitted
        .filter(|_| in_section.is_some())
        .and_then(|s| slide_into(p, nominal.projection.normal, s.plane))
        .map(Into::into);
    let nominal = nominal.projection;
    Some(PointReport {
        measured: p.into(),
        nominal: nominal.point.into(),
        normal: nominal.normal.into(),
        deviation_mm: nominal.signed_distance,
        true_deviation_mm: f64::NAN,
        edge,
        off_section,
        in_section,
        measured_in_section,
    })
}
