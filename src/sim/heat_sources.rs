//! Heat from outside a cloth: torches, fireballs, lava, and the burning particles of other
//! cloths close by.
//!
//! A source at `c` with radius `r`, temperature `T_s`, rate `k` and falloff exponent `p`
//! heats every unburnt particle within `r` towards `T_s`:
//!
//! `T ← T + (T_s − T)(1 − e^(−k w h))`, `w = (1 − d/r)^p`, only when `T < T_s`
//!
//! The update is the exact solution of `dT/dt = k w (T_s − T)` over the step, so it is stable
//! and never overshoots `T_s` for any step. Ignition follows from temperature as usual.
//! A source never cools (a cold source does nothing); use extinguishing for that.

use super::material::valid_temperature;
use super::particles::BurnState;
use super::spatial_hash::SpatialHash;
use glam::Vec3;

/// A spherical heat source in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldHeatSource {
    /// Centre, m.
    pub centre: Vec3,
    /// Reach, m.
    pub radius: f32,
    /// Temperature particles are heated towards, °C.
    pub temperature: f32,
    /// Heating rate at the centre, 1/s.
    pub rate: f32,
    /// Falloff exponent: the rate falls as `(1 − d/r)^falloff`; 0 is uniform.
    pub falloff: f32,
    /// Who owns the source (a cloth's id for its burning particles), so a cloth is not heated
    /// by itself twice; [`WorldHeatSource::NO_OWNER`] for free sources.
    pub owner: u64,
}

impl WorldHeatSource {
    /// Owner of a source that belongs to no cloth.
    pub const NO_OWNER: u64 = u64::MAX;

    /// Whether every field is usable: finite, positive radius, a valid temperature, a
    /// non-negative rate and falloff.
    pub fn is_valid(&self) -> bool {
        self.centre.is_finite()
            && self.radius.is_finite()
            && self.radius > 0.0
            && valid_temperature(self.temperature)
            && self.rate.is_finite()
            && self.rate >= 0.0
            && self.falloff.is_finite()
            && self.falloff >= 0.0
    }

    /// Heats one particle at `position` with temperature `t` over `h` seconds.
    #[inline]
    fn heat(&self, position: Vec3, t: &mut f32, h: f32) -> bool {
        let d2 = position.distance_squared(self.centre);
        if d2 >= self.radius * self.radius || *t >= self.temperature {
            return false;
        }
        let w = (1.0 - d2.sqrt() / self.radius).powf(self.falloff);
        *t += (self.temperature - *t) * (1.0 - (-self.rate * w * h).exp());
        true
    }
}

/// Heats the unburnt particles of one cloth from a few sources. Sources whose sphere misses
/// the cloth's bounding box (`bounds`, min and max corners) are skipped, so a source far away
/// costs one test; a source touching the cloth costs one distance test per particle.
/// Invalid sources are ignored. Returns how many particle heatings happened.
pub fn apply_heat_sources(
    position: &[Vec3],
    temperature: &mut [f32],
    state: &[BurnState],
    bounds: (Vec3, Vec3),
    sources: &[WorldHeatSource],
    h: f32,
) -> u32 {
    if !(h.is_finite() && h > 0.0) {
        return 0;
    }
    let mut heated = 0;
    for source in sources {
        if !source.is_valid() {
            continue;
        }
        let nearest = source.centre.clamp(bounds.0, bounds.1);
        if nearest.distance_squared(source.centre) > source.radius * source.radius {
            continue;
        }
        for ((p, t), s) in position.iter().zip(temperature.iter_mut()).zip(state) {
            if !s.is_burnt() && source.heat(*p, t, h) {
                heated += 1;
            }
        }
    }
    heated
}

/// Many small sources (the burning particles of every cloth) with a spatial hash over their
/// centres, rebuilt once per step and shared by every cloth.
#[derive(Clone, Debug, Default)]
pub struct HashedHeatSources {
    /// The sources.
    pub sources: Vec<WorldHeatSource>,
    /// Their centres, in the same order (what the hash indexes).
    pub centres: Vec<Vec3>,
    /// The hash over `centres`, cells of the largest radius.
    pub hash: SpatialHash,
    /// The largest radius.
    pub reach: f32,
    /// The box each owner's sources heat (their spheres' bounds), one entry per run of
    /// sources pushed with the same owner: a cloth skips the others' fires that cannot reach
    /// it with a few box tests.
    owners: Vec<OwnerBounds>,
}

/// The box the sources of one owner heat, m.
#[derive(Clone, Copy, Debug)]
struct OwnerBounds {
    owner: u64,
    min: Vec3,
    max: Vec3,
}

impl HashedHeatSources {
    /// Forgets every source (memory kept).
    pub fn clear(&mut self) {
        self.sources.clear();
        self.centres.clear();
        self.owners.clear();
        self.reach = 0.0;
    }

    /// Adds a source; invalid ones are dropped.
    pub fn push(&mut self, source: WorldHeatSource) {
        if !source.is_valid() {
            return;
        }
        self.reach = self.reach.max(source.radius);
        self.sources.push(source);
        self.centres.push(source.centre);
        let (min, max) = (source.centre - source.radius, source.centre + source.radius);
        match self.owners.last_mut() {
            Some(last) if last.owner == source.owner => {
                last.min = last.min.min(min);
                last.max = last.max.max(max);
            }
            _ => self.owners.push(OwnerBounds {
                owner: source.owner,
                min,
                max,
            }),
        }
    }

    /// Rebuilds the hash after the sources changed.
    pub fn rebuild(&mut self) {
        let reach = self.reach;
        // Cells twice the reach: a lookup visits at most 8 of them instead of 27.
        self.hash.build(&self.centres, 2.0 * reach, |_| true);
    }

    /// The part of `bounds` (min and max corners) that sources not owned by `owner` can heat,
    /// or `None` when none reaches it.
    fn foreign_reach(&self, owner: u64, bounds: (Vec3, Vec3)) -> Option<(Vec3, Vec3)> {
        let mut region: Option<(Vec3, Vec3)> = None;
        for other in self.owners.iter().filter(|o| o.owner != owner) {
            let (min, max) = (other.min.max(bounds.0), other.max.min(bounds.1));
            if min.cmple(max).all() {
                region = Some(match region {
                    Some((lo, hi)) => (lo.min(min), hi.max(max)),
                    None => (min, max),
                });
            }
        }
        region
    }
}

/// Heats the unburnt particles of the cloth `owner` (within `bounds`, their min and max
/// corners) from the hashed sources. Only particles inside the boxes other owners' sources
/// heat are looked up, and each visits only the sources in its neighbouring cells: a cloth no
/// other fire reaches costs a few box tests. Sources owned by `owner` are skipped. Returns
/// how many particle heatings happened.
pub fn apply_hashed_heat_sources(
    position: &[Vec3],
    temperature: &mut [f32],
    state: &[BurnState],
    bounds: (Vec3, Vec3),
    owner: u64,
    hashed: &HashedHeatSources,
    h: f32,
) -> u32 {
    let sources = &hashed.sources;
    if !(h.is_finite() && h > 0.0) || sources.is_empty() {
        return 0;
    }
    let Some((lo, hi)) = hashed.foreign_reach(owner, bounds) else {
        return 0;
    };
    let mut heated = 0;
    for ((p, t), s) in position.iter().zip(temperature.iter_mut()).zip(state) {
        let inside = p.cmpge(lo).all() && p.cmple(hi).all();
        if !inside || s.is_burnt() {
            continue;
        }
        hashed
            .hash
            .for_each_within(&hashed.centres, *p, hashed.reach, |j| {
                let source = &sources[j];
                if source.owner != owner && source.heat(*p, t, h) {
                    heated += 1;
                }
            });
    }
    heated
}

/// The bounding box of the unburnt particles, or `None` when there are none.
pub fn unburnt_bounds(position: &[Vec3], state: &[BurnState]) -> Option<(Vec3, Vec3)> {
    let mut bounds: Option<(Vec3, Vec3)> = None;
    for (p, s) in position.iter().zip(state) {
        if s.is_burnt() || !p.is_finite() {
            continue;
        }
        bounds = Some(match bounds {
            Some((lo, hi)) => (lo.min(*p), hi.max(*p)),
            None => (*p, *p),
        });
    }
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;

    fn source(centre: Vec3, radius: f32) -> WorldHeatSource {
        WorldHeatSource {
            centre,
            radius,
            temperature: 800.0,
            rate: 5.0,
            falloff: 0.0,
            owner: WorldHeatSource::NO_OWNER,
        }
    }

    #[test]
    fn a_source_approaches_its_temperature_exactly_and_never_overshoots() {
        // Uniform source: T(t) = Ts + (T0 - Ts) e^(-k t), whatever the step.
        let position = [Vec3::ZERO];
        let state = [BurnState::Intact];
        for steps in [1usize, 10, 1000] {
            let mut t = [20.0f32];
            let h = 1.0 / steps as f32;
            for _ in 0..steps {
                apply_heat_sources(
                    &position,
                    &mut t,
                    &state,
                    (Vec3::ZERO, Vec3::ZERO),
                    &[source(Vec3::ZERO, 1.0)],
                    h,
                );
            }
            let exact = 800.0 + (20.0 - 800.0) * (-5.0f32).exp();
            assert!(
                (t[0] - exact).abs() < 0.01,
                "{steps} steps: {} vs {exact}",
                t[0]
            );
            assert!(t[0] <= 800.0);
        }
    }

    #[test]
    fn only_particles_in_reach_and_unburnt_are_heated() {
        let position = [
            Vec3::ZERO,
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::ZERO,
        ];
        let state = [
            BurnState::Intact,
            BurnState::Intact,
            BurnState::Intact,
            BurnState::Burnt,
        ];
        let mut t = [20.0f32; 4];
        let mut falling = source(Vec3::ZERO, 1.0);
        falling.falloff = 1.0;
        let bounds = unburnt_bounds(&position, &state).unwrap();
        let heated = apply_heat_sources(&position, &mut t, &state, bounds, &[falling], 0.1);
        assert_eq!(heated, 2);
        assert!(t[0] > t[1] && t[1] > 20.0, "falloff: {t:?}");
        assert_eq!((t[2], t[3]), (20.0, 20.0));
        // A source whose sphere misses the bounding box costs nothing and heats nothing.
        let mut cold = [20.0f32; 4];
        let far = source(Vec3::new(10.0, 0.0, 0.0), 1.0);
        assert_eq!(
            apply_heat_sources(&position, &mut cold, &state, bounds, &[far], 0.1),
            0
        );
        // Invalid sources and steps do nothing.
        let mut bad = source(Vec3::ZERO, 1.0);
        bad.temperature = f32::NAN;
        assert_eq!(
            apply_heat_sources(&position, &mut cold, &state, bounds, &[bad], 0.1),
            0
        );
        assert_eq!(
            apply_heat_sources(&position, &mut cold, &state, bounds, &[falling], f32::NAN),
            0
        );
        assert_eq!(cold, [20.0; 4]);
    }

    #[test]
    fn hashed_sources_match_the_direct_loop_and_skip_their_owner() {
        let position: Vec<Vec3> = (0..50)
            .map(|i| Vec3::new(i as f32 * 0.02, 0.0, 0.0))
            .collect();
        let state = vec![BurnState::Intact; 50];
        let mut hashed = HashedHeatSources::default();
        let mut list = Vec::new();
        for k in 0..5 {
            let mut s = source(Vec3::new(0.2 * k as f32, 0.03, 0.0), 0.06);
            s.owner = k % 2;
            list.push(s);
            hashed.push(s);
        }
        hashed.push(source(Vec3::NAN, 1.0)); // dropped
        assert_eq!(hashed.sources.len(), 5);
        hashed.rebuild();
        let bounds = unburnt_bounds(&position, &state).unwrap();
        let mut by_hash = vec![20.0f32; 50];
        apply_hashed_heat_sources(&position, &mut by_hash, &state, bounds, 1, &hashed, 0.1);
        let others: Vec<WorldHeatSource> = list.iter().copied().filter(|s| s.owner != 1).collect();
        let mut direct = vec![20.0f32; 50];
        apply_heat_sources(&position, &mut direct, &state, bounds, &others, 0.1);
        for (a, b) in by_hash.iter().zip(&direct) {
            assert!((a - b).abs() < 1e-3, "{a} vs {b}");
        }
        assert!(by_hash.iter().any(|&t| t > 20.0));
        // A cloth 1 m away that no other owner's source reaches: nothing looked up or heated.
        let far: Vec<Vec3> = position.iter().map(|p| *p + Vec3::Y).collect();
        let far_bounds = unburnt_bounds(&far, &state).unwrap();
        assert_eq!(hashed.foreign_reach(1, far_bounds), None);
        let mut cold = vec![20.0f32; 50];
        let heated =
            apply_hashed_heat_sources(&far, &mut cold, &state, far_bounds, 1, &hashed, 0.1);
        assert_eq!(heated, 0);
    }
}
