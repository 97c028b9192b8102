//! Clipping section curves to a face: the parts on its trim, split into
//! stretches along the face's edges (which the neighbouring face may share)
//! and stretches across it.
use super::{SectionCurve, SectionOptions, SectionPoint};
use crate::geometry::trim::segment_distance;
use crate::geometry::{NurbsSurface, Plane, Trim};
use crate::math::Vec2;

/// Bisection steps locating where a curve leaves the face.
const CROSSING_BISECTIONS: usize = 60;

/// Newton steps along a trim edge onto the plane.
const EDGE_ROOT_STEPS: usize = 12;

/// Smallest sine of the angle (in `(u, v)`) between a trim edge and the
/// section curve for a crossing to be solved along that edge (below it the
/// curve runs along the edge and the crossing is not defined by it).
const EDGE_ROOT_MIN_SINE: f64 = 1e-3;

/// A clipped part of a section curve.
#[derive(Debug, Clone)]
pub(super) struct Piece {
    /// The part, ending exactly on the face's boundary where it leaves it.
    pub curve: SectionCurve,
    /// Whether it runs along the face's boundary (within
    /// [`SectionOptions::edge_tol_mm`]), where a neighbouring face may have
    /// the same stretch.
    pub on_edge: bool,
}

/// The face a curve is clipped to.
struct Face<'a> {
    surface: &'a NurbsSurface,
    trim: Option<&'a Trim>,
    plane: &'a Plane,
    opts: &'a SectionOptions,
}

impl Face<'_> {
    fn contains(&self, uv: Vec2) -> bool {
        self.trim.is_none_or(|t| t.contains(uv))
    }

    /// Whether `uv`'s point lies within the edge tolerance of the face's
    /// boundary (its trim loops, or its parameter domain's sides when it
    /// has no trim), the distance in the parameters taken times the
    /// parameters' speed `sqrt(|Su|^2 + |Sv|^2)` (an upper bound of the
    /// distance in mm); a trim is asked only for its edges within reach
    /// ([`Trim::comes_within`]).
    fn near_edge(&self, uv: Vec2) -> bool {
        let d = self.surface.derivs(uv.x, uv.y, 1);
        let speed = (d.su().norm_squared() + d.sv().norm_squared()).sqrt();
        let tol = self.opts.edge_tol_mm;
        match self.trim {
            _ if speed <= 0.0 => true,
            Some(t) => t.comes_within(uv, tol / speed),
            None => {
                let ((u0, u1), (v0, v1)) = self.surface.domain();
                let side = (uv.x - u0)
                    .abs()
                    .min((u1 - uv.x).abs())
                    .min((uv.y - v0).abs())
                    .min((v1 - uv.y).abs());
                side * speed <= tol
            }
        }
    }
}

/// The parts of `curve` that lie on the face (the trim's inside and the
/// stretches along its boundary), each ending exactly on the boundary where
/// it leaves the face, split where the curve joins or leaves the boundary.
pub(super) fn clip(
    curve: SectionCurve,
    surface: &NurbsSurface,
    trim: Option<&Trim>,
    plane: &Plane,
    opts: &SectionOptions,
) -> Vec<Piece> {
    let face = Face {
        surface,
        trim,
        plane,
        opts,
    };
    let near: Vec<bool> = curve.points.iter().map(|p| face.near_edge(p.uv)).collect();
    let on_edge = stretches(&near, curve.closed);
    let kept: Vec<bool> = (curve.points.iter().zip(&on_edge))
        .map(|(p, &e)| e || face.contains(p.uv))
        .collect();
    let runs = if kept.iter().all(|&k| k) {
        whole(&curve, &on_edge)
    } else {
        runs(&curve, &kept, &on_edge, &face)
    };
    runs.into_iter().flat_map(split_at_edges).collect()
}

/// Points near the boundary with a near neighbour along the curve: the
/// curve runs along the boundary there (a lone near point is a crossing).
fn stretches(near: &[bool], closed: bool) -> Vec<bool> {
    let n = near.len();
    let at = |k: Option<usize>| k.is_some_and(|k| near[k]);
    (0..n)
        .map(|k| {
            let prev = if k > 0 {
                Some(k - 1)
            } else {
                closed.then(|| n - 1)
            };
            let next = if k + 1 < n {
                Some(k + 1)
            } else {
                closed.then_some(0)
            };
            near[k] && (at(prev) || at(next))
        })
        .collect()
}

/// A run of kept points with their on-edge flags; a closed run repeats
/// nothing and closes on itself.
type Run = (Vec<(SectionPoint, bool)>, bool);

/// A curve wholly on the face as one run; a closed curve that is partly on
/// the boundary is opened where a stretch along the boundary starts, so the
/// split keeps each stretch in one piece.
fn whole(curve: &SectionCurve, on_edge: &[bool]) -> Vec<Run> {
    let tagged: Vec<(SectionPoint, bool)> = curve
        .points
        .iter()
        .copied()
        .zip(on_edge.iter().copied())
        .collect();
    let n = tagged.len();
    if !curve.closed || n < 2 {
        return vec![(tagged, false)];
    }
    let edge_segment = |k: usize| on_edge[k] && on_edge[(k + 1) % n];
    let start = (0..n).find(|&k| edge_segment(k) != edge_segment((k + n - 1) % n));
    match start {
        None => vec![(tagged, true)],
        Some(s) => {
            let open = (s..=s + n).map(|k| tagged[k % n]).collect();
            vec![(open, false)]
        }
    }
}

/// The runs of kept points of a curve that leaves the face, each ending
/// on the boundary.
fn runs(curve: &SectionCurve, kept: &[bool], on_edge: &[bool], face: &Face) -> Vec<Run> {
    let n = curve.points.len();
    // Start a closed curve at a dropped point so no run wraps around.
    let start = if curve.closed {
        kept.iter().position(|&b| !b).unwrap_or(0)
    } else {
        0
    };
    let order: Vec<usize> = (0..n).map(|k| (start + k) % n).collect();
    let pairs = if curve.closed { n } else { n.saturating_sub(1) };
    let tag = |k: usize| (curve.points[k], on_edge[k]);
    let mut out = Vec::new();
    let mut run: Vec<(SectionPoint, bool)> = Vec::new();
    if kept[order[0]] {
        run.push(tag(order[0]));
    }
    for k in 0..pairs {
        let (a, b) = (order[k], order[(k + 1) % n]);
        let (pa, pb) = (curve.points[a], curve.points[b]);
        match (kept[a], kept[b]) {
            (true, true) => run.push(tag(b)),
            (true, false) => {
                run.push((crossing(face, pa, pb, on_edge[a]), on_edge[a]));
                out.push((std::mem::take(&mut run), false));
            }
            (false, true) => {
                run.push((crossing(face, pb, pa, on_edge[b]), on_edge[b]));
                run.push(tag(b));
            }
            (false, false) => {}
        }
    }
    if !run.is_empty() {
        out.push((run, false));
    }
    out
}

/// Splits a run where it joins or leaves the boundary: a segment between
/// two on-edge points runs along the boundary, any other across the face.
fn split_at_edges((points, closed): Run) -> Vec<Piece> {
    let piece = |pts: &[(SectionPoint, bool)], on_edge: bool, closed: bool| Piece {
        curve: SectionCurve {
            points: pts.iter().map(|p| p.0).collect(),
            closed,
        },
        on_edge,
    };
    if points.len() < 2 {
        return Vec::new();
    }
    if closed {
        let on_edge = points.iter().all(|p| p.1);
        return vec![piece(&points, on_edge, true)];
    }
    let along = |k: usize| points[k].1 && points[k + 1].1;
    let mut out = Vec::new();
    let mut first = 0;
    for k in 1..points.len() - 1 {
        if along(k) != along(k - 1) {
            out.push(piece(&points[first..=k], along(k - 1), false));
            first = k;
        }
    }
    out.push(piece(&points[first..], along(points.len() - 2), false));
    out
}

/// The boundary point between a kept point `a` and a dropped point `b`;
/// `along_edge` when `a` is on a stretch along the boundary (which then
/// ends where the curve leaves the boundary's neighbourhood).
fn crossing(face: &Face, a: SectionPoint, b: SectionPoint, along_edge: bool) -> SectionPoint {
    let on_face = |uv: Vec2| face.contains(uv) || (along_edge && face.near_edge(uv));
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let at = |t: f64| a.uv + (b.uv - a.uv) * t;
    for _ in 0..CROSSING_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if on_face(at(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let q = at(lo);
    let reach = (b.uv - a.uv).norm();
    let uv = along_trim_edge(face, q, reach)
        .unwrap_or_else(|| onto_plane(face.surface, face.plane, q, face.opts));
    let d = face.surface.derivs(uv.x, uv.y, 2);
    SectionPoint {
        face: a.face,
        uv,
        point: d.point(),
        normal: face.surface.normal_from(&d, uv),
    }
}

/// The point where the section crosses the trim edge nearest `q` (of the
/// edges the curve crosses rather than follows): Newton on `g` along that
/// edge, so the point lies on both the plane and the trim (a step along
/// the plane's gradient would slide off the edge by the chord's sagitta).
/// `None` without a trim, or when the root is farther than `reach` in
/// parameter space.
fn along_trim_edge(face: &Face, q: Vec2, reach: f64) -> Option<Vec2> {
    let d = face.surface.derivs(q.x, q.y, 1);
    let n = face.plane.normal();
    let grad = Vec2::new(d.su().dot(&n), d.sv().dot(&n));
    let crossed = |e: Vec2| grad.dot(&e).abs() >= EDGE_ROOT_MIN_SINE * grad.norm() * e.norm();
    let (_, dir) = (face.trim?.segments())
        .filter(|&(a, b)| crossed(b - a))
        .map(|(a, b)| (segment_distance(q, (a, b)), b - a))
        .min_by(|x, y| x.0.total_cmp(&y.0))?;
    let dir = dir.try_normalize(0.0)?;
    let mut uv = q;
    for _ in 0..EDGE_ROOT_STEPS {
        let d = face.surface.derivs(uv.x, uv.y, 1);
        let g = face.plane.signed_distance(d.point());
        if g.abs() <= face.opts.plane_tol_mm {
            return Some(uv);
        }
        let slope = d.su().dot(&n) * dir.x + d.sv().dot(&n) * dir.y;
        uv -= dir * (g / slope);
        if !(uv - q).norm().is_finite() || (uv - q).norm() > reach {
            return None;
        }
    }
    None
}

/// A few gradient-Newton steps in parameter space back onto the plane
/// (the chord between two section points leaves it by a sagitta).
fn onto_plane(surface: &NurbsSurface, plane: &Plane, mut uv: Vec2, opts: &SectionOptions) -> Vec2 {
    for _ in 0..20 {
        let d = surface.derivs(uv.x, uv.y, 1);
        let g = plane.signed_distance(d.point());
        let grad = Vec2::new(d.su().dot(&plane.normal()), d.sv().dot(&plane.normal()));
        if g.abs() <= opts.plane_tol_mm || grad.norm_squared() == 0.0 {
            break;
        }
        uv = surface.clamp(uv - grad * (g / grad.norm_squared()));
    }
    uv
}
