// Flame tongues: one quad per tongue, rooted at a burning cloth particle and pointing along
// the flame, drawn additively (premultiplied, partly opaque). The shape is a tear-drop eaten away by noise that rises
// through the flame, so the tongues lick upwards, sway and break off at the tip.
//
// Per-vertex data:
//   uv.x   = across the tongue, 0 at one edge, 1 at the other;
//   uv.y   = along it, 0 at the root, 1 at the tip;
//   uv_b.x = strength: the burning particle's intensity times its share of a tongue's
//            footprint (the light of a burning area does not depend on the spacing);
//   uv_b.y = phase in [0, 1), fixed per cloth particle.
// The noise is sampled in world space, so tongues that overlap flicker together as one
// flame sheet instead of as a stack of unrelated sprites.

#import bevy_pbr::{
    forward_io::VertexOutput,
    mesh_view_bindings::globals,
}

struct FlameLook {
    // Colour of the hottest gas, near the root (linear RGB; alpha unused).
    root_colour: vec4<f32>,
    // Colour of the body of the flame.
    body_colour: vec4<f32>,
    // Colour of the cooling tips.
    tip_colour: vec4<f32>,
    // Overall brightness.
    gain: f32,
    // Spatial frequency of the noise, 1/m (its features are about 1/frequency across).
    noise_frequency: f32,
    // Speed at which the noise rises through the flame, m/s.
    rise_speed: f32,
    // How much the noise eats the flame away, 0 (smooth tear-drops) to 1 (ragged tongues).
    erosion: f32,
    // How much a flame hides what is behind it, 0 (purely additive, like light) to 1.
    opacity: f32,
}

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> look: FlameLook;

fn hash(p: vec3<f32>) -> f32 {
    var q = fract(p * vec3<f32>(0.1031, 0.1030, 0.0973));
    q += dot(q, q.yzx + 33.33);
    return fract((q.x + q.y) * q.z);
}

// Value noise in [0, 1], smooth (C1) between lattice points.
fn value_noise(p: vec3<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let u = f * f * (3.0 - 2.0 * f);
    let x00 = mix(hash(i), hash(i + vec3<f32>(1.0, 0.0, 0.0)), u.x);
    let x10 = mix(hash(i + vec3<f32>(0.0, 1.0, 0.0)), hash(i + vec3<f32>(1.0, 1.0, 0.0)), u.x);
    let x01 = mix(hash(i + vec3<f32>(0.0, 0.0, 1.0)), hash(i + vec3<f32>(1.0, 0.0, 1.0)), u.x);
    let x11 = mix(hash(i + vec3<f32>(0.0, 1.0, 1.0)), hash(i + vec3<f32>(1.0, 1.0, 1.0)), u.x);
    return mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z);
}

// Three octaves, in [0, 1].
fn fbm(p: vec3<f32>) -> f32 {
    return (4.0 * value_noise(p) + 2.0 * value_noise(p * 2.03 + 17.1)
        + value_noise(p * 4.07 + 31.7)) / 7.0;
}

// Colour of gas at relative temperature `heat` in [0, 1]: tip, body, root.
fn flame_colour(heat: f32) -> vec3<f32> {
    if heat < 0.5 {
        return mix(look.tip_colour.rgb, look.body_colour.rgb, heat * 2.0);
    }
    return mix(look.body_colour.rgb, look.root_colour.rgb, heat * 2.0 - 1.0);
}

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
#ifdef VERTEX_UVS_A
    let uv = in.uv;
#else
    let uv = vec2<f32>(0.5, 0.5);
#endif
#ifdef VERTEX_UVS_B
    let tongue = in.uv_b;
#else
    let tongue = vec2<f32>(1.0, 0.0);
#endif
    let across = uv.x * 2.0 - 1.0;
    let along = clamp(uv.y, 0.0, 1.0);
    let strength = tongue.x;
    let phase = tongue.y;

    let p = in.world_position.xyz * look.noise_frequency;
    let rise = globals.time * look.rise_speed * look.noise_frequency;
    // Detail rising through the flame, stretched along it into streaks, and a slower, larger
    // sway that bends the tongue more towards its tip.
    let detail = fbm(vec3<f32>(p.x, p.y * 0.45 - rise * 0.45, p.z) + phase * 5.3);
    let sway = fbm(vec3<f32>(p.x * 0.3 + phase * 11.0, p.y * 0.3 - rise * 0.35, p.z * 0.3));
    let x = across - (sway - 0.5) * 2.0 * along;

    // Tear-drop: rounded at the root, narrowing to a point at the tip.
    let half_width = smoothstep(0.0, 0.25, along) * pow(1.0 - along, 0.6);
    let body = clamp(1.0 - abs(x) / max(half_width, 1e-3), 0.0, 1.0);
    // The noise cuts the flame into tongues: more of it is eaten towards the tip.
    let threshold = look.erosion * (0.2 + 0.5 * along);
    let tongues = smoothstep(threshold, threshold + 0.12, detail);
    let flame = sqrt(body) * tongues;
    if flame <= 0.0 {
        discard;
    }
    // Hottest low in the flame, cooling towards the tips; the root itself stands off the
    // fuel, dim (a flame's base is blue and faint).
    let heat = clamp(flame * (1.2 - 0.7 * along), 0.0, 1.0);
    let standoff = smoothstep(0.05, 0.4, along);
    let light = flame_colour(heat) * (flame * standoff) * strength * look.gain;
    // Premultiplied output: the light is added, and the flame hides `opacity` of what is
    // behind it where it is dense (so it reads as flame over pale cloth, not as a glow).
    let cover = clamp(flame * standoff * strength * look.opacity, 0.0, 1.0);
    return vec4<f32>(light, cover);
}
