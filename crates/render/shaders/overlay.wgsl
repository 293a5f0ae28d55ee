// Overlays: the trajectory trail (screen-space ribbons of constant pixel width) and the decals —
// instanced rings, discs and crowns for contact markers, the stone's shadow and the splash cues.

struct TrailIn {
    @location(0) a: vec4<f32>,
    @location(1) b: vec4<f32>,
    @location(2) color: vec4<f32>,
};

struct ColorOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) color: vec4<f32>,
};

// a.xyz, b.xyz: the segment's ends (world); a.w: width in pixels.
@vertex
fn vs_trail(@builtin(vertex_index) vi: u32, in: TrailIn) -> ColorOut {
    let ca = g.clip_from_world * vec4<f32>(in.a.xyz, 1.0);
    let cb = g.clip_from_world * vec4<f32>(in.b.xyz, 1.0);
    var out: ColorOut;
    out.color = in.color;
    // Segments reaching behind the eye are dropped (the trail is dense, the gap is invisible).
    if (ca.w <= 1e-3 || cb.w <= 1e-3) {
        out.pos = vec4<f32>(2.0, 2.0, 0.0, 1.0);
        return out;
    }
    let sa = ca.xy / ca.w * g.viewport.xy;
    let sb = cb.xy / cb.w * g.viewport.xy;
    var d = sb - sa;
    if (dot(d, d) < 1e-8) {
        d = vec2<f32>(1.0, 0.0);
    }
    let side = normalize(vec2<f32>(-d.y, d.x)) * in.a.w;
    // Two triangles: corners (end, side) = (0,-)(1,-)(1,+) (0,-)(1,+)(0,+).
    let ends = array<f32, 6>(0.0, 1.0, 1.0, 0.0, 1.0, 0.0);
    let sides = array<f32, 6>(-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
    let t = ends[vi];
    let c = mix(ca, cb, t);
    let offset = side * sides[vi] / g.viewport.xy * c.w;
    out.pos = vec4<f32>(c.xy + offset, c.z, c.w);
    return out;
}

struct DecalIn {
    // xyz: centre (world); w: inner radius.
    @location(0) center: vec4<f32>,
    // x: outer radius; y, z: height at the inner, outer edge; w: unused.
    @location(1) shape: vec4<f32>,
    // x, y: alpha factor at the inner, outer edge.
    @location(2) fade: vec4<f32>,
    @location(3) color: vec4<f32>,
};

// Unit annulus: vertex k of a strip around the circle, `segments` = 64.
@vertex
fn vs_decal(@builtin(vertex_index) vi: u32, in: DecalIn) -> ColorOut {
    let quad = vi / 6u;
    let corner = vi % 6u;
    let ks = array<u32, 6>(0u, 1u, 1u, 0u, 1u, 0u);
    let ss = array<f32, 6>(0.0, 0.0, 1.0, 0.0, 1.0, 1.0);
    let k = quad + ks[corner];
    let s = ss[corner];
    let ang = f32(k) / 64.0 * 2.0 * PI;
    let dir = vec3<f32>(cos(ang), sin(ang), 0.0);
    let radius = mix(in.center.w, in.shape.x, s);
    let z = mix(in.shape.y, in.shape.z, s);
    let world = in.center.xyz + dir * radius + vec3<f32>(0.0, 0.0, z);
    var out: ColorOut;
    out.pos = g.clip_from_world * vec4<f32>(world, 1.0);
    out.color = vec4<f32>(in.color.rgb, in.color.a * mix(in.fade.x, in.fade.y, s));
    return out;
}

@fragment
fn fs_color(in: ColorOut) -> @location(0) vec4<f32> {
    return vec4<f32>(finish(in.color.rgb), in.color.a);
}
