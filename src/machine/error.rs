//! Errors of machine descriptions (URDF) and of their use.
use std::path::PathBuf;

/// Why a machine description (URDF) was rejected, or a pose could not be
/// computed. Every file error names the file; joint errors name the joint.
#[derive(Debug, thiserror::Error)]
pub enum MachineError {
    /// The file could not be read.
    #[error("{file}: cannot read machine description: {source}")]
    Io {
        /// The machine file.
        file: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Not well-formed XML, or not URDF that urdf-rs understands.
    #[error("{file}: not a valid URDF document: {reason}")]
    Xml {
        /// The machine file.
        file: PathBuf,
        /// The parser's message.
        reason: String,
    },
    /// A joint, or a link, has no `name` attribute, or it is empty.
    #[error("{file}: a <{element}> has no name")]
    Unnamed {
        /// The machine file.
        file: PathBuf,
        /// `joint` or `link`.
        element: &'static str,
    },
    /// Two joints, or two links, share a name.
    #[error("{file}: duplicate {element} name '{name}'")]
    Duplicate {
        /// The machine file.
        file: PathBuf,
        /// `joint` or `link`.
        element: &'static str,
        /// The repeated name.
        name: String,
    },
    /// A joint type the machine model does not support.
    #[error("{file}: joint '{joint}': unsupported type '{kind}' (expected prismatic, revolute or fixed)")]
    UnsupportedJointType {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
        /// The type attribute as written.
        kind: String,
    },
    /// A prismatic or revolute joint without a `<limit>` element.
    #[error("{file}: joint '{joint}': a {kind} joint needs a <limit lower=.. upper=.. velocity=..> element")]
    MissingLimit {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
        /// `prismatic` or `revolute`.
        kind: &'static str,
    },
    /// A `<limit>` attribute missing (`velocity` is required) or not a number.
    #[error("{file}: joint '{joint}': <limit> attribute '{attribute}' {problem}")]
    LimitAttribute {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
        /// `lower`, `upper` or `velocity`.
        attribute: &'static str,
        /// What is wrong, e.g. `is missing` or `is not a number: 'abc'`.
        problem: String,
    },
    /// Travel limits not finite, or `lower >= upper` (values in mm or rad).
    #[error("{file}: joint '{joint}': travel limits must be finite with lower < upper, found lower {lower} upper {upper} ({unit})")]
    LimitRange {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
        /// Lower limit, mm or rad.
        lower: f64,
        /// Upper limit, mm or rad.
        upper: f64,
        /// `mm` or `rad`.
        unit: &'static str,
    },
    /// Velocity limit not finite and positive (mm/s or rad/s).
    #[error("{file}: joint '{joint}': velocity limit must be finite and positive, found {velocity} ({unit})")]
    VelocityLimit {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
        /// The velocity limit, mm/s or rad/s.
        velocity: f64,
        /// `mm/s` or `rad/s`.
        unit: &'static str,
    },
    /// The joint axis is zero, not finite, or not of unit length.
    #[error(
        "{file}: joint '{joint}': axis {axis:?} must be a finite unit vector (length {length})"
    )]
    BadAxis {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
        /// The axis as written.
        axis: [f64; 3],
        /// Its length.
        length: f64,
    },
    /// An origin (`xyz` or `rpy`) with a non-finite number.
    #[error("{file}: joint '{joint}': origin has a non-finite value")]
    BadOrigin {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
    },
    /// A joint names a link that is not declared.
    #[error("{file}: joint '{joint}': {role} link '{link}' is not declared")]
    UnknownLink {
        /// The machine file.
        file: PathBuf,
        /// The joint.
        joint: String,
        /// `parent` or `child`.
        role: &'static str,
        /// The missing link.
        link: String,
    },
    /// A link is the child of two joints.
    #[error("{file}: link '{link}' has two parent joints '{first}' and '{second}'")]
    TwoParents {
        /// The machine file.
        file: PathBuf,
        /// The link.
        link: String,
        /// The first joint naming it as child.
        first: String,
        /// The second joint naming it as child.
        second: String,
    },
    /// A link is the parent of two joints: the machine is not a serial chain.
    #[error("{file}: link '{link}' has two child joints '{first}' and '{second}'; a machine must be a serial chain")]
    Branch {
        /// The machine file.
        file: PathBuf,
        /// The link.
        link: String,
        /// The first child joint.
        first: String,
        /// The second child joint.
        second: String,
    },
    /// The joints form a closed loop.
    #[error("{file}: joints {joints:?} form a cycle")]
    Cycle {
        /// The machine file.
        file: PathBuf,
        /// The joints on the loop, in order.
        joints: Vec<String>,
    },
    /// More than one link without a parent: the description falls apart.
    #[error("{file}: link '{link}' is not connected to the base link '{base}'")]
    Disconnected {
        /// The machine file.
        file: PathBuf,
        /// A link not reachable from the base.
        link: String,
        /// The base link (first root found).
        base: String,
    },
    /// No link at all, or no movable joint.
    #[error("{file}: {reason}")]
    Empty {
        /// The machine file.
        file: PathBuf,
        /// What is missing.
        reason: &'static str,
    },
    /// A joint-value vector of the wrong length.
    #[error("expected {expected} axis values, found {found}")]
    AxisCount {
        /// Number of movable axes of the machine.
        expected: usize,
        /// Number of values given.
        found: usize,
    },
}
