// The water: the simulated grid as a height-field mesh displaced in the vertex shader, and a flat
// plane to the horizon around it. Normals come from the prepared gradient texture per pixel; the
// shading is a Fresnel mix of the water body and the reflected sky, a sun highlight, fine
// procedural wind ripples (the water's texture) and haze towards the horizon.

@group(1) @binding(0) var prep_tex: texture_2d<f32>;
@group(1) @binding(1) var prep_samp: sampler;

struct WaterOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) uv: vec2<f32>,
};

@vertex
fn vs_grid(@builtin(vertex_index) vi: u32) -> WaterOut {
    let mx = u32(g.water_mesh.x);
    let my = u32(g.water_mesh.y);
    let ix = vi % mx;
    let iy = vi / mx;
    let uv = vec2<f32>(f32(ix) / f32(mx - 1u), f32(iy) / f32(my - 1u));
    let xy = g.water_rect.xy + uv * g.water_rect.zw;
    let eta = textureSampleLevel(prep_tex, prep_samp, uv, 0.0).z;
    let world = vec3<f32>(xy, eta);
    var out: WaterOut;
    out.pos = g.clip_from_world * vec4<f32>(world, 1.0);
    out.world = world;
    out.uv = uv;
    return out;
}

@vertex
fn vs_far(@location(0) p: vec3<f32>) -> WaterOut {
    var out: WaterOut;
    out.pos = g.clip_from_world * vec4<f32>(p, 1.0);
    out.world = p;
    // Outside [0, 1]: no simulated gradient.
    out.uv = vec2<f32>(-1.0, -1.0);
    return out;
}

// Slope of the fine wind ripples (the procedural texture of the surface), fading with distance.
fn detail_slope(xy: vec2<f32>, t: f32, dist: f32) -> vec2<f32> {
    let fade = 1.0 / (1.0 + dist * 0.08);
    var s = vec2<f32>(0.0);
    let a = noise2(xy * 3.1 + vec2<f32>(t * 0.31, t * 0.17));
    s += a.yz * 3.1 * 0.004;
    let b = noise2(vec2<f32>(xy.x * 7.3 - xy.y * 2.1, xy.y * 7.3 + xy.x * 2.1) + vec2<f32>(-t * 0.43, t * 0.29));
    s += b.yz * 7.3 * 0.0018;
    let c = noise2(xy * 0.45 + vec2<f32>(t * 0.05, -t * 0.04));
    s += c.yz * 0.45 * 0.03;
    return s * fade;
}

@fragment
fn fs_water(in: WaterOut) -> @location(0) vec4<f32> {
    let to_eye = g.camera_pos.xyz - in.world;
    let dist = length(to_eye);
    let v = to_eye / max(dist, 1e-6);
    var slope = vec2<f32>(0.0);
    var eta = 0.0;
    let inside = all(in.uv >= vec2<f32>(0.0)) && all(in.uv <= vec2<f32>(1.0)) && g.water_mesh.w > 0.5;
    if (inside) {
        let s = textureSampleLevel(prep_tex, prep_samp, in.uv, 0.0);
        // Fade to flat over the outermost cells so the grid meets the far plane without a seam.
        let edge = min(min(in.uv.x, 1.0 - in.uv.x) * g.water_rect.z, min(in.uv.y, 1.0 - in.uv.y) * g.water_rect.w);
        let w = smoothstep(0.0, 0.3, edge);
        slope = s.xy * g.water_mesh.z * w;
        eta = s.z * w;
    }
    slope += detail_slope(in.world.xy, g.camera_pos.w, dist);
    let n = normalize(vec3<f32>(-slope.x, -slope.y, 1.0));
    let sun = g.sun_dir.xyz;

    // Fresnel (Schlick, water F0 = 0.02).
    let ndv = max(dot(n, v), 0.0);
    let fresnel = 0.02 + 0.98 * pow(1.0 - ndv, 5.0);
    var r = reflect(-v, n);
    r.z = abs(r.z);
    let reflected = vec3<f32>(0.5);

    // Water body: deep blue-green, a little light scattered from the sun, brighter on crests.
    let deep = vec3<f32>(0.012, 0.045, 0.060);
    let scatter = vec3<f32>(0.02, 0.09, 0.085);
    let lit = max(dot(n, sun), 0.0);
    var body = deep + scatter * (0.35 + 0.65 * lit) + vec3<f32>(0.05, 0.08, 0.07) * clamp(eta * 40.0, 0.0, 1.0);
    var c = mix(body, reflected, fresnel);

    // Sun highlight: a sharp glint and a broad sheen.
    let h = normalize(sun + v);
    let ndh = max(dot(n, h), 0.0);
    let spec = pow(ndh, 1200.0) * 12.0 + pow(ndh, 120.0) * 0.12;
    c += vec3<f32>(1.0, 0.92, 0.78) * spec * g.sun_dir.w * (0.3 + fresnel);

    // Haze towards the horizon.
    let fog = 1.0 - exp(-dist / g.options.y);
    let flat_dir = normalize(vec3<f32>(-v.xy, 0.02));
    c = mix(c, vec3<f32>(0.5), fog);
    return vec4<f32>(finish(c), 1.0);
}
