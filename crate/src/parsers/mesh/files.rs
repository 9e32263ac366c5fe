//! Mesh files named by a URDF (`package://pkg/meshes/a.stl`,
//! `../meshes/a.stl`) found among files given by path (a dropped folder,
//! `robot/meshes/a.stl`) and read.
//!
//! Limits: only the tail of the path is compared (the longest shared tail
//! wins, at least the file name); a name climbing out of the folder of the
//! files (more than one leading `..`, or `..` past an absolute root) is
//! refused.

use std::collections::BTreeMap;

use super::load_mesh;
use crate::mesh::TriMesh;

/// Path components of `name`, after `package://` or `file://`, with `.`
/// dropped and `..` applied. A relative name may start with one `..` (a
/// URDF in `urdf/` naming `../meshes/a.stl`, the ROS layout); `Err` when
/// `..` climbs further out.
pub fn path_components(name: &str) -> Result<Vec<String>, String> {
    let rest = name
        .strip_prefix("package://")
        .or_else(|| name.strip_prefix("file://"))
        .unwrap_or(name);
    let mut out: Vec<String> = Vec::new();
    let mut climbs = 0;
    for c in rest.split(['/', '\\']) {
        match c {
            "" | "." => {}
            ".." => {
                if out.pop().is_none() {
                    if rest.starts_with('/') || climbs == 1 {
                        return Err(format!("\"{name}\" leads outside the folder"));
                    }
                    climbs += 1;
                }
            }
            c => out.push(c.to_owned()),
        }
    }
    if out.is_empty() {
        return Err(format!("\"{name}\" names no file"));
    }
    Ok(out)
}

/// The key of `files` that `name` (a URDF mesh `filename`) refers to: the
/// one sharing the longest tail of path components with it (at least the
/// file name), so that `package://pkg/meshes/a.stl`, `../meshes/a.stl` and
/// `meshes/a.stl` all find `robot/meshes/a.stl`.
///
/// # Errors
/// A message naming the file: not found, or a path leading outside.
pub fn resolve_mesh<'a>(
    name: &str,
    files: &'a BTreeMap<String, Vec<u8>>,
) -> Result<&'a str, String> {
    let want = path_components(name)?;
    let mut best: Option<(usize, &str)> = None;
    for key in files.keys() {
        let Ok(have) = path_components(key) else {
            continue;
        };
        let common = want
            .iter()
            .rev()
            .zip(have.iter().rev())
            .take_while(|(a, b)| a == b)
            .count();
        if common > 0 && best.is_none_or(|(c, _)| common > c) {
            best = Some((common, key.as_str()));
        }
    }
    best.map(|(_, k)| k).ok_or_else(|| {
        format!(
            "\"{name}\" was not found among the {} files given",
            files.len()
        )
    })
}

/// The mesh `name` (a URDF mesh `filename`) from `files` (paths as dropped
/// mapped to bytes): found by [`resolve_mesh`], read by [`load_mesh`], with
/// the files it refers to (a glTF's buffers) found the same way.
///
/// # Errors
/// A message naming the file: not found, outside the folder, or not read.
pub fn read_named(name: &str, files: &BTreeMap<String, Vec<u8>>) -> Result<TriMesh, String> {
    let key = resolve_mesh(name, files)?;
    let bytes = files.get(key).map_or(&[][..], Vec::as_slice);
    load_mesh(key, bytes, &mut |p| {
        let p = path_components(p).ok()?.join("/");
        files
            .iter()
            .find(|(k, _)| path_components(k).is_ok_and(|c| c.join("/") == p))
            .map(|(_, v)| v.clone())
    })
    .map_err(|e| e.to_string())
}
