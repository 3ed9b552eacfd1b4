//! Semi-Lagrangian advection (Stam 1999): each sample takes the value found where the air
//! at it came from, `x − u dt`, by trilinear interpolation. Unconditionally stable for any
//! step; it smooths a little (numerical diffusion) and does not conserve exactly.
//!
//! Scalars trace back along a midpoint (RK2) path, the velocity along one Euler step. Air
//! arriving through an open wall is ambient: it brings no excess temperature, no smoke and no
//! velocity beyond the uniform wind.

use super::active::ActiveSpans;
use super::grid::{GridShape, Stagger, face_mean};
use super::pressure::{Wall, Walls};
use crate::sim::parallel::for_each_part;
use bevy::tasks::TaskPool;
use glam::Vec3;

/// The velocity at each cell centre (the mean of its two faces per axis), m/s.
pub fn centre_velocity(shape: &GridShape, velocity: &[Vec<f32>; 3], centre: &mut [Vec<f32>; 3]) {
    let [nx, ny, nz] = shape.dims;
    for axis in 0..3 {
        let face_dims = shape.face_dims(axis);
        let stride = match axis {
            0 => 1,
            1 => face_dims[0],
            _ => face_dims[0] * face_dims[1],
        };
        let faces = &velocity[axis];
        let out = &mut centre[axis];
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let f = i + face_dims[0] * (j + face_dims[1] * k);
                    out[shape.index(i, j, k)] = 0.5 * (faces[f] + faces[f + stride]);
                }
            }
        }
    }
}

/// Whether air found at `point` came from inside the box: true unless it lies beyond an open
/// wall (a thousandth of a cell spare for round-off). Beyond a closed wall no air comes in, so
/// the nearest value inside is taken.
#[inline]
fn arrives_from_inside(shape: &GridShape, walls: &Walls, point: Vec3) -> bool {
    let margin = 1e-3 * shape.cell;
    let local = point - shape.origin;
    let size = shape.size();
    (0..3).all(|axis| {
        (local[axis] >= -margin || walls.0[axis][0] == Wall::Closed)
            && (local[axis] <= size[axis] + margin || walls.0[axis][1] == Wall::Closed)
    })
}

/// Where the air at `here` was `dt` seconds ago: a midpoint (second-order Runge-Kutta)
/// trace back through the centre velocities plus `wind`.
#[inline]
fn departure(
    shape: &GridShape,
    centre: &[Vec<f32>; 3],
    wind: Vec3,
    here: Vec3,
    u: Vec3,
    dt: f32,
) -> Vec3 {
    let midpoint = here - 0.5 * dt * (u + wind);
    here - dt * (velocity_at(shape, centre, midpoint) + wind)
}

/// The velocity at `point` from the centre velocities, m/s.
#[inline]
fn velocity_at(shape: &GridShape, centre: &[Vec<f32>; 3], point: Vec3) -> Vec3 {
    let stencil = shape.stencil(point, shape.dims, Stagger::CENTRE);
    Vec3::new(
        stencil.apply(&centre[0]),
        stencil.apply(&centre[1]),
        stencil.apply(&centre[2]),
    )
}

/// The advection of one step: the grid, its centre velocities, the wind and walls.
#[derive(Clone, Copy)]
pub struct Advection<'a> {
    /// The grid.
    pub shape: &'a GridShape,
    /// Velocity at the cell centres (relative to the wind), m/s.
    pub centre: &'a [Vec<f32>; 3],
    /// Uniform wind, m/s.
    pub wind: Vec3,
    /// What lies beyond the box's faces.
    pub walls: &'a Walls,
    /// Where the air is busy: outside, scalars become zero and velocities stay.
    pub active: &'a ActiveSpans,
    /// Step, s.
    pub dt: f32,
    /// What the air loses over the step, applied to each advected value as it is written.
    pub decay: Decay,
}

/// What the air loses over one step, as factors on the advected values (1 keeps everything):
/// applying them as advection writes each value saves a pass over the box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decay {
    /// Velocity kept (damping).
    pub velocity: f32,
    /// Excess temperature kept (cooling); the result is clamped to `±hottest`.
    pub temperature: f32,
    /// Smoke kept; the result is never negative.
    pub smoke: f32,
    /// Largest excess temperature, K.
    pub hottest: f32,
}

impl Decay {
    /// Nothing lost.
    pub const NONE: Self = Self {
        velocity: 1.0,
        temperature: 1.0,
        smoke: 1.0,
        hottest: f32::INFINITY,
    };

    #[inline(always)]
    fn temperature(&self, t: f32) -> f32 {
        (t * self.temperature).clamp(-self.hottest, self.hottest)
    }

    #[inline(always)]
    fn smoke(&self, s: f32) -> f32 {
        (s * self.smoke).max(0.0)
    }
}

/// Layers of cells (or faces) per parallel part.
const LAYERS_PER_PART: usize = 2;

impl Advection<'_> {
    /// Advects the cell-centred temperature and smoke `from` into `to`, less their
    /// [`Decay`] (solid cells hold zero, and so do cells outside the active spans), tracing back along a midpoint (RK2)
    /// path. Layers of cells run in parallel on
    /// `pool`; each value depends only on `from`, so the result is the same on any number
    /// of threads.
    pub fn scalars(
        &self,
        solid: &[bool],
        from: [&[f32]; 2],
        to: [&mut [f32]; 2],
        pool: Option<&TaskPool>,
    ) {
        let shape = self.shape;
        let [nx, ny, _] = shape.dims;
        let layer = nx * ny;
        let [temperature, smoke] = to;
        let parts = temperature
            .chunks_mut(layer * LAYERS_PER_PART)
            .zip(smoke.chunks_mut(layer * LAYERS_PER_PART))
            .enumerate();
        for_each_part(pool, parts, |(part, (t_out, s_out))| {
            let k0 = part * LAYERS_PER_PART;
            let rows = t_out.chunks_mut(nx).zip(s_out.chunks_mut(nx));
            for (row, (t_row, s_row)) in rows.enumerate() {
                let (j, k) = (row % ny, k0 + row / ny);
                let span = self.active.row(shape, j, k);
                t_row.fill(0.0);
                s_row.fill(0.0);
                for i in span {
                    let c = shape.index(i, j, k);
                    if solid[c] {
                        continue;
                    }
                    let here = shape.position(i, j, k, Stagger::CENTRE);
                    let u = Vec3::new(self.centre[0][c], self.centre[1][c], self.centre[2][c]);
                    let departure = departure(shape, self.centre, self.wind, here, u, self.dt);
                    if !arrives_from_inside(shape, self.walls, departure) {
                        continue;
                    }
                    let stencil = shape.stencil(departure, shape.dims, Stagger::CENTRE);
                    t_row[i] = self.decay.temperature(stencil.apply(from[0]));
                    s_row[i] = self.decay.smoke(stencil.apply(from[1]));
                }
            }
        });
    }

    /// Advects the staggered velocity `from` into `to` (the air carries its own momentum),
    /// less its [`Decay`].
    /// The trace is a single Euler step back from the face, whose velocity is the mean of its
    /// two cells. Faces that touch no active cell keep their velocity. Layers of faces run in
    /// parallel on `pool`.
    pub fn velocity(&self, from: &[Vec<f32>; 3], to: &mut [Vec<f32>; 3], pool: Option<&TaskPool>) {
        let shape = self.shape;
        let centre = self.centre;
        let cell_velocity = |c: usize| Vec3::new(centre[0][c], centre[1][c], centre[2][c]);
        for (axis, out) in to.iter_mut().enumerate() {
            let dims = shape.face_dims(axis);
            let layer = dims[0] * dims[1];
            let stagger = Stagger::face(axis);
            let source = &from[axis];
            let parts = out.chunks_mut(layer * LAYERS_PER_PART).enumerate();
            for_each_part(pool, parts, |(part, out)| {
                let k0 = part * LAYERS_PER_PART;
                for (row, out_row) in out.chunks_mut(dims[0]).enumerate() {
                    let (j, k) = (row % dims[1], k0 + row / dims[1]);
                    let first = dims[0] * (j + dims[1] * k);
                    let kept = self.decay.velocity;
                    let source_row = &source[first..first + dims[0]];
                    for (out, u) in out_row.iter_mut().zip(source_row) {
                        *out = u * kept;
                    }
                    for i in self.active.face_row(shape, axis, j, k) {
                        let u = face_mean(shape.face_cells(axis, [i, j, k]), cell_velocity);
                        let here = shape.position(i, j, k, stagger);
                        let departure = here - self.dt * (u + self.wind);
                        out_row[i] = if arrives_from_inside(shape, self.walls, departure) {
                            shape.sample(source, dims, stagger, departure) * kept
                        } else {
                            0.0
                        };
                    }
                }
            });
        }
    }
}
