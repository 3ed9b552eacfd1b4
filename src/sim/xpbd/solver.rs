//! [`XpbdSolver`]: one cloth's XPBD state and the substep loop.

use super::adjacency::Adjacency;
use super::kernel::{Arrays, RunData, project_indexed, project_lane};
use super::lanes::{GridLanes, GridSlots};
use crate::sim::collision::WorldCollider;
use crate::sim::forces::ForceParams;
use crate::sim::guard::GuardSettings;
use crate::sim::particles::Particles;
use crate::sim::springs::{SpringCoefficients, SpringKind, Springs};
use crate::sim::topology::GridShape;

/// Rows per band of a grid: bands two apart are independent.
const BAND_ROWS: u32 = 16;

/// No spring: a lane element past the grid's edge.
const PHANTOM: u32 = u32::MAX;

/// How the springs are walked.
#[derive(Clone, Debug, Default, PartialEq)]
enum Layout {
    /// Not built yet.
    #[default]
    Unset,
    /// A grid: particles in quarter grids, springs in lanes; element `e` of the lanes stands
    /// for spring `spring[e]` ([`PHANTOM`] for none).
    Grid {
        slots: GridSlots,
        lanes: GridLanes,
        spring: Vec<u32>,
    },
    /// Springs in their stored order, ends by index (meshes, hand-made springs): element `e`
    /// is spring `e`, slot `i` is particle `i`.
    Indexed,
}

/// What the spring factors were computed for; a change recomputes them all.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FactorKey {
    h: f32,
    coefficients: SpringCoefficients,
}

/// What one cloth needs around it for a frame of substeps.
#[derive(Clone, Copy, Debug)]
pub struct Surroundings<'a> {
    /// Gravity, wind, drag and spring coefficients.
    pub params: &'a ForceParams,
    /// Colliders in world space.
    pub colliders: &'a [WorldCollider],
    /// Distance particles keep from colliders, m.
    pub margin: f32,
    /// The blow-up guard's limits.
    pub guard: GuardSettings,
}

/// One cloth's XPBD solver: particle state as separate `f32` arrays in the solver's own order
/// (slots), one entry per spring (elements) for rest lengths and correction factors, and the
/// buffers of a substep. Built on first use from the cloth's springs and rebuilt when their
/// number changes; it allocates nothing after that.
#[derive(Clone, Debug, Default)]
pub struct XpbdSolver {
    layout: Layout,
    /// Springs and particles the layout was built for.
    built_for: (usize, usize),
    /// Each particle's slot.
    slot: Vec<u32>,
    /// The elements each particle is in (as an end, or the particle a bend passes over).
    adjacency: Adjacency,
    /// Positions at the start of the substep, m, by slot.
    x: [Vec<f32>; 3],
    /// Velocities, m/s, by slot.
    v: [Vec<f32>; 3],
    /// Displacement since the start of the substep, m, by slot: `h v` from the prediction
    /// plus the corrections.
    u: [Vec<f32>; 3],
    /// Acceleration from gravity, wind drag and external forces, m/s², by slot.
    acceleration: [Vec<f32>; 3],
    /// 1 for particles the solver moves freely, 0 for pins, burnt particles and padding.
    free: Vec<f32>,
    /// 1 for particles that move at all (free ones and pins following their anchor).
    moving: Vec<f32>,
    /// Inverse mass used by the constraints, 1/kg, by particle: zero for pins and burnt
    /// particles.
    w: Vec<f32>,
    /// Per element: rest length (m), and `w_a / ((1 + γ)(w_a + w_b) + α̃)` and the same with
    /// `w_b` (zero for a dead spring or a phantom).
    rest: Vec<f32>,
    ca: Vec<f32>,
    cb: Vec<f32>,
    /// Damping factor `γ = c / (k h)` per spring kind.
    gamma: [f32; 3],
    factors_for: Option<FactorKey>,
    /// Particles whose inverse mass changed since the factors were computed.
    dirty: Vec<u32>,
}

impl XpbdSolver {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        let floats: usize = [&self.x, &self.v, &self.u, &self.acceleration]
            .iter()
            .flat_map(|a| a.iter())
            .map(Vec::capacity)
            .sum::<usize>()
            + [
                &self.free,
                &self.moving,
                &self.w,
                &self.rest,
                &self.ca,
                &self.cb,
            ]
            .iter()
            .map(|a| a.capacity())
            .sum::<usize>();
        let layout = match &self.layout {
            Layout::Grid { lanes, spring, .. } => {
                lanes.lanes.capacity() * size_of::<super::lanes::Lane>()
                    + lanes.bands.capacity() * size_of::<std::ops::Range<usize>>()
                    + spring.capacity() * size_of::<u32>()
            }
            _ => 0,
        };
        (floats + self.slot.capacity() + self.dirty.capacity()) * size_of::<f32>()
            + layout
            + self.adjacency.heap_bytes()
    }

    /// Lays the solver out for these particles and springs if it is not already.
    fn prepare(&mut self, particles: &Particles, springs: &Springs, grid: Option<GridShape>) {
        let n = particles.len();
        if self.layout != Layout::Unset && self.built_for == (springs.len(), n) {
            return;
        }
        self.built_for = (springs.len(), n);
        self.layout = grid
            .and_then(|grid| grid_layout(grid, springs, n))
            .unwrap_or(Layout::Indexed);
        self.slot.clear();
        let (slots, elements) = match &self.layout {
            Layout::Grid {
                slots,
                lanes,
                spring,
            } => {
                let columns = grid.map_or(1, |g| g.columns);
                self.slot
                    .extend((0..n as u32).map(|i| slots.slot(i % columns, i / columns)));
                // Element e is in particle i's row when i is one of its spring's ends or
                // the particle it spans.
                self.adjacency
                    .build(n, spring.len(), |e| members(springs, spring[e as usize]));
                (slots.len(), lanes.elements as usize)
            }
            _ => {
                self.slot.extend(0..n as u32);
                self.adjacency
                    .build(n, springs.len(), |s| members(springs, s));
                (n, springs.len())
            }
        };
        for array in self
            .x
            .iter_mut()
            .chain(&mut self.v)
            .chain(&mut self.u)
            .chain(&mut self.acceleration)
        {
            array.clear();
            array.resize(slots, 0.0);
        }
        for array in [&mut self.free, &mut self.moving] {
            array.clear();
            array.resize(slots, 0.0);
        }
        self.w.clear();
        self.w.resize(n, f32::NAN);
        for array in [&mut self.rest, &mut self.ca, &mut self.cb] {
            array.clear();
            array.resize(elements, 0.0);
        }
        self.dirty.clear();
        self.dirty.reserve(n);
        self.factors_for = None;
    }

    /// Advances the cloth `substeps` substeps of `h` seconds each: the particles are read
    /// once, stepped in the solver's arrays and written back once. Returns the particles the
    /// blow-up guard put back (their position at the start, at rest).
    pub fn advance(
        &mut self,
        particles: &mut Particles,
        springs: &Springs,
        grid: Option<GridShape>,
        around: &Surroundings,
        h: f32,
        substeps: u32,
    ) -> u32 {
        if particles.is_empty() || !(h.is_finite() && h > 0.0) {
            return 0;
        }
        self.prepare(particles, springs, grid);
        let frame = h * substeps as f32;
        self.read(particles, springs, around.params, frame);
        self.update_factors(particles, springs, &around.params.coefficients, h);
        let drag = around.params.drag_per_mass.max(0.0);
        for substep in 0..substeps {
            if substep == 0 {
                self.predict(h, drag);
            }
            self.project_springs(springs);
            if !around.colliders.is_empty() {
                self.collide(around.colliders, around.margin);
            }
            self.finish_substep(h, drag, substep + 1 < substeps);
        }
        self.write(particles, &around.guard)
    }

    /// Copies the particles in (and a grid's rest lengths into lane order). Pins start where
    /// they were a frame ago (their anchor moved them to this frame's target already) and move
    /// there over the substeps.
    fn read(&mut self, particles: &Particles, springs: &Springs, params: &ForceParams, frame: f32) {
        let drag = params.drag_per_mass.max(0.0);
        let constant = params.gravity + drag * params.wind;
        let n = particles.len();
        let Self {
            slot,
            x: [x0, x1, x2],
            v: [v0, v1, v2],
            acceleration: [a0, a1, a2],
            free,
            moving,
            w,
            dirty,
            ..
        } = self;
        let p = particles;
        for i in 0..n {
            let burnt = p.state[i].is_burnt();
            let pinned = p.inv_mass[i] == 0.0;
            let mass_inverse = if burnt { 0.0 } else { p.inv_mass[i] };
            if mass_inverse.to_bits() != w[i].to_bits() {
                w[i] = mass_inverse;
                dirty.push(i as u32);
            }
            let is_free = !burnt && !pinned;
            let s = slot[i] as usize;
            free[s] = if is_free { 1.0 } else { 0.0 };
            moving[s] = if burnt { 0.0 } else { 1.0 };
            let (position, velocity) = (p.position[i], p.velocity[i]);
            let start = if pinned && !burnt {
                position - frame * velocity
            } else {
                position
            };
            let a = if is_free {
                constant + p.external_force[i] * mass_inverse
            } else {
                glam::Vec3::ZERO
            };
            (x0[s], x1[s], x2[s]) = (start.x, start.y, start.z);
            (v0[s], v1[s], v2[s]) = (velocity.x, velocity.y, velocity.z);
            (a0[s], a1[s], a2[s]) = (a.x, a.y, a.z);
        }
        if let Layout::Grid { spring, .. } = &self.layout {
            let lengths = &springs.rest_length;
            for (rest, &s) in self.rest.iter_mut().zip(spring) {
                *rest = if s == PHANTOM {
                    0.0
                } else {
                    lengths[s as usize]
                };
            }
        }
    }

    /// Recomputes the spring factors: all of them when the step or the coefficients
    /// changed, else those of the springs of particles whose inverse mass changed.
    fn update_factors(
        &mut self,
        particles: &Particles,
        springs: &Springs,
        coefficients: &SpringCoefficients,
        h: f32,
    ) {
        let key = FactorKey {
            h,
            coefficients: *coefficients,
        };
        let mut dirty = std::mem::take(&mut self.dirty);
        let spring_of = |e: usize| match &self.layout {
            Layout::Grid { spring, .. } => spring[e],
            _ => e as u32,
        };
        let factors = Factors {
            w: &self.w,
            gamma: if self.factors_for == Some(key) {
                self.gamma
            } else {
                damping_factors(coefficients, h)
            },
            particles,
            springs,
            coefficients,
            h,
        };
        if self.factors_for != Some(key) {
            for e in 0..self.ca.len() {
                (self.ca[e], self.cb[e]) = factors.of(spring_of(e));
            }
            self.gamma = factors.gamma;
            self.factors_for = Some(key);
        } else {
            for &i in &dirty {
                for &e in self.adjacency.of(i as usize) {
                    let e = e as usize;
                    (self.ca[e], self.cb[e]) = factors.of(spring_of(e));
                }
            }
        }
        dirty.clear();
        self.dirty = dirty;
    }

    /// Velocities take the outside accelerations (drag implicitly, so any step is stable) and
    /// the particles move with them: `u = h v`.
    fn predict(&mut self, h: f32, drag: f32) {
        let keep = 1.0 / (1.0 + h * drag);
        let n = self.free.len();
        let (free, moving) = (&self.free[..n], &self.moving[..n]);
        for axis in 0..3 {
            let v = &mut self.v[axis][..n];
            let a = &self.acceleration[axis][..n];
            let u = &mut self.u[axis][..n];
            for i in 0..n {
                let accelerated = (v[i] + h * a[i]) * keep;
                v[i] += free[i] * (accelerated - v[i]);
                u[i] = moving[i] * h * v[i];
            }
        }
    }

    /// One Gauss–Seidel pass over every spring: a grid's even bands, then its odd bands; a
    /// mesh's springs in stored order.
    fn project_springs(&mut self, springs: &Springs) {
        let [x0, x1, x2] = &self.x;
        let [u0, u1, u2] = &mut self.u;
        let mut arrays = Arrays {
            x: [x0, x1, x2],
            u: [u0, u1, u2],
        };
        match &self.layout {
            Layout::Grid { lanes, .. } => {
                for parity in 0..2 {
                    for band in lanes.bands.iter().skip(parity).step_by(2) {
                        for lane in &lanes.lanes[band.clone()] {
                            let elements = lane.first as usize..(lane.first + lane.len) as usize;
                            let data = RunData {
                                rest: &self.rest[elements.clone()],
                                ca: &self.ca[elements.clone()],
                                cb: &self.cb[elements],
                                gamma: self.gamma[lane.kind as usize],
                            };
                            let (a, b, len) = (lane.a as usize, lane.b as usize, lane.len as usize);
                            project_lane(&mut arrays, a, b, len, data);
                        }
                    }
                }
            }
            Layout::Indexed => {
                // A stretch of springs of one kind at a time (each kind has its own damping).
                let n = springs.len();
                let mut start = 0;
                while start < n {
                    let kind = springs.kind[start];
                    let end = (start..n).find(|&s| springs.kind[s] != kind).unwrap_or(n);
                    let data = RunData {
                        rest: &springs.rest_length[start..end],
                        ca: &self.ca[start..end],
                        cb: &self.cb[start..end],
                        gamma: self.gamma[kind as usize],
                    };
                    let (a, b) = (&springs.a[start..end], &springs.b[start..end]);
                    project_indexed(&mut arrays, a, b, data);
                    start = end;
                }
            }
            Layout::Unset => {}
        }
    }

    /// Pushes free particles out of colliders, taking `friction` of their sliding motion.
    fn collide(&mut self, colliders: &[WorldCollider], margin: f32) {
        for i in 0..self.free.len() {
            if self.free[i] == 0.0 {
                continue;
            }
            let x = glam::Vec3::new(self.x[0][i], self.x[1][i], self.x[2][i]);
            for collider in colliders {
                let u = glam::Vec3::new(self.u[0][i], self.u[1][i], self.u[2][i]);
                let (distance, normal) = collider.distance(x + u);
                if distance >= margin || distance.is_nan() {
                    continue;
                }
                let pushed = u + normal * (margin - distance);
                let sliding = pushed - normal * pushed.dot(normal);
                let moved = pushed - sliding * collider.friction.clamp(0.0, 1.0);
                for axis in 0..3 {
                    self.u[axis][i] = moved[axis];
                }
            }
        }
    }

    /// Free particles take their velocity from their displacement over the substep; every
    /// particle moves by it. With `predict_next`, the next substep's prediction follows in the
    /// same pass.
    fn finish_substep(&mut self, h: f32, drag: f32, predict_next: bool) {
        let inverse = 1.0 / h;
        let keep = 1.0 / (1.0 + h * drag);
        let n = self.free.len();
        let (free, moving) = (&self.free[..n], &self.moving[..n]);
        for axis in 0..3 {
            let x = &mut self.x[axis][..n];
            let v = &mut self.v[axis][..n];
            let u = &mut self.u[axis][..n];
            let a = &self.acceleration[axis][..n];
            if predict_next {
                for i in 0..n {
                    x[i] += u[i];
                    let velocity = v[i] + free[i] * (u[i] * inverse - v[i]);
                    let accelerated = (velocity + h * a[i]) * keep;
                    v[i] = velocity + free[i] * (accelerated - velocity);
                    u[i] = moving[i] * h * v[i];
                }
            } else {
                for i in 0..n {
                    v[i] += free[i] * (u[i] * inverse - v[i]);
                    x[i] += u[i];
                }
            }
        }
    }

    /// Copies the free particles back, putting back any that went non-finite or ran away
    /// (position as at the start, at rest). Pins keep their target; burnt particles do not
    /// move. Returns how many were put back.
    fn write(&self, particles: &mut Particles, guard: &GuardSettings) -> u32 {
        let mut repaired = 0;
        let max_speed_squared = guard.max_speed * guard.max_speed;
        for i in 0..particles.len() {
            let slot = self.slot[i] as usize;
            if self.free[slot] == 0.0 {
                continue;
            }
            let p = glam::Vec3::new(self.x[0][slot], self.x[1][slot], self.x[2][slot]);
            let v = glam::Vec3::new(self.v[0][slot], self.v[1][slot], self.v[2][slot]);
            let blown =
                !(p.is_finite() && v.is_finite() && v.length_squared() <= max_speed_squared);
            if guard.enabled && blown {
                particles.velocity[i] = glam::Vec3::ZERO;
                repaired += 1;
            } else {
                particles.position[i] = p;
                particles.velocity[i] = v;
            }
        }
        repaired
    }
}

/// The particles a spring involves: its ends and the particles it passes over.
fn members(springs: &Springs, s: u32) -> [u32; 4] {
    let Some(s) = (s != PHANTOM).then_some(s as usize) else {
        return [PHANTOM; 4];
    };
    let [first, second] = springs.spans[s];
    let second = if second == first { PHANTOM } else { second };
    [springs.a[s], springs.b[s], first, second]
}

/// Damping factors `γ = c / (k h)` per kind.
fn damping_factors(coefficients: &SpringCoefficients, h: f32) -> [f32; 3] {
    SpringKind::ALL.map(|kind| {
        let k = coefficients.stiffness[kind as usize];
        if k > 0.0 {
            coefficients.damping[kind as usize].max(0.0) / (k * h)
        } else {
            0.0
        }
    })
}

/// What the correction factors of a spring depend on.
struct Factors<'a> {
    w: &'a [f32],
    gamma: [f32; 3],
    particles: &'a Particles,
    springs: &'a Springs,
    coefficients: &'a SpringCoefficients,
    h: f32,
}

impl Factors<'_> {
    /// `(w_a, w_b) / ((1 + γ)(w_a + w_b) + α̃)` with `α̃ = 1/(k h²)` for spring `s`; zero for a
    /// phantom, a dead spring or one of no stiffness.
    fn of(&self, s: u32) -> (f32, f32) {
        if s == PHANTOM {
            return (0.0, 0.0);
        }
        let s = s as usize;
        let springs = self.springs;
        let kind = springs.kind[s] as usize;
        let k = self.coefficients.stiffness[kind];
        let (wa, wb) = (self.w[springs.a[s] as usize], self.w[springs.b[s] as usize]);
        let denominator = (1.0 + self.gamma[kind]) * (wa + wb) + 1.0 / (k * self.h * self.h);
        let live = springs.is_live(s, &self.particles.state);
        if live && k > 0.0 && denominator.is_finite() && denominator > 0.0 {
            (wa / denominator, wb / denominator)
        } else {
            (0.0, 0.0)
        }
    }
}

/// The lane layout of a grid cloth, if its springs are the grid's springs: each lane element
/// that stands for a spring is matched to the stored spring with the same ends (first end
/// first; a cut bending spring by the particle it spans). `None` when a spring is missing,
/// reversed or left over, so hand-made springs fall back to the indexed layout.
fn grid_layout(grid: GridShape, springs: &Springs, particles: usize) -> Option<Layout> {
    if (grid.columns * grid.rows) as usize != particles {
        return None;
    }
    let slots = GridSlots::new(grid);
    let lanes = GridLanes::new(slots, BAND_ROWS);
    let mut by_end = Adjacency::default();
    by_end.build(particles, springs.len(), |s| {
        [springs.a[s as usize], PHANTOM, PHANTOM, PHANTOM]
    });
    let mut spring = vec![PHANTOM; lanes.elements as usize];
    let mut matched = 0;
    for lane in &lanes.lanes {
        for k in 0..lane.len {
            let Some([(ca, ra), (cb, rb)]) = lanes.cells(slots, lane, k) else {
                continue;
            };
            let (a, b) = (grid.index(ca, ra) as u32, grid.index(cb, rb) as u32);
            let middle = grid.index((ca + cb) / 2, (ra + rb) / 2) as u32;
            let found = by_end.of(a as usize).iter().copied().find(|&s| {
                let s = s as usize;
                springs.kind[s] == lane.kind
                    && (springs.b[s] == b
                        || (lane.kind == SpringKind::Bend && springs.spans[s][0] == middle))
            })?;
            spring[(lane.first + k) as usize] = found;
            matched += 1;
        }
    }
    (matched == springs.len()).then_some(Layout::Grid {
        slots,
        lanes,
        spring,
    })
}
