//! Best-fit alignment: touch the program's alignment points at their
//! nominal positions, then find the rigid part-to-machine pose that puts the
//! measured points onto the design surfaces (Gauss-Newton on point-to-plane
//! distances, closest points re-found every iteration).
use nalgebra::{DMatrix, DVector, Rotation3};

use super::record::{AlignmentReport, CollisionReport};
use crate::host::modes::{touch_point, Collision, FreeSpace, HostProbe, ModeOptions, Outcome};
use crate::host::observe::Machine;
use crate::math::{Mat3, Point3, Vec3};
use crate::program::{NominalPoint, Pose};
use crate::workpiece::Workpiece;

/// Limits of the best fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlignOptions {
    /// Iterations of the point-to-surface best fit.
    pub max_iterations: usize,
    /// The fit stops when an update moves no point more than this, mm.
    pub step_tol_mm: f64,
    /// How far past the nominal a touch searches for contact, mm.
    pub search_mm: f64,
}

impl Default for AlignOptions {
    fn default() -> Self {
        AlignOptions {
            max_iterations: 30,
            step_tol_mm: 1e-9,
            search_mm: 6.0,
        }
    }
}

/// An alignment whose touch point could not be measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlignmentFailure {
    /// How the touch ended.
    pub outcome: Outcome,
    /// Which alignment point it was (0-based).
    pub point: usize,
    /// Machine time of the alignment up to and with the failed touch, s.
    pub machine_time_s: f64,
    /// Where the probe struck the part, for a collision.
    pub collision: Option<Collision>,
}

impl AlignmentFailure {
    /// The alignment's report: the points measured before the failed
    /// one, its time, how it ended and where the probe struck (`pose`
    /// takes machine coordinates to the part's).
    pub fn report(&self, pose: &Pose) -> AlignmentReport {
        AlignmentReport {
            points: self.point,
            rms_mm: f64::NAN,
            max_mm: f64::NAN,
            iterations: 0,
            machine_time_s: self.machine_time_s,
            failed: Some(self.outcome),
            failed_point: Some(self.point),
            collision: self.collision.map(|c| CollisionReport::new(&c, pose)),
            notes: Vec::new(),
        }
    }
}

/// Touches the alignment points (routing round the part that `free`
/// describes, when given) and returns the fitted pose and a summary; how
/// the touch that could not be measured ended otherwise (the nominal
/// placement is then kept).
pub fn align(
    cmm: &mut dyn Machine,
    (probe, free): (HostProbe, Option<&dyn FreeSpace>),
    wp: &Workpiece,
    nominal: &Pose,
    points: &[NominalPoint],
    modes: &ModeOptions,
    opts: &AlignOptions,
) -> Result<(Pose, AlignmentReport), AlignmentFailure> {
    let t0 = cmm.readings().time_s;
    let mut measured = Vec::with_capacity(points.len());
    for (k, p) in points.iter().enumerate() {
        let (m, n) = (
            nominal.to_machine(p.point),
            nominal.dir_to_machine(p.normal),
        );
        let a = touch_point(cmm, (probe, free), m, n, opts.search_mm, modes);
        match (a.outcome, a.points.first()) {
            (Outcome::Completed, Some(hit)) => measured.push(hit.point),
            (o, _) => {
                return Err(AlignmentFailure {
                    outcome: if o == Outcome::Completed {
                        Outcome::Aborted
                    } else {
                        o
                    },
                    point: k,
                    machine_time_s: cmm.readings().time_s - t0,
                    collision: a.collision,
                })
            }
        }
    }
    let free = FreeMotions::of(points);
    let (pose, iterations) = best_fit(wp, nominal, (&measured, &free), opts);
    let residuals: Vec<f64> = measured
        .iter()
        .filter_map(|&m| residual(wp, &pose, m))
        .collect();
    let n = residuals.len().max(1) as f64;
    let report = AlignmentReport {
        points: measured.len(),
        rms_mm: (residuals.iter().map(|r| r * r).sum::<f64>() / n).sqrt(),
        max_mm: residuals.iter().fold(0.0, |a: f64, r| a.max(r.abs())),
        iterations,
        machine_time_s: cmm.readings().time_s - t0,
        failed: None,
        failed_point: None,
        collision: None,
        notes: undetermined(points),
    };
    Ok((pose, report))
}

/// Singular values of the alignment's design Jacobian (rotation columns
/// scaled by the points' spread) below this fraction of the largest leave
/// a motion of the part that no alignment point's surface resists.
const UNDETERMINED_RATIO: f64 = 1e-6;

/// The decomposition [`design_svd`] gives.
pub(super) type DesignSvd = nalgebra::linalg::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>;

/// The singular value decomposition (with `V^T`) of the alignment's
/// design Jacobian: a row a point, the signed distance's change under a
/// turn `w` about the points' centroid `c` (scaled by their spread `l`)
/// and a shift; with `c` and `l`.
pub(super) fn design_svd(points: &[NominalPoint]) -> (Vec3, f64, DesignSvd) {
    let n = points.len().max(1) as f64;
    let c = points.iter().fold(Vec3::zeros(), |s, p| s + p.point.coords) / n;
    let spread = (points.iter())
        .map(|p| (p.point.coords - c).norm_squared())
        .sum::<f64>();
    let l = (spread / n).sqrt().max(1e-9);
    let jac = DMatrix::from_fn(points.len(), 6, |i, j| {
        let (x, nn) = (points[i].point.coords - c, points[i].normal);
        if j < 3 {
            x.cross(&nn)[j] / l
        } else {
            nn[j - 3]
        }
    });
    (c, l, jac.svd(false, true))
}

/// The rigid motions the alignment points cannot fix, from the design
/// alone: unit vectors `(l w, t')` of a turn `w` about the points'
/// centroid `c` (scaled by their spread `l`) and a shift `t'`, each moving
/// every point along its surface.
struct FreeMotions {
    motions: Vec<[f64; 6]>,
    centroid: Vec3,
    spread: f64,
}

impl FreeMotions {
    fn of(points: &[NominalPoint]) -> FreeMotions {
        let (c, l, svd) = design_svd(points);
        let top = svd.singular_values.iter().copied().reduce(f64::max);
        let motions = match (svd.v_t.as_ref(), top) {
            (Some(vt), Some(top)) => (0..6)
                .filter(|&k| {
                    svd.singular_values
                        .get(k)
                        .is_none_or(|&s| s < UNDETERMINED_RATIO * top)
                })
                .filter(|&k| k < vt.nrows())
                .map(|k| std::array::from_fn(|j| vt[(k, j)]))
                .collect(),
            _ => Vec::new(),
        };
        FreeMotions {
            motions,
            centroid: c,
            spread: l,
        }
    }

    /// The projector onto the steps `(w, t)` (a turn `w` about the origin
    /// and a shift `t`, part frame) that leave the free motions where the
    /// placement has them: no turn about a free turn's axis, no shift
    /// along a free shift. Removing a free motion's share of a step
    /// afterwards is not the same: a free turn about an axis away from
    /// the points' centroid carries a shift, and a shift that the
    /// measuring found would then be fitted partly as a turn about the
    /// free axis (a flange moved 0.3 mm across its axis turned by 0.085
    /// degrees about it, its bolt holes 0.055 mm off).
    fn fixing_projector(&self) -> DMatrix<f64> {
        let mut p = DMatrix::<f64>::identity(6, 6);
        for row in self.constraints() {
            let c = DVector::from_row_slice(&row);
            p -= &c * c.transpose();
        }
        p
    }

    /// Orthonormal rows `(w, t)` of what the fit holds at the placement's
    /// value: the directions of the free turns' axes (`(a, 0)`), then the
    /// free shifts (`(0, d)`), the latter from the free motions without a
    /// turn (a screw's turn holds it whole).
    fn constraints(&self) -> Vec<[f64; 6]> {
        let (c, l) = (self.centroid, self.spread);
        // The free motions as a turn (times the spread, as the motions
        // hold it) and the shift of the origin, mm.
        let motions: Vec<(Vec3, Vec3)> = (self.motions.iter())
            .map(|m| {
                let turn = Vec3::new(m[0], m[1], m[2]);
                (turn, Vec3::new(m[3], m[4], m[5]) - (turn / l).cross(&c))
            })
            .collect();
        let k = motions.len();
        if k == 0 {
            return Vec::new();
        }
        let turns = DMatrix::from_fn(3, k, |i, j| motions[j].0[i]);
        let gram = turns.transpose() * &turns;
        let eigen = gram.symmetric_eigen();
        let mut rows = Vec::new();
        let mut shifts: Vec<Vec3> = Vec::new();
        for (j, &lambda) in eigen.eigenvalues.iter().enumerate() {
            let z = eigen.eigenvectors.column(j);
            let combine = |part: &dyn Fn(&(Vec3, Vec3)) -> Vec3| {
                (motions.iter().zip(z.iter())).fold(Vec3::zeros(), |s, (m, x)| s + part(m) * *x)
            };
            if lambda > UNDETERMINED_RATIO * UNDETERMINED_RATIO {
                let a = combine(&|m| m.0).normalize();
                rows.push([a.x, a.y, a.z, 0.0, 0.0, 0.0]);
            } else {
                shifts.push(combine(&|m| m.1));
            }
        }
        let mut kept: Vec<Vec3> = Vec::new();
        for t in shifts {
            let rest = kept.iter().fold(t, |r, d| r - d * d.dot(&r));
            if let Some(d) = rest.try_normalize(UNDETERMINED_RATIO) {
                kept.push(d);
                rows.push([0.0, 0.0, 0.0, d.x, d.y, d.z]);
            }
        }
        rows
    }
}

/// What the alignment points cannot fix, from the design alone: each
/// rigid motion that moves every point along its surface (all points on
/// faces round about one axis leave the turn about it), as a note; the
/// fit then keeps the placement's value of it.
pub fn undetermined(points: &[NominalPoint]) -> Vec<String> {
    let free = FreeMotions::of(points);
    (free.motions.iter())
        .map(|v| motion_note(v.to_vec(), free.centroid, free.spread))
        .collect()
}

/// The note for the free motion `v` (scaled rotation, translation) of
/// points about their centroid `c` with spread `l`.
fn motion_note(v: Vec<f64>, c: Vec3, l: f64) -> String {
    let at = |k: usize| v.get(k).copied().unwrap_or(0.0);
    let (w, t) = (
        Vec3::new(at(0), at(1), at(2)),
        Vec3::new(at(3), at(4), at(5)),
    );
    let what = if w.norm() >= t.norm() {
        let axis = w.normalize();
        let through = c + w.cross(&t) * (l / w.norm_squared());
        format!(
            "a turn about the axis ({:.3}, {:.3}, {:.3}) through ({:.3}, {:.3}, {:.3})",
            axis.x, axis.y, axis.z, through.x, through.y, through.z
        )
    } else {
        let d = t.normalize();
        format!("a shift along ({:.3}, {:.3}, {:.3})", d.x, d.y, d.z)
    };
    format!(
        "the alignment points do not fix {what} (part frame): the fit keeps the placement's value"
    )
}

/// Signed distance of a measured machine point from the design surfaces
/// under `pose`.
fn residual(wp: &Workpiece, pose: &Pose, m: Point3) -> Option<f64> {
    Some(
        wp.closest_point(pose.to_part(m))
            .ok()?
            .projection
            .signed_distance,
    )
}

/// Gauss-Newton on six parameters (small rotation and translation of the
/// part coordinates of the measured points).
fn best_fit(
    wp: &Workpiece,
    start: &Pose,
    (measured, free): (&[Point3], &FreeMotions),
    opts: &AlignOptions,
) -> (Pose, usize) {
    // Inverse pose x = a m + b (machine to part).
    let mut a: Mat3 = start.rotation.transpose();
    let mut b: Vec3 = -(a * start.translation);
    let fixing = free.fixing_projector();
    for it in 1..=opts.max_iterations {
        let rows: Vec<(Vec3, Vec3, f64)> = measured
            .iter()
            .filter_map(|m| {
                let x = Point3::from(a * m.coords + b);
                let pr = wp.closest_point(x).ok()?.projection;
                Some((x.coords, pr.normal, (x - pr.point).dot(&pr.normal)))
            })
            .collect();
        let jac = DMatrix::from_fn(rows.len(), 6, |i, j| {
            let (x, n, _) = rows[i];
            if j < 3 {
                x.cross(&n)[j]
            } else {
                n[j - 3]
            }
        });
        let r = DVector::from_fn(rows.len(), |i, _| -rows[i].2);
        let Ok(step) = (jac * &fixing).svd(true, true).solve(&r, 1e-12) else {
            return (pose_of(a, b), it);
        };
        let step = &fixing * step;
        let (w, delta) = (
            Vec3::new(step[0], step[1], step[2]),
            Vec3::new(step[3], step[4], step[5]),
        );
        let rot = Rotation3::new(w).into_inner();
        a = rot * a;
        b = rot * b + delta;
        let moved = rows
            .iter()
            .map(|(x, _, _)| (rot * x + delta - x).norm())
            .fold(0.0, f64::max);
        if moved <= opts.step_tol_mm {
            return (pose_of(a, b), it);
        }
    }
    (pose_of(a, b), opts.max_iterations)
}

fn pose_of(a: Mat3, b: Vec3) -> Pose {
    let rotation = a.transpose();
    Pose {
        rotation,
        translation: -(rotation * b),
    }
}
