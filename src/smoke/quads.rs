//! Quads in a dynamic mesh, rebuilt in place each frame: the vertex buffers that the smoke
//! billboards and the flame tongues fill (features `smoke` and `render`).
//!
//! Buffers only grow, so a steady burn allocates nothing. A mesh starts as one degenerate,
//! invisible quad: Bevy's mesh allocator skips zero-size buffers and then logs an error when
//! the mesh is first updated.

use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, MeshVertexAttribute, PrimitiveTopology, VertexAttributeValues};
use bevy::prelude::*;

/// What each quad carries per vertex beyond position, normal and UV: a vertex attribute
/// of this type.
pub(super) trait QuadData: Copy + Default + 'static {
    /// The values of a mesh attribute of this type, if `values` holds this type.
    fn values(values: &mut VertexAttributeValues) -> Option<&mut Vec<Self>>;
    /// Wraps values of this type as a mesh attribute.
    fn wrap(values: Vec<Self>) -> VertexAttributeValues;
}

impl QuadData for [f32; 2] {
    fn values(values: &mut VertexAttributeValues) -> Option<&mut Vec<Self>> {
        match values {
            VertexAttributeValues::Float32x2(values) => Some(values),
            _ => None,
        }
    }

    fn wrap(values: Vec<Self>) -> VertexAttributeValues {
        VertexAttributeValues::Float32x2(values)
    }
}

impl QuadData for [f32; 4] {
    fn values(values: &mut VertexAttributeValues) -> Option<&mut Vec<Self>> {
        match values {
            VertexAttributeValues::Float32x4(values) => Some(values),
            _ => None,
        }
    }

    fn wrap(values: Vec<Self>) -> VertexAttributeValues {
        VertexAttributeValues::Float32x4(values)
    }
}

/// The vertex buffers of a mesh of quads whose extra per-vertex attribute is `attribute`.
pub(super) struct QuadMesh<T> {
    attribute: MeshVertexAttribute,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    data: Vec<T>,
    indices: Vec<u32>,
}

impl<T: QuadData> QuadMesh<T> {
    /// Empty buffers for quads carrying `attribute`.
    pub(super) fn new(attribute: MeshVertexAttribute) -> Self {
        Self {
            attribute,
            positions: Vec::new(),
            normals: Vec::new(),
            uvs: Vec::new(),
            data: Vec::new(),
            indices: Vec::new(),
        }
    }

    /// Removes every quad, keeping the memory.
    pub(super) fn clear(&mut self) {
        self.positions.clear();
        self.normals.clear();
        self.uvs.clear();
        self.data.clear();
        self.indices.clear();
    }

    /// Number of quads.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.positions.len() / 4
    }

    /// Adds a quad: its corners in order round the quad with their UVs, the direction it
    /// faces and its extra data, as two triangles (corners 0-1-2 and 0-2-3).
    pub(super) fn push(&mut self, corners: [(Vec3, [f32; 2]); 4], facing: Vec3, data: T) {
        let base = self.positions.len() as u32;
        for (corner, uv) in corners {
            self.positions.push(corner.to_array());
            self.normals.push(facing.to_array());
            self.uvs.push(uv);
            self.data.push(data);
        }
        self.indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }

    /// A new mesh holding one degenerate quad with default data (drawn as nothing).
    pub(super) fn placeholder(attribute: MeshVertexAttribute) -> Mesh {
        let mut quads = Self::new(attribute);
        quads.push([(Vec3::ZERO, [0.0; 2]); 4], Vec3::Z, T::default());
        Mesh::new(
            PrimitiveTopology::TriangleList,
            RenderAssetUsages::default(),
        )
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, quads.positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, quads.normals)
        .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, quads.uvs)
        .with_inserted_attribute(attribute, T::wrap(quads.data))
        .with_inserted_indices(Indices::U32(quads.indices))
    }

    /// Whether the mesh's entity should be drawn: hidden while there are no quads.
    pub(super) fn visibility(&self) -> Visibility {
        if self.indices.is_empty() {
            Visibility::Hidden
        } else {
            Visibility::Inherited
        }
    }

    /// Writes the quads into the mesh `handle` (made by [`QuadMesh::placeholder`]),
    /// overwriting its buffers in place; with no quads, leaves it as it is (hide it with
    /// [`QuadMesh::visibility`]).
    pub(super) fn write_to(&self, handle: &Handle<Mesh>, meshes: &mut Assets<Mesh>) {
        if self.indices.is_empty() {
            return;
        }
        let Some(mut mesh) = meshes.get_mut(handle) else {
            return;
        };
        for (attribute, data) in [
            (Mesh::ATTRIBUTE_POSITION, &self.positions),
            (Mesh::ATTRIBUTE_NORMAL, &self.normals),
        ] {
            if let Some(VertexAttributeValues::Float32x3(values)) = mesh.attribute_mut(attribute) {
                replace(values, data);
            }
        }
        if let Some(VertexAttributeValues::Float32x2(values)) =
            mesh.attribute_mut(Mesh::ATTRIBUTE_UV_0)
        {
            replace(values, &self.uvs);
        }
        if let Some(values) = mesh.attribute_mut(self.attribute).and_then(T::values) {
            replace(values, &self.data);
        }
        if let Some(Indices::U32(indices)) = mesh.indices_mut() {
            replace(indices, &self.indices);
        }
    }

    /// The corners of quad `k`.
    #[cfg(test)]
    pub(super) fn corners(&self, k: usize) -> [Vec3; 4] {
        core::array::from_fn(|c| Vec3::from_array(self.positions[4 * k + c]))
    }

    /// The extra data of every vertex.
    #[cfg(test)]
    pub(super) fn data(&self) -> &[T] {
        &self.data
    }

    /// The index buffer.
    #[cfg(test)]
    pub(super) fn indices(&self) -> &[u32] {
        &self.indices
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
    fn quads_are_two_triangles_with_their_data_on_every_vertex() {
        let mut quads = QuadMesh::<[f32; 4]>::new(Mesh::ATTRIBUTE_COLOR);
        let corners = [Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y].map(|p| (p, [0.0, 0.0]));
        quads.push(corners, Vec3::Z, [1.0, 0.5, 0.25, 1.0]);
        quads.push(corners, Vec3::Z, [0.0; 4]);
        assert_eq!(quads.len(), 2);
        assert_eq!(quads.indices(), &[0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]);
        assert_eq!(quads.data()[3], [1.0, 0.5, 0.25, 1.0]);
        assert_eq!(quads.corners(1)[2], Vec3::ONE);
        quads.clear();
        assert_eq!(quads.len(), 0);
    }

    #[test]
    fn the_placeholder_mesh_has_vertices_for_the_renderer_to_allocate() {
        for mesh in [
            QuadMesh::<[f32; 4]>::placeholder(Mesh::ATTRIBUTE_COLOR),
            QuadMesh::<[f32; 2]>::placeholder(Mesh::ATTRIBUTE_UV_1),
        ] {
            assert_eq!(mesh.count_vertices(), 4);
            assert_eq!(mesh.indices().map(|i| i.len()), Some(6));
        }
        let mesh = QuadMesh::<[f32; 2]>::placeholder(Mesh::ATTRIBUTE_UV_1);
        assert!(mesh.attribute(Mesh::ATTRIBUTE_UV_1).is_some());
    }

    #[test]
    fn writing_overwrites_the_mesh_and_no_quads_hide_it() {
        let mut meshes = Assets::<Mesh>::default();
        let handle = meshes.add(QuadMesh::<[f32; 2]>::placeholder(Mesh::ATTRIBUTE_UV_1));
        let mut quads = QuadMesh::<[f32; 2]>::new(Mesh::ATTRIBUTE_UV_1);
        let corners = [Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y].map(|p| (p, [0.0, 1.0]));
        for _ in 0..3 {
            quads.push(corners, Vec3::Z, [0.5, 0.25]);
        }
        assert_eq!(quads.visibility(), Visibility::Inherited);
        quads.write_to(&handle, &mut meshes);
        let mesh = meshes.get(&handle).unwrap();
        assert_eq!(mesh.count_vertices(), 12);
        let Some(VertexAttributeValues::Float32x2(data)) = mesh.attribute(Mesh::ATTRIBUTE_UV_1)
        else {
            panic!("no UV_1");
        };
        assert!(data.iter().all(|&d| d == [0.5, 0.25]));
        quads.clear();
        quads.write_to(&handle, &mut meshes);
        assert_eq!(meshes.get(&handle).unwrap().count_vertices(), 12);
        assert_eq!(quads.visibility(), Visibility::Hidden);
    }
}
