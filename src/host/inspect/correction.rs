//! Geometric correction (JP6484108B2): compare touch points with the design
//! data of a planar section and pick the simplest of a menu of corrections
//! (offset, translation, rotation, scale, combinations) whose residuals are
//! all small.
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::math::{Mat3, Point3, Vec3};

/// One design point of a section: position and outward normal (part frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DesignPoint {
    /// Position, mm.
    pub point: Point3,
    /// Outward unit normal.
    pub normal: Vec3,
}

/// A correction model: which parameters it frees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Model {
    /// Constant offset along the normals (uniform under/overcut).
    Offset,
    /// In-plane translation.
    Translation,
    /// Offset and translation.
    OffsetTranslation,
    /// Rotation about the plane normal and translation.
    Rigid,
    /// Uniform scale about the section centroid and translation.
    ScaleTranslation,
    /// Rotation, uniform scale and translation.
    Similarity,
    /// Scales along the section's two principal directions and translation.
    AxisScales,
    /// Similarity plus offset.
    SimilarityOffset,
}

impl Model {
    /// The menu, simplest first.
    pub const MENU: [Model; 8] = [
        Model::Offset,
        Model::Translation,
        Model::OffsetTranslation,
        Model::Rigid,
        Model::ScaleTranslation,
        Model::Similarity,
        Model::AxisScales,
        Model::SimilarityOffset,
    ];

    /// Name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Model::Offset => "offset",
            Model::Translation => "translation",
            Model::OffsetTranslation => "offset+translation",
            Model::Rigid => "rotation+translation",
            Model::ScaleTranslation => "uniform_scale+translation",
            Model::Similarity => "rotation+uniform_scale+translation",
            Model::AxisScales => "axis_scales+translation",
            Model::SimilarityOffset => "rotation+uniform_scale+translation+offset",
        }
    }

    /// Which of the basis motions [offset, tx, ty, rot, scale, sx, sy] it uses.
    fn uses(self) -> [bool; 7] {
        match self {
            Model::Offset => [true, false, false, false, false, false, false],
            Model::Translation => [false, true, true, false, false, false, false],
            Model::OffsetTranslation => [true, true, true, false, false, false, false],
            Model::Rigid => [false, true, true, true, false, false, false],
            Model::ScaleTranslation => [false, true, true, false, true, false, false],
            Model::Similarity => [false, true, true, true, true, false, false],
            Model::AxisScales => [false, true, true, false, false, true, true],
            Model::SimilarityOffset => [true, true, true, true, true, false, false],
        }
    }
}

/// A fitted correction, applicable to design points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Correction {
    /// The model.
    pub model: Model,
    /// Largest |residual| of the touch points after correction, mm.
    pub max_residual_mm: f64,
    /// Number of touch points.
    pub points: usize,
    frame: Frame,
    /// Parameters in the order of [`Model::uses`] (unused ones zero).
    params: [f64; 7],
}

/// In-plane frame of a section: centroid, principal axes, plane normal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
struct Frame {
    c: Point3,
    e1: Vec3,
    e2: Vec3,
}

impl Frame {
    /// The section plane's unit normal.
    fn plane_normal(&self) -> Vec3 {
        self.e1.cross(&self.e2)
    }

    fn of(design: &[DesignPoint], plane_normal: Vec3) -> Frame {
        let n = design.len().max(1) as f64;
        let c = Point3::from(design.iter().map(|d| d.point.coords).sum::<Vec3>() / n);
        let cov = design.iter().fold(nalgebra::Matrix3::zeros(), |m, d| {
            let r = d.point - c;
            let r = r - plane_normal * r.dot(&plane_normal);
            m + r * r.transpose()
        });
        let eig = cov.symmetric_eigen();
        let k = eig.eigenvalues.iamax();
        let e1 = eig.eigenvectors.column(k).into_owned();
        let e1 = (e1 - plane_normal * e1.dot(&plane_normal))
            .try_normalize(1e-12)
            .unwrap_or_else(|| any_perp(plane_normal));
        Frame {
            c,
            e1,
            e2: plane_normal.cross(&e1),
        }
    }

    /// The displacement, in the section plane, that moves a point of a
    /// surface with normal `n` by one unit along `n`: `n`'s part in the
    /// plane over its squared length (a drafted wall offset by `h` moves
    /// its section by `h / cos(draft)`, and the section stays in its
    /// plane, where `n h` would leave it by `h sin(draft)`). A normal
    /// within [`IN_PLANE_MIN`] of the plane's own gives `n`.
    fn offset_along(&self, n: Vec3) -> Vec3 {
        let pn = self.plane_normal();
        let inside = n - pn * n.dot(&pn);
        let len2 = inside.norm_squared();
        if len2 < IN_PLANE_MIN * IN_PLANE_MIN {
            return n;
        }
        inside / len2
    }

    /// Displacement of `p` (normal `n`) per unit of each basis motion.
    fn basis(&self, p: Point3, n: Vec3) -> [Vec3; 7] {
        let r = p - self.c;
        let (a, b) = (r.dot(&self.e1), r.dot(&self.e2));
        let rot = self.e2 * a - self.e1 * b;
        [
            self.offset_along(n),
            self.e1,
            self.e2,
            rot,
            self.e1 * a + self.e2 * b,
            self.e1 * a,
            self.e2 * b,
        ]
    }
}

fn any_perp(n: Vec3) -> Vec3 {
    let t = if n.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    (t - n * t.dot(&n)).normalize()
}

/// The touch points of a geometric correction: `design[i]` was touched at
/// `measured[i]` along its normal, where the section bends by
/// `curvature[i]` (1/mm; positive where it bends away from its normal, a
/// convex outline, negative in a bore).
#[derive(Debug, Clone, Copy)]
pub struct Touches<'a> {
    /// The design points touched (part frame).
    pub design: &'a [DesignPoint],
    /// The section's signed curvature at each, 1/mm.
    pub curvature: &'a [f64],
    /// Where each was measured (part frame), mm.
    pub measured: &'a [Point3],
}

impl Touches<'_> {
    fn len(&self) -> usize {
        self.design.len()
    }

    /// The distance (signed as the gap along the normal) from touch `i`'s
    /// measured point to the corrected section near it: the gap along the
    /// corrected normal less the bend of the section over the measured
    /// point's offset along it (a circle moved by `t` sideways to a
    /// touch's normal leaves a gap of `t^2 / 2R` to its tangent, none to
    /// itself).
    fn gap(&self, c: &Correction, i: usize) -> Option<f64> {
        let (d, m) = (self.design.get(i)?, self.measured.get(i)?);
        let kappa = self.curvature.get(i).copied().unwrap_or(0.0);
        let moved = c.apply(d);
        let off = m - moved.point;
        let along = off.dot(&c.frame.plane_normal().cross(&moved.normal));
        Some(off.dot(&moved.normal) + 0.5 * kappa * along * along)
    }
}

/// The signed curvature (1/mm) of the section through `design` at point
/// `i`, from its neighbours (the point itself in place of one beyond an
/// end): the turn of the normal along the chord between them over its
/// length; 0 where the normal turns by more than 30 degrees between them
/// (a corner, not a bend).
pub fn section_curvature(design: &[DesignPoint], i: usize) -> f64 {
    let here = design.get(i);
    let before = i.checked_sub(1).and_then(|j| design.get(j)).or(here);
    let (Some(a), Some(b)) = (before, design.get(i + 1).or(here)) else {
        return 0.0;
    };
    let chord = b.point - a.point;
    let (len, turn) = (chord.norm(), b.normal - a.normal);
    if len <= 0.0 || a.normal.dot(&b.normal) < CORNER_COS {
        return 0.0;
    }
    turn.dot(&(chord / len)) / len
}

/// A normal whose part in the section plane is shorter than this (it
/// stands within 30 degrees of the plane's normal) is offset along
/// itself: the section runs nearly along the surface there.
const IN_PLANE_MIN: f64 = 0.5;

/// Neighbouring design normals further apart than this (cos 30 degrees)
/// stand across a corner.
const CORNER_COS: f64 = 0.866_025_403_784_438_6;

/// Fits the simplest model whose residuals are all within `threshold_mm`;
/// with none, the simplest whose residuals are within it once the touch
/// points it leaves off by more are left out ([`fit_inliers`]; the
/// correction's `points` counts those it kept).
pub fn fit_correction(
    touches: Touches,
    plane_normal: Vec3,
    (threshold_mm, residual_share): (f64, f64),
) -> Option<Correction> {
    let frame = Frame::of(touches.design, plane_normal);
    // A model must leave at most `residual_share` of the largest gap it
    // corrects: one that leaves the error where it was (an offset fitted
    // to a hole moved sideways by less than the threshold) explains
    // nothing, and the rescan would stop where the scan stopped.
    let limit = threshold_mm.min(residual_share * largest_gap(touches, frame));
    let fits = |menu: &[Model], keep: &dyn Fn(Model) -> Option<Correction>| {
        menu.iter().find_map(|&model| {
            let c = keep(model)?;
            (c.max_residual_mm <= limit).then_some(c)
        })
    };
    fits(&Model::MENU, &|model| fit_model(touches, frame, model)).or_else(|| {
        fits(&INLIER_MODELS, &|model| {
            fit_inliers(touches, frame, (model, threshold_mm))
        })
    })
}

/// The largest gap of the touch points to the design data before any
/// correction, mm.
fn largest_gap(touches: Touches, frame: Frame) -> f64 {
    let none = Correction {
        model: Model::Offset,
        max_residual_mm: 0.0,
        points: touches.len(),
        frame,
        params: [0.0; 7],
    };
    (0..touches.len())
        .filter_map(|i| touches.gap(&none, i))
        .fold(0.0, |m, g| m.max(g.abs()))
}

/// The models fitted without outliers: the part moved as a whole (a
/// fixture's error) and a uniform layer of material. A scale or a turn
/// with scale fitted round a left-out point could bend the design into a
/// local defect.
const INLIER_MODELS: [Model; 4] = [
    Model::Offset,
    Model::Translation,
    Model::OffsetTranslation,
    Model::Rigid,
];

/// Least share of the touch points a correction fitted without the
/// outliers must keep.
const INLIER_SHARE: f64 = 0.75;

/// `model` fitted again to the touch points whose gap under its fit to
/// all of them is within `threshold_mm`, when they are at least
/// [`INLIER_SHARE`] of them: a touch at the tangent edge of a fillet
/// lands on the moved fillet or the face beside it, off the plane the
/// gap is measured along (0.37 mm on a part moved 2 mm), while the
/// others agree on the move. Only a correction that moves the design by
/// more than `threshold_mm` somewhere counts.
fn fit_inliers(
    touches: Touches,
    frame: Frame,
    (model, threshold_mm): (Model, f64),
) -> Option<Correction> {
    let all = fit_model(touches, frame, model)?;
    let kept: Vec<usize> = (0..touches.len())
        .filter(|&i| {
            touches
                .gap(&all, i)
                .is_some_and(|g| g.abs() <= threshold_mm)
        })
        .collect();
    let pick = |v: &[f64]| {
        kept.iter()
            .map(|&i| v.get(i).copied().unwrap_or(0.0))
            .collect()
    };
    let design: Vec<DesignPoint> = kept
        .iter()
        .filter_map(|&i| touches.design.get(i))
        .copied()
        .collect();
    let measured: Vec<Point3> = kept
        .iter()
        .filter_map(|&i| touches.measured.get(i))
        .copied()
        .collect();
    let curvature: Vec<f64> = pick(touches.curvature);
    let enough = kept.len() as f64 >= INLIER_SHARE * touches.len() as f64;
    let fewer = kept.len() < touches.len();
    let inliers = Touches {
        design: &design,
        curvature: &curvature,
        measured: &measured,
    };
    let c = (enough && fewer)
        .then(|| fit_model(inliers, frame, model))
        .flatten()?;
    // A correction that leaves the design where it was (a local gouge the
    // left-out points touched, on a part that has not moved) would leave
    // the rescan to stop where the scan stopped.
    let moves = touches
        .design
        .iter()
        .map(|d| (c.apply(d).point - d.point).norm())
        .fold(0.0, f64::max);
    (moves > threshold_mm).then_some(c)
}

/// Gauss-Newton on the touch points' gaps to the corrected section
/// ([`Touches::gap`]; three passes, the motions are small).
fn fit_model(touches: Touches, frame: Frame, model: Model) -> Option<Correction> {
    let cols: Vec<usize> = (0..7).filter(|&k| model.uses()[k]).collect();
    let design = touches.design;
    if design.len() < cols.len() + 1 || design.len() != touches.measured.len() {
        return None;
    }
    let mut params = [0.0; 7];
    for _ in 0..3 {
        let c = Correction {
            model,
            max_residual_mm: 0.0,
            points: design.len(),
            frame,
            params,
        };
        let moved: Vec<DesignPoint> = design.iter().map(|d| c.apply(d)).collect();
        let a = DMatrix::from_fn(design.len(), cols.len(), |i, j| {
            frame.basis(moved[i].point, moved[i].normal)[cols[j]].dot(&moved[i].normal)
        });
        let b = DVector::from_fn(design.len(), |i, _| touches.gap(&c, i).unwrap_or(0.0));
        let step = visible_step(a, &b, |j| {
            let field = moved
                .iter()
                .map(|m| frame.basis(m.point, m.normal)[cols[j]]);
            field.map(|v| v.norm_squared()).sum::<f64>().sqrt()
        })?;
        for (j, &k) in cols.iter().enumerate() {
            params[k] += step[j];
        }
    }
    let mut c = Correction {
        model,
        max_residual_mm: 0.0,
        points: design.len(),
        frame,
        params,
    };
    c.max_residual_mm = (0..design.len())
        .filter_map(|i| touches.gap(&c, i))
        .map(f64::abs)
        .fold(0.0, f64::max);
    Some(c)
}

/// The least share of a combination of the basis motions that shows in
/// the touch points' gaps along their normals (the singular values of the
/// gap matrix with each motion scaled to unit displacement over the
/// points) for it to be fitted: a motion the gaps cannot see (sliding
/// along a straight wall, or any motion in the plane of a section that
/// grazes its surface) would otherwise take any size the rounding of the
/// gaps gives it, moving the design by metres.
const MIN_VISIBLE_SHARE: f64 = 1e-2;

/// The least-squares step of the gaps `b` by the columns of `a`, each
/// scaled by `displacement(j)` (the norm over the points of its motion's
/// displacement), leaving at zero every combination of motions less than
/// [`MIN_VISIBLE_SHARE`] of which shows in the gaps.
fn visible_step(
    mut a: DMatrix<f64>,
    b: &DVector<f64>,
    displacement: impl Fn(usize) -> f64,
) -> Option<DVector<f64>> {
    let scale: Vec<f64> = (0..a.ncols())
        .map(|j| displacement(j).max(1e-300))
        .collect();
    for (j, s) in scale.iter().enumerate() {
        a.column_mut(j).unscale_mut(*s);
    }
    let step = a.svd(true, true).solve(b, MIN_VISIBLE_SHARE).ok()?;
    Some(DVector::from_fn(step.len(), |j, _| step[j] / scale[j]))
}

impl Correction {
    /// The rigid part of the correction in the part frame, `(R, t)`: its
    /// turn about the section plane's normal and its translation, so that
    /// a point `p` moves to `R p + t` but for the scales and the offset
    /// (which change the section's size, not where it stands).
    pub fn rigid(&self) -> (Mat3, Vec3) {
        let [_, tx, ty, rot, ..] = self.params;
        let f = &self.frame;
        let axis = nalgebra::Unit::new_normalize(f.plane_normal());
        let r = *nalgebra::Rotation3::from_axis_angle(&axis, rot).matrix();
        let shift = f.e1 * tx + f.e2 * ty;
        (r, f.c.coords - r * f.c.coords + shift)
    }

    /// The corrected design point.
    pub fn apply(&self, d: &DesignPoint) -> DesignPoint {
        let [h, tx, ty, rot, s, sx, sy] = self.params;
        let f = &self.frame;
        let r = d.point - f.c;
        let (a, b) = (r.dot(&f.e1), r.dot(&f.e2));
        let w = r - f.e1 * a - f.e2 * b;
        let (ka, kb) = ((1.0 + s) * (1.0 + sx), (1.0 + s) * (1.0 + sy));
        let (cr, sr) = (rot.cos(), rot.sin());
        let (a2, b2) = (ka * a, kb * b);
        let (a3, b3) = (cr * a2 - sr * b2, sr * a2 + cr * b2);
        // Normals: inverse-transpose of the in-plane scale, then the rotation.
        let (na, nb) = (d.normal.dot(&f.e1) / ka, d.normal.dot(&f.e2) / kb);
        let nw = d.normal - f.e1 * d.normal.dot(&f.e1) - f.e2 * d.normal.dot(&f.e2);
        let normal = (f.e1 * (cr * na - sr * nb) + f.e2 * (sr * na + cr * nb) + nw)
            .try_normalize(1e-12)
            .unwrap_or(d.normal);
        let point = f.c + f.e1 * (a3 + tx) + f.e2 * (b3 + ty) + w + f.offset_along(normal) * h;
        DesignPoint { point, normal }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight wall along x in the section plane z = 0, its normals
    /// along y but for a tilt of a few nanoradians (as a wall's normals
    /// are on real CAD faces), touched with gaps of 0.3 mm plus a
    /// ±0.01 mm spread: a translation along the wall and a scale about
    /// the points' centroid barely show in the gaps, and must not be
    /// fitted to the spread.
    fn straight_wall() -> (Vec<DesignPoint>, Vec<Point3>) {
        (0..16)
            .map(|i| {
                let x = i as f64 * 2.0;
                let tilt = 1e-9 * ((i * 7) % 5) as f64;
                let normal = Vec3::new(tilt, 1.0, 0.0).normalize();
                let d = DesignPoint {
                    point: Point3::new(x, 0.0, 0.0),
                    normal,
                };
                let gap = 0.3 + 0.01 * if i % 2 == 0 { 1.0 } else { -1.0 };
                (d, d.point + normal * gap)
            })
            .unzip()
    }

    #[test]
    fn motions_the_gaps_cannot_see_are_not_fitted() {
        let (design, measured) = straight_wall();
        let frame = Frame::of(&design, Vec3::z());
        let curvature = vec![0.0; design.len()];
        let touches = Touches {
            design: &design,
            curvature: &curvature,
            measured: &measured,
        };
        for model in Model::MENU {
            let c = fit_model(touches, frame, model).expect("fits");
            // Every design point moves by the gap along its normal (0.3
            // mm, the spread evened out), not along the wall.
            for d in &design {
                let moved = c.apply(d).point - d.point;
                assert!(moved.norm() < 0.32, "{model:?}: {moved:?}");
                assert!((moved.dot(&d.normal) - 0.3).abs() < 0.02, "{model:?}");
            }
        }
    }

    /// A drafted bore (a cone, 7 degrees off the section plane's normal,
    /// radius 20 mm in the plane z = 0) whose true wall lies 0.3 mm off
    /// the design along its normal, touched along the design normals: the
    /// offset moves the section to the true cone's section, the circle of
    /// radius 20 - 0.3 / cos 7 degrees in the same plane (along the
    /// normal it would leave the plane by 0.3 sin 7 degrees, 37 um).
    #[test]
    fn an_offset_of_a_drafted_wall_keeps_the_section_in_its_plane() {
        let (radius, h, draft) = (20.0f64, 0.3, 7f64.to_radians());
        let design: Vec<DesignPoint> = (0..32)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 32.0;
                let radial = Vec3::new(a.cos(), a.sin(), 0.0);
                let normal = -radial * draft.cos() + Vec3::z() * draft.sin();
                DesignPoint {
                    point: Point3::from(radial * radius),
                    normal,
                }
            })
            .collect();
        let measured: Vec<Point3> = design.iter().map(|d| d.point + d.normal * h).collect();
        let curvature: Vec<f64> = (0..design.len())
            .map(|i| section_curvature(&design, i))
            .collect();
        let touches = Touches {
            design: &design,
            curvature: &curvature,
            measured: &measured,
        };
        let c = fit_correction(touches, Vec3::z(), (0.05, 0.5)).expect("fits");
        assert_eq!(c.model, Model::Offset);
        let want = radius - h / draft.cos();
        for d in &design {
            let p = c.apply(d).point;
            assert!(p.z.abs() < 1e-9, "{p:?} off the plane");
            assert!((p.coords.xy().norm() - want).abs() < 1e-6, "{p:?}");
        }
    }

    /// A bore of radius 18 (material outside, the outward normals towards
    /// its axis) and a boss of radius 31 (normals outwards) in the plane
    /// z = 0, moved 4.5 mm along y, touched at 16 points along their
    /// nominal normals: the measured points are where those normal lines
    /// meet the moved circle (solved here in closed form). The correction
    /// is the translation (0, 4.5) with residuals of micrometres, not the
    /// t^2 / 2R a gap to each point's tangent would leave (0.56 mm on the
    /// bore, past a 0.25 mm threshold). Moved 0.2 mm, less than the
    /// threshold, the offset (which leaves all 0.2 mm of the error) is no
    /// correction: the translation is.
    #[test]
    fn a_circle_moved_sideways_is_corrected_by_its_translation() {
        let cases = [
            (4.5, 18.0f64, true),
            (4.5, 31.0, false),
            (0.2, 18.0, true),
            (0.2, 3.5, true),
        ];
        for (shift_y, radius, inward) in cases {
            let shift = Vec3::new(0.0, shift_y, 0.0);
            let n = 64;
            let design: Vec<DesignPoint> = (0..n)
                .map(|k| {
                    let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                    let radial = Vec3::new(a.cos(), a.sin(), 0.0);
                    let normal = if inward { -radial } else { radial };
                    DesignPoint {
                        point: Point3::from(radial * radius),
                        normal,
                    }
                })
                .collect();
            let picks: Vec<usize> = (0..16).map(|k| k * 4).collect();
            let touched: Vec<DesignPoint> = picks.iter().map(|&i| design[i]).collect();
            let curvature: Vec<f64> = picks
                .iter()
                .map(|&i| section_curvature(&design, i))
                .collect();
            // p + s n on the circle |x - shift| = radius: the root of
            // s^2 + 2 s (p - shift).n + |p - shift|^2 - radius^2 = 0
            // nearer zero.
            let measured: Vec<Point3> = (touched.iter())
                .map(|d| {
                    let q = d.point.coords - shift;
                    let b = q.dot(&d.normal);
                    let c = q.norm_squared() - radius * radius;
                    let root = (b * b - c).sqrt();
                    let s = [-b + root, -b - root]
                        .into_iter()
                        .min_by(|x, y| x.abs().total_cmp(&y.abs()))
                        .unwrap();
                    d.point + d.normal * s
                })
                .collect();
            let touches = Touches {
                design: &touched,
                curvature: &curvature,
                measured: &measured,
            };
            let c = fit_correction(touches, Vec3::z(), (0.25, 0.5)).expect("a correction");
            assert_eq!(c.model, Model::Translation, "radius {radius}: {c:?}");
            assert!(
                c.max_residual_mm < 0.02,
                "radius {radius}: {}",
                c.max_residual_mm
            );
            let moved = c.apply(&design[0]).point - design[0].point;
            assert!((moved - shift).norm() < 0.02, "radius {radius}: {moved:?}");
        }
    }

    /// A turn of 3 degrees about a tilted section plane's normal and a
    /// translation in it: the rigid part moves every design point where
    /// the correction does (no scale, no offset), and keeps points on the
    /// plane's normal through the centroid turning about it.
    #[test]
    fn the_rigid_part_moves_points_as_the_correction_does() {
        let normal = Vec3::new(0.2, -0.1, 1.0).normalize();
        let e = any_perp(normal);
        let design: Vec<DesignPoint> = (0..12)
            .map(|k| {
                let a = k as f64 * 0.5;
                let radial = e * a.cos() + normal.cross(&e) * (2.0 * a).sin();
                DesignPoint {
                    point: Point3::new(5.0, -3.0, 7.0) + radial * 20.0,
                    normal: radial.normalize(),
                }
            })
            .collect();
        let c = Correction {
            model: Model::Rigid,
            max_residual_mm: 0.0,
            points: design.len(),
            frame: Frame::of(&design, normal),
            params: [0.0, 0.7, -1.3, 3f64.to_radians(), 0.0, 0.0, 0.0],
        };
        let (r, t) = c.rigid();
        for d in &design {
            let by_rigid = r * d.point.coords + t;
            assert!((by_rigid - c.apply(d).point.coords).norm() < 1e-12);
        }
        let turn = r * normal;
        assert!((turn - normal).norm() < 1e-12, "{turn:?}");
    }
}
