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

// The surface is drawn from the heights under a 1-2-1 (binomial) filter in x and y, and its
// slopes are that filtered field's central differences (the Sobel operator): the columns' two-cell
// mode is the grid's noise, not a wave, and drawn raw it stands up as spikes beside a close stone
// (issue 39). A ring a few cells long keeps its shape; the simulation's heights are unchanged.
@fragment
fn fs_prep(in: PrepOut) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(eta_tex));
    // Framebuffer y runs down, the texture's rows are iy: both count from the first row.
    let p = vec2<i32>(floor(in.pos.xy));
    let cell = g.water_rect.z / f32(size.x);
    var h: array<f32, 9>;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            h[(j + 1) * 3 + (i + 1)] = eta_at(p + vec2<i32>(i, j), size);
        }
    }
    let e = (4.0 * h[4] + 2.0 * (h[1] + h[3] + h[5] + h[7]) + h[0] + h[2] + h[6] + h[8]) / 16.0;
    let wx = select(2.0, 1.0, p.x == 0 || p.x == size.x - 1);
    let wy = select(2.0, 1.0, p.y == 0 || p.y == size.y - 1);
    let gx = ((h[2] - h[0]) + 2.0 * (h[5] - h[3]) + (h[8] - h[6])) / (4.0 * wx * cell);
    let gy = ((h[6] - h[0]) + 2.0 * (h[7] - h[1]) + (h[8] - h[2])) / (4.0 * wy * cell);
    return vec4<f32>(gx, gy, e, 1.0);
}
