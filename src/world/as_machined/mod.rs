//! The as-machined part (the as-machined format), known only to the simulated world:
//! for a nominal point `p` with outward normal `n`,
//! `q(p) = T(p + h(p) n(p))` with `h` the sum of the form terms and `T` an
//! affine transform. Distances to it are exact to the Newton tolerance
//! (far below 0.1 um), using exact second derivatives of `q` (which need the
//! third derivatives of the NURBS).

mod affine;
pub mod form;
mod normal_jet;
mod trimmed;
mod validate;
#[cfg(test)]
mod walk_tests;

pub use crate::formats::as_machined::{AsMachinedSpec, FormTerm, Scale, TransformSpec};
use crate::geometry::projection::{Bounds, Foot, WarmStart};
use crate::geometry::{Jet2, ProjectionError, ProjectionOptions, SurfaceDerivs};
use crate::math::{Mat3, Point3, Vec2, Vec3};
use crate::workpiece::{FootHint, Workpiece};
use affine::Affine;
use form::Form;
use validate::{err, faces_of, form_of, transform};

/// Why an `as_machined` block is invalid; `json_path` is relative to it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{json_path}: {reason}")]
pub struct AsMachinedError {
    /// Path inside the `as_machined` object, e.g. `form[1].radius_mm`.
    pub json_path: String,
    /// What is wrong.
    pub reason: String,
}

/// Below this value of `|Qu x Qv| / (|Qu| |Qv|)` (the sine of the angle
/// between the tangents) the as-machined normal comes from the nominal one.
const NORMAL_CONDITION: f64 = 1e-6;

/// Below this ratio of the shorter tangent `|Qu|` or `|Qv|` to the longer
/// the foot lies next to a collapsed edge (a pole): the short tangent is
/// then mostly rounding error (and the form's normal derivatives there
/// are of no use), so the normal comes from the nominal limit normal.
const TANGENT_RATIO: f64 = 1e-6;

/// The true (simulated) part.
#[derive(Debug, Clone, PartialEq)]
pub struct AsMachined {
    /// The transform `T`.
    affine: Affine,
    /// Form terms with the faces they act on (`None` = all).
    terms: Vec<(Form, Option<Vec<usize>>)>,
    /// Roughness standard deviation, mm.
    pub roughness_mm: f64,
    /// The contact search's split of the design, shared by the part's
    /// copies (its variants).
    pub(crate) pieces: crate::world::contact::PieceCache,
}

/// How far the true part's seeds are sought beyond the nominal distance
/// `d` (see [`AsMachined::seed_reach`]).
#[derive(Debug, Clone, Copy)]
pub struct SeedReach<'a> {
    part: &'a AsMachined,
    stretch: f64,
    /// Twice the largest form height over all faces, stretched, mm.
    widest: f64,
}

/// Added to the seeds' reach, relative to `1 + d` (`d` the nominal
/// distance, mm), so that Newton's tolerance cannot drop a seed.
const SEED_REACH_SLACK: f64 = 1e-6;

/// `best` widened by `extra` (mm) and [`SEED_REACH_SLACK`].
#[inline(always)]
fn widened(best: f64, extra: f64) -> f64 {
    best + (extra + SEED_REACH_SLACK * (1.0 + best))
}

impl crate::workpiece::Reach for SeedReach<'_> {
    fn of(&self, face: usize, best: f64) -> f64 {
        widened(best, 2.0 * self.part.max_height(face) * self.stretch)
    }

    fn cap(&self, best: f64) -> f64 {
        // A relative hair above the widest face's reach, for rounding.
        widened(best, self.widest) * (1.0 + 1e-12)
    }
}

/// The closest point on the as-machined surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrueProjection {
    /// Face index.
    pub face: usize,
    /// Nominal parameters of the face that map to the foot point.
    pub uv: Vec2,
    /// Foot point on the true surface.
    pub point: Point3,
    /// Unit outward normal of the true surface there.
    pub normal: Vec3,
    /// Distance from the query point, mm.
    pub distance: f64,
    /// Distance signed by `(query - foot) . normal`, mm.
    pub signed_distance: f64,
}

impl AsMachined {
    /// The nominal part itself (no transform, no form, no roughness).
    pub fn nominal() -> AsMachined {
        AsMachined {
            affine: Affine::identity(),
            terms: Vec::new(),
            roughness_mm: 0.0,
            pieces: Default::default(),
        }
    }

    /// Validates a spec against the workpiece's surface names.
    pub fn from_spec(spec: &AsMachinedSpec, wp: &Workpiece) -> Result<AsMachined, AsMachinedError> {
        let (linear, offset) = match &spec.transform {
            Some(t) => transform(t)?,
            None => (Mat3::identity(), Vec3::zeros()),
        };
        let terms = spec
            .form
            .iter()
            .enumerate()
            .map(|(i, t)| Ok((form_of(t, i)?, faces_of(t, i, wp)?)))
            .collect::<Result<Vec<_>, AsMachinedError>>()?;
        let r = spec.roughness_um;
        if !(r.is_finite() && r >= 0.0) {
            return Err(err(
                "roughness_um",
                format!("{r} must be a finite non-negative number"),
            ));
        }
        Ok(AsMachined {
            affine: Affine::new(linear, offset),
            terms,
            roughness_mm: r * 1e-3,
            pieces: Default::default(),
        })
    }

    /// A random variant of this part (another part from the same machine
    /// tool): every form term's size scaled by a factor in [0.9, 1.1] and the
    /// transform's translation moved by up to 0.02 mm, drawn from `seed`.
    pub fn variant(&self, seed: u64) -> AsMachined {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(seed);
        let mut out = self.clone();
        for (form, _) in out.terms.iter_mut() {
            let k = 0.9 + 0.2 * rng.random::<f64>();
            form.scale_size(k);
        }
        let delta = Vec3::new(
            rng.random::<f64>(),
            rng.random::<f64>(),
            rng.random::<f64>(),
        )
        .map(|c| (c - 0.5) * 0.04);
        out.affine = self.affine.moved(delta);
        out
    }

    /// The same part without roughness (`--ideal`).
    pub fn without_roughness(mut self) -> AsMachined {
        self.roughness_mm = 0.0;
        self
    }

    /// Maps a nominal point to machine... to the true part: `T(x)`.
    pub fn transform_point(&self, x: Point3) -> Point3 {
        self.affine.apply(x)
    }

    /// Sum of the form terms acting on `face` at the nominal point `p`, mm.
    pub fn form_height(&self, face: usize, p: Point3) -> f64 {
        self.face_terms(face).map(|f| f.value(p)).sum()
    }

    fn face_terms(&self, face: usize) -> impl Iterator<Item = &Form> + Clone + '_ {
        self.terms
            .iter()
            .filter(move |(_, faces)| faces.as_ref().is_none_or(|fs| fs.contains(&face)))
            .map(|(f, _)| f)
    }

    /// Upper bound of |h| on `face`, mm.
    fn max_height(&self, face: usize) -> f64 {
        self.face_terms(face).map(Form::amplitude).sum()
    }

    /// The true point for nominal parameters `uv` of `face`.
    pub fn true_point(&self, wp: &Workpiece, face: usize, uv: Vec2) -> Point3 {
        self.derivs(wp, face, uv, 0).point()
    }

    /// `q(u, v)` and its derivatives to order `nd` (0 or 2) on `face`.
    pub fn derivs(&self, wp: &Workpiece, face: usize, uv: Vec2, nd: usize) -> SurfaceDerivs {
        let Some(f) = wp.faces.get(face) else {
            return SurfaceDerivs {
                d: [[Vec3::zeros(); 4]; 4],
            };
        };
        let g = if self.face_terms(face).next().is_none() {
            f.surface.derivs(uv.x, uv.y, nd)
        } else {
            normal_jet::displaced(&f.surface, self.face_terms(face), uv, nd).into()
        };
        self.apply_linear(g)
    }

    /// `q(u, v)` with its derivatives to second order on `face` (the
    /// Newton iterations' evaluation), written into `out`. Point and first
    /// derivatives are exact; the second derivatives keep only the normal
    /// part of the normal's curvature terms ([`normal_jet::Second::NormalPart`]): the
    /// Newton gradient, and so the foot, stays exact.
    fn jet_into(&self, wp: &Workpiece, face: usize, uv: Vec2, out: &mut Jet2) {
        let Some(f) = wp.faces.get(face) else {
            out.d = [Vec3::zeros(); 6];
            return;
        };
        if self.face_terms(face).next().is_none() {
            f.surface.jet2_into(uv.x, uv.y, out);
        } else {
            normal_jet::displaced_jet_into(&f.surface, self.face_terms(face), uv, out);
        }
        if !self.affine.is_identity() {
            *out = out.mapped(self.affine.linear(), self.affine.offset());
        }
    }

    fn apply_linear(&self, mut g: SurfaceDerivs) -> SurfaceDerivs {
        for row in g.d.iter_mut() {
            for v in row.iter_mut() {
                *v = self.affine.linear() * *v;
            }
        }
        g.d[0][0] += self.affine.offset();
        g
    }

    /// Warm closest point: Newton on `face` from `uv`; falls back to the cold
    /// search when the foot ends on the face boundary.
    pub fn closest_point_from(
        &self,
        wp: &Workpiece,
        x: Point3,
        face: usize,
        uv: Vec2,
    ) -> Result<TrueProjection, ProjectionError> {
        let mut warm = TrueWarm::new(face, uv);
        self.closest_point_along(wp, x, &mut warm, &wp.options)
    }

    /// Warm closest point along a path (one query per control cycle): Newton
    /// from `warm` (the previous foot and its derivatives), which is moved to
    /// the new foot; falls back to the cold search when the foot ends on the
    /// face boundary.
    pub fn closest_point_along(
        &self,
        wp: &Workpiece,
        x: Point3,
        warm: &mut TrueWarm,
        opts: &ProjectionOptions,
    ) -> Result<TrueProjection, ProjectionError> {
        let face = warm.face;
        let bounds = face_bounds(wp, face, x)?;
        let foot = warm.start.run(
            |p, out: &mut Jet2| self.jet_into(wp, face, p, out),
            x,
            &bounds,
            opts,
        )?;
        if on_boundary(wp, face, foot.uv) {
            let tp = self.closest_point_seeded(wp, x, &mut warm.seeds)?;
            *warm = TrueWarm::seeded(tp.face, tp.uv, warm.seeds);
            return Ok(tp);
        }
        Ok(self.finish(wp, x, face, foot))
    }

    /// Cold closest point over all faces. Seeds come from the nominal
    /// projection of `T^-1(x)` on every face that could hold the answer.
    pub fn closest_point(
        &self,
        wp: &Workpiece,
        x: Point3,
    ) -> Result<TrueProjection, ProjectionError> {
        self.closest_point_near(wp, x, None).map(|(tp, _)| tp)
    }

    /// [`Self::closest_point`] with the nominal search started from `seeds`
    /// (where an earlier query's nominal foot lay, such as the control
    /// cycle before), which is moved to this query's nominal foot; none:
    /// the cold search, whose foot seeds the next query. The answer is the
    /// same (the search trees confirm the nominal foot, and every face
    /// within the seed reach is searched).
    pub fn closest_point_seeded(
        &self,
        wp: &Workpiece,
        x: Point3,
        seeds: &mut Option<FootHint>,
    ) -> Result<TrueProjection, ProjectionError> {
        if seeds.is_none() {
            let tp = self.closest_point(wp, x)?;
            *seeds = Some(FootHint::at(tp.face, tp.uv));
            return Ok(tp);
        }
        let y = self.inverse_point(x);
        let foot = wp.closest_point_tracked(y, 0..wp.faces.len(), seeds)?;
        self.closest_point_tracked(wp, x, Some((y, &foot)), seeds)
    }

    /// [`Self::closest_point`] near an earlier query: `near` is a nominal
    /// foot found nearby, where the nominal searches start (taken as it is
    /// when its query is `T^-1(x)` itself). The answer is the same. Also
    /// returns where the nominal foot of `T^-1(x)` lies, for nearby queries.
    pub fn closest_point_near(
        &self,
        wp: &Workpiece,
        x: Point3,
        near: Option<&crate::workpiece::KnownFoot>,
    ) -> Result<(TrueProjection, Option<crate::workpiece::FootHint>), ProjectionError> {
        let mut hint = near.and_then(|k| k.hint);
        let known = near.map(|k| (k.query, &k.foot));
        let tp = self.closest_point_tracked(wp, x, known, &mut hint)?;
        Ok((tp, hint))
    }

    /// [`Self::closest_point_near`] with `known`, the global nominal foot
    /// of a query point found with `hint`, and `hint` moved in place to the
    /// nominal foot of `T^-1(x)`.
    pub fn closest_point_tracked(
        &self,
        wp: &Workpiece,
        x: Point3,
        known: Option<(Point3, &crate::workpiece::FaceProjection)>,
        hint: &mut Option<crate::workpiece::FootHint>,
    ) -> Result<TrueProjection, ProjectionError> {
        let y = self.inverse_point(x);
        let mut best: Option<TrueProjection> = None;
        wp.for_feet_within_reach(y, known, hint, &self.seed_reach(), |face, uv| {
            let foot = self.newton(wp, x, face, uv)?;
            if best.is_none_or(|b| foot.dist2.sqrt() < b.distance) {
                best = Some(self.finish(wp, x, face, &foot));
            }
            Ok(())
        })?;
        best.ok_or(ProjectionError::NotFinite {
            x: x.x,
            y: x.y,
            z: x.z,
        })
    }

    /// How far from `T^-1(x)` the true closest point's seeds are sought:
    /// on face `i`, within `reach(i, d)` of it, `d` its nominal distance
    /// (the form moves a face by at most max|h|, stretched by T).
    pub fn seed_reach(&self) -> SeedReach<'_> {
        let stretch = self.stretch();
        // Every face's terms are among all terms: their amplitudes (never
        // negative) sum to no more, rounding included.
        let all = self.terms.iter().map(|(f, _)| f.amplitude()).sum::<f64>();
        SeedReach {
            part: self,
            stretch,
            widest: 2.0 * all * stretch,
        }
    }

    /// Largest factor by which `T` stretches lengths.
    fn stretch(&self) -> f64 {
        self.affine.stretch()
    }

    fn inverse_point(&self, x: Point3) -> Point3 {
        self.affine.inverse_point(x)
    }

    fn newton(
        &self,
        wp: &Workpiece,
        x: Point3,
        face: usize,
        uv: Vec2,
    ) -> Result<Foot, ProjectionError> {
        let bounds = face_bounds(wp, face, x)?;
        self.trimmed_newton(wp, x, face, uv, &bounds)
    }

    #[inline(always)]
    fn finish(&self, wp: &Workpiece, x: Point3, face: usize, foot: &Foot) -> TrueProjection {
        let sign = wp
            .faces
            .get(face)
            .map_or(1.0, |f| if f.surface.is_reversed() { -1.0 } else { 1.0 });
        let (qu, qv) = (foot.d.su(), foot.d.sv());
        let n = qu.cross(&qv) * sign;
        // Near a pole Qu x Qv is ill-conditioned: use the nominal limit normal
        // mapped by the transform (inverse transpose) instead.
        let (lu, lv) = (qu.norm(), qv.norm());
        let well_posed = n.norm() > NORMAL_CONDITION * lu * lv
            && n.norm() > 0.0
            && lu.min(lv) > TANGENT_RATIO * lu.max(lv);
        let normal = if well_posed {
            n.normalize()
        } else {
            wp.faces.get(face).map_or(Vec3::z(), |f| {
                let nominal = f.surface.normal(foot.uv.x, foot.uv.y);
                let linear = self.affine.linear();
                let inv_t = linear.try_inverse().map_or(*linear, |m| m.transpose());
                (inv_t * nominal).try_normalize(1e-300).unwrap_or(nominal)
            })
        };
        let point = foot.d.point();
        let distance = foot.dist2.sqrt();
        let signed = if (x - point).dot(&normal) < 0.0 {
            -distance
        } else {
            distance
        };
        TrueProjection {
            face,
            uv: foot.uv,
            point,
            normal,
            distance,
            signed_distance: signed,
        }
    }

    /// The true deviation belonging to a measured point `m`: the signed
    /// nominal deviation of the true surface point nearest to `m`.
    pub fn true_deviation(&self, wp: &Workpiece, m: Point3) -> Result<f64, ProjectionError> {
        self.true_deviation_near(wp, m, None)
    }

    /// [`Self::true_deviation`] with its nominal searches started from
    /// `near`, a nominal foot found near `m` (such as that of `m` itself);
    /// the answer is the same.
    pub fn true_deviation_near(
        &self,
        wp: &Workpiece,
        m: Point3,
        near: Option<&crate::workpiece::KnownFoot>,
    ) -> Result<f64, ProjectionError> {
        let mut hint = near.and_then(|k| k.hint);
        let known = near.map(|k| (k.query, &k.foot));
        self.true_deviation_tracked(wp, m, known, &mut hint)
    }

    /// [`Self::true_deviation_near`] with `known`, the global nominal foot
    /// of a query point (such as `m`) found with `hint`, and `hint` moved
    /// in place to the nominal foot of the true point.
    pub fn true_deviation_tracked(
        &self,
        wp: &Workpiece,
        m: Point3,
        known: Option<(Point3, &crate::workpiece::FaceProjection)>,
        hint: &mut Option<crate::workpiece::FootHint>,
    ) -> Result<f64, ProjectionError> {
        // With a transform `T` the true point's nominal parameters are
        // those of a point moved by `T`; the true point lies near `m`, so
        // its nominal foot lies near that of `m` (`known`, when it is that
        // of `m`), found with `hint`.
        let moved = !self.affine.is_identity() && known.is_some_and(|k| k.0 == m);
        let earlier = (*hint).filter(|_| moved);
        let tp = self.closest_point_tracked(wp, m, known, hint)?;
        // The nominal foot of the true point, started from the nominal
        // parameters of that point (its foot when `T` is the identity),
        // or with a transform from the nominal foot of `m`.
        match hint.as_mut() {
            Some(h) => h.restart_near(tp.face, tp.uv, earlier.as_ref()),
            None => *hint = Some(crate::workpiece::FootHint::at(tp.face, tp.uv)),
        }
        let found = wp.closest_point_tracked(tp.point, 0..wp.faces.len(), hint)?;
        Ok(found.projection.signed_distance)
    }
}

/// Where a warm true closest-point search starts: a face and the state of
/// its Newton iteration, and where the nominal searches of its cold
/// fallback start ([`AsMachined::closest_point_seeded`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrueWarm {
    face: usize,
    start: WarmStart,
    /// The nominal foot of the last cold search, if any.
    pub seeds: Option<FootHint>,
}

impl TrueWarm {
    /// A start at nominal parameters `uv` of `face` (with no seeds).
    pub fn new(face: usize, uv: Vec2) -> TrueWarm {
        Self::seeded(face, uv, None)
    }

    /// A start at nominal parameters `uv` of `face` whose cold fallback
    /// starts its nominal searches from `seeds`.
    pub fn seeded(face: usize, uv: Vec2, seeds: Option<FootHint>) -> TrueWarm {
        TrueWarm {
            face,
            start: WarmStart::new(uv),
            seeds,
        }
    }
}

/// The parameter box of `face` (an unknown face is reported for `x`).
fn face_bounds(wp: &Workpiece, face: usize, x: Point3) -> Result<Bounds, ProjectionError> {
    let Some(f) = wp.faces.get(face) else {
        return Err(ProjectionError::NotFinite {
            x: x.x,
            y: x.y,
            z: x.z,
        });
    };
    let ((u0, u1), (v0, v1)) = f.surface.domain();
    Ok(Bounds {
        lo: Vec2::new(u0, v0),
        hi: Vec2::new(u1, v1),
    })
}

fn on_boundary(wp: &Workpiece, face: usize, uv: Vec2) -> bool {
    wp.faces.get(face).is_none_or(|f| {
        let ((u0, u1), (v0, v1)) = f.surface.domain();
        uv.x <= u0 || uv.x >= u1 || uv.y <= v0 || uv.y >= v1
    })
}
