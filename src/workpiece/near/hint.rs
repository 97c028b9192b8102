//! Where a query near an earlier one starts: the earlier foot, with its
//! derivatives and what the queries so far learnt of far leaves.
use super::far::FarLeaves;
use crate::geometry::projection::{minimise_cached, minimise_with, Bounds, Foot};
use crate::geometry::{Jet2, ProjectionError, ProjectionOptions};
use crate::math::{Point3, Vec2};
use crate::workpiece::{Face, FaceProjection};

/// A nominal foot already found: the global closest point over all faces
/// of `query`, with the hint to start nearby queries from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnownFoot {
    /// The query point.
    pub query: Point3,
    /// Its closest point over all faces.
    pub foot: FaceProjection,
    /// Where that lies in the search trees.
    pub hint: Option<FootHint>,
}

/// Where the foot of a closest-point query lies (face, leaf of its search
/// tree when known, parameters and, when known, the derivatives there), to
/// start a query near it from ([`crate::workpiece::Workpiece::closest_point_near`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootHint {
    pub(super) face: usize,
    pub(super) leaf: Option<usize>,
    /// The foot (its derivatives valid when `has_jet`).
    pub(super) foot: Foot,
    pub(super) has_jet: bool,
    /// Leaves found far away by the queries so far.
    pub(super) far: FarLeaves,
}

impl FootHint {
    /// A start at parameters `uv` of face `face` (such as the nominal
    /// parameters of a true foot point on it).
    pub fn at(face: usize, uv: Vec2) -> FootHint {
        FootHint {
            face,
            leaf: None,
            foot: Foot::unevaluated(uv),
            has_jet: false,
            far: FarLeaves::default(),
        }
    }

    /// The hint of a foot found on leaf `leaf` of face `face`.
    pub(super) fn found(face: usize, leaf: Option<usize>, foot: Foot) -> FootHint {
        FootHint {
            face,
            leaf,
            foot,
            has_jet: true,
            far: FarLeaves::default(),
        }
    }

    /// Moves the start to parameters `uv` of face `face` (no derivatives
    /// there yet), keeping what the queries learnt of far leaves.
    pub fn restart_at(&mut self, face: usize, uv: Vec2) {
        (self.face, self.leaf, self.has_jet) = (face, None, false);
        self.foot.uv = uv;
    }

    /// [`Self::restart_at`], but from the foot of `earlier` (with its
    /// derivatives and leaf) when it lies on face `face` too: the foot of
    /// a point near the one sought (such as the nominal foot of a measured
    /// point, for its true point), so that Newton's first step from there
    /// needs no evaluation. Keeps what the queries learnt of far leaves.
    pub fn restart_near(&mut self, face: usize, uv: Vec2, earlier: Option<&FootHint>) {
        match earlier.filter(|e| e.face == face && e.has_jet) {
            Some(e) => {
                (self.face, self.leaf, self.foot, self.has_jet) = (face, e.leaf, e.foot, true)
            }
            None => self.restart_at(face, uv),
        }
    }
}

impl Face {
    /// Moves the hint's foot to the local minimum of the distance from
    /// `p` on the whole face that Newton finds from it (with its
    /// derivatives, when the hint has them, so that the first step needs
    /// no evaluation).
    pub(super) fn warm_foot(
        &self,
        p: Point3,
        h: &mut FootHint,
        opts: &ProjectionOptions,
    ) -> Result<(), ProjectionError> {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(ProjectionError::NotFinite {
                x: p.x,
                y: p.y,
                z: p.z,
            });
        }
        let ((u0, u1), (v0, v1)) = self.surface.domain();
        let bounds = Bounds {
            lo: Vec2::new(u0, v0),
            hi: Vec2::new(u1, v1),
        };
        let eval = |x: Vec2, out: &mut Jet2| self.surface.jet2_into(x.x, x.y, out);
        if h.has_jet {
            minimise_cached(eval, p, &mut h.foot, &bounds, opts)
        } else {
            h.foot = minimise_with(eval, p, h.foot.uv, &bounds, opts)?;
            h.has_jet = true;
            Ok(())
        }
    }
}
