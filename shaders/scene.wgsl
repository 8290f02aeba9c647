// blockworld scene shader: flat Lambert gray levels computed on the CPU
// (src/render/gpu/mesh.rs), a dark seam about one pixel wide centred on every block face edge,
// and the ground truth: depth along the optical axis (1/16 mm steps) and block ids.
//
// The seam: each vertex carries the lines of its face's projected edges in framebuffer pixels
// (a, b, c with a^2 + b^2 = 1, computed on the CPU in f64), so |a x + b y + c| at the fragment's
// pixel centre is its exact distance in px from the edge line in the picture.

struct Frame {
    // World mm to wgpu clip space (Camera::clip_from_world).
    clip_from_world: mat4x4<f32>,
    // Third row of Camera::view_from_world: depth_mm = -dot(view_z_row, vec4(p, 1)).
    view_z_row: vec4<f32>,
    // A fragment is seam when it lies closer than this to an edge line of its face, in px
    // (silhouette edges also darken the nearest pixel on the face's side; see is_seam).
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
    // Eight edge lines (a, b, c), packed into six vec4s.
    @location(1) lines_0: vec4<f32>,
    @location(2) lines_1: vec4<f32>,
    @location(3) lines_2: vec4<f32>,
    @location(4) lines_3: vec4<f32>,
    @location(5) lines_4: vec4<f32>,
    @location(6) lines_5: vec4<f32>,
    // (gray level, block index + 1)
    @location(7) shade: vec2<u32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) lines_0: vec4<f32>,
    @location(1) @interpolate(flat) lines_1: vec4<f32>,
    @location(2) @interpolate(flat) lines_2: vec4<f32>,
    @location(3) @interpolate(flat) lines_3: vec4<f32>,
    @location(4) @interpolate(flat) lines_4: vec4<f32>,
    @location(5) @interpolate(flat) lines_5: vec4<f32>,
    // Depth along the optical axis: affine in world space, so perspective-correct
    // interpolation gives it exactly.
    @location(6) depth_mm: f32,
    @location(7) @interpolate(flat) shade: vec2<u32>,
};

// The seam's cost follows the face (src/render/gpu/mesh.rs, SeamLines): a face whose edge
// lines all sit in the first four slots (every catalog face, the floor aside) carries only
// those, and the floor, which has no edge line, carries none. Unused slots hold a line far
// outside the picture that is never seam, so leaving them out changes no pixel.

// A face with at most four edge lines: slots 0..3 in three vec4s, with each line's norm and
// seam limit computed once per vertex (see seam_limit_px) instead of once per pixel.
struct FourLinesOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) lines_0: vec4<f32>,
    @location(1) @interpolate(flat) lines_1: vec4<f32>,
    @location(2) @interpolate(flat) lines_2: vec4<f32>,
    // |l.xy| of the four lines.
    @location(3) @interpolate(flat) norms: vec4<f32>,
    // seam_limit_px of the four lines.
    @location(4) @interpolate(flat) limits_px: vec4<f32>,
    @location(6) depth_mm: f32,
    @location(7) @interpolate(flat) shade: vec2<u32>,
};

// A face without edge lines (the floor).
struct NoLinesOut {
    @builtin(position) clip: vec4<f32>,
    @location(6) depth_mm: f32,
    @location(7) @interpolate(flat) shade: vec2<u32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let p = vec4<f32>(v.position_mm, 1.0);
    var out: VertexOut;
    out.clip = frame.clip_from_world * p;
    out.lines_0 = v.lines_0;
    out.lines_1 = v.lines_1;
    out.lines_2 = v.lines_2;
    out.lines_3 = v.lines_3;
    out.lines_4 = v.lines_4;
    out.lines_5 = v.lines_5;
    out.depth_mm = -dot(frame.view_z_row, p);
    out.shade = v.shade;
    return out;
}

@vertex
fn vs_four_lines(v: VertexIn) -> FourLinesOut {
    let p = vec4<f32>(v.position_mm, 1.0);
    var out: FourLinesOut;
    out.clip = frame.clip_from_world * p;
    out.lines_0 = v.lines_0;
    out.lines_1 = v.lines_1;
    out.lines_2 = v.lines_2;
    let l0 = v.lines_0.xyz;
    let l1 = vec3<f32>(v.lines_0.w, v.lines_1.xy);
    let l2 = vec3<f32>(v.lines_1.zw, v.lines_2.x);
    let l3 = v.lines_2.yzw;
    out.norms = vec4<f32>(length(l0.xy), length(l1.xy), length(l2.xy), length(l3.xy));
    out.limits_px = vec4<f32>(seam_limit_px(l0), seam_limit_px(l1), seam_limit_px(l2), seam_limit_px(l3));
    out.depth_mm = -dot(frame.view_z_row, p);
    out.shade = v.shade;
    return out;
}

@vertex
fn vs_no_lines(v: VertexIn) -> NoLinesOut {
    let p = vec4<f32>(v.position_mm, 1.0);
    var out: NoLinesOut;
    out.clip = frame.clip_from_world * p;
    out.depth_mm = -dot(frame.view_z_row, p);
    out.shade = v.shade;
    return out;
}

// Whether the pixel centre `f` is seam for edge line `l`: within the half width of the line,
// or, for a silhouette edge (its line scaled by 2, so |l.xy| = 2), the nearest pixel centre on
// the face's side in its row or column (one step along the axis closest to the line's normal
// crosses the line).
fn seam_of_line(l: vec3<f32>, f: vec2<f32>) -> bool {
    let n = length(l.xy);
    let d = abs(l.x * f.x + l.y * f.y + l.z) / n;
    let step_px = max(abs(l.x), abs(l.y)) / n;
    return d < frame.seam_half_width_px || (n > 1.5 && d < step_px);
}

// The distance below which a pixel centre is seam for edge line `l`, the same test as
// seam_of_line: d < half width, or for a silhouette line also d < step_px, is d below the larger
// of the two. The same f32 operations as seam_of_line, so the same bits.
fn seam_limit_px(l: vec3<f32>) -> f32 {
    let n = length(l.xy);
    let step_px = max(abs(l.x), abs(l.y)) / n;
    return select(frame.seam_half_width_px, max(frame.seam_half_width_px, step_px), n > 1.5);
}

// seam_of_line with the line's norm `n` and seam_limit_px `limit_px` computed beforehand.
fn seam_of_line_within(l: vec3<f32>, n: f32, limit_px: f32, f: vec2<f32>) -> bool {
    return abs(l.x * f.x + l.y * f.y + l.z) / n < limit_px;
}

// Whether the pixel centre `f` is seam for any of the four lines of a FourLinesOut.
fn seam_of_four_lines_within(in: FourLinesOut) -> bool {
    let f = in.clip.xy;
    let u0 = in.lines_0;
    let u1 = in.lines_1;
    let u2 = in.lines_2;
    let n = in.norms;
    let m = in.limits_px;
    let s0 = seam_of_line_within(u0.xyz, n.x, m.x, f)
        || seam_of_line_within(vec3<f32>(u0.w, u1.xy), n.y, m.y, f);
    let s1 = seam_of_line_within(vec3<f32>(u1.zw, u2.x), n.z, m.z, f)
        || seam_of_line_within(u2.yzw, n.w, m.w, f);
    return s0 || s1;
}

// Whether the pixel centre `f` is seam for any of the four lines packed into `u0`, `u1`, `u2`.
fn seam_of_four_lines(u0: vec4<f32>, u1: vec4<f32>, u2: vec4<f32>, f: vec2<f32>) -> bool {
    let s0 = seam_of_line(u0.xyz, f) || seam_of_line(vec3<f32>(u0.w, u1.xy), f);
    let s1 = seam_of_line(vec3<f32>(u1.zw, u2.x), f) || seam_of_line(u2.yzw, f);
    return s0 || s1;
}

// Whether the fragment's pixel centre is seam for any edge of its face.
fn is_seam(in: VertexOut) -> bool {
    let f = in.clip.xy;
    return seam_of_four_lines(in.lines_0, in.lines_1, in.lines_2, f)
        || seam_of_four_lines(in.lines_3, in.lines_4, in.lines_5, f);
}

// The gray level of a fragment of a face of flat level `shade.x`, seam or not, for the
// normalized gray target of the multisampled pass (resolving averages the samples).
fn gray_level(shade: vec2<u32>, seam: bool) -> vec4<f32> {
    let level = select(f32(shade.x), frame.seam_level, seam);
    return vec4<f32>(level / 255.0, 0.0, 0.0, 1.0);
}

// The same level as an integer, for the single-sampled pass's integer gray target: the level
// itself, with no conversion to and from [0, 1] per pixel (the same bytes: the normalized
// target stores round(level / 255 * 255) = level).
fn gray_level_u32(shade: vec2<u32>, seam: bool) -> u32 {
    return select(shade.x, u32(frame.seam_level), seam);
}

fn gray_of(in: VertexOut) -> vec4<f32> {
    return gray_level(in.shade, is_seam(in));
}

fn depth_of(depth_mm: f32) -> u32 {
    return u32(clamp(round(depth_mm * frame.depth_units_per_mm), 1.0, 65535.0));
}

// The ground truth of a fragment in one 32-bit word, so one target holds both: depth (1/16 mm)
// in the high 16 bits, block index + 1 in the low 16 (src/render/gpu/mod.rs splits them while
// it copies the readback out).
fn truth_of(depth_mm: f32, shade: vec2<u32>) -> u32 {
    return (depth_of(depth_mm) << 16u) | (shade.y & 0xffffu);
}

struct AllOut {
    @location(0) gray: u32,
    @location(1) truth: u32,
};

// Without MSAA: picture and ground truth in one pass.
@fragment
fn fs_all(in: VertexOut) -> AllOut {
    var out: AllOut;
    out.gray = gray_level_u32(in.shade, is_seam(in));
    out.truth = truth_of(in.depth_mm, in.shade);
    return out;
}

// fs_all for a face with at most four edge lines.
@fragment
fn fs_all_four_lines(in: FourLinesOut) -> AllOut {
    var out: AllOut;
    out.gray = gray_level_u32(in.shade, seam_of_four_lines_within(in));
    out.truth = truth_of(in.depth_mm, in.shade);
    return out;
}

// fs_all for a face without edge lines.
@fragment
fn fs_all_no_lines(in: NoLinesOut) -> AllOut {
    var out: AllOut;
    out.gray = in.shade.x;
    out.truth = truth_of(in.depth_mm, in.shade);
    return out;
}

// The whole pixel in one 32-bit word, for scenes of at most 255 blocks: depth (1/16 mm) in the
// high 16 bits, the gray level in bits 8..15, block index + 1 in the low 8 bits. One target
// instead of two: lavapipe then stores, clears and copies one (src/render/gpu/mod.rs splits
// the word into the three pictures).
fn pixel_of(depth_mm: f32, shade: vec2<u32>, gray: u32) -> u32 {
    return (depth_of(depth_mm) << 16u) | (gray << 8u) | (shade.y & 0xffu);
}

// fs_all in one word (pixel_of).
@fragment
fn fs_pixel(in: VertexOut) -> @location(0) u32 {
    return pixel_of(in.depth_mm, in.shade, gray_level_u32(in.shade, is_seam(in)));
}

// fs_all_four_lines in one word.
@fragment
fn fs_pixel_four_lines(in: FourLinesOut) -> @location(0) u32 {
    let gray = gray_level_u32(in.shade, seam_of_four_lines_within(in));
    return pixel_of(in.depth_mm, in.shade, gray);
}

// fs_all_no_lines in one word.
@fragment
fn fs_pixel_no_lines(in: NoLinesOut) -> @location(0) u32 {
    return pixel_of(in.depth_mm, in.shade, in.shade.x);
}

// With MSAA: the picture alone (multisampled, then resolved).
@fragment
fn fs_gray(in: VertexOut) -> @location(0) vec4<f32> {
    return gray_of(in);
}

// fs_gray for a face with at most four edge lines.
@fragment
fn fs_gray_four_lines(in: FourLinesOut) -> @location(0) vec4<f32> {
    return gray_level(in.shade, seam_of_four_lines_within(in));
}

// fs_gray for a face without edge lines.
@fragment
fn fs_gray_no_lines(in: NoLinesOut) -> @location(0) vec4<f32> {
    return gray_level(in.shade, false);
}

// With MSAA: the ground truth in a second, single-sampled pass.
@fragment
fn fs_truth(in: VertexOut) -> @location(0) u32 {
    return truth_of(in.depth_mm, in.shade);
}
