//! How a closest-point search ended: confirmed, or the best point found
//! with the reason it could not be confirmed.

/// Whether a closest-point search confirmed its answer.
///
/// A search always returns the best point it found; `Unconfirmed` tells
/// that Newton could not certify it as a minimum (the distance is then an
/// upper bound of the true one, usually very close to it).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum SearchStatus {
    /// The first-order conditions of a minimum hold at the foot (to
    /// rounding) in every piece of the surface that could hold a closer
    /// point.
    #[default]
    Confirmed,
    /// The best point found, not certified.
    Unconfirmed {
        /// Why it could not be certified.
        reason: UnconfirmedReason,
        /// Length of the last Newton step tried, mm.
        last_step_mm: f64,
    },
}

/// Why a search could not confirm its best point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnconfirmedReason {
    /// Newton reached its iteration limit with steps still longer than the
    /// tolerance.
    IterationLimit,
    /// No step lowered the distance (neither the Newton step, nor a
    /// projected-gradient step, nor a restart), yet the gradient of the
    /// distance along the surface is not zero there.
    NoDescent,
}

impl SearchStatus {
    /// Whether the answer is certified.
    pub fn is_confirmed(&self) -> bool {
        matches!(self, SearchStatus::Confirmed)
    }

    /// The less certain of two statuses (the first when both are
    /// unconfirmed): a search over several pieces is confirmed only when
    /// each of them is.
    pub fn and(self, other: SearchStatus) -> SearchStatus {
        match self {
            SearchStatus::Confirmed => other,
            unconfirmed => unconfirmed,
        }
    }
}

impl std::fmt::Display for UnconfirmedReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            UnconfirmedReason::IterationLimit => "iteration limit reached",
            UnconfirmedReason::NoDescent => "no descent from a non-stationary point",
        })
    }
}
