//! The exact check's descent over the cylinder: point queries of the
//! true part at points of the cylinder, stepping to the cylinder's point
//! closest to the foot or deepest along the push, with a search along the
//! way to the deepest point where the distance keeps falling towards it.
use super::{LineEnds, PartCheck, Strike, LINE_STEPS, SETTLED_STEP_MM};
use crate::geometry::{ProjectionError, ProjectionOptions};
use crate::math::Point3;
use crate::workpiece::Workpiece;
use crate::world::as_machined::AsMachined;
use crate::world::contact::index::PartIndex;
use crate::world::contact::line::{least_on_segment, LineLimits, Look};
use crate::world::contact::shapes::Cylinder;
use crate::world::contact::TrueContact;

impl PartCheck {
    /// The descent of the signed distance over `cyl` from `seed`: the
    /// least distance found and where (`None` when the seed is out of the
    /// queries' reach), or the strike.
    pub(super) fn descend(
        &mut self,
        ix: &PartIndex,
        part: (&Workpiece, &AsMachined),
        cyl: &Cylinder,
        seed: Point3,
        opts: &ProjectionOptions,
    ) -> Result<Result<Option<(f64, Point3)>, Strike>, ProjectionError> {
        self.reach = self.opts.reach_mm;
        let mut c = match self.probe(ix, part, cyl, seed, opts)? {
            None => return Ok(Ok(None)),
            Some(Err(strike)) => return Ok(Err(strike)),
            Some(Ok(c)) => c,
        };
        let mut p = seed;
        let tol = self.opts.tolerance_mm;
        // The support point's look, kept for the next step: a support
        // point within the tolerance of it is not looked at again.
        let mut last_support: Option<(Point3, TrueContact)> = None;
        for _ in 0..self.opts.max_steps {
            let near = c.distance.max(0.0) + self.margin;
            self.reach = near.min(self.opts.reach_mm);
            let support = cyl.support(-c.push, p);
            // The closest point barely moved from `p` and not downhill
            // (the distance's gradient is the push; over so short a step
            // its change is the gradient's to far below the tolerance):
            // `p` stands for it.
            let closest = cyl.closest(c.point);
            let step = closest - p;
            let settled = step.norm() <= SETTLED_STEP_MM && c.push.dot(&step) >= -0.5 * tol;
            let mut best: Option<(Point3, TrueContact)> = settled.then_some((p, c));
            let mut at_support = None;
            for x in [closest, support] {
                if (x - p).norm() <= tol || (settled && x == closest) {
                    continue;
                }
                let known = (last_support.filter(|l| x == support && (l.0 - x).norm() <= tol))
                    .map(|l| Some(Ok(l.1)));
                let found = match known {
                    Some(k) => k,
                    None => self.probe(ix, part, cyl, x, opts)?,
                };
                match found {
                    Some(Err(strike)) => return Ok(Err(strike)),
                    Some(Ok(cx)) => {
                        if x == support {
                            at_support = Some(cx);
                            last_support = Some((x, cx));
                        }
                        if best.is_none_or(|b| cx.distance < b.1.distance) {
                            best = Some((x, cx));
                        }
                    }
                    None => {}
                }
            }
            // The support point overshoots where the distance keeps falling
            // towards it (a face nearly parallel to the axis that ends
            // before the cylinder does): the least distance on the way.
            let slope = c.push.dot(&(support - p));
            let support_better = best.is_some_and(|b| b.0 == support);
            if slope < -10.0 * tol && !support_better {
                let ends = ((p, c), (support, at_support));
                match self.line_search(ix, part, cyl, ends, opts)? {
                    Err(strike) => return Ok(Err(strike)),
                    Ok(Some((x, cx))) if best.is_none_or(|b| cx.distance < b.1.distance) => {
                        best = Some((x, cx));
                    }
                    Ok(_) => {}
                }
            }
            match best {
                Some((x, cx)) if cx.distance < c.distance - tol => {
                    (p, c) = (x, cx);
                }
                _ => break,
            }
        }
        Ok(Ok(Some((c.distance, p))))
    }

    /// The least signed distance on the segment `from..to` of `cyl`, from
    /// the looks at its ends (the distance falling at `from`; `None`
    /// beyond reach at `to`), by [`least_on_segment`] with the distance's
    /// slopes from the push directions; the best inner point, or the
    /// strike.
    fn line_search(
        &mut self,
        ix: &PartIndex,
        part: (&Workpiece, &AsMachined),
        cyl: &Cylinder,
        ((from, at_from), (to, at_to)): LineEnds,
        opts: &ProjectionOptions,
    ) -> Result<Result<Option<(Point3, TrueContact)>, Strike>, ProjectionError> {
        let d = to - from;
        let look_of = |at: f64, c: Option<TrueContact>| Look {
            at,
            value: c.map_or(f64::INFINITY, |c| c.distance),
            slope: c.map(|c| c.push.dot(&d)),
        };
        let limits = LineLimits {
            length_mm: d.norm(),
            tolerance_mm: self.opts.line_tolerance_mm,
            max_looks: LINE_STEPS,
        };
        let mut found: Vec<(f64, TrueContact)> = Vec::new();
        let ends = (look_of(0.0, Some(at_from)), look_of(1.0, at_to));
        let searched = least_on_segment(ends.0, ends.1, limits, |g| {
            let c = match self.probe(ix, part, cyl, from + d * g, opts) {
                Err(e) => return Err(Err(e)),
                Ok(Some(Err(strike))) => return Err(Ok(strike)),
                Ok(Some(Ok(c))) => Some(c),
                Ok(None) => None,
            };
            found.extend(c.map(|c| (g, c)));
            Ok(look_of(g, c))
        });
        match searched {
            Err(Err(e)) => Err(e),
            Err(Ok(strike)) => Ok(Err(strike)),
            Ok(best) => Ok(Ok(best.and_then(|b| {
                let (g, c) = found.iter().find(|f| f.0 == b.at)?;
                Some((from + d * *g, *c))
            }))),
        }
    }

    /// The signed distance at `x` (a point of `cyl`) with its foot, or the
    /// strike when `x` lies in the material or the foot in the cylinder;
    /// `None` beyond the queries' reach.
    fn probe(
        &mut self,
        ix: &PartIndex,
        part: (&Workpiece, &AsMachined),
        cyl: &Cylinder,
        x: Point3,
        opts: &ProjectionOptions,
    ) -> Result<Option<Result<TrueContact, Strike>>, ProjectionError> {
        let Some(c) = self.cursor.query(ix, part, x, self.reach, opts)? else {
            return Ok(None);
        };
        let pen = self.opts.penetration_mm;
        let inside = -cyl.signed_distance(c.point);
        let depth = (-c.distance).max(inside);
        if depth > pen {
            return Ok(Some(Err(Strike {
                point: c.point,
                depth_mm: depth,
            })));
        }
        Ok(Some(Ok(c)))
    }
}
