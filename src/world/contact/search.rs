//! The per-cycle search state: the free-air bound, the list of leaves near
//! the ball, the leaves' warm feet, and the near search with its sign rule.
use super::index::{LeafSource, PartIndex};
use super::leaves::Leaf;
use super::near::NearList;
use super::{ContactOptions, TrueContact};
use crate::geometry::projection::{local_minimum, local_minimum_cached, Foot};
use crate::geometry::{Jet2, ProjectionError, ProjectionOptions};
use crate::math::{Point3, Vec2};
use crate::workpiece::Workpiece;
use crate::world::as_machined::AsMachined;

/// Two opposite sides of a domain that meet within this (mm) at a foot are
/// one (the seam of a closed surface), and a side that moves less than
/// this over a hundredth of its parameter range is a point (a pole).
const SIDE_GLUE_MM: f64 = 1e-6;

/// Leaves whose last foot is kept for a warm start.
const WARM_SLOTS: usize = 8;

/// The slack of the list after one of `listed` leaves made with `slack`
/// (see [`ContactOptions::slack_mm`]).
fn next_slack(opts: &ContactOptions, slack: f64, listed: usize) -> f64 {
    if listed > opts.dense_list {
        (0.5 * slack).max(opts.min_slack_mm)
    } else if 4 * listed < opts.dense_list {
        (2.0 * slack).min(opts.slack_mm)
    } else {
        slack
    }
}

/// Taken off a leaf's warm bound for the rounding of the distances, mm.
const WARM_BOUND_ROUNDING_MM: f64 = 1e-9;

/// One leaf's last foot.
#[derive(Debug, Clone, Copy)]
struct WarmFoot {
    leaf: u32,
    foot: Foot,
    /// The query point the foot was found for.
    at: Point3,
    /// The query that last used it.
    stamp: u64,
}

impl WarmFoot {
    /// A lower bound of the leaf's distance from `y`, mm: a confirmed
    /// foot's distance from where it was found less how far `y` lies from
    /// there (the distance to a fixed set is 1-Lipschitz); none for an
    /// unconfirmed foot (its distance bounds the leaf's from above only).
    fn bound_at(&self, y: Point3) -> Option<f64> {
        let d = self.foot.dist2.sqrt();
        let moved = (y - self.at).norm();
        (self.foot.status.is_confirmed()).then_some(d - moved - WARM_BOUND_ROUNDING_MM)
    }
}

/// A foot that takes part in the answer.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    leaf: u32,
    face: usize,
    foot: Foot,
    edge: bool,
}

/// The state of one stream of point queries on a [`PartIndex`]: the
/// free-air bound, the list of near leaves, the warm feet.
#[derive(Debug, Clone)]
pub struct Cursor {
    opts: ContactOptions,
    /// A point and a lower bound of the true distance from it, mm.
    anchor: Option<(Point3, f64)>,
    /// The leaves near the ball, in order of bound at each query.
    near: NearList,
    /// The slack of the next list, mm ([`ContactOptions::slack_mm`]).
    slack: f64,
    warm: Vec<WarmFoot>,
    stamp: u64,
    /// The leaf of the last answer: searched first, its foot is the best
    /// distance to beat from the start.
    last: Option<u32>,
    /// Reused buffers: the candidates, the leaves whose foot left their
    /// face's trim.
    found: Vec<Candidate>,
    off_trim: Vec<u32>,
}

/// The contact search of one simulated machine (see the module docs of
/// [`super`]).
#[derive(Debug, Clone)]
pub struct ContactSearch {
    index: PartIndex,
    cursor: Cursor,
}

impl ContactSearch {
    /// The search for the part `wp` as machined by `am`.
    pub fn new(wp: &Workpiece, am: &AsMachined, opts: &ContactOptions) -> ContactSearch {
        ContactSearch {
            index: PartIndex::new(wp, am, &opts.leaves),
            cursor: Cursor::new(opts),
        }
    }

    /// Number of leaves made so far (a face's are made when a query
    /// first comes near it).
    pub fn leaf_count(&self) -> usize {
        self.index.leaves_made()
    }

    /// The part's leaves and tree.
    pub(crate) fn index(&self) -> &PartIndex {
        &self.index
    }

    /// Forgets what earlier queries learnt (the answers stay the same).
    pub fn reset(&mut self) {
        self.cursor.reset();
    }

    /// A stream of queries of its own on this search's part (another
    /// thread's, say), knowing nothing yet: [`Self::query_on`].
    pub fn cursor(&self) -> Cursor {
        Cursor::new(&self.cursor.opts)
    }

    /// [`Self::query`] of the stream `cursor` (made by [`Self::cursor`]).
    pub fn query_on(
        &self,
        cursor: &mut Cursor,
        part: (&Workpiece, &AsMachined),
        y: Point3,
        reach: f64,
        opts: &ProjectionOptions,
    ) -> Result<Option<TrueContact>, ProjectionError> {
        cursor.query(&self.index, part, y, reach, opts)
    }

    /// The closest point of the true part to `y` (part frame) when it comes
    /// closer than `reach` (mm), else `None` (every point of the part is at
    /// least `reach` away). `opts` are the Newton tolerances.
    #[inline(always)]
    pub fn query(
        &mut self,
        part: (&Workpiece, &AsMachined),
        y: Point3,
        reach: f64,
        opts: &ProjectionOptions,
    ) -> Result<Option<TrueContact>, ProjectionError> {
        self.cursor.query(&self.index, part, y, reach, opts)
    }
}

impl Cursor {
    /// A cursor that knows nothing yet.
    pub(crate) fn new(opts: &ContactOptions) -> Cursor {
        Cursor {
            opts: *opts,
            anchor: None,
            near: NearList::default(),
            slack: opts.slack_mm,
            warm: Vec::with_capacity(WARM_SLOTS),
            stamp: 0,
            last: None,
            found: Vec::new(),
            off_trim: Vec::new(),
        }
    }

    /// Forgets what earlier queries learnt (the answers stay the same).
    pub(crate) fn reset(&mut self) {
        self.anchor = None;
        self.near.clear();
        self.slack = self.opts.slack_mm;
        self.warm.clear();
        self.last = None;
    }

    /// [`ContactSearch::query`] on the index `ix`.
    #[inline(always)]
    pub(crate) fn query(
        &mut self,
        ix: &PartIndex,
        (wp, am): (&Workpiece, &AsMachined),
        y: Point3,
        reach: f64,
        opts: &ProjectionOptions,
    ) -> Result<Option<TrueContact>, ProjectionError> {
        if let Some((a, floor)) = self.anchor {
            if floor - (y - a).norm() >= reach {
                return Ok(None);
            }
        }
        self.near_query(ix, (wp, am), y, reach, opts)
    }

    /// [`Self::query`] once the free-air bound no longer rules out a
    /// contact.
    #[inline(never)]
    fn near_query(
        &mut self,
        ix: &PartIndex,
        (wp, am): (&Workpiece, &AsMachined),
        y: Point3,
        reach: f64,
        opts: &ProjectionOptions,
    ) -> Result<Option<TrueContact>, ProjectionError> {
        if !y.iter().all(|c| c.is_finite()) {
            return Err(ProjectionError::NotFinite {
                x: y.x,
                y: y.y,
                z: y.z,
            });
        }
        // The list made at `a` within `listed` holds every leaf whose bound
        // at `y` is below `listed - |y - a|`: it serves while that is at
        // least what the search looks at.
        let needed = reach + self.opts.edge_tie_mm;
        let fresh = self.near.margin_at(y).is_some_and(|m| m >= needed);
        if !fresh {
            let listed = needed + 2.0 * self.slack;
            let fill = |out: &mut Vec<(f64, u32)>| ix.within_bounds((wp, am), y, listed, out);
            let any = self.near.list(y, listed, fill);
            self.slack = next_slack(&self.opts, self.slack, self.near.len());
            if !any {
                let kept = (reach, self.opts.free_air_ratio);
                let floor = ix.nearest_within((wp, am), y, kept);
                self.anchor = Some((y, floor));
                return Ok(None);
            }
        }
        let off_list = self.near.margin_at(y).unwrap_or(0.0);
        let floor = self.search(ix, (wp, am), y, reach, opts);
        self.anchor = Some((y, floor.min(off_list)));
        let answer = self.answer(wp, am, y, reach);
        self.last = answer.map(|(_, leaf)| leaf);
        Ok(answer.map(|(c, _)| c))
    }

    /// Fills `self.found` with the feet that may take part in the answer
    /// (within the edge tie of the least distance below `reach`); returns
    /// a lower bound of the distance from `y` over the listed leaves.
    fn search(
        &mut self,
        ix: &PartIndex,
        (wp, am): (&Workpiece, &AsMachined),
        y: Point3,
        reach: f64,
        opts: &ProjectionOptions,
    ) -> f64 {
        let tie = self.opts.edge_tie_mm;
        self.stamp += 1;
        self.found.clear();
        self.off_trim.clear();
        let leaves = ix;
        // The last answer's leaf first: the ball mostly stays over it, and
        // its distance then clears the neighbours whose bounds reach under
        // the ball (nearest bound first after it, as the loop ends at the
        // first bound beyond the best).
        let first = (self.last)
            .filter(|&l| self.near.holds(leaves, l))
            .and_then(|l| leaves.leaf(l).map(|leaf| (leaf.lower_bound(y), l)))
            .filter(|&(b, _)| b < reach + tie);
        self.near
            .start(leaves, y, reach + tie, first.map(|(_, l)| l));
        let mut floor = reach + tie;
        let mut best = f64::INFINITY;
        let mut taken = first;
        while let Some((b, id)) = taken.take().or_else(|| self.near.pop(leaves)) {
            let limit = best.min(reach) + tie;
            if b >= limit {
                floor = floor.min(b);
                break;
            }
            let Some(leaf) = leaves.leaf(id) else {
                continue;
            };
            // The oriented box clears most of the neighbours of the leaf
            // the ball is over (whose slab and box reach under it).
            let tight = leaf.tight_bound(y, b);
            if tight >= limit {
                floor = floor.min(tight);
                continue;
            }
            // A neighbour the ball passes by keeps its last foot's
            // distance less the way come since: no Newton while that
            // clears it.
            if let Some(kept) = warm_bound(&mut self.warm, id, y, self.stamp) {
                if kept >= limit {
                    floor = floor.min(kept);
                    continue;
                }
            }
            let warm = (&mut self.warm, self.stamp, id);
            let foot = leaf_foot((ix, wp, am), leaf, warm, y, opts);
            let d = foot.dist2.sqrt();
            // An unconfirmed foot is a point of the surface, so its
            // distance bounds the leaf's from above only: the leaf's own
            // bound stands in for it below.
            floor = floor.min(if foot.status.is_confirmed() { d } else { b });
            if d >= limit {
                continue;
            }
            let face = leaf.face;
            let on_face =
                !leaf.crossed() || wp.faces.get(face).is_some_and(|f| f.contains(foot.uv));
            if on_face {
                let edge = on_domain_side(wp, face, foot.uv);
                self.found.push(Candidate {
                    leaf: id,
                    face,
                    foot,
                    edge,
                });
                best = best.min(d);
                continue;
            }
            // The foot leaves the trim: the leaf's closest point on the
            // face lies on its trim boundary, searched once every leaf's
            // foot is known (the nearest of them prunes most segments).
            self.off_trim.push(id);
        }
        self.boundary_feet(ix, (wp, am), y, reach, opts, &mut best);
        floor.min(best)
    }

    /// Adds the trim-boundary feet of the leaves in `self.off_trim` that
    /// come within the edge tie of `best` (lowered as they are found),
    /// skipping every segment whose chord keeps farther.
    fn boundary_feet(
        &mut self,
        ix: &PartIndex,
        (wp, am): (&Workpiece, &AsMachined),
        y: Point3,
        reach: f64,
        opts: &ProjectionOptions,
        best: &mut f64,
    ) {
        let tie = self.opts.edge_tie_mm;
        for &id in &self.off_trim {
            let Some(leaf) = ix.leaf(id) else {
                continue;
            };
            let face = leaf.face;
            for (seg, chord) in ix.trim_chords(id, am) {
                if chord.lower_bound(y) >= best.min(reach) + tie {
                    continue;
                }
                let f = am.closest_on_segment(wp, face, seg, y, opts);
                let df = f.dist2.sqrt();
                if df < best.min(reach) + tie {
                    self.found.push(Candidate {
                        leaf: id,
                        face,
                        foot: f,
                        edge: true,
                    });
                    *best = best.min(df);
                }
            }
        }
    }

    /// The answer from `self.found`: the closest foot, signed by the sign
    /// rule at a face boundary, with the leaf it was found on.
    fn answer(
        &self,
        wp: &Workpiece,
        am: &AsMachined,
        y: Point3,
        reach: f64,
    ) -> Option<(TrueContact, u32)> {
        let best = self
            .found
            .iter()
            .min_by(|a, b| (a.foot.dist2.total_cmp(&b.foot.dist2)).then(a.face.cmp(&b.face)))?;
        let tp = am.finish_foot(wp, y, best.face, &best.foot);
        if tp.distance >= reach {
            return None;
        }
        let away = (y - tp.point).try_normalize(1e-12).unwrap_or(tp.normal);
        let (distance, push) = if !best.edge {
            (tp.signed_distance, tp.normal)
        } else if self.sign_inside(wp, am, y, best) {
            (-tp.distance, -away)
        } else {
            (tp.distance, away)
        };
        let contact = TrueContact {
            face: best.face,
            uv: tp.uv,
            point: tp.point,
            distance,
            push,
            edge: best.edge,
        };
        Some((contact, best.leaf))
    }

    /// Whether `y` lies inside the material by the sign rule at the
    /// boundary foot `best`: among the feet on other faces within the edge
    /// tie of it (and `best` itself), the one whose outward normal is best
    /// aligned with its offset from `y` decides; with no other face near,
    /// or none whose normal leans from the offset's perpendicular by
    /// [`SIGN_MIN_COS`], outside.
    fn sign_inside(&self, wp: &Workpiece, am: &AsMachined, y: Point3, best: &Candidate) -> bool {
        let tie = self.opts.edge_tie_mm;
        let d = best.foot.dist2.sqrt();
        let near = |c: &&Candidate| c.foot.dist2.sqrt() <= d + tie;
        if !self.found.iter().filter(near).any(|c| c.face != best.face) {
            return false;
        }
        let mut decisive = (f64::NEG_INFINITY, false);
        for c in self.found.iter().filter(near) {
            let tp = am.finish_foot(wp, y, c.face, &c.foot);
            let offset = y - tp.point;
            let cos = offset.dot(&tp.normal) / offset.norm().max(1e-300);
            if cos.abs() > decisive.0 {
                decisive = (cos.abs(), cos < 0.0);
            }
        }
        decisive.0 >= SIGN_MIN_COS && decisive.1
    }
}

/// The least `|cos|` between a boundary foot's outward normal and the
/// ball's offset from it that decides the sign at an edge (about 6
/// degrees off the face's plane). Feet whose offset runs along their face
/// say nothing of the side: the ball stands beyond their edge, over the
/// face's extension. The as-machined form moves each face along its own
/// normal, so the faces of an edge part by micrometres (a bore's rim
/// standing over the top face that an offset lowered), and a ball coming
/// down over such a rim on the seam of two half bores finds only their
/// rims, the offset all but tangent to both: outside, not 1 mm inside.
const SIGN_MIN_COS: f64 = 0.1;

/// Newton on the true surface over `leaf` (number `id`), warm from its
/// last foot among `warm` when it has one (which `stamp` marks used).
///
/// Always a point of the surface: a warm foot that Newton cannot confirm
/// (a pole, where one parameter collapses) is tried again from the leaf's
/// own start and the closer of the two kept, confirmed or not. The ball
/// then still feels the surface it touches; an unconfirmed foot's
/// distance is at most a Newton tolerance above the leaf's least.
fn leaf_foot(
    (ix, wp, am): (&PartIndex, &Workpiece, &AsMachined),
    leaf: &Leaf,
    (warm, stamp, id): (&mut Vec<WarmFoot>, u64, u32),
    y: Point3,
    opts: &ProjectionOptions,
) -> Foot {
    let face = leaf.face;
    let eval = |uv: Vec2, out: &mut Jet2| am.true_jet_into(wp, face, uv, out);
    let start = || leaf.start(y, &ix.true_samples(id, (wp, am)));
    if let Some(w) = warm.iter_mut().find(|w| w.leaf == id) {
        w.stamp = stamp;
        w.at = y;
        local_minimum_cached(eval, y, &mut w.foot, &leaf.bounds, opts);
        if !w.foot.status.is_confirmed() {
            let cold = local_minimum(eval, y, start(), &leaf.bounds, opts);
            if cold.dist2 < w.foot.dist2 {
                w.foot = cold;
            }
        }
        return w.foot;
    }
    let foot = local_minimum(eval, y, start(), &leaf.bounds, opts);
    remember(
        warm,
        WarmFoot {
            leaf: id,
            foot,
            at: y,
            stamp,
        },
    );
    foot
}

/// The warm bound ([`WarmFoot::bound_at`]) of leaf `id` at `y` when it
/// has a warm foot, which `stamp` then marks used.
fn warm_bound(warm: &mut [WarmFoot], id: u32, y: Point3, stamp: u64) -> Option<f64> {
    let w = warm.iter_mut().find(|w| w.leaf == id)?;
    w.stamp = stamp;
    w.bound_at(y)
}

/// Keeps `w` among the warm feet, in place of the one unused longest.
fn remember(warm: &mut Vec<WarmFoot>, w: WarmFoot) {
    if warm.len() < WARM_SLOTS {
        warm.push(w);
        return;
    }
    if let Some(oldest) = warm.iter_mut().min_by_key(|x| x.stamp) {
        *oldest = w;
    }
}

/// Whether `uv` lies on a side of the parameter domain of `face` that is
/// an edge of the face (a boundary no trim segment stands for): not a side
/// that collapses to a point (a pole) and not one glued to the opposite
/// side (the seam of a closed surface), which lie inside the face.
fn on_domain_side(wp: &Workpiece, face: usize, uv: Vec2) -> bool {
    let Some(f) = wp.faces.get(face) else {
        return true;
    };
    let s = &f.surface;
    let ((u0, u1), (v0, v1)) = s.domain();
    let open = |k: usize, lo: f64, hi: f64| {
        let at = uv[k];
        if at > lo && at < hi {
            return false;
        }
        let mut other = uv;
        other[k] = if at <= lo { hi } else { lo };
        let (a, b) = (s.point(uv.x, uv.y), s.point(other.x, other.y));
        // Along the side: the other parameter moved by a hundredth of its
        // range; a collapsed side does not move.
        let j = 1 - k;
        let (lo_j, hi_j) = if j == 0 { (u0, u1) } else { (v0, v1) };
        let mut along = uv;
        along[j] = if uv[j] - lo_j > hi_j - uv[j] {
            uv[j] - 0.01 * (hi_j - lo_j)
        } else {
            uv[j] + 0.01 * (hi_j - lo_j)
        };
        let c = s.point(along.x, along.y);
        (b - a).norm() > SIDE_GLUE_MM && (c - a).norm() > SIDE_GLUE_MM
    };
    open(0, u0, u1) || open(1, v0, v1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense list halves the next slack down to the least, a sparse one
    /// doubles it back up to the most; one between keeps it.
    #[test]
    fn the_slack_follows_how_many_leaves_a_list_holds() {
        let o = ContactOptions::default();
        let dense = o.dense_list + 1;
        let mut s = o.slack_mm;
        let mut seen = vec![s];
        while s > o.min_slack_mm {
            s = next_slack(&o, s, dense);
            seen.push(s);
        }
        assert_eq!(seen, vec![0.3, 0.15, 0.075, 0.0375, 0.02]);
        assert_eq!(next_slack(&o, s, o.dense_list / 2), s);
        while s < o.slack_mm {
            s = next_slack(&o, s, 0);
        }
        assert_eq!(s, o.slack_mm);
    }
}
