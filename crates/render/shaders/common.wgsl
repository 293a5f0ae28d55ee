// Shared by every scene shader (prepended to each): the per-frame globals, the sky, colour output.
// Conventions: world frame z up, water at rest z = 0, colours linear until `finish`.

struct Globals {
    clip_from_world: mat4x4<f32>,
    world_from_clip: mat4x4<f32>,
    world_from_stone: mat4x4<f32>,
    // xyz: eye position (m); w: simulated time (s).
    camera_pos: vec4<f32>,
    // xyz: unit vector towards the sun; w: sun strength.
    sun_dir: vec4<f32>,
    // width, height (pixels of the viewport), 1/width, 1/height.
    viewport: vec4<f32>,
    // Water grid: origin.x, origin.y (its −x, −y corner), size.x, size.y (m).
    water_rect: vec4<f32>,
    // Projected water grid: vertices across, down; slope gain; 1 when a simulated grid exists.
    water_mesh: vec4<f32>,
    // x: 1 to encode sRGB in the shader (non-sRGB target); y: fog distance (m); z: stone radius (m);
    // w: NDC height of the horizon.
    options: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;

const PI: f32 = 3.14159265;

// Sky radiance along a unit direction, without the sun disc.
fn sky_base(dir: vec3<f32>) -> vec3<f32> {
    let up = clamp(dir.z, -1.0, 1.0);
    let zenith = vec3<f32>(0.07, 0.20, 0.55);
    let horizon = vec3<f32>(0.50, 0.64, 0.82);
    var c = mix(horizon, zenith, sqrt(clamp(up, 0.0, 1.0)));
    if (up < 0.0) {
        c = mix(horizon, vec3<f32>(0.36, 0.44, 0.52), clamp(-up * 3.0, 0.0, 1.0));
    }
    // Warm haze around the sun.
    let s = max(dot(dir, g.sun_dir.xyz), 0.0);
    // Powers by squaring (cheap everywhere, software rasterisers included).
    let s2 = s * s;
    let s4 = s2 * s2;
    let s8 = s4 * s4;
    let s16 = s8 * s8;
    let s64 = s16 * s16 * s16 * s16;
    c += vec3<f32>(0.9, 0.75, 0.5) * (0.25 * s8 + 0.35 * s64);
    return c;
}

// Sky radiance with the sun disc.
fn sky_color(dir: vec3<f32>) -> vec3<f32> {
    let s = max(dot(dir, g.sun_dir.xyz), 0.0);
    let disc = smoothstep(0.99985, 0.99995, s);
    return sky_base(dir) + vec3<f32>(1.0, 0.95, 0.85) * disc * 20.0;
}

// Tone-map (linear up to 0.8, then a soft shoulder to 1), then encode sRGB when the target does not
// (I. Taylor's three-square-root fit of the sRGB curve: within 0.1 % and far cheaper than pow).
fn finish(c: vec3<f32>) -> vec3<f32> {
    let k = vec3<f32>(0.8);
    let over = max(c - k, vec3<f32>(0.0));
    let x = clamp(min(c, k) + 0.2 * over / (over + 0.2), vec3<f32>(0.0), vec3<f32>(1.0));
    if (g.options.x > 0.5) {
        let s1 = sqrt(x);
        let s2 = sqrt(s1);
        let s3 = sqrt(s2);
        let e = 0.662002687 * s1 + 0.684122060 * s2 - 0.323583601 * s3 - 0.0225411470 * x;
        return clamp(e, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    return x;
}

// Direction from the eye through a clip-space point.
fn view_ray(ndc: vec2<f32>) -> vec3<f32> {
    let p = g.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    return normalize(p.xyz / p.w - g.camera_pos.xyz);
}

// Value noise and its gradient (for the procedural water detail and the stone's grain).
// Arithmetic hashes (no trigonometry: cheap on software rasterisers), after D. Hoskins.
fn hash2(p: vec2<f32>) -> f32 {
    var p3 = fract(vec3<f32>(p.x, p.y, p.x) * 0.1031);
    p3 += dot(p3, p3.yzx + 33.33);
    return fract((p3.x + p3.y) * p3.z);
}

fn hash3(p: vec3<f32>) -> f32 {
    var p3 = fract(p * 0.1031);
    p3 += dot(p3, p3.zyx + 31.32);
    return fract((p3.x + p3.y) * p3.z);
}

// Value noise in 2D: returns (value, d/dx, d/dy).
fn noise2(p: vec2<f32>) -> vec3<f32> {
    let i = floor(p);
    let f = p - i;
    let u = f * f * (3.0 - 2.0 * f);
    let du = 6.0 * f * (1.0 - f);
    let a = hash2(i);
    let b = hash2(i + vec2<f32>(1.0, 0.0));
    let c = hash2(i + vec2<f32>(0.0, 1.0));
    let d = hash2(i + vec2<f32>(1.0, 1.0));
    let v = a + (b - a) * u.x + (c - a) * u.y + (a - b - c + d) * u.x * u.y;
    let dx = du.x * ((b - a) + (a - b - c + d) * u.y);
    let dy = du.y * ((c - a) + (a - b - c + d) * u.x);
    return vec3<f32>(v, dx, dy);
}

fn noise3(p: vec3<f32>) -> f32 {
    let i = floor(p);
    let f = p - i;
    let u = f * f * (3.0 - 2.0 * f);
    let n000 = hash3(i);
    let n100 = hash3(i + vec3<f32>(1.0, 0.0, 0.0));
    let n010 = hash3(i + vec3<f32>(0.0, 1.0, 0.0));
    let n110 = hash3(i + vec3<f32>(1.0, 1.0, 0.0));
    let n001 = hash3(i + vec3<f32>(0.0, 0.0, 1.0));
    let n101 = hash3(i + vec3<f32>(1.0, 0.0, 1.0));
    let n011 = hash3(i + vec3<f32>(0.0, 1.0, 1.0));
    let n111 = hash3(i + vec3<f32>(1.0, 1.0, 1.0));
    let x0 = mix(mix(n000, n100, u.x), mix(n010, n110, u.x), u.y);
    let x1 = mix(mix(n001, n101, u.x), mix(n011, n111, u.x), u.y);
    return mix(x0, x1, u.z);
}
