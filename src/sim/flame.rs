//! The flame at the burning edge, in the physical heat model: what carries fire across the
//! cloth at the speeds fabrics are measured to burn.
//!
//! On a thin fuel the flame spreads because it heats the unburnt cloth just ahead of it to
//! ignition: with `Q′` the flame's heat into the cloth per metre of burning edge (W/m), `m_A`
//! the cloth's mass per area and `c` its specific heat, a straight edge advances at
//! `v = Q′ / (m_A c (T_ignition − T_initial))` (de Ris's thin-fuel balance). The flame is
//! taller above the edge than beside or below it, so `Q′`, and `v`, depend on the direction:
//! a material gives the three speeds measured on a vertical panel in still air
//! ([`BurnMaterial::flame_spread_up`], `_sideways`, `_down`), and the model turns them back
//! into heat.
//!
//! On the particles: a particle that has caught heats each intact in-plane neighbour `j` at
//! `distance` from it, in world direction `d̂`, from the temperature `j` had when a flame first
//! reached it (`T_base`) to ignition in the time the front takes to cross, `distance / v(d̂·up)`:
//! after `t` seconds `j` is at least
//!
//! `T_base + (T_ignition − T_base) × t v / distance`
//!
//! (the flame's heat per metre of edge over the heat capacity of the strip `distance` deep it
//! heats), so `j` catches `distance / v` after its neighbour did, at any spacing and on any
//! mesh. The flame's heating is a floor under the temperature: conduction, cooling, heat
//! sources and the air can raise a particle above it, never below it (the flame outweighs
//! the air's cooling next to it). A particle heated by several flames takes the one that has
//! come furthest, not the sum: they are one flame, and the front then moves at `v` whatever
//! the grid's diagonals (a sum would let a neighbour's head start add to the next flame's
//! heating). Between the three measured directions `v` follows an ellipse through them in
//! each half (`1 / v² = sin²/v_sideways² + cos²/v_up²`, or `v_down` below the horizontal),
//! the fire shape wildfire models grow fronts with (Richards 1990, "An elliptical growth
//! model of forest fire fronts"): convex, so no zig-zag of links outruns the measured
//! speeds (a straight front sideways moves at `v_sideways`, not faster by way of the
//! diagonals), and a 45° strip of cotton climbs at about 15 mm/s, in 16 CFR 1610's normal
//! class, as the standard's exemption of plain fabrics of 88 g/m² or more says it is.
//!
//! Along links alone the front would follow the mesh's edges: on a mesh of irregular
//! triangles they run off the vertical, where cotton's ellipse (8 times taller than wide) is
//! slow, and a front climbed at half the measured speed. So each source also carries where
//! its front started in a straight line (the particle first lit, and the sum of the links
//! since), and heats a neighbour from there too: `j` is reached `|offset| / v(offset)` after
//! that start when that is sooner than across the last link, the straight-line arrival the
//! vector distance transform propagates (Danielsson 1980, "Euclidean distance mapping"), here
//! with the ellipse's speed. A point fire grows as the ellipse on any mesh, a line of fire
//! moves as a straight front, and neither outruns the measured speeds. A path that doubles
//! back (round a burnt hole, a slit or a fold: less than [`STRAIGHTNESS`] as long in a straight
//! line as along its links, beyond a slack of two links) is not straight, and the front starts
//! again from the link it came along.
//!
//! The flame's heat is not drawn from the burning particle's temperature: it is the heat the
//! burning releases. The flame stays at an edge until the front has crossed it: the particle
//! that caught burns on, kept just below the burnt temperature, while it still has an intact
//! neighbour to heat (on a coarse cloth the front takes longer to cross a particle's patch
//! than the cloth takes to burn through, and the patch burns as long as the front is in it),
//! for at most [`FLAME_WINDOW`] crossing times. The time a particle caught is tracked within
//! the step, so the front does not lag by a step per particle.

use super::combustion::in_region;
use super::front::Front;
use super::material::{BurnMaterial, MAX_TEMPERATURE};
use super::particles::{BurnState, Particles};
use super::springs::Springs;
use glam::Vec3;

/// How long a flame keeps heating a neighbour, in crossing times (`distance / v`) of the link
/// between them: long enough for the front to cross, short enough that cloth doused or cooled
/// next to a burnt patch does not keep being heated by it.
pub const FLAME_WINDOW: f32 = 2.0;

/// Flame spread speed of `material`, m/s, toward a direction whose cosine with world up is
/// `cos_up`: on the half-ellipse through the sideways speed and the upward (above the
/// horizontal) or downward (below) one, `1 / v² = sin²/v_sideways² + cos²/v_up_or_down²`. A
/// non-finite cosine counts as sideways; a zero speed in the direction's way gives zero.
pub fn spread_speed(material: &BurnMaterial, cos_up: f32) -> f32 {
    let c = if cos_up.is_finite() {
        cos_up.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let along = if c >= 0.0 {
        material.flame_spread_up
    } else {
        material.flame_spread_down
    };
    let across = material.flame_spread_sideways;
    let (c2, s2) = (c * c, (1.0 - c * c).max(0.0));
    let term = |share: f32, speed: f32| {
        if share == 0.0 {
            0.0
        } else {
            share / (speed * speed)
        }
    };
    let slowness = term(s2, across) + term(c2, along);
    if slowness.is_finite() && slowness > 0.0 {
        slowness.sqrt().recip()
    } else {
        0.0
    }
}

/// Seconds the front takes to cross `offset` (world metres, `distance` = its length) at
/// `material`'s spread speed in its direction: the spread shape's gauge (infinite where the
/// speed is zero, and for no offset, which has no direction: a path back to where it started
/// is no shortcut).
fn crossing_time(material: &BurnMaterial, offset: Vec3, distance: f32, up: Vec3) -> f32 {
    if !(distance.is_finite() && distance > 0.0) {
        return f32::INFINITY;
    }
    distance / spread_speed(material, offset.dot(up) / distance)
}

/// The flames of one cloth: the particles whose flame still heats a neighbour, and scratch
/// memory for a step. Sized on first use; no allocation after.
#[derive(Clone, Debug, Default)]
pub struct Flames {
    /// Particles whose flame heats a neighbour, and whether each particle is one.
    sources: Vec<u32>,
    is_source: Vec<bool>,
    /// Seconds since each source caught.
    age: Vec<f32>,
    /// Each particle's temperature when a flame first reached it, °C (NaN: none has): the
    /// flame heats it from there to ignition.
    base: Vec<f32>,
    /// This step's share of the way the nearest flame has come to each particle (1: it has
    /// arrived), the seconds since it arrived (negative: not yet), and the particles with one.
    progress: Vec<f32>,
    arrived: Vec<f32>,
    touched: Vec<u32>,
    /// How long before the end of the last step each particle caught from a flame, s (to
    /// date its own flame within the step), and the particles it is non-zero for.
    caught_ago: Vec<f32>,
    last_touched: Vec<u32>,
    /// Where each source's front came from in a straight line, and whether the particle
    /// caught from a flame in the last step (its `origin` is then the one it caught from).
    origin: Vec<Origin>,
    caught_from_flame: Vec<bool>,
    /// This step's soonest arrival at each heated particle: where its front comes from.
    arriving_from: Vec<Origin>,
    /// Whether each source, by place in `sources`, still heats a neighbour this step.
    heats: Vec<bool>,
}

/// Where a particle's front started in a straight line: the front reached it from a fire
/// `age` seconds old at the end of the step, `offset` away (world metres, the sum of the
/// links it came along, each at its rest length), along links `path` m long in all.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Origin {
    age: f32,
    offset: Vec3,
    path: f32,
}

/// How straight a front's path must be to be taken as a straight line from where it started:
/// the least `|offset| / path`. Any direction across a flat grid or triangle mesh is a path at
/// least `cos 30°` = 0.87 times as straight; a path that doubles back (round a fold or a
/// burnt hole) is not, and the front then starts again from the link it came along. The
/// offset sums each link in its direction when the front crossed it, so on a cloth that
/// curves the straight line is a chord: within this bound (and [`DETOUR_SLACK`]) the front
/// can gain at most a fifth of its path, plus two links, on a cloth folded back on itself.
pub const STRAIGHTNESS: f32 = 0.8;

/// The detour, in links, a front's path may make and still count as straight, whatever its
/// length: near where a fire started, a path of two or three links to a neighbour's
/// neighbour is rarely 0.8 times as straight, but the detour is too short to go round a fold
/// or a burnt hole.
pub const DETOUR_SLACK: f32 = 2.0;

impl Flames {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.sources.capacity()
            + self.age.capacity()
            + self.base.capacity()
            + self.progress.capacity()
            + self.arrived.capacity()
            + self.touched.capacity()
            + self.caught_ago.capacity()
            + self.last_touched.capacity())
            * size_of::<f32>()
            + (self.origin.capacity() + self.arriving_from.capacity()) * size_of::<Origin>()
            + self.is_source.capacity()
            + self.caught_from_flame.capacity()
            + self.heats.capacity()
    }

    /// Particles whose flame still heats a neighbour.
    pub fn sources(&self) -> &[u32] {
        &self.sources
    }

    /// Forgets every flame (a cloth restored or rebuilt).
    pub fn clear(&mut self) {
        self.sources.clear();
        self.is_source.clear();
        self.last_touched.clear();
    }

    /// Puts out the flames within `radius` of `centre` (all with `None`), as a douse does:
    /// the cloth there is no longer heated by the burnt patch next to it, and a flame that
    /// reaches it later heats it from the temperature it has then.
    pub fn put_out(&mut self, position: &[Vec3], region: Option<(Vec3, f32)>) {
        let inside = |i: usize| position.get(i).is_some_and(|&p| in_region(region, p));
        let mut place = 0;
        while place < self.sources.len() {
            let i = self.sources[place] as usize;
            if inside(i) {
                self.is_source[i] = false;
                self.sources.swap_remove(place);
            } else {
                place += 1;
            }
        }
        for (i, base) in self.base.iter_mut().enumerate() {
            if inside(i) {
                *base = f32::NAN;
            }
        }
        for &j in &self.last_touched {
            if inside(j as usize) {
                self.caught_ago[j as usize] = 0.0;
            }
        }
    }

    fn prepare(&mut self, n: usize) {
        if self.is_source.len() != n {
            self.sources.clear();
            self.sources.reserve(n);
            self.is_source.clear();
            self.is_source.resize(n, false);
            self.base.clear();
            self.base.resize(n, f32::NAN);
            self.arrived.clear();
            self.arrived.resize(n, f32::NEG_INFINITY);
            for array in [&mut self.origin, &mut self.arriving_from] {
                array.clear();
                array.resize(n, Origin::default());
            }
            self.caught_from_flame.clear();
            self.caught_from_flame.resize(n, false);
            self.heats.clear();
            self.heats.reserve(n);
            for array in [&mut self.age, &mut self.progress, &mut self.caught_ago] {
                array.clear();
                array.resize(n, 0.0);
            }
            for list in [&mut self.touched, &mut self.last_touched] {
                list.clear();
                list.reserve(n);
            }
        }
    }

    /// A front that reaches `j` `lead` seconds before the end of the step (negative: after),
    /// coming from `origin`, across a last link the flame takes `crossing` seconds to cross.
    fn reach(&mut self, j: usize, lead: f32, crossing: f32, origin: Origin) {
        if self.arrived[j] == f32::NEG_INFINITY {
            self.touched.push(j as u32);
        }
        // How far the flame has come across the last link: 1 when it arrives.
        self.progress[j] = self.progress[j].max(1.0 + lead / crossing);
        if lead > self.arrived[j] {
            self.arrived[j] = lead;
            self.arriving_from[j] = origin;
        }
    }
}

/// What [`flame_step`] needs besides the cloth.
#[derive(Clone, Copy, Debug)]
pub struct FlameParams<'a> {
    /// The cloth's material: its three spread speeds and its temperatures.
    pub material: &'a BurnMaterial,
    /// World up, unit vector.
    pub up: Vec3,
}

/// One step of `h` seconds of flame heating: enrols the particles that caught since the last
/// step, brings each intact neighbour of a flame up to where the nearest flame has heated it,
/// keeps a flame's particle from burning out while it still has a neighbour to heat, and
/// retires flames with nothing left to heat. Run after the conduction step: the flame's
/// heating is a floor under what conduction and cooling leave.
pub fn flame_step(
    front: &Front,
    springs: &Springs,
    particles: &mut Particles,
    params: &FlameParams,
    flames: &mut Flames,
    h: f32,
) {
    if !(h.is_finite() && h > 0.0) {
        return;
    }
    let n = particles.len();
    flames.prepare(n);
    let material = params.material;
    let ignition = material.ignition_temperature;
    let (position, state) = (&particles.position, &particles.state);
    // Enrol the particles that caught since the last step, dated within it.
    for &i in front.ignited() {
        let i = i as usize;
        if flames.is_source[i] || !state[i].is_ignited() {
            continue;
        }
        flames.age[i] = flames.caught_ago[i];
        if !flames.caught_from_flame[i] {
            // Lit by something else (a click, conduction, a heat source): its own front starts
            // here.
            flames.origin[i] = Origin {
                age: flames.age[i],
                ..Origin::default()
            };
        }
        flames.is_source[i] = true;
        flames.sources.push(i as u32);
    }
    // Every flame ages by the step.
    for &i in &flames.sources {
        let i = i as usize;
        flames.age[i] += h;
        flames.origin[i].age += h;
    }
    // How far each flame has come toward its intact neighbours by the end of the step: along
    // the link, or straight from where its front started, whichever is sooner.
    flames.heats.clear();
    for place in 0..flames.sources.len() {
        let i = flames.sources[place] as usize;
        let reached = flames.age[i];
        let age = reached - h;
        let mut heats = false;
        if state[i] != BurnState::Intact {
            let from = flames.origin[i];
            for (s, j) in front.in_plane_neighbours(i, springs) {
                if state[j] != BurnState::Intact {
                    continue;
                }
                let distance = springs.initial_rest_length[s];
                let direction = (position[j] - position[i]).normalize_or_zero();
                let crossing = distance / spread_speed(material, direction.dot(params.up));
                if !(crossing.is_finite() && crossing > 0.0) || age > FLAME_WINDOW * crossing {
                    continue;
                }
                heats = true;
                let link = direction * distance;
                let along_link = Origin {
                    age: reached,
                    offset: link,
                    path: distance,
                };
                flames.reach(j, reached - crossing, crossing, along_link);
                if direction == Vec3::ZERO {
                    // The two ends at one point (or not finite): no direction to go straight in.
                    continue;
                }
                let straight = Origin {
                    age: from.age,
                    offset: from.offset + link,
                    path: from.path + distance,
                };
                let straight_distance = straight.offset.length();
                let detour = straight.path - straight_distance;
                if detour <= (1.0 - STRAIGHTNESS) * straight.path
                    || detour <= DETOUR_SLACK * distance
                {
                    let time =
                        crossing_time(material, straight.offset, straight_distance, params.up);
                    if time.is_finite() {
                        flames.reach(j, straight.age - time, crossing, straight);
                    }
                }
            }
        }
        flames.heats.push(heats);
        if heats && state[i].is_ignited() {
            // The front is still inside this particle's patch of cloth: it burns on (below
            // the burnt temperature) until the front has crossed to its neighbours.
            let t = &mut particles.temperature[i];
            *t = t.min(material.burnt_temperature - 1.0);
        }
    }
    // Doused (intact again), or nothing left within reach: the flame is gone.
    for place in (0..flames.sources.len()).rev() {
        if !flames.heats[place] {
            let i = flames.sources[place] as usize;
            flames.is_source[i] = false;
            flames.sources.swap_remove(place);
        }
    }
    // Raise each heated particle to its floor; date the catches.
    for &j in &flames.last_touched {
        flames.caught_ago[j as usize] = 0.0;
        flames.caught_from_flame[j as usize] = false;
    }
    flames.last_touched.clear();
    let temperature = &mut particles.temperature;
    for &j in &flames.touched {
        let j = j as usize;
        let (progress, arrived) = (flames.progress[j], flames.arrived[j]);
        flames.progress[j] = 0.0;
        flames.arrived[j] = f32::NEG_INFINITY;
        if flames.base[j].is_nan() {
            flames.base[j] = temperature[j].min(ignition);
        }
        let base = flames.base[j];
        // Just past ignition when the flame has arrived, so the scan lights it this step.
        let floor = if progress >= 1.0 {
            ignition + 1e-3 * (ignition.abs() + 1.0)
        } else {
            base + (ignition - base) * progress
        };
        if floor.is_finite() && temperature[j] < floor {
            temperature[j] = floor.min(MAX_TEMPERATURE);
        }
        if arrived >= 0.0 {
            flames.caught_ago[j] = arrived.min(h);
            flames.origin[j] = flames.arriving_from[j];
            flames.caught_from_flame[j] = true;
            flames.last_touched.push(j as u32);
        }
    }
    flames.touched.clear();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{ClothBuilder, ClothSim, HeatModel, MeshClothBuilder, MeshPins};
    use glam::Affine3A;

    #[test]
    fn the_speed_follows_the_ellipse_through_the_measured_directions() {
        let m = BurnMaterial::COTTON;
        assert!((spread_speed(&m, 1.0) - m.flame_spread_up).abs() < 1e-6);
        assert!((spread_speed(&m, 0.0) - m.flame_spread_sideways).abs() < 1e-6);
        assert!((spread_speed(&m, -1.0) - m.flame_spread_down).abs() < 1e-6);
        assert!((spread_speed(&m, f32::NAN) - m.flame_spread_sideways).abs() < 1e-6);
        // 45° up: 1 / sqrt(0.5 / 0.011² + 0.5 / 0.09²) = 15.44 mm/s; its sideways part is
        // the sideways speed's 11 mm/s at most (convex: no zig-zag outruns it).
        let diagonal = spread_speed(&m, core::f32::consts::FRAC_1_SQRT_2);
        assert!((diagonal - 0.015_44).abs() < 1e-4, "{diagonal}");
        assert!(diagonal * core::f32::consts::FRAC_1_SQRT_2 <= m.flame_spread_sideways + 1e-6);
        let mut none = m;
        none.flame_spread_down = 0.0;
        assert_eq!(spread_speed(&none, -0.5), 0.0);
    }

    #[test]
    fn a_front_goes_round_a_slit_not_across_it() {
        // A held cotton panel 0.3 m square at 25 mm, slit from the bottom to 50 mm below the
        // top between columns 5 and 6 (no triangle joins them there). Lit at the bottom of
        // the left side, the fire climbs (90 mm/s), crosses the bridge at the top (11 mm/s)
        // and creeps down the right side at 2 mm/s: the right side's bottom is 0.25 m below
        // the bridge, some 100 s away. A front taken straight from the lit particle would
        // cross the slit sideways in 0.15 m / 11 mm/s = 14 s (the straightness rule stops
        // that: the path round the slit doubles back).
        let (n, spacing) = (13u32, 0.025f32);
        let at = |column: u32, row: u32| row * n + column;
        let positions = (0..n * n)
            .map(|i| Vec3::new((i % n) as f32 * spacing, -((i / n) as f32) * spacing, 0.0))
            .collect();
        let mut triangles = Vec::new();
        for row in 0..n - 1 {
            for column in 0..n - 1 {
                if column == 5 && row >= 2 {
                    continue;
                }
                let [a, b, c, d] = [
                    at(column, row),
                    at(column + 1, row),
                    at(column, row + 1),
                    at(column + 1, row + 1),
                ];
                triangles.extend([[a, c, d], [a, d, b]]);
            }
        }
        let parts = MeshClothBuilder::new(positions, triangles)
            .with_pins(MeshPins::custom(|_, _| true))
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        let mut sim = ClothSim::from_parts(parts, BurnMaterial::COTTON, Affine3A::IDENTITY);
        sim.update_settings(|s| s.solver.heat_model = HeatModel::PHYSICAL)
            .unwrap();
        sim.ignite(at(2, n - 1) as usize).unwrap();
        let (right_top, right_bottom) = (at(9, 0) as usize, at(9, n - 1) as usize);
        for _ in 0..30 * 60 {
            sim.step(1.0 / 60.0);
        }
        let state = &sim.particles.state;
        assert_ne!(
            state[right_top],
            BurnState::Intact,
            "the fire crossed the bridge"
        );
        assert_eq!(
            state[right_bottom],
            BurnState::Intact,
            "the fire jumped the slit"
        );
    }

    /// Seconds until the particle `rows_up` rows above (negative: below) or `columns` to the
    /// side of the lit centre of a flat, held cotton panel catches, at `spacing` m.
    fn catch_time(spacing: f32, columns: i32, rows_up: i32) -> f32 {
        let n = (0.5 / spacing).round() as u32 + 1;
        let builder = ClothBuilder::grid(n, n, spacing).pin_all();
        let mut sim = ClothSim::new(&builder, BurnMaterial::COTTON, Affine3A::IDENTITY).unwrap();
        sim.update_settings(|s| s.solver.heat_model = HeatModel::PHYSICAL)
            .unwrap();
        let grid = sim.topology.grid.unwrap();
        let centre = n / 2;
        sim.ignite(grid.index(centre, centre)).unwrap();
        // Rows run down the panel.
        let at =
            |c: i32, r: i32| grid.index((centre as i32 + c) as u32, (centre as i32 - r) as u32);
        let (near, far) = (at(columns / 2, rows_up / 2), at(columns, rows_up));
        let (mut t, mut reached_near) = (0.0, None);
        for frame in 1..=6000 {
            sim.step(1.0 / 60.0);
            t = frame as f32 / 60.0;
            if reached_near.is_none() && sim.particles.state[near] != BurnState::Intact {
                reached_near = Some(t);
            }
            if sim.particles.state[far] != BurnState::Intact {
                break;
            }
        }
        t - reached_near.expect("the front reached half way")
    }

    #[test]
    fn the_front_moves_at_the_measured_speeds_at_any_spacing() {
        // From half way to the end of 0.2 m: 0.1 m at 90 mm/s up (1.11 s) and 11 mm/s sideways
        // (9.1 s), at 50, 20 and 10 mm spacing, within 10 %.
        for spacing in [0.05f32, 0.02, 0.01] {
            let steps = (0.2 / spacing).round() as i32;
            let up = catch_time(spacing, 0, steps);
            assert!(
                (up - 0.1 / 0.09).abs() < 0.11,
                "{spacing} m: up took {up} s"
            );
            let side = catch_time(spacing, steps, 0);
            assert!(
                (side - 0.1 / 0.011).abs() < 0.91,
                "{spacing} m: sideways took {side} s"
            );
        }
    }
}
