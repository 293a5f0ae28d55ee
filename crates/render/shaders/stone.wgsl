// The stone: its mesh (body frame) placed by world_from_stone, lit by the sun (diffuse and a wet,
// soft specular), the sky (hemisphere ambient) and the light the water throws back; a grainy
// slate material with a pale quartz vein so the spin is visible.

struct StoneIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct StoneOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) body: vec3<f32>,
};

@vertex
fn vs_stone(in: StoneIn) -> StoneOut {
    let world = g.world_from_stone * vec4<f32>(in.position, 1.0);
    let n = (g.world_from_stone * vec4<f32>(in.normal, 0.0)).xyz;
    var out: StoneOut;
    out.pos = g.clip_from_world * world;
    out.world = world.xyz;
    out.normal = n;
    out.body = in.position;
    return out;
}

@fragment
fn fs_stone(in: StoneOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let v = normalize(g.camera_pos.xyz - in.world);
    let sun = g.sun_dir.xyz;
    let r = max(g.options.z, 1e-3);
    let q = in.body / r;
    // Grain: two octaves of value noise in the body frame (turns with the stone), and fine
    // speckles of darker and lighter minerals.
    let grain = 0.6 * noise3(q * 6.0) + 0.4 * noise3(q * 19.0);
    var albedo = mix(vec3<f32>(0.10, 0.095, 0.085), vec3<f32>(0.27, 0.25, 0.22), grain);
    let speck = noise3(q * 70.0);
    albedo *= 0.8 + 0.4 * smoothstep(0.25, 0.75, speck);
    // A pale quartz vein across the stone.
    let vein = 1.0 - smoothstep(0.035, 0.075, abs(q.x * 0.8 + q.y * 0.6 - 0.25 + 0.05 * noise3(q * 9.0)));
    albedo = mix(albedo, vec3<f32>(0.72, 0.70, 0.64), vein * 0.85);
    // Sun, sky hemisphere, and a faint bounce from the water below.
    let diffuse = max(dot(n, sun), 0.0) * g.sun_dir.w;
    let hemi = mix(vec3<f32>(0.08, 0.11, 0.13), vec3<f32>(0.32, 0.40, 0.52), 0.5 + 0.5 * n.z);
    let h = normalize(sun + v);
    // A damp stone: a soft sheen.
    let spec = pow(max(dot(n, h), 0.0), 60.0) * 0.35 * g.sun_dir.w;
    var c = albedo * (vec3<f32>(1.0, 0.95, 0.85) * diffuse * 1.6 + hemi) + vec3<f32>(spec);
    // Rim light so the silhouette reads against the water.
    c += vec3<f32>(0.25, 0.3, 0.35) * pow(1.0 - max(dot(n, v), 0.0), 3.0) * 0.6;
    return vec4<f32>(finish(c), 1.0);
}
