//! glTF 2.0 and GLB through the `gltf` crate (default features off: no
//! file system, no images). Buffers come from the GLB's binary chunk, from
//! `data:` URIs (base64) or from the resolver; every triangle primitive of
//! the nodes of the default scene (or the first scene, or every mesh when
//! there is no scene) is read with its node's transform.

use glam::{DAffine3, DMat4, DVec3};

use super::{MAX_MESH_BYTES, MAX_TRIANGLES, MAX_VERTICES, MeshError, MeshFormat, TriMesh};

/// Reads a glTF or GLB file (GLB when its bytes start with `glTF`).
pub(super) fn read(
    path: &str,
    bytes: &[u8],
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<TriMesh, MeshError> {
    let format = if bytes.starts_with(b"glTF") {
        MeshFormat::Glb
    } else {
        MeshFormat::Gltf
    };
    let gltf =
        gltf::Gltf::from_slice(bytes).map_err(|e| unreadable(path, format, e.to_string()))?;
    let buffers = read_buffers(&gltf, path, format, resolve)?;
    let mut out = TriMesh::default();
    let scene = gltf
        .document
        .default_scene()
        .or_else(|| gltf.document.scenes().next());
    match scene {
        Some(scene) => read_scene(&scene, path, format, &buffers, &mut out)?,
        None => {
            for mesh in gltf.document.meshes() {
                add_mesh(path, &mesh, &DAffine3::IDENTITY, &buffers, &mut out)?;
            }
        }
    }
    Ok(out)
}

fn unreadable(path: &str, format: MeshFormat, reason: String) -> MeshError {
    MeshError::Unreadable {
        path: path.to_owned(),
        format,
        reason,
    }
}

/// The bytes of every buffer: the binary chunk, a `data:` URI or a file
/// the resolver gives, each within the caps and at least its `byteLength`.
fn read_buffers(
    gltf: &gltf::Gltf,
    path: &str,
    format: MeshFormat,
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, MeshError> {
    let unreadable = |reason: String| unreadable(path, format, reason);
    let mut buffers = Vec::new();
    for buffer in gltf.document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                unreadable("buffer 0 names the binary chunk, which is absent".into())
            })?,
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, b64) = rest
                        .split_once(";base64,")
                        .ok_or_else(|| unreadable("a data: URI that is not base64".into()))?;
                    decode_base64(b64)
                        .ok_or_else(|| unreadable("a data: URI with invalid base64".into()))?
                } else {
                    let full = sibling(path, uri);
                    resolve(&full).ok_or(MeshError::Missing { path: full })?
                }
            }
        };
        if data.len() > MAX_MESH_BYTES {
            return Err(MeshError::TooLarge {
                path: path.to_owned(),
                bytes: data.len(),
                max: MAX_MESH_BYTES,
            });
        }
        if data.len() < buffer.length() {
            return Err(unreadable(format!(
                "buffer {} holds {} bytes, fewer than its byteLength {}",
                buffer.index(),
                data.len(),
                buffer.length()
            )));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// Adds the meshes of the nodes of `scene`, each moved by its node's
/// transform (at most 100 000 nodes).
fn read_scene(
    scene: &gltf::Scene,
    path: &str,
    format: MeshFormat,
    buffers: &[Vec<u8>],
    out: &mut TriMesh,
) -> Result<(), MeshError> {
    let mut stack: Vec<(gltf::Node, DAffine3)> =
        scene.nodes().map(|n| (n, DAffine3::IDENTITY)).collect();
    let mut visited = 0usize;
    while let Some((node, parent)) = stack.pop() {
        visited += 1;
        if visited > 100_000 {
            return Err(unreadable(path, format, "more than 100000 nodes".into()));
        }
        let m = node.transform().matrix().map(|c| c.map(f64::from));
        let pose = parent * DAffine3::from_mat4(DMat4::from_cols_array_2d(&m));
        if let Some(mesh) = node.mesh() {
            add_mesh(path, &mesh, &pose, buffers, out)?;
        }
        stack.extend(node.children().map(|c| (c, pose)));
    }
    Ok(())
}

fn too_many(path: &str, what: &'static str, count: usize, max: usize) -> MeshError {
    MeshError::TooManyElements {
        path: path.to_owned(),
        what,
        count,
        max,
    }
}

fn add_mesh(
    path: &str,
    mesh: &gltf::Mesh,
    pose: &DAffine3,
    buffers: &[Vec<u8>],
    out: &mut TriMesh,
) -> Result<(), MeshError> {
    for primitive in mesh.primitives() {
        if primitive.mode() != gltf::mesh::Mode::Triangles {
            continue;
        }
        let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
            continue;
        };
        let vertices = out.vertices.len() + positions.count();
        if vertices > MAX_VERTICES {
            return Err(too_many(path, "vertices", vertices, MAX_VERTICES));
        }
        let corners = primitive.indices().map_or(positions.count(), |a| a.count());
        let triangles = out.triangles.len() + corners / 3;
        if triangles > MAX_TRIANGLES {
            return Err(too_many(path, "triangles", triangles, MAX_TRIANGLES));
        }
        let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let base = out.vertices.len();
        let Some(points) = reader.read_positions() else {
            continue;
        };
        out.vertices.extend(points.map(|p| {
            pose.transform_point3(DVec3::new(
                f64::from(p[0]),
                f64::from(p[1]),
                f64::from(p[2]),
            ))
        }));
        let count = out.vertices.len() - base;
        let index: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..u32::try_from(count).unwrap_or(u32::MAX)).collect(),
        };
        let base = u32::try_from(base).unwrap_or(u32::MAX);
        out.triangles.extend(
            index
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]].map(|k| k.saturating_add(base))),
        );
    }
    Ok(())
}

/// `uri` relative to the folder of `path` (percent-escapes for spaces undone).
fn sibling(path: &str, uri: &str) -> String {
    let uri = uri.replace("%20", " ");
    match path.rsplit_once('/') {
        Some((dir, _)) => format!("{dir}/{uri}"),
        None => uri,
    }
}

/// Standard base64 (RFC 4648, padding optional); `None` on any other byte.
fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => u32::from(c - b'A'),
            b'a'..=b'z' => u32::from(c - b'a') + 26,
            b'0'..=b'9' => u32::from(c - b'0') + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        })
    };
    let body = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(body.len() * 3 / 4);
    for chunk in body.chunks(4) {
        let mut acc = 0u32;
        for &c in chunk {
            acc = (acc << 6) | value(c)?;
        }
        match chunk.len() {
            4 => out.extend_from_slice(&acc.to_be_bytes()[1..]),
            3 => out.extend_from_slice(&(acc << 6).to_be_bytes()[1..3]),
            2 => out.push((acc >> 4) as u8),
            _ => return None,
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::decode_base64;

    #[test]
    fn base64_decodes_every_tail_length() {
        assert_eq!(decode_base64("TWFu").as_deref(), Some(&b"Man"[..]));
        assert_eq!(decode_base64("TWE=").as_deref(), Some(&b"Ma"[..]));
        assert_eq!(decode_base64("TQ==").as_deref(), Some(&b"M"[..]));
        assert_eq!(decode_base64("T"), None);
        assert_eq!(decode_base64("T$==").as_deref(), None);
    }
}
