// Water preparation pass: from the heights η (R32Float, one texel per column) to a filterable
// texture of (∂η/∂x, ∂η/∂y, η, 1), one texel per column, by central differences (one-sided at the
// walls). Runs on the GPU each time new heights arrive, so the CPU only copies η.

@group(1) @binding(0) var eta_tex: texture_2d<f32>;

struct PrepOut {
    @builtin(position) pos: vec4<f32>,
};

@vertex
fn vs_prep(@builtin(vertex_index) vi: u32) -> PrepOut {
    let x = f32((vi << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(vi & 2u) * 2.0 - 1.0;
    var out: PrepOut;
    out.pos = vec4<f32>(x, y, 0.0, 1.0);
    return out;
}

fn eta_at(p: vec2<i32>, size: vec2<i32>) -> f32 {
    let q = clamp(p, vec2<i32>(0, 0), size - vec2<i32>(1, 1));
    return textureLoad(eta_tex, q, 0).r;
}

@fragment
fn fs_prep(in: PrepOut) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(eta_tex));
    // Framebuffer y runs down, the texture's rows are iy: both count from the first row.
    let p = vec2<i32>(floor(in.pos.xy));
    let cell = g.water_rect.z / f32(size.x);
    let e = eta_at(p, size);
    let xl = eta_at(p - vec2<i32>(1, 0), size);
    let xr = eta_at(p + vec2<i32>(1, 0), size);
    let yd = eta_at(p - vec2<i32>(0, 1), size);
    let yu = eta_at(p + vec2<i32>(0, 1), size);
    let wx = select(2.0, 1.0, p.x == 0 || p.x == size.x - 1);
    let wy = select(2.0, 1.0, p.y == 0 || p.y == size.y - 1);
    let gx = (xr - xl) / (wx * cell);
    let gy = (yu - yd) / (wy * cell);
    return vec4<f32>(gx, gy, e, 1.0);
}
