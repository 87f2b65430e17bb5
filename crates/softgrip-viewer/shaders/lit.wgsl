// Lit, vertex-coloured triangles: the object's surface (smooth normals),
// fingers, contact markers and force arrows; and unlit lines (`fs_flat`,
// the wireframe). Two-sided: a face seen from
// behind is shaded with its normal flipped, so cut-aways and thin plates
// read correctly.

struct Camera {
    view_proj: mat4x4<f32>,
    // xyz: eye position (world, m); w unused.
    eye: vec4<f32>,
    // xyz: direction towards the key light; w unused.
    light: vec4<f32>,
};

@group(0) @binding(0) var<uniform> camera: Camera;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) world: vec3<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = camera.view_proj * vec4<f32>(v.position, 1.0);
    out.normal = v.normal;
    out.color = v.color;
    out.world = v.position;
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    let to_eye = normalize(camera.eye.xyz - v.world);
    var n = normalize(v.normal);
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    let key = max(dot(n, normalize(camera.light.xyz)), 0.0);
    let head = max(dot(n, to_eye), 0.0);
    let shade = 0.30 + 0.40 * key + 0.30 * head;
    return vec4<f32>(v.color.rgb * shade, v.color.a);
}

// Unlit: the vertex colour as it is (lines have no normal).
@fragment
fn fs_flat(v: VertexOut) -> @location(0) vec4<f32> {
    return v.color;
}
