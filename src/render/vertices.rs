//! Vertex data of a cloth mesh, computed from the simulation into reused buffers.
//!
//! Plain functions over slices, so they are tested without a renderer.

use crate::sim::{BurnMaterial, BurnState, Particles};
use bevy::math::{Affine3A, Vec3};

/// Writes each particle's position in the cloth entity's frame: `local = world_to_local × world`.
pub fn local_positions(particles: &Particles, world_to_local: Affine3A, out: &mut Vec<[f32; 3]>) {
    out.clear();
    out.extend(
        particles
            .position
            .iter()
            .map(|&p| world_to_local.transform_point3(p).to_array()),
    );
}

/// Area-weighted vertex normals of the triangles in `indices`, in the positions' frame.
/// A vertex with no live triangle gets +Z.
pub fn vertex_normals(positions: &[[f32; 3]], indices: &[u32], out: &mut Vec<[f32; 3]>) {
    out.clear();
    out.resize(positions.len(), [0.0; 3]);
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|i| i as usize);
        let (pa, pb, pc) = (
            Vec3::from(positions[a]),
            Vec3::from(positions[b]),
            Vec3::from(positions[c]),
        );
        // The cross product's length is twice the area: larger triangles weigh more.
        let normal = (pb - pa).cross(pc - pa);
        for i in [a, b, c] {
            out[i] = (Vec3::from(out[i]) + normal).to_array();
        }
    }
    for n in out.iter_mut() {
        *n = Vec3::from(*n).try_normalize().unwrap_or(Vec3::Z).to_array();
    }
}

/// Burn data of a particle for the shader, `[heat, burn]`, each in [0, 1]:
/// `heat` rises from the initial to the ignition temperature (scorch), `burn` from the
/// ignition to the burnt temperature (char, glow, and the cut where it passes the
/// material's threshold). A burnt particle is `[1, 1]`.
pub fn burn_attribute(temperature: f32, state: BurnState, material: &BurnMaterial) -> [f32; 2] {
    let fraction = |from: f32, to: f32| ((temperature - from) / (to - from)).clamp(0.0, 1.0);
    let heat = fraction(material.initial_temperature, material.ignition_temperature);
    match state {
        BurnState::Burnt => [1.0, 1.0],
        BurnState::Intact => [heat, 0.0],
        BurnState::Ignited => [
            heat,
            fraction(material.ignition_temperature, material.burnt_temperature),
        ],
    }
}

/// Writes [`burn_attribute`] for every particle.
pub fn burn_attributes(particles: &Particles, material: &BurnMaterial, out: &mut Vec<[f32; 2]>) {
    out.clear();
    out.extend(
        particles
            .temperature
            .iter()
            .zip(&particles.state)
            .map(|(&t, &s)| burn_attribute(t, s, material)),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_of_a_flat_square_face_forward() {
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        let indices = [0, 1, 2, 1, 3, 2];
        let mut normals = Vec::new();
        vertex_normals(&positions, &indices, &mut normals);
        for n in normals {
            assert!((Vec3::from(n) - Vec3::Z).length() < 1e-6);
        }
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
