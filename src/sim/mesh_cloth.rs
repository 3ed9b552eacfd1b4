//! Cloth from any triangle mesh: a banner, a tent, a sail, a loaded glTF.
//!
//! Vertices at the same position (within a weld tolerance) become one particle, so a mesh
//! split at UV seams or flat-shaded still hangs together. Every triangle edge becomes a
//! structural spring; every edge shared by two triangles adds a bending spring between the
//! two vertices opposite it. Each particle carries a third of the area of its triangles times
//! the material's areal density. Pins come from a [`MeshPins`] rule.

use super::error::ClothError;
use super::grid::{ClothParts, MAX_PARTICLES};
use super::lattice::mesh_lattice;
use super::material::BurnMaterial;
use super::particles::{BurnState, Particles};
use super::springs::{SpanRule, SpringKind, Springs};
use super::topology::{Topology, cull_triangles};
use bevy::reflect::{Reflect, std_traits::ReflectDefault};
use glam::{Affine3A, Vec2, Vec3};
use std::sync::Arc;

/// Which vertices of a mesh are pinned. Positions are in the mesh's local space (before the
/// entity's transform), as the mesh asset stores them.
#[derive(Clone, Debug, Default, PartialEq, Reflect)]
#[reflect(Default, Clone, Debug, PartialEq)]
pub enum MeshPins {
    /// None: the whole mesh falls.
    #[default]
    None,
    /// Vertices whose local `y` is at least this (e.g. the top edge of a banner).
    Above(f32),
    /// Vertices within `within` (m) of the mesh's highest local `y`: the top edge of a mesh
    /// whose coordinates you do not know (one loaded from glTF).
    Top {
        /// Depth of the pinned band below the highest vertex, m.
        within: f32,
    },
    /// Vertices whose local position is within `radius` of any of these points.
    Near {
        /// Local points, m.
        points: Vec<Vec3>,
        /// Reach, m.
        radius: f32,
    },
    /// Vertices by index into the mesh's vertex list (before welding): a vertex group.
    Indices(Vec<u32>),
    /// Vertices for which your rule returns `true`; see [`MeshPins::custom`].
    Custom(#[reflect(ignore)] PinRule),
}

impl MeshPins {
    /// Pins the vertices for which `rule(vertex index, local position)` is `true`, for
    /// example `MeshPins::custom(|_, p| p.y > 0.4 && p.x.abs() > 0.25)` for two top corners.
    pub fn custom(rule: impl Fn(u32, Vec3) -> bool + Send + Sync + 'static) -> Self {
        Self::Custom(PinRule(Arc::new(rule)))
    }

    /// Which of these local vertex positions are pinned (one flag per vertex; indices past
    /// the list are ignored).
    fn pinned_vertices(&self, positions: &[Vec3]) -> Vec<bool> {
        let mut pinned = vec![false; positions.len()];
        let mut mark_where = |rule: &dyn Fn(u32, Vec3) -> bool| {
            for (index, (flag, &local)) in pinned.iter_mut().zip(positions).enumerate() {
                *flag = rule(index as u32, local);
            }
        };
        match self {
            Self::None => {}
            Self::Above(y) => mark_where(&|_, local| local.y >= *y),
            Self::Top { within } => {
                let top = positions.iter().fold(f32::MIN, |top, p| top.max(p.y));
                mark_where(&|_, local| local.y >= top - within.max(0.0));
            }
            Self::Near { points, radius } => mark_where(&|_, local| {
                points
                    .iter()
                    .any(|p| p.distance_squared(local) <= radius * radius)
            }),
            Self::Custom(rule) => mark_where(&*rule.0),
            Self::Indices(indices) => {
                for &i in indices {
                    if let Some(flag) = pinned.get_mut(i as usize) {
                        *flag = true;
                    }
                }
            }
        }
        pinned
    }
}

/// A pin rule of your own: `(vertex index, local position) -> pinned`. Two rules are equal
/// when they are the same closure (the same `Arc`).
#[derive(Clone)]
pub struct PinRule(pub Arc<dyn Fn(u32, Vec3) -> bool + Send + Sync>);

/// A rule that pins nothing: what a custom rule becomes when a [`MeshPins`] comes back
/// through reflection (a scene file), since a closure cannot be saved.
impl Default for PinRule {
    fn default() -> Self {
        Self(Arc::new(|_, _| false))
    }
}

impl std::fmt::Debug for PinRule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PinRule(..)")
    }
}

impl PartialEq for PinRule {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// A triangle mesh to turn into a cloth.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshClothBuilder {
    /// Vertex positions in the cloth's local frame, m.
    pub positions: Vec<Vec3>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates per vertex, if the mesh has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Which vertices are pinned.
    pub pins: MeshPins,
    /// Vertices closer than this are welded into one particle, m (default 1e-4).
    pub weld_distance: f32,
}

impl MeshClothBuilder {
    /// A cloth from vertex positions and triangles, nothing pinned.
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Self {
        Self {
            positions,
            triangles,
            uvs: None,
            pins: MeshPins::None,
            weld_distance: 1e-4,
        }
    }

    /// With texture coordinates per vertex.
    pub fn with_uvs(mut self, uvs: Vec<Vec2>) -> Self {
        self.uvs = Some(uvs);
        self
    }

    /// With a pin rule.
    pub fn with_pins(mut self, pins: MeshPins) -> Self {
        self.pins = pins;
        self
    }

    /// Builds the cloth placed by `transform`. Errors on an empty or non-finite mesh,
    /// triangles pointing past the vertex list, more than [`MAX_PARTICLES`] particles, a bad
    /// material or transform, or a mesh without area.
    pub fn build(
        &self,
        material: &BurnMaterial,
        transform: Affine3A,
    ) -> Result<ClothParts, ClothError> {
        material.validate()?;
        if !(transform.matrix3.is_finite() && transform.translation.is_finite()) {
            return Err(ClothError::NonFiniteTransform);
        }
        let n_vertices = self.positions.len();
        if n_vertices < 3 || self.triangles.is_empty() {
            return Err(ClothError::InvalidMesh(
                "fewer than 3 vertices or no triangles",
            ));
        }
        if n_vertices as u64 > MAX_PARTICLES {
            return Err(ClothError::TooManyParticles {
                requested: n_vertices as u64,
                max: MAX_PARTICLES,
            });
        }
        if self.positions.iter().any(|p| !p.is_finite()) {
            return Err(ClothError::NonFinitePoint);
        }
        if self
            .triangles
            .iter()
            .flatten()
            .any(|&i| i as usize >= n_vertices)
        {
            return Err(ClothError::InvalidMesh(
                "a triangle indexes past the vertex list",
            ));
        }
        let weld = if self.weld_distance.is_finite() && self.weld_distance > 0.0 {
            self.weld_distance
        } else {
            1e-4
        };

        // Weld: sort vertices by their weld cell, merge runs of equal cells, keep only
        // vertices some triangle uses.
        let cell = |p: Vec3| (p / weld).round().as_ivec3().to_array();
        let mut order: Vec<u32> = (0..n_vertices as u32).collect();
        order.sort_by_key(|&i| (cell(self.positions[i as usize]), i));
        let mut canonical = vec![0u32; n_vertices];
        let mut start = 0;
        while start < order.len() {
            let key = cell(self.positions[order[start] as usize]);
            let mut end = start;
            while end < order.len() && cell(self.positions[order[end] as usize]) == key {
                canonical[order[end] as usize] = order[start];
                end += 1;
            }
            start = end;
        }
        let mut particle_of = vec![u32::MAX; n_vertices];
        let mut source_vertex = Vec::new();
        let mut triangles = Vec::with_capacity(self.triangles.len());
        for tri in &self.triangles {
            let mut out = [0u32; 3];
            for (k, &v) in tri.iter().enumerate() {
                let c = canonical[v as usize] as usize;
                if particle_of[c] == u32::MAX {
                    particle_of[c] = source_vertex.len() as u32;
                    source_vertex.push(c as u32);
                }
                out[k] = particle_of[c];
            }
            if out[0] != out[1] && out[1] != out[2] && out[0] != out[2] {
                triangles.push(out);
            }
        }
        if triangles.is_empty() {
            return Err(ClothError::InvalidMesh("every triangle is degenerate"));
        }
        let n = source_vertex.len();
        let anchor: Vec<Vec3> = source_vertex
            .iter()
            .map(|&v| self.positions[v as usize])
            .collect();
        let position: Vec<Vec3> = anchor
            .iter()
            .map(|&p| transform.transform_point3(p))
            .collect();

        // Mass: a third of each triangle's (world) area to each corner.
        let mut mass = vec![0.0f32; n];
        let mut area = 0.0f32;
        for t in &triangles {
            let [a, b, c] = t.map(|i| position[i as usize]);
            let tri_area = 0.5 * (b - a).cross(c - a).length();
            area += tri_area;
            for &i in t {
                mass[i as usize] += tri_area * material.areal_density / 3.0;
            }
        }
        if !(area.is_finite() && area > 0.0) {
            return Err(ClothError::InvalidMesh("the mesh has no area"));
        }
        // A vertex of only sliver triangles still needs some mass to move sanely.
        let mean_mass = area * material.areal_density / n as f32;
        for m in &mut mass {
            *m = m.max(0.05 * mean_mass);
        }
        let mut inv_mass: Vec<f32> = mass.iter().map(|m| 1.0 / m).collect();
        let mut welded_pins = vec![false; n];
        let pinned_vertex = self.pins.pinned_vertices(&self.positions);
        for (&c, &pinned) in canonical.iter().zip(&pinned_vertex) {
            let p = particle_of[c as usize];
            if p != u32::MAX && pinned {
                welded_pins[p as usize] = true;
            }
        }
        for (i, pinned) in welded_pins.iter().enumerate() {
            if *pinned {
                inv_mass[i] = 0.0;
            }
        }

        let springs = mesh_springs(&triangles, &position);
        let spacing = {
            let total: f32 = springs
                .kind
                .iter()
                .zip(&springs.rest_length)
                .filter(|(k, _)| **k == SpringKind::Structural)
                .map(|(_, l)| *l)
                .sum();
            let count = springs
                .kind
                .iter()
                .filter(|k| **k == SpringKind::Structural)
                .count();
            total / count.max(1) as f32
        };
        let uv = match &self.uvs {
            Some(uvs) if uvs.len() == n_vertices => {
                source_vertex.iter().map(|&v| uvs[v as usize]).collect()
            }
            _ => planar_uvs(&anchor),
        };
        let particles = Particles {
            position,
            velocity: vec![Vec3::ZERO; n],
            mass,
            inv_mass,
            temperature: vec![material.initial_temperature; n],
            state: vec![BurnState::Intact; n],
            burning_for: vec![0.0; n],
            anchor,
            external_force: vec![Vec3::ZERO; n],
        };
        let heat_lattice = mesh_lattice(&triangles, &particles.position);
        let topology = Topology {
            triangles,
            uv,
            grid: None,
            spacing,
            particle_mass: mean_mass,
            heat_lattice,
            live_indices: Vec::new(),
        };
        let mut parts = ClothParts {
            particles,
            springs,
            topology,
        };
        cull_triangles(
            &parts.topology.triangles,
            &parts.particles.state,
            &mut parts.topology.live_indices,
        );
        Ok(parts)
    }
}

/// Structural springs along every edge, bending springs across every edge shared by two
/// triangles (between the vertices opposite it). Each spring stored once.
fn mesh_springs(triangles: &[[u32; 3]], position: &[Vec3]) -> Springs {
    // (edge low, edge high, opposite vertex), sorted so shared edges are adjacent.
    let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    for &[a, b, c] in triangles {
        for (p, q, opposite) in [(a, b, c), (b, c, a), (c, a, b)] {
            edges.push((p.min(q), p.max(q), opposite));
        }
    }
    edges.sort_unstable();
    let mut springs = Springs::default();
    let mut bends: Vec<(u32, u32, [u32; 2])> = Vec::new();
    let mut i = 0;
    while i < edges.len() {
        let (a, b, _) = edges[i];
        let mut j = i;
        while j < edges.len() && edges[j].0 == a && edges[j].1 == b {
            j += 1;
        }
        springs.push(
            a,
            b,
            position[a as usize].distance(position[b as usize]),
            SpringKind::Structural,
        );
        if j - i == 2 {
            let (p, q) = (edges[i].2, edges[i + 1].2);
            if p != q {
                bends.push((p.min(q), p.max(q), [a, b]));
            }
        }
        i = j;
    }
    bends.sort_unstable();
    bends.dedup_by_key(|(p, q, _)| (*p, *q));
    for (p, q, edge) in bends {
        springs.push_spanning(
            [p, q],
            position[p as usize].distance(position[q as usize]),
            SpringKind::Bend,
            edge,
            SpanRule::Either,
        );
    }
    springs
}

/// Texture coordinates by projecting onto the plane of the mesh's two longest extents.
fn planar_uvs(local: &[Vec3]) -> Vec<Vec2> {
    let (lo, hi) = local.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| {
        (lo.min(*p), hi.max(*p))
    });
    let size = (hi - lo).max(Vec3::splat(1e-6));
    // Drop the axis of least extent.
    let drop = if size.x <= size.y && size.x <= size.z {
        0
    } else if size.y <= size.z {
        1
    } else {
        2
    };
    let (u, v) = match drop {
        0 => (2, 1),
        1 => (0, 2),
        _ => (0, 1),
    };
    local
        .iter()
        .map(|p| {
            let q = (*p - lo) / size;
            Vec2::new(q[u], 1.0 - q[v])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat `n × n` vertex plane in x-y, 0.1 m apart, each quad split in two, as a mesh
    /// library emits it (shared vertices).
    fn plane(n: u32) -> MeshClothBuilder {
        let mut positions = Vec::new();
        for row in 0..n {
            for column in 0..n {
                positions.push(Vec3::new(column as f32 * 0.1, -(row as f32) * 0.1, 0.0));
            }
        }
        let mut triangles = Vec::new();
        for row in 0..n - 1 {
            for column in 0..n - 1 {
                let i = row * n + column;
                triangles.push([i, i + n, i + 1]);
                triangles.push([i + 1, i + n, i + n + 1]);
            }
        }
        MeshClothBuilder::new(positions, triangles)
    }

    #[test]
    fn a_plane_gets_one_spring_per_edge_and_one_bend_per_interior_edge() {
        let n = 4u32;
        let parts = plane(n)
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        assert_eq!(parts.particles.len(), 16);
        // Edges of a 3 x 3 quad grid split by one diagonal each: 2·n·(n−1) axis edges plus
        // (n−1)² diagonals; interior edges: all but the 4·(n−1) on the border.
        let edges = 2 * n * (n - 1) + (n - 1) * (n - 1);
        let interior = edges - 4 * (n - 1);
        let count = |kind| parts.springs.kind.iter().filter(|k| **k == kind).count() as u32;
        assert_eq!(count(SpringKind::Structural), edges);
        assert_eq!(count(SpringKind::Bend), interior);
        // Mass: total = area × density.
        let total: f32 = parts.particles.mass.iter().sum();
        let area = 0.3 * 0.3;
        assert!((total - area * BurnMaterial::COTTON.areal_density).abs() < 1e-5);
        assert_eq!(parts.topology.live_triangle_count(), 18);
        assert!((parts.topology.spacing - 0.1).abs() < 0.03);
    }

    #[test]
    fn duplicated_vertices_are_welded_and_pins_follow_the_rule() {
        // The same 3 x 3 plane with every triangle's vertices duplicated (flat shading).
        let shared = plane(3);
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for t in &shared.triangles {
            let base = positions.len() as u32;
            for &v in t {
                positions.push(shared.positions[v as usize]);
            }
            triangles.push([base, base + 1, base + 2]);
        }
        let split = MeshClothBuilder::new(positions, triangles).with_pins(MeshPins::Above(-0.01));
        let parts = split
            .build(&BurnMaterial::SILK, Affine3A::from_translation(Vec3::Y))
            .unwrap();
        assert_eq!(parts.particles.len(), 9, "welded back to 9 particles");
        let pinned = (0..9).filter(|&i| parts.particles.is_pinned(i)).count();
        assert_eq!(pinned, 3, "the top row");
        for i in 0..9 {
            if parts.particles.is_pinned(i) {
                assert!((parts.particles.position[i].y - 1.0).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn bad_meshes_are_errors() {
        let m = BurnMaterial::CLOTH;
        let id = Affine3A::IDENTITY;
        assert!(MeshClothBuilder::new(vec![], vec![]).build(&m, id).is_err());
        let mut out_of_range = plane(3);
        out_of_range.triangles.push([0, 1, 99]);
        assert!(out_of_range.build(&m, id).is_err());
        let mut nan = plane(3);
        nan.positions[4] = Vec3::NAN;
        assert!(nan.build(&m, id).is_err());
        // Every triangle collapsed onto one point.
        let flat = MeshClothBuilder::new(vec![Vec3::ZERO; 3], vec![[0, 1, 2]]);
        assert!(flat.build(&m, id).is_err());
        assert!(
            plane(3)
                .build(&m, Affine3A::from_translation(Vec3::NAN))
                .is_err()
        );
    }

    #[test]
    fn every_pin_rule_pins_the_vertices_it_names() {
        // plane(4): rows at y = 0, -0.1, -0.2, -0.3; columns at x = 0 .. 0.3.
        let pinned = |pins: MeshPins| {
            let parts = plane(4)
                .with_pins(pins)
                .build(&BurnMaterial::CLOTH, Affine3A::IDENTITY)
                .unwrap();
            // Particles are numbered in the order triangles use them: name each pinned one by
            // the vertex index its position has in the plane.
            let mut vertices: Vec<u32> = (0..parts.particles.len())
                .filter(|&i| parts.particles.is_pinned(i))
                .map(|i| {
                    let p = parts.particles.position[i] / 0.1;
                    (-p.y).round() as u32 * 4 + p.x.round() as u32
                })
                .collect();
            vertices.sort_unstable();
            vertices
        };
        assert_eq!(pinned(MeshPins::None), Vec::<u32>::new());
        assert_eq!(pinned(MeshPins::Above(-0.05)), vec![0, 1, 2, 3]);
        // The top band, whatever the mesh's height: the first two rows.
        assert_eq!(
            pinned(MeshPins::Top { within: 0.15 }),
            (0..8).collect::<Vec<_>>()
        );
        assert_eq!(
            pinned(MeshPins::Near {
                points: vec![Vec3::new(0.3, 0.0, 0.0)],
                radius: 0.01
            }),
            vec![3]
        );
        // A vertex group; an index past the vertex list is ignored.
        assert_eq!(pinned(MeshPins::Indices(vec![15, 0, 99])), vec![0, 15]);
        // Two top corners by a rule of the game's own.
        let corners = MeshPins::custom(|_, p| p.y > -0.05 && (p.x < 0.05 || p.x > 0.25));
        assert_eq!(pinned(corners.clone()), vec![0, 3]);
        assert_eq!(corners.clone(), corners, "a rule equals itself");
        assert_ne!(corners, MeshPins::custom(|_, _| true));
    }
}
