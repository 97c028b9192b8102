//! Centring, principal axes and local frames shared by the fits.
use crate::math::{Mat3, Point3, Vec3};

use super::FitError;

/// Points moved so that their centroid is the origin (fits work on these
/// to keep round-off small; results are moved back).
#[derive(Debug, Clone)]
pub(crate) struct Centred {
    /// The centroid of the input, mm.
    pub centroid: Vec3,
    /// The points minus the centroid, mm.
    pub points: Vec<Vec3>,
    /// Largest distance of a point from the centroid, mm.
    pub extent: f64,
    /// Scatter matrix `sum p p^T` of the centred points, mm^2.
    pub scatter: Mat3,
}

impl Centred {
    /// Principal axes of the centred points (from the stored scatter).
    pub fn principal(&self) -> Principal {
        principal_of(self.scatter)
    }
}

/// Checks finiteness and the point count, then centres the points.
pub(crate) fn centre(
    points: &[Point3],
    element: &'static str,
    needed: usize,
) -> Result<Centred, FitError> {
    check_input(points, element, needed)?;
    let centroid = mean_of(points);
    let points: Vec<Vec3> = points.iter().map(|p| p.coords - centroid).collect();
    let parts = super::parallel::map_chunks(&points, extent_and_scatter);
    let init = (0.0f64, Mat3::zeros());
    let (max_sq, scatter) = parts
        .iter()
        .fold(init, |(m, s), (pm, ps)| (m.max(*pm), s + ps));
    let extent = max_sq.sqrt();
    Ok(Centred {
        centroid,
        points,
        extent,
        scatter,
    })
}

/// Largest squared norm and scatter matrix `sum p p^T` of a chunk.
fn extent_and_scatter(chunk: &[Vec3]) -> (f64, Mat3) {
    let max_sq = chunk.iter().map(|q| q.norm_squared()).fold(0.0, f64::max);
    (max_sq, chunk.iter().map(|p| p * p.transpose()).sum())
}

/// Fails on too few points or a non-finite coordinate.
fn check_input(points: &[Point3], element: &'static str, needed: usize) -> Result<(), FitError> {
    let found = points.len();
    if found < needed {
        return Err(FitError::TooFewPoints {
            element,
            needed,
            found,
        });
    }
    let finite = |p: &&Point3| crate::math::all_finite(p.coords.as_slice());
    match points.iter().enumerate().find(|(_, p)| !finite(p)) {
        Some((index, p)) => Err(FitError::NonFinite {
            index,
            x: p.x,
            y: p.y,
            z: p.z,
        }),
        None => Ok(()),
    }
}

/// Points per partial sum of the centroid (keeps round-off at about
/// `log2(n / MEAN_BLOCK) + MEAN_BLOCK` additions instead of `n`).
const MEAN_BLOCK: usize = 256;

/// The centroid by blocked summation (one pass, small round-off).
fn mean_of(points: &[Point3]) -> Vec3 {
    let partial = super::parallel::map_chunks(points, |chunk| {
        let blocks: Vec<Vec3> = chunk
            .chunks(MEAN_BLOCK)
            .map(|c| c.iter().map(|p| p.coords).sum())
            .collect();
        pairwise_sum(&blocks)
    });
    pairwise_sum(&partial) / points.len().max(1) as f64
}

fn pairwise_sum(v: &[Vec3]) -> Vec3 {
    match v {
        [] => Vec3::zeros(),
        [one] => *one,
        _ => {
            let (a, b) = v.split_at(v.len() / 2);
            pairwise_sum(a) + pairwise_sum(b)
        }
    }
}

/// Principal axes of centred points: unit eigenvectors of the scatter
/// matrix, by decreasing spread, and the singular values of the centred
/// point matrix.
#[derive(Debug, Clone)]
pub(crate) struct Principal {
    /// Axes by decreasing spread.
    pub axes: [Vec3; 3],
    /// Singular values by decreasing size, mm.
    pub sigma: [f64; 3],
}

/// Principal axes of centred points.
pub(crate) fn principal(points: &[Vec3]) -> Principal {
    let parts = super::parallel::map_chunks(points, |c| {
        c.iter().map(|p| p * p.transpose()).sum::<Mat3>()
    });
    principal_of(parts.iter().sum())
}

/// Principal axes from a scatter matrix.
fn principal_of(scatter: Mat3) -> Principal {
    let eig = scatter.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let axes = order.map(|i| eig.eigenvectors.column(i).into_owned());
    let sigma = order.map(|i| eig.eigenvalues[i].max(0.0).sqrt());
    Principal { axes, sigma }
}

impl Principal {
    /// Fails when the points coincide or lie on a line.
    pub fn check_spread(
        &self,
        element: &'static str,
        count: usize,
        limit: f64,
    ) -> Result<(), FitError> {
        let spread_mm = self.sigma[0] / (count as f64).sqrt();
        if spread_mm.is_nan() || spread_mm <= 0.0 {
            return Err(FitError::Coincident {
                element,
                count,
                spread_mm,
            });
        }
        let ratio = self.sigma[1] / self.sigma[0];
        if ratio < limit {
            return Err(FitError::Collinear {
                element,
                count,
                ratio,
                limit,
            });
        }
        Ok(())
    }

    /// Fails when the points coincide, lie on a line or in a plane.
    pub fn check_volume(
        &self,
        element: &'static str,
        count: usize,
        limit: f64,
    ) -> Result<(), FitError> {
        self.check_spread(element, count, limit)?;
        let ratio = self.sigma[2] / self.sigma[0];
        if ratio < limit {
            return Err(FitError::Coplanar {
                element,
                count,
                ratio,
                limit,
            });
        }
        Ok(())
    }
}

/// A right-handed orthonormal frame whose third axis is `axis`: rows of the
/// returned matrix are (e1, e2, axis), so `m * v` gives local coordinates.
pub(crate) fn frame_for(axis: &Vec3) -> Mat3 {
    let a = axis.normalize();
    let helper = if a.x.abs() <= a.y.abs() && a.x.abs() <= a.z.abs() {
        Vec3::x()
    } else if a.y.abs() <= a.z.abs() {
        Vec3::y()
    } else {
        Vec3::z()
    };
    let e1 = helper.cross(&a).normalize();
    let e2 = a.cross(&e1);
    Mat3::from_rows(&[e1.transpose(), e2.transpose(), a.transpose()])
}

/// The direction `v` with its largest-magnitude component made positive
/// (the first one on exact ties). This is the sign rule for line
/// directions, plane and circle normals and cylinder axes.
pub fn canonical_sign(v: Vec3) -> Vec3 {
    let idx = v.iamax();
    if v[idx] < 0.0 {
        -v
    } else {
        v
    }
}

/// At most `max` of the points, all of them when there are few enough,
/// else a deterministic low-discrepancy pick (golden-ratio sequence of
/// indices), which does not alias with regular scan patterns the way a
/// fixed stride can.
pub(crate) fn subsample(points: &[Vec3], max: usize) -> Vec<Vec3> {
    if points.len() <= max {
        return points.to_vec();
    }
    const GOLDEN: f64 = 0.618_033_988_749_894_8;
    let n = points.len() as f64;
    (0..max)
        .filter_map(|k| points.get(((k as f64 * GOLDEN).fract() * n) as usize))
        .copied()
        .collect()
}
