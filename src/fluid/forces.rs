//! Body forces on the air: buoyancy of hot air (and the weight of smoke), and vorticity
//! confinement (Fedkiw, Stam & Jensen 2001), which puts back the swirls that semi-Lagrangian
//! advection smooths away.

use super::active::ActiveSpans;
use super::grid::{GridShape, face_mean};
use glam::Vec3;

/// Adds `impulse (β T − κ s)` to every face, with `T` (excess temperature, K) and `s`
/// (smoke density) the mean of the face's two cells, `[temperature, smoke]` the fields,
/// `[β, κ]` the buoyancy (m/(s²·K)) and smoke weight (m/s²), and `impulse` the step times
/// the unit up vector, s. Temperature and smoke are zero outside `active` (the spans they
/// were advected in), so only the faces touching an active cell are visited.
pub fn add_buoyancy(
    shape: &GridShape,
    active: &ActiveSpans,
    [temperature, smoke]: [&[f32]; 2],
    impulse: Vec3,
    [buoyancy, smoke_weight]: [f32; 2],
    velocity: &mut [Vec<f32>; 3],
) {
    for (axis, faces) in velocity.iter_mut().enumerate() {
        let scale = impulse[axis];
        if scale == 0.0 {
            continue;
        }
        for_each_active_face(shape, active, axis, |face, cells| {
            let lift = |c: usize| buoyancy * temperature[c] - smoke_weight * smoke[c];
            faces[face] += scale * face_mean(cells, lift);
        });
    }
}

/// Scratch for [`add_vorticity_confinement`]: the vorticity, its magnitude and the force,
/// one value per cell.
#[derive(Clone, Debug, Default)]
pub struct VorticityScratch {
    omega: [Vec<f32>; 3],
    magnitude: Vec<f32>,
    force: [Vec<f32>; 3],
}

impl VorticityScratch {
    /// Scratch for `cells` cells.
    pub fn new(cells: usize) -> Self {
        Self {
            omega: core::array::from_fn(|_| vec![0.0; cells]),
            magnitude: vec![0.0; cells],
            force: core::array::from_fn(|_| vec![0.0; cells]),
        }
    }
}

/// Central difference of `field` along `axis` at cell `(i, j, k)`, one-sided at the box's
/// sides, per metre.
#[inline]
fn derivative(shape: &GridShape, field: &[f32], at: [usize; 3], axis: usize) -> f32 {
    let mut lo = at;
    let mut hi = at;
    lo[axis] = at[axis].saturating_sub(1);
    hi[axis] = (at[axis] + 1).min(shape.dims[axis] - 1);
    let span = (hi[axis] - lo[axis]) as f32 * shape.cell;
    if span == 0.0 {
        return 0.0;
    }
    (field[shape.index(hi[0], hi[1], hi[2])] - field[shape.index(lo[0], lo[1], lo[2])]) / span
}

/// Excess temperature above which vorticity confinement acts in full, K: it works in the hot
/// plume and fades out in air that has cooled, so leftover eddies die away.
pub const CONFINEMENT_FULL_AT: f32 = 20.0;

/// Adds `dt × ε h w (N × ω)` to the faces, where `ω` is the curl of the centre velocities
/// `centre`, `N` the unit gradient of `|ω|` and `w = min(1, ΔT / 20 K)` the share of
/// the plume's heat in the cell: a force that spins up existing vortices at the scale of a
/// cell, in hot air only. `[epsilon, dt]`: the confinement strength ε (dimensionless) and the
/// step, s.
///
/// The temperature is zero outside `active` (the spans it was advected in, grown by at least
/// one cell past any air that was busy), so the force is zero there and the curl is needed
/// only inside: every pass runs over the spans alone.
pub fn add_vorticity_confinement(
    shape: &GridShape,
    active: &ActiveSpans,
    centre: &[Vec<f32>; 3],
    temperature: &[f32],
    [epsilon, dt]: [f32; 2],
    scratch: &mut VorticityScratch,
    velocity: &mut [Vec<f32>; 3],
) {
    if epsilon == 0.0 {
        return;
    }
    let VorticityScratch {
        omega,
        magnitude,
        force,
    } = scratch;
    for_each_active_cell(shape, active, |at, c| {
        let d = |field: usize, axis: usize| derivative(shape, &centre[field], at, axis);
        let w = Vec3::new(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));
        omega[0][c] = w.x;
        omega[1][c] = w.y;
        omega[2][c] = w.z;
        magnitude[c] = w.length();
    });
    let strength = epsilon * shape.cell;
    // Cells outside the spans keep no force from an earlier step.
    force.iter_mut().for_each(|f| f.fill(0.0));
    for_each_active_cell(shape, active, |at, c| {
        let weight = (temperature[c].abs() / CONFINEMENT_FULL_AT).min(1.0);
        if weight == 0.0 {
            force[0][c] = 0.0;
            force[1][c] = 0.0;
            force[2][c] = 0.0;
            return;
        }
        let gradient = Vec3::new(
            derivative(shape, magnitude, at, 0),
            derivative(shape, magnitude, at, 1),
            derivative(shape, magnitude, at, 2),
        );
        let length = gradient.length();
        let f = if length > 1e-6 {
            let n = gradient / length;
            strength * weight * n.cross(Vec3::new(omega[0][c], omega[1][c], omega[2][c]))
        } else {
            Vec3::ZERO
        };
        force[0][c] = f.x;
        force[1][c] = f.y;
        force[2][c] = f.z;
    });
    for (axis, faces) in velocity.iter_mut().enumerate() {
        let f = &force[axis];
        for_each_active_face(shape, active, axis, |face, cells| {
            faces[face] += dt * face_mean(cells, |c| f[c]);
        });
    }
}

/// Calls `visit([i, j, k], cell)` for every cell inside the spans of `active`.
#[inline]
fn for_each_active_cell(
    shape: &GridShape,
    active: &ActiveSpans,
    mut visit: impl FnMut([usize; 3], usize),
) {
    let [_, ny, nz] = shape.dims;
    for k in 0..nz {
        for j in 0..ny {
            for i in active.row(shape, j, k) {
                visit([i, j, k], shape.index(i, j, k));
            }
        }
    }
}

/// Calls `visit(face, (cell below, cell above))` for every face normal to `axis` that touches
/// a cell inside the spans of `active`.
#[inline]
fn for_each_active_face(
    shape: &GridShape,
    active: &ActiveSpans,
    axis: usize,
    visit: impl FnMut(usize, (Option<usize>, Option<usize>)),
) {
    for_each_face_in_rows(
        shape,
        axis,
        |j, k| active.face_row(shape, axis, j, k),
        visit,
    );
}

/// Calls `visit(face, (cell below, cell above))` for every face normal to `axis`; a face on
/// the box's side has one of the two missing.
#[inline]
pub fn for_each_face(
    shape: &GridShape,
    axis: usize,
    visit: impl FnMut(usize, (Option<usize>, Option<usize>)),
) {
    let along = shape.face_dims(axis)[0];
    for_each_face_in_rows(shape, axis, |_, _| 0..along, visit);
}

/// Calls `visit(face, (cell below, cell above))` for the faces normal to `axis` whose `i` is
/// in `row(j, k)`, row by row.
#[inline]
fn for_each_face_in_rows(
    shape: &GridShape,
    axis: usize,
    row: impl Fn(usize, usize) -> core::ops::Range<usize>,
    mut visit: impl FnMut(usize, (Option<usize>, Option<usize>)),
) {
    let dims = shape.face_dims(axis);
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in row(j, k) {
                let face = i + dims[0] * (j + dims[1] * k);
                visit(face, shape.face_cells(axis, [i, j, k]));
            }
        }
    }
}
