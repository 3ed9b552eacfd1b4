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

/// The velocity at each cell centre (the mean of its two faces per axis), m/s: a row of
/// cells at a time, in loops over slices that the compiler turns into SIMD.
pub fn centre_velocity(shape: &GridShape, velocity: &[Vec<f32>; 3], centre: &mut [Vec<f32>; 3]) {
    let [nx, ny, nz] = shape.dims;
    for k in 0..nz {
        for j in 0..ny {
            let c = nx * (j + ny * k);
            let rows = shape.face_rows(velocity, j, k);
            for ((low, high), out) in rows.into_iter().zip(centre.iter_mut()) {
                let out = &mut out[c..c + nx];
                for i in 0..nx {
                    out[i] = 0.5 * (low[i] + high[i]);
                }
            }
        }
    }
}

/// Where air may come from, in a field's sample coordinates: per axis the lowest and highest
/// coordinate inside the box (a thousandth of a cell spare for round-off), or unbounded on a
/// closed side (no air comes in there; the nearest value inside is taken).
#[derive(Clone, Copy)]
struct Inside {
    low: Vec3,
    high: Vec3,
}

impl Inside {
    /// The bounds for a field staggered by `stagger` in a box of `shape` with `walls`.
    fn new(shape: &GridShape, walls: &Walls, stagger: Stagger) -> Self {
        let margin = 1e-3;
        let bound = |axis: usize, side: usize| match (walls.0[axis][side], side) {
            (Wall::Closed, 0) => f32::NEG_INFINITY,
            (Wall::Closed, _) => f32::INFINITY,
            (Wall::Open, 0) => -margin - stagger.0[axis],
            (Wall::Open, _) => shape.dims[axis] as f32 + margin - stagger.0[axis],
        };
        Self {
            low: Vec3::from(core::array::from_fn::<f32, 3, _>(|a| bound(a, 0))),
            high: Vec3::from(core::array::from_fn::<f32, 3, _>(|a| bound(a, 1))),
        }
    }

    /// Whether air found at `g` came from inside the box: false beyond an open wall.
    #[inline(always)]
    fn contains(&self, g: Vec3) -> bool {
        g.cmpge(self.low).all() && g.cmple(self.high).all()
    }
}

/// The centre velocities at `g` (in cell-centre sample coordinates), m/s.
#[inline(always)]
fn velocity_at(shape: &GridShape, centre: &[Vec<f32>; 3], g: Vec3) -> Vec3 {
    let stencil = GridShape::stencil_at_sample(g, shape.dims);
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

/// One field's advection, run beside the others by [`Advection::fields`].
enum Field<'a> {
    /// Temperature and smoke, into these.
    Scalars([&'a mut [f32]; 2]),
    /// The velocity component normal to the faces of an axis, into this.
    Faces(usize, &'a mut [f32]),
}

/// Layers of cells (or faces) per parallel part.
const LAYERS_PER_PART: usize = 2;

/// Active cells below which advection runs on the calling thread: handing a layer to the
/// pool costs a thread's wake-up, and on the 2-core machine a 32³ plume (6 000 active cells,
/// about 0.4 ms of advection) ran no faster split over three threads than on one.
pub const PARALLEL_ACTIVE_CELLS: usize = 50_000;

impl Advection<'_> {
    /// The pool to split this advection over: none below [`PARALLEL_ACTIVE_CELLS`].
    fn pool<'p>(&self, pool: Option<&'p TaskPool>) -> Option<&'p TaskPool> {
        pool.filter(|_| self.active.active_cells() >= PARALLEL_ACTIVE_CELLS)
    }

    /// Advects the cell-centred temperature and smoke `from` into `to`, less their
    /// [`Decay`] (solid cells hold zero, and so do cells outside the active spans), tracing
    /// back along a midpoint (RK2) path. With [`PARALLEL_ACTIVE_CELLS`] or more active cells,
    /// layers of cells run in parallel on `pool`; each value depends only on `from`, so the
    /// result is the same on any number of threads.
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
        // Traced in cell-centre sample coordinates: a velocity times `scale` is cells per step.
        let scale = self.dt / shape.cell;
        let wind = self.wind * scale;
        let inside = Inside::new(shape, self.walls, Stagger::CENTRE);
        let [cx, cy, cz] = self.centre;
        let pool = self.pool(pool);
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
                let first = nx * (j + ny * k);
                for i in span {
                    let c = first + i;
                    if solid[c] {
                        continue;
                    }
                    // Midpoint (second-order Runge-Kutta) trace back.
                    let here = Vec3::new(i as f32, j as f32, k as f32);
                    let u = Vec3::new(cx[c], cy[c], cz[c]);
                    let midpoint = here - 0.5 * (u * scale + wind);
                    let departure =
                        here - (velocity_at(shape, self.centre, midpoint) * scale + wind);
                    if !inside.contains(departure) {
                        continue;
                    }
                    let stencil = GridShape::stencil_at_sample(departure, shape.dims);
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
    /// parallel on `pool` as in [`Advection::scalars`].
    pub fn velocity(&self, from: &[Vec<f32>; 3], to: &mut [Vec<f32>; 3], pool: Option<&TaskPool>) {
        for (axis, out) in to.iter_mut().enumerate() {
            self.faces(axis, &from[axis], out, pool);
        }
    }

    /// Advects the scalars ([`Advection::scalars`]) and the velocity
    /// ([`Advection::velocity`]) of one step. Below [`PARALLEL_ACTIVE_CELLS`] active cells
    /// the four fields' advections (the scalars, then each velocity component) run beside
    /// one another on `pool`, each on one thread; at or above it each is split into layers
    /// of cells. Every value depends only on the `from` fields, so the result is the same on
    /// any number of threads.
    pub fn fields(
        &self,
        solid: &[bool],
        scalars: ([&[f32]; 2], [&mut [f32]; 2]),
        velocity: (&[Vec<f32>; 3], &mut [Vec<f32>; 3]),
        pool: Option<&TaskPool>,
    ) {
        let ((scalars, next_scalars), (velocity, next_velocity)) = (scalars, velocity);
        if self.pool(pool).is_some() {
            self.scalars(solid, scalars, next_scalars, pool);
            self.velocity(velocity, next_velocity, pool);
            return;
        }
        let [u, v, w] = next_velocity;
        let fields = [
            Field::Scalars(next_scalars),
            Field::Faces(0, u),
            Field::Faces(1, v),
            Field::Faces(2, w),
        ];
        for_each_part(pool, fields.into_iter(), |field| match field {
            Field::Scalars(to) => self.scalars(solid, scalars, to, None),
            Field::Faces(axis, to) => self.faces(axis, &velocity[axis], to, None),
        });
    }

    /// Advects the velocity component `axis` (on the faces normal to it) from `source` into
    /// `out`, as [`Advection::velocity`] does for each.
    fn faces(&self, axis: usize, source: &[f32], out: &mut [f32], pool: Option<&TaskPool>) {
        let shape = self.shape;
        let centre = self.centre;
        let cell_velocity = |c: usize| Vec3::new(centre[0][c], centre[1][c], centre[2][c]);
        // Traced in each face field's sample coordinates: a velocity times `scale` is cells
        // per step.
        let scale = self.dt / shape.cell;
        let wind = self.wind * scale;
        let kept = self.decay.velocity;
        let pool = self.pool(pool);
        let [nx, ny, _] = shape.dims;
        let dims = shape.face_dims(axis);
        let layer = dims[0] * dims[1];
        let stride = [1, nx, nx * ny][axis];
        let inside = Inside::new(shape, self.walls, Stagger::face(axis));
        let parts = out.chunks_mut(layer * LAYERS_PER_PART).enumerate();
        for_each_part(pool, parts, |(part, out)| {
            let k0 = part * LAYERS_PER_PART;
            for (row, out_row) in out.chunks_mut(dims[0]).enumerate() {
                let (j, k) = (row % dims[1], k0 + row / dims[1]);
                let first = dims[0] * (j + dims[1] * k);
                let source_row = &source[first..first + dims[0]];
                for (out, u) in out_row.iter_mut().zip(source_row) {
                    *out = u * kept;
                }
                // Faces with a cell on both sides take their mean directly; those on the
                // box's sides through `face_mean`.
                let row = self.active.face_row(shape, axis, j, k);
                let both = shape.inner_faces(axis, [j, k], row.clone());
                let cells_row = nx * (j + ny * k);
                for i in row {
                    let u = if both.contains(&i) {
                        let above = cells_row + i;
                        (cell_velocity(above - stride) + cell_velocity(above)) * 0.5
                    } else {
                        face_mean(shape.face_cells(axis, [i, j, k]), cell_velocity)
                    };
                    let here = Vec3::new(i as f32, j as f32, k as f32);
                    let departure = here - (u * scale + wind);
                    out_row[i] = if inside.contains(departure) {
                        GridShape::stencil_at_sample(departure, dims).apply(source) * kept
                    } else {
                        0.0
                    };
                }
            }
        });
    }
}
