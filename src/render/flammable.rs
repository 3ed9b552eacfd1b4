//! [`Flammable`]: any entity with a `Mesh3d` becomes a burning cloth.

use crate::plugin::{ClothParticles, ClothSolver, DespawnWhenBurntAway};
use crate::sim::{BurnMaterial, MeshClothBuilder, MeshPins};
use bevy::mesh::{PrimitiveTopology, VertexAttributeValues};
use bevy::prelude::*;

/// Makes the `Mesh3d` on this entity a burning cloth: once the mesh asset has loaded, its vertices
/// become particles (duplicates at the same position welded), its edges springs, and its triangles
/// the cloth; the entity's [`BurnMaterial`] (default cloth) sets mass and burning, its `Transform`
/// places it, and `pins` holds it up. The entity's `MeshMaterial3d<StandardMaterial>`, if any,
/// becomes the base of the burning look (its colour and texture are kept). A mesh that is not a
/// triangle list, has no positions, or cannot become a cloth is logged and left as it is.
///
/// On an entity without a `Mesh3d` (a glTF scene's `WorldAssetRoot`, Bevy 0.19's name for
/// `SceneRoot`, or any parent), `Flammable` is handed down, with the entity's `BurnMaterial`,
/// `ClothSolver` and [`DespawnWhenBurntAway`], to every descendant that has a `Mesh3d`,
/// including those a scene spawns later: each becomes a cloth of its own. Pins are
/// read in each mesh's local space; [`MeshPins::Top`] pins a mesh's top edge without knowing
/// its coordinates. To burn only part of a scene, put `Flammable` on the mesh entities you
/// want instead (found, say, by `Name` when the scene is ready).
#[derive(Component, Clone, Debug, Default, PartialEq, Reflect)]
#[reflect(Component, Default, Clone, Debug, PartialEq)]
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

    /// Pins the vertices within `within` (m) of the mesh's highest point: the top edge of a
    /// mesh whose coordinates you do not know.
    pub fn pinned_top(within: f32) -> Self {
        Self {
            pins: MeshPins::Top { within },
        }
    }
}

/// What a parent's [`Flammable`] hands down to its meshes.
type Inherited = (Flammable, Option<BurnMaterial>, Option<ClothSolver>, bool);

/// Hands [`Flammable`] on entities without a `Mesh3d` down to their descendant meshes: to new
/// meshes under such an entity (a scene that has just spawned) and to the meshes under an
/// entity that has just been made flammable. Work only where something was added.
pub(crate) fn hand_flammable_down(
    mut commands: Commands,
    new_meshes: Query<Entity, (Added<Mesh3d>, Without<Flammable>, Without<ClothParticles>)>,
    new_parents: Query<Entity, (Added<Flammable>, Without<Mesh3d>)>,
    flammables: Query<(
        &Flammable,
        Has<Mesh3d>,
        Option<&BurnMaterial>,
        Option<&ClothSolver>,
        Has<DespawnWhenBurntAway>,
    )>,
    ancestors: Query<&ChildOf>,
    children: Query<&Children>,
    plain_meshes: Query<(), (With<Mesh3d>, Without<Flammable>, Without<ClothParticles>)>,
) {
    // What a flammable entity without a mesh hands down (a flammable mesh hands nothing down:
    // it is a cloth itself).
    let inherited = |parent: Entity| -> Option<Inherited> {
        let (flammable, has_mesh, material, solver, despawn) = flammables.get(parent).ok()?;
        (!has_mesh).then(|| {
            (
                flammable.clone(),
                material.copied(),
                solver.copied(),
                despawn,
            )
        })
    };
    let mut hand = |mesh: Entity, (flammable, material, solver, despawn): Inherited| {
        let mut entity = commands.entity(mesh);
        entity.insert(flammable);
        if despawn {
            entity.insert(DespawnWhenBurntAway);
        }
        // The mesh's own material and solver, if it has them, win.
        if let Some(material) = material {
            entity.insert_if_new(material);
        }
        if let Some(solver) = solver {
            entity.insert_if_new(solver);
        }
    };
    for mesh in &new_meshes {
        // The nearest flammable ancestor decides.
        if let Some(found) = ancestors
            .iter_ancestors(mesh)
            .find(|&ancestor| flammables.contains(ancestor))
            .and_then(inherited)
        {
            hand(mesh, found);
        }
    }
    for parent in &new_parents {
        let Some(found) = inherited(parent) else {
            continue;
        };
        for mesh in children.iter_descendants(parent) {
            if plain_meshes.contains(mesh) {
                hand(mesh, found.clone());
            }
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
