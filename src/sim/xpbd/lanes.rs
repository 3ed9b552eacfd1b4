//! How a grid cloth is laid out for the solver: quarter grids, bands and lanes.
//!
//! **Slots.** Inside the solver a grid's particles are stored as four quarter grids, the
//! columns `c ≡ 0, 1, 2, 3 (mod 4)` one after another, each row by row with `W = ⌈C/4⌉` slots
//! a row ([`GridSlots`]); slots past the last column are padding that nothing moves.
//!
//! **Lanes.** In that order every family of springs joins particles a constant number of
//! slots apart: the east springs of the columns `c ≡ 0` join quarter 0 to quarter 1 slot by
//! slot, the south springs join each quarter to itself one row (`W` slots) on, and so on. A
//! lane is one family of one quarter over a band of rows: element `k` joins slot `a + k` to
//! slot `b + k`. Where the pattern reaches past the grid's edge an element stands for no
//! spring (a phantom, with zero correction factors). A lane is as long as a band is big, so
//! the kernel's loop runs long whatever the cloth's width; its ends are at least 4 slots
//! apart, so four elements at a time never touch the same particle.
//!
//! | family | kind | joins | lanes per band |
//! |---|---|---|---|
//! | east | structural | (c, r)–(c+1, r) | 4, one per quarter |
//! | south | structural | (c, r)–(c, r+1) | 4 |
//! | south-east | shear | (c, r)–(c+1, r+1) | 4 |
//! | south-west | shear | (c, r)–(c−1, r+1) | 4 |
//! | east two | bend | (c, r)–(c+2, r) | 4 |
//! | south two | bend | (c, r)–(c, r+2) | 4 |
//!
//! **Bands.** The rows are cut into bands of at least three rows; a band's lanes reach at most
//! two rows into the next band, so bands two apart share no particle. The even bands can be
//! solved at the same time, then the odd ones, and the result does not depend on how many
//! threads do it: the order within each band is fixed, and bands solved together are
//! independent.

use crate::sim::springs::SpringKind;
use crate::sim::topology::GridShape;
use std::ops::Range;

/// Where a grid's particles sit in the solver's arrays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridSlots {
    columns: u32,
    rows: u32,
    /// Slots per quarter-grid row, `⌈columns / 4⌉`.
    width: u32,
}

impl GridSlots {
    /// The slots of a `columns × rows` grid.
    pub fn new(grid: GridShape) -> Self {
        Self {
            columns: grid.columns,
            rows: grid.rows,
            width: grid.columns.div_ceil(4),
        }
    }

    /// Slots in all, padding included.
    pub fn len(&self) -> usize {
        4 * (self.rows * self.width) as usize
    }

    /// Always false: a grid has at least one slot per quarter.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first slot of quarter grid `q`.
    fn quarter(&self, q: u32) -> u32 {
        q * self.quarter_len()
    }

    /// Slots in one quarter grid.
    pub fn quarter_len(&self) -> u32 {
        self.rows * self.width
    }

    /// Where `rows` lie within each quarter grid: their slots counted from the quarter
    /// grid's first (add `q × quarter_len()` for quarter grid `q`).
    pub fn row_span(&self, rows: core::ops::Range<u32>) -> core::ops::Range<usize> {
        let width = self.width as usize;
        rows.start as usize * width..rows.end as usize * width
    }

    /// Rows of the grid.
    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// Slots per quarter-grid row.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The slot of the particle in `column`, `row`.
    pub fn slot(&self, column: u32, row: u32) -> u32 {
        self.quarter(column % 4) + row * self.width + column / 4
    }

    /// The grid column and row of `slot`, or `None` for padding.
    pub fn cell(&self, slot: u32) -> Option<(u32, u32)> {
        let q = slot / (self.rows * self.width);
        let within = slot % (self.rows * self.width);
        let (row, k) = (within / self.width, within % self.width);
        let column = 4 * k + q;
        (q < 4 && column < self.columns).then_some((column, row))
    }
}

/// One family of one quarter over a band: element `k` joins index `a + k` of quarter grid
/// `qa` to index `b + k` of quarter grid `qb` (indices within a quarter grid: `row × W + k`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lane {
    /// Quarter grid of end `a`.
    pub qa: u8,
    /// Quarter grid of end `b`.
    pub qb: u8,
    /// Index of end `a` of element 0 in its quarter grid.
    pub a: u32,
    /// Index of end `b` of element 0 in its quarter grid.
    pub b: u32,
    /// Elements.
    pub len: u32,
    /// Where the lane's elements start in the per-element arrays (rest length, factors).
    pub first: u32,
    /// The kind of its springs.
    pub kind: SpringKind,
}

/// A band of rows and its lanes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Band {
    /// The rows whose springs the band holds.
    pub rows: Range<u32>,
    /// The rows its lanes touch: its own and up to two more (below `rows.end`).
    pub reach: Range<u32>,
    /// Its lanes in [`GridLanes::lanes`].
    pub lanes: Range<usize>,
}

/// A grid's lanes, band by band.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GridLanes {
    /// Every lane.
    pub lanes: Vec<Lane>,
    /// The bands, top to bottom.
    pub bands: Vec<Band>,
    /// Elements of all lanes together.
    pub elements: u32,
}

/// The six families as (column step, row step, kind).
const FAMILIES: [(i32, u32, SpringKind); 6] = [
    (1, 0, SpringKind::Structural),
    (0, 1, SpringKind::Structural),
    (1, 1, SpringKind::Shear),
    (-1, 1, SpringKind::Shear),
    (2, 0, SpringKind::Bend),
    (0, 2, SpringKind::Bend),
];

impl GridLanes {
    /// The lanes of the grid of `slots`, in bands of `band_rows` rows (at least 3; the last
    /// band takes what is left).
    pub fn new(slots: GridSlots, band_rows: u32) -> Self {
        let band_rows = band_rows.max(3);
        let mut out = Self::default();
        let mut row = 0;
        while row < slots.rows {
            let end = if slots.rows - row < 2 * band_rows {
                slots.rows
            } else {
                row + band_rows
            };
            let start = out.lanes.len();
            for (dc, dr, kind) in FAMILIES {
                for q in 0..4 {
                    out.push_lane(slots, row..end, q, dc, dr, kind);
                }
            }
            out.bands.push(Band {
                rows: row..end,
                reach: row..(end + 2).min(slots.rows),
                lanes: start..out.lanes.len(),
            });
            row = end;
        }
        out
    }

    /// The lane of quarter `q`'s springs `(dc, dr)` from the rows `rows`: from (q, r, k) to
    /// the slot of column `4k + q + dc`, row `r + dr`. Elements whose far end leaves the grid
    /// are phantoms; the lane is cut short where the far index would leave its quarter grid.
    fn push_lane(
        &mut self,
        slots: GridSlots,
        rows: Range<u32>,
        q: u32,
        dc: i32,
        dr: u32,
        kind: SpringKind,
    ) {
        let rows = rows.start..rows.end.min(slots.rows.saturating_sub(dr));
        if rows.is_empty() {
            return;
        }
        let w = slots.width;
        let target = q as i32 + dc;
        // Quarter and shift (in slots of a quarter row) of the far end.
        let (far_q, shift) = (target.rem_euclid(4) as u32, target.div_euclid(4));
        let mut a = rows.start * w;
        let mut b = ((rows.start + dr) * w) as i32 + shift;
        let mut len = (rows.end - rows.start) * w;
        // Keep both ends inside their quarter grids: a shift of −1 drops the first element,
        // +1 the last (those elements would be phantoms anyway).
        if b < 0 {
            a += 1;
            b += 1;
            len -= 1;
        }
        let quarter_len = slots.rows * w;
        if b as u32 + len > quarter_len {
            len = quarter_len - b as u32;
        }
        if len == 0 {
            return;
        }
        self.lanes.push(Lane {
            qa: q as u8,
            qb: far_q as u8,
            a,
            b: b as u32,
            len,
            first: self.elements,
            kind,
        });
        self.elements += len;
    }

    /// The grid cells of lane element `k`'s ends, or `None` for a phantom.
    pub fn cells(&self, slots: GridSlots, lane: &Lane, k: u32) -> Option<[(u32, u32); 2]> {
        let quarter_len = slots.rows * slots.width;
        let a = slots.cell(u32::from(lane.qa) * quarter_len + lane.a + k)?;
        let b = slots.cell(u32::from(lane.qb) * quarter_len + lane.b + k)?;
        let (dc, dr) = (b.0 as i32 - a.0 as i32, b.1 as i32 - a.1 as i32);
        // Indices a quarter row apart may wrap to the next row: only the family's own step is
        // a spring.
        let family = FAMILIES
            .iter()
            .any(|&(fc, fr, kind)| kind == lane.kind && (fc, fr as i32) == (dc, dr));
        family.then_some([a, b])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(columns: u32, rows: u32, band_rows: u32) {
        let grid = GridShape { columns, rows };
        let slots = GridSlots::new(grid);
        let mut seen = std::collections::BTreeSet::new();
        for row in 0..rows {
            for column in 0..columns {
                let slot = slots.slot(column, row);
                assert!((slot as usize) < slots.len() && seen.insert(slot));
                assert_eq!(slots.cell(slot), Some((column, row)));
            }
        }
        let lanes = GridLanes::new(slots, band_rows);
        let mut springs = std::collections::BTreeSet::new();
        let mut per_particle = vec![[0u32; 3]; (columns * rows) as usize];
        let mut touched: Vec<std::collections::BTreeSet<(u32, u32)>> = Vec::new();
        let quarter = slots.quarter_len();
        for band in &lanes.bands {
            let mut band_cells = std::collections::BTreeSet::new();
            for lane in &lanes.lanes[band.lanes.clone()] {
                assert!(lane.a.max(lane.b) + lane.len <= quarter);
                if lane.qa == lane.qb {
                    assert!(
                        lane.b > lane.a,
                        "{lane:?}: a lane within a quarter runs forward"
                    );
                }
                let w = slots.width();
                for k in 0..lane.len {
                    for (q, index) in [(lane.qa, lane.a + k), (lane.qb, lane.b + k)] {
                        let row = index / w;
                        assert!(
                            band.reach.contains(&row),
                            "{lane:?} leaves its band's reach"
                        );
                        if let Some(cell) = slots.cell(u32::from(q) * quarter + index) {
                            band_cells.insert(cell);
                        }
                    }
                    let Some([a, b]) = lanes.cells(slots, lane, k) else {
                        continue;
                    };
                    assert!(springs.insert((a, b)), "{a:?}-{b:?} twice");
                    per_particle[(a.1 * columns + a.0) as usize][lane.kind as usize] += 1;
                    per_particle[(b.1 * columns + b.0) as usize][lane.kind as usize] += 1;
                }
            }
            touched.push(band_cells);
        }
        // Bands two apart share no particle.
        for i in 2..touched.len() {
            assert!(
                touched[i].is_disjoint(&touched[i - 2]),
                "bands {i} and {}",
                i - 2
            );
        }
        let (c, r) = (columns, rows);
        let total = (c - 1) * r + c * (r - 1) + 2 * (c - 1) * (r - 1) + (c - 2) * r + c * (r - 2);
        assert_eq!(springs.len() as u32, total, "{columns} x {rows}");
        if columns > 4 && rows > 4 {
            assert_eq!(per_particle[(2 * columns + 2) as usize], [4, 4, 4]);
        }
    }

    #[test]
    fn lanes_hold_every_grid_spring_once_and_bands_two_apart_share_nothing() {
        for (columns, rows, band) in [
            (2, 2, 3),
            (3, 2, 3),
            (4, 3, 3),
            (5, 7, 3),
            (8, 8, 3),
            (9, 6, 3),
            (16, 16, 4),
            (33, 17, 5),
            (64, 40, 8),
            (13, 9, 9),
            (32, 32, 32),
        ] {
            check(columns, rows, band);
        }
    }
}
