//! Smoke billboards (features `smoke` and `render`): every emitter's particles in two
//! dynamic meshes, one drawn additively (flames and embers), one alpha-blended and sorted back
//! to front (smoke). Quads face the first active 3D camera and are rebuilt in place each frame
//! from buffers that only grow, so a steady burn allocates nothing.

use super::plugin::SmokeEmitter;
use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::NoFrustumCulling;
use bevy::image::Image;
use bevy::light::NotShadowCaster;
use bevy::mesh::{Indices, PrimitiveTopology, VertexAttributeValues};
use bevy::pbr::PbrPlugin;
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};

/// Draws smoke, flames and embers as camera-facing billboards. Added by
/// [`SmokePlugin`](super::SmokePlugin) when the `render` feature is on; draws only when
/// Bevy's PBR renderer is in the app.
pub struct SmokeRenderPlugin;

impl Plugin for SmokeRenderPlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<PbrPlugin>() {
            return;
        }
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

/// Vertex buffers of one billboard mesh, reused frame to frame.
#[derive(Default)]
struct QuadBuffers {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    colours: Vec<[f32; 4]>,
    indices: Vec<u32>,
}

impl QuadBuffers {
    fn clear(&mut self) {
        self.positions.clear();
        self.normals.clear();
        self.uvs.clear();
        self.colours.clear();
        self.indices.clear();
    }

    fn quad(&mut self, centre: Vec3, right: Vec3, up: Vec3, facing: Vec3, colour: [f32; 4]) {
        let base = self.positions.len() as u32;
        for (corner, uv) in [
            (-right - up, [0.0, 1.0]),
            (right - up, [1.0, 1.0]),
            (right + up, [1.0, 0.0]),
            (-right + up, [0.0, 0.0]),
        ] {
            self.positions.push((centre + corner).to_array());
            self.normals.push(facing.to_array());
            self.uvs.push(uv);
            self.colours.push(colour);
        }
        self.indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
}

/// Scratch of the drawing system.
#[derive(Default)]
struct SmokeDrawScratch {
    additive: QuadBuffers,
    blended: QuadBuffers,
    /// Smoke particles to sort: (distance along the view, emitter, slot).
    order: Vec<(f32, Entity, u32)>,
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

/// One degenerate, transparent quad: the renderer allocates no buffer for a mesh with no
/// vertices and then logs an error when it is updated, so the mesh never starts empty.
fn placeholder_quad_mesh() -> Mesh {
    let mut buffers = QuadBuffers::default();
    buffers.quad(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::Z, [0.0; 4]);
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, buffers.positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, buffers.normals)
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, buffers.uvs)
    .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, buffers.colours)
    .with_inserted_indices(Indices::U32(buffers.indices))
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
            Mesh3d(meshes.add(placeholder_quad_mesh())),
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
                scratch.additive.quad(
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
        scratch.blended.quad(
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
        let wanted = if buffers.indices.is_empty() {
            Visibility::Hidden
        } else {
            Visibility::Inherited
        };
        visibility.set_if_neq(wanted);
        if buffers.indices.is_empty() {
            continue;
        }
        let Some(mut mesh) = meshes.get_mut(&mesh3d.0) else {
            continue;
        };
        write(&mut mesh, Mesh::ATTRIBUTE_POSITION, &buffers.positions);
        write(&mut mesh, Mesh::ATTRIBUTE_NORMAL, &buffers.normals);
        if let Some(VertexAttributeValues::Float32x2(values)) =
            mesh.attribute_mut(Mesh::ATTRIBUTE_UV_0)
        {
            replace(values, &buffers.uvs);
        }
        if let Some(VertexAttributeValues::Float32x4(values)) =
            mesh.attribute_mut(Mesh::ATTRIBUTE_COLOR)
        {
            replace(values, &buffers.colours);
        }
        if let Some(Indices::U32(indices)) = mesh.indices_mut() {
            replace(indices, &buffers.indices);
        }
    }
}

fn write(mesh: &mut Mesh, attribute: bevy::mesh::MeshVertexAttribute, data: &[[f32; 3]]) {
    if let Some(VertexAttributeValues::Float32x3(values)) = mesh.attribute_mut(attribute) {
        replace(values, data);
    }
}

/// Overwrites `target` with `source`; its memory only grows.
fn replace<T: Copy>(target: &mut Vec<T>, source: &[T]) {
    target.clear();
    target.extend_from_slice(source);
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
    fn the_placeholder_mesh_has_vertices_for_the_renderer_to_allocate() {
        let mesh = placeholder_quad_mesh();
        assert_eq!(mesh.count_vertices(), 4);
        assert_eq!(mesh.indices().map(|i| i.len()), Some(6));
    }

    #[test]
    fn quads_are_two_triangles_around_the_centre() {
        let mut buffers = QuadBuffers::default();
        buffers.quad(Vec3::ONE, Vec3::X * 0.5, Vec3::Y * 0.5, Vec3::Z, [1.0; 4]);
        assert_eq!(buffers.positions.len(), 4);
        assert_eq!(buffers.indices, vec![0, 1, 2, 0, 2, 3]);
        let centre = buffers
            .positions
            .iter()
            .fold(Vec3::ZERO, |sum, p| sum + Vec3::from_array(*p))
            / 4.0;
        assert!((centre - Vec3::ONE).length() < 1e-6);
    }
}
