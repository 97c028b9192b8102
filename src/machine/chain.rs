//! Orders URDF joints into one serial chain from the base link to the tip.
//!
//! A machine is a serial chain: every link has at most one parent joint and
//! at most one child joint, exactly one link (the base) has no parent, and
//! every link is reachable from it. Violations are reported by link and joint.
use std::collections::HashMap;
use std::path::Path;

use super::error::MachineError;
use super::urdf::JointSpec;

/// The ordered chain: base link, joint indices from base to tip, tip link.
#[derive(Debug, Clone)]
pub(super) struct Chain {
    pub base: String,
    pub order: Vec<usize>,
    pub tip: String,
}

/// Joint index by child link, and by parent link.
struct Topology<'a> {
    joints: &'a [JointSpec],
    parent_joint: HashMap<&'a str, usize>,
    child_joint: HashMap<&'a str, usize>,
}

/// Builds the chain, or names the link/joint that breaks it.
pub(super) fn build(
    links: &[String],
    joints: &[JointSpec],
    file: &Path,
) -> Result<Chain, MachineError> {
    check_links_declared(links, joints, file)?;
    let topo = topology(joints, file)?;
    let base = find_base(links, &topo, file)?;
    let (order, tip) = walk_down(&topo, base);
    let mut reached = vec![base];
    reached.extend(
        order
            .iter()
            .filter_map(|&j| joints.get(j))
            .map(|j| j.child.as_str()),
    );
    if let Some(stray) = links.iter().find(|l| !reached.contains(&l.as_str())) {
        return Err(stray_error(&topo, stray, base, file));
    }
    Ok(Chain {
        base: base.to_string(),
        order,
        tip: tip.to_string(),
    })
}

fn check_links_declared(
    links: &[String],
    joints: &[JointSpec],
    file: &Path,
) -> Result<(), MachineError> {
    for joint in joints {
        for (role, link) in [("parent", &joint.parent), ("child", &joint.child)] {
            if !links.contains(link) {
                let (joint, link) = (joint.name.clone(), link.clone());
                let file = file.to_path_buf();
                return Err(MachineError::UnknownLink {
                    file,
                    joint,
                    role,
                    link,
                });
            }
        }
    }
    Ok(())
}

/// Maps links to their parent and child joints; two of either is an error.
fn topology<'a>(joints: &'a [JointSpec], file: &Path) -> Result<Topology<'a>, MachineError> {
    let mut parent_joint: HashMap<&str, usize> = HashMap::new();
    let mut child_joint: HashMap<&str, usize> = HashMap::new();
    for (i, joint) in joints.iter().enumerate() {
        if let Some(&first) = parent_joint.get(joint.child.as_str()) {
            let (link, first, second) = names(joints, &joint.child, first, i);
            return Err(MachineError::TwoParents {
                file: file.to_path_buf(),
                link,
                first,
                second,
            });
        }
        if let Some(&first) = child_joint.get(joint.parent.as_str()) {
            let (link, first, second) = names(joints, &joint.parent, first, i);
            return Err(MachineError::Branch {
                file: file.to_path_buf(),
                link,
                first,
                second,
            });
        }
        parent_joint.insert(&joint.child, i);
        child_joint.insert(&joint.parent, i);
    }
    Ok(Topology {
        joints,
        parent_joint,
        child_joint,
    })
}

fn names(
    joints: &[JointSpec],
    link: &str,
    first: usize,
    second: usize,
) -> (String, String, String) {
    let name = |i: usize| joints.get(i).map(|j| j.name.clone()).unwrap_or_default();
    (link.to_string(), name(first), name(second))
}

/// The first link without a parent joint; none at all means a cycle.
fn find_base<'a>(
    links: &'a [String],
    topo: &Topology,
    file: &Path,
) -> Result<&'a str, MachineError> {
    let Some(first) = links.first() else {
        let reason = "no <link> elements";
        return Err(MachineError::Empty {
            file: file.to_path_buf(),
            reason,
        });
    };
    match links
        .iter()
        .find(|l| !topo.parent_joint.contains_key(l.as_str()))
    {
        Some(base) => Ok(base),
        None => Err(cycle_error(topo, first, file)),
    }
}

/// Follows child joints from the base; returns joint order and the tip link.
fn walk_down<'a>(topo: &Topology<'a>, base: &'a str) -> (Vec<usize>, &'a str) {
    let mut order = Vec::new();
    let mut link = base;
    while let Some(&j) = topo.child_joint.get(link) {
        // A cycle cannot be reached from a parentless base, but guard anyway.
        let Some(joint) = topo.joints.get(j).filter(|_| !order.contains(&j)) else {
            break;
        };
        order.push(j);
        link = &joint.child;
    }
    (order, link)
}

/// A link not reached from the base: it hangs off another root, or sits on
/// a cycle.
fn stray_error(topo: &Topology, stray: &str, base: &str, file: &Path) -> MachineError {
    let mut link = stray;
    let mut seen = vec![stray];
    while let Some(joint) = topo
        .parent_joint
        .get(link)
        .and_then(|&j| topo.joints.get(j))
    {
        link = &joint.parent;
        if seen.contains(&link) {
            return cycle_error(topo, link, file);
        }
        seen.push(link);
    }
    let (link, base) = (link.to_string(), base.to_string());
    MachineError::Disconnected {
        file: file.to_path_buf(),
        link,
        base,
    }
}

/// Walks parent joints from `start` until a link repeats; names the loop.
fn cycle_error(topo: &Topology, start: &str, file: &Path) -> MachineError {
    let mut path: Vec<(&str, &str)> = Vec::new(); // (link, joint above it)
    let mut link = start;
    while let Some(joint) = topo
        .parent_joint
        .get(link)
        .and_then(|&j| topo.joints.get(j))
    {
        if let Some(pos) = path.iter().position(|(l, _)| *l == link) {
            let joints = path
                .iter()
                .skip(pos)
                .map(|(_, j)| j.to_string())
                .rev()
                .collect();
            return MachineError::Cycle {
                file: file.to_path_buf(),
                joints,
            };
        }
        path.push((link, &joint.name));
        link = &joint.parent;
    }
    let joints = path.iter().map(|(_, j)| j.to_string()).collect();
    MachineError::Cycle {
        file: file.to_path_buf(),
        joints,
    }
}
