//! Drawing cloths with Bevy's renderer (feature `render`).
//!
//! | piece | what it does |
//! |---|---|
//! | [`ClothRenderPlugin`] | gives each cloth a dynamic [`Mesh`] and a [`BurningClothMaterial`], updates the mesh in place each frame, ignites a cloth where it is clicked |
//! | [`material`] | [`BurningClothMaterial`]: standard PBR plus scorch, char, glowing front and a smooth cut |
//!
//! The vertex data (positions in the entity's frame, normals, burn data) is computed by
//! [`crate::sim::mesh`], in parts over Bevy's compute task pool; this module copies it into
//! the mesh asset.
//!
//! The mesh is the cloth entity's own [`Mesh3d`]: positions are written in the entity's
//! frame, so its `Transform` places the cloth once, not twice. Burnt triangles leave the index
//! buffer (never drawn as degenerate triangles). Per-vertex burn data (second UV channel)
//! lets the shader scorch and char the cloth, glow orange along the burning front, and cut the
//! burnt region smoothly through the interior of triangles. Bevy recomputes the bounding box
//! when the mesh changes, so frustum culling follows the cloth as it falls.
//!
//! Add `BurningClothPlugins` after `DefaultPlugins`: the plugin draws only when Bevy's PBR
//! renderer is already in the app (a headless app simulates without drawing).
//!
//! Click-to-ignite uses Bevy's mesh picking: the plugin adds `MeshPickingPlugin` when
//! picking is present (as with `DefaultPlugins`). [`ClickToIgnite`] turns it off.

pub mod flammable;
pub mod material;

pub use flammable::Flammable;
pub use material::{BurnExtension, BurnLook, BurningClothMaterial, burning_cloth_material};

use crate::plugin::{ClothBuildSystems, ClothInUse, ClothParticles, ClothTopology, Ignite};
use crate::sim::BurnMaterial;
use crate::sim::mesh::MeshData;
use bevy::asset::RenderAssetUsages;
use bevy::diagnostic::{Diagnostic, DiagnosticPath, Diagnostics, RegisterDiagnostic};
use bevy::mesh::{Indices, PrimitiveTopology, VertexAttributeValues};
use bevy::pbr::{MaterialPlugin, PbrPlugin};
use bevy::picking::PickingPlugin;
use bevy::picking::mesh_picking::MeshPickingPlugin;
use bevy::prelude::*;
use bevy::tasks::ComputeTaskPool;

/// Draws every cloth as a dynamic mesh and ignites cloths where they are clicked.
pub struct ClothRenderPlugin;

impl Plugin for ClothRenderPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<ClickToIgnite>()
            .register_type::<ClickToIgnite>()
            .register_type::<Flammable>()
            .add_observer(ignite_on_click)
            .add_systems(
                PostUpdate,
                (flammable::hand_flammable_down, flammable::make_flammable)
                    .chain()
                    .before(ClothBuildSystems)
                    .run_if(resource_exists::<Assets<Mesh>>)
                    .run_if(any_with_component::<Flammable>),
            );
        if !app.is_plugin_added::<PbrPlugin>() {
            info!(
                "ClothRenderPlugin: no PbrPlugin in this app (headless, or added before \
                 DefaultPlugins): cloths are simulated but not drawn"
            );
            return;
        }
        if app.is_plugin_added::<PickingPlugin>() && !app.is_plugin_added::<MeshPickingPlugin>() {
            app.add_plugins(MeshPickingPlugin);
        }
        material::load_shader(app);
        app.add_plugins(MaterialPlugin::<BurningClothMaterial>::default())
            .register_diagnostic(
                Diagnostic::new(ClothRenderDiagnostics::MESH_SYNC).with_suffix("ms"),
            )
            .init_resource::<IgniteMarkerAssets>()
            .add_systems(Update, fade_ignite_markers)
            .add_systems(
                PostUpdate,
                (attach_cloth_meshes, sync_cloth_meshes)
                    .chain()
                    .after(ClothBuildSystems)
                    .run_if(any_with_component::<ClothParticles>),
            );
    }
}

/// Whether clicking a cloth sets it alight at the clicked point (primary button).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq, Reflect)]
#[reflect(Resource, Clone, Debug, PartialEq)]
pub struct ClickToIgnite {
    /// On by default.
    pub enabled: bool,
}

impl Default for ClickToIgnite {
    fn default() -> Self {
        Self { enabled: true }
    }
}

/// The dynamic mesh of a cloth and the buffers its vertex data is assembled in.
#[derive(Component, Debug, Default)]
pub struct ClothMesh {
    data: MeshData,
}

fn attach_cloth_meshes(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<BurningClothMaterial>>,
    standard_materials: Res<Assets<StandardMaterial>>,
    cloths: Query<
        (
            Entity,
            &ClothParticles,
            &ClothTopology,
            &BurnMaterial,
            Has<MeshMaterial3d<BurningClothMaterial>>,
            Option<&MeshMaterial3d<StandardMaterial>>,
        ),
        Added<ClothTopology>,
    >,
) {
    for (entity, particles, topology, material, has_material, standard) in &cloths {
        let n = particles.len();
        let uv: Vec<[f32; 2]> = topology.uv.iter().map(|uv| uv.to_array()).collect();
        let mesh = Mesh::new(
            PrimitiveTopology::TriangleList,
            RenderAssetUsages::default(),
        )
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; n])
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, vec![[0.0f32, 0.0, 1.0]; n])
        .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uv)
        .with_inserted_attribute(Mesh::ATTRIBUTE_UV_1, vec![[0.0f32; 2]; n])
        .with_inserted_indices(Indices::U32(topology.live_indices.clone()));
        let mut entity_commands = commands.entity(entity);
        entity_commands.insert((Mesh3d(meshes.add(mesh)), ClothMesh::default()));
        if !has_material {
            // A mesh made flammable keeps its own look as the base of the burning one.
            let base = standard.and_then(|handle| standard_materials.get(&handle.0));
            let burning = match base {
                Some(base) => BurningClothMaterial {
                    base: StandardMaterial {
                        double_sided: true,
                        cull_mode: None,
                        ..base.clone()
                    },
                    extension: BurnExtension::default(),
                },
                None => burning_cloth_material(material),
            };
            entity_commands
                .remove::<MeshMaterial3d<StandardMaterial>>()
                .insert(MeshMaterial3d(materials.add(burning)));
        }
    }
}

fn sync_cloth_meshes(
    mut diagnostics: Diagnostics,
    mut meshes: ResMut<Assets<Mesh>>,
    mut cloths: Query<
        (
            &ClothParticles,
            &ClothTopology,
            &ClothInUse,
            &GlobalTransform,
            &Mesh3d,
            &mut ClothMesh,
        ),
        Changed<ClothParticles>,
    >,
) {
    let started = std::time::Instant::now();
    for (particles, topology, in_use, transform, mesh3d, mut buffers) in &mut cloths {
        let Some(mut mesh) = meshes.get_mut(&mesh3d.0) else {
            continue;
        };
        let data = &mut buffers.data;
        let world_to_local = transform.affine().inverse();
        let pool = ComputeTaskPool::try_get().map(|pool| &**pool);
        data.update(particles, topology, in_use.material(), world_to_local, pool);
        write_attribute(&mut mesh, Mesh::ATTRIBUTE_POSITION, &data.positions);
        write_attribute(&mut mesh, Mesh::ATTRIBUTE_NORMAL, &data.normals);
        if let Some(VertexAttributeValues::Float32x2(burn)) =
            mesh.attribute_mut(Mesh::ATTRIBUTE_UV_1)
        {
            copy_into(burn, &data.burn);
        }
        if let Some(Indices::U32(indices)) = mesh.indices_mut() {
            copy_into(indices, &topology.live_indices);
        }
    }
    let milliseconds = started.elapsed().as_secs_f64() * 1e3;
    diagnostics.add_measurement(&ClothRenderDiagnostics::MESH_SYNC, || milliseconds);
}

/// Drawing diagnostics, read by `LogDiagnosticsPlugin` and the panel.
pub struct ClothRenderDiagnostics;

impl ClothRenderDiagnostics {
    /// Time to copy every changed cloth into its mesh (positions, normals, burn attribute,
    /// live triangles) on the CPU, ms per frame.
    pub const MESH_SYNC: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/mesh_sync");
}

fn write_attribute(mesh: &mut Mesh, attribute: bevy::mesh::MeshVertexAttribute, data: &[[f32; 3]]) {
    if let Some(VertexAttributeValues::Float32x3(values)) = mesh.attribute_mut(attribute) {
        copy_into(values, data);
    }
}

/// Overwrites `target` with `source`, reusing its memory when the length is unchanged.
fn copy_into<T: Copy>(target: &mut Vec<T>, source: &[T]) {
    if target.len() == source.len() {
        target.copy_from_slice(source);
    } else {
        target.clear();
        target.extend_from_slice(source);
    }
}

fn ignite_on_click(
    click: On<Pointer<Click>>,
    settings: Res<ClickToIgnite>,
    marker: Option<Res<IgniteMarkerAssets>>,
    cloths: Query<(), With<ClothParticles>>,
    mut commands: Commands,
) {
    if !settings.enabled || click.event.button != PointerButton::Primary {
        return;
    }
    if cloths.contains(click.entity)
        && let Some(point) = click.event.hit.position
    {
        commands.trigger(Ignite::at_world_point(click.entity, point));
        if let Some(marker) = marker {
            commands.spawn((
                IgniteMarker { age: 0.0 },
                Mesh3d(marker.mesh.clone()),
                MeshMaterial3d(marker.material.clone()),
                Transform::from_translation(point),
                bevy::light::NotShadowCaster,
                Pickable::IGNORE,
            ));
        }
    }
}

/// How long an ignite marker shows, s.
const IGNITE_MARKER_SECONDS: f32 = 0.6;

/// A glowing dot where a click set a cloth alight; it swells and vanishes.
#[derive(Component, Debug)]
pub struct IgniteMarker {
    age: f32,
}

/// Mesh and material shared by every ignite marker.
#[derive(Resource, Debug)]
struct IgniteMarkerAssets {
    mesh: Handle<Mesh>,
    material: Handle<StandardMaterial>,
}

impl FromWorld for IgniteMarkerAssets {
    fn from_world(world: &mut World) -> Self {
        let mesh = world
            .resource_mut::<Assets<Mesh>>()
            .add(Sphere::new(0.02).mesh().uv(16, 8));
        let material = world
            .resource_mut::<Assets<StandardMaterial>>()
            .add(StandardMaterial {
                base_color: Color::srgb(1.0, 0.6, 0.1),
                unlit: true,
                ..default()
            });
        Self { mesh, material }
    }
}

fn fade_ignite_markers(
    time: Res<Time>,
    mut commands: Commands,
    mut markers: Query<(Entity, &mut IgniteMarker, &mut Transform)>,
) {
    for (entity, mut marker, mut transform) in &mut markers {
        marker.age += time.delta_secs();
        let t = marker.age / IGNITE_MARKER_SECONDS;
        if t >= 1.0 {
            commands.entity(entity).despawn();
        } else {
            transform.scale = Vec3::splat(1.0 + 2.0 * t) * (1.0 - t * t);
        }
    }
}
