//! Smoke billboards (features `smoke` and `render`): every emitter's particles in two
//! dynamic meshes, one drawn additively (flames and embers), one alpha-blended and sorted back
//! to front (smoke). Quads face the first active 3D camera and are rebuilt in place each frame
//! from buffers that only grow, so a steady burn allocates nothing.

use super::plugin::SmokeEmitter;
use super::quads::QuadMesh;
use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::NoFrustumCulling;
use bevy::image::Image;
use bevy::light::NotShadowCaster;
use bevy::pbr::PbrPlugin;
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};

/// Draws smoke, flames and embers as camera-facing billboards, and flame tongues along the
/// burning front ([`FlameTongues`](super::flame_render::FlameTongues)). Added by
/// [`SmokePlugin`](super::SmokePlugin) when the `render` feature is on; draws only when
/// Bevy's PBR renderer is in the app.
pub struct SmokeRenderPlugin;

impl Plugin for SmokeRenderPlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<PbrPlugin>() {
            return;
        }
        super::flame_render::build(app);
        app.add_systems(
            PostUpdate,
            (spawn_billboards, draw_smoke)
                .chain()
                .after(bevy::transform::TransformSystems::Propagate)
                .run_if(any_with_component::<SmokeEmitter>),
        );
    }
}

/// One of the two billboard meshes: which blend mode it holds.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct SmokeBillboards {
    /// True for the additive mesh (flames, embers), false for the smoke mesh.
    pub additive: bool,
}

/// One camera-facing billboard of half-size vectors `right` and `up` around `centre`.
fn billboard(
    quads: &mut QuadMesh<[f32; 4]>,
    centre: Vec3,
    right: Vec3,
    up: Vec3,
    facing: Vec3,
    colour: [f32; 4],
) {
    quads.push(
        [
            (centre - right - up, [0.0, 1.0]),
            (centre + right - up, [1.0, 1.0]),
            (centre + right + up, [1.0, 0.0]),
            (centre - right + up, [0.0, 0.0]),
        ],
        facing,
        colour,
    );
}

/// Scratch of the drawing system.
struct SmokeDrawScratch {
    additive: QuadMesh<[f32; 4]>,
    blended: QuadMesh<[f32; 4]>,
    /// Smoke particles to sort: (distance along the view, emitter, slot).
    order: Vec<(f32, Entity, u32)>,
}

impl Default for SmokeDrawScratch {
    fn default() -> Self {
        Self {
            additive: QuadMesh::new(Mesh::ATTRIBUTE_COLOR),
            blended: QuadMesh::new(Mesh::ATTRIBUTE_COLOR),
            order: Vec::new(),
        }
    }
}

/// A soft round sprite: white, alpha falling smoothly from the centre to the rim.
fn soft_sprite() -> Image {
    const SIZE: u32 = 64;
    let mut data = Vec::with_capacity((SIZE * SIZE * 4) as usize);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let dx = (x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0;
            let dy = (y as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0;
            let r2 = (dx * dx + dy * dy).min(1.0);
            let alpha = (1.0 - r2) * (1.0 - r2);
            data.extend_from_slice(&[255, 255, 255, (alpha * 255.0).round() as u8]);
        }
    }
    Image::new(
        Extent3d {
            width: SIZE,
            height: SIZE,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        data,
        TextureFormat::Rgba8UnormSrgb,
        RenderAssetUsages::RENDER_WORLD,
    )
}

/// Where a billboard of half-size `size` at `position` is drawn: pulled towards the eye by
/// its size (at most half the way), so a sprite born on the cloth does not cut through the
/// cloth's surface in a hard line.
fn pulled_towards_eye(position: Vec3, eye: Vec3, size: f32) -> Vec3 {
    let to_eye = eye - position;
    let distance = to_eye.length();
    if distance <= f32::EPSILON {
        return position;
    }
    position + to_eye * (size.min(0.5 * distance) / distance)
}

/// Spawns the two billboard entities when the first particle appears.
fn spawn_billboards(
    mut commands: Commands,
    billboards: Query<(), With<SmokeBillboards>>,
    emitters: Query<&SmokeEmitter>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut images: ResMut<Assets<Image>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    if !billboards.is_empty() || emitters.iter().all(|e| e.pool().is_empty()) {
        return;
    }
    let sprite = images.add(soft_sprite());
    for additive in [true, false] {
        let material = materials.add(StandardMaterial {
            base_color_texture: Some(sprite.clone()),
            unlit: true,
            double_sided: true,
            cull_mode: None,
            alpha_mode: if additive {
                AlphaMode::Add
            } else {
                AlphaMode::Blend
            },
            ..default()
        });
        commands.spawn((
            Name::new(if additive {
                "Flames and embers"
            } else {
                "Smoke"
            }),
            SmokeBillboards { additive },
            Mesh3d(meshes.add(QuadMesh::<[f32; 4]>::placeholder(Mesh::ATTRIBUTE_COLOR))),
            MeshMaterial3d(material),
            Transform::IDENTITY,
            Visibility::Hidden,
            NoFrustumCulling,
            NotShadowCaster,
            bevy::picking::Pickable::IGNORE,
        ));
    }
}

/// Rebuilds both billboard meshes from every emitter's live particles.
fn draw_smoke(
    mut scratch: Local<SmokeDrawScratch>,
    cameras: Query<(&Camera, &GlobalTransform), With<Camera3d>>,
    emitters: Query<(Entity, &SmokeEmitter)>,
    mut billboards: Query<(&SmokeBillboards, &Mesh3d, &mut Visibility)>,
    mut meshes: ResMut<Assets<Mesh>>,
) {
    let Some((_, camera)) = cameras.iter().find(|(camera, _)| camera.is_active) else {
        return;
    };
    let right = camera.right().as_vec3();
    let up = camera.up().as_vec3();
    let facing = camera.back().as_vec3();
    let eye = camera.translation();
    let scratch = &mut *scratch;
    scratch.additive.clear();
    scratch.blended.clear();
    scratch.order.clear();
    for (entity, emitter) in &emitters {
        let sim = emitter.sim();
        for slot in sim.pool.live_slots() {
            let kind = sim.pool.kind[slot];
            let position = sim.pool.position[slot];
            if kind.is_additive() {
                let (size, colour) = sim.appearance(slot);
                billboard(
                    &mut scratch.additive,
                    pulled_towards_eye(position, eye, size),
                    right * size,
                    up * size,
                    facing,
                    colour,
                );
            } else {
                let depth = (position - eye).dot(facing);
                scratch.order.push((depth, entity, slot as u32));
            }
        }
    }
    // Back to front: `facing` points from the scene to the camera, so the most distant smoke
    // has the most negative depth and comes first.
    scratch.order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    for &(_, entity, slot) in &scratch.order {
        let Ok((_, emitter)) = emitters.get(entity) else {
            continue;
        };
        let sim = emitter.sim();
        let (size, colour) = sim.appearance(slot as usize);
        billboard(
            &mut scratch.blended,
            pulled_towards_eye(sim.pool.position[slot as usize], eye, size),
            right * size,
            up * size,
            facing,
            colour,
        );
    }

    for (billboard, mesh3d, mut visibility) in &mut billboards {
        let buffers = if billboard.additive {
            &scratch.additive
        } else {
            &scratch.blended
        };
        visibility.set_if_neq(buffers.visibility());
        buffers.write_to(&mesh3d.0, &mut meshes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sprite_is_opaque_at_the_centre_and_clear_at_the_rim() {
        let image = soft_sprite();
        let data = image.data.as_ref().unwrap();
        let alpha = |x: usize, y: usize| data[(y * 64 + x) * 4 + 3];
        assert!(alpha(32, 32) > 240);
        assert_eq!(alpha(0, 0), 0);
        assert!(alpha(32, 32) > alpha(48, 32) && alpha(48, 32) > alpha(62, 32));
    }

    #[test]
    fn billboards_move_towards_the_eye_by_their_size_and_never_past_half_way() {
        let eye = Vec3::new(0.0, 0.0, 10.0);
        let moved = pulled_towards_eye(Vec3::ZERO, eye, 0.25);
        assert!((moved - Vec3::new(0.0, 0.0, 0.25)).length() < 1e-6);
        let near = pulled_towards_eye(Vec3::new(0.0, 0.0, 9.9), eye, 1.0);
        assert!((near.z - 9.95).abs() < 1e-5);
        assert_eq!(pulled_towards_eye(eye, eye, 1.0), eye);
    }

    #[test]
    fn billboards_are_quads_around_their_centre() {
        let mut quads = QuadMesh::new(Mesh::ATTRIBUTE_COLOR);
        billboard(
            &mut quads,
            Vec3::ONE,
            Vec3::X * 0.5,
            Vec3::Y * 0.5,
            Vec3::Z,
            [1.0; 4],
        );
        assert_eq!(quads.len(), 1);
        let corners = quads.corners(0);
        let centre = corners.iter().sum::<Vec3>() / 4.0;
        assert!((centre - Vec3::ONE).length() < 1e-6);
        assert!(((corners[1] - corners[0]).length() - 1.0).abs() < 1e-6);
    }
}
