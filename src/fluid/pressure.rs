//! The pressure solve that makes the air incompressible: conjugate gradients preconditioned
//! by a geometric multigrid V-cycle (McAdams, Sifakis & Teran 2010, "A parallel multigrid
//! Poisson solver for fluids simulation on large grids").
//!
//! The system is the 7-point Laplacian over the air cells, scaled to whole numbers: row `i`
//! is `n_i φ_i − Σ φ_j`, where the sum runs over air neighbours and `n_i` counts the faces
//! through which air can flow (air neighbours, plus open walls where `φ = 0`; solid cells
//! and closed walls add nothing). Jacobi would need O(n²) sweeps on a grid n cells a side;
//! a multigrid-preconditioned CG needs a handful of iterations whatever the size.
//!
//! The V-cycle is symmetric (red-black Gauss-Seidel before, black-red after, restriction
//! proportional to the transpose of the piecewise-constant prolongation), so CG stays CG.
//!
//! Each level lives in a padded layout (`Padded`): a layer of ghost cells round the box, so
//! every cell's six neighbours are in memory and the sweeps, residuals and products are one
//! loop over the level, eight cells at a time (compiled for AVX where the CPU has it, with the
//! same result to the bit), with no test per cell: ghost and solid cells hold zero, so summing
//! all six neighbours sums the air ones.

use super::grid::GridShape;
use super::reduce::max_abs;
use crate::sim::parallel::for_each_part;
use bevy::reflect::Reflect;
use bevy::tasks::TaskPool;

/// What lies beyond one face of the box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
pub enum Wall {
    /// Open air: pressure is ambient there and air flows through freely.
    #[default]
    Open,
    /// A wall: no air flows through it.
    Closed,
}

/// The six walls of the box: `walls[axis][0]` at the minimum side, `[1]` at the maximum.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
pub struct Walls(pub [[Wall; 2]; 3]);

impl Walls {
    /// Every side open.
    pub const OPEN: Self = Self([[Wall::Open; 2]; 3]);
    /// Every side closed: a sealed room.
    pub const CLOSED: Self = Self([[Wall::Closed; 2]; 3]);

    fn any_open(&self) -> bool {
        self.0.iter().flatten().any(|w| *w == Wall::Open)
    }
}

/// How a solve went.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveReport {
    /// CG iterations taken.
    pub iterations: u32,
    /// Largest residual left, in the scaled units of the system.
    pub residual: f32,
}

/// Cells per chunk of the stencil loops: each chunk is one straight loop over `[f32; 8]`
/// arrays that the compiler turns into SIMD.
const LANES: usize = 8;

/// Where a level's cells live in its arrays: each axis padded with a layer of ghost cells on
/// both sides (x and y one more where needed to make the row and layer strides odd), so every
/// real cell has its six neighbours in memory and one loop serves the whole level.
///
/// Ghost and solid cells always hold 0 in the solution and residual, so a real cell's sum
/// over all six neighbours is the sum over its air neighbours: beyond an open wall `φ = 0`,
/// and a closed wall or a solid cell adds nothing (neither counts in `n_i`). With odd strides
/// a cell's colour, `(i + j + k) mod 2`, is its index's parity plus one, so a red-black
/// half-sweep updates every other lane of each chunk.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Padded {
    /// Real cells along x, y and z.
    dims: [usize; 3],
    /// Stride from a cell to the one above it in y (odd).
    row: usize,
    /// Stride from a cell to the one above it in z (odd).
    layer: usize,
    /// The chunks the loops run over, `start..end`: every real cell, starting at an even
    /// index, a whole number of chunks long.
    start: usize,
    end: usize,
    /// Allocated length: every index a loop reads, `end - 1 + layer` included.
    len: usize,
}

impl Padded {
    fn new(dims: [usize; 3]) -> Self {
        // n + 2 rounded up to an odd number.
        let odd = |n: usize| (n + 2) | 1;
        let (row, rows) = (odd(dims[0]), odd(dims[1]));
        let layer = row * rows;
        let mut shape = Self {
            dims,
            row,
            layer,
            ..Self::default()
        };
        let first = shape.index([0, 0, 0]);
        let last = shape.index([dims[0] - 1, dims[1] - 1, dims[2] - 1]);
        shape.start = first & !1;
        shape.end = shape.start + (last + 1 - shape.start).div_ceil(LANES) * LANES;
        shape.len = (layer * (dims[2] + 2)).max(shape.end + layer);
        shape
    }

    /// The index of real cell `[i, j, k]`.
    #[inline(always)]
    fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        (i + 1) + self.row * (j + 1) + self.layer * (k + 1)
    }

    /// Number of real cells.
    fn cells(&self) -> usize {
        self.dims.iter().product()
    }

    /// The index of the first cell of real row `(j, k)`.
    #[inline(always)]
    fn row_start(&self, j: usize, k: usize) -> usize {
        self.index([0, j, k])
    }

    /// A field over this level, every value `value`.
    fn field(&self, value: f32) -> Vec<f32> {
        vec![value; self.len]
    }

    /// Copies a field of real cells in natural order (`i + nx (j + ny k)`) into `padded`.
    fn scatter(&self, natural: &[f32], padded: &mut [f32]) {
        let [nx, ny, nz] = self.dims;
        for k in 0..nz {
            for j in 0..ny {
                let (from, to) = (nx * (j + ny * k), self.row_start(j, k));
                padded[to..to + nx].copy_from_slice(&natural[from..from + nx]);
            }
        }
    }

    /// Copies the real cells of `padded` into a field in natural order.
    fn gather(&self, padded: &[f32], natural: &mut [f32]) {
        let [nx, ny, nz] = self.dims;
        for k in 0..nz {
            for j in 0..ny {
                let (from, to) = (self.row_start(j, k), nx * (j + ny * k));
                natural[to..to + nx].copy_from_slice(&padded[from..from + nx]);
            }
        }
    }
}

/// `f` lane by lane.
#[inline(always)]
fn zip(a: [f32; LANES], b: [f32; LANES], f: impl Fn(f32, f32) -> f32) -> [f32; LANES] {
    core::array::from_fn(|l| f(a[l], b[l]))
}

/// The `n` values of `v` from `from` as chunks of `LANES` (`n` a whole number of chunks).
#[inline(always)]
fn chunks<T>(v: &[T], from: usize, n: usize) -> &[[T; LANES]] {
    v[from..from + n].as_chunks::<LANES>().0
}

/// A run of cells of a field and the runs of their six neighbours, as chunks: chunk `c` of
/// `west` holds the −x neighbours of chunk `c` of `here`, and so on. Reading them chunk by
/// chunk needs no bounds test per value, so the loops vectorise.
struct Around<'a, T> {
    here: &'a [[T; LANES]],
    west: &'a [[T; LANES]],
    east: &'a [[T; LANES]],
    south: &'a [[T; LANES]],
    north: &'a [[T; LANES]],
    below: &'a [[T; LANES]],
    above: &'a [[T; LANES]],
}

impl<'a, T> Around<'a, T> {
    /// The `n` cells of `x` (a field over `shape`) from `from`, and their neighbours.
    #[inline(always)]
    fn new(x: &'a [T], shape: &Padded, from: usize, n: usize) -> Self {
        let (row, layer) = (shape.row, shape.layer);
        Self {
            here: chunks(x, from, n),
            west: chunks(x, from - 1, n),
            east: chunks(x, from + 1, n),
            south: chunks(x, from - row, n),
            north: chunks(x, from + row, n),
            below: chunks(x, from - layer, n),
            above: chunks(x, from + layer, n),
        }
    }

    /// `Σ x_j` over the six neighbours of each cell of chunk `c` (−x, +x, −y, +y, −z, +z, in
    /// that order), reading each value with `get`.
    #[inline(always)]
    fn sums(&self, c: usize, get: impl Fn(&T) -> f32) -> [f32; LANES] {
        let load =
            |chunk: &[T; LANES]| -> [f32; LANES] { core::array::from_fn(|l| get(&chunk[l])) };
        let add = |a: f32, b: f32| a + b;
        let sum = zip(load(&self.west[c]), load(&self.east[c]), add);
        let sum = zip(sum, load(&self.south[c]), add);
        let sum = zip(sum, load(&self.north[c]), add);
        let sum = zip(sum, load(&self.below[c]), add);
        zip(sum, load(&self.above[c]), add)
    }
}

/// A loop over a level: writes the values of the `out.len()` cells from `from` (even, a
/// whole number of chunks). Implementations are inlined into the loop, so the loop compiled
/// for AVX ([`wide`]) computes them with AVX too.
trait Stencil: Sync {
    fn write(&self, from: usize, out: &mut [f32]);
}

/// `value` where `n > 0` (air), else zero.
#[inline(always)]
fn on_air(n: [f32; LANES], value: [f32; LANES]) -> [f32; LANES] {
    zip(n, value, |n, value| if n > 0.0 { value } else { 0.0 })
}

/// `A x`, or with `b`, `b − A x`; zero on solid and ghost cells.
struct Apply<'a> {
    shape: &'a Padded,
    diag: &'a [f32],
    x: &'a [f32],
    b: Option<&'a [f32]>,
}

impl Stencil for Apply<'_> {
    #[inline(always)]
    fn write(&self, from: usize, out: &mut [f32]) {
        let n = out.len();
        let out = out.as_chunks_mut::<LANES>().0;
        let x = Around::new(self.x, self.shape, from, n);
        let diag = chunks(self.diag, from, n);
        // Each loop's `black_box` exit keeps the compiler from vectorising across chunks
        // (gathering each lane from eight places, hundreds of inserts a chunk), so it
        // vectorises within one. (Written out, not through a closure, which it would not
        // inline into the AVX copy.)
        match self.b {
            None => {
                for c in 0..out.len() {
                    out[c] = on_air(diag[c], product(&x, diag, c));
                    if core::hint::black_box(false) {
                        break;
                    }
                }
            }
            Some(b) => {
                let b = chunks(b, from, n);
                for c in 0..out.len() {
                    let ax = product(&x, diag, c);
                    out[c] = on_air(diag[c], zip(b[c], ax, |b, ax| b - ax));
                    if core::hint::black_box(false) {
                        break;
                    }
                }
            }
        }
    }
}

/// `(A x)` at chunk `c` (before solid and ghost cells are zeroed): `n x − Σ x_j`.
#[inline(always)]
fn product(x: &Around<f32>, diag: &[[f32; LANES]], c: usize) -> [f32; LANES] {
    let dx = zip(diag[c], x.here[c], |d, x| d * x);
    zip(dx, x.sums(c, |v| *v), |dx, sum| dx - sum)
}

/// One Gauss-Seidel update of the cells of one colour, read from `x` as it was before the
/// half-sweep: lanes set in `mask` (every other one, see [`lane_mask`]) take `(b + Σ x_j) / n`,
/// the others keep their value. [`relax_in_place`] is the same on one thread.
struct Relax<'a> {
    shape: &'a Padded,
    inverse: &'a [f32],
    b: &'a [f32],
    x: &'a [f32],
    mask: [u32; LANES],
}

impl Stencil for Relax<'_> {
    #[inline(always)]
    fn write(&self, from: usize, out: &mut [f32]) {
        let n = out.len();
        let out = out.as_chunks_mut::<LANES>().0;
        let x = Around::new(self.x, self.shape, from, n);
        let (b, inverse) = (chunks(self.b, from, n), chunks(self.inverse, from, n));
        for c in 0..out.len() {
            let new = relaxed(b[c], x.sums(c, |v| *v), inverse[c]);
            out[c] = blend(self.mask, new, x.here[c]);
            if core::hint::black_box(false) {
                break;
            }
        }
    }
}

/// `(b + Σ x_j) / n`, as `1 / n` times.
#[inline(always)]
fn relaxed(b: [f32; LANES], sums: [f32; LANES], inverse: [f32; LANES]) -> [f32; LANES] {
    zip(zip(b, sums, |b, sum| b + sum), inverse, |v, inverse| {
        v * inverse
    })
}

/// `new` in the lanes set in `mask`, `old` in the others.
#[inline(always)]
fn blend(mask: [u32; LANES], new: [f32; LANES], old: [f32; LANES]) -> [f32; LANES] {
    core::array::from_fn(|l| {
        f32::from_bits((new[l].to_bits() & mask[l]) | (old[l].to_bits() & !mask[l]))
    })
}

/// The lanes a half-sweep of `colour` updates: those of the lane parity its cells have (a
/// real cell `(i, j, k)` sits at padded `(i + 1, j + 1, k + 1)`, and with odd strides an
/// index's parity is that sum's). Passed through [`core::hint::black_box`]: the compiler then
/// computes every lane in one instruction and blends, where knowing the mask it computed the
/// half it keeps one lane at a time.
fn lane_mask(colour: usize) -> [u32; LANES] {
    let parity = (colour + 1) % 2;
    core::hint::black_box(core::array::from_fn(|l| {
        if l % 2 == parity { u32::MAX } else { 0 }
    }))
}

/// A red-black half-sweep of the lanes in `mask` over the whole level, in place: [`Relax`]
/// with `x` read and written through [`Cell`](core::cell::Cell)s, so a store through one
/// view is seen by the others in program order. Each chunk is stored only after the next
/// one's neighbours are loaded: a load overlapping a store just made waits for it. (In place
/// is right because a cell reads only the other colour, which the half-sweep leaves alone.)
#[inline(always)]
fn relax_in_place(shape: &Padded, inverse: &[f32], b: &[f32], x: &mut [f32], mask: [u32; LANES]) {
    use core::cell::Cell;
    let (from, n) = (shape.start, shape.end - shape.start);
    let x = Around::new(Cell::from_mut(x).as_slice_of_cells(), shape, from, n);
    let (b, inverse) = (chunks(b, from, n), chunks(inverse, from, n));
    let store = |at: usize, values: [f32; LANES]| {
        for (cell, value) in x.here[at].iter().zip(values) {
            cell.set(value);
        }
    };
    let mut pending: Option<(usize, [f32; LANES])> = None;
    for c in 0..x.here.len() {
        let new = relaxed(b[c], x.sums(c, Cell::get), inverse[c]);
        let values = blend(mask, new, x.here[c].each_ref().map(Cell::get));
        if let Some((at, done)) = pending {
            store(at, done);
        }
        pending = Some((c, values));
    }
    if let Some((at, done)) = pending {
        store(at, done);
    }
}

/// The loops compiled for AVX, used where the CPU has it (checked at run time): eight lanes
/// in one instruction instead of two. Only AVX, no fused multiply-add, so the result is the
/// same to the bit as the baseline loops.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod wide {
    use super::{LANES, Padded, Stencil, relax_in_place};

    pub(super) use crate::sim::simd::avx_available as available;

    /// [`Stencil::write`] for AVX. Only called when [`available`].
    pub(super) fn write<S: Stencil>(stencil: &S, from: usize, out: &mut [f32]) {
        // SAFETY: called only after `available()` found AVX on this CPU.
        unsafe { write_avx(stencil, from, out) }
    }

    /// [`relax_in_place`] for AVX. Only called when [`available`].
    pub(super) fn relax(
        shape: &Padded,
        inverse: &[f32],
        b: &[f32],
        x: &mut [f32],
        mask: [u32; LANES],
    ) {
        // SAFETY: called only after `available()` found AVX on this CPU.
        unsafe { relax_avx(shape, inverse, b, x, mask) }
    }

    #[target_feature(enable = "avx")]
    fn write_avx<S: Stencil>(stencil: &S, from: usize, out: &mut [f32]) {
        stencil.write(from, out);
    }

    #[target_feature(enable = "avx")]
    fn relax_avx(shape: &Padded, inverse: &[f32], b: &[f32], x: &mut [f32], mask: [u32; LANES]) {
        relax_in_place(shape, inverse, b, x, mask);
    }
}

/// [`Stencil::write`], compiled for AVX where the CPU has it.
fn write_fast<S: Stencil>(stencil: &S, from: usize, out: &mut [f32]) {
    #[cfg(target_arch = "x86_64")]
    if wide::available() {
        return wide::write(stencil, from, out);
    }
    stencil.write(from, out);
}

/// [`relax_in_place`], compiled for AVX where the CPU has it.
fn relax_in_place_fast(
    shape: &Padded,
    inverse: &[f32],
    b: &[f32],
    x: &mut [f32],
    mask: [u32; LANES],
) {
    #[cfg(target_arch = "x86_64")]
    if wide::available() {
        return wide::relax(shape, inverse, b, x, mask);
    }
    relax_in_place(shape, inverse, b, x, mask);
}

/// One level of the multigrid hierarchy; every field but `air` in the padded layout.
#[derive(Clone, Debug, Default)]
struct Level {
    shape: Padded,
    /// Whether each cell holds air (coarse cells: any child does), in natural order.
    air: Vec<bool>,
    /// `n_i`; zero for solid and ghost cells.
    diag: Vec<f32>,
    /// `1 / n_i`; zero for solid and ghost cells, so a sweep leaves them at zero.
    inverse: Vec<f32>,
    /// Right-hand side, solution and residual of this level's correction equation.
    b: Vec<f32>,
    x: Vec<f32>,
    r: Vec<f32>,
    /// Where a half-sweep split over threads writes the new `x` (then swapped in).
    next: Vec<f32>,
}

/// Cells per parallel part of a level's loops (a whole number of chunks).
const CELLS_PER_PART: usize = 4096;
/// Levels with fewer cells than this run on the calling thread: below it a loop is too
/// short to pay for handing work to the pool. On the 2-core machine (`stress -- --plume-only`,
/// builds alternated) the split was slower at 40³ (3.7–4.9 against 3.1–3.8 ms a step) and
/// 48³ (7.0–7.9 against 5.9–6.6) and even at 64³ (about 16 ms either way): each half-sweep
/// is a few tens of microseconds, and waking the pool's threads costs as much.
const PARALLEL_CELLS: usize = 200_000;

/// The pool a loop over a level of `cells` cells runs on: none below [`PARALLEL_CELLS`] or
/// without feature `parallel`.
fn level_pool(pool: Option<&TaskPool>, cells: usize) -> Option<&TaskPool> {
    pool.filter(|_| cells >= PARALLEL_CELLS && cfg!(feature = "parallel"))
}

/// Writes `stencil`'s values of `shape`'s span into `out`, in parts over `pool`. Each part
/// writes only its own cells, so the result is the same on any number of threads.
fn for_each_chunk<S: Stencil>(
    shape: &Padded,
    out: &mut [f32],
    pool: Option<&TaskPool>,
    stencil: &S,
) {
    let (start, end) = (shape.start, shape.end);
    let pool = level_pool(pool, shape.cells());
    if pool.is_none() {
        return write_fast(stencil, start, &mut out[start..end]);
    }
    let parts = out[start..end].chunks_mut(CELLS_PER_PART).enumerate();
    for_each_part(pool, parts, |(part, out)| {
        write_fast(stencil, start + part * CELLS_PER_PART, out);
    });
}

/// Where air flows from cell `c` (natural order, an air cell of a level of `dims` whose air
/// cells are `air`): `n_c`, the faces it flows through (open walls and air neighbours), and
/// its air neighbours in the order −x, +x, −y, +y, −z, +z (`None` beyond the box or solid).
fn air_faces(dims: [usize; 3], air: &[bool], walls: &Walls, c: usize) -> (f32, [Option<usize>; 6]) {
    let stride = [1, dims[0], dims[0] * dims[1]];
    let at = [
        c % dims[0],
        (c / dims[0]) % dims[1],
        c / (dims[0] * dims[1]),
    ];
    let mut faces = 0.0;
    let mut neighbours = [None; 6];
    for axis in 0..3 {
        for side in 0..2 {
            let inside = if side == 0 {
                at[axis] > 0
            } else {
                at[axis] + 1 < dims[axis]
            };
            if !inside {
                if walls.0[axis][side] == Wall::Open {
                    faces += 1.0;
                }
                continue;
            }
            let neighbour = if side == 0 {
                c - stride[axis]
            } else {
                c + stride[axis]
            };
            if air[neighbour] {
                faces += 1.0;
                neighbours[2 * axis + side] = Some(neighbour);
            }
        }
    }
    (faces, neighbours)
}

impl Level {
    fn new(dims: [usize; 3], air: Vec<bool>, walls: &Walls) -> Self {
        let shape = Padded::new(dims);
        let mut diag = shape.field(0.0);
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let c = i + dims[0] * (j + dims[1] * k);
                    if air[c] {
                        diag[shape.index([i, j, k])] = air_faces(dims, &air, walls, c).0;
                    }
                }
            }
        }
        let inverse = diag
            .iter()
            .map(|&n| if n > 0.0 { 1.0 / n } else { 0.0 })
            .collect();
        Self {
            shape,
            air,
            diag,
            inverse,
            b: shape.field(0.0),
            x: shape.field(0.0),
            r: shape.field(0.0),
            next: shape.field(0.0),
        }
    }

    /// `y = A x` (zero on solid and ghost cells).
    fn apply(&self, x: &[f32], y: &mut [f32], pool: Option<&TaskPool>) {
        for_each_chunk(&self.shape, y, pool, &self.operator(x));
    }

    /// The operator `A` applied to `x`, as a loop.
    fn operator<'a>(&'a self, x: &'a [f32]) -> Apply<'a> {
        Apply {
            shape: &self.shape,
            diag: &self.diag,
            x,
            b: None,
        }
    }

    /// `r = b − A x` (zero on solid and ghost cells).
    fn residual(&mut self, pool: Option<&TaskPool>) {
        let mut r = core::mem::take(&mut self.r);
        let residual = Apply {
            b: Some(&self.b),
            ..self.operator(&self.x)
        };
        for_each_chunk(&self.shape, &mut r, pool, &residual);
        self.r = r;
    }

    /// One Gauss-Seidel half-sweep over the cells of one colour (`(i + j + k) % 2 ==
    /// colour`). A cell reads only neighbours of the other colour, which this half-sweep does
    /// not change: on one thread it updates in place; split over threads every part reads the
    /// `x` from before the half-sweep and writes `next`, with the same result.
    fn relax(&mut self, colour: usize, pool: Option<&TaskPool>) {
        let mask = lane_mask(colour);
        if level_pool(pool, self.shape.cells()).is_none() {
            relax_in_place_fast(&self.shape, &self.inverse, &self.b, &mut self.x, mask);
            return;
        }
        let relax = Relax {
            shape: &self.shape,
            inverse: &self.inverse,
            b: &self.b,
            x: &self.x,
            mask,
        };
        for_each_chunk(&self.shape, &mut self.next, pool, &relax);
        core::mem::swap(&mut self.x, &mut self.next);
    }

    /// The first half-sweep from `x = 0`: with every neighbour zero, a cell of `colour`
    /// takes `b / n` (the same to the bit as [`Level::relax`] on zeros), the rest stay zero.
    fn relax_from_zero(&mut self, colour: usize) {
        let Self {
            shape,
            inverse,
            b,
            x,
            ..
        } = self;
        x.fill(0.0);
        let parity = (colour + 1) % 2;
        let (from, n) = (shape.start, shape.end - shape.start);
        let (b, inverse) = (chunks(b, from, n), chunks(inverse, from, n));
        let x = x[from..from + n].as_chunks_mut::<LANES>().0;
        for ((x, b), inverse) in x.iter_mut().zip(b).zip(inverse) {
            for l in (parity..LANES).step_by(2) {
                x[l] = (b[l] + 0.0) * inverse[l];
            }
        }
    }
}

/// The dims of the level below one of `dims`.
fn coarser(dims: [usize; 3]) -> [usize; 3] {
    dims.map(|n| n.div_ceil(2))
}

/// A Poisson solver for one grid shape and set of solid cells; rebuilt when either changes,
/// reused (with its last solution as the first guess) every step otherwise.
#[derive(Clone, Debug, Default)]
pub struct PressureSolver {
    levels: Vec<Level>,
    singular: bool,
    /// The latest solution, one entry per cell in the grid's order (the first guess of the
    /// next solve).
    pub solution: Vec<f32>,
    /// The CG vectors, in the finest level's padded layout: solution, right-hand side,
    /// residual, preconditioned residual, search direction and its image.
    x: Vec<f32>,
    b: Vec<f32>,
    r: Vec<f32>,
    z: Vec<f32>,
    p: Vec<f32>,
    ap: Vec<f32>,
}

/// Gauss-Seidel sweeps before and after the coarse correction, and on the coarsest level.
const SMOOTHING_SWEEPS: usize = 2;
const COARSEST_SWEEPS: usize = 16;
/// The hierarchy stops when a level would have fewer cells than this along an axis.
const COARSEST_SIDE: usize = 4;

impl PressureSolver {
    /// A solver for `shape` where `solid[c]` marks cells no air flows through.
    pub fn new(shape: &GridShape, solid: &[bool], walls: Walls) -> Self {
        let mut dims = shape.dims;
        let mut air: Vec<bool> = solid.iter().map(|s| !s).collect();
        let mut levels = Vec::new();
        loop {
            let level = Level::new(dims, air, &walls);
            let next = coarser(dims);
            let stop = dims.iter().any(|&n| n / 2 < COARSEST_SIDE) || next == dims;
            let fine_air = level.air.clone();
            levels.push(level);
            if stop {
                break;
            }
            let mut coarse_air = vec![false; next[0] * next[1] * next[2]];
            for k in 0..dims[2] {
                for j in 0..dims[1] {
                    for i in 0..dims[0] {
                        if fine_air[i + dims[0] * (j + dims[1] * k)] {
                            coarse_air[i / 2 + next[0] * (j / 2 + next[1] * (k / 2))] = true;
                        }
                    }
                }
            }
            air = coarse_air;
            dims = next;
        }
        let field = levels[0].shape.field(0.0);
        Self {
            levels,
            singular: !walls.any_open(),
            solution: vec![0.0; shape.cells()],
            x: field.clone(),
            b: field.clone(),
            r: field.clone(),
            z: field.clone(),
            p: field.clone(),
            ap: field,
        }
    }

    /// Number of multigrid levels.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Solves `A φ = b` from the previous solution, until the largest residual is at most
    /// `tolerance` or after `max_iterations` CG iterations. The result is in
    /// [`PressureSolver::solution`]. `b` must have one entry per cell (entries of solid
    /// cells are ignored).
    pub fn solve(&mut self, b: &[f32], tolerance: f32, max_iterations: u32) -> SolveReport {
        self.solve_on(b, tolerance, max_iterations, None)
    }

    /// [`PressureSolver::solve`], the loops of levels of 200 000 cells or more split over
    /// `pool`'s threads (the result is the same on any number of threads).
    pub fn solve_on(
        &mut self,
        b: &[f32],
        tolerance: f32,
        max_iterations: u32,
        pool: Option<&TaskPool>,
    ) -> SolveReport {
        assert_eq!(
            b.len(),
            self.solution.len(),
            "one right-hand side entry per cell"
        );
        let fine = &self.levels[0];
        let shape = fine.shape;
        shape.scatter(&self.solution, &mut self.x);
        shape.scatter(b, &mut self.b);
        for ((x, b), n) in self.x.iter_mut().zip(&mut self.b).zip(&fine.diag) {
            if *n == 0.0 || !x.is_finite() {
                *x = 0.0;
            }
            if *n == 0.0 {
                *b = 0.0;
            }
        }
        let residual = Apply {
            b: Some(&self.b),
            ..fine.operator(&self.x)
        };
        for_each_chunk(&shape, &mut self.r, pool, &residual);
        if self.singular {
            remove_mean(&mut self.r, &fine.diag);
        }
        let mut residual = max_abs(&self.r);
        let mut iterations = 0;
        if residual > tolerance {
            self.precondition(pool);
            let mut rz = dot(&self.r, &self.z);
            // p = z (z is written afresh by the next preconditioning).
            core::mem::swap(&mut self.p, &mut self.z);
            while iterations < max_iterations {
                iterations += 1;
                self.levels[0].apply(&self.p, &mut self.ap, pool);
                let pap = dot(&self.p, &self.ap);
                if pap.is_nan() || pap <= 0.0 {
                    break;
                }
                let alpha = (rz / pap) as f32;
                residual = step_along(alpha, [&mut self.x, &mut self.r], [&self.p, &self.ap]);
                if residual <= tolerance {
                    break;
                }
                self.precondition(pool);
                let rz_next = dot(&self.r, &self.z);
                let beta = (rz_next / rz) as f32;
                rz = rz_next;
                for (p, z) in self.p.iter_mut().zip(&self.z) {
                    *p = z + beta * *p;
                }
            }
        }
        shape.gather(&self.x, &mut self.solution);
        SolveReport {
            iterations,
            residual,
        }
    }

    /// `z = M⁻¹ r`: one V-cycle from zero.
    fn precondition(&mut self, pool: Option<&TaskPool>) {
        // The finest level's right-hand side is `r` and its solution `z`: swapped in and out
        // (the V-cycle only reads its `b`, and starts its `x` from zero), not copied.
        core::mem::swap(&mut self.levels[0].b, &mut self.r);
        v_cycle(&mut self.levels, pool);
        core::mem::swap(&mut self.levels[0].b, &mut self.r);
        core::mem::swap(&mut self.levels[0].x, &mut self.z);
        if self.singular {
            remove_mean(&mut self.z, &self.levels[0].diag);
        }
    }
}

/// One V-cycle on `levels[0]` (its `b` in, its `x` out, starting from zero), recursing on
/// the coarser levels.
fn v_cycle(levels: &mut [Level], pool: Option<&TaskPool>) {
    let (level, coarser) = levels.split_first_mut().expect("a V-cycle needs a level");
    level.relax_from_zero(0);
    level.relax(1, pool);
    if coarser.is_empty() {
        for _ in 1..COARSEST_SWEEPS {
            level.relax(0, pool);
            level.relax(1, pool);
        }
        for _ in 0..COARSEST_SWEEPS {
            level.relax(1, pool);
            level.relax(0, pool);
        }
        return;
    }
    for _ in 1..SMOOTHING_SWEEPS {
        level.relax(0, pool);
        level.relax(1, pool);
    }
    level.residual(pool);
    restrict(level, &mut coarser[0]);
    v_cycle(coarser, pool);
    prolong_add(&coarser[0], level);
    for _ in 0..SMOOTHING_SWEEPS {
        level.relax(1, pool);
        level.relax(0, pool);
    }
}

/// Calls `visit(fine row start, coarse row start)` for every real row of a fine level, with
/// the start of the coarse row its cells' parents lie in (cell `i` of the fine row has
/// parent `i / 2` of the coarse one).
fn for_each_row_pair(fine: &Padded, coarse: &Padded, mut visit: impl FnMut(usize, usize)) {
    let [_, ny, nz] = fine.dims;
    for k in 0..nz {
        for j in 0..ny {
            visit(fine.row_start(j, k), coarse.row_start(j / 2, k / 2));
        }
    }
}

/// The coarse right-hand side: half the sum of the children's residuals (the residual's
/// average, scaled by the coarse cell's four-times-larger area per volume).
fn restrict(fine: &Level, coarse: &mut Level) {
    coarse.b.fill(0.0);
    let nx = fine.shape.dims[0];
    for_each_row_pair(&fine.shape, &coarse.shape, |f, c| {
        let (pairs, last) = fine.r[f..f + nx].as_chunks::<2>();
        let b = &mut coarse.b[c..c + nx.div_ceil(2)];
        for (b, [r0, r1]) in b.iter_mut().zip(pairs) {
            *b += 0.5 * (r0 + r1);
        }
        if let [r] = last {
            b[nx / 2] += 0.5 * r;
        }
    });
}

/// Adds each coarse cell's correction to its air children.
fn prolong_add(coarse: &Level, fine: &mut Level) {
    let nx = fine.shape.dims[0];
    let Level { shape, diag, x, .. } = fine;
    for_each_row_pair(shape, &coarse.shape, |f, c| {
        let parents = &coarse.x[c..c + nx.div_ceil(2)];
        let (x, n) = (&mut x[f..f + nx], &diag[f..f + nx]);
        for (i, (x, n)) in x.iter_mut().zip(n).enumerate() {
            if *n > 0.0 {
                *x += parents[i / 2];
            }
        }
    });
}

/// CG's step: `x += α p` and `r −= α A p` in one pass; returns the largest `|r|` after.
fn step_along(alpha: f32, [x, r]: [&mut [f32]; 2], [p, ap]: [&[f32]; 2]) -> f32 {
    let n = x.len();
    let (x, r, p, ap) = (&mut x[..n], &mut r[..n], &p[..n], &ap[..n]);
    for i in 0..n {
        x[i] += alpha * p[i];
        r[i] -= alpha * ap[i];
    }
    max_abs(r)
}

/// `Σ a b` in f64, summed in `LANES` running sums (a fixed order, so the same result
/// whatever the machine; the loop vectorises).
fn dot(a: &[f32], b: &[f32]) -> f64 {
    let mut sums = [0.0f64; LANES];
    let (a_chunks, b_chunks) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let (a_rest, b_rest) = (a_chunks.remainder(), b_chunks.remainder());
    for (a, b) in a_chunks.zip(b_chunks) {
        for l in 0..LANES {
            sums[l] += f64::from(a[l]) * f64::from(b[l]);
        }
    }
    for (l, (a, b)) in a_rest.iter().zip(b_rest).enumerate() {
        sums[l] += f64::from(*a) * f64::from(*b);
    }
    sums.iter().sum()
}

/// Subtracts the mean over the air cells (`n > 0`) from those cells (a sealed box's pressure
/// is defined up to a constant; its right-hand side must sum to zero).
fn remove_mean(v: &mut [f32], n: &[f32]) {
    let (sum, count) = v
        .iter()
        .zip(n)
        .filter(|(_, n)| **n > 0.0)
        .fold((0.0f64, 0usize), |(s, n), (x, _)| {
            (s + f64::from(*x), n + 1)
        });
    if count == 0 {
        return;
    }
    let mean = (sum / count as f64) as f32;
    for (x, n) in v.iter_mut().zip(n) {
        if *n > 0.0 {
            *x -= mean;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn shape(n: usize) -> GridShape {
        GridShape {
            dims: [n, n, n],
            cell: 0.1,
            origin: Vec3::ZERO,
        }
    }

    /// Values with structure at every scale, one per cell of `dims` in natural order.
    fn values(dims: [usize; 3], seed: usize) -> Vec<f32> {
        (0..dims.iter().product())
            .map(|c| (((c + seed) * 7919) % 101) as f32 / 37.0 - 1.3)
            .collect()
    }

    /// A level of odd sizes with a solid block (cells with and without solid neighbours) and
    /// one closed wall, `x` and `b` set from [`values`] (`x` zero in solid cells, as every
    /// loop keeps it).
    fn level_with_a_block(dims: [usize; 3]) -> (Level, Walls) {
        let n = dims.iter().product();
        let air: Vec<bool> = (0..n)
            .map(|c| {
                let (i, j, k) = (
                    c % dims[0],
                    (c / dims[0]) % dims[1],
                    c / (dims[0] * dims[1]),
                );
                !((4..7).contains(&i) && (3..5).contains(&j) && (2..6).contains(&k))
            })
            .collect();
        let mut walls = Walls::OPEN;
        walls.0[1][0] = Wall::Closed;
        let mut level = Level::new(dims, air, &walls);
        let shape = level.shape;
        let x: Vec<f32> = values(dims, 1)
            .iter()
            .zip(&level.air)
            .map(|(x, air)| if *air { *x } else { 0.0 })
            .collect();
        shape.scatter(&x, &mut level.x);
        shape.scatter(&values(dims, 2), &mut level.b);
        (level, walls)
    }

    /// The textbook stencil, cell by cell in natural order: `(n_c, Σ x_j)` over the air
    /// neighbours of air cell `c`, `n_c` counting open walls too.
    fn stencil(dims: [usize; 3], air: &[bool], walls: &Walls, x: &[f32], c: usize) -> (f32, f32) {
        let (n, neighbours) = air_faces(dims, air, walls, c);
        let mut sum = 0.0f32;
        for neighbour in neighbours {
            sum += neighbour.map_or(0.0, |j| x[j]);
        }
        (n, sum)
    }

    fn bits(x: &[f32]) -> Vec<u32> {
        x.iter().map(|v| v.to_bits()).collect()
    }

    /// The shortcut for a V-cycle level's first half-sweep gives what a sweep from zero
    /// gives, to the bit, for both colours, with solid cells about.
    #[test]
    fn the_first_half_sweep_from_zero_is_the_sweep_on_zeros() {
        let dims = [9, 8, 7];
        let n = dims.iter().product::<usize>();
        let air: Vec<bool> = (0..n).map(|c| c % 5 != 3).collect();
        let mut level = Level::new(dims, air, &Walls::OPEN);
        let shape = level.shape;
        shape.scatter(&values(dims, 0), &mut level.b);
        for colour in 0..2 {
            let mut swept = level.clone();
            swept.x.fill(0.0);
            swept.relax(colour, None);
            let mut shortcut = level.clone();
            shortcut.x.fill(7.0);
            shortcut.relax_from_zero(colour);
            assert_eq!(bits(&swept.x), bits(&shortcut.x), "colour {colour}");
        }
    }

    #[test]
    fn the_chunked_loops_equal_the_cell_by_cell_stencil_to_the_bit() {
        // Each loop over the padded layout (eight cells at a time, every neighbour read
        // without a test) must give exactly what the plain per-cell stencil over the air
        // neighbours gives, next to solid cells and a closed wall, on odd sizes.
        let dims = [13, 9, 8];
        let (mut level, walls) = level_with_a_block(dims);
        assert!(level.air.iter().any(|a| !a), "a solid block");
        let n: usize = dims.iter().product();
        let shape = level.shape;
        let natural = |padded: &[f32]| {
            let mut out = vec![0.0; n];
            shape.gather(padded, &mut out);
            out
        };
        let (x, b) = (natural(&level.x), natural(&level.b));
        let air = level.air.clone();
        // y = A x
        let mut y = level.shape.field(0.0);
        level.apply(&level.x, &mut y, None);
        let y = natural(&y);
        // Solid cells hold zero (of either sign: a masked product), air cells the stencil's
        // value to the bit.
        let same = |got: f32, expected: Option<f32>| match expected {
            Some(expected) => got.to_bits() == expected.to_bits(),
            None => got == 0.0,
        };
        for c in 0..n {
            let (diag, sum) = stencil(dims, &air, &walls, &x, c);
            let expected = air[c].then(|| diag * x[c] - sum);
            assert!(
                same(y[c], expected),
                "apply, cell {c}: {} {expected:?}",
                y[c]
            );
        }
        // r = b − A x
        level.residual(None);
        let r = natural(&level.r);
        for c in 0..n {
            let (diag, sum) = stencil(dims, &air, &walls, &x, c);
            let expected = air[c].then(|| b[c] - (diag * x[c] - sum));
            assert!(
                same(r[c], expected),
                "residual, cell {c}: {} {expected:?}",
                r[c]
            );
        }
        // A half-sweep of each colour, against the cell-by-cell Gauss-Seidel.
        let mut expected = x.clone();
        for colour in [0, 1] {
            for c in 0..n {
                let [i, j, k] = [
                    c % dims[0],
                    (c / dims[0]) % dims[1],
                    c / (dims[0] * dims[1]),
                ];
                if (i + j + k) % 2 == colour && air[c] {
                    let (diag, sum) = stencil(dims, &air, &walls, &expected, c);
                    expected[c] = (b[c] + sum) * (1.0 / diag);
                }
            }
            level.relax(colour, None);
            let got = natural(&level.x);
            for c in 0..n {
                let expected = air[c].then_some(expected[c]);
                assert!(same(got[c], expected), "relax {colour}, cell {c}");
            }
        }
        // Ghost and solid cells stayed zero.
        for (p, (x, n)) in level.x.iter().zip(&level.diag).enumerate() {
            if *n == 0.0 {
                assert_eq!(*x, 0.0, "padded cell {p}");
            }
        }
    }

    /// A level big enough to split over threads sweeps, applies and takes residuals with the
    /// same bits on a pool as on one thread.
    #[test]
    fn a_level_split_over_threads_gives_the_serial_result() {
        let dims = [61, 59, 57];
        assert!(dims.iter().product::<usize>() >= PARALLEL_CELLS);
        let pool = TaskPool::new();
        let (serial, _) = level_with_a_block(dims);
        let mut threaded = serial.clone();
        let mut serial = serial;
        for colour in [0, 1, 1, 0] {
            serial.relax(colour, None);
            threaded.relax(colour, Some(&pool));
        }
        assert_eq!(bits(&serial.x), bits(&threaded.x));
        serial.residual(None);
        threaded.residual(Some(&pool));
        assert_eq!(bits(&serial.r), bits(&threaded.r));
    }

    /// A right-hand side with structure at every scale.
    fn rhs(n: usize) -> Vec<f32> {
        values([n; 3], 0)
    }

    /// The largest `|b − A φ|` over the air cells, by the textbook stencil.
    fn residual_of(solver: &PressureSolver, b: &[f32], walls: &Walls) -> f32 {
        let level = &solver.levels[0];
        let dims = level.shape.dims;
        (0..b.len())
            .filter(|&c| level.air[c])
            .map(|c| {
                let (diag, sum) = stencil(dims, &level.air, walls, &solver.solution, c);
                (b[c] - (diag * solver.solution[c] - sum)).abs()
            })
            .fold(0.0, f32::max)
    }

    #[test]
    fn solves_the_open_box_poisson_problem_in_few_iterations() {
        let n = 32;
        let shape = shape(n);
        let mut solver = PressureSolver::new(&shape, &vec![false; shape.cells()], Walls::OPEN);
        assert!(solver.level_count() >= 3);
        let b = rhs(n);
        let report = solver.solve(&b, 1e-4, 100);
        assert!(report.residual <= 1e-4, "{report:?}");
        assert!(
            report.iterations <= 20,
            "multigrid-preconditioned CG: {report:?}"
        );
        // The residual it reports is the true one.
        assert!(residual_of(&solver, &b, &Walls::OPEN) <= 2e-4);
    }

    #[test]
    fn solid_cells_and_closed_walls_are_respected() {
        let n = 16;
        let shape = shape(n);
        let mut solid = vec![false; shape.cells()];
        // A solid slab across the lower quarter, with a hole.
        for k in 0..n {
            for i in 0..n {
                if !(6..9).contains(&i) {
                    solid[shape.index(i, 4, k)] = true;
                }
            }
        }
        let mut walls = Walls::OPEN;
        walls.0[1][0] = Wall::Closed;
        let mut solver = PressureSolver::new(&shape, &solid, walls);
        let b = rhs(n);
        let report = solver.solve(&b, 1e-4, 200);
        assert!(report.residual <= 1e-4, "{report:?}");
        assert!(residual_of(&solver, &b, &walls) <= 2e-4);
        for (c, s) in solid.iter().enumerate() {
            if *s {
                assert_eq!(solver.solution[c], 0.0);
            }
        }
    }

    #[test]
    fn a_sealed_box_with_a_balanced_source_converges() {
        let n = 16;
        let shape = shape(n);
        let mut solver = PressureSolver::new(&shape, &vec![false; shape.cells()], Walls::CLOSED);
        let mut b = rhs(n);
        let mean = b.iter().map(|v| f64::from(*v)).sum::<f64>() / b.len() as f64;
        b.iter_mut().for_each(|v| *v -= mean as f32);
        let report = solver.solve(&b, 1e-3, 200);
        assert!(report.residual <= 1e-3, "{report:?}");
        assert!(residual_of(&solver, &b, &Walls::CLOSED) <= 2e-3);
    }

    #[test]
    fn warm_start_from_the_solution_takes_no_iterations() {
        let n = 16;
        let shape = shape(n);
        let mut solver = PressureSolver::new(&shape, &vec![false; shape.cells()], Walls::OPEN);
        let b = rhs(n);
        solver.solve(&b, 1e-4, 100);
        let again = solver.solve(&b, 1e-4, 100);
        assert_eq!(again.iterations, 0);
    }

    /// Sizes that are odd, unequal and down to the smallest allowed solve too (the padded
    /// layout's strides and chunk ends).
    #[test]
    fn odd_and_small_boxes_solve() {
        for dims in [[4, 4, 4], [5, 9, 4], [17, 6, 11], [33, 8, 9]] {
            let shape = GridShape {
                dims,
                cell: 0.1,
                origin: Vec3::ZERO,
            };
            let mut solver = PressureSolver::new(&shape, &vec![false; shape.cells()], Walls::OPEN);
            let b = values(dims, 3);
            let report = solver.solve(&b, 1e-4, 100);
            assert!(report.residual <= 1e-4, "{dims:?}: {report:?}");
            assert!(residual_of(&solver, &b, &Walls::OPEN) <= 2e-4, "{dims:?}");
        }
    }
}
