// Lopin 3D view: flat-shaded, vertex-coloured triangles with a section clip, drawn
// offscreen with depth and 4x MSAA (blit.wgsl then copies the picture into egui's pass).

struct Uniforms {
    view_proj: mat4x4<f32>,
    // xyz: direction towards the light (world), w: unused
    light: vec4<f32>,
    // x: 1 when a section is active
    flags: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
    @location(3) clip: f32,
    @location(4) body: f32,
};

struct MeshOut {
    @builtin(position) position: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec3<f32>,
    @location(2) clip: f32,
};

@vertex
fn vs_mesh(v: MeshIn) -> MeshOut {
    var o: MeshOut;
    var p = u.view_proj * vec4<f32>(v.position, 1.0);
    // a tiny per-body depth offset: touching faces of two bodies never z-fight
    p.z = p.z - v.body * 2.0e-6 * p.w;
    o.position = p;
    o.normal = v.normal;
    o.color = v.color;
    o.clip = v.clip;
    return o;
}

@fragment
fn fs_mesh(i: MeshOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    if (u.flags.x > 0.5 && i.clip > 0.0) {
        discard;
    }
    var n = normalize(i.normal);
    if (!front) {
        n = -n;
    }
    let l = normalize(u.light.xyz);
    let diffuse = abs(dot(n, l));
    let shade = 0.45 + 0.55 * diffuse;
    return vec4<f32>(i.color * shade, 1.0);
}
