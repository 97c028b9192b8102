//! How firmly the alignment points fix the part where it is measured,
//! from the design alone. A motion the points resist only weakly (four
//! points facing one way, close together, fixing a turn about an axis far
//! from the features) lets a small common error of the points (an offset
//! of the true surface, a probe's radius error) turn or shift the whole
//! part: `cmm check` notes each motion that moves a feature's design point
//! by more than [`WeakOptions::gain`] times that error.
use super::align::design_svd;
use crate::math::{Point3, Vec3};
use crate::program::NominalPoint;

/// When a motion counts as weakly fixed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeakOptions {
    /// A common error of the alignment points moving a feature point by
    /// more than this many times the error is noted (dimensionless).
    pub gain: f64,
    /// The error the note quotes, mm.
    pub error_mm: f64,
}

impl Default for WeakOptions {
    fn default() -> Self {
        WeakOptions {
            gain: 20.0,
            error_mm: 0.005,
        }
    }
}

/// Notes for the motions the alignment `points` fix weakly for the
/// feature points `targets` (part frame). A motion is a unit vector `(l w,
/// t)` of the scaled Jacobian's `V`, resisted by its singular value `s`:
/// the same error `e` at each of the `n` points (a residual vector of norm
/// `e sqrt(n)`) moves the part by up to `e sqrt(n) / s` along it, a point
/// at `x` from the points' centroid by `|w x (x) + t|` times that. Motions
/// no point resists at all are [`super::align::undetermined`]'s.
pub fn weakly_fixed(
    points: &[NominalPoint],
    targets: &[Point3],
    opts: &WeakOptions,
) -> Vec<String> {
    let (c, l, svd) = design_svd(points);
    let Some(vt) = svd.v_t.as_ref() else {
        return Vec::new();
    };
    let top = svd.singular_values.iter().copied().fold(0.0, f64::max);
    let root_n = (points.len() as f64).sqrt();
    let mut notes = Vec::new();
    for (k, &s) in svd.singular_values.iter().enumerate() {
        if s < 1e-6 * top || k >= vt.nrows() {
            continue;
        }
        let v = |j: usize| vt[(k, j)];
        let (w, t) = (Vec3::new(v(0), v(1), v(2)) / l, Vec3::new(v(3), v(4), v(5)));
        let moved = |p: &Point3| (w.cross(&(p.coords - c)) + t).norm();
        let worst = targets
            .iter()
            .map(|p| (moved(p), *p))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((reach, at)) = worst else {
            continue;
        };
        let gain = root_n * reach / s;
        if gain > opts.gain {
            let turn = w.norm() * (at.coords - c).norm() >= t.norm();
            notes.push(note(
                (w, t, turn),
                (gain * opts.error_mm, at),
                opts.error_mm,
            ));
        }
    }
    notes
}

/// The note for a weakly fixed motion (turn `w`, shift `t`; mostly a
/// turn where it moves the point `at` more by its turn) that moves `at` by
/// `by` mm for a common error of `error` mm.
fn note((w, t, turn): (Vec3, Vec3, bool), (by, at): (f64, Point3), error: f64) -> String {
    let what = match w.try_normalize(1e-12) {
        Some(axis) if turn => {
            format!("a turn about ({:.3}, {:.3}, {:.3})", axis.x, axis.y, axis.z)
        }
        _ => {
            let d = t.try_normalize(1e-12).unwrap_or(Vec3::zeros());
            format!("a shift along ({:.3}, {:.3}, {:.3})", d.x, d.y, d.z)
        }
    };
    format!(
        "the alignment points fix {what} (part frame) weakly: an error of {error} mm at every point can move the design point ({:.3}, {:.3}, {:.3}) by {by:.3} mm",
        at.x, at.y, at.z
    )
}
