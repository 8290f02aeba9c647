// blockworld photographic look (docs/rendering.md "Photographic look"): linear radiance of a bevelled,
// cracked render mesh (src/render/photo/mesh/mod.rs) under a key light with a shadow map plus
// ambient, no drawn ink. The sensor (blur, noise, gamma, quantization) runs on the CPU.

struct Photo {
    // World mm to clip space of the picture (Camera::clip_from_world).
    clip_from_world: mat4x4<f32>,
    // World mm to clip space of the key light's orthographic shadow camera.
    light_clip_from_world: mat4x4<f32>,
    // xyz: unit vector towards the light; w: diffuse intensity.
    towards_light: vec4<f32>,
    // x: ambient; y: depth bias, mm; z: receiver offset along its normal, mm; w: shadow
    // map texel, mm.
    params: vec4<f32>,
    // x: tan of the key light's angular radius (an area light: soft shadows whose penumbra
    // grows with the distance from the occluder); y: shadow camera depth range, mm; z: blocker
    // search radius, mm; w: largest penumbra radius, mm.
    soft: vec4<f32>,
    // World normal to the shadow camera's clip-space plane normal (inverse transpose of the
    // linear part of light_clip_from_world): the receiver's plane in the shadow map, so each
    // filter tap compares against the receiver's own depth there, not its centre's.
    light_clip_normal: mat4x4<f32>,
    // x: smallest penumbra radius, mm (even contact shadows are soft); y: weight of the
    // specular highlight (0: matte); z: its Blinn-Phong exponent; w: the floor's bounce
    // (KeyLight::floor_bounce; 0: the ambient alike on every face).
    soft_min: vec4<f32>,
    // The eye: position (w = 1, perspective) or unit direction towards it (w = 0,
    // orthographic); read only for the highlight.
    eye: vec4<f32>,
};

@group(0) @binding(0) var<uniform> photo: Photo;
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;

struct VertexIn {
    @location(0) position_mm: vec3<f32>,
    @location(1) albedo: f32,
    @location(2) normal: vec3<f32>,
};

struct VertexOut {
    // Invariant: every pipeline drawing the mesh computes the same depth for the same vertex
    // (the whole faces drawn behind their shadowed parts rely on it).
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) world_mm: vec3<f32>,
    @location(1) @interpolate(flat) albedo: f32,
    @location(2) @interpolate(flat) normal: vec3<f32>,
};

// The shadow pass: depth from the light only.
@vertex
fn vs_shadow(v: VertexIn) -> @builtin(position) vec4<f32> {
    return photo.light_clip_from_world * vec4<f32>(v.position_mm, 1.0);
}

@vertex
fn vs_photo(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = photo.clip_from_world * vec4<f32>(v.position_mm, 1.0);
    out.world_mm = v.position_mm;
    out.albedo = v.albedo;
    out.normal = v.normal;
    return out;
}

// Taps of the soft-shadow filters: a Vogel (golden-angle) spiral over the unit disk, turned
// by a per-pixel angle so that too few taps give fine noise (which the sensor's blur
// averages) instead of bands. The spiral is walked by turning a unit vector by the golden
// angle at each tap, so only the first tap needs trigonometry.
const SEARCH_TAPS: i32 = 12;
const FILTER_TAPS: i32 = 12;
// cos and sin of the golden angle, 2.39996323 radians.
const GOLDEN_TURN: vec2<f32> = vec2<f32>(-0.73736888, 0.67549029);

// The direction after `d` turned by the golden angle.
fn next_direction(d: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(d.x * GOLDEN_TURN.x - d.y * GOLDEN_TURN.y, d.x * GOLDEN_TURN.y + d.y * GOLDEN_TURN.x);
}

// A fixed pseudo-random angle per pixel (interleaved gradient noise), radians.
fn pixel_turn(frag: vec2<f32>) -> f32 {
    return 6.2831853 * fract(52.9829189 * fract(dot(frag, vec2<f32>(0.06711056, 0.00583715))));
}

// Share of the key light reaching world point `p` with normal `n` (1 lit, 0 in shadow):
// percentage-closer soft shadows of an area light. The mean depth of the occluders near the
// point sets the penumbra (receiver-to-occluder distance times the light's angular radius),
// then filtered comparisons (each a 2 x 2 bilinear comparison of the sampler) over that disk.
// 1 outside the shadow map (nothing there casts a shadow).
fn light_share(p: vec3<f32>, n: vec3<f32>, turn: f32) -> f32 {
    let q = photo.light_clip_from_world * vec4<f32>(p + n * photo.params.z, 1.0);
    let ndc = q.xyz / q.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0) {
        return 1.0;
    }
    let size = vec2<f32>(textureDimensions(shadow_map));
    // Depth change of the receiver's plane per unit of uv (clamped for grazing planes).
    let g = (photo.light_clip_normal * vec4<f32>(n, 0.0)).xyz;
    let slope = clamp(vec2<f32>(-2.0 * g.x, 2.0 * g.y) / max(abs(g.z), 1e-6) * sign(g.z), vec2<f32>(-1e3), vec2<f32>(1e3));
    let uv_per_mm = 1.0 / (photo.params.w * size);
    let receiver_mm = ndc.z * photo.soft.y;
    let first = vec2<f32>(cos(turn), sin(turn));
    var d = first;
    var blockers = 0.0;
    var blocker_mm = 0.0;
    for (var i = 0; i < SEARCH_TAPS; i++) {
        let r = sqrt((f32(i) + 0.5) / f32(SEARCH_TAPS));
        let at = uv + d * (r * photo.soft.z) * uv_per_mm;
        d = next_direction(d);
        let texel = vec2<i32>(clamp(at, vec2<f32>(0.0), vec2<f32>(1.0)) * (size - 1.0));
        let d_mm = textureLoad(shadow_map, texel, 0) * photo.soft.y;
        let plane_mm = receiver_mm + dot(slope, at - uv) * photo.soft.y;
        if (d_mm < plane_mm - photo.params.y) {
            blockers += 1.0;
            blocker_mm += d_mm;
        }
    }
    if (blockers == 0.0) {
        return 1.0;
    }
    let distance_mm = receiver_mm - blocker_mm / blockers;
    let radius_mm = clamp(distance_mm * photo.soft.x, photo.soft_min.x, photo.soft.w);
    let reference = (receiver_mm - photo.params.y) / photo.soft.y;
    var lit = 0.0;
    d = first;
    for (var i = 0; i < FILTER_TAPS; i++) {
        let r = sqrt((f32(i) + 0.5) / f32(FILTER_TAPS));
        let at = uv + d * (r * radius_mm) * uv_per_mm;
        d = next_direction(d);
        let tap_reference = reference + dot(slope, at - uv);
        lit += textureSampleCompareLevel(shadow_map, shadow_sampler, at, tap_reference);
    }
    return lit / f32(FILTER_TAPS);
}

// The Blinn-Phong highlight at world point `p` with normal `n` (before the light's share):
// weight * intensity * (n . h)^exponent, h halfway between the light and the eye.
fn highlight(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let to_eye = normalize(photo.eye.xyz - p * photo.eye.w);
    let h = normalize(photo.towards_light.xyz + to_eye);
    return photo.soft_min.y * photo.towards_light.w * pow(max(dot(n, h), 0.0), photo.soft_min.z);
}

@fragment
fn fs_photo(in: VertexOut) -> @location(0) vec4<f32> {
    let cos_light = dot(in.normal, photo.towards_light.xyz);
    var direct = 0.0;
    var gloss = 0.0;
    if (cos_light > 0.0) {
        let share = light_share(in.world_mm, in.normal, pixel_turn(in.clip.xy));
        direct = cos_light * photo.towards_light.w * share;
        if (photo.soft_min.y > 0.0 && in.albedo > 0.0) {
            gloss = highlight(in.world_mm, in.normal) * share;
        }
    }
    let radiance = in.albedo * (ambient_in(in.normal) + direct) + gloss;
    return vec4<f32>(radiance, 0.0, 0.0, 1.0);
}

// Radiance of a surface the key light's shadow cannot reach (src/render/photo/mesh/mod.rs,
// PhotoMesh): faces turned away from the light (ambient only), the black crack sheets, and the
// floor outside the shadow camera's frame. The same radiance fs_photo gives there.
@fragment
fn fs_photo_unshadowed(in: VertexOut) -> @location(0) vec4<f32> {
    let cos_light = dot(in.normal, photo.towards_light.xyz);
    let direct = max(cos_light, 0.0) * photo.towards_light.w;
    var gloss = 0.0;
    if (photo.soft_min.y > 0.0 && in.albedo > 0.0 && cos_light > 0.0) {
        gloss = highlight(in.world_mm, in.normal);
    }
    return vec4<f32>(in.albedo * (ambient_in(in.normal) + direct) + gloss, 0.0, 0.0, 1.0);
}

// The light a face with unit normal n receives besides the direct light, per unit albedo
// (src/render/photo/mesh/mod.rs ambient_radiance): the ambient alike on every face, or, with
// a floor bounce, the sky's share of it above the face's horizon plus the lit floor's bounce
// below it.
fn ambient_in(n: vec3<f32>) -> f32 {
    if (photo.soft_min.w > 0.0) {
        return photo.params.x * 0.5 * (1.0 + n.y) + photo.soft_min.w * (1.0 - n.y);
    }
    return photo.params.x;
}
