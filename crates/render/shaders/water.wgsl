// The water: a projected grid — a mesh fixed in screen space, from the bottom of the view up to
// the horizon, whose vertices are cast onto the plane z = 0 and displaced by the simulated height
// η there (inside the grid; flat water beyond it, out to the horizon). Normals come from the
// prepared slope texture per pixel; the shading is a Fresnel mix of the water body and the
// reflected sky, a sun highlight, fine procedural wind ripples (the water's texture) and haze.

@group(1) @binding(0) var prep_tex: texture_2d<f32>;
@group(1) @binding(1) var prep_samp: sampler;

struct WaterOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) world: vec3<f32>,
};

// Farthest water drawn (m): the haze has swallowed everything by then.
const WATER_FAR: f32 = 8000.0;

// Texture coordinate of a world point on the grid (outside [0, 1]: beyond it).
fn grid_uv(xy: vec2<f32>) -> vec2<f32> {
    return (xy - g.water_rect.xy) / max(g.water_rect.zw, vec2<f32>(1e-6));
}

fn on_grid(uv: vec2<f32>) -> bool {
    return g.water_mesh.w > 0.5 && all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
}

// 1 inside the grid, falling to 0 over its outermost metre, so it meets the flat water seamlessly.
fn edge_fade(uv: vec2<f32>) -> f32 {
    let d = min(min(uv.x, 1.0 - uv.x) * g.water_rect.z, min(uv.y, 1.0 - uv.y) * g.water_rect.w);
    return smoothstep(0.0, 1.0, d);
}

@vertex
fn vs_water(@builtin(vertex_index) vi: u32) -> WaterOut {
    let mx = u32(g.water_mesh.x);
    let my = u32(g.water_mesh.y);
    let fx = f32(vi % mx) / f32(mx - 1u);
    let fy = f32(vi / mx) / f32(my - 1u);
    // Rows from just below the view up to the horizon (options.w), a margin left and right.
    let top = min(g.options.w, 1.05);
    let ndc = vec2<f32>(mix(-1.05, 1.05, fx), mix(-1.05, top, fy));
    let dir = view_ray(ndc);
    let eye = g.camera_pos.xyz;
    var xy: vec2<f32>;
    if (dir.z < -1e-6 && eye.z / -dir.z < WATER_FAR) {
        xy = eye.xy + dir.xy * (eye.z / -dir.z);
    } else {
        // At or above the horizon: the far rim of the water, straight out.
        xy = eye.xy + normalize(dir.xy + vec2<f32>(1e-9, 0.0)) * WATER_FAR;
    }
    var z = 0.0;
    let uv = grid_uv(xy);
    if (on_grid(uv)) {
        z = textureSampleLevel(prep_tex, prep_samp, uv, 0.0).z * edge_fade(uv);
    }
    let world = vec3<f32>(xy, z);
    var out: WaterOut;
    out.pos = g.clip_from_world * vec4<f32>(world, 1.0);
    out.world = world;
    return out;
}

// Slope of the fine wind ripples (the procedural texture of the surface): two octaves of value
// noise drifting with the simulated time, fading with distance (they would only alias there).
fn detail_slope(xy: vec2<f32>, t: f32, dist: f32) -> vec2<f32> {
    let fade = 1.0 / (1.0 + dist * 0.08);
    let a = noise2(vec2<f32>(xy.x * 3.1 - xy.y * 0.9, xy.y * 3.1 + xy.x * 0.9) + vec2<f32>(t * 0.31, t * 0.17));
    let c = noise2(xy * 0.45 + vec2<f32>(t * 0.05, -t * 0.04));
    return (a.yz * (3.1 * 0.006) + c.yz * (0.45 * 0.03)) * fade;
}

@fragment
fn fs_water(in: WaterOut) -> @location(0) vec4<f32> {
    let to_eye = g.camera_pos.xyz - in.world;
    let dist = length(to_eye);
    let v = to_eye / max(dist, 1e-6);
    var slope = vec2<f32>(0.0);
    var eta = 0.0;
    let uv = grid_uv(in.world.xy);
    if (on_grid(uv)) {
        let s = textureSampleLevel(prep_tex, prep_samp, uv, 0.0);
        let w = edge_fade(uv);
        slope = s.xy * g.water_mesh.z * w;
        eta = s.z * w;
    }
    slope += detail_slope(in.world.xy, g.camera_pos.w, dist);
    let n = normalize(vec3<f32>(-slope.x, -slope.y, 1.0));
    let sun = g.sun_dir.xyz;

    // Fresnel (Schlick, water F0 = 0.02), the fifth power by squaring.
    let m = 1.0 - max(dot(n, v), 0.0);
    let m2 = m * m;
    let fresnel = 0.02 + 0.98 * m2 * m2 * m;
    var r = reflect(-v, n);
    r.z = abs(r.z);
    let reflected = sky_base(r);

    // Water body: deep blue-green, a little light scattered from the sun, brighter on crests.
    let deep = vec3<f32>(0.012, 0.045, 0.060);
    let scatter = vec3<f32>(0.02, 0.09, 0.085);
    let lit = max(dot(n, sun), 0.0);
    let body = deep + scatter * (0.35 + 0.65 * lit) + vec3<f32>(0.05, 0.08, 0.07) * clamp(eta * 40.0, 0.0, 1.0);
    var c = mix(body, reflected, fresnel);

    // Sun highlight: a sharp glint (power ~4000: the sun's own reflection, broken up by the
    // ripples into sparkles) and a broad sheen (power 120).
    let h = normalize(sun + v);
    let sheen = pow(max(dot(n, h), 0.0), 120.0);
    let s2 = sheen * sheen;
    let s4 = s2 * s2;
    let s8 = s4 * s4;
    let s16 = s8 * s8;
    let glint = s16 * s16 * sheen;
    let spec = glint * 25.0 + sheen * 0.15;
    c += vec3<f32>(1.0, 0.92, 0.78) * spec * g.sun_dir.w * (0.3 + fresnel);

    // Haze towards the horizon.
    let fog = 1.0 - exp(-dist / g.options.y);
    let flat_dir = normalize(vec3<f32>(-v.xy, 0.02));
    c = mix(c, sky_base(flat_dir), fog);
    return vec4<f32>(finish(c), 1.0);
}
