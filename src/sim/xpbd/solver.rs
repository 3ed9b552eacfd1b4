//! [`XpbdSolver`]: one cloth's XPBD state and the substep loop.
//!
//! A substep is four passes: the grid's even bands of springs, its odd bands (the bending
//! springs in every other substep, [`bend_interval`]), the stretch limit on the heated springs
//! (in rounds, each over the even bands, the odd bands, then any left over), then one pass
//! over the particles (tethers, colliders, the velocity update and the next substep's
//! prediction).
//! The frame's passes are listed once (`XpbdSolver::plan_passes`) and run under one scope of
//! the task pool when the cloth is big enough ([`run_phases`]). Bands solved together share
//! no particle and particles are independent in the last pass, so the result is the same on
//! any number of threads.

use super::adjacency::Adjacency;
use super::kernel::{
    Arrays, RunData, project_indexed, project_shared, project_shared_together, project_split,
};
use super::lanes::{Band, GridLanes, GridSlots, Lane};
use super::staggered::{self, Staggered};
use super::stretch_limit::{Flat, LimitedSprings, Reach, RoundTallies, limit_all, limit_bucket};
use crate::sim::anchors::Anchors;
use crate::sim::collision::{WorldCollider, sliding_kept};
use crate::sim::forces::ForceParams;
use crate::sim::guard::GuardSettings;
use crate::sim::parallel::{Claims, Disjoint, parts_for, piece, run_phases};
use crate::sim::particles::{BurnState, Particles};
use crate::sim::springs::{SpringCoefficients, SpringKind, Springs};
use crate::sim::topology::GridShape;
use bevy::tasks::TaskPool;
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

/// Rows per band of a grid stepped on the pool's threads: bands two apart are independent,
/// and the threads take a band at a time.
const BAND_ROWS: u32 = 8;

/// Slots below which a cloth is stepped on one thread: splitting smaller ones costs more in
/// handing work out than it saves.
const PARALLEL_SLOTS: usize = 8192;

/// Slots per run of the per-slot pass, at least; and at most this many runs.
const SLOT_PART: usize = 512;
const MAX_SLOT_PARTS: usize = 16;

/// Distance between a lane's ends, in slots, below which a family's four quarter lanes are
/// projected side by side ([`side_by_side`]): two chunks of eight.
const TOGETHER_BELOW: u32 = 16;

/// Distance between a lane's ends, in slots, below which (from [`TOGETHER_BELOW`]) a family's
/// quarter lanes are projected two side by side ([`side_by_side`]).
const PAIR_BELOW: u32 = 32;

/// No spring: a lane element past the grid's edge.
const PHANTOM: u32 = u32::MAX;

/// How the springs are walked.
#[derive(Clone, Debug, Default, PartialEq)]
enum Layout {
    /// Not built yet.
    #[default]
    Unset,
    /// A grid: particles in quarter grids, springs in lanes; element `e` of the lanes stands
    /// for spring `spring[e]` ([`PHANTOM`] for none), and spring `s` is element `element[s]`.
    Grid {
        slots: GridSlots,
        lanes: GridLanes,
        spring: Vec<u32>,
        element: Vec<u32>,
    },
    /// Springs in their stored order, ends by index (meshes, hand-made springs): element `e`
    /// is spring `e`, slot `i` is particle `i`.
    Indexed,
}

/// What the spring factors were computed for; a change recomputes them all.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FactorKey {
    h: f32,
    bend_interval: u32,
    coefficients: SpringCoefficients,
}

/// What one cloth needs around it for a frame of substeps.
#[derive(Clone, Copy)]
pub struct Surroundings<'a> {
    /// Gravity, wind, drag and spring coefficients.
    pub params: &'a ForceParams,
    /// Colliders in world space.
    pub colliders: &'a [WorldCollider],
    /// Distance particles keep from colliders, m.
    pub margin: f32,
    /// The blow-up guard's limits.
    pub guard: GuardSettings,
    /// Tethers: each particle stays within `(1 + stretch) ×` its distance through the cloth
    /// to the pin it hangs from; `None` for none.
    pub tethers: Option<(&'a Anchors, f32)>,
    /// Provot's limit on the springs heat shrinks, after the springs of every substep;
    /// `None` for none.
    pub stretch_limit: Option<StretchLimit<'a>>,
    /// Threads to share the work with, if any.
    pub pool: Option<&'a TaskPool>,
}

/// Provot's limit on a list of springs: Gauss–Seidel passes that pull each live in-plane
/// spring of the list longer than `(1 + stretch) ×` its rest length back to that length (a
/// hard, one-sided constraint). Given the springs heat has shrunk
/// ([`Front::shrunk`](crate::sim::front::Front::shrunk)), it makes the burning cloth pull in
/// and crumple around the fire, as the shrinking springs would with every spring held
/// to the limit, instead of stretching: one compliant constraint pass per substep is too soft
/// to carry the shrinking to the cold cloth around it.
#[derive(Clone, Copy, Debug)]
pub struct StretchLimit<'a> {
    /// The springs, by index.
    pub springs: &'a [u32],
    /// Largest relative stretch (0.1 is 10 %).
    pub stretch: f32,
    /// Passes per substep, each over every spring of the list, stopping once one corrects
    /// none; 0 turns the limit off.
    pub passes: u32,
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
    /// Each particle's slot, and the slots that hold no particle (a grid's padding).
    slot: Vec<u32>,
    padding: Vec<u32>,
    /// The elements each particle is in (as an end, or the particle a bend passes over).
    adjacency: Adjacency,
    /// Per slot: positions at the start of the substep (m), velocities (m/s), displacement
    /// since the start of the substep (m: `h v` from the prediction plus the corrections),
    /// and the acceleration of gravity, wind drag and external forces (m/s²).
    slots: SlotArrays,
    /// Inverse mass used by the constraints, 1/kg, by particle: zero for pins and burnt
    /// particles.
    w: Vec<f32>,
    /// Per element: rest length (m), and `w_a / ((1 + γ)(w_a + w_b) + α̃)` and the same with
    /// `w_b` (zero for a dead spring or a phantom).
    rest: Vec<f32>,
    ca: Vec<f32>,
    cb: Vec<f32>,
    /// A grid's rest lengths as last copied into `rest`, m, in spring order: a frame copies
    /// only the springs whose length changed since.
    seen_rest: Vec<f32>,
    /// Damping factor `γ = c / (k h)` per spring kind.
    gamma: [f32; 3],
    /// Fraction of the stiffness that resists compression, per spring kind (in [0, 1]).
    compression: [f32; 3],
    factors_for: Option<FactorKey>,
    /// Particles whose inverse mass changed since the factors were computed.
    dirty: Vec<u32>,
    /// The slots of the pins tethers hold to (entry 0 stands for none), each particle's
    /// entry if it is one of them (else 0), their positions in the current substep, and the
    /// stretch the tethers were made for.
    pin_slots: Vec<u32>,
    pin_index: Vec<u32>,
    pin_positions: Vec<[f32; 3]>,
    tethers_for: Option<f32>,
    /// Whether the slots' tether targets hold their pins' positions.
    targets_valid: bool,
    /// This frame's springs under the stretch limit, by band.
    limited: LimitedSprings,
    /// The frame's passes with the items each is cut into, and the items alone.
    passes: Vec<(Pass, usize)>,
    pass_sizes: Vec<usize>,
    claims: Claims,
    /// Springs corrected by each of the frame's rounds of the stretch limit.
    tallies: RoundTallies,
}

/// What reading the particles found out about the pins.
#[derive(Default)]
struct PinNews {
    /// A pin came or went.
    changed: bool,
    /// Some pin moves this frame.
    moving: bool,
    /// Some particle moves freely (neither pinned nor burnt).
    free: bool,
    /// The free particles' outside acceleration, m/s², when no particle has an external
    /// force (so it is gravity and wind drag for all of them).
    uniform: Option<[f32; 3]>,
}

/// The per-slot arrays; those of `f32` each start at its own offset within a page
/// ([`staggered`](super::staggered)).
#[derive(Clone, Debug, Default)]
struct SlotArrays {
    /// The particle in each slot (`PHANTOM` for padding).
    particle: Vec<u32>,
    x: [Staggered; 3],
    v: [Staggered; 3],
    u: [Staggered; 3],
    acceleration: [Staggered; 3],
    /// 1 for particles the solver moves freely, 0 for pins, burnt particles and padding.
    free: Staggered,
    /// 1 for particles that move at all (free ones and pins following their anchor).
    moving: Staggered,
    /// Index in `pin_slots` of the pin the slot is tethered to (0 for none), and how far from
    /// it it may be (m; infinite for none).
    tether_pin: Vec<u32>,
    tether_length: Staggered,
    /// Where the pin of each slot's tether is (m), while pins stand still.
    tether_target: [Staggered; 3],
}

impl SlotArrays {
    /// Every array of `f32`, with the value a slot holds before it is first read.
    fn floats_mut(&mut self) -> impl Iterator<Item = (&mut Staggered, f32)> {
        self.x
            .iter_mut()
            .chain(&mut self.v)
            .chain(&mut self.u)
            .chain(&mut self.acceleration)
            .chain(&mut self.tether_target)
            .map(|array| (array, 0.0))
            .chain([
                (&mut self.free, 0.0),
                (&mut self.moving, 0.0),
                (&mut self.tether_length, f32::INFINITY),
            ])
    }

    fn resize(&mut self, slots: usize) {
        let count = self.floats_mut().count();
        for (k, (array, value)) in self.floats_mut().enumerate() {
            array.reset(slots, value, staggered::spread(k, count));
        }
        self.tether_pin.clear();
        self.tether_pin.resize(slots, 0);
        self.particle.clear();
        self.particle.resize(slots, PHANTOM);
    }

    /// Every slot's arrays as one chunk (for tests: the solver hands its passes runs of
    /// slots through [`SharedSlots`]).
    #[cfg(test)]
    fn whole(&mut self) -> SlotChunk<'_> {
        let SlotArrays {
            particle,
            x,
            v,
            u,
            acceleration,
            free,
            moving,
            tether_pin,
            tether_length,
            tether_target,
        } = self;
        SlotChunk {
            particle,
            x: x.each_mut().map(|a| &mut a[..]),
            v: v.each_mut().map(|a| &mut a[..]),
            u: u.each_mut().map(|a| &mut a[..]),
            acceleration: acceleration.each_mut().map(|a| &mut a[..]),
            free,
            moving,
            tether_pin,
            tether_length,
            tether_target: tether_target.each_mut().map(|a| &mut a[..]),
        }
    }

    fn heap_bytes(&self) -> usize {
        let floats: usize = self
            .x
            .iter()
            .chain(&self.v)
            .chain(&self.u)
            .chain(&self.acceleration)
            .chain(&self.tether_target)
            .chain([&self.free, &self.moving, &self.tether_length])
            .map(Staggered::capacity)
            .sum();
        (floats + self.tether_pin.capacity() + self.particle.capacity()) * size_of::<f32>()
    }

    fn len(&self) -> usize {
        self.free.len()
    }
}

impl XpbdSolver {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        let floats = [&self.w, &self.rest, &self.ca, &self.cb, &self.seen_rest]
            .iter()
            .map(|a| a.capacity())
            .sum::<usize>();
        let layout = match &self.layout {
            Layout::Grid {
                lanes,
                spring,
                element,
                ..
            } => {
                lanes.lanes.capacity() * size_of::<Lane>()
                    + lanes.bands.capacity() * size_of::<Band>()
                    + (spring.capacity() + element.capacity()) * size_of::<u32>()
            }
            _ => 0,
        };
        (floats
            + self.slot.capacity()
            + self.padding.capacity()
            + self.dirty.capacity()
            + self.pin_slots.capacity()
            + self.pin_index.capacity()
            + self.pass_sizes.capacity())
            * size_of::<f32>()
            + self.pin_positions.capacity() * size_of::<[f32; 3]>()
            + self.passes.capacity() * size_of::<(Pass, usize)>()
            + self.limited.heap_bytes()
            + layout
            + self.slots.heap_bytes()
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
                ..
            } => {
                let columns = grid.map_or(1, |g| g.columns);
                self.slot
                    .extend((0..n as u32).map(|i| slots.slot(i % columns, i / columns)));
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
        self.slots.resize(slots);
        for (i, &slot) in self.slot.iter().enumerate() {
            self.slots.particle[slot as usize] = i as u32;
        }
        self.padding.clear();
        self.padding
            .extend((0..slots as u32).filter(|&s| self.slots.particle[s as usize] == PHANTOM));
        self.w.clear();
        self.w.resize(n, f32::NAN);
        let grid_lanes = match (&self.layout, grid) {
            (Layout::Grid { slots, lanes, .. }, Some(grid)) => Some((lanes, *slots, grid.columns)),
            _ => None,
        };
        self.limited.prepare(grid_lanes, springs.len());
        for array in [&mut self.rest, &mut self.ca, &mut self.cb] {
            array.clear();
            array.resize(elements, 0.0);
        }
        self.seen_rest.clear();
        if let Layout::Grid { spring, .. } = &self.layout {
            self.seen_rest.extend_from_slice(&springs.rest_length);
            for (rest, &s) in self.rest.iter_mut().zip(spring) {
                // `PHANTOM` is past every spring: one test for both.
                *rest = springs.rest_length.get(s as usize).copied().unwrap_or(0.0);
            }
        }
        self.dirty.clear();
        self.dirty.reserve(n);
        self.factors_for = None;
        self.pin_slots.clear();
        self.pin_slots.reserve(n + 1);
        self.pin_index.clear();
        self.pin_index.resize(n, 0);
        self.pin_positions.clear();
        self.pin_positions.reserve(n + 1);
        self.tethers_for = None;
        self.targets_valid = false;
    }

    /// Advances the cloth `substeps` substeps of `h` seconds each: the particles are read
    /// once, stepped in the solver's arrays and written back once. Returns the particles the
    /// blow-up guard put back (their position at the start, at rest), and whether a particle
    /// was pinned or unpinned since the last call (what hangs from what must then be found
    /// anew).
    pub fn advance(
        &mut self,
        particles: &mut Particles,
        springs: &Springs,
        grid: Option<GridShape>,
        around: &Surroundings,
        h: f32,
        substeps: u32,
    ) -> (u32, bool) {
        if particles.is_empty() || !(h.is_finite() && h > 0.0) {
            return (0, false);
        }
        self.prepare(particles, springs, grid);
        let frame = h * substeps as f32;
        let pool = around.pool.filter(|_| self.slots.len() >= PARALLEL_SLOTS);
        let (pins, constant) = self.scan(particles, around.params);
        let bend_interval = bend_interval(substeps);
        self.update_factors(
            particles,
            springs,
            &around.params.coefficients,
            h,
            bend_interval,
        );
        if !pins.free {
            // Nothing moves freely (every particle pinned or burnt): the pins are already at
            // their targets and nothing else moves, so the substeps would change nothing.
            self.targets_valid = false;
            return (0, pins.changed);
        }
        let tethered = match around.tethers {
            Some((anchors, stretch)) => {
                self.update_tethers(anchors, stretch);
                true
            }
            None => false,
        };
        self.gather_limited(particles, springs, around.stretch_limit);
        // Tether targets stay where they are while the pins stand still.
        let refresh = tethered && (!self.targets_valid || pins.moving);
        let step = Substep {
            h,
            drag: around.params.drag_per_mass.max(0.0),
            uniform: pins.uniform,
            colliders: around.colliders,
            margin: around.margin,
            tethered,
            refresh_targets: false,
        };
        let shared = pool.is_some_and(|pool| pool.thread_num() > 0);
        let rounds = around.stretch_limit.map_or(0, |limit| limit.passes);
        let refresh = [refresh, tethered && pins.moving];
        let write_parts = parts_for(pool, particles.len(), 2048);
        self.plan_passes(
            substeps,
            bend_interval,
            rounds,
            shared,
            refresh,
            write_parts,
        );
        let copies = Copies {
            constant,
            frame,
            guard: around.guard,
        };
        let repaired = self.run_passes(particles, springs, &step, rounds, copies, pool);
        self.targets_valid = tethered && !pins.moving;
        (repaired, pins.changed)
    }

    /// This frame's springs under the stretch limit.
    fn gather_limited(
        &mut self,
        particles: &Particles,
        springs: &Springs,
        limit: Option<StretchLimit>,
    ) {
        match limit.filter(|limit| limit.passes > 0) {
            Some(limit) => {
                let scale = 1.0 + limit.stretch.max(0.0);
                let ends = (self.w.as_slice(), self.slot.as_slice());
                self.limited
                    .gather(limit.springs, particles, springs, ends, scale);
            }
            None => self.limited.clear(),
        }
    }

    /// What the frame's copy of the particles into the slots needs to know: each particle's
    /// inverse mass (burnt ones zero; those that changed listed as dirty), whether a pin came
    /// or went, whether any pin moves, whether anything moves freely, and the free particles'
    /// outside acceleration but for their external forces (gravity and wind drag). The copy
    /// itself, and that of a grid's changed rest lengths into lane order, are the first
    /// pass's ([`Self::run_passes`]).
    fn scan(&mut self, particles: &Particles, params: &ForceParams) -> (PinNews, glam::Vec3) {
        let mut news = PinNews::default();
        let n = particles.len();
        let (state, inv_mass) = (&particles.state[..n], &particles.inv_mass[..n]);
        let whole = n - n % SCAN_RUN;
        // A run of particles whose inverse masses are as last read and holds no pin is only
        // searched for a free particle, with no branch; the rest go one by one.
        for start in (0..whole).step_by(SCAN_RUN) {
            let run = start..start + SCAN_RUN;
            let (state, inv_mass) = (&state[run.clone()], &inv_mass[run.clone()]);
            let w = &self.w[run];
            let (mut changed, mut free, mut pin) = (false, false, false);
            for k in 0..SCAN_RUN {
                let burnt = state[k].is_burnt();
                let pinned = inv_mass[k] == 0.0;
                let mass_inverse = if burnt { 0.0 } else { inv_mass[k] };
                changed |= mass_inverse.to_bits() != w[k].to_bits();
                free |= !burnt & !pinned;
                pin |= pinned & !burnt;
            }
            news.free |= free;
            if changed || pin {
                for i in start..start + SCAN_RUN {
                    read_one(particles, i, &mut self.w, &mut self.dirty, &mut news);
                }
            }
        }
        for i in whole..n {
            read_one(particles, i, &mut self.w, &mut self.dirty, &mut news);
        }
        let drag = params.drag_per_mass.max(0.0);
        let constant = params.gravity + drag * params.wind;
        if !news.free {
            return (news, constant);
        }
        let uniform = no_force(&particles.external_force).then_some(constant.to_array());
        // Padding back to rest at the origin: a NaN that reached it in a blown-up frame
        // through a phantom element (whose factors are zero, and zero times NaN is NaN)
        // would otherwise stay, and come back through the same element every frame after.
        // (The copy in leaves padding alone.)
        let SlotArrays {
            x, v, acceleration, ..
        } = &mut self.slots;
        for array in x.iter_mut().chain(v).chain(acceleration) {
            for &s in &self.padding {
                array[s as usize] = 0.0;
            }
        }
        (PinNews { uniform, ..news }, constant)
    }

    /// Recomputes the spring factors: all of them when the step, the bending springs'
    /// interval or the coefficients changed, else those of the springs of particles whose
    /// inverse mass changed.
    fn update_factors(
        &mut self,
        particles: &Particles,
        springs: &Springs,
        coefficients: &SpringCoefficients,
        h: f32,
        bend_interval: u32,
    ) {
        let key = FactorKey {
            h,
            bend_interval,
            coefficients: *coefficients,
        };
        let mut dirty = std::mem::take(&mut self.dirty);
        let spring_of = |e: usize| match &self.layout {
            Layout::Grid { spring, .. } => spring[e],
            _ => e as u32,
        };
        let all = self.factors_for != Some(key);
        let factors = Factors {
            w: &self.w,
            gamma: if all {
                damping_factors(coefficients, h)
            } else {
                self.gamma
            },
            particles,
            springs,
            coefficients,
            h,
            bend_interval: bend_interval as f32,
        };
        if all {
            for e in 0..self.ca.len() {
                (self.ca[e], self.cb[e]) = factors.of(spring_of(e));
            }
            self.gamma = factors.gamma;
            // A NaN or out-of-range fraction (hand-made coefficients) is taken as 1 or clamped.
            self.compression = coefficients
                .compression
                .map(|c| if c.is_nan() { 1.0 } else { c.clamp(0.0, 1.0) });
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

    /// Tether pins and lengths from what each particle hangs from: for the particles whose
    /// anchor changed, or all of them when the stretch changed or the pins did.
    fn update_tethers(&mut self, anchors: &Anchors, stretch: f32) {
        let scale = 1.0 + stretch.max(0.0);
        if !anchors.changed().is_empty() || self.tethers_for != Some(stretch) {
            self.targets_valid = false;
        }
        let everything = anchors.changed().len() == self.slot.len();
        if self.tethers_for != Some(stretch) || everything {
            // Number the pins: entry 0 stands for "no tether".
            self.pin_slots.clear();
            self.pin_slots.push(0);
            for i in 0..self.slot.len() {
                self.pin_index[i] = if anchors.anchor(i) == Some(i as u32) {
                    self.pin_slots.push(self.slot[i]);
                    (self.pin_slots.len() - 1) as u32
                } else {
                    0
                };
            }
            self.pin_positions.clear();
            self.pin_positions.resize(self.pin_slots.len(), [0.0; 3]);
            self.tethers_for = Some(stretch);
            for i in 0..self.slot.len() {
                self.set_tether(anchors, i, scale);
            }
        } else {
            for &i in anchors.changed() {
                self.set_tether(anchors, i as usize, scale);
            }
        }
    }

    fn set_tether(&mut self, anchors: &Anchors, i: usize, scale: f32) {
        let own = self.slot[i] as usize;
        let pin = anchors
            .anchor(i)
            .filter(|_| anchors.distance(i) > 0.0)
            .map_or(0, |pin| self.pin_index[pin as usize]);
        (self.slots.tether_pin[own], self.slots.tether_length[own]) = if pin > 0 {
            (pin, anchors.distance(i) * scale)
        } else {
            (0, f32::INFINITY)
        };
    }

    /// Lists the frame's passes and how many items each is cut into: the first prediction,
    /// then per substep the springs (a grid's even bands, then its odd bands, an item per band;
    /// a mesh's springs as one item; the bending springs only in the first substep of every
    /// `bend_interval`), the stretch limit on the springs in the grid's bands
    /// (even bands, then odd ones), the limit on the rest and the pins' positions when needed
    /// (one item), and the per-slot pass (one item on one thread; shared between threads, a
    /// grid's band's rows or runs of slots); then the copy back, in `write_parts` runs of
    /// particles. The first prediction copies its slots in first. `refresh`: whether the
    /// tether targets must be looked up again in the first substep, and in the later ones.
    fn plan_passes(
        &mut self,
        substeps: u32,
        bend_interval: u32,
        rounds: u32,
        shared: bool,
        refresh: [bool; 2],
        write_parts: usize,
    ) {
        let limiting = !self.limited.is_empty();
        let rest = self.limited.has_rest();
        let (slot_parts, bands) = match &self.layout {
            Layout::Grid { lanes, .. } => (
                lanes.bands.len(),
                [lanes.bands.len().div_ceil(2), lanes.bands.len() / 2],
            ),
            _ => (
                self.slots
                    .len()
                    .div_ceil(SLOT_PART)
                    .clamp(1, MAX_SLOT_PARTS),
                [1, 0],
            ),
        };
        let slot_parts = if shared { slot_parts } else { 1 };
        let banded = shared && matches!(self.layout, Layout::Grid { .. });
        self.passes.clear();
        self.passes.push((Pass::Predict, slot_parts));
        let mut round = 0;
        for substep in 0..substeps {
            let refresh = refresh[usize::from(substep > 0)];
            let bends = substep % bend_interval.max(1) == 0;
            for (parity, items) in [(0, bands[0]), (1, bands[1])] {
                self.passes.push((Pass::Springs { parity, bends }, items));
            }
            if limiting && banded {
                for r in 0..rounds {
                    let first = r == 0;
                    let parities = [(0, bands[0]), (1, bands[1]), (2, usize::from(rest))];
                    for (parity, items) in parities.into_iter().filter(|&(_, n)| n > 0) {
                        self.passes.push((
                            Pass::Limit {
                                parity,
                                round,
                                first,
                            },
                            items,
                        ));
                    }
                    round += 1;
                }
            }
            let limit = limiting && !banded;
            if limit || refresh {
                self.passes.push((Pass::Serial { limit, refresh }, 1));
            }
            let last = substep + 1 == substeps;
            self.passes
                .push((Pass::Finish { last, refresh }, slot_parts));
        }
        self.passes.push((Pass::Write, write_parts));
        self.pass_sizes.clear();
        self.pass_sizes
            .extend(self.passes.iter().map(|&(_, items)| items));
        self.tallies.reset(round as usize);
    }

    /// Runs the planned passes, on `pool`'s threads when one is given (see [`run_phases`]):
    /// items of one pass touch disjoint slots (or particles), and each pass starts when the
    /// one before it has finished, so the result is the same on any number of threads. The
    /// copy in, the substeps and the copy back are one scope: a pool thread woken once joins
    /// them all (with a scope each, it was woken three times a frame, and each time the
    /// calling thread worked alone until it came). Returns how many particles the guard put
    /// back.
    #[allow(unsafe_code)]
    fn run_passes(
        &mut self,
        particles: &mut Particles,
        springs: &Springs,
        step: &Substep,
        rounds: u32,
        copies: Copies,
        pool: Option<&TaskPool>,
    ) -> u32 {
        let n = particles.len();
        let Particles {
            position,
            velocity,
            state,
            external_force,
            ..
        } = particles;
        let (position, velocity) = (
            Disjoint::new(&mut position[..n]),
            Disjoint::new(&mut velocity[..n]),
        );
        let (state, force) = (&state[..n], &external_force[..n]);
        let (w, slot) = (&self.w, &self.slot);
        let accelerations = step.uniform.is_none();
        let check_guard = copies.guard.enabled;
        let max_speed_squared = copies.guard.max_speed * copies.guard.max_speed;
        let blown = AtomicBool::new(false);
        let repaired = AtomicU32::new(0);
        let write_parts = self.pass_sizes.last().copied().unwrap_or(1);
        let shared = SharedSlots::new(&mut self.slots);
        let pin_positions = Disjoint::new(&mut self.pin_positions);
        let buckets = self.limited.share();
        let (passes, layout, pin_slots) = (&self.passes, &self.layout, &self.pin_slots);
        // A grid's rest lengths in lane order, brought up to date by the first pass, a piece
        // of the springs per item, and read by the later ones.
        let lengths = &springs.rest_length;
        let element: &[u32] = match layout {
            Layout::Grid { element, .. } => element,
            _ => &[],
        };
        let compared = lengths.len().min(self.seen_rest.len()).min(element.len());
        let seen = Disjoint::new(&mut self.seen_rest[..compared]);
        let rest = Disjoint::new(&mut self.rest[..]);
        let (ca, cb, gamma, compression) = (&self.ca, &self.cb, self.gamma, self.compression);
        let parts = self.pass_sizes.first().copied().unwrap_or(1);
        // The slots of a per-slot item: a grid's band's rows in each quarter grid (the rows
        // whose springs the same end of the pool just projected), else a run of slots.
        let runs = |item: usize| -> [core::ops::Range<usize>; 4] {
            match layout {
                Layout::Grid {
                    slots: grid, lanes, ..
                } if parts > 1 => {
                    let quarter = grid.quarter_len() as usize;
                    let span = grid.row_span(lanes.bands[item].rows.clone());
                    four(|q| q * quarter + span.start..q * quarter + span.end)
                }
                _ => [piece(shared.len(), parts, item), 0..0, 0..0, 0..0],
            }
        };
        let (claims, tallies) = (&mut self.claims, &self.tallies);
        run_phases(pool, &self.pass_sizes, claims, |phase, item| {
            match passes[phase].0 {
                Pass::Predict => {
                    // SAFETY: nothing writes the particles' positions and velocities before
                    // the last pass.
                    let (position, velocity) =
                        unsafe { (position.read(0..n), velocity.read(0..n)) };
                    let incoming = Incoming {
                        state,
                        position,
                        velocity,
                        force,
                        w,
                        constant: copies.constant,
                        frame: copies.frame,
                        accelerations,
                    };
                    for run in runs(item) {
                        // SAFETY: the items of a pass take disjoint runs of slots.
                        let mut slots = unsafe { shared.chunk(run) };
                        slots.read(&incoming);
                        slots.run(&[], step, Phase::PredictOnly);
                    }
                    let piece = piece(compared, parts, item);
                    // SAFETY: the items take disjoint pieces of the springs, and no two
                    // springs share an element (`grid_layout`), so they write disjoint
                    // lengths; nothing reads the lane-order lengths until the springs' pass,
                    // which starts after every item of this one has finished.
                    let seen = unsafe { seen.part(piece.clone()) };
                    let element = &element[piece.clone()];
                    copy_changed_lengths(&lengths[piece], seen, element, |e, length| {
                        if e < rest.len() {
                            // SAFETY: as above.
                            unsafe { rest.part(e..e + 1)[0] = length };
                        }
                    });
                }
                Pass::Springs { parity, bends } => {
                    // SAFETY: the rest lengths are written only in the first pass.
                    let rest = unsafe { rest.read(0..rest.len()) };
                    let elements = Elements {
                        rest,
                        ca,
                        cb,
                        gamma,
                        compression,
                    };
                    match layout {
                        Layout::Grid {
                            slots: grid, lanes, ..
                        } => {
                            let band = &lanes.bands[parity as usize + 2 * item];
                            // SAFETY: bands of one parity reach disjoint rows, and x is not written
                            // while springs are projected.
                            let view = unsafe { shared.band(*grid, band) };
                            let lanes = &lanes.lanes[band.lanes.clone()];
                            project_band::<true>(view, with_bends(lanes, bends), &elements);
                        }
                        Layout::Indexed => {
                            // SAFETY: a mesh's springs are one item, the pass's only one.
                            let (x, u) = unsafe { shared.positions() };
                            project_all_indexed(x, u, springs, &elements, bends);
                        }
                        Layout::Unset => {}
                    }
                }
                Pass::Limit {
                    parity,
                    round,
                    first,
                } => {
                    let Layout::Grid {
                        slots: grid, lanes, ..
                    } = layout
                    else {
                        return;
                    };
                    let round = round as usize;
                    if !first && tallies.corrected_nothing(round - 1) {
                        // The round before changed nothing, so this one would not either.
                        return;
                    }
                    let (bucket, reach) = if parity < 2 {
                        let band = parity as usize + 2 * item;
                        (band, lanes.bands[band].reach.clone())
                    } else {
                        (buckets.rest(), 0..grid.quarter_len() / grid.width())
                    };
                    // SAFETY: bands of one parity reach disjoint rows (the springs outside
                    // the bands are their pass's only item), and x is not written while
                    // springs are limited.
                    let mut reach = unsafe { shared.reach(*grid, reach) };
                    tallies.add(round, limit_bucket(&mut reach, &buckets, bucket));
                }
                Pass::Serial { limit, refresh } => {
                    if limit {
                        // SAFETY: the only item of its pass.
                        let (x, u) = unsafe { shared.positions() };
                        limit_all(&mut Flat { x, u }, &buckets, rounds);
                    }
                    if refresh {
                        // SAFETY: the only item of its pass; only this pass writes the pins'
                        // positions, and none reads them meanwhile.
                        let ((x, u), positions) = unsafe {
                            (
                                shared.positions(),
                                pin_positions.part(0..pin_positions.len()),
                            )
                        };
                        place_pins((x, u), pin_slots, positions);
                    }
                }
                Pass::Finish { last, refresh } => {
                    // SAFETY: the pins' positions are written only in the limit's pass.
                    let pins = unsafe { pin_positions.read(0..pin_positions.len()) };
                    let phase = if last {
                        Phase::Finish
                    } else {
                        Phase::FinishAndPredict
                    };
                    let step = Substep {
                        refresh_targets: refresh,
                        ..*step
                    };
                    for run in runs(item) {
                        // SAFETY: the items of a pass take disjoint runs of slots.
                        let mut slots = unsafe { shared.chunk(run) };
                        slots.run(pins, &step, phase);
                        if last && check_guard && slots.any_blown(max_speed_squared) {
                            blown.store(true, Ordering::Relaxed);
                        }
                    }
                }
                Pass::Write => {
                    let run = piece(n, write_parts, item);
                    // SAFETY: the items take disjoint runs of particles; no other pass
                    // reads the particles' positions and velocities meanwhile, nor writes the
                    // slots.
                    let (position, velocity, finals) = unsafe {
                        (
                            position.part(run.clone()),
                            velocity.part(run.clone()),
                            shared.finals(),
                        )
                    };
                    // Read after every item of the last substep's pass has finished (and
                    // published its stores with it).
                    let check = blown.load(Ordering::Relaxed);
                    let put_back = write_part(
                        (position, velocity),
                        &slot[run],
                        finals,
                        check.then_some(max_speed_squared),
                    );
                    repaired.fetch_add(put_back, Ordering::Relaxed);
                }
            }
        });
        repaired.into_inner()
    }
}

/// What the first pass copies in and the last copies back need besides the particles.
#[derive(Clone, Copy)]
struct Copies {
    /// The free particles' outside acceleration but for their external forces, m/s².
    constant: glam::Vec3,
    /// The frame, s: pins start a frame of their velocity before their target.
    frame: f32,
    /// What the copy back puts back.
    guard: GuardSettings,
}

/// Copies the free particles of a run back from their slots (`slot`, by particle), putting
/// back any that went non-finite or ran away (position as at the start, at rest) when
/// `check` gives the guard's largest speed squared. Pins keep their target; burnt particles
/// do not move. Returns how many were put back.
fn write_part(
    (position, velocity): (&mut [glam::Vec3], &mut [glam::Vec3]),
    slot: &[u32],
    (x, v, free): ([&[f32]; 3], [&[f32]; 3], &[f32]),
    check: Option<f32>,
) -> u32 {
    // Every slot array cut to one length here, where the loop is, so one test per particle
    // checks all its reads.
    let slots = free.len();
    let free = &free[..slots];
    let (x0, x1, x2) = (&x[0][..slots], &x[1][..slots], &x[2][..slots]);
    let (v0, v1, v2) = (&v[0][..slots], &v[1][..slots], &v[2][..slots]);
    let mut put_back = 0;
    for ((p, vel), &s) in position.iter_mut().zip(velocity.iter_mut()).zip(slot) {
        let s = s as usize;
        if s >= slots || free[s] == 0.0 {
            continue;
        }
        let new_position = glam::Vec3::new(x0[s], x1[s], x2[s]);
        let new_velocity = glam::Vec3::new(v0[s], v1[s], v2[s]);
        if let Some(max_speed_squared) = check
            && !(new_position.is_finite()
                && new_velocity.is_finite()
                && new_velocity.length_squared() <= max_speed_squared)
        {
            *vel = glam::Vec3::ZERO;
            put_back += 1;
        } else {
            *p = new_position;
            *vel = new_velocity;
        }
    }
    put_back
}

/// The per-element arrays a band pass reads.
struct Elements<'a> {
    rest: &'a [f32],
    ca: &'a [f32],
    cb: &'a [f32],
    gamma: [f32; 3],
    /// Per spring kind, the fraction of the stiffness that resists compression.
    compression: [f32; 3],
}

/// One band's share of the particle arrays: every quarter grid's rows in the band's reach,
/// and positions of the whole quarter grids.
struct BandView<'a> {
    x: [[&'a [f32]; 4]; 3],
    u: [[&'a mut [f32]; 4]; 3],
    /// Index, within a quarter grid, of the first entry of `u`.
    base: usize,
}

/// A band's lanes without its bending ones unless `bends` (they come last in a band, see
/// [`GridLanes::new`](super::lanes::GridLanes::new)).
fn with_bends(lanes: &[Lane], bends: bool) -> &[Lane] {
    if bends {
        return lanes;
    }
    let end = lanes
        .iter()
        .position(|lane| lane.kind == SpringKind::Bend)
        .unwrap_or(lanes.len());
    &lanes[..end]
}

/// Substeps from one projection of the bending springs to the next in a frame of `substeps`:
/// 2 when the frame's substeps pair up, else 1. Bending springs are the cloth's softest: a
/// projection every other substep, with the compliance of a step of `interval × h` over `h`
/// (`α̃ = 1/(k h · interval h)`: the impulse of the spring's force and damping over both
/// substeps, given in the first), holds the same bend and swing and saves a third of the
/// spring pass in every other substep. Stretch and shear springs, which carry the cloth's
/// weight, are projected every substep.
fn bend_interval(substeps: u32) -> u32 {
    if substeps >= 2 && substeps.is_multiple_of(2) {
        2
    } else {
        1
    }
}

/// Projects one band's lanes in order, a family's quarter lanes side by side where that
/// helps ([`side_by_side`]; the same bits as one by one, which `SIDE_BY_SIDE = false` does).
fn project_band<const SIDE_BY_SIDE: bool>(mut view: BandView, lanes: &[Lane], elements: &Elements) {
    let data = |lane: &Lane| {
        let range = lane.first as usize..(lane.first + lane.len) as usize;
        RunData {
            rest: &elements.rest[range.clone()],
            ca: &elements.ca[range.clone()],
            cb: &elements.cb[range],
            gamma: elements.gamma[lane.kind as usize],
            compression: elements.compression[lane.kind as usize],
        }
    };
    let mut next = 0;
    while next < lanes.len() {
        let lane = &lanes[next];
        let (a, b) = (lane.a as usize - view.base, lane.b as usize - view.base);
        if SIDE_BY_SIDE {
            // Ends under two chunks apart: every chunk waits for the one before, so all four
            // quarter lanes go side by side. From two to under four chunks apart each waits
            // for the one two or three before, and four lanes at once read from too many
            // places: two go side by side.
            if let Some(four) = side_by_side::<4>(&lanes[next..], 0..TOGETHER_BELOW) {
                project_side_by_side(&mut view, four, (a, b), &data);
                next += 4;
                continue;
            }
            if let Some(two) = side_by_side::<2>(&lanes[next..], TOGETHER_BELOW..PAIR_BELOW) {
                project_side_by_side(&mut view, two, (a, b), &data);
                next += 2;
                continue;
            }
        }
        let (qa, qb) = (lane.qa as usize, lane.qb as usize);
        let len = lane.len as usize;
        if qa == qb {
            let x = three(|axis| view.x[axis][qa]);
            let [u0, u1, u2] = &mut view.u;
            let mut u: [&mut [f32]; 3] = [&mut *u0[qa], &mut *u1[qa], &mut *u2[qa]];
            project_shared(x, &mut u, a, b, data(lane));
        } else {
            let xa = three(|axis| &view.x[axis][qa][a..a + len]);
            let xb = three(|axis| &view.x[axis][qb][b..b + len]);
            let (mut ua, mut ub) = split_quarters(&mut view.u, qa, qb, (a, b), len);
            project_split((xa, xb), &mut ua, &mut ub, data(lane));
        }
        next += 1;
    }
}

/// The first `L` of `lanes` if they are one family's lanes in quarter grids `q` to
/// `q + L − 1` in order (`q` a multiple of `L`), each within its own quarter grid, with the
/// same ends and length, their ends a number of slots apart in `apart`: lanes on disjoint
/// arrays whose chunks wait for ones just before, which [`project_shared_together`]
/// projects side by side. (Four lanes at once with ends 16 apart, on a 64 x 64 cloth, took
/// 0.375 ms of dynamics a frame against 0.316 one lane at a time, medians of five
/// alternated runs of `examples/stress.rs`; two at once took 0.344 against 0.354.)
fn side_by_side<const L: usize>(
    lanes: &[Lane],
    apart: core::ops::Range<u32>,
) -> Option<&[Lane; L]> {
    let group: &[Lane; L] = lanes.get(..L)?.try_into().ok()?;
    let first = &group[0];
    let q = usize::from(first.qa);
    if !apart.contains(&first.a.abs_diff(first.b)) || !q.is_multiple_of(L) {
        return None;
    }
    let same = group.iter().enumerate().all(|(k, lane)| {
        usize::from(lane.qa) == q + k
            && lane.qb == lane.qa
            && (lane.a, lane.b, lane.len, lane.kind) == (first.a, first.b, first.len, first.kind)
    });
    same.then_some(group)
}

/// Projects a [`side_by_side`] group of lanes with [`project_shared_together`]; `ends`: the
/// first element's ends within their quarter grids.
fn project_side_by_side<'e, const L: usize>(
    view: &mut BandView,
    group: &[Lane; L],
    ends: (usize, usize),
    data: &impl Fn(&Lane) -> RunData<'e>,
) {
    let q = usize::from(group[0].qa);
    let x = group
        .each_ref()
        .map(|lane| three(|axis| view.x[axis][usize::from(lane.qa)]));
    let [u0, u1, u2] = &mut view.u;
    let mut axes = [u0, u1, u2].map(|axis| quarter_group::<L>(axis, q).into_iter());
    let mut u: [[&mut [f32]; 3]; L] = core::array::from_fn(|_| {
        axes.each_mut().map(|axis| match axis.next() {
            Some(quarter) => quarter,
            None => unreachable!("one quarter grid per lane"),
        })
    });
    project_shared_together(x, &mut u, ends, group.each_ref().map(data));
}

/// Quarter grids `q` to `q + L − 1` of one axis.
fn quarter_group<'v, const L: usize>(
    axis: &'v mut [&mut [f32]; 4],
    q: usize,
) -> [&'v mut [f32]; L] {
    match axis.get_disjoint_mut(core::array::from_fn(|k| q + k)) {
        Ok(group) => group.map(|quarter| &mut **quarter),
        Err(_) => unreachable!("a group of quarter grids lies within the four"),
    }
}

/// The `len` entries from `a` of quarter `qa` and from `b` of quarter `qb` (`qa ≠ qb`), per axis.
fn split_quarters<'v>(
    u: &'v mut [[&mut [f32]; 4]; 3],
    qa: usize,
    qb: usize,
    (a, b): (usize, usize),
    len: usize,
) -> ([&'v mut [f32]; 3], [&'v mut [f32]; 3]) {
    let [u0, u1, u2] = u;
    let axis = |quarters: &'v mut [&mut [f32]; 4]| match quarters.get_disjoint_mut([qa, qb]) {
        Ok([ua, ub]) => (&mut ua[a..a + len], &mut ub[b..b + len]),
        Err(_) => unreachable!("a split lane's ends are in two quarter grids"),
    };
    let ((ua0, ub0), (ua1, ub1), (ua2, ub2)) = (axis(u0), axis(u1), axis(u2));
    ([ua0, ua1, ua2], [ub0, ub1, ub2])
}

/// What the per-slot pass of a substep needs.
#[derive(Clone, Copy)]
struct Substep<'a> {
    h: f32,
    drag: f32,
    /// Every free slot's outside acceleration (m/s²) when it is the same for all of them (no
    /// particle has an external force): the per-slot pass reads it instead of the
    /// acceleration arrays, which [`SlotChunk::read`] then leaves unwritten.
    uniform: Option<[f32; 3]>,
    colliders: &'a [WorldCollider],
    margin: f32,
    tethered: bool,
    /// Whether the tether targets must be looked up again from `pins` (the pins moved, or
    /// what hangs from what changed).
    refresh_targets: bool,
}

/// Which part of the per-slot pass runs.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// The first substep's prediction.
    PredictOnly,
    /// Tethers, colliders, the velocity update, then the next substep's prediction.
    FinishAndPredict,
    /// The last substep: tethers, colliders, the velocity update.
    Finish,
}

/// Where the tethers' pins are in this substep: `positions[k]` of the pin in slot
/// `pin_slots[k]` (entry 0 stands for none and is left alone).
fn place_pins(
    (x, u): ([&[f32]; 3], [&mut [f32]; 3]),
    pin_slots: &[u32],
    positions: &mut [[f32; 3]],
) {
    for (position, &slot) in positions.iter_mut().zip(pin_slots).skip(1) {
        let s = slot as usize;
        *position = three(|axis| x[axis][s] + u[axis][s]);
    }
}

/// One Gauss–Seidel pass over a mesh's springs in stored order, a run of springs of one kind
/// at a time (each kind has its own damping); the runs of bending springs only when `bends`.
fn project_all_indexed(
    x: [&[f32]; 3],
    u: [&mut [f32]; 3],
    springs: &Springs,
    elements: &Elements,
    bends: bool,
) {
    let mut arrays = Arrays { x, u };
    let n = springs.len();
    let mut start = 0;
    while start < n {
        let kind = springs.kind[start];
        let end = (start..n).find(|&s| springs.kind[s] != kind).unwrap_or(n);
        if kind == SpringKind::Bend && !bends {
            start = end;
            continue;
        }
        let data = RunData {
            rest: &springs.rest_length[start..end],
            ca: &elements.ca[start..end],
            cb: &elements.cb[start..end],
            gamma: elements.gamma[kind as usize],
            compression: elements.compression[kind as usize],
        };
        let (a, b) = (&springs.a[start..end], &springs.b[start..end]);
        project_indexed(&mut arrays, a, b, data);
        start = end;
    }
}

/// One pass of a frame's substeps, as [`XpbdSolver::run_passes`] runs it.
#[derive(Clone, Copy, Debug)]
enum Pass {
    /// The particles copied in and the first substep's prediction, over runs of slots.
    Predict,
    /// The springs of a grid's bands of one parity (0: even, 1: odd), an item per band; a
    /// mesh's springs (parity 0) as one item. The bending springs too when `bends`.
    Springs { parity: u8, bends: bool },
    /// One round of the stretch limit: one pass over the springs in a grid's bands of one
    /// parity (0: even, 1: odd), an item per band, or (parity 2) over those outside the bands,
    /// as one item. `round` numbers the frame's rounds ([`RoundTallies`]); a round that is
    /// not the `first` of its substep is skipped when the one before corrected nothing.
    Limit { parity: u8, round: u32, first: bool },
    /// On one thread, as one item: every limited spring, round after round (when `limit`:
    /// the cloth is not split between threads), and the pins' positions (when `refresh`).
    Serial { limit: bool, refresh: bool },
    /// Tethers (their targets looked up again when `refresh`), colliders, the velocity
    /// update and, unless `last`, the next substep's prediction, over runs of slots; in the
    /// `last`, whether the guard has anything to put back.
    Finish { last: bool, refresh: bool },
    /// The free particles copied back (the guard putting back any that went non-finite or
    /// ran away), over runs of particles.
    Write,
}

/// The per-slot arrays handed to the threads of a frame's passes, each item taking the part
/// its pass gives it.
struct SharedSlots<'a> {
    particle: Disjoint<'a, u32>,
    x: [Disjoint<'a, f32>; 3],
    v: [Disjoint<'a, f32>; 3],
    u: [Disjoint<'a, f32>; 3],
    acceleration: [Disjoint<'a, f32>; 3],
    free: Disjoint<'a, f32>,
    moving: Disjoint<'a, f32>,
    tether_pin: Disjoint<'a, u32>,
    tether_length: Disjoint<'a, f32>,
    tether_target: [Disjoint<'a, f32>; 3],
}

#[allow(unsafe_code)]
impl<'a> SharedSlots<'a> {
    fn new(slots: &'a mut SlotArrays) -> Self {
        let axes = |a: &'a mut [Staggered; 3]| a.each_mut().map(|a| Disjoint::new(&mut a[..]));
        Self {
            particle: Disjoint::new(&mut slots.particle),
            x: axes(&mut slots.x),
            v: axes(&mut slots.v),
            u: axes(&mut slots.u),
            acceleration: axes(&mut slots.acceleration),
            free: Disjoint::new(&mut slots.free[..]),
            moving: Disjoint::new(&mut slots.moving[..]),
            tether_pin: Disjoint::new(&mut slots.tether_pin),
            tether_length: Disjoint::new(&mut slots.tether_length[..]),
            tether_target: axes(&mut slots.tether_target),
        }
    }

    /// Slots in all.
    fn len(&self) -> usize {
        self.free.len()
    }

    /// Every array's slots in `range`.
    ///
    /// # Safety
    /// Nothing else uses these slots while the chunk is used.
    unsafe fn chunk(&self, range: core::ops::Range<usize>) -> SlotChunk<'a> {
        let axes = |a: &[Disjoint<'a, f32>; 3]| {
            // SAFETY: the caller's promise.
            three(|axis| unsafe { a[axis].part(range.clone()) })
        };
        // SAFETY: the caller's promise.
        unsafe {
            SlotChunk {
                particle: self.particle.part(range.clone()),
                x: axes(&self.x),
                v: axes(&self.v),
                u: axes(&self.u),
                acceleration: axes(&self.acceleration),
                free: self.free.part(range.clone()),
                moving: self.moving.part(range.clone()),
                tether_pin: self.tether_pin.part(range.clone()),
                tether_length: self.tether_length.part(range.clone()),
                tether_target: axes(&self.tether_target),
            }
        }
    }

    /// What a band of a grid laid out as `grid` projects: the displacements of its reach's
    /// rows in every quarter grid, and the positions from its reach's first row on.
    ///
    /// # Safety
    /// Nothing else uses the displacements of these rows while these are used, and no
    /// position is written meanwhile.
    unsafe fn band(&self, grid: GridSlots, band: &Band) -> BandView<'a> {
        let quarter = grid.quarter_len() as usize;
        let core::ops::Range { start, end } = grid.row_span(band.reach.clone());
        BandView {
            // SAFETY: the caller's promise.
            x: three(|axis| {
                four(|q| unsafe { self.x[axis].read(q * quarter + start..(q + 1) * quarter) })
            }),
            // SAFETY: the caller's promise.
            u: three(|axis| {
                four(|q| unsafe { self.u[axis].part(q * quarter + start..q * quarter + end) })
            }),
            base: start,
        }
    }

    /// The rows `reach` of a grid laid out as `grid`, in every quarter grid, as a band's
    /// stretch-limit pass reads and moves them. Panics if they are not all in the slots.
    ///
    /// # Safety
    /// As [`Self::band`].
    unsafe fn reach(&self, grid: GridSlots, reach: core::ops::Range<u32>) -> Reach<'a> {
        let quarter = grid.quarter_len() as usize;
        let core::ops::Range { start, end } = grid.row_span(reach);
        let slots = self.x.iter().chain(&self.u).map(Disjoint::len).min();
        assert!(
            start <= end && end <= quarter && slots.is_some_and(|n| n >= 4 * quarter),
            "reach out of bounds"
        );
        let (x, u) = (
            three(|axis| self.x[axis].as_mut_ptr().cast_const()),
            three(|axis| self.u[axis].as_mut_ptr()),
        );
        // SAFETY: each quarter grid's rows of the reach are in every array (checked above);
        // the rest is the caller's promise.
        unsafe { Reach::new(x, u, four(|q| q * quarter + start), end - start) }
    }

    /// Every slot's position, velocity and freedom, to read.
    ///
    /// # Safety
    /// Nothing writes them while these are used.
    unsafe fn finals(&self) -> ([&'a [f32]; 3], [&'a [f32]; 3], &'a [f32]) {
        let all = 0..self.len();
        // SAFETY: the caller's promise.
        unsafe {
            (
                three(|axis| self.x[axis].read(all.clone())),
                three(|axis| self.v[axis].read(all.clone())),
                self.free.read(all),
            )
        }
    }

    /// All positions to read and all displacements to write.
    ///
    /// # Safety
    /// Nothing else uses the displacements or writes a position while these are used.
    unsafe fn positions(&self) -> ([&'a [f32]; 3], [&'a mut [f32]; 3]) {
        let all = 0..self.len();
        // SAFETY: the caller's promise.
        unsafe {
            (
                three(|axis| self.x[axis].read(all.clone())),
                three(|axis| self.u[axis].part(all.clone())),
            )
        }
    }
}

/// The particles as the first pass copies them in: by particle, their burn states,
/// positions, velocities, external forces and inverse masses (zero for burnt and pinned
/// ones); the free particles' outside acceleration but for their external forces, m/s²; the
/// frame, s; and whether the acceleration arrays are written (some particle has an external
/// force).
struct Incoming<'a> {
    state: &'a [BurnState],
    position: &'a [glam::Vec3],
    velocity: &'a [glam::Vec3],
    force: &'a [glam::Vec3],
    w: &'a [f32],
    constant: glam::Vec3,
    frame: f32,
    accelerations: bool,
}

/// A contiguous run of the per-slot arrays.
struct SlotChunk<'a> {
    particle: &'a mut [u32],
    x: [&'a mut [f32]; 3],
    v: [&'a mut [f32]; 3],
    u: [&'a mut [f32]; 3],
    acceleration: [&'a mut [f32]; 3],
    free: &'a mut [f32],
    moving: &'a mut [f32],
    tether_pin: &'a mut [u32],
    tether_length: &'a mut [f32],
    tether_target: [&'a mut [f32]; 3],
}

impl<'a> SlotChunk<'a> {
    /// Copies in the particles of these slots (padding stays still). Pins start `frame`
    /// seconds of their velocity before their target and move there over the substeps.
    fn read(&mut self, incoming: &Incoming) {
        if incoming.accelerations {
            self.read_slots::<true>(incoming);
        } else {
            self.read_slots::<false>(incoming);
        }
    }

    /// [`Self::read`], writing the acceleration arrays when `ACCELERATIONS`.
    #[inline(always)]
    fn read_slots<const ACCELERATIONS: bool>(&mut self, incoming: &Incoming) {
        let (constant, frame, w) = (incoming.constant, incoming.frame, incoming.w);
        // Every array cut to the slots' length once, so the loop checks no bounds on them.
        let n = self.free.len();
        let (particle, free, moving) = (
            &self.particle[..n],
            &mut self.free[..n],
            &mut self.moving[..n],
        );
        let [x0, x1, x2] = &mut self.x;
        let [v0, v1, v2] = &mut self.v;
        let [a0, a1, a2] = &mut self.acceleration;
        let (x0, x1, x2) = (&mut x0[..n], &mut x1[..n], &mut x2[..n]);
        let (v0, v1, v2) = (&mut v0[..n], &mut v1[..n], &mut v2[..n]);
        let (a0, a1, a2) = (&mut a0[..n], &mut a1[..n], &mut a2[..n]);
        // `w` has one entry per particle; padding slots name no particle.
        let count = w.len();
        let state = &incoming.state[..count];
        let (position, velocity) = (&incoming.position[..count], &incoming.velocity[..count]);
        let force = &incoming.force[..count];
        for s in 0..n {
            let i = particle[s] as usize;
            if i >= count {
                free[s] = 0.0;
                moving[s] = 0.0;
                continue;
            }
            // `w` is zero for burnt and pinned particles: the free ones are the rest.
            let mass_inverse = w[i];
            let burnt = state[i].is_burnt();
            let is_free = mass_inverse != 0.0;
            free[s] = if is_free { 1.0 } else { 0.0 };
            moving[s] = if burnt { 0.0 } else { 1.0 };
            let (p, v) = (position[i], velocity[i]);
            // A pin (not free, not burnt) starts a frame of its velocity before its target.
            let start = if !is_free && !burnt { p - frame * v } else { p };
            (x0[s], x1[s], x2[s]) = (start.x, start.y, start.z);
            (v0[s], v1[s], v2[s]) = (v.x, v.y, v.z);
            if ACCELERATIONS {
                let a = if is_free {
                    constant + force[i] * mass_inverse
                } else {
                    glam::Vec3::ZERO
                };
                (a0[s], a1[s], a2[s]) = (a.x, a.y, a.z);
            }
        }
    }

    /// Whether the guard may have anything to put back in these slots ([`any_blown`]).
    fn any_blown(&self, max_speed_squared: f32) -> bool {
        let [x0, x1, x2] = &self.x;
        let [v0, v1, v2] = &self.v;
        any_blown([x0, x1, x2], [v0, v1, v2], self.free, max_speed_squared)
    }

    /// One substep's per-slot work: tethers, colliders, then the velocity update and the
    /// next prediction as `phase` says. Compiled for AVX too, taken where the CPU has it
    /// (the same operations, no fused multiply-add, so the same bits).
    fn run(&mut self, pins: &[[f32; 3]], step: &Substep, phase: Phase) {
        #[cfg(target_arch = "x86_64")]
        if crate::sim::simd::avx_available() {
            // SAFETY: this CPU has AVX.
            #[allow(unsafe_code)]
            return unsafe { self.run_avx(pins, step, phase) };
        }
        self.run_portable(pins, step, phase);
    }

    /// [`Self::run`] compiled for AVX. Only called when the CPU has it.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    fn run_avx(&mut self, pins: &[[f32; 3]], step: &Substep, phase: Phase) {
        self.run_portable(pins, step, phase);
    }

    #[inline(always)]
    fn run_portable(&mut self, pins: &[[f32; 3]], step: &Substep, phase: Phase) {
        match step.uniform {
            Some(a) => self.run_with::<true>(pins, step, phase, a),
            None => self.run_with::<false>(pins, step, phase, [0.0; 3]),
        }
    }

    /// [`Self::run`], the outside accelerations `uniform` for every slot when `UNIFORM`, else
    /// from the acceleration arrays.
    #[inline(always)]
    fn run_with<const UNIFORM: bool>(
        &mut self,
        pins: &[[f32; 3]],
        step: &Substep,
        phase: Phase,
        uniform: [f32; 3],
    ) {
        if phase == Phase::FinishAndPredict && step.tethered && step.colliders.is_empty() {
            // Tethers, then the end of the substep and the start of the next, slot by slot:
            // one pass over the arrays instead of two (the same operations on each slot).
            if step.refresh_targets {
                self.place_targets(pins);
            }
            self.tethers_finish_and_predict::<UNIFORM>(step.h, step.drag, uniform);
            return;
        }
        if phase != Phase::PredictOnly {
            if step.tethered {
                if step.refresh_targets {
                    self.place_targets(pins);
                }
                self.tethers();
            }
            if !step.colliders.is_empty() {
                self.collide(step.colliders, step.margin, step.h);
            }
        }
        match phase {
            Phase::PredictOnly => self.predict::<UNIFORM>(step.h, step.drag, uniform),
            Phase::FinishAndPredict => {
                self.finish_and_predict::<UNIFORM>(step.h, step.drag, uniform)
            }
            Phase::Finish => self.finish(step.h),
        }
    }

    /// Each slot's tether target: the position of its pin in `pins`.
    #[inline(always)]
    fn place_targets(&mut self, pins: &[[f32; 3]]) {
        for (s, &pin) in self.tether_pin.iter().enumerate() {
            for (target, &coordinate) in self.tether_target.iter_mut().zip(&pins[pin as usize]) {
                target[s] = coordinate;
            }
        }
    }

    /// Pulls every particle farther from its pin than its tether allows back to the tether's
    /// length (the pin does not move).
    #[inline(always)]
    fn tethers(&mut self) {
        let n = self.free.len();
        let (length, free) = (&self.tether_length[..n], &self.free[..n]);
        let [x0, x1, x2] = &self.x;
        let [u0, u1, u2] = &mut self.u;
        let [t0, t1, t2] = &self.tether_target;
        let (x0, x1, x2) = (&x0[..n], &x1[..n], &x2[..n]);
        let (t0, t1, t2) = (&t0[..n], &t1[..n], &t2[..n]);
        let (u0, u1, u2) = (&mut u0[..n], &mut u1[..n], &mut u2[..n]);
        for s in 0..n {
            let d = [
                (x0[s] + u0[s]) - t0[s],
                (x1[s] + u1[s]) - t1[s],
                (x2[s] + u2[s]) - t2[s],
            ];
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let k = free[s] * (l - length[s]).max(0.0) / l.max(1e-9);
            u0[s] -= k * d[0];
            u1[s] -= k * d[1];
            u2[s] -= k * d[2];
        }
    }

    /// [`Self::tethers`] then [`Self::finish_and_predict`], each slot through both before the
    /// next: the same operations in the same order on every slot, read and written once.
    #[inline(always)]
    fn tethers_finish_and_predict<const UNIFORM: bool>(
        &mut self,
        h: f32,
        drag: f32,
        uniform: [f32; 3],
    ) {
        let (inverse, keep) = (1.0 / h, 1.0 / (1.0 + h * drag));
        let n = self.free.len();
        let (length, free, moving) = (&self.tether_length[..n], &self.free[..n], &self.moving[..n]);
        let [x0, x1, x2] = &mut self.x;
        let [v0, v1, v2] = &mut self.v;
        let [u0, u1, u2] = &mut self.u;
        let [a0, a1, a2] = &self.acceleration;
        let [t0, t1, t2] = &self.tether_target;
        let (x0, x1, x2) = (&mut x0[..n], &mut x1[..n], &mut x2[..n]);
        let (v0, v1, v2) = (&mut v0[..n], &mut v1[..n], &mut v2[..n]);
        let (u0, u1, u2) = (&mut u0[..n], &mut u1[..n], &mut u2[..n]);
        let (a0, a1, a2) = (&a0[..n], &a1[..n], &a2[..n]);
        let (t0, t1, t2) = (&t0[..n], &t1[..n], &t2[..n]);
        for s in 0..n {
            let d = [
                (x0[s] + u0[s]) - t0[s],
                (x1[s] + u1[s]) - t1[s],
                (x2[s] + u2[s]) - t2[s],
            ];
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let k = free[s] * (l - length[s]).max(0.0) / l.max(1e-9);
            // One axis of `finish_and_predict`, from the tethered motion `u`: the next `u`.
            let finish = |x: &mut f32, v: &mut f32, u: f32, a: f32| {
                *x += u;
                let finished = *v + free[s] * (u * inverse - *v);
                let accelerated = (finished + h * a) * keep;
                *v = finished + free[s] * (accelerated - finished);
                moving[s] * h * *v
            };
            let a = if UNIFORM {
                uniform
            } else {
                [a0[s], a1[s], a2[s]]
            };
            u0[s] = finish(&mut x0[s], &mut v0[s], u0[s] - k * d[0], a[0]);
            u1[s] = finish(&mut x1[s], &mut v1[s], u1[s] - k * d[1], a[1]);
            u2[s] = finish(&mut x2[s], &mut v2[s], u2[s] - k * d[2], a[2]);
        }
    }

    /// The end of a substep and the start of the next in one pass: free particles take their
    /// velocity from their displacement, every particle moves by it; then the velocities
    /// take the outside accelerations (`uniform` for every slot when `UNIFORM`, else the
    /// acceleration arrays; drag implicitly, so any step is stable) and the
    /// particles move with them, `u = h v`.
    #[inline(always)]
    fn finish_and_predict<const UNIFORM: bool>(&mut self, h: f32, drag: f32, uniform: [f32; 3]) {
        let (inverse, keep) = (1.0 / h, 1.0 / (1.0 + h * drag));
        let n = self.free.len();
        let (free, moving) = (&self.free[..n], &self.moving[..n]);
        for (axis, &constant) in uniform.iter().enumerate() {
            let x = &mut self.x[axis][..n];
            let v = &mut self.v[axis][..n];
            let u = &mut self.u[axis][..n];
            let a = &self.acceleration[axis][..n];
            for i in 0..n {
                x[i] += u[i];
                let finished = v[i] + free[i] * (u[i] * inverse - v[i]);
                let a = if UNIFORM { constant } else { a[i] };
                let accelerated = (finished + h * a) * keep;
                v[i] = finished + free[i] * (accelerated - finished);
                u[i] = moving[i] * h * v[i];
            }
        }
    }

    /// Pushes free particles out of colliders, taking each collider's friction of their
    /// sliding motion over this substep of `h` seconds ([`sliding_kept`]).
    fn collide(&mut self, colliders: &[WorldCollider], margin: f32, h: f32) {
        for s in 0..self.free.len() {
            if self.free[s] == 0.0 {
                continue;
            }
            let x = glam::Vec3::new(self.x[0][s], self.x[1][s], self.x[2][s]);
            for collider in colliders {
                let u = glam::Vec3::new(self.u[0][s], self.u[1][s], self.u[2][s]);
                let (distance, normal) = collider.distance(x + u);
                if distance >= margin || distance.is_nan() {
                    continue;
                }
                let pushed = u + normal * (margin - distance);
                let sliding = pushed - normal * pushed.dot(normal);
                let moved = pushed - sliding * (1.0 - sliding_kept(collider.friction, h));
                for axis in 0..3 {
                    self.u[axis][s] = moved[axis];
                }
            }
        }
    }

    /// Free particles take their velocity from their displacement over the substep; every
    /// particle moves by it.
    #[inline(always)]
    fn finish(&mut self, h: f32) {
        let inverse = 1.0 / h;
        let n = self.free.len();
        let free = &self.free[..n];
        for axis in 0..3 {
            let (x, v, u) = (
                &mut self.x[axis][..n],
                &mut self.v[axis][..n],
                &self.u[axis][..n],
            );
            for i in 0..n {
                x[i] += u[i];
                v[i] += free[i] * (u[i] * inverse - v[i]);
            }
        }
    }

    /// Velocities take the outside accelerations (`uniform` for every slot when `UNIFORM`, else
    /// the acceleration arrays; drag implicitly, so any step is stable) and
    /// the particles move with them: `u = h v`.
    #[inline(always)]
    fn predict<const UNIFORM: bool>(&mut self, h: f32, drag: f32, uniform: [f32; 3]) {
        let keep = 1.0 / (1.0 + h * drag);
        let n = self.free.len();
        let (free, moving) = (&self.free[..n], &self.moving[..n]);
        for (axis, &constant) in uniform.iter().enumerate() {
            let v = &mut self.v[axis][..n];
            let a = &self.acceleration[axis][..n];
            let u = &mut self.u[axis][..n];
            for i in 0..n {
                let a = if UNIFORM { constant } else { a[i] };
                let accelerated = (v[i] + h * a) * keep;
                v[i] += free[i] * (accelerated - v[i]);
                u[i] = moving[i] * h * v[i];
            }
        }
    }
}

/// Particles [`XpbdSolver::read`] first looks over at a time for a change of inverse mass or a
/// pin, with no branch.
const SCAN_RUN: usize = 16;

/// Reads particle `i`'s inverse mass into `w` (zero once burnt), listing it in `dirty` when
/// it changed, and adds to `news` whether it is free, a moving pin, or a pin that came or went.
#[inline(always)]
fn read_one(
    particles: &Particles,
    i: usize,
    w: &mut [f32],
    dirty: &mut Vec<u32>,
    news: &mut PinNews,
) {
    let burnt = particles.state[i].is_burnt();
    let pinned = particles.inv_mass[i] == 0.0;
    news.free |= !burnt && !pinned;
    news.moving |= pinned && !burnt && particles.velocity[i] != glam::Vec3::ZERO;
    let mass_inverse = if burnt { 0.0 } else { particles.inv_mass[i] };
    let w = &mut w[i];
    if mass_inverse.to_bits() != w.to_bits() {
        // Not burnt, and from or to zero: a pin came or went (the first read after a layout
        // sees every particle change, from NaN; that is no pin change).
        news.changed |= !burnt && !w.is_nan() && (*w == 0.0) != pinned;
        *w = mass_inverse;
        dirty.push(i as u32);
    }
}

/// Vectors [`no_force`] takes at a time: twelve components in separate lanes.
const FORCE_CHUNK: usize = 4;

/// Whether no particle has an external force (each component zero, of either sign): then
/// every free particle's outside acceleration is the same. One pass with no branch, the
/// components of [`FORCE_CHUNK`] vectors at a time in separate lanes, compiled for AVX too
/// and taken where the CPU has it. Folded into one value, each vector's three components
/// waited for one another: over 65 536 vectors (a 256 x 256 cloth, every frame) a copy of
/// the loop outside the crate took 65.7 µs that way, 29.1 in lanes, 9.6 in lanes with AVX.
fn no_force(force: &[glam::Vec3]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if crate::sim::simd::avx_available() {
        #[target_feature(enable = "avx")]
        fn no_force_avx(force: &[glam::Vec3]) -> bool {
            no_force_portable(force)
        }
        // SAFETY: this CPU has AVX.
        #[allow(unsafe_code)]
        return unsafe { no_force_avx(force) };
    }
    no_force_portable(force)
}

/// [`no_force`] on any CPU.
#[inline(always)]
fn no_force_portable(force: &[glam::Vec3]) -> bool {
    let chunks = force.chunks_exact(FORCE_CHUNK);
    let tail = chunks.remainder();
    let mut lanes = [0u32; 3 * FORCE_CHUNK];
    for chunk in chunks {
        for (k, f) in chunk.iter().enumerate() {
            lanes[3 * k] |= f.x.to_bits();
            lanes[3 * k + 1] |= f.y.to_bits();
            lanes[3 * k + 2] |= f.z.to_bits();
        }
    }
    let bits = tail.iter().fold(0u32, |bits, f| {
        bits | f.x.to_bits() | f.y.to_bits() | f.z.to_bits()
    });
    let bits = lanes.iter().fold(bits, |bits, lane| bits | lane);
    bits & !(1 << 31) == 0
}

/// `[f(0), f(1), f(2)]`: per axis, built in place (`core::array::from_fn` is not always
/// inlined, and views are built for every band of every substep).
#[inline(always)]
fn three<T>(mut f: impl FnMut(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// `[f(0), f(1), f(2), f(3)]`: per quarter grid, as [`three`].
#[inline(always)]
fn four<T>(mut f: impl FnMut(usize) -> T) -> [T; 4] {
    [f(0), f(1), f(2), f(3)]
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
    /// Substeps between projections of the bending springs ([`bend_interval`]).
    bend_interval: f32,
}

impl Factors<'_> {
    /// `(w_a, w_b) / ((1 + γ)(w_a + w_b) + α̃)` with `α̃ = 1/(k h²)` for spring `s`
    /// (`1/(k h · interval h)` for a bending spring, projected every `interval` substeps);
    /// zero for a phantom, a dead spring or one of no stiffness.
    fn of(&self, s: u32) -> (f32, f32) {
        if s == PHANTOM {
            return (0.0, 0.0);
        }
        let s = s as usize;
        let springs = self.springs;
        let kind = springs.kind[s] as usize;
        let k = self.coefficients.stiffness[kind];
        let (wa, wb) = (self.w[springs.a[s] as usize], self.w[springs.b[s] as usize]);
        let interval = if springs.kind[s] == SpringKind::Bend {
            self.bend_interval
        } else {
            1.0
        };
        let compliance = 1.0 / (k * self.h * (interval * self.h));
        let denominator = (1.0 + self.gamma[kind]) * (wa + wb) + compliance;
        let live = springs.is_live(s, &self.particles.state);
        if live && k > 0.0 && denominator.is_finite() && denominator > 0.0 {
            (wa / denominator, wb / denominator)
        } else {
            (0.0, 0.0)
        }
    }
}

/// Rows per band of a grid laid out as `slots`. A grid stepped on the pool's threads (of
/// [`PARALLEL_SLOTS`] and up) has bands of [`BAND_ROWS`], each a share of the work; a smaller
/// one, always stepped on one thread, is one band. A lane is a band's rows long and costs a
/// fixed amount to set up: on a 32 x 32 grid, bands of 8 rows made lanes of 64 springs and
/// the set-up a sixth of the spring pass (one band: 7.01 → 6.36 G instructions over `stress
/// --default-only --sizes 32`; in time, ten alternated runs gave medians of 0.220 and
/// 0.209 ms a frame, within the 2-core machine's run-to-run noise). On one thread one band
/// was no slower at 64 x 64 and 88 x 88 than bands of a thousand slots that stay in the
/// first-level cache. Which springs are projected together depends on the grid's size,
/// never on the number of threads.
fn band_rows(slots: GridSlots) -> u32 {
    if slots.len() >= PARALLEL_SLOTS {
        BAND_ROWS
    } else {
        slots.rows()
    }
}

/// The lane layout of a grid cloth, if its springs are the grid's springs: each lane element that
/// stands for a spring is matched to the stored spring with the same ends (first end first; a cut
/// bending or shear spring by the particles it spans). `None` when a spring is missing, reversed or
/// left over, so hand-made springs fall back to the indexed layout.
fn grid_layout(grid: GridShape, springs: &Springs, particles: usize) -> Option<Layout> {
    if (grid.columns * grid.rows) as usize != particles {
        return None;
    }
    let slots = GridSlots::new(grid);
    let lanes = GridLanes::new(slots, band_rows(slots));
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
            // What the spring spans, which still names it once a cut has moved its second end.
            let spans = match lane.kind {
                SpringKind::Bend => {
                    let middle = grid.index((ca + cb) / 2, (ra + rb) / 2) as u32;
                    Some([middle, middle])
                }
                SpringKind::Shear => Some([grid.index(cb, ra) as u32, grid.index(ca, rb) as u32]),
                SpringKind::Structural => None,
            };
            let found = by_end.of(a as usize).iter().copied().find(|&s| {
                let s = s as usize;
                springs.kind[s] == lane.kind
                    && (springs.b[s] == b || spans == Some(springs.spans[s]))
            })?;
            spring[(lane.first + k) as usize] = found;
            matched += 1;
        }
    }
    if matched != springs.len() {
        return None;
    }
    // Each spring matched once (the count is equal, so none twice unless one is missing).
    let mut element = vec![PHANTOM; springs.len()];
    for (e, &s) in spring.iter().enumerate() {
        if let Some(slot) = element.get_mut(s as usize) {
            if *slot != PHANTOM {
                return None;
            }
            *slot = e as u32;
        }
    }
    Some(Layout::Grid {
        slots,
        lanes,
        spring,
        element,
    })
}

/// Whether any free slot's position or velocity is not finite, or its speed squared is past
/// `max_speed_squared` (m²/s²): what the blow-up guard puts back. Branch-free over the slots
/// so it vectorises. It may say yes when the guard puts nothing back (a finite velocity
/// whose square overflows), never no when it puts something back: its answer only decides
/// whether each particle is tested.
fn any_blown(x: [&[f32]; 3], v: [&[f32]; 3], free: &[f32], max_speed_squared: f32) -> bool {
    let n = free.len();
    let (x0, x1, x2) = (&x[0][..n], &x[1][..n], &x[2][..n]);
    let (v0, v1, v2) = (&v[0][..n], &v[1][..n], &v[2][..n]);
    let mut blown = 0u32;
    for s in 0..n {
        // `< ∞` is false for NaN and infinities: an infinite or NaN velocity makes the
        // speed squared infinite or NaN.
        let finite = (x0[s].abs() < f32::INFINITY)
            & (x1[s].abs() < f32::INFINITY)
            & (x2[s].abs() < f32::INFINITY);
        let speed = v0[s] * v0[s] + v1[s] * v1[s] + v2[s] * v2[s];
        let ok = finite & (speed < f32::INFINITY) & (speed <= max_speed_squared);
        blown += u32::from(!ok & (free[s] != 0.0));
    }
    blown > 0
}

/// Springs compared at a time by [`copy_changed_lengths`]: a chunk whose lengths all match
/// is passed over in one vector compare.
const LENGTH_CHUNK: usize = 16;

/// Hands `set` (element, length) the lengths of `lengths` that differ from `seen` in their
/// bits (spring `s` at element `element[s]`), and records them in `seen`. Most frames shrink
/// a few hundred springs along the fire, or none: a grid's rest lengths cost a vector compare
/// per [`LENGTH_CHUNK`] springs, and a copy of the chunks that changed, not a scattered copy
/// of every spring.
fn copy_changed_lengths(
    lengths: &[f32],
    seen: &mut [f32],
    element: &[u32],
    mut set: impl FnMut(usize, f32),
) {
    let n = lengths.len().min(seen.len()).min(element.len());
    let (lengths, seen, element) = (&lengths[..n], &mut seen[..n], &element[..n]);
    let whole = n - n % LENGTH_CHUNK;
    let mut copy = |lengths: &[f32], seen: &mut [f32], element: &[u32]| {
        seen.copy_from_slice(lengths);
        for (&length, &e) in lengths.iter().zip(element) {
            set(e as usize, length);
        }
    };
    for ((lengths, seen), element) in lengths[..whole]
        .chunks_exact(LENGTH_CHUNK)
        .zip(seen[..whole].chunks_exact_mut(LENGTH_CHUNK))
        .zip(element[..whole].chunks_exact(LENGTH_CHUNK))
    {
        let (now, then): (&[f32; LENGTH_CHUNK], &[f32; LENGTH_CHUNK]) =
            (lengths.try_into().unwrap(), (&*seen).try_into().unwrap());
        let mut differ = 0;
        for k in 0..LENGTH_CHUNK {
            differ |= now[k].to_bits() ^ then[k].to_bits();
        }
        if differ != 0 {
            copy(lengths, seen, element);
        }
    }
    copy(&lengths[whole..], &mut seen[whole..], &element[whole..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::integrate::tests::spring_to_pin;

    /// Largest gap over 1 s between a 1 kg particle on a 100 N/m spring of `kind` to a pin
    /// (ω = 10 rad/s, released 0.1 m from rest, no gravity, no damping) and the exact
    /// `0.1 cos ω t`, stepped in frames of `substeps` substeps of `h`.
    fn oscillator_error(kind: SpringKind, h: f32, substeps: u32) -> f32 {
        let (mut particles, springs, params) = spring_to_pin(kind, 100.0, 0.1);
        let around = still_air(&params);
        let mut solver = XpbdSolver::default();
        let frame = h * substeps as f32;
        let frames = (1.0 / frame).round() as u32;
        let mut worst: f32 = 0.0;
        for f in 1..=frames {
            solver.advance(&mut particles, &springs, None, &around, h, substeps);
            let exact = 0.1 * (10.0 * f as f32 * frame).cos();
            worst = worst.max((particles.position[1].x - 1.0 - exact).abs());
        }
        worst
    }

    /// A band's lanes projected side by side (four quarter lanes at 32 columns, pairs at 64)
    /// give the same bits as each lane alone, on grids whose lanes take each way.
    #[test]
    fn lanes_side_by_side_in_a_band_equal_one_by_one() {
        use super::super::lanes::{GridLanes, GridSlots};
        let value = |i: usize, scale: f32| scale * ((i * 7919 % 101) as f32 - 50.0) / 37.0;
        for (columns, rows) in [(32, 6), (64, 6), (64, 9), (100, 5), (40, 7)] {
            let slots = GridSlots::new(GridShape { columns, rows });
            let lanes = GridLanes::new(slots, rows);
            let quarter = slots.quarter_len() as usize;
            let elements = lanes.elements as usize;
            let rest: Vec<f32> = (0..elements).map(|e| 0.05 + value(e, 1e-3)).collect();
            let ca: Vec<f32> = (0..elements).map(|e| 0.3 + value(e + 1, 1e-2)).collect();
            let cb: Vec<f32> = (0..elements).map(|e| 0.2 + value(e + 2, 1e-2)).collect();
            let data = Elements {
                rest: &rest,
                ca: &ca,
                cb: &cb,
                gamma: [0.01, 0.02, 0.03],
                compression: [0.2, 0.5, 1.0],
            };
            let x: [[Vec<f32>; 4]; 3] = core::array::from_fn(|axis| {
                core::array::from_fn(|q| {
                    (0..quarter)
                        .map(|i| 0.05 * ((axis + i + q) % 7) as f32 + value(i + 5 * q + axis, 1e-3))
                        .collect()
                })
            });
            let u0: [[Vec<f32>; 4]; 3] = core::array::from_fn(|axis| {
                core::array::from_fn(|q| {
                    (0..quarter)
                        .map(|i| value(i + 3 * q + axis, 1e-4))
                        .collect()
                })
            });
            let run = |side_by_side: bool| {
                let mut u = u0.clone();
                let view = BandView {
                    x: x.each_ref().map(|axis| axis.each_ref().map(|q| &q[..])),
                    u: u.each_mut().map(|axis| axis.each_mut().map(|q| &mut q[..])),
                    base: 0,
                };
                if side_by_side {
                    project_band::<true>(view, &lanes.lanes, &data);
                } else {
                    project_band::<false>(view, &lanes.lanes, &data);
                }
                u.iter()
                    .flatten()
                    .flatten()
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            };
            let alone = run(false);
            let start: Vec<u32> = u0.iter().flatten().flatten().map(|v| v.to_bits()).collect();
            assert_ne!(
                alone, start,
                "{columns} x {rows}: the springs moved nothing"
            );
            assert_eq!(run(true), alone, "{columns} x {rows}");
        }
    }

    /// A 9 x 7 cotton grid 5 cm apart pinned along its top, its grid shape, and forces with
    /// cotton's springs.
    fn hanging_grid() -> (Particles, Springs, Option<GridShape>, ForceParams) {
        cotton(crate::sim::ClothBuilder::grid(9, 7, 0.05).pin_top_edge())
    }

    /// A cotton cloth as `builder` makes it, its grid shape, and forces with cotton's springs.
    fn cotton(
        builder: crate::sim::ClothBuilder,
    ) -> (Particles, Springs, Option<GridShape>, ForceParams) {
        use crate::sim::material::BurnMaterial;
        let parts = builder
            .build(&BurnMaterial::COTTON, glam::Affine3A::IDENTITY)
            .unwrap();
        let params = ForceParams {
            coefficients: SpringCoefficients::from_material(
                &BurnMaterial::COTTON,
                parts.topology.particle_mass,
            ),
            ..ForceParams::default()
        };
        let grid = parts.topology.grid;
        assert!(grid.is_some());
        (parts.particles, parts.springs, grid, params)
    }

    /// A cloth's surroundings with nothing in them: no collider, tether, stretch limit or
    /// pool, the default guard.
    fn still_air(params: &ForceParams) -> Surroundings<'_> {
        Surroundings {
            params,
            colliders: &[],
            margin: 0.0,
            guard: GuardSettings::default(),
            tethers: None,
            stretch_limit: None,
            pool: None,
        }
    }

    /// `n` slots of made-up state: positions, velocities, motions and tether targets from a
    /// fixed pattern, every fourth slot pinned, every ninth still, every third untethered,
    /// and the acceleration `acceleration(slot, axis)`.
    fn patterned_slots(
        n: usize,
        acceleration: impl Fn(&SlotArrays, usize, usize) -> f32,
    ) -> SlotArrays {
        let mut slots = SlotArrays::default();
        slots.resize(n);
        let wave = |s: usize, k: usize| ((s * 7 + k * 13) % 17) as f32 / 17.0 - 0.5;
        for s in 0..n {
            slots.free[s] = f32::from(s % 4 != 0);
            slots.moving[s] = f32::from(s % 9 != 0);
            slots.tether_length[s] = if s % 3 == 0 { f32::INFINITY } else { 0.1 };
            for k in 0..3 {
                slots.x[k][s] = wave(s, k);
                slots.v[k][s] = 0.3 * wave(s, k + 3);
                slots.u[k][s] = 0.01 * wave(s, k + 6);
                slots.acceleration[k][s] = acceleration(&slots, s, k);
                slots.tether_target[k][s] = 0.2 * wave(s, k + 9);
            }
        }
        slots
    }

    /// Every per-slot array of `f32` starts on a cache line of its own within a page, so no
    /// two alias (see [`staggered`]).
    #[test]
    fn the_slot_arrays_start_on_separate_lines_of_a_page() {
        let mut slots = SlotArrays::default();
        slots.resize(4096);
        let mut lines: Vec<usize> = slots
            .floats_mut()
            .map(|(array, _)| array.as_ptr() as usize % 4096 / 64)
            .collect();
        let count = lines.len();
        lines.sort_unstable();
        lines.dedup();
        assert_eq!(lines.len(), count, "{lines:?}");
    }

    /// A 1/360 s substep with air drag, no collider, the accelerations from their arrays, and
    /// tethers when `tethered`.
    fn still_substep(tethered: bool) -> Substep<'static> {
        Substep {
            h: 1.0 / 360.0,
            drag: 0.4,
            uniform: None,
            colliders: &[],
            margin: 0.0,
            tethered,
            refresh_targets: false,
        }
    }

    /// The bits of every slot's position, velocity and motion.
    fn motion_bits(arrays: &SlotArrays) -> Vec<u32> {
        [&arrays.x, &arrays.v, &arrays.u]
            .into_iter()
            .flatten()
            .flatten()
            .map(|value| value.to_bits())
            .collect()
    }

    /// The per-slot pass with tethers and no colliders runs tethers and the velocity update
    /// slot by slot, in one pass: every array comes out as the two passes leave it, to the
    /// bit, pulled particles included.
    #[test]
    fn the_fused_per_slot_pass_equals_tethers_then_the_velocity_update() {
        let mut slots = patterned_slots(37, |_, s, k| -9.81 * f32::from(k == 1 && s % 5 != 0));
        let step = still_substep(true);
        let original = slots.clone();
        let mut apart = slots.clone();
        slots.whole().run(&[], &step, Phase::FinishAndPredict);
        let mut chunk = apart.whole();
        chunk.tethers();
        chunk.finish_and_predict::<false>(step.h, step.drag, [0.0; 3]);
        let bits = motion_bits;
        assert_eq!(bits(&slots), bits(&apart));
        // The tethers pulled: without them the velocity update alone ends elsewhere.
        let mut untethered = apart.clone();
        untethered.x = original.x.clone();
        untethered.v = original.v.clone();
        untethered.u = original.u.clone();
        untethered
            .whole()
            .finish_and_predict::<false>(step.h, step.drag, [0.0; 3]);
        assert_ne!(bits(&untethered), bits(&apart));
    }

    /// With one outside acceleration for every free slot, the per-slot pass reads it in place
    /// of the acceleration arrays and moves every slot as the arrays do (holding it for the
    /// free slots and zero for the rest, as the copy-in writes them), to the bit, in every
    /// phase, with tethers and without.
    #[test]
    fn one_acceleration_for_all_moves_as_the_arrays_do() {
        let a = [0.25, -9.81, 0.5];
        // The copy-in's accelerations: `a` for the free slots, zero for the rest.
        let slots = patterned_slots(37, |slots, s, k| a[k] * slots.free[s]);
        let bits = motion_bits;
        for tethered in [false, true] {
            for phase in [Phase::PredictOnly, Phase::FinishAndPredict, Phase::Finish] {
                let step = still_substep(tethered);
                let (mut arrays, mut one) = (slots.clone(), slots.clone());
                // The copy-in leaves the arrays unwritten: whatever is in them is not read.
                for axis in &mut one.acceleration {
                    axis.fill(f32::NAN);
                }
                arrays.whole().run(&[], &step, phase);
                let uniform = Substep {
                    uniform: Some(a),
                    ..step
                };
                one.whole().run(&[], &uniform, phase);
                assert_eq!(bits(&arrays), bits(&one), "tethered {tethered}");
                if phase != Phase::Finish {
                    assert_ne!(bits(&arrays), bits(&slots), "the slots moved");
                }
            }
        }
    }

    /// A cloth with nothing pinned, no gravity and an external force on every particle of its
    /// mass times `a` moves as one body accelerating at `a` (its springs stay at rest length),
    /// as it does with no force and gravity `a`: the force reaches the solver through the
    /// acceleration arrays, gravity through the one acceleration of every free particle. The
    /// grid is big enough to be cut into bands (each a share of the per-slot pass on a pool),
    /// stepped here on one thread: every band's slots must move.
    #[test]
    fn an_external_force_accelerates_the_cloth_as_gravity_does() {
        let (mut pushed, springs, grid, params) = cotton(crate::sim::ClothBuilder::grid(
            16,
            PARALLEL_SLOTS as u32 / 16,
            0.02,
        ));
        let mut falling = pushed.clone();
        let a = glam::Vec3::new(0.6, -2.0, 1.2);
        for i in 0..pushed.len() {
            pushed.external_force[i] = pushed.mass[i] * a;
        }
        let weightless = ForceParams {
            gravity: glam::Vec3::ZERO,
            ..params
        };
        let falls = ForceParams {
            gravity: a,
            ..params
        };
        let (h, substeps) = (1.0 / 360.0, 6);
        let frame = h * substeps as f32;
        for (particles, params) in [(&mut pushed, &weightless), (&mut falling, &falls)] {
            let mut solver = XpbdSolver::default();
            solver.advance(particles, &springs, grid, &still_air(params), h, substeps);
            match &solver.layout {
                Layout::Grid { lanes, .. } => assert!(lanes.bands.len() > 2, "several bands"),
                _ => panic!("a grid"),
            }
            for v in &particles.velocity {
                assert!(
                    (*v - a * frame).length() < 1e-4,
                    "{v} against {}",
                    a * frame
                );
            }
        }
    }

    /// A particle whose velocity went NaN is put back where it was, at rest, and counted
    /// (with the neighbours its NaN reached through their springs within the frame); no NaN
    /// is left, and the cloth carries on from there.
    #[test]
    fn the_guard_puts_back_a_blown_particle_and_the_cloth_carries_on() {
        let (mut particles, springs, grid, params) = hanging_grid();
        let around = still_air(&params);
        let mut solver = XpbdSolver::default();
        let (h, substeps) = (1.0 / 360.0, 6);
        solver.advance(&mut particles, &springs, grid, &around, h, substeps);
        let blown = 40;
        particles.velocity[blown] = glam::Vec3::new(f32::NAN, 0.0, 0.0);
        let before = particles.position.clone();
        let (put_back, _) = solver.advance(&mut particles, &springs, grid, &around, h, substeps);
        assert!(put_back >= 1, "{put_back}");
        assert_eq!(particles.position[blown], before[blown]);
        assert_eq!(particles.velocity[blown], glam::Vec3::ZERO);
        assert!(particles.position.iter().all(|p| p.is_finite()));
        assert!(particles.velocity.iter().all(|v| v.is_finite()));
        // The next frames carry on, moving the cloth and putting nothing back.
        for _ in 0..5 {
            let before = particles.position.clone();
            let (put_back, _) =
                solver.advance(&mut particles, &springs, grid, &around, h, substeps);
            assert_eq!(put_back, 0);
            assert_ne!(particles.position, before);
        }
    }

    /// On a cloth big enough to be shared between threads, whose copy in, substeps and copy
    /// back run under one scope, a blown particle is found by the last substep's per-slot
    /// pass and put back by the copy back, as on one thread: the same count and the same
    /// bits with a pool of one, two and four threads as with none.
    #[test]
    fn the_guard_puts_back_a_blown_particle_on_any_number_of_threads() {
        use bevy::tasks::TaskPoolBuilder;
        let run = |threads: Option<usize>| {
            let pool = threads.map(|n| TaskPoolBuilder::new().num_threads(n).build());
            let (mut particles, springs, grid, params) =
                cotton(crate::sim::ClothBuilder::grid(96, 96, 0.015).pin_top_edge());
            let around = Surroundings {
                pool: pool.as_ref(),
                ..still_air(&params)
            };
            let mut solver = XpbdSolver::default();
            let (h, substeps) = (1.0 / 360.0, 6);
            solver.advance(&mut particles, &springs, grid, &around, h, substeps);
            assert!(
                solver.slots.len() >= PARALLEL_SLOTS,
                "shared between threads"
            );
            let blown = 96 * 60 + 30;
            particles.velocity[blown] = glam::Vec3::new(0.0, f32::NAN, 0.0);
            let before = particles.position[blown];
            let (put_back, _) =
                solver.advance(&mut particles, &springs, grid, &around, h, substeps);
            assert!(put_back >= 1, "{put_back}");
            assert_eq!(particles.position[blown], before);
            assert_eq!(particles.velocity[blown], glam::Vec3::ZERO);
            assert!(particles.position.iter().all(|p| p.is_finite()));
            assert!(particles.velocity.iter().all(|v| v.is_finite()));
            let (again, _) = solver.advance(&mut particles, &springs, grid, &around, h, substeps);
            assert_eq!(again, 0, "nothing left to put back");
            (put_back, particles.position, particles.velocity)
        };
        let alone = run(None);
        for threads in [1, 2, 4] {
            assert!(run(Some(threads)) == alone, "{threads} threads");
        }
    }

    /// A grid's rest lengths reach the solver when they change between frames (heat shrinks a
    /// few, or a game sets one): after a change, a solver that copies only the changed
    /// lengths steps to the same bits as one built afresh on the same state, and the change
    /// shows (a shortened spring pulls its ends together).
    #[test]
    fn a_changed_rest_length_steps_as_a_fresh_solver_would() {
        let (mut particles, mut springs, grid, params) = hanging_grid();
        let around = still_air(&params);
        let (h, substeps) = (1.0 / 600.0, 10);
        let mut kept = XpbdSolver::default();
        for _ in 0..20 {
            kept.advance(&mut particles, &springs, grid, &around, h, substeps);
        }
        assert!(matches!(kept.layout, Layout::Grid { .. }), "a grid layout");
        // Shorten every structural spring in the middle column by 30 %, as heat would.
        let middle = |i: u32| i % 9 == 4;
        let mut changed = 0;
        for s in 0..springs.len() {
            let (a, b) = (springs.a[s], springs.b[s]);
            if springs.kind[s] == SpringKind::Structural && middle(a) && middle(b) {
                springs.rest_length[s] *= 0.7;
                changed += 1;
            }
        }
        assert_eq!(changed, 6);
        let mut fresh_particles = particles.clone();
        let mut fresh = XpbdSolver::default();
        for _ in 0..10 {
            kept.advance(&mut particles, &springs, grid, &around, h, substeps);
            fresh.advance(&mut fresh_particles, &springs, grid, &around, h, substeps);
        }
        let bits = |p: &Particles| -> Vec<[u32; 3]> {
            p.position
                .iter()
                .map(|x| x.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&particles), bits(&fresh_particles));
        // The column pulled up: its bottom particle is higher than its neighbours'.
        let bottom = 6 * 9;
        let y = |i: usize| particles.position[i].y;
        assert!(
            y(bottom + 4) > y(bottom + 2) + 0.01,
            "{} {}",
            y(bottom + 4),
            y(bottom + 2)
        );
    }

    /// Any non-zero component of any vector, in a whole chunk or the tail, is a force; zeros
    /// of either sign are not. The same with AVX and without.
    #[test]
    fn no_force_finds_any_non_zero_component() {
        let both = |force: &[glam::Vec3]| {
            let (portable, chosen) = (no_force_portable(force), no_force(force));
            assert_eq!(portable, chosen, "{force:?}");
            chosen
        };
        for n in [0, 1, 3, 4, 5, 8, 13] {
            let mut force = vec![glam::Vec3::ZERO; n];
            assert!(both(&force), "{n} zeros");
            if n == 0 {
                continue;
            }
            force[n / 2] = glam::Vec3::new(-0.0, 0.0, -0.0);
            assert!(both(&force), "{n}: a negative zero is no force");
            for i in 0..n {
                for axis in 0..3 {
                    for value in [1.0e-30, -2.0, f32::NAN, f32::INFINITY] {
                        let mut pushed = force.clone();
                        pushed[i][axis] = value;
                        assert!(!both(&pushed), "{n}: {value} at {i}, axis {axis}");
                    }
                }
            }
        }
    }

    /// A bending spring projected every other substep with the compliance of the two
    /// substeps swings at the spring's own frequency, as closely as one projected every
    /// substep. A compliance of one substep would make it a spring of half the stiffness,
    /// one of two substeps (`1/(k (2h)²)`) twice the stiffness: either puts the particle
    /// out of phase within the second.
    #[test]
    fn bending_springs_every_other_substep_keep_their_frequency() {
        assert_eq!(bend_interval(6), 2);
        assert_eq!(bend_interval(5), 1);
        assert_eq!(bend_interval(1), 1);
        let h = 1.0 / 360.0;
        let every = oscillator_error(SpringKind::Structural, h, 6);
        let other = oscillator_error(SpringKind::Bend, h, 6);
        // XPBD is first order in ω h: 1.2 cm of the 0.1 m swing after 1 s at ω h = 0.028.
        // The wrong compliances measured 18 and 19 cm.
        assert!(every < 0.02, "every substep: {every} m");
        assert!(
            (other - every).abs() < 0.1 * every,
            "every other substep: {other} m against {every} m every substep"
        );
        // Frames of an odd number of substeps project every substep: the same as a
        // structural spring to the bit.
        let odd = oscillator_error(SpringKind::Bend, h, 5);
        assert_eq!(odd, oscillator_error(SpringKind::Structural, h, 5));
    }
}
