//! [`Plume`]: the air around a fire on a staggered grid, stepped as Stam's stable fluids:
//! advect, add forces, project.

use super::active::{ActiveSpans, BUSY_SMOKE, BUSY_SPEED, BUSY_TEMPERATURE};
use super::advect::{Advection, Decay, centre_velocity};
use super::forces::{VorticityScratch, add_buoyancy, add_vorticity_confinement, for_each_face};
use super::grid::{GridShape, Stagger};
use super::pressure::{PressureSolver, SolveReport, Wall};
use super::reduce::{max_abs, max_non_negative};
use super::settings::{AIR_HEAT_CAPACITY, PlumeSettings, PlumeSettingsError};
use bevy::tasks::TaskPool;
use glam::Vec3;

/// What the latest [`Plume::step`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlumeReport {
    /// Whether the step ran (false while the air is still and cold).
    pub stepped: bool,
    /// The pressure solve.
    pub solve: SolveReport,
    /// Largest divergence left in an air cell, 1/s.
    pub max_divergence: f32,
    /// Largest excess temperature, K.
    pub max_temperature: f32,
    /// Fastest face velocity, m/s.
    pub max_speed: f32,
    /// Cells advected: those near hot, smoky or moving air (the rest of the box is still).
    pub active_cells: usize,
}

/// The air of a fire: velocity on cell faces (m/s, relative to the uniform wind), excess
/// temperature over ambient (K) and smoke density at cell centres, in a box of
/// [`PlumeSettings::resolution`] cells.
#[derive(Clone, Debug)]
pub struct Plume {
    settings: PlumeSettings,
    shape: GridShape,
    velocity: [Vec<f32>; 3],
    temperature: Vec<f32>,
    smoke: Vec<f32>,
    solid: Vec<bool>,
    solver: PressureSolver,
    // Scratch, allocated once.
    next_velocity: [Vec<f32>; 3],
    next_temperature: Vec<f32>,
    next_smoke: Vec<f32>,
    centre: [Vec<f32>; 3],
    vorticity: VorticityScratch,
    rhs: Vec<f32>,
    active: ActiveSpans,
    /// One row of cells' busy flags ([`Plume::find_busy_air`]).
    busy: Vec<bool>,
    /// Per axis, the faces no air flows through: touching a solid cell or a closed wall.
    blocked: [Vec<u32>; 3],
    /// Whether heat, smoke or a push came in since the last step.
    fed: bool,
    /// Whether the air has settled to still, ambient and clear (steps do nothing).
    quiet: bool,
    report: PlumeReport,
}

/// Below these the air is still: excess temperature, K; speed, m/s; smoke density.
const QUIET_TEMPERATURE: f32 = 0.5;
const QUIET_SPEED: f32 = 0.05;
const QUIET_SMOKE: f32 = 1e-3;

impl Plume {
    /// Still, ambient air in a box whose minimum corner is at `origin` (m). Every buffer is
    /// allocated here, none in [`Plume::step`].
    pub fn new(settings: PlumeSettings, origin: Vec3) -> Result<Self, PlumeSettingsError> {
        settings.validate()?;
        if !origin.is_finite() {
            return Err(PlumeSettingsError(format!("origin {origin} is not finite")));
        }
        let shape = GridShape {
            dims: settings.resolution,
            cell: settings.cell_size,
            origin,
        };
        let n = shape.cells();
        let faces = || core::array::from_fn(|axis| vec![0.0; shape.faces(axis)]);
        let solid = vec![false; n];
        Ok(Self {
            solver: PressureSolver::new(&shape, &solid, settings.walls),
            settings,
            shape,
            velocity: faces(),
            temperature: vec![0.0; n],
            smoke: vec![0.0; n],
            solid,
            next_velocity: faces(),
            next_temperature: vec![0.0; n],
            next_smoke: vec![0.0; n],
            centre: core::array::from_fn(|_| vec![0.0; n]),
            vorticity: VorticityScratch::new(n),
            rhs: vec![0.0; n],
            active: ActiveSpans::new(&shape),
            busy: vec![false; shape.dims[0]],
            blocked: Default::default(),
            fed: false,
            quiet: true,
            report: PlumeReport::default(),
        }
        .with_blocked_faces())
    }

    /// The plume with its list of blocked faces made.
    fn with_blocked_faces(mut self) -> Self {
        self.find_blocked_faces();
        self
    }

    /// Lists, per axis, the faces no air flows through (touching a solid cell or a closed
    /// wall), reusing the lists' memory. Run when the solids change.
    fn find_blocked_faces(&mut self) {
        let walls = self.settings.walls.0;
        let solid = &self.solid;
        for (axis, list) in self.blocked.iter_mut().enumerate() {
            list.clear();
            for_each_face(&self.shape, axis, |face, cells| {
                let blocked = match cells {
                    (Some(a), Some(b)) => solid[a] || solid[b],
                    (None, Some(a)) => solid[a] || walls[axis][0] == Wall::Closed,
                    (Some(a), None) => solid[a] || walls[axis][1] == Wall::Closed,
                    (None, None) => true,
                };
                if blocked {
                    list.push(face as u32);
                }
            });
        }
    }

    /// Takes new rates and strengths (buoyancy, vorticity, cooling, what the fire gives the
    /// air, ...) without disturbing the air. Settings that change the grid (resolution, cell
    /// size, walls) need a new plume: they are an error here, as are invalid ones.
    pub fn retune(&mut self, settings: PlumeSettings) -> Result<(), PlumeSettingsError> {
        settings.validate()?;
        let grid = |s: &PlumeSettings| (s.resolution, s.cell_size, s.walls);
        if grid(&settings) != grid(&self.settings) {
            return Err(PlumeSettingsError(
                "the resolution, cell size or walls changed: build a new plume".to_owned(),
            ));
        }
        self.settings = settings;
        Ok(())
    }

    /// The settings in use.
    pub fn settings(&self) -> &PlumeSettings {
        &self.settings
    }

    /// The grid: cells, cell size and where the box is.
    pub fn shape(&self) -> &GridShape {
        &self.shape
    }

    /// What the latest step did.
    pub fn report(&self) -> &PlumeReport {
        &self.report
    }

    /// Whether the air is still, ambient and clear, so steps cost nothing.
    pub fn is_quiet(&self) -> bool {
        self.quiet && !self.fed
    }

    /// Staggered velocity components (x faces, y faces, z faces), m/s.
    pub fn velocity(&self) -> &[Vec<f32>; 3] {
        &self.velocity
    }

    /// Mutable velocity faces (for tests and scripted gusts); wakes the air.
    pub fn velocity_mut(&mut self) -> &mut [Vec<f32>; 3] {
        self.fed = true;
        &mut self.velocity
    }

    /// Excess temperature over ambient per cell, K.
    pub fn temperature(&self) -> &[f32] {
        &self.temperature
    }

    /// Mutable excess temperatures (for tests and scripted sources); wakes the air.
    pub fn temperature_mut(&mut self) -> &mut [f32] {
        self.fed = true;
        &mut self.temperature
    }

    /// Smoke density per cell (1 is thick smoke).
    pub fn smoke(&self) -> &[f32] {
        &self.smoke
    }

    /// Mutable smoke densities; wakes the air.
    pub fn smoke_mut(&mut self) -> &mut [f32] {
        self.fed = true;
        &mut self.smoke
    }

    /// Which cells are solid.
    pub fn solid(&self) -> &[bool] {
        &self.solid
    }

    /// Marks the cells whose centre `is_solid` says is inside something solid; the pressure
    /// solver is rebuilt only when the set changes. Solid cells hold no heat or smoke.
    pub fn set_solids(&mut self, is_solid: impl Fn(Vec3) -> bool) {
        let mut changed = false;
        let [nx, ny, nz] = self.shape.dims;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let c = self.shape.index(i, j, k);
                    let solid = is_solid(self.shape.position(i, j, k, Stagger::CENTRE));
                    changed |= solid != self.solid[c];
                    self.solid[c] = solid;
                }
            }
        }
        if changed {
            self.solver = PressureSolver::new(&self.shape, &self.solid, self.settings.walls);
            self.find_blocked_faces();
            for (c, solid) in self.solid.iter().enumerate() {
                if *solid {
                    self.temperature[c] = 0.0;
                    self.smoke[c] = 0.0;
                }
            }
        }
    }

    /// Moves the box so its minimum corner is as near `origin` as a whole number of cells
    /// allows, carrying the air along: cells that stay inside keep their state, cells that
    /// enter are still and ambient. Returns whether it moved.
    pub fn move_towards(&mut self, origin: Vec3) -> bool {
        if !origin.is_finite() {
            return false;
        }
        let shift = ((origin - self.shape.origin) / self.shape.cell).round();
        if shift == Vec3::ZERO {
            return false;
        }
        let shift = [shift.x as i64, shift.y as i64, shift.z as i64];
        let dims = self.shape.dims;
        let moved = |field: &mut Vec<f32>, scratch: &mut Vec<f32>, dims: [usize; 3]| {
            scratch.fill(0.0);
            for k in 0..dims[2] {
                for j in 0..dims[1] {
                    for i in 0..dims[0] {
                        let from = [
                            i as i64 + shift[0],
                            j as i64 + shift[1],
                            k as i64 + shift[2],
                        ];
                        if (0..3).all(|a| from[a] >= 0 && from[a] < dims[a] as i64) {
                            let f = from[0] as usize
                                + dims[0] * (from[1] as usize + dims[1] * from[2] as usize);
                            scratch[i + dims[0] * (j + dims[1] * k)] = field[f];
                        }
                    }
                }
            }
            core::mem::swap(field, scratch);
        };
        moved(&mut self.temperature, &mut self.next_temperature, dims);
        moved(&mut self.smoke, &mut self.next_smoke, dims);
        for axis in 0..3 {
            let face_dims = self.shape.face_dims(axis);
            moved(
                &mut self.velocity[axis],
                &mut self.next_velocity[axis],
                face_dims,
            );
        }
        self.solver.solution.fill(0.0);
        self.shape.origin +=
            Vec3::new(shift[0] as f32, shift[1] as f32, shift[2] as f32) * self.shape.cell;
        true
    }

    /// Adds `energy` joules of heat to the air at `point` (spread over the eight nearest
    /// cells), raising their temperature by `energy / (ρ c_p V)`. Heat outside the box, or
    /// not finite, is ignored.
    pub fn add_heat(&mut self, point: Vec3, energy: f32) {
        if !(energy.is_finite() && point.is_finite() && self.shape.contains(point)) {
            return;
        }
        let volume = self.shape.cell.powi(3);
        let rise = energy / (AIR_HEAT_CAPACITY * volume);
        self.shape
            .stencil(point, self.shape.dims, Stagger::CENTRE)
            .splat(&mut self.temperature, rise);
        self.fed = true;
    }

    /// Adds `amount` of smoke (density × m³) at `point`, spread over the nearest cells.
    pub fn add_smoke(&mut self, point: Vec3, amount: f32) {
        if !(amount.is_finite() && point.is_finite() && self.shape.contains(point)) {
            return;
        }
        let volume = self.shape.cell.powi(3);
        self.shape
            .stencil(point, self.shape.dims, Stagger::CENTRE)
            .splat(&mut self.smoke, amount / volume);
        self.fed = true;
    }

    /// Air velocity at `point` relative to the wind, m/s; zero outside the box.
    pub fn velocity_at(&self, point: Vec3) -> Vec3 {
        if !self.shape.contains(point) || self.is_quiet() {
            return Vec3::ZERO;
        }
        self.shape.sample_velocity(&self.velocity, point)
    }

    /// Excess temperature of the air at `point` over ambient, K; zero outside the box.
    pub fn temperature_at(&self, point: Vec3) -> f32 {
        if !self.shape.contains(point) || self.is_quiet() {
            return 0.0;
        }
        self.shape
            .sample(&self.temperature, self.shape.dims, Stagger::CENTRE, point)
    }

    /// The air at `point`: its velocity relative to the wind, m/s, and its excess
    /// temperature over ambient, K ([`Plume::velocity_at`] and [`Plume::temperature_at`] in
    /// one, the point converted once); `None` outside the box or while the air is quiet.
    #[inline]
    pub fn air_at(&self, point: Vec3) -> Option<(Vec3, f32)> {
        if !self.shape.contains(point) || self.is_quiet() {
            return None;
        }
        let g = self.shape.sample_coordinates(point);
        let velocity = self.shape.sample_velocity_at(&self.velocity, g);
        let temperature = GridShape::stencil_at_sample(g - Stagger::CENTRE.0, self.shape.dims)
            .apply(&self.temperature);
        Some((velocity, temperature))
    }

    /// Smoke density at `point`; zero outside the box.
    pub fn smoke_at(&self, point: Vec3) -> f32 {
        if !self.shape.contains(point) || self.is_quiet() {
            return 0.0;
        }
        self.shape
            .sample(&self.smoke, self.shape.dims, Stagger::CENTRE, point)
    }

    /// Total smoke in the box, density × m³.
    pub fn total_smoke(&self) -> f64 {
        let volume = f64::from(self.shape.cell).powi(3);
        self.smoke.iter().map(|s| f64::from(*s)).sum::<f64>() * volume
    }

    /// Advances the air `dt` seconds in a uniform `wind` (m/s) with `up` the direction hot
    /// air rises: advection by the current (divergence-free) velocity, cooling, buoyancy,
    /// vorticity confinement, then the pressure projection that makes the velocity
    /// divergence-free again. Does nothing while the air is quiet and nothing fed it.
    pub fn step(&mut self, dt: f32, wind: Vec3, up: Vec3) -> PlumeReport {
        self.step_on(dt, wind, up, None)
    }

    /// [`Plume::step`] with the advection split over `pool`'s threads (feature `parallel`);
    /// the result is the same on any number of threads.
    pub fn step_on(
        &mut self,
        dt: f32,
        wind: Vec3,
        up: Vec3,
        pool: Option<&TaskPool>,
    ) -> PlumeReport {
        if !(dt.is_finite() && dt > 0.0 && wind.is_finite()) || self.is_quiet() {
            self.report = PlumeReport::default();
            return self.report;
        }
        let up = up.normalize_or(Vec3::Y);
        let shape = self.shape;
        centre_velocity(&shape, &self.velocity, &mut self.centre);
        self.find_busy_air(dt, wind);
        let advection = Advection {
            shape: &shape,
            centre: &self.centre,
            wind,
            walls: &self.settings.walls,
            active: &self.active,
            dt,
            decay: Decay {
                velocity: (-self.settings.damping * dt).exp(),
                temperature: (-self.settings.cooling * dt).exp(),
                smoke: (-self.settings.smoke_decay * dt).exp(),
                hottest: self.settings.max_temperature,
            },
        };
        advection.fields(
            &self.solid,
            (
                [&self.temperature, &self.smoke],
                [&mut self.next_temperature, &mut self.next_smoke],
            ),
            (&self.velocity, &mut self.next_velocity),
            pool,
        );
        core::mem::swap(&mut self.temperature, &mut self.next_temperature);
        core::mem::swap(&mut self.smoke, &mut self.next_smoke);
        core::mem::swap(&mut self.velocity, &mut self.next_velocity);

        add_buoyancy(
            &shape,
            &self.active,
            [&self.temperature, &self.smoke],
            up * dt,
            [self.settings.buoyancy, self.settings.smoke_weight],
            &mut self.velocity,
        );
        centre_velocity(&shape, &self.velocity, &mut self.centre);
        add_vorticity_confinement(
            &shape,
            &self.active,
            &self.centre,
            &self.temperature,
            [self.settings.vorticity, dt],
            &mut self.vorticity,
            &mut self.velocity,
        );
        let solve = self.project(pool);
        self.fed = false;
        let max_temperature = max_abs(&self.temperature);
        let max_speed = self.velocity.iter().map(|v| max_abs(v)).fold(0.0, f32::max);
        let max_smoke = max_non_negative(&self.smoke);
        self.quiet = max_temperature < QUIET_TEMPERATURE
            && max_speed < QUIET_SPEED
            && max_smoke < QUIET_SMOKE;
        if self.quiet {
            self.temperature.fill(0.0);
            self.smoke.fill(0.0);
            self.velocity.iter_mut().for_each(|v| v.fill(0.0));
            self.solver.solution.fill(0.0);
        }
        self.report = PlumeReport {
            stepped: true,
            solve,
            max_divergence: self.divergence_left(),
            max_temperature,
            max_speed,
            active_cells: self.active.active_cells(),
        };
        self.report
    }

    /// Updates the active spans: the cells whose air is hotter, smokier or faster than the
    /// busy thresholds, grown by the farthest the air travels in `dt` plus one cell.
    fn find_busy_air(&mut self, dt: f32, wind: Vec3) {
        let shape = self.shape;
        let fastest = self.velocity.iter().map(|v| max_abs(v)).fold(0.0, f32::max);
        let travel = (fastest * 3f32.sqrt() + wind.length()) * dt / shape.cell;
        let largest = shape.dims.into_iter().max().unwrap_or(1);
        if !travel.is_finite() || travel >= largest as f32 {
            self.active.all(&shape);
            return;
        }
        let reach = travel.ceil() as usize + 1;
        let velocity = &self.velocity;
        let (temperature, smoke, flags) = (&self.temperature, &self.smoke, &mut self.busy);
        let [nx, ny, _] = shape.dims;
        self.active.update_rows(&shape, reach, |j, k| {
            // A row at a time, in loops over slices that the compiler turns into SIMD: a cell
            // is busy when hot, smoky, or one of its six faces is fast.
            let c = nx * (j + ny * k);
            let (t, s) = (&temperature[c..c + nx], &smoke[c..c + nx]);
            let [(west, east), (south, north), (below, above)] = shape.face_rows(velocity, j, k);
            let fast = |a: f32| a.abs() > BUSY_SPEED;
            let flags = &mut flags[..nx];
            for i in 0..nx {
                flags[i] = (t[i].abs() > BUSY_TEMPERATURE)
                    | (s[i] > BUSY_SMOKE)
                    | fast(west[i])
                    | fast(east[i])
                    | fast(south[i])
                    | fast(north[i])
                    | fast(below[i])
                    | fast(above[i]);
            }
            let first = flags.iter().position(|&f| f)?;
            Some([first, flags.iter().rposition(|&f| f).unwrap_or(first)])
        });
    }

    /// Zeroes the faces no air flows through (those touching a solid cell or a closed wall),
    /// solves for the pressure that removes the divergence, and subtracts its gradient.
    fn project(&mut self, pool: Option<&TaskPool>) -> SolveReport {
        let shape = self.shape;
        self.zero_blocked_faces();
        // b = −h² ∇·u = −h Σ (outflow − inflow)
        divergence(&shape, &self.velocity, &mut self.rhs);
        let h = shape.cell;
        for (b, s) in self.rhs.iter_mut().zip(&self.solid) {
            *b = if *s { 0.0 } else { -*b * h * h };
        }
        let report = self.solver.solve_on(
            &self.rhs,
            self.settings.tolerance * h * h,
            self.settings.max_iterations,
            pool,
        );
        // φ is zero beyond open walls and in solid cells; the faces into solids and closed
        // walls, which this also changes, are zeroed again after.
        subtract_gradient(&shape, &self.solver.solution, &mut self.velocity);
        self.zero_blocked_faces();
        SolveReport {
            iterations: report.iterations,
            residual: report.residual / (h * h),
        }
    }

    /// Zeroes the velocity on the faces no air flows through.
    fn zero_blocked_faces(&mut self) {
        for (faces, blocked) in self.velocity.iter_mut().zip(&self.blocked) {
            for &face in blocked {
                faces[face as usize] = 0.0;
            }
        }
    }

    /// Largest `|∇·u|` over the air cells, 1/s (into the scratch right-hand side).
    fn divergence_left(&mut self) -> f32 {
        divergence(&self.shape, &self.velocity, &mut self.rhs);
        largest_over_air(&self.rhs, &self.solid)
    }

    /// Largest `|∇·u|` over the air cells now, 1/s. Allocates a scratch field: for tests
    /// and tools, not for every frame ([`PlumeReport::max_divergence`] has it after a step).
    pub fn max_divergence(&self) -> f32 {
        let mut div = vec![0.0; self.shape.cells()];
        divergence(&self.shape, &self.velocity, &mut div);
        largest_over_air(&div, &self.solid)
    }
}

/// `u −= ∇φ` on every face, `(φ_above − φ_below) / h`, with `φ = 0` beyond the box: row by
/// row, each row's faces from the one or two rows of cells beside them, in loops the compiler
/// turns into SIMD.
fn subtract_gradient(shape: &GridShape, phi: &[f32], velocity: &mut [Vec<f32>; 3]) {
    let [nx, ny, nz] = shape.dims;
    let h = shape.cell;
    let cells = |j: usize, k: usize| &phi[nx * (j + ny * k)..nx * (j + ny * k) + nx];
    // Along x: a row of nx + 1 faces over one row of cells.
    for k in 0..nz {
        for j in 0..ny {
            let first = (nx + 1) * (j + ny * k);
            let faces = &mut velocity[0][first..first + nx + 1];
            let row = cells(j, k);
            faces[0] -= row[0] / h;
            for i in 1..nx {
                faces[i] -= (row[i] - row[i - 1]) / h;
            }
            faces[nx] -= (0.0 - row[nx - 1]) / h;
        }
    }
    // Along y and z: a row of nx faces between the rows of cells below and above (none
    // beyond the box).
    let between =
        |faces: &mut [f32], below: Option<&[f32]>, above: Option<&[f32]>| match (below, above) {
            (Some(below), Some(above)) => {
                for ((u, b), a) in faces.iter_mut().zip(below).zip(above) {
                    *u -= (a - b) / h;
                }
            }
            (None, Some(above)) => {
                for (u, a) in faces.iter_mut().zip(above) {
                    *u -= (a - 0.0) / h;
                }
            }
            (Some(below), None) => {
                for (u, b) in faces.iter_mut().zip(below) {
                    *u -= (0.0 - b) / h;
                }
            }
            (None, None) => {}
        };
    for k in 0..nz {
        for j in 0..=ny {
            let first = nx * (j + (ny + 1) * k);
            let below = (j > 0).then(|| cells(j - 1, k));
            let above = (j < ny).then(|| cells(j, k));
            between(&mut velocity[1][first..first + nx], below, above);
        }
    }
    for k in 0..=nz {
        for j in 0..ny {
            let first = nx * (j + ny * k);
            let below = (k > 0).then(|| cells(j, k - 1));
            let above = (k < nz).then(|| cells(j, k));
            between(&mut velocity[2][first..first + nx], below, above);
        }
    }
}

/// The largest `|value|` over the cells that are not solid.
fn largest_over_air(values: &[f32], solid: &[bool]) -> f32 {
    values
        .iter()
        .zip(solid)
        .filter(|(_, s)| !**s)
        .fold(0.0f32, |m, (d, _)| m.max(d.abs()))
}

/// `∇·u` per cell, 1/s: the net outflow through its six faces over its size; a row of cells
/// at a time, in loops over slices that the compiler turns into SIMD.
fn divergence(shape: &GridShape, velocity: &[Vec<f32>; 3], out: &mut [f32]) {
    let [nx, ny, nz] = shape.dims;
    for k in 0..nz {
        for j in 0..ny {
            let c = nx * (j + ny * k);
            let [(west, east), (south, north), (below, above)] = shape.face_rows(velocity, j, k);
            let out = &mut out[c..c + nx];
            for i in 0..nx {
                out[i] =
                    (east[i] - west[i] + north[i] - south[i] + above[i] - below[i]) / shape.cell;
            }
        }
    }
}
