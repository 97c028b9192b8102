//! Faces, bounds, loops and edges: sampled to 3-D polylines.
use super::access::{has_record, Ctx};
use super::curves::{curve, point, Space};
use crate::cad::error::CadResult;
use crate::cad::geom::Curve;
use crate::cad::geom::EPS_PARAM;
use crate::cad::options::ImportOptions;
use crate::cad::sample::adaptive;
use crate::math::Point3;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_8, TAU};

/// One face bound: the loop's edges as (EDGE_CURVE id, traversed forward).
#[derive(Debug, Clone, PartialEq)]
pub struct Bound {
    /// The loop entity.
    pub loop_id: u64,
    /// True for FACE_OUTER_BOUND.
    pub outer: bool,
    /// Oriented edges in traversal order (bound orientation applied).
    pub edges: Vec<(u64, bool)>,
    /// Vertex of a VERTEX_LOOP, or polygon of a POLY_LOOP.
    pub points: Vec<Point3>,
}

/// An ADVANCED_FACE or FACE_SURFACE.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceData {
    /// Entity id.
    pub id: u64,
    /// Name string.
    pub name: String,
    /// Surface entity.
    pub surface: u64,
    /// Face normal agrees with the surface normal.
    pub same_sense: bool,
    /// Bounds.
    pub bounds: Vec<Bound>,
}

/// Reads a face and its bounds.
pub fn face(ctx: &Ctx, id: u64, type_name: &str) -> CadResult<FaceData> {
    let args = ctx.args(id, type_name)?;
    let bounds = args
        .refs(1)?
        .into_iter()
        .map(|b| bound(ctx, b))
        .collect::<CadResult<Vec<_>>>()?;
    Ok(FaceData {
        id,
        name: args.string(0)?.to_string(),
        surface: args.reference(2)?,
        same_sense: args.boolean(3)?,
        bounds,
    })
}

fn bound(ctx: &Ctx, id: u64) -> CadResult<Bound> {
    let outer = has_record(ctx.inst(id)?, "FACE_OUTER_BOUND");
    let name = if outer {
        "FACE_OUTER_BOUND"
    } else {
        "FACE_BOUND"
    };
    let args = ctx.args(id, name)?;
    let loop_id = args.reference(1)?;
    let (mut edges, mut points) = read_loop(ctx, loop_id)?;
    if !args.boolean(2)? {
        edges.reverse();
        edges.iter_mut().for_each(|e| e.1 = !e.1);
        points.reverse();
    }
    Ok(Bound {
        loop_id,
        outer,
        edges,
        points,
    })
}

/// Oriented edges and points of an EDGE_LOOP, VERTEX_LOOP or POLY_LOOP.
type LoopContents = (Vec<(u64, bool)>, Vec<Point3>);

fn read_loop(ctx: &Ctx, id: u64) -> CadResult<LoopContents> {
    let lp = ctx.first(id)?;
    match lp.inst.records.first().map_or("", |r| r.name.as_str()) {
        "EDGE_LOOP" => Ok((
            lp.refs(1)?
                .into_iter()
                .map(|e| oriented_edge(ctx, e))
                .collect::<CadResult<_>>()?,
            Vec::new(),
        )),
        "VERTEX_LOOP" => Ok((Vec::new(), vec![vertex(ctx, lp.reference(1)?)?])),
        "POLY_LOOP" => Ok((
            Vec::new(),
            lp.refs(1)?
                .into_iter()
                .map(|p| point(ctx, p, Space::Model))
                .collect::<CadResult<_>>()?,
        )),
        other => Err(lp.err(format!("unsupported loop type {other}"))),
    }
}

fn oriented_edge(ctx: &Ctx, id: u64) -> CadResult<(u64, bool)> {
    let args = ctx.args(id, "ORIENTED_EDGE")?;
    Ok((args.reference(3)?, args.boolean(4)?))
}

/// The point of a VERTEX_POINT.
pub fn vertex(ctx: &Ctx, id: u64) -> CadResult<Point3> {
    let args = ctx.args(id, "VERTEX_POINT")?;
    point(ctx, args.reference(1)?, Space::Model)
}

/// Samples edges and caches the polylines (each edge bounds two faces).
pub struct EdgeSampler<'a> {
    ctx: Ctx<'a>,
    /// The tolerances in use.
    pub opts: ImportOptions,
    cache: HashMap<u64, Vec<Point3>>,
}

impl<'a> EdgeSampler<'a> {
    /// A sampler for `ctx`.
    pub fn new(ctx: Ctx<'a>, opts: ImportOptions) -> Self {
        EdgeSampler {
            ctx,
            opts,
            cache: HashMap::new(),
        }
    }

    /// The 3-D polyline of a bound, closed implicitly (last point != first).
    pub fn bound_points(&mut self, b: &Bound) -> CadResult<Vec<Point3>> {
        let mut out = b.points.clone();
        for &(edge, forward) in &b.edges {
            let mut pts = self.edge(edge)?;
            if !forward {
                pts.reverse();
            }
            let skip = usize::from(out.last().is_some_and(|l| {
                pts.first()
                    .is_some_and(|f| (l - f).norm() <= self.opts.point_tolerance_mm)
            }));
            out.extend(pts.into_iter().skip(skip));
        }
        if out.len() > 1
            && out
                .first()
                .zip(out.last())
                .is_some_and(|(f, l)| (f - l).norm() <= self.opts.point_tolerance_mm)
        {
            out.pop();
        }
        Ok(out)
    }

    /// The polyline of an EDGE_CURVE from its start vertex to its end vertex.
    pub fn edge(&mut self, id: u64) -> CadResult<Vec<Point3>> {
        if let Some(pts) = self.cache.get(&id) {
            return Ok(pts.clone());
        }
        let pts = self.sample_edge(id)?;
        self.cache.insert(id, pts.clone());
        Ok(pts)
    }

    fn sample_edge(&self, id: u64) -> CadResult<Vec<Point3>> {
        let e = edge_ends(&self.ctx, id, &self.opts)?;
        let mut pts = self.between(&e.curve, e.from, e.to, e.range);
        if !e.same {
            pts.reverse();
        }
        Ok(pts)
    }

    /// Samples `c` from `from` to `to` in its parameter direction.
    fn between(&self, c: &Curve, from: Point3, to: Point3, (t0, t1): (f64, f64)) -> Vec<Point3> {
        if matches!(c, Curve::Line { .. }) {
            return vec![from, to];
        }
        let initial = initial_segments(c, t0, t1);
        let f = |t: f64| c.eval(t);
        let mut pts: Vec<Point3> = adaptive(
            &f,
            t0,
            t1,
            initial,
            self.opts.chord_tolerance_mm,
            self.opts.max_edge_samples,
        )
        .into_iter()
        .map(|(_, p)| p)
        .collect();
        if let Some(first) = pts.first_mut() {
            *first = from;
        }
        if let Some(last) = pts.last_mut() {
            *last = to;
        }
        pts
    }
}

/// An EDGE_CURVE resolved: its curve and the ends in the curve's direction.
pub struct EdgeEnds {
    /// The edge geometry entity.
    pub geometry: u64,
    /// The curve.
    pub curve: Curve,
    /// Start point in the curve's direction.
    pub from: Point3,
    /// End point in the curve's direction.
    pub to: Point3,
    /// The edge runs along the curve's direction.
    pub same: bool,
    /// Start and end vertex coincide.
    pub closed: bool,
    /// Curve parameters of `from` and `to`.
    pub range: (f64, f64),
}

/// Reads an EDGE_CURVE and locates its vertices on its curve.
pub fn edge_ends(ctx: &Ctx, id: u64, opts: &ImportOptions) -> CadResult<EdgeEnds> {
    let args = ctx.args(id, "EDGE_CURVE")?;
    let (v0, v1) = (args.reference(1)?, args.reference(2)?);
    let (p0, p1) = (vertex(ctx, v0)?, vertex(ctx, v1)?);
    let geometry = args.reference(3)?;
    let curve = curve(ctx, geometry, Space::Model)?;
    let same = args.boolean(4)?;
    let closed = v0 == v1 || (p0 - p1).norm() <= opts.point_tolerance_mm;
    let (from, to) = if same { (p0, p1) } else { (p1, p0) };
    let range = param_range(&curve, from, to, closed);
    Ok(EdgeEnds {
        geometry,
        curve,
        from,
        to,
        same,
        closed,
        range,
    })
}

/// The parameter range of `c` from `from` to `to` (a full period or the
/// whole domain for closed edges).
pub fn param_range(c: &Curve, from: Point3, to: Point3, closed: bool) -> (f64, f64) {
    let t0 = c.param_of(from);
    if let Some(period) = c.period() {
        let mut sweep = (c.param_of(to) - t0).rem_euclid(period);
        if closed || sweep <= EPS_PARAM {
            sweep = period;
        }
        return (t0, t0 + sweep);
    }
    if let Curve::Nurbs(n) = c {
        let (lo, hi) = n.domain();
        let t1 = c.param_of(to);
        if closed || t1 <= t0 {
            return (lo, hi);
        }
        return (t0, t1);
    }
    (t0, c.param_of(to))
}

/// Initial sample intervals before adaptive refinement.
pub fn initial_segments(c: &Curve, t0: f64, t1: f64) -> usize {
    match c {
        Curve::Nurbs(n) => 2 * crate::cad::nurbs::breaks(n).len().max(2),
        _ => {
            (((t1 - t0).abs() / FRAC_PI_8).ceil() as usize).clamp(1, (TAU / FRAC_PI_8) as usize + 1)
        }
    }
}
