//! [`Flammable`]: any entity with a `Mesh3d` becomes a burning cloth.

use crate::plugin::ClothParticles;
use crate::sim::{MeshClothBuilder, MeshPins};
use bevy::mesh::{PrimitiveTopology, VertexAttributeValues};
use bevy::prelude::*;

/// Makes the `Mesh3d` on this entity a burning cloth: once the mesh asset has loaded, its
/// vertices become particles (duplicates at the same position welded), its edges springs,
/// and its triangles the cloth; the entity's [`BurnMaterial`](crate::sim::BurnMaterial)
/// (default cloth) sets mass and burning, its `Transform` places it, and `pins` holds it up.
/// The entity's `MeshMaterial3d<StandardMaterial>`, if any, becomes the base of the burning
/// look (its colour and texture are kept). Works for Bevy's primitive meshes and for meshes
/// from glTF (put `Flammable` on the entity that holds the `Mesh3d`). A mesh that is not a
/// triangle list, has no positions, or cannot become a cloth is logged and left as it is.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct Flammable {
    /// Which vertices are pinned (local space of the mesh).
    pub pins: MeshPins,
}

impl Flammable {
    /// Pins the vertices at or above local height `y` (the top edge of a banner).
    pub fn pinned_above(y: f32) -> Self {
        Self {
            pins: MeshPins::Above(y),
        }
    }
}

/// The cloth of a mesh asset, or why it cannot be one.
pub fn mesh_cloth_builder(mesh: &Mesh, pins: MeshPins) -> Result<MeshClothBuilder, String> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err(format!(
            "{:?} mesh: only triangle lists can burn",
            mesh.primitive_topology()
        ));
    }
    let Some(VertexAttributeValues::Float32x3(positions)) =
        mesh.attribute(Mesh::ATTRIBUTE_POSITION)
    else {
        return Err("the mesh has no Float32x3 positions".to_owned());
    };
    let positions: Vec<Vec3> = positions.iter().map(|p| Vec3::from_array(*p)).collect();
    let indices: Vec<u32> = match mesh.indices() {
        Some(indices) => indices.iter().map(|i| i as u32).collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let triangles = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let mut builder = MeshClothBuilder::new(positions, triangles).with_pins(pins);
    if let Some(VertexAttributeValues::Float32x2(uvs)) = mesh.attribute(Mesh::ATTRIBUTE_UV_0) {
        builder = builder.with_uvs(uvs.iter().map(|uv| Vec2::from_array(*uv)).collect());
    }
    Ok(builder)
}

/// Turns loaded [`Flammable`] meshes into [`MeshClothBuilder`]s (which the simulation then
/// builds); waits for meshes still loading.
pub(crate) fn make_flammable(
    mut commands: Commands,
    meshes: Res<Assets<Mesh>>,
    candidates: Query<
        (Entity, &Flammable, &Mesh3d),
        (Without<MeshClothBuilder>, Without<ClothParticles>),
    >,
) {
    for (entity, flammable, mesh3d) in &candidates {
        let Some(mesh) = meshes.get(&mesh3d.0) else {
            continue;
        };
        match mesh_cloth_builder(mesh, flammable.pins.clone()) {
            Ok(builder) => {
                commands.entity(entity).insert(builder);
            }
            Err(why) => {
                error!("Flammable on {entity} ignored: {why}");
                commands.entity(entity).remove::<Flammable>();
            }
        }
    }
}
