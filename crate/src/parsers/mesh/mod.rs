//! Mesh files read into a [`TriMesh`]: STL (binary and ASCII), Wavefront
//! OBJ, COLLADA (`.dae`) and glTF 2.0 (`.gltf` with its buffers, `.glb`),
//! and the mesh files a URDF names found among files given by path
//! ([`resolve_mesh`], [`read_named`]).
//!
//! [`load_mesh`] turns the bytes of one mesh file into a [`TriMesh`] in the
//! file's own units and frame; [`TriMesh::transformed`] applies a URDF
//! `<mesh scale>` and the `<origin>` of its `<visual>` or `<collision>`.
//! COLLADA's `<unit meter>` and node transforms are applied while reading
//! (so a `.dae` in millimetres comes back in metres); glTF node transforms of
//! the default scene are applied, its axes are kept as they are (no Y-up to
//! Z-up turn: a URDF places the mesh with its `<origin>`).
//!
//! The parsers: [`mesh-loader`](https://docs.rs/mesh-loader) (Apache-2.0,
//! from the openrr project, the loader of `urdf-viz`) reads STL, OBJ and
//! COLLADA, pure Rust without `unsafe`, builds for `wasm32-unknown-unknown`;
//! [`gltf`](https://docs.rs/gltf)
//! (MIT OR Apache-2.0, the reference Rust glTF crate) reads glTF and GLB with
//! its default features off (no image decoding, no file system).
//!
//! # Caps (hostile or broken files)
//! - A file longer than [`MAX_MESH_BYTES`] is refused before parsing.
//! - A mesh with more than [`MAX_TRIANGLES`] triangles or [`MAX_VERTICES`]
//!   vertices is refused (glTF: checked on the accessors' declared counts
//!   before reading them; a binary STL's declared triangle count is checked
//!   before parsing: more than the cap, or more than its bytes hold — a
//!   truncated file — refuses it, [`MeshError::Truncated`]).
//! - A vertex that is not a finite number, or an index past the vertices,
//!   refuses the whole mesh ([`MeshError::NotFinite`],
//!   [`MeshError::BadIndex`]): nothing is loaded from it.
//! - A glTF buffer shorter than its declared `byteLength`, or one that
//!   cannot be found, refuses the mesh.
//! - A mesh name leading outside the folder of the files given
//!   (`../../etc/passwd`) is refused by [`resolve_mesh`].
//!
//! See also [`crate::mesh`] (the triangle mesh and its geometry),
//! [`crate::parsers::urdf`] (which meshes a URDF names) and
//! [`crate::fitting`] (volumes fitted to them).

mod files;
mod gltf_file;

pub use files::{path_components, read_named, resolve_mesh};

use glam::DVec3;

use crate::mesh::TriMesh;

/// Largest mesh file read (bytes): 32 MiB.
pub const MAX_MESH_BYTES: usize = 32 << 20;
/// Largest number of triangles in one mesh: one million.
pub const MAX_TRIANGLES: usize = 1_000_000;
/// Largest number of vertices in one mesh: three million.
pub const MAX_VERTICES: usize = 3_000_000;

/// File formats [`load_mesh`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum MeshFormat {
    /// STL, binary or ASCII.
    Stl,
    /// Wavefront OBJ (materials ignored).
    Obj,
    /// COLLADA 1.4/1.5.
    Collada,
    /// glTF 2.0, JSON with external or embedded (`data:`) buffers.
    Gltf,
    /// glTF 2.0 binary container.
    Glb,
}

impl MeshFormat {
    /// The format named by a path's extension (case-insensitive), `None` for
    /// any other.
    #[must_use]
    pub fn from_path(path: &str) -> Option<Self> {
        let ext = path.rsplit_once('.')?.1.to_ascii_lowercase();
        match ext.as_str() {
            "stl" => Some(Self::Stl),
            "obj" => Some(Self::Obj),
            "dae" => Some(Self::Collada),
            "gltf" => Some(Self::Gltf),
            "glb" => Some(Self::Glb),
            _ => None,
        }
    }
}

/// Why a mesh could not be loaded.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The file (or a buffer it names) was not given.
    #[error("\"{path}\" was not found")]
    Missing {
        /// Path as named.
        path: String,
    },
    /// The extension names no format this module reads.
    #[error("\"{path}\": unknown mesh format (expected .stl, .obj, .dae, .gltf or .glb)")]
    UnknownFormat {
        /// Path as named.
        path: String,
    },
    /// The file is longer than [`MAX_MESH_BYTES`].
    #[error("\"{path}\": {bytes} bytes is more than the {max} a mesh may have")]
    TooLarge {
        /// Path as named.
        path: String,
        /// Its length.
        bytes: usize,
        /// The cap.
        max: usize,
    },
    /// More triangles or vertices than [`MAX_TRIANGLES`], [`MAX_VERTICES`].
    #[error("\"{path}\": {count} {what} is more than the {max} a mesh may have")]
    TooManyElements {
        /// Path as named.
        path: String,
        /// "triangles" or "vertices".
        what: &'static str,
        /// How many the file holds or declares.
        count: usize,
        /// The cap.
        max: usize,
    },
    /// The parser refused the bytes.
    #[error("\"{path}\": not a readable {format:?} file: {reason}")]
    Unreadable {
        /// Path as named.
        path: String,
        /// The format tried.
        format: MeshFormat,
        /// The parser's message.
        reason: String,
    },
    /// A binary STL shorter than its declared triangle count needs.
    #[error(
        "\"{path}\": declares {declared} triangles ({needed} bytes) but has {bytes} bytes: truncated"
    )]
    Truncated {
        /// Path as named.
        path: String,
        /// Triangles the header declares.
        declared: usize,
        /// Bytes those triangles need (84 + 50 each).
        needed: usize,
        /// Bytes the file has.
        bytes: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("\"{path}\": vertex {vertex} is not a finite point")]
    NotFinite {
        /// Path as named.
        path: String,
        /// Index of the vertex.
        vertex: usize,
    },
    /// A triangle names a vertex that does not exist.
    #[error("\"{path}\": triangle {triangle} names vertex {index} of {vertices}")]
    BadIndex {
        /// Path as named.
        path: String,
        /// Index of the triangle.
        triangle: usize,
        /// The index it names.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
}

/// Reads one mesh file.
///
/// `path` names the file (its extension picks the format; a `.gltf` or
/// `.glb` whose bytes start with `glTF` is read as GLB either way);
/// `resolve` returns the bytes of a file the mesh refers to (a glTF's
/// external buffers, relative to `path`), or `None`. All meshes of the file
/// are merged into one; units and frame are the file's (see the module
/// docs for COLLADA units and glTF nodes).
///
/// # Errors
/// [`MeshError`]: too large, unknown format, unreadable, not finite, bad
/// index, a missing glTF buffer. Nothing is returned from a refused file.
///
/// # Example
/// ```
/// use skeleton_avoidance::parsers::mesh::load_mesh;
/// let stl = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
/// let mesh = load_mesh("t.stl", stl, &mut |_| None)?;
/// assert_eq!(mesh.triangles.len(), 1);
/// # Ok::<(), skeleton_avoidance::parsers::mesh::MeshError>(())
/// ```
pub fn load_mesh(
    path: &str,
    bytes: &[u8],
    resolve: &mut dyn FnMut(&str) -> Option<Vec<u8>>,
) -> Result<TriMesh, MeshError> {
    if bytes.len() > MAX_MESH_BYTES {
        return Err(MeshError::TooLarge {
            path: path.to_owned(),
            bytes: bytes.len(),
            max: MAX_MESH_BYTES,
        });
    }
    let format = MeshFormat::from_path(path).ok_or_else(|| MeshError::UnknownFormat {
        path: path.to_owned(),
    })?;
    let unreadable = |e: std::io::Error| MeshError::Unreadable {
        path: path.to_owned(),
        format,
        reason: e.to_string(),
    };
    if format == MeshFormat::Stl {
        check_binary_stl(path, bytes)?;
    }
    let mesh = match format {
        MeshFormat::Stl => from_scene(mesh_loader::stl::from_slice(bytes).map_err(unreadable)?),
        MeshFormat::Obj => from_scene(
            mesh_loader::obj::from_slice(bytes, None, |_| Ok::<_, std::io::Error>(Vec::new()))
                .map_err(unreadable)?,
        ),
        MeshFormat::Collada => {
            from_scene(mesh_loader::collada::from_slice(bytes).map_err(unreadable)?)
        }
        MeshFormat::Gltf | MeshFormat::Glb => gltf_file::read(path, bytes, resolve)?,
    };
    checked(mesh, path)
}

/// Refuses a binary STL whose header declares more triangles than the cap or
/// than its bytes hold (an ASCII STL — all bytes ASCII — and a binary one
/// whose length matches or exceeds its count pass; trailing bytes are the
/// parser's to judge).
fn check_binary_stl(path: &str, bytes: &[u8]) -> Result<(), MeshError> {
    const HEADER: usize = 84;
    const TRIANGLE: usize = 50;
    let Some(count) = bytes.get(80..HEADER) else {
        return Ok(()); // too short for a binary header: the parser says why
    };
    let declared = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as usize;
    let needed = HEADER.saturating_add(declared.saturating_mul(TRIANGLE));
    if needed <= bytes.len() || bytes.is_ascii() {
        return Ok(());
    }
    if declared > MAX_TRIANGLES {
        return Err(MeshError::TooManyElements {
            path: path.to_owned(),
            what: "triangles",
            count: declared,
            max: MAX_TRIANGLES,
        });
    }
    Err(MeshError::Truncated {
        path: path.to_owned(),
        declared,
        needed,
        bytes: bytes.len(),
    })
}

fn from_scene(scene: mesh_loader::Scene) -> TriMesh {
    let mut out = TriMesh::default();
    for m in scene.meshes {
        let base = u32::try_from(out.vertices.len()).unwrap_or(u32::MAX);
        out.vertices.extend(
            m.vertices
                .iter()
                .map(|v| DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))),
        );
        out.triangles
            .extend(m.faces.iter().map(|f| f.map(|k| k.saturating_add(base))));
    }
    out
}

/// The mesh if it is within the caps, finite and its indices valid.
fn checked(mesh: TriMesh, path: &str) -> Result<TriMesh, MeshError> {
    for (what, count, max) in [
        ("triangles", mesh.triangles.len(), MAX_TRIANGLES),
        ("vertices", mesh.vertices.len(), MAX_VERTICES),
    ] {
        if count > max {
            return Err(MeshError::TooManyElements {
                path: path.to_owned(),
                what,
                count,
                max,
            });
        }
    }
    if let Some(vertex) = mesh.vertices.iter().position(|v| !v.is_finite()) {
        return Err(MeshError::NotFinite {
            path: path.to_owned(),
            vertex,
        });
    }
    let n = mesh.vertices.len();
    for (triangle, t) in mesh.triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&k| k as usize >= n) {
            return Err(MeshError::BadIndex {
                path: path.to_owned(),
                triangle,
                index,
                vertices: n,
            });
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nan_vertex_refuses_the_mesh() {
        let stl = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let e = load_mesh("t.stl", stl, &mut |_| None);
        assert!(
            matches!(e, Err(MeshError::NotFinite { vertex: 1, .. })),
            "{e:?}"
        );
    }

    #[test]
    fn a_binary_stl_declaring_more_triangles_than_it_holds_is_refused() {
        let mut b = vec![0u8; 84];
        b[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
        let tri: [f32; 12] = [0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0.];
        for f in tri {
            b.extend_from_slice(&f.to_le_bytes());
        }
        b.extend_from_slice(&[0, 0]);
        assert_eq!(
            load_mesh("t.stl", &b, &mut |_| None).map(|m| m.triangles.len()),
            Err(MeshError::TooManyElements {
                path: "t.stl".into(),
                what: "triangles",
                count: u32::MAX as usize,
                max: MAX_TRIANGLES,
            })
        );
        // Declaring what it holds: read.
        b[80..84].copy_from_slice(&1u32.to_le_bytes());
        assert_eq!(
            load_mesh("t.stl", &b, &mut |_| None).map(|m| m.triangles.len()),
            Ok(1)
        );
        // Two declared, one and a half there (cut mid-triangle): refused.
        b[80..84].copy_from_slice(&2u32.to_le_bytes());
        b.extend_from_slice(&[0u8; 25]);
        assert_eq!(
            load_mesh("t.stl", &b, &mut |_| None).map(|m| m.triangles.len()),
            Err(MeshError::Truncated {
                path: "t.stl".into(),
                declared: 2,
                needed: 184,
                bytes: 159,
            })
        );
    }

    #[test]
    fn truncated_and_oversized_files_are_refused_by_name() {
        let e = load_mesh("cut.stl", &[0u8; 90], &mut |_| None).map_err(|e| e.to_string());
        assert!(e.as_ref().is_err_and(|m| m.contains("cut.stl")), "{e:?}");
        let big = vec![0u8; MAX_MESH_BYTES + 1];
        let e = load_mesh("big.stl", &big, &mut |_| None);
        assert!(matches!(e, Err(MeshError::TooLarge { .. })), "{e:?}");
        let e = load_mesh("x.ply", b"ply", &mut |_| None);
        assert!(matches!(e, Err(MeshError::UnknownFormat { .. })), "{e:?}");
    }
}
