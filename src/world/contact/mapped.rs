//! A piece's bounds on the image of its control points under the linear
//! part `L` of a true part's transform `T(x) = L x + t`, made once for
//! every part with that `L` (a batch's variants differ in `t` and in the
//! form's size only): each part places them at its own `t` and widens
//! them by its own form bound.
//!
//! Moving points by `t` moves their axis-aligned box by `t` and their
//! extent along any unit direction `e` by `e . t`, so the slab and the
//! oriented box of the mapped control points need no new look at them.
use std::sync::{Arc, Mutex};

use super::leaves::{Aabb, Obb, Piece, Slab};
use crate::math::{Mat3, Point3, Vec3};

/// A piece's bounds under `L` alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Shape {
    aabb: Aabb,
    slab: Slab,
    obb: Option<Obb>,
}

/// The bounds of a leaf: its box, slab and oriented box.
pub(super) type Placed = (Aabb, Slab, Option<Obb>);

impl Shape {
    /// The bounds of `piece`'s control points mapped by `linear`;
    /// `mapped` is room for them.
    fn of(piece: &Piece, linear: &Mat3, mapped: &mut Vec<Point3>) -> Shape {
        mapped.clear();
        piece.control_points(|p| mapped.push(Point3::from(linear * p.coords)));
        let aabb = Aabb::of(mapped.iter().copied());
        let slab = Slab::of(mapped, piece.degree);
        let obb = Obb::of(mapped, piece.degree, &slab);
        Shape { aabb, slab, obb }
    }

    /// The bounds moved by `t` and widened by `inflate` (mm) on every side.
    pub(super) fn placed(&self, t: Vec3, inflate: f64) -> Placed {
        let grow = Vec3::repeat(inflate);
        let aabb = Aabb {
            min: self.aabb.min + t - grow,
            max: self.aabb.max + t + grow,
        };
        let slab = self.slab.moved(t, inflate);
        let obb = self.obb.map(|o| o.moved(t, inflate));
        (aabb, slab, obb)
    }
}

/// The shapes of every piece for one linear map.
type Held = Option<([u64; 9], Arc<Vec<Shape>>)>;

/// The shapes last made for a set of pieces, with the linear map they
/// were made for.
#[derive(Default)]
pub(super) struct ShapeCache(Mutex<Held>);

impl ShapeCache {
    /// The shapes of `pieces` under `linear`, made on first use.
    pub(super) fn shapes(&self, pieces: &[Piece], linear: &Mat3) -> Arc<Vec<Shape>> {
        let key: [u64; 9] =
            std::array::from_fn(|k| linear.as_slice().get(k).map_or(0, |x| x.to_bits()));
        if let Ok(held) = self.0.lock() {
            if let Some((_, s)) = held.as_ref().filter(|(k, _)| *k == key) {
                return Arc::clone(s);
            }
        }
        let mut mapped = Vec::new();
        let made: Arc<Vec<Shape>> = Arc::new(
            (pieces.iter())
                .map(|p| Shape::of(p, linear, &mut mapped))
                .collect(),
        );
        if let Ok(mut held) = self.0.lock() {
            *held = Some((key, Arc::clone(&made)));
        }
        made
    }
}

/// A cache is no part of the pieces' value: copies start empty and
/// compare equal.
impl Clone for ShapeCache {
    fn clone(&self) -> ShapeCache {
        ShapeCache::default()
    }
}

impl PartialEq for ShapeCache {
    fn eq(&self, _: &ShapeCache) -> bool {
        true
    }
}

impl std::fmt::Debug for ShapeCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("ShapeCache")
    }
}

impl Slab {
    /// The slab round `points` (a row-major net of the degrees `[p, q]`)
    /// normal to the cross product of its diagonals (the whole space when
    /// that vanishes).
    fn of(points: &[Point3], [p, q]: [usize; 2]) -> Slab {
        let everywhere = Slab {
            normal: Vec3::z(),
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        };
        let corners = (
            points.first(),
            points.last(),
            points.get(q),
            points.get(p * (q + 1)),
        );
        let (Some(&c00), Some(&c11), Some(&c01), Some(&c10)) = corners else {
            return everywhere;
        };
        let Some(normal) = (c11 - c00).cross(&(c01 - c10)).try_normalize(1e-12) else {
            return everywhere;
        };
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                let s = p.coords.dot(&normal);
                (l.min(s), h.max(s))
            });
        Slab { normal, lo, hi }
    }

    /// The slab moved by `t` and widened by `inflate` on both sides.
    fn moved(&self, t: Vec3, inflate: f64) -> Slab {
        let shift = self.normal.dot(&t);
        Slab {
            normal: self.normal,
            lo: self.lo + shift - inflate,
            hi: self.hi + shift + inflate,
        }
    }
}

impl Obb {
    /// The oriented box of the control points `points` (whose hull holds
    /// the surface; a row-major net of the degrees `[p, q]`) in the frame
    /// of `slab`'s normal and the net's mean direction along `u` across
    /// it (the two `u` sides of the net, corner to corner): a piece of a
    /// plane, cylinder or cone, whose parameter lines run along and
    /// round it, is boxed tightly both ways. Along the normal it is the
    /// slab itself (`None` without a normal or with the `u` sides along
    /// it).
    fn of(points: &[Point3], [p, q]: [usize; 2], slab: &Slab) -> Option<Obb> {
        let n = slab.normal;
        if !(slab.lo.is_finite() && slab.hi.is_finite()) {
            return None;
        }
        let corner = |i: usize, j: usize| points.get(i * (q + 1) + j).copied();
        let d = (corner(p, 0)? - corner(0, 0)?) + (corner(p, q)? - corner(0, q)?);
        let t = (d - n * d.dot(&n)).try_normalize(1e-12)?;
        let axes = [n, t, n.cross(&t)];
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for (k, e) in [t, axes[2]].iter().enumerate() {
                let s = p.coords.dot(e);
                (lo[k], hi[k]) = (lo[k].min(s), hi[k].max(s));
            }
        }
        Some(Obb {
            axes,
            lo: Point3::new(slab.lo, lo[0], lo[1]),
            hi: Point3::new(slab.hi, hi[0], hi[1]),
        })
    }

    /// The box moved by `t` and widened by `inflate` on every side.
    fn moved(&self, t: Vec3, inflate: f64) -> Obb {
        let shift = Vec3::from(self.axes.map(|e| e.dot(&t)));
        let grow = Vec3::repeat(inflate);
        Obb {
            axes: self.axes,
            lo: self.lo + shift - grow,
            hi: self.hi + shift + grow,
        }
    }
}
