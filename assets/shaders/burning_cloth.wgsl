// The burning-cloth material: Bevy's standard PBR lighting, with the cloth scorching and
// charring as it heats, a glowing rim at the burning front, and a smooth cut through the
// interior of triangles where the cloth has burnt away.
//
// Per-vertex burn data arrives in the second UV channel (ATTRIBUTE_UV_1):
//   uv_b.x = heat: 0 at the initial temperature, 1 at the ignition temperature;
//   uv_b.y = burn: 0 until ignition, 1 at the burnt temperature.
// Interpolated across a triangle, `burn` crosses `look.cut` along a smooth line, which is
// where the fragment shader cuts the cloth.

#import bevy_pbr::{
    pbr_fragment::pbr_input_from_standard_material,
    pbr_functions::alpha_discard,
    mesh_view_bindings::globals,
}

#ifdef PREPASS_PIPELINE
#import bevy_pbr::{
    prepass_io::{VertexOutput, FragmentOutput},
    pbr_deferred_functions::deferred_output,
}
#else
#import bevy_pbr::{
    forward_io::{VertexOutput, FragmentOutput},
    pbr_functions::{apply_pbr_lighting, main_pass_post_lighting_processing},
}
#endif

struct BurnLook {
    scorch_colour: vec4<f32>,
    char_colour: vec4<f32>,
    ember_colour: vec4<f32>,
    // Burn value at which the cloth is cut away.
    cut: f32,
    // Width of the glowing rim, in burn units below the cut.
    glow_width: f32,
    // Emissive strength of the rim.
    glow_strength: f32,
    // Relative amplitude of the rim's flicker.
    flicker: f32,
    // 1: draw a temperature heat map instead of the burn look.
    heat_map: f32,
}

// Temperature ramp over s in [0, 1]: 0 initial (blue), 0.5 ignition (yellow), 1 burnt (white).
fn heat_ramp(s: f32) -> vec3<f32> {
    let blue = vec3<f32>(0.02, 0.05, 0.45);
    let teal = vec3<f32>(0.0, 0.45, 0.35);
    let yellow = vec3<f32>(1.0, 0.85, 0.05);
    let red = vec3<f32>(0.9, 0.08, 0.0);
    let white = vec3<f32>(1.0, 0.95, 0.85);
    if s < 0.25 {
        return mix(blue, teal, s / 0.25);
    } else if s < 0.5 {
        return mix(teal, yellow, (s - 0.25) / 0.25);
    } else if s < 0.75 {
        return mix(yellow, red, (s - 0.5) / 0.25);
    }
    return mix(red, white, (s - 0.75) / 0.25);
}

@group(#{MATERIAL_BIND_GROUP}) @binding(100)
var<uniform> look: BurnLook;

@fragment
fn fragment(
    in: VertexOutput,
    @builtin(front_facing) is_front: bool,
) -> FragmentOutput {
#ifdef VERTEX_UVS_B
    let heat = clamp(in.uv_b.x, 0.0, 1.0);
    let burn = clamp(in.uv_b.y, 0.0, 1.0);
#else
    let heat = 0.0;
    let burn = 0.0;
#endif

    // The smooth edge: everything past the cut has burnt away.
    if burn > look.cut {
        discard;
    }

    var pbr_input = pbr_input_from_standard_material(in, is_front);

    if look.heat_map > 0.5 {
        // The heat map: matte ramp colour, lit a little from within so it reads in shadow.
        let ramp = heat_ramp(0.5 * heat + 0.5 * burn);
        pbr_input.material.base_color = vec4<f32>(ramp, 1.0);
        pbr_input.material.perceptual_roughness = 1.0;
        pbr_input.material.reflectance = vec3<f32>(0.0);
        pbr_input.material.emissive = vec4<f32>(ramp * 0.4, 0.0);
#ifdef PREPASS_PIPELINE
        return deferred_output(in, pbr_input);
#else
        var map_out: FragmentOutput;
        map_out.color = apply_pbr_lighting(pbr_input);
        map_out.color = main_pass_post_lighting_processing(pbr_input, map_out.color);
        return map_out;
#endif
    }

    // Scorch browns the cloth as it heats; char blackens it from just before ignition on.
    let scorch = smoothstep(0.1, 0.7, heat);
    // (An ignited vertex has heat 1, so the iso-line of heat is a smooth char edge.)
    let charring = smoothstep(0.6, 1.0, heat);
    let base = pbr_input.material.base_color;
    let scorched = mix(base.rgb, look.scorch_colour.rgb, scorch);
    pbr_input.material.base_color = vec4<f32>(mix(scorched, look.char_colour.rgb, charring), base.a);
    // Char is matte soot: no specular sheen.
    pbr_input.material.perceptual_roughness = mix(pbr_input.material.perceptual_roughness, 1.0, charring);
    pbr_input.material.reflectance = mix(pbr_input.material.reflectance, vec3<f32>(0.0), charring);

    // The glowing rim just inside the cut, flickering in space and time.
    let rim = smoothstep(look.cut - look.glow_width, look.cut, burn);
    let p = in.world_position.xyz;
    let flicker = 1.0 + look.flicker * sin(globals.time * 17.0 + p.x * 41.0 + p.y * 29.0 + p.z * 37.0)
        * sin(globals.time * 7.3 + p.y * 53.0);
    let glow = rim * rim * look.glow_strength * flicker;
    // Alpha 0: emissive in display units, not scaled by the camera's exposure, so the
    // glow reads the same under any lighting.
    pbr_input.material.emissive = vec4<f32>(look.ember_colour.rgb * glow, 0.0);

    pbr_input.material.base_color = alpha_discard(pbr_input.material, pbr_input.material.base_color);

#ifdef PREPASS_PIPELINE
    let out = deferred_output(in, pbr_input);
#else
    var out: FragmentOutput;
    out.color = apply_pbr_lighting(pbr_input);
    out.color = main_pass_post_lighting_processing(pbr_input, out.color);
#endif
    return out;
}
