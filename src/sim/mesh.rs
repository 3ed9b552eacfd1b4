//! Vertex data of a cloth's mesh, computed from the simulation into reused buffers: each
//! particle's position in the cloth's own frame, an area-weighted normal from the triangles
//! still drawn, and burn data for the shader. Plain arrays the render layer copies into its
//! mesh; computed in parts over the task pool (each vertex and each triangle on its own, so
//! the result does not depend on the split).

use super::material::BurnMaterial;
use super::parallel::{for_each_part, parts_for, pieces};
use super::particles::{BurnState, Particles};
use super::topology::Topology;
use bevy::tasks::TaskPool;
use glam::{Affine3A, Vec3, Vec3A};

/// Vertices below which a cloth's mesh is updated on one thread. A mesh bench (two threads,
/// medians of 15 blocks, three alternated runs): at 64 x 64, four parts took 0.09–0.12 ms
/// against 0.05–0.08 in one.
const SERIAL_BELOW: usize = 8192;

/// Vertices or triangles per part, at least, of a mesh updated on the pool's threads. The
/// same bench at 128 x 128: parts of 1 024 took 0.18–0.24 ms against 0.26–0.27 for parts
/// of 4 096.
const SMALLEST_PART: usize = 1024;

/// A cloth's vertex data and the buffers behind it.
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    /// Each particle's position in the cloth entity's frame, m.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals in the same frame (+Z where no drawn triangle touches a particle).
    pub normals: Vec<[f32; 3]>,
    /// [`burn_attribute`] of each particle.
    pub burn: Vec<[f32; 2]>,
    /// Twice-area normal of each triangle (zero when it is not drawn); SIMD vectors, so
    /// summing a vertex's faces is a vector add a face.
    face: Vec<Vec3A>,
    /// The triangles of each particle, compressed rows.
    rows_start: Vec<u32>,
    rows: Vec<u32>,
}

impl MeshData {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.positions.capacity() + self.normals.capacity()) * size_of::<[f32; 3]>()
            + self.burn.capacity() * size_of::<[f32; 2]>()
            + self.face.capacity() * size_of::<Vec3A>()
            + (self.rows_start.capacity() + self.rows.capacity()) * size_of::<u32>()
    }

    /// Recomputes the vertex data of a cloth placed by `world_to_local`'s inverse.
    pub fn update(
        &mut self,
        particles: &Particles,
        topology: &Topology,
        material: &BurnMaterial,
        world_to_local: Affine3A,
        pool: Option<&TaskPool>,
    ) {
        let n = particles.len();
        self.prepare(n, &topology.triangles);
        let pool = pool.filter(|_| n >= SERIAL_BELOW);
        let parts = parts_for(pool, n, SMALLEST_PART);
        let size = n.div_ceil(parts).max(1);
        // Positions and burn data, vertex by vertex.
        let state = &particles.state[..n];
        let work = pieces(&mut self.positions, parts)
            .zip(pieces(&mut self.burn, parts))
            .zip(particles.position.chunks(size))
            .zip(particles.temperature.chunks(size).zip(state.chunks(size)));
        for_each_part(
            pool,
            work,
            |(((positions, burn), world), (temperature, state))| {
                local_vertices(positions, world, world_to_local);
                burn_data(burn, temperature, state, material);
            },
        );
        // Face normals, triangle by triangle, from the local positions.
        let triangles = &topology.triangles;
        let face_parts = parts_for(pool, triangles.len(), SMALLEST_PART);
        let face_size = triangles.len().div_ceil(face_parts).max(1);
        let positions = &self.positions[..n];
        let work = pieces(&mut self.face, face_parts).zip(triangles.chunks(face_size));
        for_each_part(pool, work, |(faces, triangles)| {
            face_normals(faces, triangles, positions, state);
        });
        // Vertex normals, vertex by vertex, from the faces around each.
        let (faces, start, rows) = (&self.face, &self.rows_start, &self.rows);
        let work = pieces(&mut self.normals, parts).enumerate();
        for_each_part(pool, work, |(part, normals)| {
            let first = part * size;
            vertex_normals(normals, &start[first..=first + normals.len()], rows, faces);
        });
    }

    /// Sizes the buffers and, when the triangles changed in number, the rows from each
    /// particle to its triangles.
    fn prepare(&mut self, n: usize, triangles: &[[u32; 3]]) {
        self.positions.resize(n, [0.0; 3]);
        self.normals.resize(n, [0.0; 3]);
        self.burn.resize(n, [0.0; 2]);
        if self.face.len() == triangles.len() && self.rows_start.len() == n + 1 {
            return;
        }
        self.face.clear();
        self.face.resize(triangles.len(), Vec3A::ZERO);
        self.rows_start.clear();
        self.rows_start.resize(n + 1, 0);
        for triangle in triangles {
            for &i in triangle {
                if (i as usize) < n {
                    self.rows_start[i as usize + 1] += 1;
                }
            }
        }
        for i in 0..n {
            self.rows_start[i + 1] += self.rows_start[i];
        }
        self.rows.clear();
        self.rows.resize(self.rows_start[n] as usize, 0);
        let mut cursor = self.rows_start[..n].to_vec();
        for (t, triangle) in triangles.iter().enumerate() {
            for &i in triangle {
                if (i as usize) < n {
                    self.rows[cursor[i as usize] as usize] = t as u32;
                    cursor[i as usize] += 1;
                }
            }
        }
    }
}

/// Each world position of `world` in the cloth's local frame.
fn local_vertices(out: &mut [[f32; 3]], world: &[Vec3], world_to_local: Affine3A) {
    for (out, p) in out.iter_mut().zip(world) {
        *out = world_to_local.transform_point3(*p).to_array();
    }
}

/// Each particle's [`burn_attribute`].
fn burn_data(
    out: &mut [[f32; 2]],
    temperature: &[f32],
    state: &[BurnState],
    material: &BurnMaterial,
) {
    // [`burn_attribute`] without a branch, so the loop vectorises: both fractions always,
    // then the state picks (the same values to the bit). Written here, not as a branch-free
    // `burn_attribute` called from the loop: that compiled to 4.6 % more instructions for the
    // whole mesh update (callgrind, 32 x 32 and 64 x 64 cloths).
    let (cold, ignition, burnt) = (
        material.initial_temperature,
        material.ignition_temperature,
        material.burnt_temperature,
    );
    for ((out, &t), &s) in out.iter_mut().zip(temperature).zip(state) {
        let heat = fraction(t, cold, ignition);
        let burn = fraction(t, ignition, burnt);
        let [heat, burn] = [heat, if s == BurnState::Ignited { burn } else { 0.0 }];
        *out = if s == BurnState::Burnt {
            [1.0, 1.0]
        } else {
            [heat, burn]
        };
    }
}

/// Where `temperature` lies from `from` to `to`, in [0, 1].
#[inline(always)]
fn fraction(temperature: f32, from: f32, to: f32) -> f32 {
    ((temperature - from) / (to - from)).clamp(0.0, 1.0)
}

/// Each triangle's normal scaled by twice its area, or zero once a corner has burnt.
/// `positions` and `state` have one entry per particle.
fn face_normals(
    out: &mut [Vec3A],
    triangles: &[[u32; 3]],
    positions: &[[f32; 3]],
    state: &[BurnState],
) {
    // Both cut to one length, so one test per corner checks both reads.
    let state = &state[..positions.len()];
    for (face, triangle) in out.iter_mut().zip(triangles) {
        let [a, b, c] = triangle.map(|i| i as usize);
        let burnt = |i: usize| state[i] == BurnState::Burnt;
        // `|` rather than `||`: no branch per corner.
        *face = if burnt(a) | burnt(b) | burnt(c) {
            Vec3A::ZERO
        } else {
            let [pa, pb, pc] = [a, b, c].map(|i| Vec3A::from(positions[i]));
            // The cross product's length is twice the area: larger triangles weigh more.
            (pb - pa).cross(pc - pa)
        };
    }
}

/// Each vertex's normal: the normalised sum of the faces around it, `+Z` for none. Vertex
/// `k`'s faces are `rows[bounds[k]..bounds[k + 1]]`.
fn vertex_normals(out: &mut [[f32; 3]], bounds: &[u32], rows: &[u32], faces: &[Vec3A]) {
    for (normal, ends) in out.iter_mut().zip(bounds.windows(2)) {
        let around = &rows[ends[0] as usize..ends[1] as usize];
        let sum: Vec3A = around.iter().map(|&t| faces[t as usize]).sum();
        *normal = sum.try_normalize().unwrap_or(Vec3A::Z).to_array();
    }
}

/// Burn data of a particle for the shader, `[heat, burn]`, each in [0, 1]:
/// `heat` rises from the initial to the ignition temperature (scorch), `burn` from the
/// ignition to the burnt temperature (char, glow, and the cut where it passes the
/// material's threshold). A burnt particle is `[1, 1]`.
pub fn burn_attribute(temperature: f32, state: BurnState, material: &BurnMaterial) -> [f32; 2] {
    let heat = fraction(
        temperature,
        material.initial_temperature,
        material.ignition_temperature,
    );
    match state {
        BurnState::Burnt => [1.0, 1.0],
        BurnState::Intact => [heat, 0.0],
        BurnState::Ignited => [
            heat,
            fraction(
                temperature,
                material.ignition_temperature,
                material.burnt_temperature,
            ),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{ClothBuilder, GridPlane};

    #[test]
    fn a_flat_cloth_faces_forward_and_a_burnt_corner_is_left_out() {
        let parts = ClothBuilder::grid(4, 3, 0.1)
            .build(&BurnMaterial::COTTON, Affine3A::from_translation(Vec3::Y))
            .unwrap();
        let (mut particles, topology) = (parts.particles, parts.topology);
        let mut mesh = MeshData::default();
        let to_local = Affine3A::from_translation(-Vec3::Y);
        mesh.update(&particles, &topology, &BurnMaterial::COTTON, to_local, None);
        assert_eq!(mesh.positions[0], particles.anchor[0].to_array());
        for n in &mesh.normals {
            assert!((Vec3::from(*n) - Vec3::Z).length() < 1e-6, "{n:?}");
        }
        // A corner lifted out of the plane tilts its normal; burnt, it no longer counts.
        particles.position[0].z += 0.1;
        mesh.update(&particles, &topology, &BurnMaterial::COTTON, to_local, None);
        assert!(Vec3::from(mesh.normals[1]).z < 0.999);
        particles.state[0] = BurnState::Burnt;
        mesh.update(&particles, &topology, &BurnMaterial::COTTON, to_local, None);
        assert!((Vec3::from(mesh.normals[1]) - Vec3::Z).length() < 1e-6);
        assert_eq!(mesh.normals[0], [0.0, 0.0, 1.0], "no drawn triangle: +Z");
        assert_eq!(mesh.burn[0], [1.0, 1.0]);
        // A horizontal cloth faces up (its own +Y, as built).
        let flat = ClothBuilder::grid(3, 3, 0.1)
            .in_plane(GridPlane::Horizontal)
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        mesh.update(
            &flat.particles,
            &flat.topology,
            &BurnMaterial::COTTON,
            Affine3A::IDENTITY,
            None,
        );
        assert!(
            mesh.normals.iter().all(|n| n[1].abs() > 0.999),
            "{:?}",
            mesh.normals
        );
    }

    #[test]
    fn burn_data_runs_from_cold_through_ignition_to_burnt() {
        let m = BurnMaterial::COTTON;
        assert_eq!(
            burn_attribute(m.initial_temperature, BurnState::Intact, &m),
            [0.0, 0.0]
        );
        let [heat, burn] = burn_attribute(m.ignition_temperature, BurnState::Intact, &m);
        assert_eq!((heat, burn), (1.0, 0.0));
        let middle = 0.5 * (m.ignition_temperature + m.burnt_temperature);
        let [_, burn] = burn_attribute(middle, BurnState::Ignited, &m);
        assert!((burn - 0.5).abs() < 1e-5);
        assert_eq!(burn_attribute(-50.0, BurnState::Burnt, &m), [1.0, 1.0]);
        assert_eq!(burn_attribute(f32::MAX, BurnState::Ignited, &m), [1.0, 1.0]);
    }
}
