//! The search of one leaf (bounded Newton from its nearest samples, with
//! restarts when the first start cannot be confirmed) and the bookkeeping
//! of a search's status.
use super::{Leaf, LeafMemo, ProjectionIndex, SearchStatus};
use crate::geometry::projection::newton::{local_minimum, Foot};
use crate::geometry::{Jet2, NurbsSurface, ProjectionError, Trim};
use crate::math::{Point3, Vec2};

/// A leaf whose foot could not be confirmed: how close its points may
/// still come (mm: the foot's distance less its last Newton step) and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Doubt {
    floor: f64,
    status: SearchStatus,
}

impl Doubt {
    /// The doubt of an unconfirmed foot (`None` for a confirmed one).
    fn of(foot: &Foot) -> Option<Doubt> {
        match foot.status {
            SearchStatus::Confirmed => None,
            SearchStatus::Unconfirmed { last_step_mm, .. } => Some(Doubt {
                floor: foot.dist2.sqrt() - last_step_mm,
                status: foot.status,
            }),
        }
    }

    /// The doubt with the lower floor.
    pub(crate) fn least(a: Option<Doubt>, b: Option<Doubt>) -> Option<Doubt> {
        match (a, b) {
            (Some(x), Some(y)) => Some(if y.floor < x.floor { y } else { x }),
            (x, None) => x,
            (None, y) => y,
        }
    }
}

/// The best foot of a search so far (with the leaf it came from, `None`
/// on the trim boundary), the squared distance a better one must beat, and
/// the doubt left by leaves that could not be confirmed.
pub(crate) struct Best {
    pub(crate) dist2: f64,
    pub(crate) found: Option<(Option<usize>, Foot)>,
    pub(crate) doubt: Option<Doubt>,
}

impl Best {
    /// Nothing found yet; a foot must beat `dist2`.
    pub(crate) fn new(dist2: f64) -> Best {
        Best {
            dist2,
            found: None,
            doubt: None,
        }
    }

    /// The search's answer: unconfirmed when the best foot is, or when a
    /// doubtful leaf may come closer than it (than the bound, when nothing
    /// was found).
    pub(crate) fn finish(self) -> Searched {
        let own = self
            .found
            .as_ref()
            .map_or(SearchStatus::Confirmed, |f| f.1.status);
        let doubt = (self.doubt)
            .filter(|d| d.floor < self.dist2.sqrt() || d.floor.is_nan())
            .map_or(SearchStatus::Confirmed, |d| d.status);
        Searched {
            found: self.found,
            status: own.and(doubt),
        }
    }
}

/// The outcome of a search of one surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Searched {
    /// The closest point found closer than the bound, with its leaf
    /// (`None` on the trim boundary).
    pub(crate) found: Option<(Option<usize>, Foot)>,
    /// Whether the search is confirmed (unconfirmed also when nothing was
    /// found but a leaf that could not be confirmed may hold a point closer
    /// than the bound).
    pub(crate) status: SearchStatus,
}

impl Searched {
    /// Nothing to search.
    pub(crate) fn nothing() -> Searched {
        Searched {
            found: None,
            status: SearchStatus::Confirmed,
        }
    }

    /// The foot found, carrying the status of the whole search.
    pub(crate) fn into_found(self) -> Option<(Option<usize>, Foot)> {
        self.found.map(|(leaf, mut foot)| {
            foot.status = foot.status.and(self.status);
            (leaf, foot)
        })
    }
}

impl ProjectionIndex {
    /// The closest point of leaf `leaf` (on the face, with a trim) closer
    /// than `sqrt(best_dist2)`, and the doubt the leaf leaves when its
    /// foot could not be confirmed; skipped (nothing, no doubt) when
    /// `memo` knows the leaf to be far enough. On an untrimmed surface a
    /// confirmed foot's distance is noted in `memo`.
    pub(super) fn leaf_search(
        &self,
        surface: &NurbsSurface,
        trim: Option<&Trim>,
        leaf: usize,
        (p, best_dist2): (Point3, f64),
        memo: &mut dyn LeafMemo,
    ) -> Result<(Option<Foot>, Option<Doubt>), ProjectionError> {
        let Some(l) = self.leaves.get(leaf) else {
            return Ok((None, None));
        };
        if l.obb.dist2(p) >= best_dist2 {
            return Ok((None, None));
        }
        if trim.is_some_and(|t| !t.may_touch(l.bounds.lo, l.bounds.hi)) {
            return Ok((None, None));
        }
        let floor = memo.floor(leaf, p);
        if floor > 0.0 && floor * floor >= best_dist2 {
            return Ok((None, None));
        }
        let foot = self.leaf_minimum(surface, l, p);
        if trim.is_none() && foot.status.is_confirmed() {
            memo.note(leaf, p, foot.dist2.sqrt());
        }
        let on_face = trim.is_none_or(|t| t.contains(foot.uv));
        let better = on_face && foot.dist2 < best_dist2;
        let doubt = if better { None } else { Doubt::of(&foot) };
        Ok((better.then_some(foot), doubt))
    }

    /// The local minimum of the distance from `p` over leaf `l`, by
    /// bounded Newton from its nearest sample. When that foot cannot be
    /// confirmed, Newton starts again from it and from the next-nearest
    /// samples (up to `max_restarts` starts in all), and the best foot is
    /// kept: confirmed when a confirmed one is as close as any.
    fn leaf_minimum(&self, surface: &NurbsSurface, l: &Leaf, p: Point3) -> Foot {
        let eval = |x: Vec2, out: &mut Jet2| surface.jet2_into(x.x, x.y, out);
        let mut foot = local_minimum(eval, p, l.nearest_sample(p).0, &l.bounds, &self.opts);
        if foot.status.is_confirmed() {
            return foot;
        }
        let mut iterations = foot.iterations;
        let starts = l.samples_by_distance(p);
        let again = std::iter::once(foot.uv).chain(starts.into_iter().skip(1));
        for start in again.take(self.opts.max_restarts) {
            if foot.status.is_confirmed() {
                break;
            }
            let next = local_minimum(eval, p, start, &l.bounds, &self.opts);
            iterations += next.iterations;
            let slack = 1e-12 * foot.dist2 + 1e-24;
            let settles = next.status.is_confirmed() && next.dist2 <= foot.dist2 + slack;
            if settles || next.dist2 < foot.dist2 {
                foot = next;
            }
        }
        foot.iterations = iterations;
        foot
    }
}

impl Leaf {
    /// The parameters of the samples, nearest to `p` first (ties in sample
    /// order).
    fn samples_by_distance(&self, p: Point3) -> Vec<Vec2> {
        let mut by: Vec<(f64, Vec2)> = (self.samples.iter())
            .map(|s| ((s.1 - p).norm_squared(), s.0))
            .collect();
        by.sort_by(|a, b| a.0.total_cmp(&b.0));
        by.into_iter().map(|s| s.1).collect()
    }
}
