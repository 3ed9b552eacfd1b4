//! Triangles, texture coordinates and scale of a cloth, and triangle culling.

use super::lattice::Lattice;
use super::particles::BurnState;
use glam::Vec2;

/// Columns and rows of a grid cloth; particle `row × columns + column`, row 0 at the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GridShape {
    /// Particles per row.
    pub columns: u32,
    /// Particles per column.
    pub rows: u32,
}

impl GridShape {
    /// Index of the particle at `column`, `row`.
    pub fn index(&self, column: u32, row: u32) -> usize {
        (row * self.columns + column) as usize
    }
}

/// The surface of a cloth: what the renderer draws and the heat model walks.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// Every triangle of the cloth as built, counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinate of each particle, in [0, 1]².
    pub uv: Vec<Vec2>,
    /// Grid layout, for grid cloths.
    pub grid: Option<GridShape>,
    /// Typical distance between neighbouring particles when built, m.
    pub spacing: f32,
    /// Typical particle mass, kg (sets spring damping from the damping ratio).
    pub particle_mass: f32,
    /// For a mesh cloth, its row spacing and neighbour count, which scale the paper model's
    /// heat push to the grid's footing (see [`super::lattice`]); `None` for a grid, whose
    /// `spacing` and 8 neighbours are that footing.
    pub heat_lattice: Option<Lattice>,
    /// Flattened indices of the triangles whose three particles are unburnt, kept up to date
    /// by [`cull_triangles`]; this is the index buffer the renderer draws.
    pub live_indices: Vec<u32>,
}

impl Topology {
    /// Number of triangles currently drawn.
    pub fn live_triangle_count(&self) -> usize {
        self.live_indices.len() / 3
    }
}

/// Rewrites `out` with the flattened indices of the triangles whose three particles are
/// unburnt. Reuses `out`'s memory.
pub fn cull_triangles(triangles: &[[u32; 3]], state: &[BurnState], out: &mut Vec<u32>) {
    out.clear();
    for triangle in triangles {
        if triangle.iter().all(|&i| !state[i as usize].is_burnt()) {
            out.extend_from_slice(triangle);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangles_touching_a_burnt_particle_are_dropped() {
        let triangles = [[0, 1, 2], [1, 3, 2], [3, 4, 2]];
        let mut state = [BurnState::Intact; 5];
        state[3] = BurnState::Burnt;
        state[0] = BurnState::Ignited;
        let mut out = Vec::new();
        cull_triangles(&triangles, &state, &mut out);
        assert_eq!(out, vec![0, 1, 2]);
    }
}
