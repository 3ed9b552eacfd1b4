//! Area-weighted vertex normals of a grid cloth's mesh, as loops along its rows.
//!
//! A grid's triangles are known: two per cell, the diagonal alternating from cell to cell
//! (`grid::grid_triangles`). So instead of scattering each drawn triangle's normal to its
//! corners, one triangle at a time, each cell row's two face normals per cell are computed
//! along the row, four or eight cells at once, and each vertex row then gathers the faces
//! around its vertices from the two cell rows beside it. Every loop reads and writes plain
//! `f32` arrays in order with no branch, so the compiler turns it into SIMD instructions.
//!
//! For the cell at column `c`, row `r` (corners `TL`, `TR` on row `r`, `BL`, `BR` below),
//! even when `r + c` is: `T1 = [TL, BL, TR]`, `T2 = [TR, BL, BR]`; odd:
//! `T1 = [TL, BL, BR]`, `T2 = [TL, BR, TR]`; each face's normal is
//! `(b − a) × (c − a)` for corners `[a, b, c]` (twice the area), zero when a corner is burnt
//! (the triangle is not drawn). A vertex whose `r + c` is odd is a corner of all eight
//! triangles of its four cells; an even one of four: `T1` of the cell below right, `T2` of
//! the one below left, `T1` of the one above right (where it is `BL`), `T2` of the one above
//! left (where it is `BR`).

use core::ops::Range;

/// A cell row's face normals per axis: `T1`'s and `T2`'s.
pub(crate) struct FaceRow<'a> {
    pub first: [&'a mut [f32]; 3],
    pub second: [&'a mut [f32]; 3],
}

/// The same range of each axis.
#[inline(always)]
pub(crate) fn cut(axes: [&[f32]; 3], range: Range<usize>) -> [&[f32]; 3] {
    axes.map(|axis| &axis[range.clone()])
}

/// Both bit patterns of a select: all ones where `odd`.
#[inline(always)]
fn mask(odd: bool) -> u32 {
    if odd { u32::MAX } else { 0 }
}

/// `odd_value` where `odd` (all ones) and `even_value` where it is zero, bit for bit.
#[inline(always)]
fn pick(odd: u32, even_value: f32, odd_value: f32) -> f32 {
    f32::from_bits((even_value.to_bits() & !odd) | (odd_value.to_bits() & odd))
}

#[inline(always)]
fn cross(u: [f32; 3], v: [f32; 3]) -> [f32; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

#[inline(always)]
fn minus(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The face normals of one cell row (between vertex rows `top` and `bottom`, `columns`
/// vertices each; positions per axis and `alive`, 1 for an unburnt vertex and 0 for a burnt
/// one): `out.first[c]` and `out.second[c]` for the row's `columns − 1` cells. `first_odd`:
/// whether the row's first cell has `r + c` odd.
pub(crate) fn face_row(
    rows: ([&[f32]; 3], [&[f32]; 3]),
    alive: (&[f32], &[f32]),
    first_odd: bool,
    out: FaceRow,
) {
    #[cfg(target_arch = "x86_64")]
    if crate::sim::simd::avx_available() {
        // SAFETY: this CPU has AVX.
        #[allow(unsafe_code)]
        return unsafe { wide::face_row(rows, alive, first_odd, out) };
    }
    face_row_portable(rows, alive, first_odd, out);
}

#[inline(always)]
fn face_row_portable(
    (top, bottom): ([&[f32]; 3], [&[f32]; 3]),
    (alive_top, alive_bottom): (&[f32], &[f32]),
    first_odd: bool,
    out: FaceRow,
) {
    let cells = out.first[0].len();
    // Every array cut to one length, so the loop checks no bounds and vectorises.
    let top_left = top.map(|a| &a[..cells]);
    let top_right = top.map(|a| &a[1..=cells]);
    let bottom_left = bottom.map(|a| &a[..cells]);
    let bottom_right = bottom.map(|a| &a[1..=cells]);
    let (alive_tl, alive_tr) = (&alive_top[..cells], &alive_top[1..=cells]);
    let (alive_bl, alive_br) = (&alive_bottom[..cells], &alive_bottom[1..=cells]);
    let FaceRow { first, second } = out;
    let [f0, f1, f2] = first;
    let [s0, s1, s2] = second;
    let (f0, f1, f2) = (&mut f0[..cells], &mut f1[..cells], &mut f2[..cells]);
    let (s0, s1, s2) = (&mut s0[..cells], &mut s1[..cells], &mut s2[..cells]);
    let at = |axes: [&[f32]; 3], c: usize| [axes[0][c], axes[1][c], axes[2][c]];
    for c in 0..cells {
        let odd = mask(first_odd ^ (c % 2 == 1));
        let (tl, tr, bl, br) = (
            at(top_left, c),
            at(top_right, c),
            at(bottom_left, c),
            at(bottom_right, c),
        );
        let choose = |even: [f32; 3], odd_value: [f32; 3]| {
            [
                pick(odd, even[0], odd_value[0]),
                pick(odd, even[1], odd_value[1]),
                pick(odd, even[2], odd_value[2]),
            ]
        };
        // T1: (BL − TL) × (TR or BR − TL).
        let one = cross(minus(bl, tl), minus(choose(tr, br), tl));
        // T2: even (BL − TR) × (BR − TR), odd (BR − TL) × (TR − TL).
        let base = choose(tr, tl);
        let two = cross(minus(choose(bl, br), base), minus(choose(br, tr), base));
        let (a_tl, a_tr, a_bl, a_br) = (alive_tl[c], alive_tr[c], alive_bl[c], alive_br[c]);
        let live_one = a_tl * a_bl * pick(odd, a_tr, a_br);
        let live_two = pick(odd, a_tr * a_bl * a_br, a_tl * a_br * a_tr);
        (f0[c], f1[c], f2[c]) = (one[0] * live_one, one[1] * live_one, one[2] * live_one);
        (s0[c], s1[c], s2[c]) = (two[0] * live_two, two[1] * live_two, two[2] * live_two);
    }
}

/// A vertex row's unit normals (`+Z` where no drawn triangle touches a vertex), from the face
/// rows above it (`above`, zeros for the first row) and below it (`below`, zeros for the
/// last), each padded with a zero cell at both ends (`columns + 1` entries: cell `c` at
/// `c + 1`). `first_odd`: whether the row's first vertex has `r + c` odd.
pub(crate) fn normal_row(
    above: ([&[f32]; 3], [&[f32]; 3]),
    below: ([&[f32]; 3], [&[f32]; 3]),
    first_odd: bool,
    out: &mut [[f32; 3]],
) {
    #[cfg(target_arch = "x86_64")]
    if crate::sim::simd::avx_available() {
        // SAFETY: this CPU has AVX.
        #[allow(unsafe_code)]
        return unsafe { wide::normal_row(above, below, first_odd, out) };
    }
    normal_row_portable(above, below, first_odd, out);
}

#[inline(always)]
fn normal_row_portable(
    (above_first, above_second): ([&[f32]; 3], [&[f32]; 3]),
    (below_first, below_second): ([&[f32]; 3], [&[f32]; 3]),
    first_odd: bool,
    out: &mut [[f32; 3]],
) {
    let columns = out.len();
    // Cells right of a vertex are at `c + 1`, left of it at `c`.
    let right = |a| cut(a, 1..columns + 1);
    let left = |a| cut(a, 0..columns);
    let (below_right_1, below_right_2) = (right(below_first), right(below_second));
    let (below_left_1, below_left_2) = (left(below_first), left(below_second));
    let (above_right_1, above_right_2) = (right(above_first), right(above_second));
    let (above_left_1, above_left_2) = (left(above_first), left(above_second));
    for (c, out) in out.iter_mut().enumerate() {
        let odd = mask(first_odd ^ (c % 2 == 1));
        let mut sum = [0.0f32; 3];
        for (axis, sum) in sum.iter_mut().enumerate() {
            // The four faces every vertex has, then the four an odd one adds.
            let every = below_right_1[axis][c]
                + below_left_2[axis][c]
                + above_right_1[axis][c]
                + above_left_2[axis][c];
            let more = below_right_2[axis][c]
                + below_left_1[axis][c]
                + above_right_2[axis][c]
                + above_left_1[axis][c];
            *sum = pick(odd, every, every + more);
        }
        *out = unit_or_z(sum);
    }
}

/// `v` normalised, or `+Z` where it has no direction (zero or not finite): what
/// `Vec3A::try_normalize(..).unwrap_or(Vec3A::Z)` gives, without a branch.
#[inline(always)]
pub(crate) fn unit_or_z(v: [f32; 3]) -> [f32; 3] {
    let inverse = 1.0 / (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let ok = mask(inverse.is_finite() & (inverse > 0.0));
    [
        pick(ok, 0.0, v[0] * inverse),
        pick(ok, 0.0, v[1] * inverse),
        pick(ok, 1.0, v[2] * inverse),
    ]
}

/// The row loops compiled for AVX, taken where the CPU has it: eight cells at a time instead
/// of four (the same operations, no fused multiply-add, so the same bits).
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod wide {
    use super::{FaceRow, face_row_portable, normal_row_portable};

    #[target_feature(enable = "avx")]
    pub(super) fn face_row(
        rows: ([&[f32]; 3], [&[f32]; 3]),
        alive: (&[f32], &[f32]),
        first_odd: bool,
        out: FaceRow,
    ) {
        face_row_portable(rows, alive, first_odd, out);
    }

    #[target_feature(enable = "avx")]
    pub(super) fn normal_row(
        above: ([&[f32]; 3], [&[f32]; 3]),
        below: ([&[f32]; 3], [&[f32]; 3]),
        first_odd: bool,
        out: &mut [[f32; 3]],
    ) {
        normal_row_portable(above, below, first_odd, out);
    }
}

/// A grid mesh's scratch: its vertices' local positions per axis, whether each is drawn
/// (1, or 0 when burnt), and each cell's two face normals per axis, in rows of
/// `columns + 1` entries padded with zeros (cell `c` of cell row `r` at row `r + 1`, entry
/// `c + 1`; rows 0 and `rows`, and each row's entries 0 and `columns`, stay zero), so every
/// vertex finds four cells around it, real or empty.
#[derive(Clone, Debug, Default)]
pub(crate) struct GridFaces {
    /// Vertices per row and rows.
    pub columns: usize,
    pub rows: usize,
    /// Local positions, m, per axis.
    pub position: [Vec<f32>; 3],
    /// 1 for a vertex that is drawn, 0 for a burnt one.
    pub alive: Vec<f32>,
    /// Twice-area normals of each cell's first and second triangles, per axis.
    pub first: [Vec<f32>; 3],
    pub second: [Vec<f32>; 3],
}

impl GridFaces {
    /// Sized for a grid of `columns` × `rows` vertices, the padding zero.
    pub fn prepare(&mut self, columns: usize, rows: usize) {
        let (n, padded) = (columns * rows, (columns + 1) * (rows + 1));
        if (self.columns, self.rows) == (columns, rows) && self.alive.len() == n {
            return;
        }
        (self.columns, self.rows) = (columns, rows);
        for axis in &mut self.position {
            axis.clear();
            axis.resize(n, 0.0);
        }
        self.alive.clear();
        self.alive.resize(n, 0.0);
        for axis in self.first.iter_mut().chain(&mut self.second) {
            axis.clear();
            axis.resize(padded, 0.0);
        }
    }

    /// Entries per padded row of faces.
    pub fn width(&self) -> usize {
        self.columns + 1
    }

    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        let floats: usize = self
            .position
            .iter()
            .chain(&self.first)
            .chain(&self.second)
            .map(Vec::capacity)
            .sum::<usize>()
            + self.alive.capacity();
        floats * size_of::<f32>()
    }
}
