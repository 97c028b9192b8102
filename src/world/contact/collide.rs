//! The collision check of one probe part beyond the ball (the stylus shaft
//! or the probe body): a solid cylinder against the true (as-machined,
//! trimmed) part, on the contact search's leaves and tree.
//!
//! - **Free air**: the check remembers the cylinder's axis ends at its
//!   last exact check and a lower bound `L` of the cylinder's distance to
//!   the part there. A cylinder whose axis ends moved by at most `m` (and
//!   whose unit axis turned by `|e' - e|`) lies within
//!   `m + radius |e' - e|` of the old one, so no check runs until that
//!   reaches `L`.
//! - **Broad phase**: the leaves whose bound comes within the radius plus
//!   the check's margin (at most [`CollisionOptions::margin_mm`]) of the
//!   axis segment (an exact segment-box distance and the leaf's slab; for
//!   the probe body also how far the leaf lies beyond an end cap's plane,
//!   so a body standing above a part wider than it lists none of the
//!   part); with none, `L` is the nearest leaf bound less the radius. A
//!   leaf whose bound keeps [`CollisionOptions::certify_mm`] from the
//!   cylinder's surface is cleared by its bound alone (a shaft running
//!   0.4 mm beside a wall is cleared this way, without a descent).
//! - **Exact check** (when a leaf's bound comes nearer than that): from
//!   where the last check found its least distance,
//!   then from the cylinder's point nearest to each candidate
//!   leaf's box (nearest bound first, up to the first leaf whose bound
//!   is not below the least distance found: no closer point there), a
//!   descent of the true signed distance over the cylinder.
//!   The distance at a point is the ball contact's point query (Newton on
//!   the true surface, trims honoured exactly, the same sign rule at the
//!   edges), so there is no material over holes and pockets. Each step
//!   tries the cylinder's point closest to the foot (an alternating
//!   projection: exact in one step for a face parallel to the axis or to
//!   an end) and the cylinder's point deepest along the foot's normal (the
//!   support point: exact in one step for a flat face at any angle) and
//!   keeps the better one; where the distance falls towards the support
//!   point but is higher there (a face nearly parallel to the axis that
//!   ends before the cylinder does), a search on the way to it guided by
//!   the distance's slopes ([`super::line`]). The part collides when a point of the cylinder
//!   lies inside the material, or a foot inside the cylinder, by more than
//!   [`CollisionOptions::penetration_mm`].
//! - **Limits**: the descent finds the least distance of the cylinder
//!   near each seed (the leaves are near-flat pieces, over which it has
//!   one minimum); a seed within [`CollisionOptions::seed_merge_mm`] of an
//!   earlier one is not descended from (the distance descended is that of
//!   the whole part, so a descent from it would start in the basin of the
//!   earlier one). The leaves' boxes bound the whole of a leaf crossed by
//!   its trim, over a hole too: they only choose the seeds, the descent's
//!   point queries honour the trims.
mod descent;
#[cfg(test)]
mod tests;

use super::index::{LeafSource, PartIndex};
use super::search::Cursor;
use super::shapes::{CappedAxis, Cylinder};
use super::tree::Shape;
use super::{ContactOptions, TrueContact};
use crate::geometry::{ProjectionError, ProjectionOptions};
use crate::math::{Point3, Vec3};
use crate::workpiece::Workpiece;
use crate::world::as_machined::AsMachined;

/// Tolerances of the collision check of the probe's shaft and body (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionOptions {
    /// Leaves whose bound comes within the part's radius plus the check's
    /// margin (mm) of its axis are checked exactly; after an exact check
    /// the free-air bound is at most that margin. The margin is at most
    /// this.
    pub margin_mm: f64,
    /// The check's margin is [`Self::margin_growth`] times the last
    /// check's free-air bound, but not under this (mm) nor over
    /// [`Self::margin_mm`]: a probe part that runs close beside the part
    /// (a stylus down a small bore) looks only at the leaves near it,
    /// while one in free air keeps the full margin.
    pub min_margin_mm: f64,
    /// See [`Self::min_margin_mm`]: the free-air bound can grow by this
    /// factor from one check to the next.
    pub margin_growth: f64,
    /// A probe part collides once a point of it lies this far (mm) inside
    /// the material, or a point of the part's surface this far inside it:
    /// a touch within this counts as free (the ball's roughness and the
    /// rounding of the distances stay well inside it).
    pub penetration_mm: f64,
    /// The exact check's descent stops when a step gains less than this
    /// (mm); the free-air bound is the least distance found less this or
    /// [`Self::line_tolerance_mm`], the larger.
    pub tolerance_mm: f64,
    /// The search along a descent's support step stops when its best
    /// distance is within this (mm) of the least its slopes allow.
    pub line_tolerance_mm: f64,
    /// Most steps of one descent.
    pub max_steps: usize,
    /// A seed this close (mm) to an earlier one of the same check is not
    /// descended from (it would start in the same basin).
    pub seed_merge_mm: f64,
    /// The point queries of the exact check look this far (mm); a seed
    /// further from the part counts with its leaf's bound.
    pub reach_mm: f64,
    /// A leaf whose bound comes no nearer than this (mm) to the cylinder's
    /// surface is cleared by its bound alone, without a descent (its box
    /// and slab hold the true surface over it, so the bound is a true
    /// lower bound); the free-air bound is then at most that bound.
    pub certify_mm: f64,
    /// The leaves near the axis are listed this many margins (at most
    /// [`Self::max_list_slack_mm`]) beyond what a check needs, and the
    /// list serves the next checks while neither axis end has moved
    /// farther than that (a leaf's bound from the axis changes by at most
    /// the larger end move): a shaft close beside the part lists again
    /// after a short move rather than looking again at every leaf a long
    /// move could have brought near (a list made for a wider margin
    /// serves only while the axis has moved less than this check's
    /// slack).
    pub list_slack_margins: f64,
    /// See [`Self::list_slack_margins`], mm.
    pub max_list_slack_mm: f64,
}

impl Default for CollisionOptions {
    fn default() -> Self {
        CollisionOptions {
            margin_mm: 1.0,
            min_margin_mm: 0.1,
            margin_growth: 4.0,
            penetration_mm: 1e-3,
            tolerance_mm: 1e-4,
            line_tolerance_mm: 1e-3,
            max_steps: 32,
            seed_merge_mm: 1.0,
            reach_mm: 5.0,
            certify_mm: 0.05,
            list_slack_margins: 2.0,
            max_list_slack_mm: 2.0,
        }
    }
}

/// Where a probe part strikes the part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strike {
    /// The contact point on the true part (part frame), mm.
    pub point: Point3,
    /// How deep the probe part is in the material there, mm.
    pub depth_mm: f64,
}

/// A list of leaves near a probe part's axis serves later checks only
/// while the axis vector `b - a` stays within this (mm) of the one it was
/// made for: the rounding of a rigid move, not a turn (see
/// `PartCheck::near_leaves`).
const AXIS_TURN_MM: f64 = 1e-9;

/// No leaf of a part lies farther than this (mm) from a probe part's axis
/// (10 m: beyond any machine's travel); bounds how far a cap's plane
/// swings at a leaf when the axis turns by a rounding.
const PART_REACH_MM: f64 = 1e4;

/// A descent's alternating-projection step shorter than this (mm) that
/// does not point downhill is not looked at.
const SETTLED_STEP_MM: f64 = 0.01;

/// Most looks of the search along a descent's support step.
const LINE_STEPS: usize = 12;

/// The ends of a descent's support step, each with its look (the far
/// end's `None` beyond reach).
type LineEnds = ((Point3, TrueContact), (Point3, Option<TrueContact>));

/// The last exact check: the axis ends, a lower bound of the cylinder's
/// distance to the part (mm), and the factor `2 radius / |b - a|` by which
/// a change of `b - a` turns the cylinder's rim.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Anchor {
    a: Point3,
    b: Point3,
    floor: f64,
    turn: f64,
}

/// The collision check of one probe part.
#[derive(Debug, Clone)]
pub struct PartCheck {
    cursor: Cursor,
    opts: CollisionOptions,
    anchor: Option<Anchor>,
    /// Where the last exact check found its least distance: the axial
    /// coordinate as a fraction of the length, and the radial offset.
    warm: Option<(f64, Vec3)>,
    /// Reused buffers: candidate leaves with their bounds, seeds.
    order: Vec<(f64, u32)>,
    seeds: Vec<Point3>,
    exact_checks: u64,
    /// Leaf bounds the broad phase worked out so far: the leaves listed
    /// and the listed leaves looked at again.
    bounds_looked: u64,
    /// The leaves listed near the axis: the axis ends and the distance
    /// (mm) they were listed within, and the leaves with their bounds
    /// from the axis then (mm).
    listed_at: Option<(Point3, Point3, f64)>,
    listed: Vec<(f64, u32)>,
    /// How far the next point queries look, mm: the full reach for a
    /// descent's first point, then its least distance so far plus the
    /// margin (a farther point cannot lower it).
    reach: f64,
    /// [`ContactOptions::free_air_ratio`].
    free_air_ratio: f64,
    /// Whether the broad phase bounds leaves by the cylinder's end caps
    /// too ([`PartCheck::with_caps`]).
    caps: bool,
    /// The margin of the check running, mm.
    margin: f64,
}

impl PartCheck {
    /// A check that knows nothing yet.
    pub fn new(contact: &ContactOptions, opts: &CollisionOptions) -> PartCheck {
        PartCheck {
            cursor: Cursor::new(contact),
            opts: *opts,
            anchor: None,
            warm: None,
            order: Vec::new(),
            seeds: Vec::new(),
            exact_checks: 0,
            bounds_looked: 0,
            listed_at: None,
            listed: Vec::new(),
            reach: opts.reach_mm,
            free_air_ratio: contact.free_air_ratio,
            margin: opts.margin_mm,
            caps: false,
        }
    }

    /// The check with its broad phase also bounding leaves by how far
    /// they lie beyond the planes of the cylinder's end caps: for a
    /// cylinder wider than the parts below it (a probe body).
    pub fn with_caps(self) -> PartCheck {
        PartCheck { caps: true, ..self }
    }

    /// Forgets what earlier checks learnt.
    pub fn reset(&mut self) {
        self.anchor = None;
        self.warm = None;
        self.listed_at = None;
        self.cursor.reset();
    }

    /// How far below the least distance found the free-air bound is put,
    /// mm.
    fn slack(&self) -> f64 {
        self.opts.tolerance_mm.max(self.opts.line_tolerance_mm)
    }

    /// The margin of the next exact check, mm (see
    /// [`CollisionOptions::min_margin_mm`]).
    fn next_margin(&self) -> f64 {
        let o = &self.opts;
        let last = self.anchor.map_or(o.margin_mm, |k| k.floor);
        (o.margin_growth * last).clamp(o.min_margin_mm, o.margin_mm)
    }

    /// Number of exact checks run so far.
    pub fn exact_checks(&self) -> u64 {
        self.exact_checks
    }

    /// Whether the cylinder round the axis `a..b` (in any one rigid frame,
    /// the same at every call; the radius that of the last exact check)
    /// may have come within reach of the part since the last exact check.
    #[inline(always)]
    pub fn may_touch(&self, a: Point3, b: Point3) -> bool {
        let Some(k) = self.anchor else {
            return true;
        };
        // The axis turns by |e' - e| <= 2 |v' - v| / |v| (v = b - a), which
        // moves the rim by the radius times that.
        let (da, db) = (a - k.a, b - k.b);
        let ends = da.norm_squared().max(db.norm_squared()).sqrt();
        let moved = ends + k.turn * (db - da).norm();
        moved >= k.floor
    }

    /// The exact check of the cylinder `cyl` (part frame) whose axis ends
    /// are `ends` in the frame [`Self::may_touch`] is asked in; the strike
    /// when the cylinder is in the material.
    pub(crate) fn check(
        &mut self,
        (ix, part): (&PartIndex, (&Workpiece, &AsMachined)),
        cyl: &Cylinder,
        ends: (Point3, Point3),
        opts: &ProjectionOptions,
    ) -> Result<Option<Strike>, ProjectionError> {
        self.exact_checks += 1;
        let found = self.exact(ix, part, cyl, opts);
        let floor = match found {
            Ok(Ok(floor)) => floor,
            Ok(Err(_)) | Err(_) => f64::NEG_INFINITY,
        };
        let length = (ends.1 - ends.0).norm();
        self.anchor = Some(Anchor {
            a: ends.0,
            b: ends.1,
            floor,
            turn: if length > 0.0 {
                2.0 * cyl.radius / length
            } else {
                f64::INFINITY
            },
        });
        match found {
            Ok(Ok(_)) => Ok(None),
            Ok(Err(strike)) => Ok(Some(strike)),
            Err(e) => {
                self.reset();
                Err(e)
            }
        }
    }

    /// The strike, or a lower bound of the cylinder's distance to the part.
    fn exact(
        &mut self,
        ix: &PartIndex,
        part: (&Workpiece, &AsMachined),
        cyl: &Cylinder,
        opts: &ProjectionOptions,
    ) -> Result<Result<f64, Strike>, ProjectionError> {
        let seg = cyl.segment();
        let leaves = ix;
        let margin = self.next_margin();
        self.margin = margin;
        let near = cyl.radius + margin;
        let axis = CappedAxis::of(cyl, self.caps);
        self.near_leaves((ix, part), axis, near);
        if self.order.is_empty() {
            // No leaf comes within the margin: the nearest leaf's bound.
            let kept = (cyl.radius, self.free_air_ratio);
            return Ok(Ok(ix.nearest_within(part, axis, kept) - cyl.radius));
        }
        // A leaf whose bound would not clear it: its oriented box may, and
        // for a crossed leaf its trimmed box (the part inside the trim).
        let certify_at = cyl.radius + self.opts.certify_mm;
        for o in &mut self.order {
            let Some(leaf) = leaves.leaf(o.1).filter(|_| o.0 < certify_at) else {
                continue;
            };
            o.0 = leaf.tight_segment_bound(seg.a, seg.b, o.0);
            if o.0 < certify_at && leaf.crossed() {
                let tight = ix.trimmed_bound(o.1, part, seg, certify_at);
                o.0 = o.0.max(tight.unwrap_or(0.0));
            }
        }
        // Nearest bound first; a leaf whose bound is not below the least
        // distance found so far holds no closer point.
        // Only leaves below the certifying distance are ever descended
        // into: the others are sorted no further than the least of them.
        let certify = self.opts.certify_mm;
        let mut rest = f64::INFINITY;
        self.order.retain_mut(|o| {
            o.0 -= cyl.radius;
            let keep = o.0 < certify;
            if !keep {
                rest = rest.min(o.0);
            }
            keep
        });
        self.order.sort_unstable_by(super::near::by_bound);
        let mut floor = margin;
        self.seeds.clear();
        let mut least: Option<(f64, Point3)> = None;
        let nearest = self.order.first().map_or(rest, |o| o.0);
        if nearest >= certify {
            return Ok(Ok(floor.min(nearest)));
        }
        // First from where the last check found its least distance.
        if let Some((s, w)) = self.warm {
            let seed = cyl.closest(cyl.a + cyl.axis * (s * cyl.length) + w);
            self.seeds.push(seed);
            match self.descend(ix, part, cyl, seed, opts)? {
                Ok(Some((d, at))) => {
                    floor = floor.min(d - self.slack());
                    least = Some((d, at));
                }
                Ok(None) => {}
                Err(strike) => return Ok(Err(strike)),
            }
        }
        let mut ended = true;
        for k in 0..self.order.len() {
            let Some(&(bound, id)) = self.order.get(k) else {
                continue;
            };
            if bound >= floor.min(certify) {
                floor = floor.min(bound);
                ended = false;
                break;
            }
            let Some(leaf) = leaves.leaf(id) else {
                continue;
            };
            let (_, s) = super::shapes::segment_box(seg.a, seg.b, &leaf.aabb);
            let x = seg.a + (seg.b - seg.a) * s;
            let on_box = x.sup(&leaf.aabb.min).inf(&leaf.aabb.max);
            let seed = cyl.closest(on_box);
            let merge = self.opts.seed_merge_mm;
            if self.seeds.iter().any(|s| (s - seed).norm() < merge) {
                continue;
            }
            self.seeds.push(seed);
            match self.descend(ix, part, cyl, seed, opts)? {
                Ok(Some((d, at))) => {
                    floor = floor.min(d - self.slack());
                    if least.is_none_or(|l| d < l.0) {
                        least = Some((d, at));
                    }
                }
                Ok(None) => floor = floor.min(bound),
                Err(strike) => return Ok(Err(strike)),
            }
        }
        if ended {
            // The next leaf in order would have been the least of the rest.
            floor = floor.min(rest);
        }
        self.warm = least.map(|(_, at)| {
            let v = at - cyl.a;
            let t = v.dot(&cyl.axis);
            (t / cyl.length.max(1e-300), v - cyl.axis * t)
        });
        Ok(Ok(floor))
    }

    /// Fills `self.order` with every leaf whose bound from `axis` is below
    /// `radius`, with its bound (in no particular order): from the listed
    /// leaves while the list serves, else from the tree (listing again,
    /// [`CollisionOptions::list_slack_margins`] wider). A leaf's bound is the
    /// larger of a box, a slab and an end-cap distance, each moving by at
    /// most the larger end move `m` when the axis moves without turning
    /// (every point of the axis and each cap's plane moves by at most
    /// that), so a listed leaf whose bound then was at least `radius + m`
    /// is left out without looking at it again. An axis that turned (a
    /// head indexed; beyond rounding) lists again: a cap's plane swings
    /// by more than its ends move far from them.
    fn near_leaves(
        &mut self,
        (ix, part): (&PartIndex, (&Workpiece, &AsMachined)),
        axis: CappedAxis,
        radius: f64,
    ) {
        self.order.clear();
        let seg = axis.seg;
        let moved = |(a, b, _): (Point3, Point3, f64)| {
            let turn = ((seg.b - seg.a) - (b - a)).norm();
            if turn > AXIS_TURN_MM {
                return f64::INFINITY;
            }
            // The unit axis turns by at most 2 |dv| / |v|, which moves a
            // cap's plane at a leaf by that times the leaf's distance.
            let swing = 2.0 * turn * PART_REACH_MM / (b - a).norm().max(f64::MIN_POSITIVE);
            (seg.a - a).norm().max((seg.b - b).norm()) + swing
        };
        let o = &self.opts;
        let slack = (o.list_slack_margins * self.margin).min(o.max_list_slack_mm);
        let fresh = (self.listed_at).filter(|l| l.2 - moved(*l) >= radius && moved(*l) <= slack);
        let Some(listed_at) = fresh else {
            let wide = radius + slack;
            ix.within_bounds(part, axis, wide, &mut self.order);
            self.bounds_looked += self.order.len() as u64;
            self.listed.clear();
            self.listed.extend_from_slice(&self.order);
            self.listed_at = Some((seg.a, seg.b, wide));
            self.order.retain(|o| o.0 < radius);
            return;
        };
        let reach = radius + moved(listed_at);
        let r2 = radius * radius;
        for &(then, id) in &self.listed {
            if then >= reach {
                continue;
            }
            let Some(l) = ix.leaf(id) else {
                continue;
            };
            self.bounds_looked += 1;
            match axis.leaf_bound_within(l, r2) {
                Some(bound) if bound < radius => self.order.push((bound, id)),
                _ => {}
            }
        }
    }
}
