//! Flame tongues on screen (features `smoke` and `render`): every burning cloth's
//! [`FlameTongue`]s as quads in one dynamic mesh, drawn additively in one draw call by
//! [`FlameMaterial`] (shader `assets/shaders/flame_tongue.wgsl`, embedded in the binary).
//!
//! Each quad turns about its tongue's axis to face the camera. The shader draws a tear-drop
//! that noise, rising through the flame in world space, eats into licking tongues. Buffers
//! only grow, so a steady burn allocates nothing; a scene with no fire draws nothing.

use super::emitter::BurningCloth;
use super::plugin::{SmokeEmitter, air};
use super::quads::QuadMesh;
use super::tongues::{FlameTongue, gather_tongues};
use crate::plugin::{ClothEnvironment, ClothInUse, ClothParticles, ClothStatus, ClothTopology};
use bevy::asset::{load_internal_asset, uuid_handle};
use bevy::camera::visibility::NoFrustumCulling;
use bevy::light::NotShadowCaster;
use bevy::pbr::{Material, MaterialPlugin};
use bevy::prelude::*;
use bevy::render::render_resource::{AsBindGroup, ShaderType};
use bevy::shader::ShaderRef;

/// Handle of the embedded flame-tongue shader.
pub const FLAME_TONGUE_SHADER: Handle<Shader> =
    uuid_handle!("b3f0c7a2-3e51-4d8e-9f26-7c4a1d5e8b90");

/// Shader parameters of the flames' look.
#[derive(Clone, Copy, Debug, PartialEq, ShaderType, Reflect)]
pub struct FlameLook {
    /// Colour of the hottest gas, near the root, linear RGB (alpha unused).
    pub root_colour: Vec4,
    /// Colour of the body of the flame, linear RGB.
    pub body_colour: Vec4,
    /// Colour of the cooling tips, linear RGB.
    pub tip_colour: Vec4,
    /// Overall brightness (1: a full-strength tongue's core at the root colour).
    pub gain: f32,
    /// Spatial frequency of the flicker noise, 1/m (features about 1/frequency across).
    pub noise_frequency: f32,
    /// Speed at which the flicker rises through the flame, m/s.
    pub rise_speed: f32,
    /// How much the noise eats the flame away: 0 smooth tear-drops, 1 ragged tongues.
    pub erosion: f32,
    /// How much a dense flame hides what is behind it: 0 purely additive (light only), 1
    /// opaque. A little keeps flames reading as flames over pale cloth.
    pub opacity: f32,
}

impl Default for FlameLook {
    fn default() -> Self {
        Self {
            root_colour: Vec4::new(1.0, 0.78, 0.38, 1.0),
            body_colour: Vec4::new(1.0, 0.36, 0.05, 1.0),
            tip_colour: Vec4::new(0.55, 0.06, 0.01, 1.0),
            gain: 6.0,
            noise_frequency: 14.0,
            rise_speed: 1.6,
            erosion: 1.0,
            opacity: 0.5,
        }
    }
}

/// The additive material of the flame tongues.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone, Default)]
pub struct FlameMaterial {
    /// The look.
    #[uniform(0)]
    pub look: FlameLook,
}

impl Material for FlameMaterial {
    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(FLAME_TONGUE_SHADER)
    }

    fn alpha_mode(&self) -> AlphaMode {
        AlphaMode::Premultiplied
    }

    fn enable_prepass() -> bool {
        false
    }

    fn enable_shadows() -> bool {
        false
    }
}

/// The entity holding every cloth's flame tongues in one mesh. Its
/// `MeshMaterial3d<FlameMaterial>` sets their look.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct FlameTongues;

/// Registers the material and its embedded shader, and the drawing systems.
pub(super) fn build(app: &mut App) {
    load_internal_asset!(
        app,
        FLAME_TONGUE_SHADER,
        "../../assets/shaders/flame_tongue.wgsl",
        Shader::from_wgsl
    );
    app.add_plugins(MaterialPlugin::<FlameMaterial>::default())
        .add_systems(
            PostUpdate,
            (spawn_flame_mesh, draw_flame_tongues)
                .chain()
                .after(bevy::transform::TransformSystems::Propagate)
                .run_if(any_with_component::<SmokeEmitter>),
        );
}

/// One tongue as a quad that turns about its axis to face `eye`, from its root to its tip,
/// pulled towards the eye by its half-width so it does not cut through the cloth it stands
/// on. Strength and phase go in `UV_1`.
fn tongue_quad(
    quads: &mut QuadMesh<[f32; 2]>,
    tongue: &FlameTongue,
    eye: Vec3,
    fallback_side: Vec3,
) {
    let to_eye = (eye - tongue.root).normalize_or(Vec3::Z);
    let side = tongue.axis.cross(to_eye).normalize_or(fallback_side) * tongue.half_width;
    let shift = to_eye * tongue.half_width.min(0.5 * (eye - tongue.root).length());
    let bottom = tongue.root + shift;
    let top = bottom + tongue.axis * tongue.height;
    quads.push(
        [
            (bottom - side, [0.0, 0.0]),
            (bottom + side, [1.0, 0.0]),
            (top + side, [1.0, 1.0]),
            (top - side, [0.0, 1.0]),
        ],
        to_eye,
        [tongue.strength, tongue.phase],
    );
}

/// Scratch of the drawing system.
struct TongueScratch {
    tongues: Vec<FlameTongue>,
    quads: QuadMesh<[f32; 2]>,
}

impl Default for TongueScratch {
    fn default() -> Self {
        Self {
            tongues: Vec::new(),
            quads: QuadMesh::new(Mesh::ATTRIBUTE_UV_1),
        }
    }
}

/// Spawns the tongue mesh entity when the first cloth burns.
fn spawn_flame_mesh(
    mut commands: Commands,
    existing: Query<(), With<FlameTongues>>,
    cloths: Query<&ClothStatus, With<SmokeEmitter>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<FlameMaterial>>,
) {
    if !existing.is_empty() || cloths.iter().all(|status| status.ignited == 0) {
        return;
    }
    commands.spawn((
        Name::new("Flame tongues"),
        FlameTongues,
        Mesh3d(meshes.add(QuadMesh::<[f32; 2]>::placeholder(Mesh::ATTRIBUTE_UV_1))),
        MeshMaterial3d(materials.add(FlameMaterial::default())),
        Transform::IDENTITY,
        Visibility::Hidden,
        NoFrustumCulling,
        NotShadowCaster,
        bevy::picking::Pickable::IGNORE,
    ));
}

/// Rebuilds the tongue mesh from every burning cloth.
#[allow(clippy::too_many_arguments)]
fn draw_flame_tongues(
    mut scratch: Local<TongueScratch>,
    environment: Res<ClothEnvironment>,
    #[cfg(feature = "fluid")] fire: Option<Res<crate::fluid::FirePlume>>,
    cameras: Query<(&Camera, &GlobalTransform), With<Camera3d>>,
    cloths: Query<(
        &SmokeEmitter,
        &ClothParticles,
        &ClothInUse,
        &ClothTopology,
        &ClothStatus,
    )>,
    mut tongue_meshes: Query<(&Mesh3d, &mut Visibility), With<FlameTongues>>,
    mut meshes: ResMut<Assets<Mesh>>,
) {
    let Some((_, camera)) = cameras.iter().find(|(camera, _)| camera.is_active) else {
        return;
    };
    let eye = camera.translation();
    let fallback_side = camera.right().as_vec3();
    let air = air(&environment);
    #[cfg(feature = "fluid")]
    let plume = fire.as_deref().and_then(crate::fluid::FirePlume::active);
    let scratch = &mut *scratch;
    scratch.quads.clear();
    for (emitter, particles, in_use, topology, status) in &cloths {
        if status.ignited == 0 {
            continue;
        }
        let cloth = BurningCloth::new(particles, in_use.material(), topology, &[]);
        let settings = &emitter.settings().tongues;
        #[cfg(feature = "fluid")]
        match plume {
            Some(plume) => {
                let flow = |p: Vec3| plume.shape().contains(p).then(|| plume.velocity_at(p));
                gather_tongues(&cloth, &air, flow, settings, &mut scratch.tongues);
            }
            None => gather_tongues(&cloth, &air, |_| None, settings, &mut scratch.tongues),
        }
        #[cfg(not(feature = "fluid"))]
        gather_tongues(&cloth, &air, |_| None, settings, &mut scratch.tongues);
        for tongue in &scratch.tongues {
            tongue_quad(&mut scratch.quads, tongue, eye, fallback_side);
        }
    }

    for (mesh3d, mut visibility) in &mut tongue_meshes {
        visibility.set_if_neq(scratch.quads.visibility());
        scratch.quads.write_to(&mesh3d.0, &mut meshes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quads() -> QuadMesh<[f32; 2]> {
        QuadMesh::new(Mesh::ATTRIBUTE_UV_1)
    }

    #[test]
    fn a_tongue_runs_from_its_root_to_its_tip_and_faces_the_eye() {
        let tongue = FlameTongue {
            root: Vec3::ZERO,
            axis: Vec3::Y,
            height: 0.2,
            half_width: 0.03,
            strength: 0.5,
            phase: 0.25,
        };
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let mut buffers = quads();
        tongue_quad(&mut buffers, &tongue, eye, Vec3::X);
        let [a, b, c, d] = buffers.corners(0);
        // Root side at the root, tip side at the tip; pulled 3 cm towards the eye.
        assert!(a.y.abs() < 1e-6 && b.y.abs() < 1e-6);
        assert!((c.y - 0.2).abs() < 1e-6 && (d.y - 0.2).abs() < 1e-6);
        assert!([a, b, c, d].iter().all(|p| (p.z - 0.03).abs() < 1e-6));
        // Width across, perpendicular to the axis and the view.
        assert!(((b - a).length() - 0.06).abs() < 1e-6);
        assert!((b - a).dot(Vec3::Y).abs() < 1e-6 && (b - a).dot(Vec3::Z).abs() < 1e-6);
        // The quad's normal points at the eye.
        let normal = (b - a).cross(d - a).normalize();
        assert!(normal.dot(Vec3::Z) > 0.999);
        assert!(buffers.data().iter().all(|&data| data == [0.5, 0.25]));
    }

    #[test]
    fn a_leaning_tongue_keeps_its_axis_and_an_end_on_view_uses_the_fallback() {
        let axis = Vec3::new(1.0, 1.0, 0.0).normalize();
        let tongue = FlameTongue {
            root: Vec3::ONE,
            axis,
            height: 0.1,
            half_width: 0.02,
            strength: 1.0,
            phase: 0.0,
        };
        let mut buffers = quads();
        tongue_quad(&mut buffers, &tongue, Vec3::new(1.0, 1.0, 4.0), Vec3::X);
        let [a, _, _, d] = buffers.corners(0);
        assert!(((d - a).normalize() - axis).length() < 1e-5);
        // Looking straight down the axis: the side is the fallback, nothing is NaN.
        let mut buffers = quads();
        tongue_quad(&mut buffers, &tongue, Vec3::ONE + axis * 3.0, Vec3::Z);
        let [a, b, c, d] = buffers.corners(0);
        assert!([a, b, c, d].iter().all(|p| p.is_finite()));
        assert!(((b - a).normalize() - Vec3::Z).length() < 1e-5);
    }
}
