//! The manifold solid B-rep form: 186 manifold solid -> 514 shells (with
//! orientation flags) -> 510 faces (surface, outer-loop flag) -> 508 loops
//! -> 504 edge lists (curve and vertex references) -> 502 vertex lists.
//!
//! A face's normal is its surface's natural normal, flipped when the face's
//! flag in its shell and the shell's flag in its solid disagree. Edges are
//! sampled once per solid (shared by their two faces) from their start to
//! their terminate vertex; a loop takes each edge forward or reversed by
//! its orientation flag. Transformations of the topological entities
//! (186 aside) are ignored; curves and surfaces keep theirs.
use super::curves::{pieces, polyline};
use super::entities::{Affine, Fields, Model};
use super::faces::{bounded, FaceLoop, FaceOut};
use super::pspace::{close, join, uv_curve, P2};
use super::records::Entry;
use super::surfaces::{surface, Surf};
use crate::cad::error::CadResult;
use crate::cad::options::ImportOptions;
use crate::geometry::NurbsSurface;
use crate::math::Point3;
use std::collections::HashMap;

/// A face of a solid or shell with its orientation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellFace {
    /// DE pointer of the 510 face.
    pub face: u64,
    /// True when the outward normal is the surface's natural normal.
    pub same_sense: bool,
}

/// The faces of 186 solid `e`, outer shell first, then the void shells.
pub fn solid_faces(m: &Model, e: &Entry) -> CadResult<Vec<ShellFace>> {
    let f = m.fields(e)?;
    let mut out = shell_faces(m, shell(&f, 1)?, flag(&f, 2)?)?;
    let n = f.count(3)?;
    for k in 0..n {
        out.extend(shell_faces(m, shell(&f, 4 + 2 * k)?, flag(&f, 5 + 2 * k)?)?);
    }
    Ok(out)
}

/// The 514 shell that field `k` points to.
fn shell<'a>(f: &Fields<'a>, k: usize) -> CadResult<&'a Entry> {
    let e = f.target(k)?;
    if e.kind != 514 {
        return Err(f.bad(
            k,
            &format!("points to entity {} (expected a 514 shell)", e.kind),
        ));
    }
    Ok(e)
}

/// A 0/1 orientation flag (1 = agrees).
fn flag(f: &Fields, k: usize) -> CadResult<bool> {
    match f.int(k)? {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(f.bad(k, "is not an orientation flag (0 or 1)")),
    }
}

/// The faces of 514 shell `e`; `shell_sense` is the shell's own flag.
pub fn shell_faces(m: &Model, e: &Entry, shell_sense: bool) -> CadResult<Vec<ShellFace>> {
    let g = m.fields(e)?;
    (0..g.count(1)?)
        .map(|i| {
            let face = g.target(2 + 2 * i)?;
            if face.kind != 510 {
                return Err(g.bad(
                    2 + 2 * i,
                    &format!("points to entity {} (expected a 510 face)", face.kind),
                ));
            }
            Ok(ShellFace {
                face: face.seq,
                same_sense: flag(&g, 3 + 2 * i)? == shell_sense,
            })
        })
        .collect()
}

/// Edge polylines of one placed solid, sampled once.
pub struct EdgeCache {
    place: Affine,
    opts: ImportOptions,
    vertices: HashMap<u64, Vec<Point3>>,
    edges: HashMap<(u64, usize), Vec<Point3>>,
}

impl EdgeCache {
    /// A cache for topology placed by `place` (definition space to mm).
    pub fn new(place: Affine, opts: ImportOptions) -> EdgeCache {
        EdgeCache {
            place,
            opts,
            vertices: HashMap::new(),
            edges: HashMap::new(),
        }
    }

    /// Vertex `k` (1-based) of 502 list `list`.
    fn vertex(&mut self, m: &Model, f: &Fields, field: usize, k: i64) -> CadResult<Point3> {
        let list = f.target(field)?;
        if list.kind != 502 {
            return Err(f.bad(
                field,
                &format!(
                    "points to entity {} (expected a 502 vertex list)",
                    list.kind
                ),
            ));
        }
        if !self.vertices.contains_key(&list.seq) {
            let g = m.fields(list)?;
            let pts = (0..g.count(1)?)
                .map(|i| {
                    let c = g.reals(2 + 3 * i, 3)?;
                    let at = |d: usize| c.get(d).copied().unwrap_or(0.0);
                    Ok(self.place.apply(Point3::new(at(0), at(1), at(2))))
                })
                .collect::<CadResult<Vec<_>>>()?;
            self.vertices.insert(list.seq, pts);
        }
        let pts = self
            .vertices
            .get(&list.seq)
            .map(Vec::as_slice)
            .unwrap_or(&[]);
        usize::try_from(k)
            .ok()
            .and_then(|k| k.checked_sub(1))
            .and_then(|i| pts.get(i).copied())
            .ok_or_else(|| f.bad(field + 1, &format!("is not a vertex of list #{}", list.seq)))
    }

    /// Edge `k` (1-based) of 504 list `list`, from its start to its terminate vertex.
    fn edge(&mut self, m: &Model, list: &Entry, k: usize) -> CadResult<Vec<Point3>> {
        if let Some(p) = self.edges.get(&(list.seq, k)) {
            return Ok(p.clone());
        }
        if list.kind != 504 {
            return Err(m.err(
                list,
                format!(
                    "loop edge is entity {} (expected a 504 edge list)",
                    list.kind
                ),
            ));
        }
        let g = m.fields(list)?;
        let at = 2 + 5 * k.saturating_sub(1);
        if k == 0 || k > g.count(1)? {
            return Err(g.bad(1, &format!("has no edge {k}")));
        }
        let curve = g.target(at)?;
        let from = self.vertex(m, &g, at + 1, g.int(at + 2)?)?;
        let to = self.vertex(m, &g, at + 3, g.int(at + 4)?)?;
        let ps = pieces(m, curve, &self.place)?;
        let o = &self.opts;
        let mut pts = polyline(
            &ps,
            o.chord_tolerance_mm,
            o.max_edge_samples,
            o.point_tolerance_mm,
        );
        let closed = (from - to).norm() <= o.point_tolerance_mm;
        let d = |a: Option<&Point3>, b: Point3| a.map_or(f64::INFINITY, |a| (a - b).norm());
        if !closed
            && d(pts.first(), to) + d(pts.last(), from) < d(pts.first(), from) + d(pts.last(), to)
        {
            pts.reverse();
        }
        if let Some(p) = pts.first_mut() {
            *p = from;
        }
        if let Some(p) = pts.last_mut() {
            *p = to;
        }
        self.edges.insert((list.seq, k), pts.clone());
        Ok(pts)
    }
}

/// One loop edge: its model-space polyline and its parameter curves.
struct LoopEdge {
    points: Vec<Point3>,
    uv: Option<Vec<P2>>,
}

/// Converts 510 face `sf` of a solid placed as the cache's placement.
pub fn face510(
    m: &Model,
    sf: ShellFace,
    cache: &mut EdgeCache,
    opts: &ImportOptions,
) -> CadResult<FaceOut> {
    let Some(e) = m.get(sf.face) else {
        return Err(m.missing(sf.face));
    };
    let f = m.fields(e)?;
    let base = f.target(1)?;
    let surf = surface(m, base, &cache.place.clone())?;
    let spline = match &surf {
        Surf::Spline(spec, _) => spec.to_surface().ok(),
        _ => None,
    };
    let outer_first = f.int(3)? == 1;
    let loops = (0..f.count(2)?)
        .map(|k| {
            let l = f.target(4 + k)?;
            loop508(m, l, cache, spline.as_ref(), opts, outer_first && k == 0)
        })
        .collect::<CadResult<Vec<_>>>()?;
    let (s, note) = bounded(&surf, &loops, sf.same_sense, opts).map_err(|r| m.err(e, r))?;
    Ok((s, note, base.kind))
}

fn loop508(
    m: &Model,
    e: &Entry,
    cache: &mut EdgeCache,
    spline: Option<&NurbsSurface>,
    opts: &ImportOptions,
    outer: bool,
) -> CadResult<FaceLoop> {
    if e.kind != 508 {
        return Err(m.err(
            e,
            format!("loop pointer is entity {} (expected a 508 loop)", e.kind),
        ));
    }
    let f = m.fields(e)?;
    let mut at = 2;
    let mut edges = Vec::new();
    for _ in 0..f.count(1)? {
        let (kind, forward, k_psc) = (f.int(at)?, f.int(at + 3)? == 1, f.count(at + 4)?);
        let list = f.target(at + 1)?;
        let points = if kind == 1 {
            vec![cache.vertex(m, &f, at + 1, f.int(at + 2)?)?]
        } else {
            let mut p = cache.edge(m, list, f.count(at + 2)?)?;
            if !forward {
                p.reverse();
            }
            p
        };
        let uv = match spline {
            Some(s) if k_psc > 0 && kind == 0 => {
                let mut acc = Vec::new();
                for j in 0..k_psc {
                    join(&mut acc, uv_curve(m, f.target(at + 6 + 2 * j)?, s, opts)?);
                }
                orient_uv(acc, &points, s, opts)
            }
            _ => None,
        };
        edges.push(LoopEdge { points, uv });
        at += 5 + 2 * k_psc;
    }
    Ok(assemble_loop(edges, outer, opts))
}

/// The parameter curve oriented like the edge's points, `None` when its
/// ends do not map onto the edge's ends within the pcurve tolerance.
fn orient_uv(
    uv: Vec<P2>,
    points: &[Point3],
    s: &NurbsSurface,
    opts: &ImportOptions,
) -> Option<Vec<P2>> {
    let at = |p: Option<&P2>| p.map(|q| s.point(q[0], q[1]));
    let near = |a: Option<Point3>, b: Option<&Point3>| {
        a.zip(b)
            .is_some_and(|(a, b)| (a - b).norm() <= opts.pcurve_tolerance_mm)
    };
    let (first, last) = (points.first(), points.last());
    if near(at(uv.first()), first) && near(at(uv.last()), last) {
        return Some(uv);
    }
    if near(at(uv.last()), first) && near(at(uv.first()), last) {
        let mut r = uv;
        r.reverse();
        return Some(r);
    }
    None
}

fn assemble_loop(edges: Vec<LoopEdge>, outer: bool, opts: &ImportOptions) -> FaceLoop {
    let mut points: Vec<Point3> = Vec::new();
    let mut uv: Option<Vec<P2>> = Some(Vec::new());
    for e in edges {
        let skip = usize::from(
            points
                .last()
                .zip(e.points.first())
                .is_some_and(|(a, b)| (a - b).norm() <= opts.point_tolerance_mm),
        );
        points.extend(e.points.into_iter().skip(skip));
        uv = match (uv, e.uv) {
            (Some(mut acc), Some(p)) => {
                join(&mut acc, p);
                Some(acc)
            }
            _ => None,
        };
    }
    let closed = points.len() > 1
        && points
            .first()
            .zip(points.last())
            .is_some_and(|(a, b)| (a - b).norm() <= opts.point_tolerance_mm);
    if closed {
        points.pop();
    }
    FaceLoop {
        points,
        uv: uv.filter(|u| !u.is_empty()).map(close),
        outer,
    }
}
