//! Reading URDF text into validated joint descriptions (units converted).
//!
//! **Units.** cmm machine files are ordinary URDF, in SI units as ROS tools
//! expect: lengths in metres, angles in radians, velocities in m/s or rad/s.
//! They are converted on reading: every length (joint origins, prismatic
//! travel limits) is multiplied by [`MM_PER_M`], prismatic velocity limits
//! become mm/s; angles stay in radians. Everything after this module is in mm.
//!
//! urdf-rs silently gives a prismatic joint without `<limit>` a 0..0 range and
//! its errors carry no location, so the raw XML is scanned first: every joint
//! is named, its type checked, and a movable joint without `<limit>` rejected
//! by name.
use std::collections::HashSet;
use std::path::Path;

use super::error::MachineError;
use super::model::{AxisKind, AxisLimits};
use crate::math::{Iso3, Vec3};

/// Millimetres per metre: URDF lengths are metres, cmm works in mm.
pub const MM_PER_M: f64 = 1000.0;

/// Allowed deviation of a joint axis from unit length (URDF axes must be
/// normalised; a small rounding in the file is accepted and normalised away).
pub const AXIS_UNIT_TOLERANCE: f64 = 1e-6;

/// What a joint does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum JointKind {
    /// Rigid offset.
    Fixed,
    /// A machine axis.
    Movable(AxisKind),
}

/// One validated joint, lengths in mm.
#[derive(Debug, Clone)]
pub(super) struct JointSpec {
    pub name: String,
    pub kind: JointKind,
    pub parent: String,
    pub child: String,
    /// Joint frame in the parent link frame, mm.
    pub origin: Iso3,
    /// Unit axis in the joint frame (meaningless for fixed joints).
    pub axis: Vec3,
    /// Travel and velocity limits (mm, mm/s or rad, rad/s); movable only.
    pub limits: Option<AxisLimits>,
}

/// A parsed URDF: link names in file order and validated joints.
#[derive(Debug, Clone)]
pub(super) struct ParsedUrdf {
    pub name: String,
    pub links: Vec<String>,
    pub joints: Vec<JointSpec>,
}

/// Deepest element nesting accepted in a URDF file. URDF itself nests four
/// levels (`robot > link > visual > geometry > box`); the XML parsers
/// recurse per level, so a file nested thousands of levels deep would
/// overflow the stack: it is refused before they see it.
pub const MAX_URDF_DEPTH: usize = 32;

/// Parses and validates URDF text; `file` is used in messages only.
pub(super) fn parse(text: &str, file: &Path) -> Result<ParsedUrdf, MachineError> {
    check_depth(text, file)?;
    scan_raw(text, file)?;
    let robot = urdf_rs::read_from_string(text).map_err(|e| urdf_error(text, file, e))?;
    let joints = robot
        .joints
        .iter()
        .map(|j| joint_spec(j, file))
        .collect::<Result<Vec<_>, _>>()?;
    let links = robot.links.iter().map(|l| l.name.clone()).collect();
    Ok(ParsedUrdf {
        name: robot.name,
        links,
        joints,
    })
}

fn xml_error(file: &Path, reason: String) -> MachineError {
    MachineError::Xml {
        file: file.to_path_buf(),
        reason,
    }
}

/// 1-based line of byte offset `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    1 + text
        .as_bytes()
        .iter()
        .take(at)
        .filter(|&&b| b == b'\n')
        .count()
}

/// Refuses element nesting deeper than [`MAX_URDF_DEPTH`], naming the line
/// where it is exceeded. A light scan of the markup: comments, CDATA,
/// processing instructions and declarations are skipped, quoted attribute
/// values may hold `>`.
fn check_depth(text: &str, file: &Path) -> Result<(), MachineError> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut at = 0usize;
    while let Some(offset) = bytes
        .get(at..)
        .and_then(|b| b.iter().position(|&c| c == b'<'))
    {
        let start = at + offset;
        let rest = bytes.get(start..).unwrap_or_default();
        let skip_to = |end: &[u8]| {
            rest.windows(end.len())
                .position(|w| w == end)
                .map_or(bytes.len(), |i| start + i + end.len())
        };
        at = if rest.starts_with(b"<!--") {
            skip_to(b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            skip_to(b"]]>")
        } else if rest.starts_with(b"<?") {
            skip_to(b"?>")
        } else if rest.starts_with(b"<!") {
            skip_to(b">")
        } else {
            let end = tag_end(rest).map_or(bytes.len(), |i| start + i + 1);
            let tag = bytes.get(start..end).unwrap_or_default();
            if tag.starts_with(b"</") {
                depth = depth.saturating_sub(1);
            } else if !tag.ends_with(b"/>") {
                depth += 1;
                if depth > MAX_URDF_DEPTH {
                    let reason = format!(
                        "line {}: elements nested more than {MAX_URDF_DEPTH} levels deep (URDF needs four)",
                        line_of(text, start)
                    );
                    return Err(xml_error(file, reason));
                }
            }
            end
        };
    }
    Ok(())
}

/// Offset of the `>` closing the tag that starts `tag` (quotes respected).
fn tag_end(tag: &[u8]) -> Option<usize> {
    let mut quote = None;
    for (i, &c) in tag.iter().enumerate() {
        match (quote, c) {
            (None, b'"' | b'\'') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, b'>') => return Some(i),
            _ => {}
        }
    }
    None
}

/// An urdf-rs error, located: the first `<joint>` or `<link>` that urdf-rs
/// rejects on its own is named with its line.
fn urdf_error(text: &str, file: &Path, err: urdf_rs::UrdfError) -> MachineError {
    let reason = err.to_string();
    let Ok(root) = text.parse::<xml::Element>() else {
        return xml_error(file, reason);
    };
    for element in ["joint", "link"] {
        for child in root.get_children(element, None) {
            let alone = format!("<robot name=\"r\">{child}</robot>");
            if let Err(e) = urdf_rs::read_from_string(&alone) {
                let name = child.get_attribute("name", None).unwrap_or("");
                let line = find_element_line(text, element, name);
                let reason = format!("line {line}: {element} '{name}': {e}");
                return xml_error(file, reason);
            }
        }
    }
    xml_error(file, reason)
}

/// The line of `<element ... name="name"` in `text` (1 when not found).
fn find_element_line(text: &str, element: &str, name: &str) -> usize {
    let open = format!("<{element}");
    let mut from = 0;
    while let Some(i) = text.get(from..).and_then(|t| t.find(&open)) {
        let start = from + i;
        let tag = text.get(start..).unwrap_or_default();
        let tag = tag
            .get(..tag.find('>').unwrap_or(tag.len()))
            .unwrap_or_default();
        if tag.contains(&format!("\"{name}\"")) || tag.contains(&format!("'{name}'")) {
            return line_of(text, start);
        }
        from = start + open.len();
    }
    1
}

/// Checks names, joint types and `<limit>` presence on the raw XML.
fn scan_raw(text: &str, file: &Path) -> Result<(), MachineError> {
    let root: xml::Element = text
        .parse()
        .map_err(|e: xml::BuilderError| xml_error(file, e.to_string()))?;
    if root.name != "robot" {
        let reason = format!("root element is <{}>, expected <robot>", root.name);
        return Err(xml_error(file, reason));
    }
    check_names(&root, "link", file)?;
    check_names(&root, "joint", file)?;
    root.get_children("joint", None)
        .try_for_each(|joint| check_raw_joint(joint, file))
}

/// Every `element` child has a non-empty, unique name.
fn check_names(
    root: &xml::Element,
    element: &'static str,
    file: &Path,
) -> Result<(), MachineError> {
    let mut seen = HashSet::new();
    for child in root.get_children(element, None) {
        let name = raw_name(child, element, file)?;
        if !seen.insert(name) {
            let name = name.to_string();
            let file = file.to_path_buf();
            return Err(MachineError::Duplicate {
                file,
                element,
                name,
            });
        }
    }
    Ok(())
}

fn raw_name<'a>(
    elem: &'a xml::Element,
    element: &'static str,
    file: &Path,
) -> Result<&'a str, MachineError> {
    match elem.get_attribute("name", None) {
        Some(name) if !name.trim().is_empty() => Ok(name),
        _ => Err(MachineError::Unnamed {
            file: file.to_path_buf(),
            element,
        }),
    }
}

/// Supported type; a movable joint has a `<limit>` child.
fn check_raw_joint(joint: &xml::Element, file: &Path) -> Result<(), MachineError> {
    let name = raw_name(joint, "joint", file)?;
    let Some(kind) = movable_kind(joint, name, file)? else {
        return Ok(());
    };
    match joint.get_child("limit", None) {
        Some(limit) => check_limit_attributes(limit, name, file),
        None => Err(MachineError::MissingLimit {
            file: file.to_path_buf(),
            joint: name.into(),
            kind,
        }),
    }
}

/// `Some("prismatic" | "revolute")`, `None` for fixed, else an error.
fn movable_kind(
    joint: &xml::Element,
    name: &str,
    file: &Path,
) -> Result<Option<&'static str>, MachineError> {
    match joint.get_attribute("type", None).unwrap_or("") {
        "fixed" => Ok(None),
        "prismatic" => Ok(Some("prismatic")),
        "revolute" => Ok(Some("revolute")),
        other => Err(MachineError::UnsupportedJointType {
            file: file.to_path_buf(),
            joint: name.into(),
            kind: other.into(),
        }),
    }
}

/// `velocity` present; `lower`, `upper`, `velocity` numbers where present
/// (an absent `lower`/`upper` is 0 in URDF 1.0, and is checked later).
fn check_limit_attributes(
    limit: &xml::Element,
    joint: &str,
    file: &Path,
) -> Result<(), MachineError> {
    for attribute in ["lower", "upper", "velocity"] {
        let problem = match limit.get_attribute(attribute, None) {
            None if attribute == "velocity" => "is missing".to_string(),
            Some(text) if text.trim().parse::<f64>().is_err() => {
                format!("is not a number: '{text}'")
            }
            _ => continue,
        };
        let (file, joint) = (file.to_path_buf(), joint.to_string());
        return Err(MachineError::LimitAttribute {
            file,
            joint,
            attribute,
            problem,
        });
    }
    Ok(())
}

/// Converts one urdf-rs joint (metres) into a validated spec (mm).
fn joint_spec(joint: &urdf_rs::Joint, file: &Path) -> Result<JointSpec, MachineError> {
    let kind = match joint.joint_type {
        urdf_rs::JointType::Prismatic => JointKind::Movable(AxisKind::Prismatic),
        urdf_rs::JointType::Revolute => JointKind::Movable(AxisKind::Revolute),
        _ => JointKind::Fixed,
    };
    let (axis, limits) = match kind {
        JointKind::Fixed => (Vec3::z(), None),
        JointKind::Movable(k) => (unit_axis(joint, file)?, Some(limits(joint, k, file)?)),
    };
    Ok(JointSpec {
        name: joint.name.clone(),
        kind,
        parent: joint.parent.link.clone(),
        child: joint.child.link.clone(),
        origin: origin(joint, file)?,
        axis,
        limits,
    })
}

/// Joint origin in mm: translation `xyz * 1000`, rotation from `rpy`
/// (URDF: `Rz(yaw) * Ry(pitch) * Rx(roll)` about fixed axes).
fn origin(joint: &urdf_rs::Joint, file: &Path) -> Result<Iso3, MachineError> {
    let [x, y, z] = joint.origin.xyz.0;
    let [roll, pitch, yaw] = joint.origin.rpy.0;
    if !crate::math::all_finite(&[x, y, z, roll, pitch, yaw]) {
        let joint = joint.name.clone();
        return Err(MachineError::BadOrigin {
            file: file.to_path_buf(),
            joint,
        });
    }
    let rotation = nalgebra::UnitQuaternion::from_euler_angles(roll, pitch, yaw);
    let translation = Vec3::new(x, y, z) * MM_PER_M;
    Ok(Iso3::from_parts(translation.into(), rotation))
}

fn unit_axis(joint: &urdf_rs::Joint, file: &Path) -> Result<Vec3, MachineError> {
    let axis = joint.axis.xyz.0;
    let v = Vec3::from(axis);
    let length = v.norm();
    if length.is_finite() && (length - 1.0).abs() <= AXIS_UNIT_TOLERANCE {
        return Ok(v / length);
    }
    let joint = joint.name.clone();
    let file = file.to_path_buf();
    Err(MachineError::BadAxis {
        file,
        joint,
        axis,
        length,
    })
}

/// Travel and velocity limits converted to mm (prismatic) or kept in rad.
fn limits(joint: &urdf_rs::Joint, kind: AxisKind, file: &Path) -> Result<AxisLimits, MachineError> {
    let scale = match kind {
        AxisKind::Prismatic => MM_PER_M,
        AxisKind::Revolute => 1.0,
    };
    let l = &joint.limit;
    let limits = AxisLimits {
        lower: l.lower * scale,
        upper: l.upper * scale,
        velocity: l.velocity * scale,
    };
    check_limits(&limits, kind, &joint.name, file).map(|()| limits)
}

/// Finite travel with `lower < upper`; finite positive velocity.
fn check_limits(
    l: &AxisLimits,
    kind: AxisKind,
    joint: &str,
    file: &Path,
) -> Result<(), MachineError> {
    let (file, joint) = (file.to_path_buf(), joint.to_string());
    let (lower, upper, velocity) = (l.lower, l.upper, l.velocity);
    if !(lower.is_finite() && upper.is_finite() && lower < upper) {
        let unit = kind.unit();
        return Err(MachineError::LimitRange {
            file,
            joint,
            lower,
            upper,
            unit,
        });
    }
    if !(velocity.is_finite() && velocity > 0.0) {
        let unit = kind.velocity_unit();
        return Err(MachineError::VelocityLimit {
            file,
            joint,
            velocity,
            unit,
        });
    }
    Ok(())
}
