//! Marching squares on a parameter grid: the topology of the section and
//! its exact crossings with the grid lines.
use super::SectionOptions;
use crate::geometry::{NurbsSurface, Plane};
use crate::math::Vec2;

/// A branch: crossings in order, and whether it closes on itself.
pub(super) type Branch = (Vec<Vec2>, bool);

struct Grid<'a> {
    surface: &'a NurbsSurface,
    plane: &'a Plane,
    us: Vec<f64>,
    vs: Vec<f64>,
    /// g at node (i, j), index `i * vs.len() + j`.
    g: Vec<f64>,
    /// Which side a node exactly on the plane counts as.
    zero_is_positive: bool,
}

impl Grid<'_> {
    fn g_at(&self, i: usize, j: usize) -> f64 {
        self.g[i * self.vs.len() + j]
    }
    fn node(&self, i: usize, j: usize) -> Vec2 {
        Vec2::new(self.us[i], self.vs[j])
    }
    fn positive(&self, g: f64) -> bool {
        g > 0.0 || (g == 0.0 && self.zero_is_positive)
    }
    fn eval(&self, uv: Vec2) -> f64 {
        self.plane.signed_distance(self.surface.point(uv.x, uv.y))
    }
}

/// Grid lines: each knot span cut into equal cells.
fn lines(breaks: &[f64], cells_per_span: usize, min_cells: usize) -> Vec<f64> {
    let spans = breaks.len().saturating_sub(1).max(1);
    let k = cells_per_span.max(min_cells.div_ceil(spans)).max(1);
    let mut out = Vec::with_capacity(spans * k + 1);
    for w in breaks.windows(2) {
        out.extend((0..k).map(|i| w[0] + (w[1] - w[0]) * i as f64 / k as f64));
    }
    if let Some(&last) = breaks.last() {
        out.push(last);
    }
    out
}

/// Traces the section's branches in the parameter domain.
pub(super) fn branches(
    surface: &NurbsSurface,
    plane: &Plane,
    opts: &SectionOptions,
) -> Vec<Branch> {
    let us = lines(
        &surface.knots_u().breakpoints(),
        opts.cells_per_span,
        opts.min_cells,
    );
    let vs = lines(
        &surface.knots_v().breakpoints(),
        opts.cells_per_span,
        opts.min_cells,
    );
    let snap = |g: f64| if g.abs() <= opts.snap_tol_mm { 0.0 } else { g };
    let g = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .map(|(u, v)| snap(plane.signed_distance(surface.point(u, v))))
        .collect();
    let grid = Grid {
        surface,
        plane,
        us,
        vs,
        g,
        zero_is_positive: true,
    };
    let found = trace(&grid, opts);
    // A section lying exactly along a parameter boundary (g = 0 there) shows
    // up only when zeros count as the other side.
    if found.is_empty() && grid.g.contains(&0.0) {
        return trace(
            &Grid {
                zero_is_positive: false,
                ..grid
            },
            opts,
        );
    }
    found
}

fn trace(grid: &Grid, opts: &SectionOptions) -> Vec<Branch> {
    let mut graph = Graph::default();
    for i in 0..grid.us.len().saturating_sub(1) {
        for j in 0..grid.vs.len().saturating_sub(1) {
            cell(grid, i, j, &mut graph, opts);
        }
    }
    graph.chains()
}

/// Edge key: (i, j, 0) along u from node (i, j); (i, j, 1) along v.
type EdgeKey = (usize, usize, u8);

#[derive(Default)]
struct Graph {
    keys: std::collections::BTreeMap<EdgeKey, usize>,
    points: Vec<Vec2>,
    links: Vec<Vec<usize>>,
}

impl Graph {
    fn crossing(&mut self, grid: &Grid, key: EdgeKey, opts: &SectionOptions) -> usize {
        if let Some(&id) = self.keys.get(&key) {
            return id;
        }
        let (i, j, dir) = key;
        let (i2, j2) = if dir == 0 { (i + 1, j) } else { (i, j + 1) };
        let uv = edge_root(
            grid,
            grid.node(i, j),
            grid.node(i2, j2),
            grid.g_at(i, j),
            grid.g_at(i2, j2),
            opts,
        );
        self.points.push(uv);
        self.links.push(Vec::new());
        self.keys.insert(key, self.points.len() - 1);
        self.points.len() - 1
    }

    fn link(&mut self, a: usize, b: usize) {
        if let (Some(la), true) = (self.links.get(a), a != b) {
            if !la.contains(&b) {
                self.links[a].push(b);
                self.links[b].push(a);
            }
        }
    }

    /// Walks the graph: open chains from their ends first, then loops.
    fn chains(&self) -> Vec<Branch> {
        let mut seen = vec![false; self.points.len()];
        let mut out = Vec::new();
        let ends: Vec<usize> = (0..self.points.len())
            .filter(|&k| self.links[k].len() == 1)
            .collect();
        for start in ends.into_iter().chain(0..self.points.len()) {
            if seen[start] || self.links[start].is_empty() {
                continue;
            }
            let (chain, closed) = self.walk(start, &mut seen);
            out.push((chain.into_iter().map(|k| self.points[k]).collect(), closed));
        }
        out
    }

    fn walk(&self, start: usize, seen: &mut [bool]) -> (Vec<usize>, bool) {
        let mut chain = vec![start];
        seen[start] = true;
        let mut current = start;
        loop {
            let next = self.links[current].iter().copied().find(|&k| !seen[k]);
            match next {
                Some(k) => {
                    seen[k] = true;
                    chain.push(k);
                    current = k;
                }
                None => {
                    let closed = chain.len() > 2 && self.links[current].contains(&start);
                    return (chain, closed);
                }
            }
        }
    }
}

fn cell(grid: &Grid, i: usize, j: usize, graph: &mut Graph, opts: &SectionOptions) {
    let pos = |a: usize, b: usize| grid.positive(grid.g_at(a, b));
    let (a, b, c, d) = (pos(i, j), pos(i + 1, j), pos(i + 1, j + 1), pos(i, j + 1));
    let bottom = (i, j, 0u8);
    let right = (i + 1, j, 1u8);
    let top = (i, j + 1, 0u8);
    let left = (i, j, 1u8);
    let crossed: Vec<EdgeKey> = [
        (bottom, a != b),
        (right, b != c),
        (top, d != c),
        (left, a != d),
    ]
    .into_iter()
    .filter(|e| e.1)
    .map(|e| e.0)
    .collect();
    let join = |e1: EdgeKey, e2: EdgeKey, graph: &mut Graph| {
        let (x, y) = (
            graph.crossing(grid, e1, opts),
            graph.crossing(grid, e2, opts),
        );
        graph.link(x, y);
    };
    match crossed.as_slice() {
        [e1, e2] => join(*e1, *e2, graph),
        [_, _, _, _] => {
            let centre = 0.5 * (grid.node(i, j) + grid.node(i + 1, j + 1));
            if grid.positive(grid.eval(centre)) == a {
                join(bottom, right, graph);
                join(top, left, graph);
            } else {
                join(bottom, left, graph);
                join(right, top, graph);
            }
        }
        _ => {}
    }
}

/// Root of g on the segment `p0 -> p1` (g0, g1 of opposite signs): Illinois
/// regula falsi, exact to the plane tolerance.
fn edge_root(grid: &Grid, p0: Vec2, p1: Vec2, g0: f64, g1: f64, opts: &SectionOptions) -> Vec2 {
    if g0 == 0.0 || g1 == 0.0 {
        return if g0 == 0.0 { p0 } else { p1 };
    }
    let (mut a, mut b, mut ga, mut gb) = (0.0f64, 1.0f64, g0, g1);
    let mut side = 0i8;
    let mut t = 0.5;
    for _ in 0..200 {
        t = if ga != gb {
            (a * gb - b * ga) / (gb - ga)
        } else {
            0.5 * (a + b)
        };
        if !(t > a && t < b) {
            t = 0.5 * (a + b);
        }
        let gt = grid.eval(p0 + (p1 - p0) * t);
        if gt.abs() <= opts.plane_tol_mm || b - a <= 1e-15 {
            break;
        }
        if grid.positive(gt) == grid.positive(ga) {
            a = t;
            ga = gt;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            b = t;
            gb = gt;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    p0 + (p1 - p0) * t
}
