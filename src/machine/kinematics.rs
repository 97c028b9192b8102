//! Forward kinematics: a product of nalgebra isometries along the chain.
//!
//! Each chain link contributes `origin * motion(q)`: the fixed joint frame in
//! the parent link (from URDF `<origin>`, mm), then the joint's own motion —
//! a translation `q * axis` (mm) for a prismatic joint, a rotation by `q`
//! (rad, right-hand rule) about `axis` for a revolute one, nothing for a
//! fixed joint. The tip pose is the product from base to tip.
use super::model::AxisKind;
use crate::math::{Iso3, Vec3};

/// One joint of the ordered chain.
#[derive(Debug, Clone)]
pub(super) struct ChainLink {
    /// Joint frame in the parent link frame, mm.
    pub origin: Iso3,
    /// Unit joint axis in the joint frame.
    pub axis: Vec3,
    /// Index into `q` and kind, for movable joints.
    pub moved: Option<(usize, AxisKind)>,
}

impl ChainLink {
    /// The joint's motion for axis values `q` (a missing value counts as 0;
    /// callers check the length first).
    fn motion(&self, q: &[f64]) -> Iso3 {
        let Some((index, kind)) = self.moved else {
            return Iso3::identity();
        };
        let value = q.get(index).copied().unwrap_or(0.0);
        match kind {
            AxisKind::Prismatic => translation(self.axis * value),
            AxisKind::Revolute => Iso3::rotation(self.axis * value),
        }
    }
}

fn translation(v: Vec3) -> Iso3 {
    Iso3::translation(v.x, v.y, v.z)
}

/// Tip pose in the base frame for axis values `q`.
pub(super) fn forward(links: &[ChainLink], q: &[f64]) -> Iso3 {
    links.iter().fold(Iso3::identity(), |pose, link| {
        pose * link.origin * link.motion(q)
    })
}
