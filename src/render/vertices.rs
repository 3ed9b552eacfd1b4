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

/// Colour a particle multiplies the cloth's colour by, linear RGBA.
///
/// White while cold; browning to scorch as it heats toward ignition; on fire, glowing
/// orange at ignition darkening to black char as it nears the burnt temperature.
pub fn burn_colour(temperature: f32, state: BurnState, material: &BurnMaterial) -> [f32; 4] {
    const SCORCH: Vec3 = Vec3::new(0.45, 0.30, 0.18);
    const EMBER: Vec3 = Vec3::new(1.6, 0.55, 0.08);
    const CHAR: Vec3 = Vec3::new(0.03, 0.025, 0.02);
    let fraction = |t: f32, from: f32, to: f32| ((t - from) / (to - from)).clamp(0.0, 1.0);
    let colour = match state {
        BurnState::Burnt => CHAR,
        BurnState::Intact => Vec3::ONE.lerp(
            SCORCH,
            fraction(
                temperature,
                material.initial_temperature,
                material.ignition_temperature,
            ),
        ),
        BurnState::Ignited => EMBER.lerp(
            CHAR,
            fraction(
                temperature,
                material.ignition_temperature,
                material.burnt_temperature,
            )
            .sqrt(),
        ),
    };
    [colour.x, colour.y, colour.z, 1.0]
}

/// Writes [`burn_colour`] for every particle.
pub fn burn_colours(particles: &Particles, material: &BurnMaterial, out: &mut Vec<[f32; 4]>) {
    out.clear();
    out.extend(
        particles
            .temperature
            .iter()
            .zip(&particles.state)
            .map(|(&t, &s)| burn_colour(t, s, material)),
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
    fn colour_goes_from_white_through_scorch_and_glow_to_char() {
        let m = BurnMaterial::COTTON;
        let cold = burn_colour(m.initial_temperature, BurnState::Intact, &m);
        assert_eq!(cold, [1.0, 1.0, 1.0, 1.0]);
        let hot = burn_colour(m.ignition_temperature - 1.0, BurnState::Intact, &m);
        assert!(hot[2] < 0.3, "scorched toward brown: {hot:?}");
        let lit = burn_colour(m.ignition_temperature + 1.0, BurnState::Ignited, &m);
        assert!(
            lit[0] > 1.0 && lit[0] > 2.0 * lit[2],
            "glowing orange: {lit:?}"
        );
        let charred = burn_colour(m.burnt_temperature, BurnState::Ignited, &m);
        assert!(charred[0] < 0.05, "char: {charred:?}");
    }
}
