//! The links and joints of a URDF as a tree: the base, the default tip and
//! the path of joints between them; closed loops and undefined links are
//! refused.

use std::collections::{HashMap, HashSet};

use urdf_rs::JointType as UrdfJointType;

use super::joint_error;
use crate::error::FieldError;

/// The links and joints of a URDF as a tree.
pub(super) struct Tree<'a> {
    urdf: &'a urdf_rs::Robot,
    links: HashSet<&'a str>,
    /// Child link → index of its parent joint.
    parent: HashMap<&'a str, usize>,
    /// Parent link → indices of its child joints, in document order.
    children: HashMap<&'a str, Vec<usize>>,
}

impl<'a> Tree<'a> {
    pub(super) fn new(urdf: &'a urdf_rs::Robot) -> Result<Self, FieldError> {
        let links: HashSet<&str> = urdf.links.iter().map(|l| l.name.as_str()).collect();
        let mut parent = HashMap::new();
        let mut children: HashMap<&str, Vec<usize>> = HashMap::new();
        for (k, j) in urdf.joints.iter().enumerate() {
            for (what, l) in [("parent", &j.parent.link), ("child", &j.child.link)] {
                if !links.contains(l.as_str()) {
                    return Err(joint_error(
                        &j.name,
                        format!("{what} link \"{l}\" is not defined"),
                    ));
                }
            }
            if let Some(&other) = parent.get(j.child.link.as_str()) {
                let other: &urdf_rs::Joint = &urdf.joints[other];
                return Err(joint_error(
                    &j.name,
                    format!(
                        "link \"{}\" already has parent joint \"{}\" (closed loops are not supported)",
                        j.child.link, other.name
                    ),
                ));
            }
            parent.insert(j.child.link.as_str(), k);
            children.entry(j.parent.link.as_str()).or_default().push(k);
        }
        Ok(Self {
            urdf,
            links,
            parent,
            children,
        })
    }

    pub(super) fn link(&self, name: &str, field: &str) -> Result<(), FieldError> {
        if self.links.contains(name) {
            Ok(())
        } else {
            Err(FieldError::new(field, format!("no link named \"{name}\"")))
        }
    }

    pub(super) fn base(&self, requested: Option<&str>) -> Result<String, FieldError> {
        if let Some(b) = requested {
            self.link(b, "base")?;
            return Ok(b.to_owned());
        }
        let roots: Vec<&str> = self
            .urdf
            .links
            .iter()
            .map(|l| l.name.as_str())
            .filter(|l| !self.parent.contains_key(l))
            .collect();
        match roots.as_slice() {
            [root] => Ok((*root).to_owned()),
            [] => Err(FieldError::new(
                "xml",
                "no root link (every link has a parent joint: a closed loop)",
            )),
            many => Err(FieldError::new(
                "base",
                format!(
                    "the URDF has several root links ({}); name one",
                    many.iter()
                        .map(|r| format!("\"{r}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    /// Whether joint `k` counts towards the default tip's chain.
    fn is_chain_joint(&self, k: usize) -> bool {
        let j = &self.urdf.joints[k];
        j.mimic.is_none()
            && matches!(
                j.joint_type,
                UrdfJointType::Revolute | UrdfJointType::Continuous | UrdfJointType::Prismatic
            )
    }

    /// The end of the longest chain of movable, non-mimic joints below
    /// `base` (the first in document order on ties), then through single
    /// fixed joints.
    pub(super) fn default_tip(&self, base: &str) -> String {
        let mut best = (0usize, base);
        let mut stack = vec![(base, 0usize)];
        let mut seen = HashSet::new();
        while let Some((link, count)) = stack.pop() {
            if !seen.insert(link) {
                continue;
            }
            if count > best.0 {
                best = (count, link);
            }
            let kids = self.children.get(link).map_or(&[][..], Vec::as_slice);
            for &k in kids.iter().rev() {
                let j = &self.urdf.joints[k];
                let next = match j.joint_type {
                    UrdfJointType::Fixed => count,
                    _ if self.is_chain_joint(k) => count + 1,
                    _ => continue,
                };
                stack.push((j.child.link.as_str(), next));
            }
        }
        let mut tip = best.1;
        let mut steps = 0;
        while let Some([k]) = self.children.get(tip).map(Vec::as_slice) {
            let j = &self.urdf.joints[*k];
            if j.joint_type != UrdfJointType::Fixed || steps > self.urdf.joints.len() {
                break;
            }
            tip = j.child.link.as_str();
            steps += 1;
        }
        tip.to_owned()
    }

    /// Indices of the joints from `base` down to `tip`, in chain order.
    pub(super) fn path(&self, base: &str, tip: &str) -> Result<Vec<usize>, FieldError> {
        let mut out = Vec::new();
        let mut link = tip;
        while link != base {
            let Some(&k) = self.parent.get(link) else {
                return Err(FieldError::new(
                    "tip",
                    format!("link \"{tip}\" is not below base link \"{base}\""),
                ));
            };
            if out.len() > self.urdf.joints.len() {
                return Err(joint_error(
                    &self.urdf.joints[k].name,
                    "is part of a closed loop (not supported)",
                ));
            }
            out.push(k);
            link = self.urdf.joints[k].parent.link.as_str();
        }
        out.reverse();
        Ok(out)
    }
}
