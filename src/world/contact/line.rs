//! The least value of a distance along a segment, from its values and
//! slopes: each look at a point gives the distance and its derivative
//! along the segment (the push direction is the distance's gradient), so
//! the tangents at the two ends of the bracket meet where a kink (the foot
//! jumping from one face to an edge) or the bottom of a smooth dip lies.
//!
//! The bracket `lo..hi` always holds a local minimum: the distance falls
//! at `lo`, and at `hi` it rises or is higher than at `lo`. Each step looks
//! where the two tangents meet (a tenth of the bracket from either end at
//! least), or halfway when a slope is unknown or the last step did not
//! halve the bracket. It stops when the best value found is within the
//! tolerance of the tangents' meeting value (the least value of a convex
//! distance lies between the two), when the bracket is shorter than the
//! tolerance, or after the most looks allowed.

/// A look at one point of the segment: its parameter in `[0, 1]`, the
/// distance (infinite beyond the looks' reach) and the distance's
/// derivative with respect to the parameter (`None` beyond reach).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Look {
    pub(crate) at: f64,
    pub(crate) value: f64,
    pub(crate) slope: Option<f64>,
}

/// Limits of the search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LineLimits {
    /// The segment's length, mm.
    pub(crate) length_mm: f64,
    /// Values within this of the least (mm) are as good.
    pub(crate) tolerance_mm: f64,
    /// Most looks.
    pub(crate) max_looks: usize,
}

/// The best look inside the segment (`None` when no inner look beat both
/// ends), from the ends `lo` (the distance falling there) and `hi`;
/// `look(at)` looks at a parameter.
pub(crate) fn least_on_segment<E>(
    lo: Look,
    hi: Look,
    limits: LineLimits,
    mut look: impl FnMut(f64) -> Result<Look, E>,
) -> Result<Option<Look>, E> {
    // Still falling at a lower far end: no dip is bracketed, the end is
    // the better point.
    if hi.slope.is_some_and(|s| s < 0.0) && hi.value <= lo.value {
        return Ok(None);
    }
    let (mut lo, mut hi) = (lo, hi);
    let mut best: Option<Look> = None;
    let mut least = lo.value.min(hi.value);
    let mut slow = false;
    for _ in 0..limits.max_looks {
        let width = hi.at - lo.at;
        if width * limits.length_mm <= limits.tolerance_mm {
            break;
        }
        let meet = tangents_meet(&lo, &hi);
        if meet.is_some_and(|(_, bound)| least - bound <= limits.tolerance_mm) {
            break;
        }
        let at = match meet {
            Some((at, _)) if !slow => at.clamp(lo.at + 0.1 * width, hi.at - 0.1 * width),
            _ => lo.at + 0.5 * width,
        };
        let l = look(at)?;
        if l.value < least {
            least = l.value;
            best = Some(l);
        }
        if l.slope.is_none_or(|s| s >= 0.0) || l.value > lo.value {
            hi = l;
        } else {
            lo = l;
        }
        slow = hi.at - lo.at > 0.5 * width;
    }
    Ok(best)
}

/// Where the tangents at `lo` (falling) and `hi` (rising faster) meet,
/// with their value there.
fn tangents_meet(lo: &Look, hi: &Look) -> Option<(f64, f64)> {
    let (sl, sh) = (lo.slope?, hi.slope?);
    if sh <= sl || !lo.value.is_finite() || !hi.value.is_finite() {
        return None;
    }
    let at = (hi.value - lo.value + sl * lo.at - sh * hi.at) / (sl - sh);
    Some((at, lo.value + sl * (at - lo.at)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn search(f: impl Fn(f64) -> (f64, f64), limits: LineLimits) -> (Option<Look>, usize) {
        let at = |g: f64| {
            let (value, slope) = f(g);
            Look {
                at: g,
                value,
                slope: Some(slope),
            }
        };
        let mut looks = 0;
        let found = least_on_segment::<()>(at(0.0), at(1.0), limits, |g| {
            looks += 1;
            Ok(at(g))
        });
        (found.unwrap_or(None), looks)
    }

    const LIMITS: LineLimits = LineLimits {
        length_mm: 20.0,
        tolerance_mm: 1e-4,
        max_looks: 12,
    };

    /// A kink between two straight pieces (a wall that ends: the foot
    /// jumps to its edge) is found in one look, exactly.
    #[test]
    fn finds_a_kink_at_once() {
        let kink = 0.3721;
        let f = |g: f64| {
            if g < kink {
                (5.0 - 4.0 * g, -4.0)
            } else {
                (5.0 - 4.0 * kink + 9.0 * (g - kink), 9.0)
            }
        };
        let (found, looks) = search(f, LIMITS);
        let l = found.unwrap();
        assert!((l.at - kink).abs() < 1e-12, "{l:?}");
        assert!(looks <= 2, "{looks}");
    }

    /// A smooth dip: the least value to the tolerance, in fewer looks than
    /// a golden-section search of the same bracket needs.
    #[test]
    fn finds_a_smooth_minimum() {
        for m in [0.05, 0.2, 0.5, 0.77, 0.93] {
            let f = |g: f64| (1.0 + 3.0 * (g - m).powi(2), 6.0 * (g - m));
            let (found, looks) = search(f, LIMITS);
            let l = found.unwrap();
            assert!(l.value - 1.0 <= LIMITS.tolerance_mm, "{m}: {l:?}");
            assert!(looks <= 9, "{m}: {looks}");
        }
    }

    /// A distance that keeps falling to the far end: no inner point beats
    /// it, and the search does not look.
    #[test]
    fn leaves_a_fall_to_the_end_to_the_end() {
        let f = |g: f64| (2.0 - g, -1.0);
        assert_eq!(search(f, LIMITS), (None, 0));
    }

    /// A dip between a fall and a higher far end that still falls (the
    /// foot beyond reach there: no slope) is found by halving.
    #[test]
    fn halves_without_slopes() {
        let lo = Look {
            at: 0.0,
            value: 1.0,
            slope: Some(-1.0),
        };
        let hi = Look {
            at: 1.0,
            value: f64::INFINITY,
            slope: None,
        };
        let f = |g: f64| 1.0 - g + 4.0 * g * g;
        let mut looks = 0;
        let found = least_on_segment::<()>(lo, hi, LIMITS, |g| {
            looks += 1;
            Ok(Look {
                at: g,
                value: f(g),
                slope: Some(8.0 * g - 1.0),
            })
        });
        let l = found.unwrap().unwrap();
        assert!(f(l.at) - f(0.125) <= LIMITS.tolerance_mm, "{l:?}");
        assert!(looks <= 12);
    }
}
