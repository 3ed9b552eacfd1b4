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

/// The cells of row `(j, k)` in `span` split into those at the box's sides (the first and
/// the last) and those between, whose six neighbours are all inside the box: there a
/// derivative is the central difference `(f[c + s] − f[c − s]) / 2h`, the same to the bit as
/// [`derivative`], computed a row at a time over slices of one length (no index arithmetic
/// or bounds test per cell).
fn split_row(
    shape: &GridShape,
    j: usize,
    k: usize,
    span: core::ops::Range<usize>,
) -> [core::ops::Range<usize>; 3] {
    let [nx, ny, nz] = shape.dims;
    let interior_row = j > 0 && j + 1 < ny && k > 0 && k + 1 < nz && nx > 2;
    if !interior_row || span.is_empty() {
        return [span, 0..0, 0..0];
    }
    let (lo, hi) = (
        span.start.max(1),
        span.end.min(nx - 1).max(span.start.max(1)),
    );
    [span.start..lo, lo..hi, hi..span.end]
}

/// The `n` values of `field` from `a − stride` and from `a + stride`: the neighbours below
/// and above a run of cells along one axis.
#[inline(always)]
fn around(field: &[f32], a: usize, n: usize, stride: usize) -> (&[f32], &[f32]) {
    (
        &field[a - stride..a - stride + n],
        &field[a + stride..a + stride + n],
    )
}

/// The curl `ω` of the centre velocities and its magnitude at cell `c` at `at`, one cell at
/// a time (any cell).
#[inline]
fn curl_at(shape: &GridShape, centre: &[Vec<f32>; 3], at: [usize; 3]) -> Vec3 {
    let d = |field: usize, axis: usize| derivative(shape, &centre[field], at, axis);
    Vec3::new(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1))
}

/// The confinement force at cell `c` at `at` from the vorticity and its magnitude, one cell
/// at a time (any cell).
#[inline]
fn force_at(
    shape: &GridShape,
    omega: &[Vec<f32>; 3],
    magnitude: &[f32],
    weight: f32,
    strength: f32,
    at: [usize; 3],
    c: usize,
) -> Vec3 {
    let gradient = Vec3::new(
        derivative(shape, magnitude, at, 0),
        derivative(shape, magnitude, at, 1),
        derivative(shape, magnitude, at, 2),
    );
    confinement(
        gradient,
        Vec3::new(omega[0][c], omega[1][c], omega[2][c]),
        weight,
        strength,
    )
}

/// `strength × weight × (N × ω)` with `N` the unit `gradient` (zero where the gradient is
/// below 1e-6 per metre or the weight is zero).
#[inline(always)]
fn confinement(gradient: Vec3, omega: Vec3, weight: f32, strength: f32) -> Vec3 {
    let length = gradient.length();
    if weight != 0.0 && length > 1e-6 {
        strength * weight * (gradient / length).cross(omega)
    } else {
        Vec3::ZERO
    }
}

/// Adds `dt × ε h w (N × ω)` to the faces, where `ω` is the curl of the centre velocities
/// `centre`, `N` the unit gradient of `|ω|` and `w = min(1, ΔT / 20 K)` the share of
/// the plume's heat in the cell: a force that spins up existing vortices at the scale of a
/// cell, in hot air only. `[epsilon, dt]`: the confinement strength ε (dimensionless) and the
/// step, s.
///
/// The temperature is zero outside `active` (the spans it was advected in, grown by at least
/// one cell past any air that was busy), so the force is zero there and the curl is needed
/// only inside: every pass runs over the spans alone, a row at a time.
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
    let [nx, ny, nz] = shape.dims;
    let (sy, sz) = (nx, nx * ny);
    let span = 2.0 * shape.cell;
    let [u, v, w] = centre;
    // The vorticity wherever the force's differences read it: at the active cells and
    // their neighbours (a neighbour outside the spans would otherwise hold an old step's).
    for k in 0..nz {
        for j in 0..ny {
            let row = active.row_with_neighbours(shape, j, k);
            let [before, inside, after] = split_row(shape, j, k, row);
            let first = nx * (j + ny * k);
            for i in before.chain(after) {
                let curl = curl_at(shape, centre, [i, j, k]);
                let c = first + i;
                (omega[0][c], omega[1][c], omega[2][c]) = (curl.x, curl.y, curl.z);
                magnitude[c] = curl.length();
            }
            // Central differences over the row's middle, as `curl_at` takes them, over
            // slices of one length (no bounds test per cell).
            let (a, n) = (first + inside.start, inside.len());
            if n == 0 {
                continue;
            }
            let pair = |f, s| around(f, a, n, s);
            let (wy, vz, uz) = (pair(w, sy), pair(v, sz), pair(u, sz));
            let (wx, vx, uy) = (pair(w, 1), pair(v, 1), pair(u, sy));
            let [o0, o1, o2] = omega;
            let (o0, o1, o2) = (&mut o0[a..a + n], &mut o1[a..a + n], &mut o2[a..a + n]);
            let magnitude = &mut magnitude[a..a + n];
            let d = |(below, above): (&[f32], &[f32]), i: usize| (above[i] - below[i]) / span;
            for i in 0..n {
                let curl = Vec3::new(
                    d(wy, i) - d(vz, i),
                    d(uz, i) - d(wx, i),
                    d(vx, i) - d(uy, i),
                );
                (o0[i], o1[i], o2[i]) = (curl.x, curl.y, curl.z);
                magnitude[i] = curl.length();
            }
        }
    }
    let strength = epsilon * shape.cell;
    // Cells outside the spans keep no force from an earlier step.
    force.iter_mut().for_each(|f| f.fill(0.0));
    let weight = |c: usize| (temperature[c].abs() / CONFINEMENT_FULL_AT).min(1.0);
    for k in 0..nz {
        for j in 0..ny {
            let [before, inside, after] = split_row(shape, j, k, active.row(shape, j, k));
            let first = nx * (j + ny * k);
            for i in before.chain(after) {
                let c = first + i;
                let f = force_at(shape, omega, magnitude, weight(c), strength, [i, j, k], c);
                (force[0][c], force[1][c], force[2][c]) = (f.x, f.y, f.z);
            }
            let (a, n) = (first + inside.start, inside.len());
            if n == 0 {
                continue;
            }
            let pair = |s| around(magnitude, a, n, s);
            let (mx, my, mz) = (pair(1), pair(sy), pair(sz));
            let d = |(below, above): (&[f32], &[f32]), i: usize| (above[i] - below[i]) / span;
            let [o0, o1, o2] = &*omega;
            let (o0, o1, o2) = (&o0[a..a + n], &o1[a..a + n], &o2[a..a + n]);
            let t = &temperature[a..a + n];
            let [f0, f1, f2] = force;
            let (f0, f1, f2) = (&mut f0[a..a + n], &mut f1[a..a + n], &mut f2[a..a + n]);
            for i in 0..n {
                let gradient = Vec3::new(d(mx, i), d(my, i), d(mz, i));
                let curl = Vec3::new(o0[i], o1[i], o2[i]);
                let weight = (t[i].abs() / CONFINEMENT_FULL_AT).min(1.0);
                let f = confinement(gradient, curl, weight, strength);
                (f0[i], f1[i], f2[i]) = (f.x, f.y, f.z);
            }
        }
    }
    for (axis, faces) in velocity.iter_mut().enumerate() {
        add_face_means(shape, active, axis, &force[axis], dt, faces);
    }
}

/// Adds `scale ×` the mean of `values` over each face's cells ([`face_mean`]) to every face
/// normal to `axis` that touches a cell inside the spans of `active`: a row of faces at a
/// time, the faces with a cell on both sides in one loop over slices that vectorises, those
/// on the box's sides one by one. The same result to the bit as face by face.
fn add_face_means(
    shape: &GridShape,
    active: &ActiveSpans,
    axis: usize,
    values: &[f32],
    scale: f32,
    faces: &mut [f32],
) {
    let [nx, ny, _] = shape.dims;
    let dims = shape.face_dims(axis);
    let stride = [1, nx, nx * ny][axis];
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            let row = active.face_row(shape, axis, j, k);
            let first = dims[0] * (j + dims[1] * k);
            let both = shape.inner_faces(axis, [j, k], row.clone());
            for i in row.clone().filter(|i| !both.contains(i)) {
                let cells = shape.face_cells(axis, [i, j, k]);
                faces[first + i] += scale * face_mean(cells, |c| values[c]);
            }
            if both.is_empty() {
                continue;
            }
            // The cell above face `(i, j, k)` is cell `(i, j, k)`; the one below is a stride
            // back along `axis`.
            let above = both.start + nx * (j + ny * k);
            let n = both.len();
            let (below, above) = (
                &values[above - stride..above - stride + n],
                &values[above..above + n],
            );
            let out = &mut faces[first + both.start..first + both.end];
            for i in 0..n {
                out[i] += scale * ((below[i] + above[i]) * 0.5);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The confinement as first written, one cell at a time with [`derivative`] everywhere,
    /// the vorticity taken at every cell: the reference the row-wise loops must equal to the
    /// bit.
    fn confinement_cell_by_cell(
        shape: &GridShape,
        active: &ActiveSpans,
        centre: &[Vec<f32>; 3],
        temperature: &[f32],
        [epsilon, dt]: [f32; 2],
        velocity: &mut [Vec<f32>; 3],
    ) {
        let n = shape.cells();
        let mut omega: [Vec<f32>; 3] = core::array::from_fn(|_| vec![0.0; n]);
        let mut magnitude = vec![0.0; n];
        let mut force: [Vec<f32>; 3] = core::array::from_fn(|_| vec![0.0; n]);
        let [nx, ny, nz] = shape.dims;
        let cells = || {
            (0..nz).flat_map(move |k| {
                (0..ny).flat_map(move |j| active.row(shape, j, k).map(move |i| [i, j, k]))
            })
        };
        // The vorticity everywhere: it is a property of the velocity, not of the spans.
        let every_cell =
            (0..nz).flat_map(|k| (0..ny).flat_map(move |j| (0..nx).map(move |i| [i, j, k])));
        for [i, j, k] in every_cell {
            let c = shape.index(i, j, k);
            let w = curl_at(shape, centre, [i, j, k]);
            (omega[0][c], omega[1][c], omega[2][c]) = (w.x, w.y, w.z);
            magnitude[c] = w.length();
        }
        for [i, j, k] in cells() {
            let c = shape.index(i, j, k);
            let weight = (temperature[c].abs() / CONFINEMENT_FULL_AT).min(1.0);
            let f = force_at(
                shape,
                &omega,
                &magnitude,
                weight,
                epsilon * shape.cell,
                [i, j, k],
                c,
            );
            (force[0][c], force[1][c], force[2][c]) = (f.x, f.y, f.z);
        }
        for (axis, faces) in velocity.iter_mut().enumerate() {
            let f = &force[axis];
            for_each_active_face(shape, active, axis, |face, cells| {
                faces[face] += dt * face_mean(cells, |c| f[c]);
            });
        }
    }

    #[test]
    fn the_row_wise_confinement_equals_the_cell_by_cell_one_to_the_bit_whatever_the_scratch_held() {
        let shape = GridShape {
            dims: [11, 9, 7],
            cell: 0.1,
            origin: Vec3::ZERO,
        };
        let n = shape.cells();
        let wave = |c: usize, seed: usize| (((c + seed) * 7919) % 211) as f32 / 50.0 - 2.0;
        let centre: [Vec<f32>; 3] = core::array::from_fn(|a| (0..n).map(|c| wave(c, a)).collect());
        let temperature: Vec<f32> = (0..n).map(|c| 15.0 * wave(c, 5)).collect();
        // Spans that reach the box's sides and spans inside it, and some empty rows.
        let mut active = ActiveSpans::new(&shape);
        let (a, b) = (shape.index(0, 2, 3), shape.index(6, 6, 4));
        active.update(&shape, 2, |_, c| c == a || c == b);
        assert!(active.active_cells() > 0 && active.active_cells() < n);
        for spans in [active, ActiveSpans::new(&shape)] {
            let faces: [Vec<f32>; 3] =
                core::array::from_fn(|a| vec![0.5; shape.face_dims(a).iter().product()]);
            let mut expected = faces.clone();
            confinement_cell_by_cell(
                &shape,
                &spans,
                &centre,
                &temperature,
                [0.4, 0.02],
                &mut expected,
            );
            let mut got = faces;
            // The scratch as an earlier step with other air, everywhere busy, left it.
            let mut scratch = VorticityScratch::new(n);
            let other: [Vec<f32>; 3] =
                core::array::from_fn(|a| (0..n).map(|c| wave(c, a + 11)).collect());
            add_vorticity_confinement(
                &shape,
                &ActiveSpans::new(&shape),
                &other,
                &temperature,
                [0.4, 0.02],
                &mut scratch,
                &mut got.clone(),
            );
            add_vorticity_confinement(
                &shape,
                &spans,
                &centre,
                &temperature,
                [0.4, 0.02],
                &mut scratch,
                &mut got,
            );
            for axis in 0..3 {
                let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got[axis]), bits(&expected[axis]), "axis {axis}");
                assert!(
                    got[axis]
                        .iter()
                        .zip(&expected[axis])
                        .any(|(g, _)| *g != 0.5)
                );
            }
        }
    }
}
