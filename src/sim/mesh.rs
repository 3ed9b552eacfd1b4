//! Vertex data of a cloth's mesh, computed from the simulation into reused buffers: each
//! particle's position in the cloth's own frame, an area-weighted normal from the triangles
//! still drawn, and burn data for the shader. Plain arrays the render layer copies into its
//! mesh.
//!
//! Normals are summed by scattering: each drawn triangle adds its twice-area normal to its
//! three corners, in triangle order, and each vertex's sum is then normalised. On one thread
//! that is the whole update; a big mesh goes in four phases over the task pool (positions and
//! burn data by runs of vertices; the triangles in parts, those of even parts at once, then
//! those of odd parts; normalising by runs of vertices), its triangle parts cut from the mesh
//! alone, so the result does not depend on the number of threads.

use super::grid::grid_triangles;
use super::grid_normals::{self, GridFaces};
use super::material::BurnMaterial;
use super::parallel::{Claims, Disjoint, parts_for, piece, run_phases};
use super::particles::{BurnState, Particles};
use super::topology::{GridShape, Topology};
use bevy::tasks::TaskPool;
use core::ops::Range;
use glam::{Affine3A, Vec3, Vec3A};

/// Vertices below which a cloth's mesh is updated on one thread, its triangles as one part.
/// A mesh bench (a cotton cloth 6 s after lighting, medians of 9 or 15 blocks of 200
/// updates, the 2-core machine): at 64 x 64 one thread took 0.037–0.043 ms and two, from
/// 4 096 vertices, 0.027–0.053 in three runs (not reliably faster); at 128 x 128 0.155 on
/// one thread and 0.096–0.106 on two, at 256 x 256 0.63 and 0.36–0.44.
const SERIAL_BELOW: usize = 8192;

/// Vertices per row from which a whole grid's normals are gathered along its rows
/// ([`grid_normals`]) rather than scattered triangle by triangle. Per row the loops cost a
/// fixed set-up, and short rows leave much of them to the scalar tail: `stress --
/// --default-only`, two runs alternated, the mesh phase in ms a frame: 32 x 32 0.014 → 0.017
/// (slower), 64 x 64 0.056 → 0.048–0.051, 128 x 128 0.16 → 0.14, 256 x 256 0.55 → 0.42–0.46.
const ROWS_FROM_COLUMNS: u32 = 64;

/// Vertices per part, at least, of the per-vertex phases of a mesh updated on the pool's
/// threads.
const SMALLEST_PART: usize = 1024;

/// Triangles per part of the face phase of a mesh of [`SERIAL_BELOW`] vertices or more: on a
/// grid 128 wide, eight rows of quads, so a part two on touches none of the same vertices.
const TRIANGLE_PART: usize = 2048;

/// A cloth's vertex data and the buffers behind it.
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    /// Each particle's position in the cloth entity's frame, m.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals in the same frame (+Z where no drawn triangle touches a particle).
    pub normals: Vec<[f32; 3]>,
    /// [`burn_attribute`] of each particle.
    pub burn: Vec<[f32; 2]>,
    /// Each vertex's sum of the twice-area normals of its drawn triangles; SIMD vectors, so
    /// adding a face is one vector add.
    sums: Vec<Vec3A>,
    /// The face phase's parts: their triangles and the vertices those touch.
    face_parts: Vec<FacePart>,
    /// Vertices and triangles the parts were cut for; `None` before the first update.
    cut_for: Option<(usize, usize)>,
    /// Whether the mesh is a whole grid's, triangulated as `ClothBuilder::grid` does: its
    /// normals are then gathered along its rows ([`grid_normals`]).
    whole_grid: Option<GridShape>,
    grid_faces: GridFaces,
    claims: Claims,
}

/// Consecutive triangles of the face phase and the run of vertices they touch.
#[derive(Clone, Debug)]
struct FacePart {
    triangles: Range<usize>,
    vertices: Range<usize>,
}

impl MeshData {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.positions.capacity() + self.normals.capacity()) * size_of::<[f32; 3]>()
            + self.burn.capacity() * size_of::<[f32; 2]>()
            + self.sums.capacity() * size_of::<Vec3A>()
            + self.face_parts.capacity() * size_of::<FacePart>()
            + self.grid_faces.heap_bytes()
    }

    /// Recomputes the vertex data of a cloth placed by `world_to_local`'s inverse.
    #[allow(unsafe_code)]
    pub fn update(
        &mut self,
        particles: &Particles,
        topology: &Topology,
        material: &BurnMaterial,
        world_to_local: Affine3A,
        pool: Option<&TaskPool>,
    ) {
        let n = particles.len();
        let triangles = &topology.triangles;
        self.prepare(n, topology);
        let pool = pool.filter(|_| n >= SERIAL_BELOW);
        if let Some(grid) = self.whole_grid {
            return self.update_grid(particles, grid, material, world_to_local, pool);
        }
        let runs = parts_for(pool, n, SMALLEST_PART);
        let run = |item: usize| piece(n, runs, item);
        let parts = self.face_parts.len();
        let sizes = [runs, parts.div_ceil(2), parts / 2, runs];
        let state = &particles.state[..n];
        let positions = Disjoint::new(&mut self.positions[..n]);
        let burn = Disjoint::new(&mut self.burn[..n]);
        let sums = Disjoint::new(&mut self.sums[..n]);
        let normals = Disjoint::new(&mut self.normals[..n]);
        let face_parts = &self.face_parts;
        run_phases(pool, &sizes, &mut self.claims, |phase, item| match phase {
            0 => {
                // Positions, burn data and cleared sums, a run of vertices at a time.
                let run = run(item);
                // SAFETY: the runs of a phase are disjoint, and nothing else reads or writes
                // these arrays in this phase.
                let (positions, burn, sums) = unsafe {
                    (
                        positions.part(run.clone()),
                        burn.part(run.clone()),
                        sums.part(run.clone()),
                    )
                };
                local_vertices(positions, &particles.position[run.clone()], world_to_local);
                burn_run(burn, particles, run, material);
                sums.fill(Vec3A::ZERO);
            }
            1 | 2 => {
                // Every even part's triangles, then every odd part's: the parts of one
                // parity touch disjoint vertices (see `prepare`).
                let part = &face_parts[2 * item + phase - 1];
                // SAFETY: positions are only read in this phase; the vertices of the parts
                // of one phase are disjoint.
                let (positions, sums) =
                    unsafe { (positions.read(0..n), sums.part(part.vertices.clone())) };
                add_faces(
                    sums,
                    part.vertices.start,
                    &triangles[part.triangles.clone()],
                    positions,
                    state,
                );
            }
            _ => {
                let run = run(item);
                // SAFETY: the runs of a phase are disjoint; the sums are only read here.
                let (normals, sums) = unsafe { (normals.part(run.clone()), sums.read(run)) };
                normalise(normals, sums);
            }
        });
    }

    /// [`Self::update`] for a whole grid: positions and burn data by runs of vertices, with
    /// the positions per axis and which vertices are drawn; the face normals by runs of cell
    /// rows; the vertex normals by runs of vertex rows ([`grid_normals`]).
    #[allow(unsafe_code)]
    fn update_grid(
        &mut self,
        particles: &Particles,
        grid: GridShape,
        material: &BurnMaterial,
        world_to_local: Affine3A,
        pool: Option<&TaskPool>,
    ) {
        let n = particles.len();
        let (columns, rows) = (grid.columns as usize, grid.rows as usize);
        let width = self.grid_faces.width();
        let runs = parts_for(pool, n, SMALLEST_PART);
        let row_parts = parts_for(pool, rows, SMALLEST_PART.div_ceil(columns));
        let cell_parts = parts_for(pool, rows - 1, SMALLEST_PART.div_ceil(columns));
        let sizes = [runs, cell_parts, row_parts];
        let GridFaces {
            position: axes,
            alive,
            first,
            second,
            ..
        } = &mut self.grid_faces;
        let axes = axes.each_mut().map(|axis| Disjoint::new(&mut axis[..n]));
        let alive = Disjoint::new(&mut alive[..n]);
        let first = first.each_mut().map(|axis| Disjoint::new(&mut axis[..]));
        let second = second.each_mut().map(|axis| Disjoint::new(&mut axis[..]));
        let positions = Disjoint::new(&mut self.positions[..n]);
        let burn = Disjoint::new(&mut self.burn[..n]);
        let normals = Disjoint::new(&mut self.normals[..n]);
        let state = &particles.state[..n];
        run_phases(pool, &sizes, &mut self.claims, |phase, item| match phase {
            0 => {
                let run = piece(n, runs, item);
                // SAFETY: the runs of a phase are disjoint, and nothing else reads or writes
                // these arrays in this phase.
                let (positions, burn, axes, alive) = unsafe {
                    (
                        positions.part(run.clone()),
                        burn.part(run.clone()),
                        axes.each_ref().map(|axis| axis.part(run.clone())),
                        alive.part(run.clone()),
                    )
                };
                let world = &particles.position[run.clone()];
                local_vertices_by_axis(positions, axes, world, world_to_local);
                for (alive, &state) in alive.iter_mut().zip(&state[run.clone()]) {
                    *alive = if state == BurnState::Burnt { 0.0 } else { 1.0 };
                }
                burn_run(burn, particles, run, material);
            }
            1 => {
                // SAFETY: the positions are only read in this phase; each cell row's faces
                // (padded row `r + 1`) belong to one run of cell rows.
                let (axes, alive) = unsafe {
                    (
                        axes.each_ref().map(|axis| axis.read(0..n)),
                        alive.read(0..n),
                    )
                };
                for r in piece(rows - 1, cell_parts, item) {
                    let (top, bottom) = (
                        r * columns..(r + 1) * columns,
                        (r + 1) * columns..(r + 2) * columns,
                    );
                    let cells = (r + 1) * width + 1..(r + 1) * width + columns;
                    // SAFETY: as above.
                    let out = unsafe {
                        grid_normals::FaceRow {
                            first: first.each_ref().map(|axis| axis.part(cells.clone())),
                            second: second.each_ref().map(|axis| axis.part(cells.clone())),
                        }
                    };
                    grid_normals::face_row(
                        (
                            grid_normals::cut(axes, top.clone()),
                            grid_normals::cut(axes, bottom.clone()),
                        ),
                        (&alive[top], &alive[bottom]),
                        r % 2 == 1,
                        out,
                    );
                }
            }
            _ => {
                // SAFETY: the faces are only read in this phase; the runs of vertex rows
                // are disjoint.
                let (first, second) = unsafe {
                    (
                        first.each_ref().map(|axis| axis.read(0..axis.len())),
                        second.each_ref().map(|axis| axis.read(0..axis.len())),
                    )
                };
                let row = |faces, padded: usize| {
                    grid_normals::cut(faces, padded * width..(padded + 1) * width)
                };
                for r in piece(rows, row_parts, item) {
                    // SAFETY: as above.
                    let out = unsafe { normals.part(r * columns..(r + 1) * columns) };
                    grid_normals::normal_row(
                        (row(first, r), row(second, r)),
                        (row(first, r + 1), row(second, r + 1)),
                        r % 2 == 1,
                        out,
                    );
                }
            }
        });
    }

    /// Sizes the buffers and, when the mesh changed, cuts the triangles into the face phase's
    /// parts: one part below [`SERIAL_BELOW`] vertices, or when the mesh's triangles are not
    /// in an order whose parts two apart touch disjoint vertices (a grid's are); else parts
    /// of [`TRIANGLE_PART`].
    fn prepare(&mut self, n: usize, topology: &Topology) {
        let triangles = &topology.triangles;
        self.positions.resize(n, [0.0; 3]);
        self.normals.resize(n, [0.0; 3]);
        self.burn.resize(n, [0.0; 2]);
        if self.cut_for == Some((n, triangles.len())) {
            return;
        }
        self.cut_for = Some((n, triangles.len()));
        self.whole_grid = topology.grid.filter(|&grid| {
            grid.columns >= ROWS_FROM_COLUMNS
                && grid.rows >= 2
                && (grid.columns * grid.rows) as usize == n
                && *triangles == grid_triangles(grid)
        });
        if let Some(grid) = self.whole_grid {
            self.grid_faces
                .prepare(grid.columns as usize, grid.rows as usize);
            self.sums = Vec::new();
            self.face_parts.clear();
            return;
        }
        self.sums.resize(n, Vec3A::ZERO);
        self.face_parts.clear();
        let whole = FacePart {
            triangles: 0..triangles.len(),
            vertices: 0..n,
        };
        if n < SERIAL_BELOW {
            self.face_parts.push(whole);
            return;
        }
        for (k, chunk) in triangles.chunks(TRIANGLE_PART).enumerate() {
            let corners = chunk.iter().flatten().map(|&i| i as usize);
            let first = corners.clone().min().unwrap_or(0);
            let end = corners.max().map_or(first, |last| last + 1);
            let start = k * TRIANGLE_PART;
            self.face_parts.push(FacePart {
                triangles: start..start + chunk.len(),
                vertices: first..end.min(n),
            });
        }
        let apart = self
            .face_parts
            .windows(3)
            .all(|w| w[0].vertices.end <= w[2].vertices.start);
        if !apart {
            self.face_parts.clear();
            self.face_parts.push(whole);
        }
    }
}

/// A run of vertices' burn data.
fn burn_run(
    burn: &mut [[f32; 2]],
    particles: &Particles,
    run: Range<usize>,
    material: &BurnMaterial,
) {
    burn_data(
        burn,
        &particles.temperature[run.clone()],
        &particles.state[run.clone()],
        particles.burning_for.get(run),
        material,
    );
}

/// [`local_vertices`], each also written to one array per axis.
fn local_vertices_by_axis(
    out: &mut [[f32; 3]],
    [x, y, z]: [&mut [f32]; 3],
    world: &[Vec3],
    world_to_local: Affine3A,
) {
    let n = out.len();
    let (x, y, z, world) = (&mut x[..n], &mut y[..n], &mut z[..n], &world[..n]);
    for (k, out) in out.iter_mut().enumerate() {
        let p = world_to_local.transform_point3(world[k]);
        *out = p.to_array();
        (x[k], y[k], z[k]) = (p.x, p.y, p.z);
    }
}

/// Each world position of `world` in the cloth's local frame.
fn local_vertices(out: &mut [[f32; 3]], world: &[Vec3], world_to_local: Affine3A) {
    for (out, p) in out.iter_mut().zip(world) {
        *out = world_to_local.transform_point3(*p).to_array();
    }
}

/// Each particle's [`burn_attribute`] (`burning_for`: each particle's time on fire; `None`
/// for particles built without clocks, taken as done burning, so char follows temperature).
/// Compiled for AVX too and taken where the CPU has it (the same operations, so the same
/// bits): without it the loop went two particles at a time, about 3 ns a particle.
fn burn_data(
    out: &mut [[f32; 2]],
    temperature: &[f32],
    state: &[BurnState],
    burning_for: Option<&[f32]>,
    material: &BurnMaterial,
) {
    #[cfg(target_arch = "x86_64")]
    if crate::sim::simd::avx_available() {
        #[target_feature(enable = "avx")]
        fn burn_data_avx(
            out: &mut [[f32; 2]],
            temperature: &[f32],
            state: &[BurnState],
            burning_for: Option<&[f32]>,
            material: &BurnMaterial,
        ) {
            burn_data_portable(out, temperature, state, burning_for, material);
        }
        // SAFETY: this CPU has AVX.
        #[allow(unsafe_code)]
        return unsafe { burn_data_avx(out, temperature, state, burning_for, material) };
    }
    burn_data_portable(out, temperature, state, burning_for, material);
}

/// [`burn_data`] on any CPU.
#[inline(always)]
fn burn_data_portable(
    out: &mut [[f32; 2]],
    temperature: &[f32],
    state: &[BurnState],
    burning_for: Option<&[f32]>,
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
    let burn_time = material.burn_time;
    let pixel = |t: f32, s: BurnState, clock: f32| {
        let heat = fraction(t, cold, ignition);
        let burn = fraction(t, ignition, burnt).min(clock);
        let [heat, burn] = [heat, if s == BurnState::Ignited { burn } else { 0.0 }];
        if s == BurnState::Burnt {
            [1.0, 1.0]
        } else {
            [heat, burn]
        }
    };
    match burning_for {
        Some(burning_for) => {
            for (((out, &t), &s), &age) in
                out.iter_mut().zip(temperature).zip(state).zip(burning_for)
            {
                *out = pixel(t, s, burn_clock(age, burn_time));
            }
        }
        None => {
            for ((out, &t), &s) in out.iter_mut().zip(temperature).zip(state) {
                *out = pixel(t, s, 1.0);
            }
        }
    }
}

/// How far through its burn time a particle on fire for `burning_for` seconds is, in [0, 1]
/// (1 for a material that burns away at once).
#[inline(always)]
fn burn_clock(burning_for: f32, burn_time: f32) -> f32 {
    if burn_time > 0.0 {
        (burning_for / burn_time).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Where `temperature` lies from `from` to `to`, in [0, 1].
#[inline(always)]
fn fraction(temperature: f32, from: f32, to: f32) -> f32 {
    ((temperature - from) / (to - from)).clamp(0.0, 1.0)
}

/// Adds each drawn triangle's normal, scaled by twice its area, to its three corners' sums,
/// in order; a triangle with a burnt corner is not drawn and adds nothing. `sums` holds the
/// vertices from `first` on that `triangles` touch; `positions` and `state` have one entry
/// per particle.
fn add_faces(
    sums: &mut [Vec3A],
    first: usize,
    triangles: &[[u32; 3]],
    positions: &[[f32; 3]],
    state: &[BurnState],
) {
    // Both cut to one length, so one test per corner checks both reads.
    let state = &state[..positions.len()];
    for triangle in triangles {
        let [a, b, c] = triangle.map(|i| i as usize);
        let burnt = |i: usize| state[i] == BurnState::Burnt;
        // `|` rather than `||`: no branch per corner.
        if burnt(a) | burnt(b) | burnt(c) {
            continue;
        }
        let [pa, pb, pc] = [a, b, c].map(|i| Vec3A::from(positions[i]));
        // The cross product's length is twice the area: larger triangles weigh more.
        let face = (pb - pa).cross(pc - pa);
        for corner in [a, b, c] {
            sums[corner - first] += face;
        }
    }
}

/// Each vertex's unit normal from its sum of faces, `+Z` where it has none.
fn normalise(out: &mut [[f32; 3]], sums: &[Vec3A]) {
    for (normal, sum) in out.iter_mut().zip(sums) {
        // What `sum.try_normalize().unwrap_or(Vec3A::Z)` gives, with no branch: burnt
        // vertices (no faces) are scattered through a burning cloth.
        *normal = grid_normals::unit_or_z(sum.to_array());
    }
}

/// Burn data of a particle for the shader, `[heat, burn]`, each in [0, 1]:
/// `heat` rises from the initial to the ignition temperature (scorch), `burn` from the
/// ignition to the burnt temperature (char, glow, and the cut where it passes the
/// material's threshold), but no faster than the particle's time on fire, `burning_for`
/// seconds, goes through the material's `burn_time`: a particle that passed the burnt
/// temperature early (on a fine grid) chars over its burn time, as it burns away after it.
/// A burnt particle is `[1, 1]`.
pub fn burn_attribute(
    temperature: f32,
    state: BurnState,
    burning_for: f32,
    material: &BurnMaterial,
) -> [f32; 2] {
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
            )
            .min(burn_clock(burning_for, material.burn_time)),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{ClothBuilder, GridPlane};

    /// The branch-free normalisation gives `Vec3A::try_normalize(..).unwrap_or(Vec3A::Z)`
    /// to the bit: unit vectors of sums large and small, `+Z` for a zero, non-finite or
    /// overflowing sum.
    #[test]
    fn normalise_gives_try_normalize_to_the_bit() {
        let mut sums = vec![
            Vec3A::ZERO,
            Vec3A::new(1e-30, 0.0, 0.0),
            Vec3A::new(1e-20, -3e-21, 2e-20),
            Vec3A::new(3e19, 4e19, 0.0),
            Vec3A::new(3e30, 4e30, 1e30),
            Vec3A::new(f32::NAN, 1.0, 0.0),
            Vec3A::new(f32::INFINITY, 0.0, 0.0),
            Vec3A::new(-0.0, -0.0, -0.0),
        ];
        for k in 0..500 {
            let t = k as f32;
            sums.push(
                Vec3A::new((t * 0.37).sin(), (t * 1.13).cos(), (t * 0.71).sin() * 3.0) * (1.0 + t),
            );
        }
        let mut normals = vec![[0.0; 3]; sums.len()];
        normalise(&mut normals, &sums);
        for (normal, sum) in normals.iter().zip(&sums) {
            let expected = sum.try_normalize().unwrap_or(Vec3A::Z).to_array();
            assert_eq!(
                normal.map(f32::to_bits),
                expected.map(f32::to_bits),
                "{sum}"
            );
        }
    }

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

    /// Each vertex's area-weighted normal summed in f64 from every drawn triangle that has
    /// it as a corner, by brute force, as a reference.
    fn reference_normals(
        positions: &[[f32; 3]],
        triangles: &[[u32; 3]],
        burnt: &[bool],
    ) -> Vec<[f64; 3]> {
        let mut sums = vec![[0.0f64; 3]; positions.len()];
        for t in triangles
            .iter()
            .filter(|t| t.iter().all(|&i| !burnt[i as usize]))
        {
            let [a, b, c] = t.map(|i| positions[i as usize].map(f64::from));
            let (u, v) = (
                [0, 1, 2].map(|k| b[k] - a[k]),
                [0, 1, 2].map(|k| c[k] - a[k]),
            );
            let face = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            for &i in t {
                for k in 0..3 {
                    sums[i as usize][k] += face[k];
                }
            }
        }
        sums.iter()
            .map(|s| {
                let length = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
                if length > 0.0 {
                    s.map(|x| x / length)
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect()
    }

    /// How a test mesh's triangles are given.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Given {
        /// A grid's, with its shape: normals gathered along rows.
        Grid,
        /// A grid's triangles in its order, without the shape: scattered in parts.
        GridSequence,
        /// Scrambled: scattered as one part.
        Scrambled,
    }

    /// A crumpled 100 x 100 grid (past [`SERIAL_BELOW`], so its work is split) with a burnt
    /// hole, its triangles as `order` says.
    fn crumpled(order: Given) -> (Particles, Topology) {
        let parts = ClothBuilder::grid(100, 100, 0.01)
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        let (mut particles, mut topology) = (parts.particles, parts.topology);
        for (i, p) in particles.position.iter_mut().enumerate() {
            let (x, y) = ((i % 100) as f32, (i / 100) as f32);
            p.z = 0.03 * (0.37 * x).sin() * (0.23 * y).cos() + 0.002 * (7.1 * x + 3.3 * y).sin();
        }
        for row in 40..46 {
            for column in 30..37 {
                particles.state[row * 100 + column] = BurnState::Burnt;
            }
        }
        if order != Given::Grid {
            topology.grid = None;
        }
        if order == Given::Scrambled {
            // A fixed scramble: every 7th triangle, wrapping round.
            let n = topology.triangles.len();
            let order: Vec<usize> = (0..n).map(|k| (k * 7919) % n).collect();
            topology.triangles = order.iter().map(|&k| topology.triangles[k]).collect();
        }
        (particles, topology)
    }

    /// Every way of summing the faces gives each vertex its drawn triangles' area-weighted
    /// normal (against the f64 sum), and the same bits on any number of threads.
    #[test]
    fn normals_are_area_weighted_and_the_same_on_any_number_of_threads() {
        for order in [Given::Grid, Given::GridSequence, Given::Scrambled] {
            let (particles, topology) = crumpled(order);
            let update = |pool: Option<&TaskPool>| {
                let mut mesh = MeshData::default();
                let m = &BurnMaterial::COTTON;
                mesh.update(&particles, &topology, m, Affine3A::IDENTITY, pool);
                mesh
            };
            let alone = update(None);
            assert_eq!(alone.whole_grid.is_some(), order == Given::Grid);
            assert_eq!(
                alone.face_parts.len() > 1,
                order == Given::GridSequence,
                "grid order is cut in parts, a scramble is not"
            );
            let burnt: Vec<bool> = particles.state.iter().map(|s| s.is_burnt()).collect();
            let reference = reference_normals(&alone.positions, &topology.triangles, &burnt);
            for (got, want) in alone.normals.iter().zip(&reference) {
                let error = (0..3)
                    .map(|k| (f64::from(got[k]) - want[k]).abs())
                    .fold(0.0, f64::max);
                assert!(error < 1e-5, "{order:?}: {got:?} against {want:?}");
            }
            for threads in [1, 2, 3] {
                let pool = bevy::tasks::TaskPoolBuilder::new()
                    .num_threads(threads)
                    .build();
                let shared = update(Some(&pool));
                assert_eq!(
                    shared.normals, alone.normals,
                    "{order:?}, {threads} threads"
                );
                assert_eq!(shared.positions, alone.positions);
                assert_eq!(shared.burn, alone.burn);
            }
        }
    }

    /// Along rows or scattered, a grid on one thread gets the same normals
    /// to round-off, through a burnt patch and a vertex whose neighbours are all burnt (+Z).
    #[test]
    fn a_grid_gathered_along_rows_matches_the_scattered_faces() {
        // Wide enough for rows (`ROWS_FROM_COLUMNS`), with a tail past the last eight cells.
        const W: usize = ROWS_FROM_COLUMNS as usize + 3;
        let parts = ClothBuilder::grid(W as u32, 7, 0.02)
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        let (mut particles, topology) = (parts.particles, parts.topology);
        for (i, p) in particles.position.iter_mut().enumerate() {
            let (x, y) = ((i % W) as f32, (i / W) as f32);
            p.z = 0.04 * (1.3 * x).sin() * (0.9 * y).cos();
        }
        // A burnt ring around particle (4, 3), and a corner.
        for (column, row) in [
            (3, 2),
            (4, 2),
            (5, 2),
            (3, 3),
            (5, 3),
            (3, 4),
            (4, 4),
            (5, 4),
        ] {
            particles.state[row * W + column] = BurnState::Burnt;
        }
        particles.state[0] = BurnState::Burnt;
        let scattered_topology = Topology {
            grid: None,
            ..topology.clone()
        };
        let m = &BurnMaterial::COTTON;
        let (mut rows, mut scattered) = (MeshData::default(), MeshData::default());
        rows.update(&particles, &topology, m, Affine3A::IDENTITY, None);
        scattered.update(&particles, &scattered_topology, m, Affine3A::IDENTITY, None);
        assert!(rows.whole_grid.is_some() && scattered.whole_grid.is_none());
        assert_eq!(rows.normals[3 * W + 4], [0.0, 0.0, 1.0], "no drawn face");
        for (k, (a, b)) in rows.normals.iter().zip(&scattered.normals).enumerate() {
            let error = (0..3)
                .map(|axis| (a[axis] - b[axis]).abs())
                .fold(0.0, f32::max);
            assert!(error < 1e-6, "vertex {k}: {a:?} against {b:?}");
        }
        assert_eq!(rows.positions, scattered.positions);
        assert_eq!(rows.burn, scattered.burn);
    }

    #[test]
    fn burn_data_runs_from_cold_through_ignition_to_burnt() {
        let m = BurnMaterial::COTTON;
        let done = m.burn_time;
        assert_eq!(
            burn_attribute(m.initial_temperature, BurnState::Intact, 0.0, &m),
            [0.0, 0.0]
        );
        let [heat, burn] = burn_attribute(m.ignition_temperature, BurnState::Intact, 0.0, &m);
        assert_eq!((heat, burn), (1.0, 0.0));
        let middle = 0.5 * (m.ignition_temperature + m.burnt_temperature);
        let [_, burn] = burn_attribute(middle, BurnState::Ignited, done, &m);
        assert!((burn - 0.5).abs() < 1e-5);
        assert_eq!(burn_attribute(-50.0, BurnState::Burnt, 0.0, &m), [1.0, 1.0]);
        assert_eq!(
            burn_attribute(f32::MAX, BurnState::Ignited, done, &m),
            [1.0, 1.0]
        );
        // Past the burnt temperature a quarter of the way through its burn time (a fine
        // grid): charred a quarter.
        let [_, burn] = burn_attribute(f32::MAX, BurnState::Ignited, 0.25 * done, &m);
        assert!((burn - 0.25).abs() < 1e-6, "{burn}");
        // The mesh's loop gives the same values to the bit.
        let temperature = [
            m.initial_temperature,
            middle,
            middle,
            f32::MAX,
            f32::MAX,
            2e3,
        ];
        let state = [
            BurnState::Intact,
            BurnState::Ignited,
            BurnState::Ignited,
            BurnState::Ignited,
            BurnState::Ignited,
            BurnState::Burnt,
        ];
        let clocks = [0.0, 0.1 * done, 2.0 * done, 0.0, 0.3 * done, done];
        let mut out = [[0.0; 2]; 6];
        burn_data(&mut out, &temperature, &state, Some(&clocks), &m);
        for k in 0..6 {
            let expected = burn_attribute(temperature[k], state[k], clocks[k], &m);
            assert_eq!(out[k], expected, "particle {k}");
        }
    }

    /// The mesh's loop (compiled for AVX where the CPU has it, several particles at a time)
    /// gives every particle's `burn_attribute` to the bit, with clocks and without, over runs
    /// long enough for its vector loop and its tail: temperatures across the material's range
    /// and beyond, NaN and infinities, every state.
    #[test]
    fn the_burn_data_loop_gives_burn_attribute_to_the_bit() {
        let m = BurnMaterial::COTTON;
        let done = m.burn_time;
        let states = [BurnState::Intact, BurnState::Ignited, BurnState::Burnt];
        for n in [1usize, 7, 8, 9, 31, 64, 101] {
            let temperature: Vec<f32> = (0..n)
                .map(|k| match k % 11 {
                    0 => f32::NAN,
                    1 => f32::INFINITY,
                    2 => f32::NEG_INFINITY,
                    _ => -100.0 + 37.3 * k as f32,
                })
                .collect();
            let state: Vec<BurnState> = (0..n).map(|k| states[(k * 7 / 3) % 3]).collect();
            let clocks: Vec<f32> = (0..n).map(|k| 0.13 * done * (k % 9) as f32).collect();
            for with_clocks in [true, false] {
                let mut out = vec![[0.0f32; 2]; n];
                let burning_for = with_clocks.then_some(clocks.as_slice());
                burn_data(&mut out, &temperature, &state, burning_for, &m);
                for k in 0..n {
                    let clock = if with_clocks { clocks[k] } else { done };
                    let expected = burn_attribute(temperature[k], state[k], clock, &m);
                    assert_eq!(
                        out[k].map(f32::to_bits),
                        expected.map(f32::to_bits),
                        "{n} particles, clocks {with_clocks}, particle {k}"
                    );
                }
            }
        }
    }
}
