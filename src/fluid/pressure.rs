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

use super::grid::GridShape;
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

/// One level of the multigrid hierarchy.
#[derive(Clone, Debug, Default)]
struct Level {
    dims: [usize; 3],
    /// Whether each cell holds air (coarse cells: any child does).
    air: Vec<bool>,
    /// `n_i`; zero for solid cells.
    diag: Vec<f32>,
    /// Coupling to the +x, +y, +z neighbour: 1 when both cells hold air, else 0.
    couple: [Vec<f32>; 3],
    /// Right-hand side and solution of this level's correction equation.
    b: Vec<f32>,
    x: Vec<f32>,
    r: Vec<f32>,
    /// `x` as it was before the current half-sweep (the neighbours it reads).
    frozen: Vec<f32>,
    /// One row's updated values (both colours) before this colour's are copied into `x`.
    row_values: Vec<f32>,
    /// Per row `(j, k)` (index `j + ny k`): whether the row is interior ([`is_interior_row`])
    /// and every coupling of its interior cells is 1 (no solid cell among them or their
    /// neighbours), so its sums need no coupling factors.
    all_air_rows: Vec<bool>,
}

/// Layers of cells per parallel part of a sweep.
const LAYERS_PER_PART: usize = 2;
/// Levels with fewer cells than this sweep on the calling thread: below it a half-sweep is
/// too short to pay for handing work to the pool (measured with the stress example: at 32³
/// the split gained nothing, at 48³ it saves a fifth of a step).
const PARALLEL_CELLS: usize = 50_000;

/// The pool a sweep over a level of `cells` cells runs on: none below [`PARALLEL_CELLS`] or
/// without feature `parallel` (the sweep then runs on the calling thread).
fn sweep_pool(pool: Option<&TaskPool>, cells: usize) -> Option<&TaskPool> {
    pool.filter(|_| cells >= PARALLEL_CELLS && cfg!(feature = "parallel"))
}

/// `Σ c_ij x_j` over the neighbours of cell `c` at `at` of a level of `dims` with
/// couplings `couple`.
#[inline(always)]
fn neighbour_sum(
    dims: [usize; 3],
    couple: &[Vec<f32>; 3],
    x: &[f32],
    c: usize,
    at: [usize; 3],
) -> f32 {
    let stride = [1, dims[0], dims[0] * dims[1]];
    let mut sum = 0.0;
    for axis in 0..3 {
        if at[axis] > 0 {
            sum += couple[axis][c - stride[axis]] * x[c - stride[axis]];
        }
        if at[axis] + 1 < dims[axis] {
            sum += couple[axis][c] * x[c + stride[axis]];
        }
    }
    sum
}

/// Whether row `(j, k)` of a level of `dims` lies inside the level (not on its y or z faces)
/// and is long enough to have interior cells: its cells `1..nx − 1` have all six neighbours.
#[inline(always)]
fn is_interior_row(dims: [usize; 3], j: usize, k: usize) -> bool {
    let [nx, ny, nz] = dims;
    nx > 2 && j > 0 && j + 1 < ny && k > 0 && k + 1 < nz
}

/// Calls `visit(i, Σ c_ij x_j)` for the interior cells `i = 1 .. nx − 1` of the interior row
/// that starts at cell `first` ([`is_interior_row`]; `all_air`: every coupling the row's
/// cells have is 1, see [`Level::all_air_rows`]), each sum taken in the order
/// [`neighbour_sum`] takes it (so the result is the same to the bit), as one straight loop over
/// slices that the compiler turns into SIMD.
#[inline(always)]
fn interior_sums(
    dims: [usize; 3],
    couple: &[Vec<f32>; 3],
    all_air: bool,
    x: &[f32],
    first: usize,
    mut visit: impl FnMut(usize, f32),
) {
    let [nx, ny, _] = dims;
    let (sy, sz) = (nx, nx * ny);
    let (c0, n) = (first + 1, nx - 2);
    fn run(v: &[f32], at: usize, n: usize) -> &[f32] {
        &v[at..at + n]
    }
    let (xm, xp) = (run(x, c0 - 1, n), run(x, c0 + 1, n));
    let (ym, yp) = (run(x, c0 - sy, n), run(x, c0 + sy, n));
    let (zm, zp) = (run(x, c0 - sz, n), run(x, c0 + sz, n));
    let (cxm, cxp) = (run(&couple[0], c0 - 1, n), run(&couple[0], c0, n));
    let (cym, cyp) = (run(&couple[1], c0 - sy, n), run(&couple[1], c0, n));
    let (czm, czp) = (run(&couple[2], c0 - sz, n), run(&couple[2], c0, n));
    if all_air {
        // Every coupling is 1, and `1 · x` is `x` exactly.
        for i in 0..n {
            let mut sum = 0.0;
            sum += xm[i];
            sum += xp[i];
            sum += ym[i];
            sum += yp[i];
            sum += zm[i];
            sum += zp[i];
            visit(i + 1, sum);
        }
        return;
    }
    for i in 0..n {
        let mut sum = 0.0;
        sum += cxm[i] * xm[i];
        sum += cxp[i] * xp[i];
        sum += cym[i] * ym[i];
        sum += cyp[i] * yp[i];
        sum += czm[i] * zm[i];
        sum += czp[i] * zp[i];
        visit(i + 1, sum);
    }
}

/// One Gauss-Seidel update of cell `c` at `at`, in place (a solid cell is left alone).
#[inline(always)]
fn relax_cell(
    dims: [usize; 3],
    couple: &[Vec<f32>; 3],
    b: &[f32],
    diag: &[f32],
    x: &mut [f32],
    c: usize,
    at: [usize; 3],
) {
    if diag[c] > 0.0 {
        let sum = neighbour_sum(dims, couple, x, c, at);
        x[c] = (b[c] + sum) / diag[c];
    }
}

/// Calls `visit(first cell, j, k, row)` for every row of `out` (a field over a level of
/// `dims`), rows along x; layers of rows run in parallel on `pool`. Each call writes only
/// its own row, so the result does not depend on the number of threads.
fn for_each_row(
    dims: [usize; 3],
    out: &mut [f32],
    pool: Option<&TaskPool>,
    visit: impl Fn(usize, usize, usize, &mut [f32]) + Sync,
) {
    let [nx, ny, _] = dims;
    let layer = nx * ny;
    let pool = sweep_pool(pool, out.len());
    let parts = out.chunks_mut(layer * LAYERS_PER_PART).enumerate();
    for_each_part(pool, parts, |(part, out)| {
        let k0 = part * LAYERS_PER_PART;
        for (row, values) in out.chunks_mut(nx).enumerate() {
            let (j, k) = (row % ny, k0 + row / ny);
            visit(nx * (j + ny * k), j, k, values);
        }
    });
}

impl Level {
    fn new(dims: [usize; 3], air: Vec<bool>, walls: &Walls) -> Self {
        let n = dims[0] * dims[1] * dims[2];
        let stride = [1, dims[0], dims[0] * dims[1]];
        let mut diag = vec![0.0; n];
        let mut couple = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let c = i + dims[0] * (j + dims[1] * k);
                    if !air[c] {
                        continue;
                    }
                    let at = [i, j, k];
                    for axis in 0..3 {
                        for side in 0..2 {
                            let inside = if side == 0 {
                                at[axis] > 0
                            } else {
                                at[axis] + 1 < dims[axis]
                            };
                            if !inside {
                                if walls.0[axis][side] == Wall::Open {
                                    diag[c] += 1.0;
                                }
                                continue;
                            }
                            let neighbour = if side == 0 {
                                c - stride[axis]
                            } else {
                                c + stride[axis]
                            };
                            if air[neighbour] {
                                diag[c] += 1.0;
                                if side == 1 {
                                    couple[axis][c] = 1.0;
                                }
                            }
                        }
                    }
                }
            }
        }
        let [nx, ny, nz] = dims;
        let all_air_rows = (0..ny * nz)
            .map(|row| {
                let (j, k) = (row % ny, row / ny);
                if !is_interior_row(dims, j, k) {
                    return false;
                }
                let c0 = nx * row + 1;
                let ones = |axis: usize, from: usize, to: usize| {
                    couple[axis][from..to].iter().all(|&c| c == 1.0)
                };
                ones(0, c0 - 1, c0 + nx - 2)
                    && ones(1, c0 - stride[1], c0 - stride[1] + nx - 2)
                    && ones(1, c0, c0 + nx - 2)
                    && ones(2, c0 - stride[2], c0 - stride[2] + nx - 2)
                    && ones(2, c0, c0 + nx - 2)
            })
            .collect();
        Self {
            dims,
            air,
            diag,
            couple,
            all_air_rows,
            b: vec![0.0; n],
            x: vec![0.0; n],
            r: vec![0.0; n],
            frozen: vec![0.0; n],
            row_values: vec![0.0; dims[0]],
        }
    }

    /// `y = A x`.
    fn apply(&self, x: &[f32], y: &mut [f32], pool: Option<&TaskPool>) {
        self.operator().rows(x, y, pool, |_, ax| ax);
    }

    /// The operator's coefficients, borrowed apart from the level's vectors.
    fn operator(&self) -> Operator<'_> {
        Operator {
            dims: self.dims,
            diag: &self.diag,
            couple: &self.couple,
            all_air_rows: &self.all_air_rows,
        }
    }

    /// One Gauss-Seidel sweep over the cells of one colour (`(i + j + k) % 2 == colour`).
    /// A cell reads only neighbours of the other colour, which this sweep does not change:
    /// it reads them from a copy, so rows can run in parallel with the serial result.
    fn relax(&mut self, colour: usize, pool: Option<&TaskPool>) {
        let Self {
            dims,
            diag,
            couple,
            b,
            x,
            frozen,
            row_values,
            all_air_rows: all_air,
            ..
        } = self;
        let dims = *dims;
        if sweep_pool(pool, x.len()).is_none() {
            // On this thread: in place, as a cell's neighbours are of the other colour.
            // Interior rows: every cell's update from the unchanged other colour into
            // `row_values` in one SIMD loop, then this colour's cells copied in.
            let [nx, ny, nz] = dims;
            for k in 0..nz {
                for j in 0..ny {
                    let first = nx * (j + ny * k);
                    let start = (colour + j + k) % 2;
                    if !is_interior_row(dims, j, k) {
                        for i in (start..nx).step_by(2) {
                            relax_cell(dims, couple, b, diag, x, first + i, [i, j, k]);
                        }
                        continue;
                    }
                    let (bs, ds) = (&b[first..first + nx], &diag[first..first + nx]);
                    interior_sums(
                        dims,
                        couple,
                        all_air[j + dims[1] * k],
                        x,
                        first,
                        |i, sum| {
                            row_values[i] = (bs[i] + sum) / ds[i];
                        },
                    );
                    for i in (start..nx).step_by(2) {
                        let c = first + i;
                        if i == 0 || i + 1 == nx {
                            relax_cell(dims, couple, b, diag, x, c, [i, j, k]);
                        } else if diag[c] > 0.0 {
                            x[c] = row_values[i];
                        }
                    }
                }
            }
            return;
        }
        frozen.copy_from_slice(x);
        let frozen = &*frozen;
        for_each_row(dims, x, pool, |first, j, k, row| {
            for i in ((colour + j + k) % 2..row.len()).step_by(2) {
                let c = first + i;
                if diag[c] > 0.0 {
                    let sum = neighbour_sum(dims, couple, frozen, c, [i, j, k]);
                    row[i] = (b[c] + sum) / diag[c];
                }
            }
        });
    }

    /// The first half-sweep from `x = 0`: with every neighbour zero, a cell of `colour`
    /// takes `b / n` (the same to the bit as [`Level::relax`] on zeros), the rest stay zero.
    fn relax_from_zero(&mut self, colour: usize) {
        let [nx, ny, nz] = self.dims;
        let (b, diag, x) = (&self.b, &self.diag, &mut self.x);
        x.fill(0.0);
        for k in 0..nz {
            for j in 0..ny {
                let first = nx * (j + ny * k);
                for i in ((colour + j + k) % 2..nx).step_by(2) {
                    let c = first + i;
                    if diag[c] > 0.0 {
                        x[c] = (b[c] + 0.0) / diag[c];
                    }
                }
            }
        }
    }

    /// `r = b − A x`.
    fn residual(&mut self, pool: Option<&TaskPool>) {
        let operator = Operator {
            dims: self.dims,
            diag: &self.diag,
            couple: &self.couple,
            all_air_rows: &self.all_air_rows,
        };
        let b = &self.b;
        operator.rows(&self.x, &mut self.r, pool, |c, ax| b[c] - ax);
    }
}

/// A level's operator `A`: what [`Level::apply`] and [`Level::residual`] share.
struct Operator<'a> {
    dims: [usize; 3],
    diag: &'a [f32],
    couple: &'a [Vec<f32>; 3],
    all_air_rows: &'a [bool],
}

impl Operator<'_> {
    /// Writes `finish(c, (A x)_c)` into `out` for every air cell `c` and zero for solid
    /// ones, row by row (rows in parallel on `pool`); the interior rows' products in one SIMD
    /// loop ([`interior_sums`]), the same to the bit as the cell-by-cell stencil.
    fn rows(
        &self,
        x: &[f32],
        out: &mut [f32],
        pool: Option<&TaskPool>,
        finish: impl Fn(usize, f32) -> f32 + Sync,
    ) {
        let Self {
            dims,
            diag,
            couple,
            all_air_rows,
        } = *self;
        let cell = |c: usize, at: [usize; 3]| {
            if diag[c] > 0.0 {
                finish(c, diag[c] * x[c] - neighbour_sum(dims, couple, x, c, at))
            } else {
                0.0
            }
        };
        for_each_row(dims, out, pool, |first, j, k, row| {
            if !is_interior_row(dims, j, k) {
                for (i, out) in row.iter_mut().enumerate() {
                    *out = cell(first + i, [i, j, k]);
                }
                return;
            }
            let n = row.len();
            let (ds, xs) = (&diag[first..first + n], &x[first..first + n]);
            let all_air = all_air_rows[j + dims[1] * k];
            interior_sums(dims, couple, all_air, x, first, |i, sum| {
                let value = finish(first + i, ds[i] * xs[i] - sum);
                row[i] = if ds[i] > 0.0 { value } else { 0.0 };
            });
            row[0] = cell(first, [0, j, k]);
            row[n - 1] = cell(first + n - 1, [n - 1, j, k]);
        });
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
    /// The latest solution (the first guess of the next solve).
    pub solution: Vec<f32>,
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
        let n = shape.cells();
        Self {
            levels,
            singular: !walls.any_open(),
            solution: vec![0.0; n],
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            ap: vec![0.0; n],
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

    /// [`PressureSolver::solve`], its multigrid sweeps split over `pool`'s threads (the
    /// result is the same on any number of threads).
    pub fn solve_on(
        &mut self,
        b: &[f32],
        tolerance: f32,
        max_iterations: u32,
        pool: Option<&TaskPool>,
    ) -> SolveReport {
        let n = self.solution.len();
        assert_eq!(b.len(), n, "one right-hand side entry per cell");
        let fine = &self.levels[0];
        for c in 0..n {
            if fine.diag[c] == 0.0 || !self.solution[c].is_finite() {
                self.solution[c] = 0.0;
            }
        }
        fine.apply(&self.solution, &mut self.ap, pool);
        for (((r, b), ap), diag) in self.r.iter_mut().zip(b).zip(&self.ap).zip(&fine.diag) {
            *r = if *diag > 0.0 { b - ap } else { 0.0 };
        }
        if self.singular {
            remove_mean(&mut self.r, &fine.diag);
        }
        let mut residual = max_abs(&self.r);
        if residual <= tolerance {
            return SolveReport {
                iterations: 0,
                residual,
            };
        }
        self.precondition(pool);
        self.p.copy_from_slice(&self.z);
        let mut rz = dot(&self.r, &self.z);
        let mut iterations = 0;
        while iterations < max_iterations {
            iterations += 1;
            self.levels[0].apply(&self.p, &mut self.ap, pool);
            let pap = dot(&self.p, &self.ap);
            if pap.is_nan() || pap <= 0.0 {
                break;
            }
            let alpha = (rz / pap) as f32;
            for c in 0..n {
                self.solution[c] += alpha * self.p[c];
                self.r[c] -= alpha * self.ap[c];
            }
            residual = max_abs(&self.r);
            if residual <= tolerance {
                break;
            }
            self.precondition(pool);
            let rz_next = dot(&self.r, &self.z);
            let beta = (rz_next / rz) as f32;
            rz = rz_next;
            for c in 0..n {
                self.p[c] = self.z[c] + beta * self.p[c];
            }
        }
        SolveReport {
            iterations,
            residual,
        }
    }

    /// `z = M⁻¹ r`: one V-cycle from zero.
    fn precondition(&mut self, pool: Option<&TaskPool>) {
        self.levels[0].b.copy_from_slice(&self.r);
        v_cycle(&mut self.levels, pool);
        self.z.copy_from_slice(&self.levels[0].x);
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

/// Calls `visit(fine cell, its parent cell)` for every cell of a level of `fine` dims whose
/// coarser level has `coarse` dims.
fn for_each_child(fine: [usize; 3], coarse: [usize; 3], mut visit: impl FnMut(usize, usize)) {
    let [nx, ny, nz] = fine;
    let [cx, cy, _] = coarse;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                visit(i + nx * (j + ny * k), i / 2 + cx * (j / 2 + cy * (k / 2)));
            }
        }
    }
}

/// The coarse right-hand side: half the sum of the children's residuals (the residual's
/// average, scaled by the coarse cell's four-times-larger area per volume).
fn restrict(fine: &Level, coarse: &mut Level) {
    coarse.b.fill(0.0);
    for_each_child(fine.dims, coarse.dims, |child, parent| {
        coarse.b[parent] += 0.5 * fine.r[child];
    });
}

/// Adds each coarse cell's correction to its air children.
fn prolong_add(coarse: &Level, fine: &mut Level) {
    let Level { diag, x, dims, .. } = fine;
    for_each_child(*dims, coarse.dims, |child, parent| {
        if diag[child] > 0.0 {
            x[child] += coarse.x[parent];
        }
    });
}

fn dot(a: &[f32], b: &[f32]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| f64::from(*x) * f64::from(*y))
        .sum()
}

fn max_abs(a: &[f32]) -> f32 {
    a.iter().fold(0.0f32, |m, x| m.max(x.abs()))
}

/// Subtracts the mean over the air cells (a sealed box's pressure is defined up to a
/// constant; its right-hand side must sum to zero).
fn remove_mean(v: &mut [f32], diag: &[f32]) {
    let (sum, count) = v
        .iter()
        .zip(diag)
        .filter(|(_, d)| **d > 0.0)
        .fold((0.0f64, 0usize), |(s, n), (x, _)| {
            (s + f64::from(*x), n + 1)
        });
    if count == 0 {
        return;
    }
    let mean = (sum / count as f64) as f32;
    for (x, d) in v.iter_mut().zip(diag) {
        if *d > 0.0 {
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

    /// The shortcut for a V-cycle level's first half-sweep gives what a sweep from zero
    /// gives, to the bit, for both colours, with solid cells about.
    #[test]
    fn the_first_half_sweep_from_zero_is_the_sweep_on_zeros() {
        let dims = [9, 8, 7];
        let n = dims.iter().product::<usize>();
        let air: Vec<bool> = (0..n).map(|c| c % 5 != 3).collect();
        let mut level = Level::new(dims, air, &Walls::OPEN);
        for (c, b) in level.b.iter_mut().enumerate() {
            *b = ((c * 7919) % 101) as f32 / 50.0 - 1.0;
        }
        for colour in 0..2 {
            let mut swept = level.clone();
            swept.x.fill(0.0);
            swept.relax(colour, None);
            let mut shortcut = level.clone();
            shortcut.x.fill(7.0);
            shortcut.relax_from_zero(colour);
            let bits = |x: &[f32]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&swept.x), bits(&shortcut.x), "colour {colour}");
        }
    }

    /// A right-hand side with structure at every scale.
    fn rhs(n: usize) -> Vec<f32> {
        (0..n * n * n)
            .map(|c| ((c * 7919) % 101) as f32 / 50.0 - 1.0)
            .collect()
    }

    fn residual_of(solver: &PressureSolver, b: &[f32]) -> f32 {
        let mut ax = vec![0.0; b.len()];
        solver.levels[0].apply(&solver.solution, &mut ax, None);
        b.iter()
            .zip(&ax)
            .zip(&solver.levels[0].diag)
            .filter(|(_, d)| **d > 0.0)
            .fold(0.0f32, |m, ((b, ax), _)| m.max((b - ax).abs()))
    }

    #[test]
    fn the_row_sweeps_equal_the_cell_by_cell_stencil_to_the_bit() {
        // A box with a solid block (rows with and without solid neighbours), one closed wall,
        // odd sizes; x and b with structure at every scale. Each row-wise loop (SIMD on the
        // interior rows) must give exactly what the plain per-cell stencil gives.
        let dims = [13, 9, 8];
        let n = dims[0] * dims[1] * dims[2];
        let air: Vec<bool> = (0..n)
            .map(|c| {
                let (i, j, k) = (c % 13, (c / 13) % 9, c / (13 * 9));
                !((4..7).contains(&i) && (3..5).contains(&j) && (2..6).contains(&k))
            })
            .collect();
        let mut walls = Walls::OPEN;
        walls.0[1][0] = Wall::Closed;
        let mut level = Level::new(dims, air, &walls);
        assert!(
            level.all_air_rows.iter().any(|&a| a),
            "some rows are all air"
        );
        let interior = (0..dims[1] * dims[2])
            .filter(|&row| is_interior_row(dims, row % dims[1], row / dims[1]))
            .count();
        assert!(
            level.all_air_rows.iter().filter(|&&a| a).count() < interior,
            "some interior rows touch the block"
        );
        let values = |seed: usize| -> Vec<f32> {
            (0..n)
                .map(|c| (((c + seed) * 7919) % 101) as f32 / 37.0 - 1.3)
                .collect()
        };
        level.x = values(1);
        level.b = values(2);
        let at = |c: usize| {
            [
                c % dims[0],
                (c / dims[0]) % dims[1],
                c / (dims[0] * dims[1]),
            ]
        };
        let sum =
            |level: &Level, x: &[f32], c: usize| neighbour_sum(dims, &level.couple, x, c, at(c));
        // y = A x
        let mut y = vec![0.0; n];
        level.apply(&level.x, &mut y, None);
        for (c, y) in y.iter().enumerate() {
            let expected = if level.diag[c] > 0.0 {
                level.diag[c] * level.x[c] - sum(&level, &level.x, c)
            } else {
                0.0
            };
            assert_eq!(y.to_bits(), expected.to_bits(), "apply, cell {c}");
        }
        // r = b − A x
        level.residual(None);
        for c in 0..n {
            let expected = if level.diag[c] > 0.0 {
                level.b[c] - (level.diag[c] * level.x[c] - sum(&level, &level.x, c))
            } else {
                0.0
            };
            assert_eq!(
                level.r[c].to_bits(),
                expected.to_bits(),
                "residual, cell {c}"
            );
        }
        // A half-sweep of each colour, against the cell-by-cell Gauss-Seidel.
        for colour in [0, 1] {
            let mut expected = level.x.clone();
            for c in 0..n {
                let [i, j, k] = at(c);
                if (i + j + k) % 2 == colour && level.diag[c] > 0.0 {
                    expected[c] = (level.b[c] + sum(&level, &expected, c)) / level.diag[c];
                }
            }
            level.relax(colour, None);
            for (c, (x, expected)) in level.x.iter().zip(&expected).enumerate() {
                assert_eq!(x.to_bits(), expected.to_bits(), "relax {colour}, cell {c}");
            }
        }
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
        assert!(residual_of(&solver, &b) <= 2e-4);
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
        let ones = vec![1.0; b.len()];
        remove_mean(&mut b, &ones);
        let report = solver.solve(&b, 1e-3, 200);
        assert!(report.residual <= 1e-3, "{report:?}");
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
}
