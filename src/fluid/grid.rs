//! The box the air is simulated in: its cells, its staggered faces, and trilinear sampling.
//!
//! Cell `(i, j, k)` covers `origin + cell × [i, i+1) × [j, j+1) × [k, k+1)` in world
//! axes. Scalars (temperature, smoke, pressure) live at cell centres; the velocity is
//! staggered (a MAC grid): its x component on the faces between cells along x, and so on,
//! so the divergence of a cell is the sum of its six face fluxes.

use glam::Vec3;

/// Where a field's samples sit inside a cell, in cells: centres are at `(0.5, 0.5, 0.5)`,
/// the x faces at `(0, 0.5, 0.5)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stagger(pub Vec3);

impl Stagger {
    /// Cell centres.
    pub const CENTRE: Self = Self(Vec3::splat(0.5));
    /// Faces between cells along `axis` (0 = x, 1 = y, 2 = z).
    pub const fn face(axis: usize) -> Self {
        match axis {
            0 => Self(Vec3::new(0.0, 0.5, 0.5)),
            1 => Self(Vec3::new(0.5, 0.0, 0.5)),
            _ => Self(Vec3::new(0.5, 0.5, 0.0)),
        }
    }
}

/// The shape of a grid: cells along each axis, cell size and where its corner is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridShape {
    /// Cells along x, y and z.
    pub dims: [usize; 3],
    /// Edge of a cubic cell, m.
    pub cell: f32,
    /// World position of the grid's minimum corner, m.
    pub origin: Vec3,
}

impl GridShape {
    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// Sample counts along each axis of the faces normal to `axis`.
    pub fn face_dims(&self, axis: usize) -> [usize; 3] {
        let mut dims = self.dims;
        dims[axis] += 1;
        dims
    }

    /// Number of faces normal to `axis`.
    pub fn faces(&self, axis: usize) -> usize {
        let [x, y, z] = self.face_dims(axis);
        x * y * z
    }

    /// Index of cell `(i, j, k)`.
    #[inline]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The two cells either side of face `at` normal to `axis`: (below, above); a face on
    /// the box's side has one of them missing.
    #[inline]
    pub fn face_cells(&self, axis: usize, at: [usize; 3]) -> (Option<usize>, Option<usize>) {
        let below = (at[axis] > 0).then(|| {
            let mut b = at;
            b[axis] -= 1;
            self.index(b[0], b[1], b[2])
        });
        let above = (at[axis] < self.dims[axis]).then(|| self.index(at[0], at[1], at[2]));
        (below, above)
    }

    /// The faces of row `(j, k)` of cells, per axis `(low, high)`: the `nx` faces on each
    /// cell's low side and the `nx` on its high side (along x the row's faces `0..nx` and
    /// `1..=nx`; along y the face rows below and above; along z the face layers).
    #[inline]
    pub fn face_rows<'a>(
        &self,
        velocity: &'a [Vec<f32>; 3],
        j: usize,
        k: usize,
    ) -> [(&'a [f32], &'a [f32]); 3] {
        let [nx, ny, _] = self.dims;
        let [u, v, w] = velocity;
        let (c, layer) = (nx * (j + ny * k), nx * ny);
        let fu = (nx + 1) * (j + ny * k);
        let fv = nx * (j + (ny + 1) * k);
        [
            (&u[fu..fu + nx], &u[fu + 1..fu + 1 + nx]),
            (&v[fv..fv + nx], &v[fv + nx..fv + 2 * nx]),
            (&w[c..c + nx], &w[c + layer..c + layer + nx]),
        ]
    }

    /// Of the faces `row` (a range of `i`) in row `(j, k)` of the faces normal to `axis`,
    /// those with a cell on both sides: along x all but the first and last face of the box;
    /// along y or z every face of a row that is not on the box's side, none of one that is.
    #[inline]
    pub fn inner_faces(
        &self,
        axis: usize,
        [j, k]: [usize; 2],
        row: core::ops::Range<usize>,
    ) -> core::ops::Range<usize> {
        let [nx, ny, nz] = self.dims;
        match axis {
            0 => {
                let start = row.start.max(1);
                start..row.end.min(nx).max(start)
            }
            1 if j == 0 || j == ny => 0..0,
            2 if k == 0 || k == nz => 0..0,
            _ => row,
        }
    }

    /// World size of the box, m.
    pub fn size(&self) -> Vec3 {
        Vec3::new(
            self.dims[0] as f32,
            self.dims[1] as f32,
            self.dims[2] as f32,
        ) * self.cell
    }

    /// Whether `point` lies inside the box.
    pub fn contains(&self, point: Vec3) -> bool {
        let local = point - self.origin;
        local.cmpge(Vec3::ZERO).all() && local.cmplt(self.size()).all()
    }

    /// World position of a sample `(i, j, k)` of a field staggered by `stagger`.
    #[inline]
    pub fn position(&self, i: usize, j: usize, k: usize, stagger: Stagger) -> Vec3 {
        self.origin + (Vec3::new(i as f32, j as f32, k as f32) + stagger.0) * self.cell
    }

    /// The trilinear stencil at `point` for a field of `dims` samples staggered by
    /// `stagger`: points outside the samples take the nearest sample's value.
    #[inline(always)]
    pub fn stencil(&self, point: Vec3, dims: [usize; 3], stagger: Stagger) -> Stencil {
        Self::stencil_at_sample(self.sample_coordinates(point) - stagger.0, dims)
    }

    /// The trilinear stencil at `g`, a point in a field's sample coordinates (sample `(i, j,
    /// k)` at `g = (i, j, k)`), for a field of `dims` samples.
    #[inline(always)]
    pub fn stencil_at_sample(g: Vec3, dims: [usize; 3]) -> Stencil {
        let (i, fx) = axis_cell(g.x, dims[0]);
        let (j, fy) = axis_cell(g.y, dims[1]);
        let (k, fz) = axis_cell(g.z, dims[2]);
        let sy = dims[0];
        let sz = dims[0] * dims[1];
        Stencil {
            base: i + sy * j + sz * k,
            step: [
                usize::from(dims[0] > 1),
                if dims[1] > 1 { sy } else { 0 },
                if dims[2] > 1 { sz } else { 0 },
            ],
            frac: [fx, fy, fz],
        }
    }

    /// Trilinear value of a field of `dims` samples staggered by `stagger` at `point`.
    #[inline(always)]
    pub fn sample(&self, field: &[f32], dims: [usize; 3], stagger: Stagger, point: Vec3) -> f32 {
        self.stencil(point, dims, stagger).apply(field)
    }

    /// The velocity of a staggered field `(u, v, w)` at `point`, m/s.
    #[inline]
    pub fn sample_velocity(&self, velocity: &[Vec<f32>; 3], point: Vec3) -> Vec3 {
        self.sample_velocity_at(velocity, self.sample_coordinates(point))
    }

    /// `point` in cells from the box's corner (cell `(i, j, k)` spans `i..i+1` along x).
    #[inline(always)]
    pub fn sample_coordinates(&self, point: Vec3) -> Vec3 {
        (point - self.origin) * (1.0 / self.cell)
    }

    /// [`GridShape::sample_velocity`] at `g`, a point in cells from the box's corner
    /// ([`GridShape::sample_coordinates`]).
    #[inline(always)]
    pub fn sample_velocity_at(&self, velocity: &[Vec<f32>; 3], g: Vec3) -> Vec3 {
        let component = |axis: usize| {
            Self::stencil_at_sample(g - Stagger::face(axis).0, self.face_dims(axis))
                .apply(&velocity[axis])
        };
        Vec3::new(component(0), component(1), component(2))
    }
}

/// The mean of `value` over a face's cells (from [`GridShape::face_cells`]): both when it
/// has two, the one on a side of the box, zero for none.
#[inline]
pub fn face_mean<T>(cells: (Option<usize>, Option<usize>), value: impl Fn(usize) -> T) -> T
where
    T: Default + core::ops::Add<Output = T> + core::ops::Mul<f32, Output = T>,
{
    match cells {
        (Some(a), Some(b)) => (value(a) + value(b)) * 0.5,
        (Some(c), None) | (None, Some(c)) => value(c),
        (None, None) => T::default(),
    }
}

/// The lower sample and the fraction towards the next along one axis of `n` samples, for a
/// coordinate `x` in samples; clamped to the samples, NaN to the first.
#[inline(always)]
fn axis_cell(x: f32, n: usize) -> (usize, f32) {
    // Through `u32`: a grid's side fits it, and a `u32` becomes an `f32` in one instruction
    // (a `usize` takes several); the values are the same.
    let top = (n - 1) as u32 as f32;
    // `max` first: NaN becomes 0.
    let x = x.max(0.0).min(top);
    // `x` is in `0..=top` here, so the 32-bit conversion (one instruction) is exact.
    let i = (x as i32 as u32).min(n.saturating_sub(2) as u32);
    (i as usize, (x - i as f32).min(1.0))
}

/// Eight samples and their weights around a point: built once, applied to any field with
/// the same layout.
#[derive(Clone, Copy, Debug)]
pub struct Stencil {
    base: usize,
    step: [usize; 3],
    frac: [f32; 3],
}

impl Stencil {
    /// The interpolated value of `field` at the stencil's point.
    #[inline(always)]
    pub fn apply(&self, field: &[f32]) -> f32 {
        let [dx, dy, dz] = self.step;
        let [fx, fy, fz] = self.frac;
        let cube = &field[self.base..=self.base + dx + dy + dz];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let c00 = lerp(cube[0], cube[dx], fx);
        let c10 = lerp(cube[dy], cube[dy + dx], fx);
        let c01 = lerp(cube[dz], cube[dz + dx], fx);
        let c11 = lerp(cube[dz + dy], cube[dz + dy + dx], fx);
        lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz)
    }

    /// Adds `amount` to `field` spread over the stencil's samples by their trilinear
    /// weights (the transpose of [`Stencil::apply`]: the weights sum to one).
    #[inline]
    pub fn splat(&self, field: &mut [f32], amount: f32) {
        let [dx, dy, dz] = self.step;
        let [fx, fy, fz] = self.frac;
        for (oz, wz) in [(0, 1.0 - fz), (dz, fz)] {
            for (oy, wy) in [(0, 1.0 - fy), (dy, fy)] {
                for (ox, wx) in [(0, 1.0 - fx), (dx, fx)] {
                    field[self.base + oz + oy + ox] += amount * wx * wy * wz;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape() -> GridShape {
        GridShape {
            dims: [4, 5, 6],
            cell: 0.5,
            origin: Vec3::new(-1.0, 0.0, 2.0),
        }
    }

    #[test]
    fn trilinear_sampling_reproduces_a_linear_field_exactly() {
        let shape = shape();
        let dims = shape.dims;
        let linear = |p: Vec3| 2.0 * p.x - 3.0 * p.y + 0.5 * p.z + 1.0;
        let mut field = vec![0.0; shape.cells()];
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    field[shape.index(i, j, k)] = linear(shape.position(i, j, k, Stagger::CENTRE));
                }
            }
        }
        for point in [
            Vec3::new(-0.3, 1.1, 3.3),
            Vec3::new(0.6, 2.2, 4.1),
            shape.position(1, 2, 3, Stagger::CENTRE),
        ] {
            let value = shape.sample(&field, dims, Stagger::CENTRE, point);
            assert!(
                (value - linear(point)).abs() < 1e-4,
                "{value} vs {}",
                linear(point)
            );
        }
    }

    #[test]
    fn splat_puts_the_whole_amount_down() {
        let shape = shape();
        let mut field = vec![0.0; shape.cells()];
        let stencil = shape.stencil(Vec3::new(0.1, 1.3, 3.7), shape.dims, Stagger::CENTRE);
        stencil.splat(&mut field, 2.5);
        let total: f32 = field.iter().sum();
        assert!((total - 2.5).abs() < 1e-5);
    }

    #[test]
    fn points_outside_take_the_nearest_value_and_never_panic() {
        let shape = shape();
        let field: Vec<f32> = (0..shape.cells()).map(|i| i as f32).collect();
        let far = shape.sample(&field, shape.dims, Stagger::CENTRE, Vec3::splat(1e9));
        assert_eq!(far, (shape.cells() - 1) as f32);
        let nan = shape.sample(&field, shape.dims, Stagger::CENTRE, Vec3::NAN);
        assert_eq!(nan, 0.0);
    }
}
