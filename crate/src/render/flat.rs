//! Lines, flat triangles and the grid, lit and encoded on the CPU each
//! frame (as the capsules are, `solids.rs`), so that the shaders only place
//! the vertices: a software rasteriser shades vertices slowly, and a line
//! drawn as an instance is a draw of its own there.

use glam::{Vec2, Vec3, Vec4};

use super::geometry::{ClipVertex, ShadedVertex};
use super::solids::{Shading, Viewpoint, srgb_to_linear};
use crate::view::{Grid, Line, Triangle};

/// The colour `srgb` unlit, in the surface's colour space.
fn unlit(color: [f32; 4], shading: &Shading<'_>) -> [f32; 4] {
    if shading.encode {
        color.map(|c| c.clamp(0.0, 1.0))
    } else {
        let [r, g, b, a] = color;
        [srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b), a]
    }
}

/// Lines as screen-space quads of their width in pixels (two triangles
/// each, in clip space), opaque ones first; returns how many lines are
/// opaque. Lines with a non-finite value are dropped.
pub(super) fn line_quads(lines: &[Line], shading: &Shading<'_>, out: &mut Vec<ClipVertex>) -> u32 {
    out.clear();
    let finite = |l: &&Line| {
        l.a.iter()
            .chain(&l.b)
            .chain(&l.color)
            .chain([&l.width])
            .all(|x| x.is_finite())
    };
    let (opaque, blended): (Vec<&Line>, Vec<&Line>) =
        lines.iter().filter(finite).partition(|l| l.color[3] >= 1.0);
    let half_px = shading.half_px;
    for l in opaque.iter().chain(&blended) {
        let c0 = shading.view_proj * Vec3::from(l.a).extend(1.0);
        let c1 = shading.view_proj * Vec3::from(l.b).extend(1.0);
        let s0 = c0.truncate().truncate() / c0.w.abs().max(1e-6) * half_px;
        let s1 = c1.truncate().truncate() / c1.w.abs().max(1e-6) * half_px;
        let mut d = s1 - s0;
        if d.length() < 1e-6 {
            d = Vec2::X;
        }
        let d = d.normalize();
        let color = unlit(l.color, shading);
        let width = l.width.max(0.0);
        // Corners as (which end, which side), two triangles.
        for (end, side) in [
            (0, -1.0),
            (1, -1.0),
            (1, 1.0),
            (0, -1.0),
            (1, 1.0),
            (0, 1.0),
        ] {
            let normal_px = Vec2::new(-d.y, d.x) * side * 0.5 * width;
            let c: Vec4 = if end == 1 { c1 } else { c0 };
            let xy = c.truncate().truncate() + normal_px / half_px * c.w;
            out.push(ClipVertex {
                clip: [xy.x, xy.y, c.z, c.w],
                color,
            });
        }
    }
    opaque.len() as u32
}

/// Triangles as lit vertices, opaque first (`closed` ones only where they
/// face `viewpoint`), then translucent ones back to front by centroid from
/// `eye`; returns how many vertices are opaque. Each face is lit on the
/// side the camera sees. Triangles with a non-finite value are dropped.
pub(super) fn triangle_vertices(
    (triangles, closed): (&[Triangle], &[Triangle]),
    (eye, viewpoint): (Vec3, Viewpoint),
    shading: &Shading<'_>,
    out: &mut Vec<ShadedVertex>,
) -> u32 {
    out.clear();
    let finite = |t: &&Triangle| t.p.iter().flatten().chain(&t.color).all(|x| x.is_finite());
    let (mut opaque, mut blend): (Vec<&Triangle>, Vec<&Triangle>) = triangles
        .iter()
        .filter(finite)
        .partition(|t| t.color[3] >= 1.0);
    opaque.extend(
        closed
            .iter()
            .filter(finite)
            .filter(|t| !viewpoint.faces_away(t.p.map(Vec3::from))),
    );
    let centroid =
        |t: &Triangle| (Vec3::from(t.p[0]) + Vec3::from(t.p[1]) + Vec3::from(t.p[2])) / 3.0;
    blend.sort_by(|x, y| {
        centroid(y)
            .distance_squared(eye)
            .total_cmp(&centroid(x).distance_squared(eye))
    });
    let opaque_vertices = 3 * opaque.len() as u32;
    // Faces of a mesh share their colour.
    let mut decoded: Option<([f32; 4], [f32; 3])> = None;
    for t in opaque.into_iter().chain(blend) {
        let [a, b, c] = t.p.map(Vec3::from);
        let mut n = (b - a).cross(c - a).normalize_or(Vec3::Z);
        if n.dot(shading.to_camera) < 0.0 {
            n = -n;
        }
        let key = n.dot(shading.key_light).max(0.0);
        let head = n.dot(shading.to_camera).max(0.0);
        let light = 0.35 + 0.4 * key + 0.3 * head;
        let srgb = [t.color[0], t.color[1], t.color[2]];
        let linear = match decoded {
            Some((color, linear)) if color == t.color => linear,
            _ => {
                let linear = srgb.map(srgb_to_linear);
                decoded = Some((t.color, linear));
                linear
            }
        };
        let [r, g, b] = shading.lit(srgb, linear, light);
        let color = [r, g, b, t.color[3]];
        out.extend(t.p.iter().map(|&position| ShadedVertex { position, color }));
    }
    opaque_vertices
}

/// Adds the lines of `grid` (the two through the origin in the axis
/// colour) as pairs of vertices: every [`Grid::COARSE`]-th line across the
/// whole square, the others across the fine square only.
pub(super) fn push_grid(lines: &mut Vec<ShadedVertex>, grid: &Grid, shading: &Shading<'_>) {
    if !(grid.spacing.is_finite() && grid.half_extent.is_finite())
        || grid.spacing <= 0.0
        || grid.half_extent <= 0.0
    {
        return;
    }
    let h = grid.half_extent;
    let fine = if grid.fine_extent.is_finite() {
        grid.fine_extent.clamp(0.0, h)
    } else {
        h
    };
    let n = ((h / grid.spacing).floor() as i32).min(500);
    let (color, axis_color) = (unlit(grid.color, shading), unlit(grid.axis_color, shading));
    for i in -n..=n {
        let t = i as f32 * grid.spacing;
        let reach = if i % Grid::COARSE == 0 {
            h
        } else if t.abs() <= fine + 1e-4 {
            fine
        } else {
            continue;
        };
        let color = if i == 0 { axis_color } else { color };
        for (a, b) in [
            ([t, -reach, 0.0], [t, reach, 0.0]),
            ([-reach, t, 0.0], [reach, t, 0.0]),
        ] {
            for position in [a, b] {
                lines.push(ShadedVertex { position, color });
            }
        }
    }
}
