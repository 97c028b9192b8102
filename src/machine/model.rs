//! The machine's kinematic model: a serial chain of joints read from URDF,
//! with axis metadata and forward kinematics.
use std::path::{Path, PathBuf};

use super::chain;
use super::error::MachineError;
use super::kinematics::ChainLink;
use super::urdf::{self, JointKind};
use crate::math::{Iso3, Vec3};

/// Kind of a machine axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// A linear axis (X, Y, Z carriages); positions in mm.
    Prismatic,
    /// A rotary axis (probe head A/B, rotary table); positions in rad.
    Revolute,
}

impl AxisKind {
    /// Unit of positions on this kind of axis.
    pub fn unit(self) -> &'static str {
        match self {
            AxisKind::Prismatic => "mm",
            AxisKind::Revolute => "rad",
        }
    }

    /// Unit of velocities on this kind of axis.
    pub fn velocity_unit(self) -> &'static str {
        match self {
            AxisKind::Prismatic => "mm/s",
            AxisKind::Revolute => "rad/s",
        }
    }
}

/// Travel and velocity limits of one axis (mm and mm/s, or rad and rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisLimits {
    /// Lowest position, mm or rad.
    pub lower: f64,
    /// Highest position, mm or rad.
    pub upper: f64,
    /// Largest speed, mm/s or rad/s.
    pub velocity: f64,
}

impl AxisLimits {
    /// `true` when `position` lies within `[lower, upper]`.
    pub fn contains(&self, position: f64) -> bool {
        (self.lower..=self.upper).contains(&position)
    }
}

/// Metadata of one movable axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Joint name from the URDF (e.g. `x`, `a`).
    pub name: String,
    /// Linear or rotary.
    pub kind: AxisKind,
    /// Travel and velocity limits.
    pub limits: AxisLimits,
    /// Unit axis in the joint's own frame.
    pub joint_axis: Vec3,
    /// Unit axis in machine coordinates with every axis at 0.
    pub home_direction: Vec3,
}

/// A machine: a serial chain from the base link (machine coordinates) to the
/// tip link (spindle reference point / probe mount). Axis values `q` are
/// given in chain order, base to tip (see [`MachineModel::axes`]).
#[derive(Debug, Clone)]
pub struct MachineModel {
    name: String,
    source: PathBuf,
    base_link: String,
    tip_link: String,
    links: Vec<ChainLink>,
    axes: Vec<Axis>,
}

impl MachineModel {
    /// Reads and validates a URDF file (metres, see [`urdf::MM_PER_M`]).
    pub fn from_urdf_file(path: impl AsRef<Path>) -> Result<Self, MachineError> {
        let path = path.as_ref();
        let text = crate::jsonfile::read_text(path).map_err(|source| MachineError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        Self::from_urdf_str(&text, path)
    }

    /// Parses and validates URDF text; `path_for_messages` names it in errors.
    pub fn from_urdf_str(
        text: &str,
        path_for_messages: impl AsRef<Path>,
    ) -> Result<Self, MachineError> {
        let file = path_for_messages.as_ref();
        let parsed = urdf::parse(text, file)?;
        let chain = chain::build(&parsed.links, &parsed.joints, file)?;
        let (links, mut axes) = chain_links(&parsed.joints, &chain.order);
        if axes.is_empty() {
            let reason = "the chain has no prismatic or revolute joint";
            return Err(MachineError::Empty {
                file: file.to_path_buf(),
                reason,
            });
        }
        set_home_directions(&links, &mut axes);
        let (base_link, tip_link) = (chain.base, chain.tip);
        let (name, source) = (parsed.name, file.to_path_buf());
        Ok(Self {
            name,
            source,
            base_link,
            tip_link,
            links,
            axes,
        })
    }

    /// The embedded bridge CMM (X 0-700, Y 0-1000, Z 0-600 mm), used when no
    /// machine file is given. See [`super::builtin::DEFAULT_BRIDGE_URDF`].
    pub fn default_bridge() -> Self {
        Self::from_urdf_str(super::builtin::DEFAULT_BRIDGE_URDF, "<default bridge>")
            .expect("the embedded default bridge URDF is valid (checked by tests)")
    }

    /// The robot name from the URDF.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The file (or label) the model was read from.
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// The base link (machine coordinate frame).
    pub fn base_link(&self) -> &str {
        &self.base_link
    }

    /// The tip link (spindle reference point / probe mount).
    pub fn tip_link(&self) -> &str {
        &self.tip_link
    }

    /// The movable axes in chain order (the order of `q`).
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// Index in `q` of the axis (joint) called `name`.
    pub fn axis_index(&self, name: &str) -> Option<usize> {
        self.axes.iter().position(|a| a.name == name)
    }

    /// Pose of the tip link in machine coordinates (mm) for axis values `q`
    /// (mm for prismatic axes, rad for revolute ones, chain order).
    pub fn pose(&self, q: &[f64]) -> Result<Iso3, MachineError> {
        self.check_count(q)?;
        Ok(super::kinematics::forward(&self.links, q))
    }

    /// Nominal X, Y, Z of the linear axes (mm): `sum q_i * home_direction_i`
    /// over prismatic axes. The 21 geometric error terms take this position.
    pub fn linear_xyz(&self, q: &[f64]) -> Result<[f64; 3], MachineError> {
        self.check_count(q)?;
        let linear = self
            .axes
            .iter()
            .zip(q)
            .filter(|(a, _)| a.kind == AxisKind::Prismatic);
        let sum: Vec3 = linear.map(|(a, v)| a.home_direction * *v).sum();
        Ok([sum.x, sum.y, sum.z])
    }

    /// This machine with its revolute joints moved: the `k`-th revolute
    /// joint's origin shifted by `offsets_mm[k]` and its axis turned by the
    /// rotation vector `tilts_rad[k]` (missing entries leave a joint as it
    /// is). The world builds its true probe head this way.
    pub fn with_revolute_errors(&self, offsets_mm: &[Vec3], tilts_rad: &[Vec3]) -> MachineModel {
        let mut moved = self.clone();
        let mut k = 0;
        for link in moved.links.iter_mut() {
            let Some((index, AxisKind::Revolute)) = link.moved else {
                continue;
            };
            if let Some(offset) = offsets_mm.get(k) {
                link.origin.translation.vector += offset;
            }
            if let Some(tilt) = tilts_rad.get(k) {
                let turned = nalgebra::Rotation3::new(*tilt) * link.axis;
                link.axis = turned.normalize();
                if let Some(axis) = moved.axes.get_mut(index) {
                    axis.joint_axis = link.axis;
                }
            }
            k += 1;
        }
        moved
    }

    /// Index in `q` of every revolute (rotary) axis, chain order.
    pub fn revolute_axes(&self) -> Vec<usize> {
        let rotary = self.axes.iter().enumerate();
        rotary
            .filter(|(_, a)| a.kind == AxisKind::Revolute)
            .map(|(i, _)| i)
            .collect()
    }

    fn check_count(&self, q: &[f64]) -> Result<(), MachineError> {
        if q.len() == self.axes.len() {
            return Ok(());
        }
        let (expected, found) = (self.axes.len(), q.len());
        Err(MachineError::AxisCount { expected, found })
    }
}

/// Chain links in order and the axes they move.
fn chain_links(joints: &[urdf::JointSpec], order: &[usize]) -> (Vec<ChainLink>, Vec<Axis>) {
    let mut links = Vec::new();
    let mut axes = Vec::new();
    for joint in order.iter().filter_map(|&i| joints.get(i)) {
        let moved = match (joint.kind, joint.limits) {
            (JointKind::Movable(kind), Some(limits)) => {
                axes.push(new_axis(joint, kind, limits));
                Some((axes.len() - 1, kind))
            }
            _ => None,
        };
        links.push(ChainLink {
            origin: joint.origin,
            axis: joint.axis,
            moved,
        });
    }
    (links, axes)
}

fn new_axis(joint: &urdf::JointSpec, kind: AxisKind, limits: AxisLimits) -> Axis {
    Axis {
        name: joint.name.clone(),
        kind,
        limits,
        joint_axis: joint.axis,
        home_direction: joint.axis,
    }
}

/// Rotates each joint axis into machine coordinates at the home pose.
fn set_home_directions(links: &[ChainLink], axes: &mut [Axis]) {
    let mut frame = Iso3::identity();
    for link in links {
        frame *= link.origin;
        if let Some(axis) = link.moved.and_then(|(i, _)| axes.get_mut(i)) {
            axis.home_direction = frame.rotation * axis.joint_axis;
        }
    }
}
