// blockworld photographic look (README "Photographic look"): linear radiance of a bevelled,
// cracked render mesh (src/render/photo/mesh.rs) under a key light with a shadow map plus
// ambient, no drawn ink. The sensor (blur, noise, gamma, quantization) runs on the CPU.

struct Photo {
    // World mm to clip space of the picture (Camera::clip_from_world).
    clip_from_world: mat4x4<f32>,
    // World mm to clip space of the key light's orthographic shadow camera.
    light_clip_from_world: mat4x4<f32>,
    // xyz: unit vector towards the light; w: diffuse intensity.
    towards_light: vec4<f32>,
    // x: ambient; y: depth bias in shadow-map depth units; z: receiver offset along its
    // normal, mm; w: unused.
    params: vec4<f32>,
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
    @builtin(position) clip: vec4<f32>,
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

// Share of the key light reaching world point `p` with normal `n`: 1 lit, 0 in shadow,
// 3 x 3 percentage-closer filtered; 1 outside the shadow map (nothing there casts a shadow).
fn light_share(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let q = photo.light_clip_from_world * vec4<f32>(p + n * photo.params.z, 1.0);
    let ndc = q.xyz / q.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0) {
        return 1.0;
    }
    let texel = 1.0 / vec2<f32>(textureDimensions(shadow_map));
    let reference = ndc.z - photo.params.y;
    var lit = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let o = vec2<f32>(f32(dx), f32(dy)) * texel;
            lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + o, reference);
        }
    }
    return lit / 9.0;
}

@fragment
fn fs_photo(in: VertexOut) -> @location(0) vec4<f32> {
    let cos_light = dot(in.normal, photo.towards_light.xyz);
    var direct = 0.0;
    if (cos_light > 0.0) {
        direct = cos_light * photo.towards_light.w * light_share(in.world_mm, in.normal);
    }
    let radiance = in.albedo * (photo.params.x + direct);
    return vec4<f32>(radiance, 0.0, 0.0, 1.0);
}
