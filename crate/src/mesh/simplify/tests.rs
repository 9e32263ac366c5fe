//! Simplification of a sphere, a flat sheet and a published link mesh:
//! budgets met, closed surfaces kept closed and wound the same way, borders
//! kept, and the simplified surface near the original. Natively and under
//! `wasm-pack test --node`. Compiled only through `#[cfg(test)] mod tests;`:
//! its unwraps cannot reach a JavaScript caller.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::collections::HashMap;

use glam::DVec3;
use parry3d_f64::math::Vector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::Triangle;

use super::simplify;

/// An icosphere of radius `r` subdivided `levels` times (20 · 4^levels triangles).
fn icosphere(r: f64, levels: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = HashMap::new();
        let mut next = Vec::new();
        for tri in &f {
            let mut m = [0u32; 3];
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                m[e] = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    v.push((v[a as usize] + v[b as usize]).normalize());
                    (v.len() - 1) as u32
                });
            }
            next.extend([
                [tri[0], m[0], m[2]],
                [tri[1], m[1], m[0]],
                [tri[2], m[2], m[1]],
                m,
            ]);
        }
        f = next;
    }
    (v.into_iter().map(|p| p * r).collect(), f)
}

/// Every directed edge once and its reverse once: closed, consistently wound.
fn closed(triangles: &[[u32; 3]]) -> bool {
    let mut edges = HashMap::new();
    for t in triangles {
        for e in 0..3 {
            *edges.entry((t[e], t[(e + 1) % 3])).or_insert(0) += 1;
        }
    }
    edges
        .iter()
        .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
}

fn volume(v: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| v[t[0] as usize].dot(v[t[1] as usize].cross(v[t[2] as usize])) / 6.0)
        .sum()
}

#[test]
fn a_sphere_keeps_its_shape_closed_and_outwards() {
    let (v, t) = icosphere(0.1, 4);
    assert_eq!(t.len(), 5120);
    let (sv, st) = simplify(&v, &t, 500);
    assert!((400..=500).contains(&st.len()), "{}", st.len());
    eprintln!("sphere: 5120 -> {} triangles", st.len());
    assert!(closed(&st));
    let (before, after) = (volume(&v, &t), volume(&sv, &st));
    assert!(
        after > 0.0 && (after / before - 1.0).abs() < 0.03,
        "{before} {after}"
    );
    for p in &sv {
        assert!((p.length() - 0.1).abs() < 1e-3, "{}", p.length());
    }
}

#[test]
fn a_sheet_keeps_its_border_and_stays_flat() {
    let n = 20u32;
    let v: Vec<DVec3> = (0..=n)
        .flat_map(|i| {
            (0..=n).map(move |j| {
                DVec3::new(
                    f64::from(i) / f64::from(n),
                    f64::from(j) / f64::from(n),
                    0.0,
                )
            })
        })
        .collect();
    let at = |i: u32, j: u32| i * (n + 1) + j;
    let t: Vec<[u32; 3]> = (0..n)
        .flat_map(|i| {
            (0..n).flat_map(move |j| {
                [
                    [at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                    [at(i, j), at(i + 1, j + 1), at(i, j + 1)],
                ]
            })
        })
        .collect();
    let (sv, st) = simplify(&v, &t, 60);
    assert!(st.len() <= 60 && st.len() >= 2, "{}", st.len());
    let area: f64 = st
        .iter()
        .map(|k| {
            0.5 * (sv[k[1] as usize] - sv[k[0] as usize])
                .cross(sv[k[2] as usize] - sv[k[0] as usize])
                .z
        })
        .sum();
    assert!((area - 1.0).abs() < 1e-9, "{area}");
    for p in &sv {
        assert!(
            p.z.abs() < 1e-12
                && (-1e-12..=1.0 + 1e-12).contains(&p.x)
                && (-1e-12..=1.0 + 1e-12).contains(&p.y),
            "{p}"
        );
    }
}

#[test]
fn a_published_link_mesh_stays_within_a_millimetre_and_a_half() {
    let bytes = include_bytes!("../../../tests/data/meshes/iiwa14/collision/link_1.stl");
    let mesh = crate::parsers::mesh::load_mesh("link_1.stl", bytes, &mut |_| None).unwrap();
    // Merge the STL's repeated corners first, as the viewer does.
    let mut index = HashMap::new();
    let mut v = Vec::new();
    let t: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|tri| {
            tri.map(|i| {
                let p = mesh.vertices[i as usize];
                *index
                    .entry(p.to_array().map(f64::to_bits))
                    .or_insert_with(|| {
                        v.push(p);
                        (v.len() - 1) as u32
                    })
            })
        })
        .collect();
    let target = t.len() / 4;
    let (sv, st) = simplify(&v, &t, target);
    assert!(
        st.len() <= target && st.len() > target / 2,
        "{} of {}",
        st.len(),
        t.len()
    );
    assert_eq!(closed(&t), closed(&st));
    let originals: Vec<Triangle> = t
        .iter()
        .map(|k| {
            let p = k.map(|i| Vector::new(v[i as usize].x, v[i as usize].y, v[i as usize].z));
            Triangle::new(p[0], p[1], p[2])
        })
        .collect();
    let mut worst: f64 = 0.0;
    for p in &sv {
        let q = Vector::new(p.x, p.y, p.z);
        let d = originals
            .iter()
            .map(|tri| (tri.project_local_point(q, true).point - q).length())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    eprintln!(
        "link_1: {} -> {} triangles, farthest vertex {worst:.2e} m",
        t.len(),
        st.len()
    );
    assert!(
        worst < 1.5e-3,
        "a vertex {worst} m off the original surface"
    );
}

#[test]
fn a_mesh_within_budget_or_with_a_bad_index_comes_back_as_it_is() {
    let (v, t) = icosphere(1.0, 1);
    assert_eq!(simplify(&v, &t, 80), (v.clone(), t.clone()));
    let bad = vec![[0, 1, 99]; 100];
    assert_eq!(simplify(&v, &bad, 10), (v, bad));
}
