//! The burning-cloth material: Bevy's [`StandardMaterial`] extended with scorch, char, a
//! glowing front and a smooth cut (shader `assets/shaders/burning_cloth.wgsl`, embedded in the
//! binary so games need not ship it).

use crate::sim::BurnMaterial;
use bevy::asset::{load_internal_asset, uuid_handle};
use bevy::pbr::{ExtendedMaterial, MaterialExtension};
use bevy::prelude::*;
use bevy::render::render_resource::{AsBindGroup, ShaderType};
use bevy::shader::ShaderRef;

/// Handle of the embedded burning-cloth shader.
pub const BURNING_CLOTH_SHADER: Handle<Shader> =
    uuid_handle!("6d1c1f4e-5b0a-4f43-9a52-0b2f6a8c7e31");

/// The material of a drawn cloth. Its `base` is an ordinary [`StandardMaterial`] (colour,
/// texture, roughness); its `extension` sets how the cloth burns on screen.
pub type BurningClothMaterial = ExtendedMaterial<StandardMaterial, BurnExtension>;

/// Shader parameters of the burn look.
#[derive(Clone, Copy, Debug, PartialEq, ShaderType, Reflect)]
pub struct BurnLook {
    /// Colour of scorched cloth (hot, not yet burning), linear RGBA.
    pub scorch_colour: Vec4,
    /// Colour of charred cloth, linear RGBA.
    pub char_colour: Vec4,
    /// Colour of the glowing front, linear RGBA.
    pub ember_colour: Vec4,
    /// Burn value (0 at ignition, 1 at the burnt temperature) where the cloth is cut away.
    pub cut: f32,
    /// Width of the glowing rim below the cut, in burn units.
    pub glow_width: f32,
    /// Emissive strength of the rim in display units (1 = the ember colour at full
    /// brightness, independent of camera exposure).
    pub glow_strength: f32,
    /// Relative amplitude of the rim's flicker, 0 for a steady glow.
    pub flicker: f32,
    /// 1 draws a temperature heat map instead of the burn look: blue at the initial
    /// temperature, yellow at ignition, red to white towards the burnt temperature. 0 (default)
    /// draws the cloth.
    pub heat_map: f32,
}

impl Default for BurnLook {
    fn default() -> Self {
        Self {
            scorch_colour: Vec4::new(0.16, 0.08, 0.03, 1.0),
            char_colour: Vec4::new(0.012, 0.010, 0.008, 1.0),
            ember_colour: Vec4::new(1.0, 0.33, 0.04, 1.0),
            cut: 0.6,
            glow_width: 0.3,
            glow_strength: 2.5,
            flicker: 0.25,
            heat_map: 0.0,
        }
    }
}

/// The [`MaterialExtension`] of [`BurningClothMaterial`].
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone, Default)]
pub struct BurnExtension {
    /// The burn look.
    #[uniform(100)]
    pub look: BurnLook,
}

impl MaterialExtension for BurnExtension {
    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(BURNING_CLOTH_SHADER)
    }

    fn deferred_fragment_shader() -> ShaderRef {
        ShaderRef::Handle(BURNING_CLOTH_SHADER)
    }
}

/// The default burning-cloth material for a [`BurnMaterial`]: its colour, matte, double-sided.
pub fn burning_cloth_material(material: &BurnMaterial) -> BurningClothMaterial {
    let [r, g, b] = material.base_colour;
    ExtendedMaterial {
        base: StandardMaterial {
            base_color: Color::srgb(r, g, b),
            perceptual_roughness: 0.85,
            double_sided: true,
            cull_mode: None,
            ..default()
        },
        extension: BurnExtension::default(),
    }
}

/// Registers the embedded shader. Needs `Assets<Shader>`.
pub(crate) fn load_shader(app: &mut App) {
    load_internal_asset!(
        app,
        BURNING_CLOTH_SHADER,
        "../../assets/shaders/burning_cloth.wgsl",
        Shader::from_wgsl
    );
}
