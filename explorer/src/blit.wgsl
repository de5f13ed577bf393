// Lopin 3D view: copy of the offscreen picture into egui's pass.

@group(0) @binding(0) var picture: texture_2d<f32>;
@group(0) @binding(1) var picture_sampler: sampler;

struct BlitOut {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_blit(@builtin(vertex_index) i: u32) -> BlitOut {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var o: BlitOut;
    o.position = vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
    o.uv = vec2<f32>(uv.x, 1.0 - uv.y);
    return o;
}

@fragment
fn fs_blit(i: BlitOut) -> @location(0) vec4<f32> {
    return textureSample(picture, picture_sampler, i.uv);
}

// for an sRGB target: the picture holds sRGB-encoded colours, the target expects linear ones
@fragment
fn fs_blit_linear(i: BlitOut) -> @location(0) vec4<f32> {
    let c = textureSample(picture, picture_sampler, i.uv);
    return vec4<f32>(pow(c.rgb, vec3<f32>(2.2)), c.a);
}
