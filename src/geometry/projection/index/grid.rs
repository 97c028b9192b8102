//! A uniform grid over a surface's leaf boxes: each cell lists the leaves
//! whose axis-aligned boxes overlap it, so that the leaves near a point
//! come from a cell or a few instead of a walk down the box tree.
use super::Aabb;
use crate::geometry::ProjectionOptions;
use crate::math::Point3;

/// The cells and what they list.
#[derive(Debug, Clone)]
pub(super) struct Grid {
    /// Lower corner of cell (0, 0, 0).
    origin: Point3,
    /// One over the cell size, 1/mm.
    inv_cell: f64,
    /// Cells per axis (all zero for a surface without leaves).
    dims: [usize; 3],
    /// The same as numbers.
    dims_f: [f64; 3],
    /// Where each cell's leaves start in `items` (x fastest); one more
    /// entry than cells.
    starts: Vec<usize>,
    /// Leaf indices, cell after cell.
    items: Vec<usize>,
    /// Per leaf, the first cell its box overlaps along each axis.
    first: Vec<[usize; 3]>,
    /// Most cells a query may span.
    query_cells: usize,
}

/// The cells a query covers.
pub(super) enum Cells {
    /// The query's cube misses the grid: no leaf comes near.
    Miss,
    /// The cells from `lo` to `hi` (inclusive) per axis.
    Range([usize; 3], [usize; 3]),
    /// Too many cells (or a bound that is no number): search the tree.
    Many,
}

impl Grid {
    /// The grid over the leaves' boxes `boxes`.
    pub(super) fn new(boxes: &[Aabb], opts: &ProjectionOptions) -> Grid {
        let mut grid = Grid {
            origin: Point3::origin(),
            inv_cell: 1.0,
            dims: [0; 3],
            dims_f: [0.0; 3],
            starts: vec![0],
            items: Vec::new(),
            first: Vec::new(),
            query_cells: opts.grid_query_cells,
        };
        let Some(root) = boxes.iter().copied().reduce(|a, b| a.union(&b)) else {
            return grid;
        };
        let extent = root.max - root.min;
        let mut sides: Vec<f64> = boxes.iter().map(|b| (b.max - b.min).max()).collect();
        let mid = sides.len() / 2;
        let median = *sides.select_nth_unstable_by(mid, f64::total_cmp).1;
        let mut cell = median * opts.grid_cell_ratio;
        if !(cell.is_finite() && cell > 0.0) {
            cell = extent.max().max(1.0);
        }
        let dims = loop {
            let dims = [0, 1, 2].map(|k| (extent[k] / cell).floor() as usize + 1);
            let count = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
            if count.is_some_and(|n| n <= opts.grid_max_cells.clamp(1, u32::MAX as usize)) {
                break dims;
            }
            cell *= 1.25;
        };
        (grid.origin, grid.inv_cell, grid.dims) = (root.min, 1.0 / cell, dims);
        grid.dims_f = dims.map(|d| d as f64);
        grid.fill(boxes);
        grid
    }

    /// Lists each leaf in the cells its box overlaps (counting first,
    /// then placing).
    fn fill(&mut self, boxes: &[Aabb]) {
        let ranges: Vec<([usize; 3], [usize; 3])> = boxes
            .iter()
            .map(|b| (self.cell_of(b.min), self.cell_of(b.max)))
            .collect();
        let cells = self.dims.iter().product::<usize>();
        let mut counts = vec![0usize; cells + 1];
        for (lo, hi) in &ranges {
            self.for_cells(*lo, *hi, |c| {
                if let Some(n) = counts.get_mut(c + 1) {
                    *n += 1;
                }
            });
        }
        for k in 1..counts.len() {
            counts[k] += counts[k - 1];
        }
        let mut next = counts.clone();
        let mut items = vec![0; counts.last().copied().unwrap_or(0)];
        for (leaf, (lo, hi)) in ranges.iter().enumerate() {
            self.for_cells(*lo, *hi, |c| {
                if let Some(at) = next.get_mut(c) {
                    if let Some(slot) = items.get_mut(*at) {
                        *slot = leaf;
                    }
                    *at += 1;
                }
            });
        }
        self.first = ranges.iter().map(|r| r.0).collect();
        (self.starts, self.items) = (counts, items);
    }

    /// The cell holding `x` (clamped to the grid).
    fn cell_of(&self, x: Point3) -> [usize; 3] {
        [0, 1, 2].map(|k| cell_index((x[k] - self.origin[k]) * self.inv_cell, self.dims[k]))
    }

    /// Calls `f` with the index of every cell from `lo` to `hi`.
    fn for_cells(&self, lo: [usize; 3], hi: [usize; 3], mut f: impl FnMut(usize)) {
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    f(x + self.dims[0] * (y + self.dims[1] * z));
                }
            }
        }
    }

    /// The cells the cube of half side `r` around `p` overlaps.
    pub(super) fn cells_near(&self, p: Point3, r: f64) -> Cells {
        if !(r.is_finite() && p.iter().all(|c| c.is_finite())) {
            return Cells::Many;
        }
        let mut lo = [0; 3];
        let mut hi = [0; 3];
        let mut count = 1usize;
        for k in 0..3 {
            let a = (p[k] - r - self.origin[k]) * self.inv_cell;
            let b = (p[k] + r - self.origin[k]) * self.inv_cell;
            let cells = self.dims_f[k];
            if b < 0.0 || a >= cells {
                return Cells::Miss;
            }
            // Now 0 <= floor of each clamped end < cells <= u32::MAX, so
            // truncation through u32 (cheaper than through usize) is the
            // floor, as `cell_index` has it.
            (lo[k], hi[k]) = (
                a.max(0.0) as u32 as usize,
                b.min(cells - 1.0) as u32 as usize,
            );
            count = count.saturating_mul(hi[k].saturating_sub(lo[k]) + 1);
        }
        if count > self.query_cells {
            return Cells::Many;
        }
        Cells::Range(lo, hi)
    }

    /// Calls `f` once with every leaf listed in the cells from `lo` to
    /// `hi` (a leaf in several of them only in the first it shares with
    /// the range), stopping at the first error.
    pub(super) fn for_leaves<E>(
        &self,
        (lo, hi): ([usize; 3], [usize; 3]),
        mut f: impl FnMut(usize) -> Result<(), E>,
    ) -> Result<(), E> {
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let c = x + self.dims[0] * (y + self.dims[1] * z);
                    let (Some(&a), Some(&b)) = (self.starts.get(c), self.starts.get(c + 1)) else {
                        continue;
                    };
                    for &leaf in self.items.get(a..b).unwrap_or_default() {
                        let first = self.first.get(leaf).copied().unwrap_or_default();
                        let here = [x, y, z];
                        if (0..3).all(|k| first[k].max(lo[k]) == here[k]) {
                            f(leaf)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// The cell of the scaled coordinate `x` along an axis of `dims` cells:
/// `floor(x)` clamped to the grid (truncation is the floor for `x >= 0`;
/// a NaN gives cell 0).
fn cell_index(x: f64, dims: usize) -> usize {
    if x > 0.0 {
        (x as usize).min(dims.saturating_sub(1))
    } else {
        0
    }
}
