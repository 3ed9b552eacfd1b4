//! How densely a mesh's particles sit and how many neighbours each has, so that the paper's
//! heat model, whose push goes particle to neighbour, moves a front as fast on any
//! triangulation as on the grid its rates are given for.
//!
//! On a grid of spacing `l` every interior particle pushes to 8 neighbours (structural and
//! shear springs) and a front crosses one row every `l`. A mesh particle pushes along its
//! triangle edges: a triangulated square grid gives it 6 neighbours, a fan or an imported
//! mesh anything from 3 to 12, and the mean edge is not the distance between rows (a
//! triangulated grid's mean edge is 1.14 `l`). Two measures put a mesh on the grid's footing:
//! - the **row spacing** `√(A / n)`, the side of the square of the area each interior
//!   particle owns (a third of each triangle it is a corner of): `l` for a triangulated grid
//!   of spacing `l`, whatever its diagonals;
//! - the **push neighbours**, the mean number of edges at an interior particle.
//!
//! Interior particles are those on no boundary edge (an edge of one triangle only); a mesh
//! with none falls back to every particle.

use glam::Vec3;

/// In-plane neighbours an interior particle of a grid pushes heat to (structural and shear).
pub const GRID_PUSH_NEIGHBOURS: f32 = 8.0;

/// A mesh's heat lattice: its row spacing and its particles' mean neighbour count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    /// Side of the square of area each interior particle owns, m.
    pub row_spacing: f32,
    /// Mean number of distinct edges at an interior particle.
    pub push_neighbours: f32,
}

/// The lattice of a triangle mesh over `position` (particles not in any triangle are not
/// counted). `None` when no triangle has area.
pub fn mesh_lattice(triangles: &[[u32; 3]], position: &[Vec3]) -> Option<Lattice> {
    let n = position.len();
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    let mut area = vec![0.0f32; n];
    for &[a, b, c] in triangles {
        let [pa, pb, pc] = [a, b, c].map(|i| position[i as usize]);
        let share = 0.5 * (pb - pa).cross(pc - pa).length() / 3.0;
        for (p, q) in [(a, b), (b, c), (c, a)] {
            edges.push((p.min(q), p.max(q)));
            area[p as usize] += share;
        }
    }
    edges.sort_unstable();
    // Distinct edges per particle, and whether it lies on an edge of one triangle.
    let mut degree = vec![0u32; n];
    let mut boundary = vec![false; n];
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j] == edges[i] {
            j += 1;
        }
        let (a, b) = (edges[i].0 as usize, edges[i].1 as usize);
        degree[a] += 1;
        degree[b] += 1;
        if j - i == 1 {
            boundary[a] = true;
            boundary[b] = true;
        }
        i = j;
    }
    let measure = |interior_only: bool| {
        let (mut owned, mut neighbours, mut count) = (0.0f64, 0u64, 0u64);
        for p in 0..n {
            if degree[p] == 0 || (interior_only && boundary[p]) {
                continue;
            }
            owned += f64::from(area[p]);
            neighbours += u64::from(degree[p]);
            count += 1;
        }
        (count > 0 && owned > 0.0).then(|| Lattice {
            row_spacing: (owned / count as f64).sqrt() as f32,
            push_neighbours: neighbours as f32 / count as f32,
        })
    };
    measure(true).or_else(|| measure(false))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square grid of `n` x `n` particles `l` apart, each cell split along a diagonal that
    /// alternates (or not) from cell to cell.
    fn triangulated_grid(n: u32, l: f32, alternate: bool) -> (Vec<[u32; 3]>, Vec<Vec3>) {
        let mut position = Vec::new();
        for row in 0..n {
            for column in 0..n {
                position.push(Vec3::new(column as f32 * l, row as f32 * l, 0.0));
            }
        }
        let mut triangles = Vec::new();
        for row in 0..n - 1 {
            for column in 0..n - 1 {
                let [a, b, c, d] = [
                    row * n + column,
                    row * n + column + 1,
                    (row + 1) * n + column,
                    (row + 1) * n + column + 1,
                ];
                if alternate && (row + column) % 2 == 1 {
                    triangles.extend([[a, b, c], [b, d, c]]);
                } else {
                    triangles.extend([[a, b, d], [a, d, c]]);
                }
            }
        }
        (triangles, position)
    }

    #[test]
    fn a_triangulated_grid_has_the_grids_spacing_and_six_neighbours() {
        for alternate in [false, true] {
            let (triangles, position) = triangulated_grid(9, 0.02, alternate);
            let lattice = mesh_lattice(&triangles, &position).unwrap();
            assert!(
                (lattice.row_spacing / 0.02 - 1.0).abs() < 0.01,
                "{lattice:?}"
            );
            if !alternate {
                // Each interior particle: 4 axis edges and 2 on the shared diagonal.
                assert_eq!(lattice.push_neighbours, 6.0);
            } else {
                // Alternating diagonals: about half the interior particles have 4 diagonals
                // (8 edges, 8 triangles), half none (4 and 4).
                assert!((lattice.push_neighbours - 6.0).abs() < 0.2, "{lattice:?}");
            }
        }
    }

    #[test]
    fn an_equilateral_mesh_owns_a_third_of_each_triangle() {
        // A hexagon of six equilateral triangles of side a around one interior particle:
        // it owns 6 x (√3/4 a²) / 3 and has 6 edges.
        let a = 0.05;
        let mut position = vec![Vec3::ZERO];
        for k in 0..6 {
            let angle = k as f32 * core::f32::consts::FRAC_PI_3;
            position.push(Vec3::new(a * angle.cos(), a * angle.sin(), 0.0));
        }
        let triangles: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        let lattice = mesh_lattice(&triangles, &position).unwrap();
        let owned = 6.0 * (3.0f32.sqrt() / 4.0 * a * a) / 3.0;
        assert!(
            (lattice.row_spacing - owned.sqrt()).abs() < 1e-5,
            "{lattice:?}"
        );
        assert_eq!(lattice.push_neighbours, 6.0);
    }

    #[test]
    fn a_mesh_without_area_has_no_lattice() {
        let position = vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        assert_eq!(mesh_lattice(&[[0, 1, 2]], &position), None);
    }
}
