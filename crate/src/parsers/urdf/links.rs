//! The links of an imported chain with their meshes and poses at `q = 0`.

use std::collections::HashSet;

use glam::{DAffine3, DVec3};
use urdf_rs::{Geometry, JointType as UrdfJointType};

use super::{Chain, ChainLink, MeshRef, finite_vec, origin, rpy_matrix};
use crate::error::FieldError;

fn meshes(link: &urdf_rs::Link, collision: bool) -> Result<Vec<MeshRef>, FieldError> {
    let items: Vec<(&urdf_rs::Pose, &Geometry)> = if collision {
        link.collision
            .iter()
            .map(|c| (&c.origin, &c.geometry))
            .collect()
    } else {
        link.visual
            .iter()
            .map(|v| (&v.origin, &v.geometry))
            .collect()
    };
    let what = if collision { "collision" } else { "visual" };
    let mut out = Vec::new();
    for (k, (pose, geometry)) in items.into_iter().enumerate() {
        let Geometry::Mesh { filename, scale } = geometry else {
            continue;
        };
        let field = format!("link \"{}\"", link.name);
        let at = |w: &str| format!("{what}[{k}].{w}");
        let xyz = finite_vec(&field, &at("origin.xyz"), pose.xyz.0)?;
        let rpy = finite_vec(&field, &at("origin.rpy"), pose.rpy.0)?;
        let scale = match scale {
            Some(s) => finite_vec(&field, &at("scale"), s.0)?,
            None => DVec3::ONE,
        };
        out.push(MeshRef {
            filename: filename.clone(),
            scale,
            origin: DAffine3::from_mat3_translation(rpy_matrix(rpy), xyz),
        });
    }
    Ok(out)
}

fn chain_link(link: &urdf_rs::Link, row: usize, pose: DAffine3) -> Result<ChainLink, FieldError> {
    Ok(ChainLink {
        name: link.name.clone(),
        row,
        pose,
        collision: meshes(link, true)?,
        visual: meshes(link, false)?,
    })
}

/// The base link, every link after a joint of `path`, and the links hung
/// from those by fixed joints off the path (a hand on a flange), each with
/// the row that moves it.
pub(super) fn chain_links(
    urdf: &urdf_rs::Robot,
    base: &str,
    path: &[usize],
    chain: &Chain,
) -> Result<Vec<ChainLink>, FieldError> {
    let find = |name: &str| urdf.links.iter().find(|l| l.name == name);
    let mut out = Vec::new();
    let mut stack = Vec::new();
    if let Some(l) = find(base) {
        stack.push((l, 0usize, DAffine3::IDENTITY));
    }
    for (k, &j) in path.iter().enumerate() {
        let (row, pose) = chain.poses[k];
        if let Some(l) = find(&urdf.joints[j].child.link) {
            stack.push((l, row, pose));
        }
    }
    let on_path: HashSet<usize> = path.iter().copied().collect();
    let mut seen = HashSet::new();
    while let Some((link, row, pose)) = stack.pop() {
        if !seen.insert(link.name.clone()) || seen.len() > urdf.links.len() {
            continue;
        }
        out.push(chain_link(link, row, pose)?);
        for (k, j) in urdf.joints.iter().enumerate() {
            if j.parent.link == link.name
                && j.joint_type == UrdfJointType::Fixed
                && !on_path.contains(&k)
                && let Some(child) = find(&j.child.link)
            {
                stack.push((child, row, pose * origin(j)?));
            }
        }
    }
    out.sort_by_key(|l| l.row);
    Ok(out)
}
