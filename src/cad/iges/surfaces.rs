//! IGES surfaces in model space (mm): 128 rational B-splines, 118 ruled
//! surfaces, 120 surfaces of revolution, 122 tabulated cylinders, 108
//! bounded planes and the 190 / 192 / 194 / 196 / 198 analytic surfaces with
//! their 116 point and 123 direction entities.
use super::curves::{pieces, Piece};
use super::entities::{Affine, Fields, Model};
use super::records::Entry;
use super::ruled::{restrict, ruled};
use crate::cad::convert::analytic::{Analytic, AxisMap, NaturalSurface};
use crate::cad::convert::arc::Arc;
use crate::cad::convert::revolve::{extrude, revolve, Profile};
use crate::cad::error::CadResult;
use crate::cad::geom::{Curve, Frame};
use crate::cad::nurbs::NurbsCurve;
use crate::formats::workpiece::SurfaceSpec;
use crate::math::{Point3, Vec3};
use std::f64::consts::{FRAC_PI_2, TAU};

/// A surface entity converted to model space.
#[derive(Debug, Clone, PartialEq)]
pub enum Surf {
    /// Plane, cylinder, cone, sphere or torus.
    Analytic(Analytic),
    /// 120: `profile` revolved about the frame's z axis over `angles` (rad).
    Revolution {
        /// Axis frame (origin on the axis, z along it).
        frame: Frame,
        /// The generatrix.
        profile: NurbsCurve,
        /// Start and terminate angles.
        angles: (f64, f64),
    },
    /// 122: the directrix swept along `dir` (unit) over `[0, length]`.
    Extrusion {
        /// The directrix.
        profile: NurbsCurve,
        /// Unit generatrix direction.
        dir: Vec3,
        /// Generatrix length, mm.
        length: f64,
    },
    /// 128 (parameter range `[u0, u1, v0, v1]`) or 118 (over `[0, 1]^2`).
    Spline(SurfaceSpec, [f64; 4]),
}

/// Entity types this module converts.
pub const SURFACE_TYPES: [i64; 10] = [108, 118, 120, 122, 128, 190, 192, 194, 196, 198];

/// The surface entity `e` placed by `place` (parent's definition space to mm).
pub fn surface(m: &Model, e: &Entry, place: &Affine) -> CadResult<Surf> {
    let tr = place.then_inner(&m.transform(e)?);
    let f = m.fields(e)?;
    match e.kind {
        128 => surface128(&f, &tr).map(|(s, r)| Surf::Spline(s, r)),
        118 => ruled(m, &f, &tr).map(|s| Surf::Spline(s, [0.0, 1.0, 0.0, 1.0])),
        120 => revolution120(m, &f, &tr),
        122 => extrusion122(m, &f, &tr),
        108 => plane108(&f, &tr).map(Surf::Analytic),
        190..=198 => analytic(&f, &tr).map(Surf::Analytic),
        other => Err(m.err(e, format!("unsupported surface type {other}"))),
    }
}

impl Surf {
    /// The whole surface as NURBS, for surfaces used without a boundary.
    pub fn untrimmed(&self) -> Result<SurfaceSpec, String> {
        match self {
            Surf::Spline(s, _) => Ok(s.clone()),
            Surf::Revolution {
                frame,
                profile,
                angles: (a0, a1),
            } => Ok(revolve(
                frame,
                &Arc::new(*a0, *a1),
                &Profile::from_curve(frame, profile),
            )),
            Surf::Extrusion {
                profile,
                dir,
                length,
            } => Ok(extrude(profile, *dir, [0.0, *length])),
            Surf::Analytic(a @ Analytic::Sphere(..)) => {
                let maps = [
                    AxisMap::Angle(Arc::new(0.0, TAU)),
                    AxisMap::Angle(Arc::new(-FRAC_PI_2, FRAC_PI_2)),
                ];
                Ok(a.to_nurbs(&maps))
            }
            Surf::Analytic(a @ Analytic::Torus(..)) => {
                Ok(a.to_nurbs(&a.maps((0.0, TAU), (0.0, TAU))))
            }
            Surf::Analytic(_) => Err("unbounded analytic surface used without a boundary".into()),
        }
    }

    /// Short type name for reports.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Surf::Analytic(Analytic::Plane(_)) => "plane",
            Surf::Analytic(Analytic::Cylinder(..)) => "cylinder",
            Surf::Analytic(Analytic::Cone(..)) => "cone",
            Surf::Analytic(Analytic::Sphere(..)) => "sphere",
            Surf::Analytic(Analytic::Torus(..)) => "torus",
            Surf::Revolution { .. } => "surface of revolution",
            Surf::Extrusion { .. } => "tabulated cylinder",
            Surf::Spline(..) => "B-spline",
        }
    }
}

/// Entity 128 mapped by `tr` (mm); also returns the parameter range.
pub fn surface128(f: &Fields, tr: &Affine) -> CadResult<(SurfaceSpec, [f64; 4])> {
    let (k1, k2, m1, m2) = (f.count(1)?, f.count(2)?, f.count(3)?, f.count(4)?);
    let (n1, n2) = (k1 + 1, k2 + 1);
    let mut at = 10;
    let knots_u = f.take(&mut at, k1 + m1 + 2)?;
    let knots_v = f.take(&mut at, k2 + m2 + 2)?;
    let w = f.take(&mut at, n1 * n2)?;
    let xyz = f.take(&mut at, 3 * n1 * n2)?;
    let range: [f64; 4] = f
        .take(&mut at, 4)?
        .try_into()
        .map_err(|_| f.bad(at, "missing parameter range"))?;
    let point = |k: usize| {
        let c = |d: usize| xyz.get(3 * k + d).copied().unwrap_or(0.0);
        let p = tr.apply(Point3::new(c(0), c(1), c(2)));
        [p.x, p.y, p.z]
    };
    let weights = grid(n1, n2, |k| w.get(k).copied().unwrap_or(1.0));
    let rational = weights.iter().flatten().any(|x| *x != 1.0);
    let spec = SurfaceSpec {
        name: String::new(),
        degree: [m1, m2],
        knots_u,
        knots_v,
        control_points: grid(n1, n2, point),
        weights: rational.then_some(weights),
        reversed: false,
        trim: None,
    };
    crate::cad::step::surfaces::check_spline(&spec).map_err(|r| f.bad(1, &r))?;
    Ok((spec, range))
}

/// `out[i][j] = f(i + n1 j)`: IGES lists the first index fastest.
fn grid<T>(n1: usize, n2: usize, f: impl Fn(usize) -> T) -> Vec<Vec<T>> {
    (0..n1)
        .map(|i| (0..n2).map(|j| f(i + n1 * j)).collect())
        .collect()
}

/// A curve entity as one NURBS curve (lines over their segment, arcs over
/// their sweep, B-splines over their range).
pub fn curve_nurbs(m: &Model, f: &Fields, k: usize, tr: &Affine) -> CadResult<NurbsCurve> {
    let e = f.target(k)?;
    let ps = pieces(m, e, tr)?;
    let c = match ps.as_slice() {
        [Piece::Segment(a, b)] => line_nurbs(*a, *b),
        [Piece::Arc(Curve::Circle { frame, radius }, t0, t1)] => {
            arc_nurbs(frame, *radius, *t0, *t1)
        }
        [Piece::Arc(Curve::Nurbs(c), t0, t1)] => {
            let (lo, hi) = c.domain();
            if *t0 > lo || *t1 < hi {
                restrict(c, *t0, *t1)
            } else {
                Ok(c.clone())
            }
        }
        _ => Err("not a line, circular arc or B-spline curve".into()),
    };
    c.map_err(|r| f.bad(k, &format!("points to an unusable curve: {r}")))
}

fn line_nurbs(a: Point3, b: Point3) -> Result<NurbsCurve, String> {
    crate::cad::nurbs::new_curve(1, vec![0.0, 0.0, 1.0, 1.0], &[a, b], vec![1.0; 2])
        .map_err(|e| e.to_string())
}

/// The circle arc `[t0, t1]` as a rational quadratic B-spline (parameter = angle at the joints).
pub fn arc_nurbs(frame: &Frame, r: f64, t0: f64, t1: f64) -> Result<NurbsCurve, String> {
    let arc = Arc::new(t0, t1);
    let pts = arc.points();
    let points: Vec<Point3> = pts
        .iter()
        .map(|p| frame.world(r * p.c, r * p.s, 0.0))
        .collect();
    crate::cad::nurbs::new_curve(2, arc.knots(), &points, pts.iter().map(|p| p.w).collect())
        .map_err(|e| e.to_string())
}

fn revolution120(m: &Model, f: &Fields, tr: &Affine) -> CadResult<Surf> {
    let axis = f.target(1)?;
    let [o, end] = match pieces(m, axis, tr)?.as_slice() {
        [Piece::Segment(a, b)] => [*a, *b],
        _ => return Err(f.bad(1, "is not a line (110) axis")),
    };
    let frame = Frame::new(o, end - o, None).ok_or_else(|| f.bad(1, "is a zero-length axis"))?;
    let profile = curve_nurbs(m, f, 2, tr)?;
    let (a0, a1) = (f.real(3)?, f.real(4)?);
    if !(a1 > a0 && a1 - a0 <= TAU + 1e-9) {
        return Err(f.bad(
            3,
            "and the terminate angle do not give a sweep in (0, 2 pi]",
        ));
    }
    Ok(Surf::Revolution {
        frame,
        profile,
        angles: (a0, a1.min(a0 + TAU)),
    })
}

fn extrusion122(m: &Model, f: &Fields, tr: &Affine) -> CadResult<Surf> {
    let profile = curve_nurbs(m, f, 1, tr)?;
    let (lo, _) = profile.domain();
    let start = profile.point(lo);
    let end = tr.apply(Point3::new(f.real(2)?, f.real(3)?, f.real(4)?));
    let d = end - start;
    let length = d.norm();
    let dir = d
        .try_normalize(1e-12)
        .ok_or_else(|| f.bad(2, "gives a zero-length generatrix"))?;
    Ok(Surf::Extrusion {
        profile,
        dir,
        length,
    })
}

/// 108: `A x + B y + C z = D` (the boundary comes from the face).
fn plane108(f: &Fields, tr: &Affine) -> CadResult<Analytic> {
    let n = Vec3::new(f.real(1)?, f.real(2)?, f.real(3)?);
    let d = f.real(4)?;
    let len2 = n.norm_squared();
    if len2.is_nan() || len2 < 1e-24 {
        return Err(f.bad(1, "gives a zero plane normal"));
    }
    let o = Point3::from(n * (d / len2));
    let frame = Frame::new(tr.apply(o), tr.vector(n), None)
        .ok_or_else(|| f.bad(1, "gives a degenerate plane"))?;
    Ok(Analytic::Plane(frame))
}

/// A 116 point mapped by `tr` and its own transformation.
fn point116(f: &Fields, k: usize, tr: &Affine) -> CadResult<Point3> {
    let m = f.model();
    let e = f.target(k)?;
    if e.kind != 116 {
        return Err(f.bad(
            k,
            &format!("points to entity {} (expected a 116 point)", e.kind),
        ));
    }
    let own = tr.then_inner(&m.transform(e)?);
    let g = m.fields(e)?;
    Ok(own.apply(Point3::new(g.real(1)?, g.real(2)?, g.real(3)?)))
}

/// A 123 direction mapped by the linear part of `tr` and its own transformation.
fn direction123(f: &Fields, k: usize, tr: &Affine) -> CadResult<Vec3> {
    let m = f.model();
    let e = f.target(k)?;
    if e.kind != 123 {
        return Err(f.bad(
            k,
            &format!("points to entity {} (expected a 123 direction)", e.kind),
        ));
    }
    let own = tr.then_inner(&m.transform(e)?);
    let g = m.fields(e)?;
    own.vector(Vec3::new(g.real(1)?, g.real(2)?, g.real(3)?))
        .try_normalize(1e-12)
        .ok_or_else(|| g.bad(1, "is a zero direction"))
}

fn optional_direction(f: &Fields, k: usize, tr: &Affine) -> CadResult<Option<Vec3>> {
    if f.entry.form == 0 || k >= f.len() || f.int(k).ok() == Some(0) {
        return Ok(None);
    }
    direction123(f, k, tr).map(Some)
}

/// 190 plane, 192 cylinder, 194 cone, 196 sphere, 198 torus.
fn analytic(f: &Fields, tr: &Affine) -> CadResult<Analytic> {
    let s = tr.scale();
    let loc = point116(f, 1, tr)?;
    let frame = |axis: Vec3, refk: usize| {
        Frame::new(loc, axis, optional_direction(f, refk, tr)?)
            .ok_or_else(|| f.bad(2, "gives a degenerate placement"))
    };
    let positive = |k: usize| -> CadResult<f64> {
        let r = f.real(k)?;
        (r > 0.0)
            .then_some(r * s)
            .ok_or_else(|| f.bad(k, "is not a positive radius"))
    };
    Ok(match f.entry.kind {
        190 => Analytic::Plane(frame(direction123(f, 2, tr)?, 3)?),
        192 => Analytic::Cylinder(frame(direction123(f, 2, tr)?, 4)?, positive(3)?),
        194 => {
            let semi = f.real(4)?.to_radians();
            if !(semi > 0.0 && semi < FRAC_PI_2) {
                return Err(f.bad(4, "is not a cone semi-angle in (0, 90) degrees"));
            }
            Analytic::Cone(
                frame(direction123(f, 2, tr)?, 5)?,
                f.real(3)?.abs() * s,
                semi,
            )
        }
        196 => {
            let axis = match optional_direction(f, 3, tr)? {
                Some(a) => a,
                None => tr.vector(Vec3::z()),
            };
            Analytic::Sphere(frame(axis, 4)?, positive(2)?)
        }
        _ => {
            let (big, small) = (positive(3)?, positive(4)?);
            Analytic::Torus(frame(direction123(f, 2, tr)?, 5)?, big, small)
        }
    })
}
