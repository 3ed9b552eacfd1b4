//! Where the air is doing something: for each row of cells along x, the span of cells whose
//! air is hot, smoky or moving, grown by as far as the air can travel in a step. A fire's
//! plume fills a few percent of its box; advection runs inside the spans only.
//!
//! Outside the spans every cell is below the thresholds ([`BUSY_TEMPERATURE`],
//! [`BUSY_SMOKE`], [`BUSY_SPEED`]) and so is every cell the air there can come from, because
//! the spans are grown by the step's largest travel plus the trilinear stencil's one cell.
//! There advected temperature and smoke are below the thresholds too, and are set to zero;
//! the velocity there is kept as it is, which differs from the advected one by less than
//! twice [`BUSY_SPEED`].

use super::grid::GridShape;

/// Excess temperature above which a cell's air is busy, K: a hundredth of a kelvin lifts air
/// by about 3e-4 m/s² and warms no cloth.
pub const BUSY_TEMPERATURE: f32 = 1e-2;
/// Smoke density above which a cell's air is busy: a ten-thousandth of thick smoke, a tenth of
/// what the plume counts as clear air when it goes to sleep.
pub const BUSY_SMOKE: f32 = 1e-4;
/// Face speed above which a cell's air is busy, m/s: what the plume counts as still air when
/// it goes to sleep. Slower air keeps its velocity instead of being advected (in a 1/60 s step
/// it moves under a millimetre) and is still projected with the rest.
pub const BUSY_SPEED: f32 = 5e-2;

/// For every row of cells `(j, k)` along x, the cells `lo..hi` to advect (empty when
/// `lo >= hi`). Allocated once per grid.
#[derive(Clone, Debug, Default)]
pub struct ActiveSpans {
    /// `[lo, hi)` per row `j + ny k`.
    spans: Vec<[u32; 2]>,
    /// Scratch for the growth along y and z.
    grown: Vec<[u32; 2]>,
    /// Cells inside the spans, after the latest [`ActiveSpans::update`].
    active_cells: usize,
}

const EMPTY: [u32; 2] = [u32::MAX, 0];

/// The smallest span holding both.
#[inline]
fn union(a: [u32; 2], b: [u32; 2]) -> [u32; 2] {
    [a[0].min(b[0]), a[1].max(b[1])]
}

impl ActiveSpans {
    /// Spans for a grid of `shape`, all of it active until the first update.
    pub fn new(shape: &GridShape) -> Self {
        let [nx, ny, nz] = shape.dims;
        Self {
            spans: vec![[0, nx as u32]; ny * nz],
            grown: vec![EMPTY; ny * nz],
            active_cells: shape.cells(),
        }
    }

    /// Marks every cell active (as after a change the spans did not see).
    pub fn all(&mut self, shape: &GridShape) {
        self.spans.fill([0, shape.dims[0] as u32]);
        self.active_cells = shape.cells();
    }

    /// The cells of row `(j, k)` to advect, as a range of `i`.
    #[inline]
    pub fn row(&self, shape: &GridShape, j: usize, k: usize) -> core::ops::Range<usize> {
        let [lo, hi] = self.spans[j + shape.dims[1] * k];
        if lo >= hi {
            0..0
        } else {
            lo as usize..hi as usize
        }
    }

    /// The cells of row `(j, k)` inside the spans or beside a cell that is (along x, y or
    /// z), as a range of `i`: where a difference taken at an active cell reads.
    #[inline]
    pub fn row_with_neighbours(
        &self,
        shape: &GridShape,
        j: usize,
        k: usize,
    ) -> core::ops::Range<usize> {
        let [nx, ny, nz] = shape.dims;
        let span = |j: usize, k: usize| self.spans[j + ny * k];
        let [lo, hi] = span(j, k);
        let mut hull = if lo < hi {
            [lo.saturating_sub(1), (hi + 1).min(nx as u32)]
        } else {
            EMPTY
        };
        for (beside, exists) in [
            ((j.wrapping_sub(1), k), j > 0),
            ((j + 1, k), j + 1 < ny),
            ((j, k.wrapping_sub(1)), k > 0),
            ((j, k + 1), k + 1 < nz),
        ] {
            if exists {
                hull = union(hull, span(beside.0, beside.1));
            }
        }
        let [lo, hi] = hull;
        if lo >= hi {
            0..0
        } else {
            lo as usize..hi as usize
        }
    }

    /// Cells inside the spans.
    pub fn active_cells(&self) -> usize {
        self.active_cells
    }

    /// The faces normal to `axis` in row `(j, k)` of that axis's faces that touch a cell
    /// inside the spans, as a range of `i`.
    #[inline]
    pub fn face_row(
        &self,
        shape: &GridShape,
        axis: usize,
        j: usize,
        k: usize,
    ) -> core::ops::Range<usize> {
        let [_, ny, nz] = shape.dims;
        let span = |j: usize, k: usize| self.spans[j + ny * k];
        let [lo, hi] = match axis {
            // Faces lo..=hi bound cells lo..hi.
            0 => {
                let [lo, hi] = span(j, k);
                [lo, hi + 1]
            }
            1 => {
                let below = if j > 0 { span(j - 1, k) } else { EMPTY };
                let above = if j < ny { span(j, k) } else { EMPTY };
                union(below, above)
            }
            _ => {
                let below = if k > 0 { span(j, k - 1) } else { EMPTY };
                let above = if k < nz { span(j, k) } else { EMPTY };
                union(below, above)
            }
        };
        if lo >= hi {
            0..0
        } else {
            lo as usize..hi as usize
        }
    }

    /// Finds the busy cells (`busy([i, j, k], cell)`, over the cells of `shape`), and grows
    /// each row's span by `reach` cells along x, y and z (the spans' hulls: a little more
    /// than needed, never less).
    pub fn update(
        &mut self,
        shape: &GridShape,
        reach: usize,
        busy: impl Fn([usize; 3], usize) -> bool,
    ) {
        let nx = shape.dims[0];
        self.update_rows(shape, reach, |j, k| {
            let first = nx * (j + shape.dims[1] * k);
            let is_busy = |i: usize| busy([i, j, k], first + i);
            let lo = (0..nx).position(is_busy)?;
            Some([lo, (lo..nx).rev().find(|&i| is_busy(i)).unwrap_or(lo)])
        });
    }

    /// [`ActiveSpans::update`] from each row's first and last busy cell, `busy_row(j, k) ->
    /// Some([first, last])` (`None`: nothing busy in the row), for callers that find them a
    /// row at a time.
    pub fn update_rows(
        &mut self,
        shape: &GridShape,
        reach: usize,
        mut busy_row: impl FnMut(usize, usize) -> Option<[usize; 2]>,
    ) {
        let [nx, ny, nz] = shape.dims;
        let reach_u = reach as u32;
        for (row, span) in self.spans.iter_mut().enumerate() {
            *span = match busy_row(row % ny, row / ny) {
                None => EMPTY,
                Some([lo, hi]) => [
                    (lo as u32).saturating_sub(reach_u),
                    (hi as u32 + 1 + reach_u).min(nx as u32),
                ],
            };
        }
        // Grow along y, then along z: a row takes the hull of the rows within `reach`.
        for k in 0..nz {
            for j in 0..ny {
                let range = j.saturating_sub(reach)..(j + reach + 1).min(ny);
                self.grown[j + ny * k] =
                    range.fold(EMPTY, |hull, jj| union(hull, self.spans[jj + ny * k]));
            }
        }
        for k in 0..nz {
            for j in 0..ny {
                let range = k.saturating_sub(reach)..(k + reach + 1).min(nz);
                self.spans[j + ny * k] =
                    range.fold(EMPTY, |hull, kk| union(hull, self.grown[j + ny * kk]));
            }
        }
        self.active_cells = self
            .spans
            .iter()
            .map(|&[lo, hi]| hi.saturating_sub(lo) as usize)
            .sum();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn shape() -> GridShape {
        GridShape {
            dims: [10, 8, 6],
            cell: 0.1,
            origin: Vec3::ZERO,
        }
    }

    #[test]
    fn a_busy_cell_makes_a_box_of_side_two_reach_plus_one_active() {
        let shape = shape();
        let mut spans = ActiveSpans::new(&shape);
        assert_eq!(spans.active_cells(), shape.cells());
        let busy = shape.index(5, 4, 3);
        spans.update(&shape, 2, |_, c| c == busy);
        assert_eq!(spans.active_cells(), 5 * 5 * 5);
        for k in 0..6 {
            for j in 0..8 {
                let expected = if (2..=6).contains(&j) && (1..=5).contains(&k) {
                    3..8
                } else {
                    0..0
                };
                assert_eq!(spans.row(&shape, j, k), expected, "row {j} {k}");
            }
        }
    }

    #[test]
    fn a_row_with_its_neighbours_holds_every_cell_beside_an_active_one() {
        let shape = shape();
        let mut spans = ActiveSpans::new(&shape);
        let busy = shape.index(5, 4, 3);
        spans.update(&shape, 0, |_, c| c == busy);
        for k in 0..6 {
            for j in 0..8 {
                let expected = match (j, k) {
                    (4, 3) => 4..7,
                    (3 | 5, 3) | (4, 2 | 4) => 5..6,
                    _ => 0..0,
                };
                assert_eq!(
                    spans.row_with_neighbours(&shape, j, k),
                    expected,
                    "row {j} {k}"
                );
            }
        }
        // At the box's sides it stops there.
        let corner = shape.index(0, 0, 0);
        spans.update(&shape, 0, |_, c| c == corner);
        assert_eq!(spans.row_with_neighbours(&shape, 0, 0), 0..2);
        assert_eq!(spans.row_with_neighbours(&shape, 1, 0), 0..1);
        assert_eq!(spans.row_with_neighbours(&shape, 0, 1), 0..1);
        assert_eq!(spans.row_with_neighbours(&shape, 1, 1), 0..0);
    }

    #[test]
    fn spans_stop_at_the_box_and_nothing_busy_is_nothing_active() {
        let shape = shape();
        let mut spans = ActiveSpans::new(&shape);
        let corner = shape.index(0, 0, 0);
        spans.update(&shape, 1, |_, c| c == corner);
        assert_eq!(spans.row(&shape, 0, 0), 0..2);
        assert_eq!(spans.row(&shape, 1, 1), 0..2);
        assert_eq!(spans.row(&shape, 2, 0), 0..0);
        assert_eq!(spans.active_cells(), 8);
        spans.update(&shape, 3, |_, _| false);
        assert_eq!(spans.active_cells(), 0);
        spans.all(&shape);
        assert_eq!(spans.row(&shape, 7, 5), 0..10);
    }

    #[test]
    fn two_busy_cells_in_a_row_give_their_hull() {
        let shape = shape();
        let mut spans = ActiveSpans::new(&shape);
        let (a, b) = (shape.index(1, 3, 2), shape.index(7, 3, 2));
        spans.update(&shape, 0, |at, c| {
            assert_eq!(shape.index(at[0], at[1], at[2]), c);
            c == a || c == b
        });
        assert_eq!(spans.row(&shape, 3, 2), 1..8);
        assert_eq!(spans.active_cells(), 7);
        // Faces: along x the faces 1..=8 bound the cells 1..8; along y and z a face row
        // takes the rows on both sides.
        assert_eq!(spans.face_row(&shape, 0, 3, 2), 1..9);
        assert_eq!(spans.face_row(&shape, 1, 3, 2), 1..8);
        assert_eq!(spans.face_row(&shape, 1, 4, 2), 1..8);
        assert_eq!(spans.face_row(&shape, 1, 5, 2), 0..0);
        assert_eq!(spans.face_row(&shape, 2, 3, 3), 1..8);
        assert_eq!(spans.face_row(&shape, 2, 3, 1), 0..0);
    }
}
