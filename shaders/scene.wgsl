// blockworld scene shader (issue #2): flat Lambert gray levels computed on the CPU
// (src/render/gpu/mesh.rs), a dark seam about one pixel wide centred on every block face edge,
// and the ground truth: depth along the optical axis (1/16 mm steps) and block ids.

struct Frame {
    // World mm to wgpu clip space (Camera::clip_from_world).
    clip_from_world: mat4x4<f32>,
    // Third row of Camera::view_from_world: depth_mm = -dot(view_z_row, vec4(p, 1)).
    view_z_row: vec4<f32>,
    // A fragment is seam when it lies closer than this to an edge line of its face, in px.
    seam_half_width_px: f32,
    // Gray level of the seam, 0..255.
    seam_level: f32,
    // Depth PNG steps per mm (render::DEPTH_UNITS_PER_MM).
    depth_units_per_mm: f32,
    _pad: f32,
};

@group(0) @binding(0) var<uniform> frame: Frame;

struct VertexIn {
    @location(0) position_mm: vec3<f32>,
    @location(1) edge_mm_a: vec4<f32>,
    @location(2) edge_mm_b: vec4<f32>,
    // (gray level, block index + 1)
    @location(3) shade: vec2<u32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // Distances to the face's edge lines: affine over the face, interpolated exactly.
    @location(0) edge_mm_a: vec4<f32>,
    @location(1) edge_mm_b: vec4<f32>,
    @location(2) depth_mm: f32,
    @location(3) @interpolate(flat) shade: vec2<u32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let p = vec4<f32>(v.position_mm, 1.0);
    var out: VertexOut;
    out.clip = frame.clip_from_world * p;
    out.edge_mm_a = v.edge_mm_a;
    out.edge_mm_b = v.edge_mm_b;
    out.depth_mm = -dot(frame.view_z_row, p);
    out.shade = v.shade;
    return out;
}

// Distance in pixels to each edge line: the distance in mm over its screen-space gradient
// length (mm per pixel across the line).
fn edge_px(d: vec4<f32>) -> vec4<f32> {
    let gx = dpdx(d);
    let gy = dpdy(d);
    let g = sqrt(gx * gx + gy * gy);
    return d / max(g, vec4<f32>(1e-20));
}

fn gray_of(in: VertexOut) -> vec4<f32> {
    let a = edge_px(in.edge_mm_a);
    let b = edge_px(in.edge_mm_b);
    let m = min(min(min(a.x, a.y), min(a.z, a.w)), min(min(b.x, b.y), min(b.z, b.w)));
    let level = select(f32(in.shade.x), frame.seam_level, m < frame.seam_half_width_px);
    return vec4<f32>(level / 255.0, 0.0, 0.0, 1.0);
}

fn depth_of(in: VertexOut) -> u32 {
    return u32(clamp(round(in.depth_mm * frame.depth_units_per_mm), 1.0, 65535.0));
}

struct AllOut {
    @location(0) gray: vec4<f32>,
    @location(1) depth: u32,
    @location(2) id: u32,
};

// Without MSAA: picture and ground truth in one pass.
@fragment
fn fs_all(in: VertexOut) -> AllOut {
    var out: AllOut;
    out.gray = gray_of(in);
    out.depth = depth_of(in);
    out.id = in.shade.y;
    return out;
}

// With MSAA: the picture alone (multisampled, then resolved).
@fragment
fn fs_gray(in: VertexOut) -> @location(0) vec4<f32> {
    return gray_of(in);
}

struct TruthOut {
    @location(0) depth: u32,
    @location(1) id: u32,
};

// With MSAA: the ground truth in a second, single-sampled pass.
@fragment
fn fs_truth(in: VertexOut) -> TruthOut {
    var out: TruthOut;
    out.depth = depth_of(in);
    out.id = in.shade.y;
    return out;
}
