//! Mesh loading: one published file per format (crate/tests/data/meshes,
//! licences beside them), with vertex and triangle counts and bounds read
//! independently of the loader (the STL's header and 50-byte records, the
//! COLLADA `<triangles count>`, the OBJ's `v`/`f` lines, the glTF accessor's
//! own `min`/`max`); hostile input refused by name. Runs natively and,
//! unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DAffine3, DQuat, DVec3};
use skeleton_avoidance::mesh::TriMesh;
use skeleton_avoidance::parsers::mesh::{MeshError, load_mesh};

const PANDA_LINK0: &[u8] = include_bytes!("data/meshes/panda/collision/link0.stl");
const UR5_WRIST3: &[u8] = include_bytes!("data/meshes/formats/ur5_wrist3.dae");
const IIWA_POLYTOPE: &[u8] = include_bytes!("data/meshes/formats/iiwa14_link_7_polytope.obj");
const KUKA_GLTF: &[u8] = include_bytes!("data/meshes/formats/iiwa14_kuka.gltf");
const KUKA_BIN: &[u8] = include_bytes!("data/meshes/formats/kuka.bin");

fn none(_: &str) -> Option<Vec<u8>> {
    None
}

fn load(path: &str, bytes: &[u8]) -> TriMesh {
    load_mesh(path, bytes, &mut none).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn assert_bounds(m: &TriMesh, lo: [f64; 3], hi: [f64; 3], tol: f64) {
    let (a, b) = m.bounds().unwrap();
    for k in 0..3 {
        assert!(
            (a[k] - lo[k]).abs() <= tol,
            "min[{k}] {} vs {}",
            a[k],
            lo[k]
        );
        assert!(
            (b[k] - hi[k]).abs() <= tol,
            "max[{k}] {} vs {}",
            b[k],
            hi[k]
        );
    }
}

/// The triangles of a binary STL straight from its records.
fn stl_records(bytes: &[u8]) -> Vec<[[f32; 3]; 3]> {
    let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    (0..n)
        .map(|k| {
            let r = &bytes[84 + 50 * k + 12..84 + 50 * k + 48];
            let f = |i: usize| f32::from_le_bytes(r[4 * i..4 * i + 4].try_into().unwrap());
            [[f(0), f(1), f(2)], [f(3), f(4), f(5)], [f(6), f(7), f(8)]]
        })
        .collect()
}

#[test]
fn binary_stl_panda_link0() {
    let m = load("link0.stl", PANDA_LINK0);
    // (10084 − 84) / 50 records.
    assert_eq!(m.triangles.len(), 200);
    let records = stl_records(PANDA_LINK0);
    assert_eq!(records.len(), 200);
    for (k, r) in records.iter().enumerate() {
        let c = m.corners(k);
        for i in 0..3 {
            assert_eq!(c[i], DVec3::from_array(r[i].map(f64::from)), "triangle {k}");
        }
    }
    assert_bounds(
        &m,
        [-0.154_078_69, -0.094_613_75, -3.249_28e-5],
        [0.071_566_99, 0.094_670_44, 0.140_002_83],
        1e-8,
    );
}

#[test]
fn ascii_stl_gives_the_same_triangles_as_binary() {
    // No published description found ships ASCII STL: write the Panda's
    // binary link0.stl out as ASCII (shortest round-trip decimal of each
    // f32) and read it back.
    let mut text = String::from("solid link0\n");
    for r in stl_records(PANDA_LINK0) {
        text.push_str(" facet normal 0 0 0\n  outer loop\n");
        for v in r {
            text.push_str(&format!("   vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        text.push_str("  endloop\n endfacet\n");
    }
    text.push_str("endsolid link0\n");
    let ascii = load("link0_ascii.STL", text.as_bytes());
    let binary = load("link0.stl", PANDA_LINK0);
    assert_eq!(ascii.triangles.len(), 200);
    for k in 0..200 {
        assert_eq!(ascii.corners(k), binary.corners(k), "triangle {k}");
    }
}

#[test]
fn collada_ur5_wrist3() {
    let m = load("wrist3.dae", UR5_WRIST3);
    // Two <triangles count="1222"> and count="436"; unit 1 m, Z up.
    assert_eq!(m.triangles.len(), 1222 + 436);
    assert_bounds(
        &m,
        [-0.037_499_96, 0.047_324_95, -0.037_499_96],
        [0.037_499_96, 0.081_824_89, 0.042_999_98],
        1e-7,
    );
}

#[test]
fn obj_iiwa_link7_polytope() {
    let m = load("link_7_polytope.obj", IIWA_POLYTOPE);
    // 64 `v` lines, 124 triangular `f` lines; bounds from the `v` lines.
    assert_eq!(m.triangles.len(), 124);
    let text = std::str::from_utf8(IIWA_POLYTOPE).unwrap();
    let vs: Vec<[f64; 3]> = text
        .lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| {
            let f: Vec<f64> = l
                .split_whitespace()
                .skip(1)
                .map(|x| x.parse().unwrap())
                .collect();
            [f[0], f[1], f[2]]
        })
        .collect();
    assert_eq!(vs.len(), 64);
    for v in &m.vertices {
        assert!(
            vs.iter()
                .any(|w| (DVec3::from_array(*w) - *v).length() < 1e-6),
            "{v} is not a `v` line"
        );
    }
    assert_bounds(
        &m,
        [-0.051_854, -0.051_854, -1.4e-5],
        [0.051_854, 0.051_854, 0.044_998],
        1e-6,
    );
}

fn kuka_resolver(path: &str) -> Option<Vec<u8>> {
    (path == "meshes/kuka.bin").then(|| KUKA_BIN.to_vec())
}

#[test]
fn gltf_iiwa_kuka_lettering_with_external_buffer() {
    let m = load_mesh("meshes/kuka.gltf", KUKA_GLTF, &mut kuka_resolver).unwrap();
    // The positions accessor: count 206, min/max as written in the JSON.
    assert_eq!(m.vertices.len(), 206);
    assert_bounds(
        &m,
        [
            -0.047_981_001_436_710_36,
            0.008_081_999_607_384_205,
            -0.067_936_003_208_160_4,
        ],
        [
            0.047_981_001_436_710_36,
            0.024_651_000_276_207_924,
            0.067_936_003_208_160_4,
        ],
        1e-12,
    );
    assert_eq!(m.triangles.len(), 194);
    // Without its buffer: refused, naming the buffer.
    let e = load_mesh("meshes/kuka.gltf", KUKA_GLTF, &mut none);
    assert!(
        matches!(&e, Err(MeshError::Missing { path }) if path == "meshes/kuka.bin"),
        "{e:?}"
    );
}

/// The glTF above packed into a GLB container (JSON chunk with the buffer's
/// URI removed, BIN chunk holding kuka.bin).
fn kuka_glb() -> Vec<u8> {
    let json = std::str::from_utf8(KUKA_GLTF).unwrap();
    let json = json.replace(
        "\"byteLength\": 6108,\n      \"uri\": \"kuka.bin\"",
        "\"byteLength\": 6108",
    );
    assert!(!json.contains("kuka.bin"), "the URI must be gone");
    let mut j = json.into_bytes();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut bin = KUKA_BIN.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

#[test]
fn glb_gives_the_same_mesh_as_gltf() {
    let glb = load("kuka.glb", &kuka_glb());
    let gltf = load_mesh("meshes/kuka.gltf", KUKA_GLTF, &mut kuka_resolver).unwrap();
    assert_eq!(glb, gltf);
    // A truncated container is refused by name.
    let cut = &kuka_glb()[..400];
    let e = load_mesh("kuka.glb", cut, &mut none).map_err(|e| e.to_string());
    assert!(e.as_ref().is_err_and(|m| m.contains("kuka.glb")), "{e:?}");
}

#[test]
fn urdf_scale_and_origin_are_applied_in_that_order() {
    let m = load("link0.stl", PANDA_LINK0);
    let pose = DAffine3::from_rotation_translation(
        DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        DVec3::new(1.0, 2.0, 3.0),
    );
    let t = m.transformed(&pose, DVec3::new(2.0, 1.0, 1.0));
    for (v, w) in m.vertices.iter().zip(&t.vertices) {
        let expect = DVec3::new(1.0 - v.y, 2.0 + 2.0 * v.x, 3.0 + v.z);
        assert!((expect - *w).length() < 1e-12);
    }
    // A mirror turns the triangles over, so the enclosed volume stays positive
    // and scales by |det|.
    let mirrored = m.transformed(&DAffine3::IDENTITY, DVec3::new(-1.0, 1.0, 1.0));
    assert!((mirrored.volume() - m.volume()).abs() < 1e-12);
}

#[test]
fn hostile_files_are_refused_with_their_name() {
    // A COLLADA file cut in the middle, an OBJ naming a vertex that does not
    // exist, an OBJ with a NaN, a glTF declaring more vertices than allowed.
    let cut = &UR5_WRIST3[..UR5_WRIST3.len() / 2];
    let e = load_mesh("cut.dae", cut, &mut none).map_err(|e| e.to_string());
    assert!(e.as_ref().is_err_and(|m| m.contains("cut.dae")), "{e:?}");
    let e = load_mesh(
        "nan.obj",
        b"v 0 0 0\nv NaN 0 0\nv 0 1 0\nf 1 2 3\n",
        &mut none,
    );
    assert!(
        matches!(
            e,
            Err(MeshError::NotFinite { .. }) | Err(MeshError::Unreadable { .. })
        ),
        "{e:?}"
    );
    let e = load_mesh(
        "idx.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
        &mut none,
    );
    assert!(e.is_err(), "{e:?}");
    let huge = std::str::from_utf8(KUKA_GLTF).unwrap().replacen(
        "\"count\": 206",
        "\"count\": 4000000000",
        1,
    );
    let e = load_mesh("meshes/huge.gltf", huge.as_bytes(), &mut kuka_resolver)
        .map_err(|e| e.to_string());
    assert!(e.as_ref().is_err_and(|m| m.contains("huge.gltf")), "{e:?}");
}
