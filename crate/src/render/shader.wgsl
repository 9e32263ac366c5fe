// Shaders of the playground renderer.
//
// Colours arrive sRGB-encoded (as in CSS) and are decoded per vertex.
// Lighting is computed in linear space; the result is encoded back to sRGB here when the surface format is
// not an sRGB one (`globals.viewport.z == 1`), so the pixels are the same on
// WebGPU and WebGL2 whichever format the surface ends up with. Capsules and
// spheres arrive lit and encoded already, by the same formulas on the CPU
// (render/solids.rs).
//
// Everything is lit and encoded per vertex and the fragment shaders only
// pass the colour on: a software rasteriser (SwiftShader) spends most of a
// frame shading the fragments of large translucent volumes, and three `pow`
// per fragment were most of that. Flat triangles, lines and the grid have
// one colour per primitive, so nothing changes for them; the capsule
// template (lit per vertex on the CPU) is fine enough (18 sectors, 7 rings per cap) that lighting its
// vertices reads the same as lighting its pixels.

struct Globals {
    view_proj: mat4x4<f32>,
    // Unit vector from the scene towards the camera (the headlight).
    to_camera: vec4<f32>,
    // Unit vector towards the key light.
    key_light: vec4<f32>,
    // x, y: drawing-buffer size in pixels; z: 1 to encode sRGB in the shader.
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

fn encode(linear: vec3<f32>) -> vec3<f32> {
    if globals.viewport.z > 0.5 {
        return linear_to_srgb(clamp(linear, vec3<f32>(0.0), vec3<f32>(1.0)));
    }
    return linear;
}

// ---- Solids: tapered capsules and spheres, lit on the CPU ----

struct SolidOut {
    @builtin(position) clip: vec4<f32>,
    // Lit and encoded.
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_solid(@location(0) position: vec3<f32>, @location(1) color: vec4<f32>) -> SolidOut {
    var out: SolidOut;
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.color = color;
    return out;
}

@fragment
fn fs_solid(in: SolidOut) -> @location(0) vec4<f32> {
    return in.color;
}

// ---- Lines: screen-space quads of a given width in pixels ----

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_line(
    // Template: x = which end (0 or 1), y = which side of the line (-1 or 1).
    @location(0) corner: vec2<f32>,
    @location(1) p0_width: vec4<f32>,
    @location(2) p1: vec4<f32>,
    @location(3) color: vec4<f32>,
) -> LineOut {
    let c0 = globals.view_proj * vec4<f32>(p0_width.xyz, 1.0);
    let c1 = globals.view_proj * vec4<f32>(p1.xyz, 1.0);
    let half_px = 0.5 * globals.viewport.xy;
    let s0 = c0.xy / max(abs(c0.w), 1e-6) * half_px;
    let s1 = c1.xy / max(abs(c1.w), 1e-6) * half_px;
    var d = s1 - s0;
    if length(d) < 1e-6 {
        d = vec2<f32>(1.0, 0.0);
    }
    d = normalize(d);
    let normal_px = vec2<f32>(-d.y, d.x) * corner.y * 0.5 * p0_width.w;
    var c = c0;
    if corner.x > 0.5 {
        c = c1;
    }
    var out: LineOut;
    out.clip = vec4<f32>(c.xy + normal_px / half_px * c.w, c.z, c.w);
    out.color = vec4<f32>(encode(srgb_to_linear(color.rgb)), color.a);
    return out;
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.color;
}

// ---- Meshes: flat triangles lit from both sides ----

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    // Lit (triangles) or not (hairlines), and encoded.
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_mesh(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
) -> MeshOut {
    // Light whichever face is seen: turn the normal towards the camera. The
    // normal is the face's, the same at its three corners.
    var n = normalize(normal);
    if dot(n, globals.to_camera.xyz) < 0.0 {
        n = -n;
    }
    let key = max(dot(n, globals.key_light.xyz), 0.0);
    let head = max(dot(n, globals.to_camera.xyz), 0.0);
    let light = 0.35 + 0.4 * key + 0.3 * head;
    var out: MeshOut;
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.color = vec4<f32>(encode(srgb_to_linear(color.rgb) * light), color.a);
    return out;
}

@fragment
fn fs_mesh(in: MeshOut) -> @location(0) vec4<f32> {
    return in.color;
}

// ---- Hairlines (the ground grid): one pixel wide, unlit ----

@vertex
fn vs_hair(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
) -> MeshOut {
    var out: MeshOut;
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.color = vec4<f32>(encode(srgb_to_linear(color.rgb)), color.a);
    return out;
}
