//! Trims of B-spline faces without usable PCURVEs: the face's 3-D edges are
//! sampled and projected onto the surface with the geometry kernel (cold
//! search for the first sample of an edge, warm Newton from the previous
//! (u, v) for the rest), refined in (u, v) until the parameter polyline maps
//! back onto the edge, and unwrapped across the seams of closed directions.
use super::access::Ctx;
use super::pcurves::assemble;
use super::topology::{edge_ends, initial_segments, Bound, EdgeEnds, FaceData};
use crate::cad::geom::Curve;
use crate::cad::options::ImportOptions;
use crate::cad::sample::adaptive;
use crate::formats::workpiece::TrimSpec;
use crate::geometry::projection::project_from;
use crate::geometry::{NurbsSurface, Projection, ProjectionIndex, ProjectionOptions};
use crate::math::{Point3, Vec2};

type P2 = [f64; 2];

/// Deepest bisection of one sample interval while refining in (u, v).
const MAX_REFINE_DEPTH: usize = 12;
/// Values of the other parameter at which a possible seam is compared.
const SEAM_CHECKS: usize = 9;
/// Relative parameter slack (fraction of the period) within which a loop
/// counts as inside the domain or closed.
const PERIOD_SLACK: f64 = 1e-9;

/// The trim of `face` on `spec` from its projected edges, or why there is
/// none (including the largest miss in mm).
pub fn projected_trim(
    ctx: &Ctx,
    face: &FaceData,
    surface: &NurbsSurface,
    opts: &ImportOptions,
) -> Result<TrimSpec, String> {
    let target = Target::new(surface, opts);
    let mut loops = Vec::new();
    for b in face.bounds.iter().filter(|b| !b.edges.is_empty()) {
        let raw = bound_uv(ctx, &target, b, opts)?;
        loops.push((b.outer, target.normalise(raw, b.loop_id)?));
    }
    assemble(&loops)
}

/// The face's surface prepared for projection.
struct Target<'s> {
    surface: &'s NurbsSurface,
    index: ProjectionIndex,
    popts: ProjectionOptions,
    /// Period of each closed direction (the domain width), `None` if open.
    periods: [Option<f64>; 2],
    /// Largest allowed miss, mm.
    tol: f64,
}

/// An edge sample: curve parameter, 3-D point and its (u, v).
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    uv: P2,
}

impl<'s> Target<'s> {
    fn new(surface: &'s NurbsSurface, opts: &ImportOptions) -> Target<'s> {
        let popts = ProjectionOptions::default();
        let index = ProjectionIndex::new(surface, &popts);
        let periods = [0, 1].map(|axis| period(surface, axis, opts.seam_tolerance_mm));
        Target {
            surface,
            index,
            popts,
            periods,
            tol: opts.projection_tolerance_mm,
        }
    }

    /// Global projection of `p`: (u, v) and miss in mm.
    fn cold(&self, p: Point3) -> Result<(P2, f64), String> {
        let pr = self
            .index
            .project(self.surface, p)
            .map_err(|e| e.to_string())?;
        Ok(foot(&pr))
    }

    /// Warm projection from `hint`, cold when that misses; unwrapped near `hint`.
    fn warm(&self, p: Point3, hint: P2) -> Result<(P2, f64), String> {
        let [u, v] = self.wrapped(hint);
        let start = self.surface.clamp(Vec2::new(u, v));
        let warm = project_from(self.surface, p, start, &self.popts)
            .map(|pr| foot(&pr))
            .map_err(|e| e.to_string())?;
        let best = match warm.1 > self.tol {
            true => Some(self.cold(p)?).filter(|c| c.1 < warm.1).unwrap_or(warm),
            false => warm,
        };
        Ok((self.near(best.0, hint), best.1))
    }

    /// `uv` shifted by whole periods of the closed directions to lie next to `to`.
    fn near(&self, uv: P2, to: P2) -> P2 {
        let mut out = uv;
        for (axis, per) in self.periods.iter().enumerate() {
            if let (Some(per), Some(c), Some(t)) = (per, out.get_mut(axis), to.get(axis)) {
                *c += per * ((*t - *c) / per).round();
            }
        }
        out
    }

    /// Distance from `S(uv)` (uv taken modulo the periods) to `p`, mm.
    fn gap(&self, uv: P2, p: Point3) -> f64 {
        let [u, v] = self.wrapped(uv);
        (self.surface.point(u, v) - p).norm()
    }

    /// `uv` brought into the domain along closed directions.
    fn wrapped(&self, uv: P2) -> P2 {
        let ((u0, _), (v0, _)) = self.surface.domain();
        let [u, v] = uv;
        [wrap(u, u0, self.periods[0]), wrap(v, v0, self.periods[1])]
    }
}

fn wrap(x: f64, lo: f64, period: Option<f64>) -> f64 {
    period.map_or(x, |p| lo + (x - lo).rem_euclid(p))
}

fn foot(pr: &Projection) -> (P2, f64) {
    ([pr.uv.x, pr.uv.y], pr.distance)
}

/// The domain width along `axis` when the surface closes on itself there
/// (opposite boundary curves within `tol` mm at [`SEAM_CHECKS`] places).
fn period(s: &NurbsSurface, axis: usize, tol: f64) -> Option<f64> {
    let ((u0, u1), (v0, v1)) = s.domain();
    let closed = (0..SEAM_CHECKS).all(|k| {
        let f = k as f64 / (SEAM_CHECKS - 1) as f64;
        let (a, b) = if axis == 0 {
            let v = v0 + f * (v1 - v0);
            (s.point(u0, v), s.point(u1, v))
        } else {
            let u = u0 + f * (u1 - u0);
            (s.point(u, v0), s.point(u, v1))
        };
        (a - b).norm() <= tol
    });
    let width = if axis == 0 { u1 - u0 } else { v1 - v0 };
    (closed && width > 0.0).then_some(width)
}

/// One edge being traced: its curve and the samples so far.
struct Trace<'a> {
    target: &'a Target<'a>,
    curve: &'a Curve,
    samples: Vec<Sample>,
    /// Largest miss of a projected sample, mm.
    miss: f64,
    max_samples: usize,
}

impl Trace<'_> {
    /// Projects `p` (the point at `t`) warm from `hint` and records its miss.
    fn project(&mut self, t: f64, p: Point3, hint: P2) -> Result<Sample, String> {
        let (uv, miss) = self.target.warm(p, hint)?;
        self.miss = self.miss.max(miss);
        Ok(Sample { t, uv })
    }

    /// Appends samples of `(a, b]`, bisecting while the (u, v) chord's
    /// midpoint maps farther than the tolerance from the edge.
    fn refine(&mut self, a: Sample, b: Sample, depth: usize) -> Result<(), String> {
        let tm = 0.5 * (a.t + b.t);
        let mid = [0.5 * (a.uv[0] + b.uv[0]), 0.5 * (a.uv[1] + b.uv[1])];
        let room = depth < MAX_REFINE_DEPTH && self.samples.len() < self.max_samples;
        let pm = self.curve.eval(tm);
        if room && self.target.gap(mid, pm) > self.target.tol {
            let m = self.project(tm, pm, mid)?;
            self.refine(a, m, depth + 1)?;
            return self.refine(m, b, depth + 1);
        }
        self.samples.push(b);
        Ok(())
    }
}

/// The (u, v) polyline of an edge in traversal direction.
fn edge_uv(
    ctx: &Ctx,
    target: &Target,
    (edge, forward): (u64, bool),
    opts: &ImportOptions,
) -> Result<Vec<P2>, String> {
    let ends = edge_ends(ctx, edge, opts).map_err(|e| e.to_string())?;
    let pts = edge_samples(&ends, opts);
    let mut trace = Trace {
        target,
        curve: &ends.curve,
        samples: Vec::with_capacity(pts.len()),
        miss: 0.0,
        max_samples: opts.max_edge_samples,
    };
    trace_samples(&mut trace, &pts)?;
    if trace.miss > target.tol {
        return Err(format!(
            "edge #{edge}: projected edge samples miss the surface by up to {:.3e} mm",
            trace.miss
        ));
    }
    let mut uv: Vec<P2> = trace.samples.iter().map(|s| s.uv).collect();
    if ends.same != forward {
        uv.reverse();
    }
    Ok(uv)
}

/// The edge's curve sampled to the chord tolerance in the curve's
/// direction, its vertices put at the ends (files place vertices within
/// their modelling tolerance of the curve ends, not exactly on them).
fn edge_samples(ends: &EdgeEnds, opts: &ImportOptions) -> Vec<(f64, Point3)> {
    let (t0, t1) = ends.range;
    let f = |t: f64| ends.curve.eval(t);
    let initial = initial_segments(&ends.curve, t0, t1);
    let tol = opts.chord_tolerance_mm;
    let mut pts = adaptive(&f, t0, t1, initial, tol, opts.max_edge_samples);
    if let Some(first) = pts.first_mut() {
        first.1 = ends.from;
    }
    if let Some(last) = pts.last_mut() {
        last.1 = ends.to;
    }
    pts
}

/// Projects the 3-D samples in order (the first cold) and refines between them.
fn trace_samples(trace: &mut Trace, pts: &[(f64, Point3)]) -> Result<(), String> {
    let Some(&(t_first, p_first)) = pts.first() else {
        return Err("edge has no samples".into());
    };
    let (uv, miss) = trace.target.cold(p_first)?;
    trace.miss = trace.miss.max(miss);
    let mut prev = Sample { t: t_first, uv };
    trace.samples.push(prev);
    for &(t, p) in pts.iter().skip(1) {
        let next = trace.project(t, p, prev.uv)?;
        trace.refine(prev, next, 0)?;
        prev = next;
    }
    Ok(())
}

/// The (u, v) loop of a bound: edges chained, each shifted by whole periods
/// to continue where the previous one ended.
fn bound_uv(
    ctx: &Ctx,
    target: &Target,
    b: &Bound,
    opts: &ImportOptions,
) -> Result<Vec<P2>, String> {
    let mut out: Vec<P2> = Vec::new();
    for &e in &b.edges {
        let uv = edge_uv(ctx, target, e, opts)?;
        let shift = match (out.last(), uv.first()) {
            (Some(&end), Some(&start)) => sub(target.near(start, end), start),
            _ => [0.0, 0.0],
        };
        let moved = uv.into_iter().map(|p| [p[0] + shift[0], p[1] + shift[1]]);
        let skip = usize::from(!out.is_empty());
        out.extend(moved.skip(skip));
    }
    Ok(out)
}

fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

impl Target<'_> {
    /// Checks that a loop closes (it does not wind around a closed
    /// direction) and shifts it by whole periods into the domain.
    fn normalise(&self, mut pts: Vec<P2>, loop_id: u64) -> Result<Vec<P2>, String> {
        let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
            return Err(format!("loop #{loop_id} has no points"));
        };
        if let Some(name) = self.winding(first, last) {
            return Err(format!(
                "loop #{loop_id} winds around the closed {name} direction"
            ));
        }
        let centre = self.loop_shift(&pts);
        pts.iter_mut()
            .for_each(|p| *p = [p[0] + centre[0], p[1] + centre[1]]);
        if pts.len() > 1 && first == last {
            pts.pop();
        }
        self.check_inside(&pts, loop_id)?;
        Ok(pts)
    }

    /// The closed direction (`"u"` or `"v"`) in which a loop from `first`
    /// to `last` does not close but goes once around.
    fn winding(&self, first: P2, last: P2) -> Option<&'static str> {
        let shift = sub(self.near(last, first), last);
        let winds = |axis: usize| {
            let per = self.periods.get(axis).copied().flatten();
            per.zip(shift.get(axis))
                .is_some_and(|(p, s)| s.abs() > 0.5 * p)
        };
        ["u", "v"]
            .into_iter()
            .enumerate()
            .find(|(axis, _)| winds(*axis))
            .map(|(_, n)| n)
    }

    /// Whole periods that bring the loop's bounding-box centre into the domain.
    fn loop_shift(&self, pts: &[P2]) -> P2 {
        let ((u0, u1), (v0, v1)) = self.surface.domain();
        let mid = [0.5 * (u0 + u1), 0.5 * (v0 + v1)];
        let centre = box_centre(pts);
        sub(self.near(centre, mid), centre)
    }

    /// Fails when a loop leaves the domain of a closed direction (it crosses
    /// the seam without a seam edge).
    fn check_inside(&self, pts: &[P2], loop_id: u64) -> Result<(), String> {
        let ((u0, u1), (v0, v1)) = self.surface.domain();
        let range = [(u0, u1), (v0, v1)];
        for (axis, (per, (lo, hi))) in self.periods.iter().zip(range).enumerate() {
            let Some(per) = per else { continue };
            let slack = PERIOD_SLACK * per;
            let out = pts
                .iter()
                .filter_map(|p| p.get(axis))
                .any(|c| *c < lo - slack || *c > hi + slack);
            if out {
                return Err(format!(
                    "loop #{loop_id} crosses the seam of the closed direction {axis} (0 = u, 1 = v)"
                ));
            }
        }
        Ok(())
    }
}

fn box_centre(pts: &[P2]) -> P2 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in pts {
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]
}
