// Shaders of the playground renderer.
//
// Everything arrives lit and in the surface's colour space: colours are
// given sRGB-encoded (as in CSS), lit in linear space on the CPU and encoded
// back to sRGB there when the surface format is not an sRGB one, so the
// pixels are the same on WebGPU and WebGL2 whichever format the surface ends
// up with (render/solids.rs, render/flat.rs). The shaders only place the
// vertices and pass the colour on: a software rasteriser (SwiftShader)
// shades vertices and fragments slowly, and `pow` per fragment once was most
// of a frame. Flat triangles, lines and the grid have one colour per
// primitive; each solid is cut finely enough for its size on screen (its
// outline within a pixel or so, view/tessellation.rs) that lighting its
// vertices reads like lighting its pixels.

struct Globals {
    view_proj: mat4x4<f32>,
    // Unit vector from the scene towards the camera (the headlight).
    to_camera: vec4<f32>,
    // Unit vector towards the key light.
    key_light: vec4<f32>,
    // x, y: drawing-buffer size in pixels; z: 1 when colours are encoded
    // to sRGB before they arrive (the surface format is not an sRGB one).
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct Out {
    @builtin(position) clip: vec4<f32>,
    // Lit and encoded.
    @location(0) color: vec4<f32>,
};

// Capsules, spheres, flat triangles and the grid's hairlines: a position in
// the world.
@vertex
fn vs_world(@location(0) position: vec3<f32>, @location(1) color: vec4<f32>) -> Out {
    var out: Out;
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.color = color;
    return out;
}

// Lines: the corners of screen-space quads of a given width in pixels,
// placed in clip space.
@vertex
fn vs_clip(@location(0) clip: vec4<f32>, @location(1) color: vec4<f32>) -> Out {
    var out: Out;
    out.clip = clip;
    out.color = color;
    return out;
}

@fragment
fn fs_color(in: Out) -> @location(0) vec4<f32> {
    return in.color;
}
