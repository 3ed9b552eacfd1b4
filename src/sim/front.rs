//! The burning front: which particles are on fire, which springs are still shrinking, which
//! triangles are still drawn, kept as lists so a step's work follows the fire instead of
//! sweeping the whole cloth.
//!
//! One pass over the particles remains per step, [`Front::scan`]: it reads each temperature
//! and state (so a temperature or a state written from outside takes effect) and counts what
//! the report needs, a run of 16 particles at a time, doing per-particle work only in runs
//! where something changes. It does no work per spring or per triangle; everything else runs over
//! the lists: the heat push from the particles on fire to their neighbours, the shrinking of
//! the springs of warm particles down to their floor (and, for XPBD, Provot's stretch limit
//! on them), the cutting of springs that span a particle that just burnt, and the removal of
//! its triangles from the drawn list.

use super::combustion::CombustionReport;
use super::material::BurnMaterial;
use super::particles::{BurnState, Particles};
#[cfg(test)]
use super::springs::SpanRule;
use super::springs::{NO_SPAN, SpringCoefficients, SpringKind, Springs};
use super::topology::Topology;

const NONE: u32 = u32::MAX;

/// Particles [`Front::scan`] tests at a time for a run with nothing to do.
const SETTLED_RUN: usize = 16;

/// The fraction of its initial length a spring's rest length must drop below before the
/// stretch limit holds it: a spring warmed by a trace of heat (conduction, or a plume's air
/// reaching the whole cloth) has barely shrunk, and the constraints hold it as they hold a
/// cold one. Without this the limit ran over every spring of a cloth in a plume, each substep.
pub const LIMITED_BELOW: f32 = 0.99;

/// Whether a spring of rest length `rest` built `initial` long (m) has shrunk past
/// [`LIMITED_BELOW`]: one of the springs the stretch limit holds.
#[inline]
pub fn is_shrunk_length(rest: f32, initial: f32) -> bool {
    rest < LIMITED_BELOW * initial
}

/// Removes `item` from `list` (by swapping in the last item) if `place` says it is there;
/// `place` holds each item's place in `list`, `NONE` when absent.
fn remove_from(list: &mut Vec<u32>, place: &mut [u32], item: usize) {
    let at = place[item];
    if at == NONE {
        return;
    }
    list.swap_remove(at as usize);
    if let Some(&moved) = list.get(at as usize) {
        place[moved as usize] = at;
    }
    place[item] = NONE;
}

/// Compressed rows: `start[i]..start[i + 1]` indexes `items` for row `i`.
#[derive(Clone, Debug, Default)]
struct Rows {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Rows {
    /// Rows for `rows` rows holding, for each of `count` items, the rows `of(item)` names
    /// (`NONE` and out-of-range entries skipped).
    fn build(&mut self, rows: usize, count: usize, of: impl Fn(usize) -> [u32; 4]) {
        self.start.clear();
        self.start.resize(rows + 1, 0);
        for item in 0..count {
            for row in of(item) {
                if (row as usize) < rows {
                    self.start[row as usize + 1] += 1;
                }
            }
        }
        for row in 0..rows {
            self.start[row + 1] += self.start[row];
        }
        self.items.clear();
        self.items.resize(self.start[rows] as usize, 0);
        let mut cursor = self.start[..rows].to_vec();
        for item in 0..count {
            for row in of(item) {
                if (row as usize) < rows {
                    self.items[cursor[row as usize] as usize] = item as u32;
                    cursor[row as usize] += 1;
                }
            }
        }
    }

    fn of(&self, row: usize) -> &[u32] {
        &self.items[self.start[row] as usize..self.start[row + 1] as usize]
    }

    fn heap_bytes(&self) -> usize {
        (self.start.capacity() + self.items.capacity()) * size_of::<u32>()
    }
}

/// A cloth's burning front and the rows that lead from a particle to its springs and
/// triangles.
#[derive(Clone, Debug, Default)]
pub struct Front {
    built_for: (usize, usize, usize),
    /// The springs each particle is in as an end or spans.
    springs_of: Rows,
    /// The triangles each particle is a corner of.
    triangles_of: Rows,
    /// Particles on fire, and each particle's place in that list (`NONE` when not).
    ignited: Vec<u32>,
    ignited_at: Vec<u32>,
    /// Whether each particle has been warmer than the cloth's initial temperature, and how
    /// many have.
    warm: Vec<bool>,
    warm_count: u32,
    /// Whether each burnt particle has been dealt with (springs cut, triangles removed).
    gone: Vec<bool>,
    /// The heated springs (an end has been warm; live): those shrinking and those shrunk to
    /// their floor, by index, then those added since the last [`Front::shrink`]; whether each
    /// spring is in that list; and scratch for merging the added ones in.
    shrinking: Vec<u32>,
    is_shrinking: Vec<bool>,
    sorted_len: usize,
    merged: Vec<u32>,
    /// The shrinking springs whose rest length is below [`LIMITED_BELOW`] of its initial
    /// length (those the XPBD solver's stretch limit holds), by index, as of the last shrink.
    shrunk: Vec<u32>,
    /// The triangle in each place of the drawn list, and each triangle's place.
    live_triangle: Vec<u32>,
    live_at: Vec<u32>,
    /// Pinned particles not burnt, as of the latest scan.
    pins: Vec<u32>,
}

/// What a scan counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Particles burnt.
    pub burnt: u32,
    /// Pinned particles not burnt.
    pub pins_left: u32,
}

impl Front {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        let words = [
            &self.ignited,
            &self.ignited_at,
            &self.shrinking,
            &self.merged,
            &self.shrunk,
            &self.live_triangle,
            &self.live_at,
            &self.pins,
        ]
        .iter()
        .map(|v| v.capacity())
        .sum::<usize>();
        words * size_of::<u32>()
            + self.warm.capacity()
            + self.is_shrinking.capacity()
            + self.gone.capacity()
            + self.springs_of.heap_bytes()
            + self.triangles_of.heap_bytes()
    }

    /// Makes the next [`Self::prepare`] build everything anew (memory is reused).
    pub fn restart(&mut self) {
        self.built_for = (usize::MAX, 0, 0);
    }

    /// Particles on fire.
    pub fn ignited(&self) -> &[u32] {
        &self.ignited
    }

    /// Pinned particles not burnt (as of the latest scan).
    pub fn pins(&self) -> &[u32] {
        &self.pins
    }

    /// The heated springs: live springs with an end that has been warm, shrinking or shrunk
    /// to their floor.
    pub fn shrinking(&self) -> &[u32] {
        &self.shrinking
    }

    /// The shrunk springs: live springs on the [`Front::shrinking`] list whose rest length is
    /// below [`LIMITED_BELOW`] of its initial length, by index, as of the last
    /// [`Front::shrink`].
    pub fn shrunk(&self) -> &[u32] {
        &self.shrunk
    }

    /// Whether any particle has ever been warmer than the initial temperature.
    pub fn any_warm(&self) -> bool {
        self.warm_count > 0
    }

    /// Builds the rows and lists for this cloth if not already: on its first step, or when
    /// its particles, springs or triangles changed in number. Springs spanning particles that
    /// were burnt before the first step (cut-outs) are cut.
    pub fn prepare(
        &mut self,
        particles: &Particles,
        springs: &mut Springs,
        topology: &mut Topology,
    ) {
        let n = particles.len();
        let key = (n, springs.len(), topology.triangles.len());
        if self.built_for == key {
            return;
        }
        self.built_for = key;
        self.springs_of.build(n, springs.len(), |s| {
            let [first, second] = springs.spans[s];
            let second = if second == first { NO_SPAN } else { second };
            [springs.a[s], springs.b[s], first, second]
        });
        let triangles = &topology.triangles;
        self.triangles_of.build(n, triangles.len(), |t| {
            let [a, b, c] = triangles[t];
            [a, b, c, NONE]
        });
        self.ignited.clear();
        self.ignited.reserve(n);
        self.ignited_at.clear();
        self.ignited_at.resize(n, NONE);
        self.warm.clear();
        self.warm.resize(n, false);
        self.warm_count = 0;
        self.gone.clear();
        self.gone.resize(n, false);
        self.shrinking.clear();
        self.shrinking.reserve(springs.len());
        self.is_shrinking.clear();
        self.is_shrinking.resize(springs.len(), false);
        self.sorted_len = 0;
        self.merged.clear();
        self.merged.reserve(springs.len());
        self.shrunk.clear();
        self.shrunk.reserve(springs.len());
        self.pins.clear();
        self.pins.reserve(n);
        // The drawn list from the triangles whose corners have not burnt.
        self.live_at.clear();
        self.live_at.resize(triangles.len(), NONE);
        self.live_triangle.clear();
        self.live_triangle.reserve(triangles.len());
        topology.live_indices.clear();
        topology.live_indices.reserve(3 * triangles.len());
        for (t, triangle) in triangles.iter().enumerate() {
            if triangle
                .iter()
                .all(|&i| !particles.state[i as usize].is_burnt())
            {
                self.live_at[t] = self.live_triangle.len() as u32;
                self.live_triangle.push(t as u32);
                topology.live_indices.extend_from_slice(triangle);
            }
        }
        // Particles burnt before the first step (cut-outs) are gone already: their triangles
        // are not drawn, their springs are dead by their ends, and the springs over them cut.
        for i in 0..n {
            if particles.state[i].is_burnt() {
                self.gone[i] = true;
                self.sever(springs, &particles.state, &[i as u32]);
            }
            if particles.inv_mass[i] == 0.0 && !particles.state[i].is_burnt() {
                self.pins.push(i as u32);
            }
        }
    }

    /// Updates burn states from temperatures and the time on fire, over every particle:
    /// ignited strictly above the ignition temperature; an ignited particle burnt once it is
    /// strictly above the burnt temperature and has been on fire for the material's
    /// [`burn_time`](BurnMaterial::burn_time) (its clock, [`Particles::burning_for`], runs on by
    /// `h` seconds each scan); an intact particle strictly above the burnt temperature (set
    /// from outside) burnt at once; burnt is final; an ignited particle cooled below ignition
    /// is intact again, its clock back to zero.
    ///
    /// The two conditions, each the later: on a fine grid the front crosses a particle's patch
    /// quickly and its temperature passes the burnt one early, and the particle glows on
    /// (spent: it no longer pushes heat, see [`super::heat`]) until its burn time is up, so
    /// the band of burning cloth behind the front is as wide in metres as on the reference
    /// grid; on a coarse grid the front takes longer to cross than the burn time, and the
    /// particle burns as long as the front is inside its patch, as the physical model's flame
    /// keeps it.
    ///
    /// Appends the particles burnt in this step (or set burnt from outside since the last
    /// step) to `newly_burnt`; keeps the list of particles on fire; starts the springs of
    /// newly warm particles shrinking; counts burnt particles and pins left.
    pub fn scan(
        &mut self,
        particles: &mut Particles,
        springs: &Springs,
        material: &BurnMaterial,
        h: f32,
        newly_burnt: &mut Vec<u32>,
    ) -> (CombustionReport, Counts) {
        let mut report = CombustionReport::default();
        let mut counts = Counts::default();
        self.pins.clear();
        let (ignition, burnt_above, initial) = (
            material.ignition_temperature,
            material.burnt_temperature,
            material.initial_temperature,
        );
        let burn_time = material.burn_time;
        let h = if h.is_finite() { h.max(0.0) } else { 0.0 };
        let n = particles.len();
        // Particles built by hand may lack clocks: they start at zero.
        particles.burning_for.resize(n, 0.0);
        let mut first = 0;
        while first < n {
            let end = (first + SETTLED_RUN).min(n);
            // A run of particles none of which changes or is listed this step (the usual
            // case far from the fire) needs only its burnt ones counted.
            if let Some(burnt) =
                self.settled_run(particles, first..end, [ignition, burnt_above, initial])
            {
                counts.burnt += burnt;
                first = end;
                continue;
            }
            for i in first..end {
                let t = particles.temperature[i];
                let state = particles.state[i];
                let clock = &mut particles.burning_for[i];
                if state == BurnState::Ignited {
                    *clock += h;
                }
                let next = match state {
                    BurnState::Burnt => BurnState::Burnt,
                    BurnState::Intact if t > burnt_above => BurnState::Burnt,
                    BurnState::Ignited if t > burnt_above && *clock >= burn_time => {
                        BurnState::Burnt
                    }
                    _ if t > ignition => BurnState::Ignited,
                    _ => BurnState::Intact,
                };
                if next == BurnState::Intact {
                    *clock = 0.0;
                }
                if next == BurnState::Burnt {
                    counts.burnt += 1;
                    if !self.gone[i] {
                        self.gone[i] = true;
                        newly_burnt.push(i as u32);
                        report.newly_burnt += 1;
                    }
                } else if particles.inv_mass[i] == 0.0 {
                    self.pins.push(i as u32);
                }
                if state == BurnState::Intact && next == BurnState::Ignited {
                    report.newly_ignited += 1;
                }
                particles.state[i] = next;
                let on_fire = next == BurnState::Ignited;
                if on_fire != (self.ignited_at[i] != NONE) {
                    if on_fire {
                        self.ignited_at[i] = self.ignited.len() as u32;
                        self.ignited.push(i as u32);
                    } else {
                        self.remove_ignited(i);
                    }
                }
                if !self.warm[i] && t > initial && next != BurnState::Burnt {
                    self.warm[i] = true;
                    self.warm_count += 1;
                    self.start_shrinking(i, springs);
                }
            }
            first = end;
        }
        counts.pins_left = self.pins.len() as u32;
        report.ignited = self.ignited.len() as u32;
        (report, counts)
    }

    /// If no particle of `run` would change in [`Front::scan`] (its state stays, it joins or
    /// leaves no list, it is not a pin to list), how many of them are burnt; else `None`.
    /// `[ignition, burnt_above, initial]`: the material's temperatures, °C, as the scan
    /// compares with them.
    /// Settled: burnt and already dealt with, or intact, not on fire, no hotter than its
    /// ignition and burnt temperatures, not pinned, and warm already or no warmer than the
    /// initial temperature. Tested without a branch per particle, so the whole run costs a
    /// few instructions a particle.
    fn settled_run(
        &self,
        particles: &Particles,
        run: core::ops::Range<usize>,
        [ignition, burnt_above, initial]: [f32; 3],
    ) -> Option<u32> {
        let temperature = &particles.temperature[run.clone()];
        let state = &particles.state[run.clone()];
        let inv_mass = &particles.inv_mass[run.clone()];
        let (gone, warm) = (&self.gone[run.clone()], &self.warm[run.clone()]);
        let ignited_at = &self.ignited_at[run];
        let mut settled = true;
        let mut burnt = 0;
        for k in 0..temperature.len() {
            let t = temperature[k];
            let is_burnt = state[k] == BurnState::Burnt;
            // The same comparisons as the scan's, so a NaN temperature settles as it scans.
            let above = |limit: f32| t > limit;
            let quiet = (state[k] == BurnState::Intact)
                & !above(burnt_above)
                & !above(ignition)
                & (inv_mass[k] != 0.0)
                & (warm[k] | !above(initial))
                & (ignited_at[k] == NONE);
            settled &= (is_burnt & gone[k]) | quiet;
            burnt += u32::from(is_burnt);
        }
        settled.then_some(burnt)
    }

    fn remove_ignited(&mut self, i: usize) {
        remove_from(&mut self.ignited, &mut self.ignited_at, i);
    }

    /// Puts particle `i`'s springs (those it ends; not those it only spans) on the shrinking
    /// list.
    fn start_shrinking(&mut self, i: usize, springs: &Springs) {
        for &s in self.springs_of.of(i) {
            let spring = s as usize;
            let ends = springs.a[spring] as usize == i || springs.b[spring] as usize == i;
            if ends && !self.is_shrinking[spring] {
                self.is_shrinking[spring] = true;
                self.shrinking.push(s);
            }
        }
    }

    /// Sorts the springs added to the shrinking list since the last shrink into the rest, so
    /// the list is in index order (a pass over it reads the spring arrays in order, not in
    /// the order the particles warmed: under a plume, that is scattered over the whole
    /// cloth). Costs a sort of the added springs and one merge, only when some were added.
    fn merge_added(&mut self) {
        let sorted = self.sorted_len;
        if sorted == self.shrinking.len() {
            return;
        }
        let (old, added) = self.shrinking.split_at_mut(sorted);
        added.sort_unstable();
        self.merged.clear();
        let (mut i, mut j) = (0, 0);
        while i < old.len() && j < added.len() {
            if old[i] <= added[j] {
                self.merged.push(old[i]);
                i += 1;
            } else {
                self.merged.push(added[j]);
                j += 1;
            }
        }
        self.merged.extend_from_slice(&old[i..]);
        self.merged.extend_from_slice(&added[j..]);
        core::mem::swap(&mut self.shrinking, &mut self.merged);
    }

    /// Cuts the live springs that pass over the particles in `newly_burnt` (a bending or shear
    /// spring would otherwise hold across the gap), by each spring's
    /// [`SpanRule`](super::springs::SpanRule): each one's second end is moved to the burnt particle
    /// it spanned, which makes it dead for every loop that checks its ends. Returns how many were
    /// cut.
    pub fn sever(&self, springs: &mut Springs, state: &[BurnState], newly_burnt: &[u32]) -> u32 {
        let mut cut = 0;
        for &burnt in newly_burnt {
            for &s in self.springs_of.of(burnt as usize) {
                let s = s as usize;
                if springs.is_live(s, state) && springs.cut_by(s, burnt, state) {
                    springs.b[s] = burnt;
                    cut += 1;
                }
            }
        }
        cut
    }

    /// Shrinks the rest length of every spring on the shrinking list by Larboulette's rule as
    /// the paper uses it, per second of `h`:
    ///
    /// `l ← max(l − factor × h × l_init × (ΔT_a + ΔT_b) / k, floor × l_init)`
    ///
    /// with `ΔT = max(T − T_initial, 0)` (measured from the initial temperature so cold cloth
    /// keeps its size). A spring of zero stiffness does not shrink; a spring that dies leaves
    /// the list (one at its floor stays: its stretch is still limited). The springs whose rest
    /// length is then below [`LIMITED_BELOW`] of their initial one are the
    /// [`Front::shrunk`] list.
    pub fn shrink(
        &mut self,
        springs: &mut Springs,
        particles: &Particles,
        material: &BurnMaterial,
        coefficients: &SpringCoefficients,
        h: f32,
    ) {
        let rate = material.shrink_factor * h;
        let (floor, t0) = (material.min_rest_fraction, material.initial_temperature);
        // Per kind, the shrink per metre of initial length per kelvin of heat this step (none
        // for a spring of zero stiffness, or for no rate).
        let per_kelvin = coefficients
            .stiffness
            .map(|k| if rate > 0.0 && k > 0.0 { rate / k } else { 0.0 });
        self.merge_added();
        // The spring arrays sliced to one length, so indexing by a listed spring checks once.
        let n = springs.len();
        let (a, b, kind) = (&springs.a[..n], &springs.b[..n], &springs.kind[..n]);
        let (initial, rest) = (
            &springs.initial_rest_length[..n],
            &mut springs.rest_length[..n],
        );
        let (state, temperature) = (&particles.state, &particles.temperature);
        let excess = |p: u32| (temperature[p as usize] - t0).max(0.0);
        self.shrunk.clear();
        let mut kept = 0;
        for place in 0..self.shrinking.len() {
            let s = self.shrinking[place];
            let spring = s as usize;
            let (pa, pb) = (a[spring], b[spring]);
            if state[pa as usize].is_burnt() || state[pb as usize].is_burnt() {
                self.is_shrinking[spring] = false;
                continue;
            }
            let by =
                initial[spring] * (excess(pa) + excess(pb)) * per_kelvin[kind[spring] as usize];
            if by > 0.0 {
                rest[spring] = (rest[spring] - by).max(floor * initial[spring]);
            }
            if is_shrunk_length(rest[spring], initial[spring]) {
                self.shrunk.push(s);
            }
            self.shrinking[kept] = s;
            kept += 1;
        }
        self.shrinking.truncate(kept);
        self.sorted_len = kept;
    }

    /// Removes the triangles of the particles in `newly_burnt` from the drawn list (each by
    /// swapping in the list's last triangle).
    pub fn cull(&mut self, topology: &mut Topology, newly_burnt: &[u32]) {
        for &burnt in newly_burnt {
            for &t in self.triangles_of.of(burnt as usize) {
                let place = self.live_at[t as usize];
                if place == NONE {
                    continue;
                }
                let place = place as usize;
                let last = self.live_triangle.len() - 1;
                let moved = self.live_triangle[last];
                self.live_triangle.swap_remove(place);
                topology
                    .live_indices
                    .copy_within(3 * last..3 * last + 3, 3 * place);
                topology.live_indices.truncate(3 * last);
                if place != last {
                    self.live_at[moved as usize] = place as u32;
                }
                self.live_at[t as usize] = NONE;
            }
        }
    }

    /// The in-plane springs of particle `i` (structural and shear; a mesh's edges), with the
    /// particle at their other end.
    pub fn in_plane_neighbours<'a>(
        &'a self,
        i: usize,
        springs: &'a Springs,
    ) -> impl Iterator<Item = (usize, usize)> + 'a {
        self.springs_of.of(i).iter().filter_map(move |&s| {
            let s = s as usize;
            if springs.kind[s] == SpringKind::Bend {
                return None;
            }
            let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
            match (a == i, b == i) {
                (true, false) => Some((s, b)),
                (false, true) => Some((s, a)),
                _ => None,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// The step between scans, s.
    const STEP: f32 = 1.0 / 60.0;

    /// `n` particles in a row 5 cm apart, none pinned, at the initial temperature of
    /// `material`, with the springs `pairs`.
    fn row(
        n: usize,
        material: &BurnMaterial,
        pairs: &[(u32, u32, SpringKind)],
    ) -> (Particles, Springs) {
        let position: Vec<Vec3> = (0..n).map(|i| Vec3::X * 0.05 * i as f32).collect();
        let particles = Particles {
            velocity: vec![Vec3::ZERO; n],
            mass: vec![1.0; n],
            inv_mass: vec![1.0; n],
            temperature: vec![material.initial_temperature; n],
            state: vec![BurnState::Intact; n],
            burning_for: vec![0.0; n],
            anchor: position.clone(),
            external_force: vec![Vec3::ZERO; n],
            position,
        };
        let mut springs = Springs::default();
        for &(a, b, kind) in pairs {
            springs.push(a, b, 0.05 * b.abs_diff(a) as f32, kind);
        }
        (particles, springs)
    }

    fn scanned(
        front: &mut Front,
        particles: &mut Particles,
        springs: &mut Springs,
        material: &BurnMaterial,
    ) -> (CombustionReport, Vec<u32>) {
        front.prepare(particles, springs, &mut Topology::default());
        let mut newly_burnt = Vec::new();
        let (report, _) = front.scan(particles, springs, material, STEP, &mut newly_burnt);
        (report, newly_burnt)
    }

    #[test]
    fn every_material_ignites_exactly_above_its_threshold() {
        for material in BurnMaterial::PRESETS {
            let (mut particles, mut springs) = row(3, &material, &[]);
            let threshold = material.ignition_temperature;
            particles.temperature = vec![threshold, threshold.next_up(), threshold.next_down()];
            let (report, _) = scanned(
                &mut Front::default(),
                &mut particles,
                &mut springs,
                &material,
            );
            assert_eq!(
                particles.state,
                [BurnState::Intact, BurnState::Ignited, BurnState::Intact],
                "{}",
                material.name
            );
            assert_eq!((report.newly_ignited, report.ignited), (1, 1));
        }
    }

    /// The scan skips runs of particles with nothing to do; whatever is edited wherever in a
    /// run (heat, a pin, a burn or a put-out set from outside, cooling, NaN), the states,
    /// lists and counts are those of the rules applied to every particle.
    #[test]
    fn a_scan_finds_every_change_wherever_it_falls_in_a_run() {
        let material = BurnMaterial::COTTON;
        let n = 100; // six runs of 16 and a part run
        let (mut particles, mut springs) = row(n, &material, &[]);
        let mut front = Front::default();
        front.prepare(&particles, &mut springs, &mut Topology::default());
        // First by hand: a fire in the middle of a calm run, then put out from outside (state
        // and temperature written back): it leaves the list though its run is calm again.
        let mut newly_burnt = Vec::new();
        particles.temperature[40] = material.ignition_temperature + 1.0;
        front.scan(&mut particles, &springs, &material, STEP, &mut newly_burnt);
        assert_eq!(front.ignited(), [40]);
        particles.state[40] = BurnState::Intact;
        particles.temperature[40] = material.initial_temperature;
        front.scan(&mut particles, &springs, &material, STEP, &mut newly_burnt);
        assert!(front.ignited().is_empty());
        let (mut warm, mut seen_burnt) = (front.warm.clone(), vec![false; n]);
        let mut seed = 7u32;
        let mut next = |below: usize| {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as usize % below
        };
        let temperatures = [
            material.initial_temperature,
            material.initial_temperature + 1.0,
            material.ignition_temperature + 1.0,
            material.ignition_temperature - 1.0,
            material.burnt_temperature + 1.0,
            f32::NAN,
        ];
        for step in 0..400 {
            // Every so often the unburnt cloth is calm again, so most runs have nothing to do
            // (pins and fires would otherwise build up in every run).
            if step % 20 == 0 {
                for i in 0..n {
                    particles.inv_mass[i] = 1.0;
                    if !particles.state[i].is_burnt() {
                        particles.temperature[i] = material.initial_temperature;
                    }
                }
            }
            // A few edits a step, anywhere.
            for _ in 0..next(4) {
                let i = next(n);
                match next(5) {
                    0 => particles.inv_mass[i] = if next(2) == 0 { 0.0 } else { 1.0 },
                    1 => particles.state[i] = BurnState::Burnt,
                    // Put out and cooled from outside (a bucket of water).
                    2 => {
                        particles.state[i] = BurnState::Intact;
                        particles.temperature[i] = material.initial_temperature;
                    }
                    _ => particles.temperature[i] = temperatures[next(temperatures.len())],
                }
            }
            let before = particles.state.clone();
            let mut newly_burnt = Vec::new();
            let (_, counts) =
                front.scan(&mut particles, &springs, &material, STEP, &mut newly_burnt);
            let mut expected_burnt = Vec::new();
            for i in 0..n {
                let t = particles.temperature[i];
                let state = match before[i] {
                    BurnState::Burnt => BurnState::Burnt,
                    _ if t > material.burnt_temperature => BurnState::Burnt,
                    _ if t > material.ignition_temperature => BurnState::Ignited,
                    _ => BurnState::Intact,
                };
                assert_eq!(particles.state[i], state, "step {step}, particle {i}");
                if state == BurnState::Burnt && !seen_burnt[i] {
                    seen_burnt[i] = true;
                    expected_burnt.push(i as u32);
                }
                warm[i] |= t > material.initial_temperature && state != BurnState::Burnt;
                assert_eq!(front.warm[i], warm[i], "step {step}, particle {i}");
            }
            assert_eq!(newly_burnt, expected_burnt, "step {step}");
            let burnt = particles.state.iter().filter(|s| s.is_burnt()).count();
            let pins = (0..n)
                .filter(|&i| !particles.state[i].is_burnt() && particles.inv_mass[i] == 0.0)
                .count();
            assert_eq!(
                (counts.burnt, counts.pins_left),
                (burnt as u32, pins as u32)
            );
            let mut on_fire: Vec<u32> = front.ignited().to_vec();
            on_fire.sort_unstable();
            let expected: Vec<u32> = (0..n as u32)
                .filter(|&i| particles.state[i as usize] == BurnState::Ignited)
                .collect();
            assert_eq!(on_fire, expected, "step {step}");
        }
    }

    /// An ignited particle burns away when it is past the burnt temperature and has been on
    /// fire for the material's burn time, whichever comes later; an intact one set past the
    /// burnt temperature burns away at once; one put out is intact with its clock at zero.
    #[test]
    fn a_particle_on_fire_burns_away_after_its_burn_time_and_its_temperature() {
        let material = BurnMaterial::COTTON;
        let (mut particles, mut springs) = row(4, &material, &[]);
        let hot = material.burnt_temperature + 1.0;
        let burning = 0.5 * (material.ignition_temperature + material.burnt_temperature);
        // 0 past the burnt temperature from its first step on fire (a fine grid); 1 on fire
        // but below it (a coarse grid's slow front); 2 intact, set past it; 3 on fire, put out.
        particles.temperature = vec![burning, burning, hot, burning];
        let mut front = Front::default();
        scanned(&mut front, &mut particles, &mut springs, &material);
        particles.temperature[0] = hot;
        // The scans until the clock, counting up by the step, reaches the burn time.
        let mut steps = 0;
        let mut clock = 0.0_f32;
        while clock < material.burn_time {
            clock += STEP;
            steps += 1;
        }
        let mut burnt_at = [None; 4];
        for step in 1..=2 * steps {
            if step == 3 {
                particles.temperature[3] = material.initial_temperature;
            }
            if step == 2 * steps - 1 {
                particles.temperature[1] = hot;
            }
            front.scan(&mut particles, &springs, &material, STEP, &mut Vec::new());
            for (i, at) in burnt_at.iter_mut().enumerate() {
                if particles.state[i].is_burnt() && at.is_none() {
                    *at = Some(step);
                }
            }
        }
        assert!(particles.burning_for[0] >= material.burn_time);
        assert_eq!(burnt_at[0], Some(steps), "after the burn time");
        assert_eq!(
            burnt_at[1],
            Some(2 * steps - 1),
            "when it got past the temperature"
        );
        assert_eq!(burnt_at[2], Some(1), "at once");
        assert_eq!(burnt_at[3], None);
        assert_eq!(particles.state[3], BurnState::Intact);
        assert_eq!(particles.burning_for[3], 0.0);
    }

    #[test]
    fn burnt_is_final_reported_once_and_counted() {
        let material = BurnMaterial::PAPER;
        let (mut particles, mut springs) = row(2, &material, &[]);
        particles.inv_mass[0] = 0.0;
        particles.state[0] = BurnState::Ignited;
        particles.temperature[0] = material.burnt_temperature + 1.0;
        particles.burning_for[0] = material.burn_time;
        let mut front = Front::default();
        let (report, burnt) = scanned(&mut front, &mut particles, &mut springs, &material);
        assert_eq!((report.newly_burnt, burnt), (1, vec![0]));
        assert!(front.ignited().is_empty());
        particles.temperature[0] = 20.0;
        let mut newly_burnt = Vec::new();
        let (report, counts) =
            front.scan(&mut particles, &springs, &material, STEP, &mut newly_burnt);
        assert_eq!(particles.state[0], BurnState::Burnt);
        assert_eq!(report.newly_burnt, 0);
        assert!(newly_burnt.is_empty());
        assert_eq!(
            counts,
            Counts {
                burnt: 1,
                pins_left: 0
            },
            "the burnt pin holds nothing"
        );
    }

    #[test]
    fn rest_lengths_shrink_with_heat_and_never_below_the_floor() {
        let material = BurnMaterial::SILK;
        let coefficients = SpringCoefficients::from_material(&material, 1e-4);
        let (mut particles, mut springs) = row(
            3,
            &material,
            &[(0, 1, SpringKind::Structural), (0, 2, SpringKind::Bend)],
        );
        let mut front = Front::default();
        scanned(&mut front, &mut particles, &mut springs, &material);
        front.shrink(&mut springs, &particles, &material, &coefficients, 0.01);
        assert_eq!(
            springs.rest_length,
            vec![0.05, 0.1],
            "cold cloth keeps its size"
        );
        assert!(front.shrinking().is_empty());
        particles.temperature.fill(900.0);
        particles.state.fill(BurnState::Ignited);
        front.scan(&mut particles, &springs, &material, STEP, &mut Vec::new());
        front.shrink(&mut springs, &particles, &material, &coefficients, 0.01);
        let expected = 0.05
            - material.shrink_factor * 0.01 * 0.05 * 2.0 * (900.0 - material.initial_temperature)
                / material.structural_stiffness;
        assert!((springs.rest_length[0] - expected).abs() < 1e-7);
        for _ in 0..100_000 {
            front.shrink(&mut springs, &particles, &material, &coefficients, 0.01);
        }
        for s in 0..springs.len() {
            assert_eq!(
                springs.rest_length[s],
                material.min_rest_fraction * springs.initial_rest_length[s]
            );
        }
        assert_eq!(
            front.shrinking().len(),
            2,
            "springs at their floor stay on the list"
        );
        particles.state[2] = BurnState::Burnt;
        front.shrink(&mut springs, &particles, &material, &coefficients, 0.01);
        assert_eq!(front.shrinking(), &[0], "dead springs leave it");
    }

    #[test]
    fn a_spring_joins_the_shrunk_list_when_its_rest_length_drops_below_the_limit_fraction() {
        let material = BurnMaterial::COTTON;
        let coefficients = SpringCoefficients::from_material(&material, 1e-4);
        let (mut particles, mut springs) = row(
            4,
            &material,
            &[
                (0, 1, SpringKind::Structural),
                (2, 3, SpringKind::Structural),
            ],
        );
        let mut front = Front::default();
        scanned(&mut front, &mut particles, &mut springs, &material);
        // Spring 0 a trace warmer than the cloth, spring 1 on fire.
        let t0 = material.initial_temperature;
        particles.temperature = vec![t0 + 0.01, t0 + 0.01, 900.0, 900.0];
        front.scan(&mut particles, &springs, &material, STEP, &mut Vec::new());
        assert_eq!(front.shrinking().len(), 2, "both are warm");
        let h = 1.0 / 60.0;
        let mut joined = None;
        for frame in 0..600 {
            let before = springs.rest_length[1];
            front.shrink(&mut springs, &particles, &material, &coefficients, h);
            let limit = LIMITED_BELOW * springs.initial_rest_length[1];
            let is_shrunk = front.shrunk().contains(&1);
            assert_eq!(is_shrunk, springs.rest_length[1] < limit, "frame {frame}");
            if is_shrunk && before >= limit {
                joined = Some(frame);
            }
        }
        assert!(joined.is_some(), "the burning spring shrank past the limit");
        assert!(
            springs.rest_length[0] > LIMITED_BELOW * springs.initial_rest_length[0],
            "a trace of heat barely shrinks a spring"
        );
        assert_eq!(front.shrunk(), &[1], "the trace-warm spring is not limited");
        particles.state[3] = BurnState::Burnt;
        front.shrink(&mut springs, &particles, &material, &coefficients, h);
        assert!(front.shrunk().is_empty(), "a dead spring leaves the list");
        assert_eq!(front.shrinking(), &[0]);
    }

    #[test]
    fn the_shrinking_list_is_in_index_order_whatever_order_the_particles_warmed_in() {
        let material = BurnMaterial::COTTON;
        let coefficients = SpringCoefficients::from_material(&material, 1e-4);
        let chain: Vec<_> = (0..5).map(|i| (i, i + 1, SpringKind::Structural)).collect();
        let (mut particles, mut springs) = row(6, &material, &chain);
        let mut front = Front::default();
        scanned(&mut front, &mut particles, &mut springs, &material);
        let mut heat_and_shrink = |particles: &mut Particles, i: usize, t: f32| {
            particles.temperature[i] = t;
            front.scan(particles, &springs, &material, STEP, &mut Vec::new());
            front.shrink(&mut springs, particles, &material, &coefficients, 0.01);
            front.shrinking().to_vec()
        };
        assert_eq!(heat_and_shrink(&mut particles, 4, 300.0), [3, 4]);
        assert_eq!(heat_and_shrink(&mut particles, 0, 300.0), [0, 3, 4]);
        assert_eq!(heat_and_shrink(&mut particles, 2, 300.0), [0, 1, 2, 3, 4]);
        let burnt = material.burnt_temperature + 1.0;
        assert_eq!(
            heat_and_shrink(&mut particles, 5, burnt),
            [0, 1, 2, 3],
            "the dead one left"
        );
    }

    #[test]
    fn a_burnt_particle_cuts_the_springs_over_it_and_leaves_the_drawn_list() {
        let material = BurnMaterial::COTTON;
        let (mut particles, mut springs) = row(3, &material, &[(0, 1, SpringKind::Structural)]);
        springs.push_spanning([0, 2], 0.1, SpringKind::Bend, [1, 1], SpanRule::Either);
        let mut topology = Topology {
            triangles: vec![[0, 1, 2], [0, 2, 1]],
            ..Topology::default()
        };
        let mut front = Front::default();
        front.prepare(&particles, &mut springs, &mut topology);
        assert_eq!(topology.live_triangle_count(), 2);
        particles.temperature[1] = material.burnt_temperature + 1.0;
        let mut burnt = Vec::new();
        front.scan(&mut particles, &springs, &material, STEP, &mut burnt);
        assert_eq!(front.sever(&mut springs, &particles.state, &burnt), 1);
        assert!(
            !springs.is_live(1, &particles.state),
            "the bend over it is cut"
        );
        front.cull(&mut topology, &burnt);
        assert_eq!(topology.live_triangle_count(), 0);
    }

    /// A cotton grid `columns` x `rows`, 10 cm apart, pinned at its top corners.
    fn cotton_grid(columns: u32, rows: u32) -> crate::sim::ClothSim {
        crate::sim::ClothSim::new(
            &crate::sim::ClothBuilder::grid(columns, rows, 0.1).pin_top_corners(),
            BurnMaterial::COTTON,
            glam::Affine3A::IDENTITY,
        )
        .unwrap()
    }

    /// A 4 x 4 cotton cloth after one frame in which `burn` were raised past the burnt
    /// temperature, and the index of its shear spring from `a` to `b` (grid columns, rows).
    fn cloth_with_burnt(
        burn: &[(u32, u32)],
        [a, b]: [(u32, u32); 2],
    ) -> (crate::sim::ClothSim, usize) {
        let mut sim = cotton_grid(4, 4);
        let grid = sim.topology.grid.unwrap();
        let [a, b] = [a, b].map(|(c, r)| grid.index(c, r) as u32);
        let spring = (0..sim.springs.len())
            .find(|&s| {
                sim.springs.kind[s] == SpringKind::Shear
                    && sim.springs.a[s] == a
                    && sim.springs.b[s] == b
            })
            .expect("the diagonal");
        let hot = BurnMaterial::COTTON.burnt_temperature + 100.0;
        for &(c, r) in burn {
            let i = grid.index(c, r);
            sim.particles.temperature[i] = hot;
            sim.particles.state[i] = BurnState::Ignited;
            sim.particles.burning_for[i] = BurnMaterial::COTTON.burn_time;
        }
        sim.step(1.0 / 60.0);
        for &(c, r) in burn {
            assert!(sim.particles.state[grid.index(c, r)].is_burnt());
        }
        (sim, spring)
    }

    /// Through burns and cuts, an intact particle's in-plane neighbours are what a search of
    /// every spring finds: the live structural and shear springs it ends, in spring order.
    #[test]
    fn in_plane_neighbours_are_the_live_in_plane_springs_a_particle_ends() {
        use crate::sim::ClothSim;
        let mut sim = cotton_grid(6, 5);
        let grid = sim.topology.grid.unwrap();
        let mut front = Front::default();
        front.prepare(&sim.particles, &mut sim.springs, &mut sim.topology);
        let searched = |sim: &ClothSim, i: usize| -> Vec<(usize, usize)> {
            let springs = &sim.springs;
            (0..springs.len())
                .filter(|&s| {
                    springs.kind[s] != SpringKind::Bend && springs.is_live(s, &sim.particles.state)
                })
                .filter_map(|s| {
                    let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
                    match (a == i, b == i) {
                        (true, false) => Some((s, b)),
                        (false, true) => Some((s, a)),
                        _ => None,
                    }
                })
                .collect()
        };
        let listed = |front: &Front, sim: &ClothSim, i: usize| -> Vec<(usize, usize)> {
            front
                .in_plane_neighbours(i, &sim.springs)
                .filter(|&(_, j)| !sim.particles.state[j].is_burnt())
                .collect()
        };
        // Cell (1, 1)'s drawn diagonal joins (2, 1) and (1, 2); burning (1, 1) and (2, 2)
        // cuts it with both its ends intact.
        let (top_right, bottom_left) = (grid.index(2, 1), grid.index(1, 2));
        let joined = |front: &Front, sim: &ClothSim| {
            front
                .in_plane_neighbours(top_right, &sim.springs)
                .any(|(_, j)| j == bottom_left)
        };
        assert!(joined(&front, &sim));
        for batch in [&[(1, 1), (2, 2)][..], &[(4, 3), (3, 0), (0, 4)]] {
            let newly_burnt: Vec<u32> = batch
                .iter()
                .map(|&(c, r)| grid.index(c, r) as u32)
                .collect();
            for &i in &newly_burnt {
                sim.particles.state[i as usize] = BurnState::Burnt;
            }
            assert!(front.sever(&mut sim.springs, &sim.particles.state, &newly_burnt) > 0);
            for i in 0..sim.particles.len() {
                if !sim.particles.state[i].is_burnt() {
                    assert_eq!(listed(&front, &sim, i), searched(&sim, i), "particle {i}");
                }
            }
        }
        assert!(
            !joined(&front, &sim),
            "the cut diagonal is no longer a link"
        );
        assert!(!listed(&front, &sim, top_right).is_empty());
    }

    #[test]
    fn a_cells_diagonal_is_cut_when_the_cloth_along_it_has_burnt() {
        // Cell (1, 1): its drawn diagonal rises from top right (2, 1) to bottom left (1, 2),
        // an edge of both its triangles; the falling one, (1, 1) to (2, 2), crosses it.
        let rising = [(2, 1), (1, 2)];
        let falling = [(1, 1), (2, 2)];
        // One of the drawn diagonal's other corners gone: the other triangle still holds it.
        let (sim, s) = cloth_with_burnt(&[(1, 1)], rising);
        assert!(sim.springs.is_live(s, &sim.particles.state));
        // Both gone: no cloth along it, it is cut.
        let (sim, s) = cloth_with_burnt(&[(1, 1), (2, 2)], rising);
        assert!(!sim.springs.is_live(s, &sim.particles.state));
        // The crossing diagonal needs both triangles: one corner of the drawn one gone cuts it.
        let (sim, s) = cloth_with_burnt(&[(2, 1)], falling);
        assert!(!sim.springs.is_live(s, &sim.particles.state));
        // Its own ends intact and no spanned corner burnt elsewhere: it stays.
        let (sim, s) = cloth_with_burnt(&[(0, 3)], falling);
        assert!(sim.springs.is_live(s, &sim.particles.state));
    }
}
