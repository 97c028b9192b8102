//! The probe body ([`ProbeBody`]) as the solid cylinder with flat ends it
//! is.
//!
//! From one body radius above the probe mount on, the body lies within its
//! radius of its axis: the area the axis sweeps keeping the radius plus the
//! margin (a capsule whose lower cap ends at the mount, swept) holds that
//! part. The rest is the flat end's region: the points within the radius
//! of the axis from the mount up to one radius (to the top of a body no
//! longer than that). It is checked by the boundary of the region shrunk by
//! an inset `e`: the cylinder `e` less in radius from `e` above the mount,
//! whose points must keep the margin plus `e`, so that the check reaches
//! just the margin below the flat end and beside the side:
//! - standing, and at both ends of a move: its bottom disc, its side, and
//!   its top disc on a body no longer than its radius (the capsule holds
//!   its top otherwise);
//! - along a move: what its bottom rim (and such a body's top rim) sweeps,
//!   and what the two side lines whose normals lie across the move sweep.
//!   The region swept is convex, and a point of its boundary lies on the
//!   region's boundary at an end of the move or on the sweep of a point of
//!   the region with a supporting plane along the move: a rim, one of those
//!   side lines, the whole side on a move along the stylus (held by the
//!   rim's sweep and the side at the upper end) or the whole disc on a move
//!   across it (held by the discs at the ends and the rim's sweep); the
//!   capsule's sweep holds the rest.
//!
//! The round surfaces are cut into arcs of a circle swept, or grown for a
//! disc, along a straight line, and checked as the stylus' area is (see the
//! parent module), each piece judged by its sample alone once it lies
//! within `e` of it. Every sample keeps the margin plus `e`, so every point
//! of the shrunk boundary keeps the margin, and a surface crossing it comes
//! within `e` of a sample and is seen. The boundary is joined to the probe
//! mount in free space, so the part's surface cannot come nearer a point
//! inside without crossing it, unless a whole shell of the design lies
//! inside (a part smaller than the body's radius). Every point of the body
//! lies within `e` of the shrunk region (`e sqrt(2)` on the flat end's rim)
//! and keeps the margin less that. A plane along the flat end or the side
//! keeps the margin exactly (the part farther than the margin below the
//! flat end is clear), and an edge along the rim keeps it less
//! `(sqrt(2) - 1) e` (the shrunk region's rim is round).
//!
//! The inset is `step_mm / sqrt(2)`, at most twice the margin so that an
//! edge along the rim keeps some of it (the finer pieces cost samples only
//! where the part comes that near the flat end).
use super::area::{AreaCheck, AreaPiece};
use super::{Axes, PartClearance, Piece, ProbeBody, Rim};
use crate::math::{Point3, Vec3};
use std::f64::consts::{FRAC_1_SQRT_2, SQRT_2, TAU};

/// Arcs a circle is cut into before it is checked: a quarter's hull (its
/// ends and where the tangents there meet) reaches `sqrt(2) - 1` radii
/// beyond it.
const ARCS: usize = 4;

/// Below this length a vector has no direction: the stylus (mm), and the
/// cross product of the stylus' and the move's unit vectors (a move along
/// the stylus has no side lines).
const MIN_DIRECTION: f64 = 1e-12;

/// Largest inset of the flat end's region, as a share of the body's
/// radius and of its length, so that the shrunk region is not empty.
const MAX_INSET_SHARE: f64 = 0.5;

/// Largest inset of the flat end's region, as a share of the margin it
/// keeps: the rounding of its rim, `sqrt(2) - 1` insets, stays below the
/// margin.
const INSET_PER_MARGIN: f64 = 2.0;

/// Smallest inset of the flat end's region, mm (for a margin of zero).
const MIN_INSET_MM: f64 = 1e-3;

impl PartClearance<'_> {
    /// Whether the body keeps `margin` (mm) from the part while the ball
    /// centre moves from `ends.0` to `ends.1` (machine; standing when they
    /// are the same), to the sampling `step` (mm). A stylus with no
    /// direction or a point not finite is never clear.
    pub(super) fn body_clear(
        &self,
        ends: (Point3, Point3),
        body: &ProbeBody,
        margin: f64,
        step: f64,
    ) -> bool {
        let Some(end) = self.flat_end(ends, body, (margin, step)) else {
            return false;
        };
        self.capsule_clear(ends, body, margin, step) && self.flat_end_clear(&end, margin)
    }

    /// Whether the body's axis from one radius above the mount to its top,
    /// swept, keeps the body radius plus `margin`; a body no longer than
    /// its radius has none.
    fn capsule_clear(
        &self,
        ends: (Point3, Point3),
        body: &ProbeBody,
        margin: f64,
        step: f64,
    ) -> bool {
        let (r, l) = (body.radius_mm, body.length_mm);
        let Some(up) = self.stylus.try_normalize(MIN_DIRECTION) else {
            return false;
        };
        if l <= r {
            return true;
        }
        let (bottom, top) = (self.stylus + up * r, self.stylus + up * l);
        let origin = self.pose.to_part(ends.0 + bottom);
        let area = Piece {
            origin,
            a: self.pose.to_part(ends.1 + bottom) - origin,
            b: self.pose.to_part(ends.0 + top) - origin,
            rim: Rim {
                path: true,
                start: true,
                end: true,
            },
        };
        self.area_clear(area, r + margin, step)
    }

    /// The shrunk flat end's region at the move's start and its move, part
    /// coordinates, for the `margin` and the sampling `step` (mm; `None`:
    /// no stylus direction, a point not finite, or no body).
    fn flat_end(
        &self,
        ends: (Point3, Point3),
        body: &ProbeBody,
        (margin, step): (f64, f64),
    ) -> Option<FlatEnd> {
        let up = self.stylus.try_normalize(MIN_DIRECTION)?;
        let mount = self.pose.to_part(ends.0 + self.stylus);
        let shift = self.pose.to_part(ends.1 + self.stylus) - mount;
        let finite = |v: Vec3| v.iter().all(|x| x.is_finite());
        let (r, l) = (body.radius_mm, body.length_mm);
        let inset = (step * FRAC_1_SQRT_2).min(INSET_PER_MARGIN * margin);
        let inset = inset.max(MIN_INSET_MM).min(MAX_INSET_SHARE * r.min(l));
        if !(finite(mount.coords) && finite(shift) && inset > 0.0) {
            return None;
        }
        let up = self.pose.rotation.transpose() * up;
        let x = up.cross(&least_aligned(up)).normalize();
        let whole = l <= r;
        let top = if whole { l - inset } else { r };
        Some(FlatEnd {
            base: mount + up * inset,
            shift,
            up,
            across: (x, up.cross(&x)),
            radius: r - inset,
            height: top - inset,
            inset,
            whole,
        })
    }

    /// Whether the boundary of the shrunk flat end's region, swept, keeps
    /// `margin` (mm) plus the inset.
    fn flat_end_clear(&self, end: &FlatEnd, margin: f64) -> bool {
        let need = margin + end.inset;
        let mut check = AreaCheck::new(need, end.inset, end.axes());
        if !self.boxes_near(&end.hull(), &mut check) {
            return true;
        }
        let step = end.inset * SQRT_2;
        self.pieces_clear(end.patches(), check)
            && (end.side_lines().into_iter()).all(|line| self.area_clear(line, need, step))
    }
}

/// The world axis least aligned with `v` (one not along it).
fn least_aligned(v: Vec3) -> Vec3 {
    let a = v.abs();
    if a.x <= a.y && a.x <= a.z {
        Vec3::x()
    } else if a.y <= a.z {
        Vec3::y()
    } else {
        Vec3::z()
    }
}

/// The flat end's region of the body shrunk by the inset, and its move,
/// part coordinates.
struct FlatEnd {
    /// The centre of its bottom disc at the start of the move, mm.
    base: Point3,
    /// The move, mm.
    shift: Vec3,
    /// Unit vector along the stylus, away from the ball.
    up: Vec3,
    /// Unit vectors across the stylus, at right angles.
    across: (Vec3, Vec3),
    /// Its radius, mm.
    radius: f64,
    /// Its height, mm.
    height: f64,
    /// How far it lies inside the body's surface, mm.
    inset: f64,
    /// Whether it stands for the whole body (no capsule above it).
    whole: bool,
}

impl FlatEnd {
    /// Whether the move has a length.
    fn moves(&self) -> bool {
        self.shift != Vec3::zeros()
    }

    /// The separating axes of the region's pieces: along the stylus and
    /// across it, and along the move.
    fn axes(&self) -> Axes {
        let along = self.shift.try_normalize(0.0);
        Axes {
            normals: vec![self.up],
            edges: [self.up, self.across.0, self.across.1]
                .into_iter()
                .chain(along)
                .collect(),
        }
    }

    /// Corners of the square prisms round the region at both ends of the
    /// move (their hull holds everything checked).
    fn hull(&self) -> Vec<Point3> {
        let (x, y) = (self.across.0 * self.radius, self.across.1 * self.radius);
        let top = self.up * self.height;
        let mut out = Vec::with_capacity(16);
        for m in [self.base, self.base + self.shift] {
            for corner in [x + y, x - y, y - x, -x - y] {
                out.extend([m + corner, m + corner + top]);
            }
        }
        out
    }

    /// The round surfaces checked, in arcs: the region's boundary at both
    /// ends of the move, then what its rims sweep.
    fn patches(&self) -> Vec<Patch> {
        let top = self.up * self.height;
        let standing = |base: Point3| {
            let lid = self.whole.then(|| self.disc(base + top, None));
            [self.disc(base, Some(1.0)), self.side(base)]
                .into_iter()
                .chain(lid)
        };
        let mut out: Vec<Patch> = standing(self.base).collect();
        if self.moves() {
            out.extend(standing(self.base + self.shift));
            out.push(self.rim_sweep(self.base));
            out.extend(self.whole.then(|| self.rim_sweep(self.base + top)));
        }
        out.into_iter().flat_map(Patch::arcs).collect()
    }

    /// The region's disc centred at `centre` (its rim at `t = 1`, named as
    /// the flat end's by `rim`).
    fn disc(&self, centre: Point3, rim: Option<f64>) -> Patch {
        Patch {
            centre,
            shift: Vec3::zeros(),
            radius: 0.0,
            flare: self.radius,
            across: self.across,
            phi: (0.0, TAU),
            t: (0.0, 1.0),
            rim,
        }
    }

    /// The region's side standing on `base` (its bottom rim at `t = 0`).
    fn side(&self, base: Point3) -> Patch {
        Patch {
            shift: self.up * self.height,
            radius: self.radius,
            flare: 0.0,
            rim: Some(0.0),
            ..self.disc(base, None)
        }
    }

    /// What the rim round `centre` sweeps on the move (its ends are
    /// sampled at the move's ends).
    fn rim_sweep(&self, centre: Point3) -> Patch {
        Patch {
            shift: self.shift,
            rim: None,
            ..self.side(centre)
        }
    }

    /// The areas the two side lines across the move sweep (none when the
    /// move has no length or runs along the stylus).
    fn side_lines(&self) -> Vec<Piece> {
        let across = (self.shift.try_normalize(0.0))
            .and_then(|d| self.up.cross(&d).try_normalize(MIN_DIRECTION));
        let rim = Rim {
            path: true,
            start: true,
            end: true,
        };
        (across.into_iter())
            .flat_map(|e| [e, -e])
            .map(|e| Piece {
                origin: self.base + e * self.radius,
                a: self.shift,
                b: self.up * self.height,
                rim,
            })
            .collect()
    }
}

/// A piece of a round surface: the points `centre + t shift + (radius + t
/// flare) (cos(phi) x + sin(phi) y)` for `phi` in `phi.0..phi.1` and `t` in
/// `t.0..t.1`, with `(x, y) = across`, part coordinates, mm: an arc of a
/// circle swept along `shift`, or grown by `flare` (a disc's sector).
#[derive(Debug, Clone, Copy)]
struct Patch {
    centre: Point3,
    shift: Vec3,
    radius: f64,
    flare: f64,
    across: (Vec3, Vec3),
    phi: (f64, f64),
    t: (f64, f64),
    /// The `t` of the flat end's rim, where the probe comes closest: a
    /// piece that reaches it is sampled there.
    rim: Option<f64>,
}

impl Patch {
    /// The point at `(phi, t)`.
    fn at(&self, phi: f64, t: f64) -> Point3 {
        let e = self.across.0 * phi.cos() + self.across.1 * phi.sin();
        self.centre + self.shift * t + e * (self.radius + self.flare * t)
    }

    /// The whole patch cut into [`ARCS`] arcs.
    fn arcs(self) -> [Patch; ARCS] {
        let (p0, p1) = self.phi;
        let at = |k: usize| p0 + (p1 - p0) * k as f64 / ARCS as f64;
        std::array::from_fn(|k| Patch {
            phi: (at(k), at(k + 1)),
            ..self
        })
    }

    /// Whether the piece reaches the flat end's rim (and is sampled on it).
    fn on_rim(&self) -> bool {
        self.rim.is_some_and(|r| r == self.t.0 || r == self.t.1)
    }

    /// The `t` of the sample: on the rim, else in the middle.
    fn sample_t(&self) -> f64 {
        match self.rim {
            Some(r) if self.on_rim() => r,
            _ => 0.5 * (self.t.0 + self.t.1),
        }
    }
}

impl AreaPiece for Patch {
    type Hull = [Point3; 6];

    /// The arc's ends at both ends of `t`, and where the tangents at its
    /// ends meet (the arc is less than a half circle).
    fn hull(&self) -> [Point3; 6] {
        let (p0, p1) = self.phi;
        let (mid, out) = (0.5 * (p0 + p1), 1.0 / (0.5 * (p1 - p0)).cos());
        let arc = |t: f64| {
            let apex = self.at(mid, t) - self.centre - self.shift * t;
            let c = self.centre + self.shift * t;
            [self.at(p0, t), self.at(p1, t), c + apex * out]
        };
        let ([a, b, c], [d, e, f]) = (arc(self.t.0), arc(self.t.1));
        [a, b, c, d, e, f]
    }

    fn sample(&self) -> Point3 {
        self.at(0.5 * (self.phi.0 + self.phi.1), self.sample_t())
    }

    fn reach(&self) -> f64 {
        let s = AreaPiece::sample(self);
        (self.hull().iter()).fold(0.0, |r, h| r.max((h - s).norm()))
    }

    /// The halves across the longer side, weighted as the stylus' pieces
    /// are (a side counts double when the sample lies at one of its ends);
    /// the half on the rim first.
    fn halves(&self) -> [Patch; 2] {
        let ((p0, p1), (t0, t1)) = (self.phi, self.t);
        let widest = (self.radius + self.flare * t0).max(self.radius + self.flare * t1);
        let arc = 0.5 * widest * (p1 - p0);
        let weight = if self.on_rim() { 1.0 } else { 0.5 };
        let along = weight * (t1 - t0) * (self.shift.norm() + self.flare.abs());
        if arc >= along {
            let pm = 0.5 * (p0 + p1);
            [(p0, pm), (pm, p1)].map(|phi| Patch { phi, ..*self })
        } else {
            let tm = 0.5 * (t0 + t1);
            let halves = [(t0, tm), (tm, t1)].map(|t| Patch { t, ..*self });
            match self.rim {
                Some(r) if r == t1 => [halves[1], halves[0]],
                _ => halves,
            }
        }
    }
}

#[cfg(test)]
mod tests;
