//! Flame tongues: where flames stand on a burning cloth, how tall they are and which way they
//! lean. Plain functions over a [`BurningCloth`], no ECS; `SmokeRenderPlugin` draws them.
//!
//! Every burning particle carries one tongue, rooted at the particle, as tall as the particle
//! burns hard, leaning with the air that blows through it (the wind and, with feature `fluid`,
//! the fire's plume). A tongue's strength is the particle's intensity times the share of a
//! tongue's footprint its cloth area covers, so the light a burning area gives off is the
//! same whatever the particle spacing: four times as many particles at half the spacing give
//! four times as many tongues, each a quarter as strong. Above
//! [`TongueSettings::max_tongues`] every k-th burning particle carries a tongue k times as
//! strong, so the cost is bounded and the light the same.

use super::emitter::{Air, BurningCloth};
use glam::Vec3;

/// How flame tongues look on a burning cloth. Part of
/// [`SmokeSettings`](super::SmokeSettings).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TongueSettings {
    /// Height of a tongue on a particle burning at full intensity, m. A particle just
    /// ignited (intensity 0.1) carries one 0.4 times as tall.
    pub height: f32,
    /// Width of a tongue at its root, m.
    pub width: f32,
    /// Speed of the burning gas in a flame, m/s. A tongue leans along the sum of this speed
    /// upwards and the air's velocity at its root: in a wind of this speed it leans 45°.
    pub gas_speed: f32,
    /// The most tongues one cloth draws (0: none). Past it, every k-th burning particle
    /// carries a tongue k times as strong.
    pub max_tongues: usize,
}

impl TongueSettings {
    /// No flame tongues.
    pub const NONE: Self = Self {
        max_tongues: 0,
        ..Self::DEFAULT
    };

    /// Tongues 15 cm tall and 6 cm wide at full intensity: sized for cloth seen across a
    /// room; scale both with the scene.
    pub const DEFAULT: Self = Self {
        height: 0.15,
        width: 0.06,
        gas_speed: 1.5,
        max_tongues: 4096,
    };

    /// Checks every field; returns the name, value and requirement of the first bad one.
    pub fn validate(&self) -> Result<(), (&'static str, f32, &'static str)> {
        for (field, value) in [
            ("tongues.height", self.height),
            ("tongues.width", self.width),
            ("tongues.gas_speed", self.gas_speed),
        ] {
            if !(value.is_finite() && value > 0.0 && value <= 1e3) {
                return Err((field, value, "finite, > 0 and <= 1000"));
            }
        }
        if self.max_tongues > 1 << 20 {
            return Err((
                "tongues.max_tongues",
                self.max_tongues as f32,
                "at most 2^20",
            ));
        }
        Ok(())
    }
}

impl Default for TongueSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// One flame tongue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlameTongue {
    /// Where it is rooted (a burning cloth particle), m.
    pub root: Vec3,
    /// Unit direction from root to tip.
    pub axis: Vec3,
    /// Root-to-tip length, m.
    pub height: f32,
    /// Half its width at the root, m.
    pub half_width: f32,
    /// How much light it gives: the particle's intensity (0.1 to 1) times the share of a
    /// tongue's footprint (its width times the full height) the particles it stands for
    /// cover (at most 1 each).
    pub strength: f32,
    /// A number in [0, 1) fixed per cloth particle, so neighbouring tongues flicker apart.
    pub phase: f32,
}

/// The flame tongues of a burning cloth, into `out` (cleared first; its memory is reused).
/// `flow(position)` is the air's velocity relative to the wind where a simulated plume
/// covers `position` (m/s), or `None`. Non-finite particles carry no tongue.
pub fn gather_tongues(
    cloth: &BurningCloth,
    air: &Air,
    flow: impl Fn(Vec3) -> Option<Vec3>,
    settings: &TongueSettings,
    out: &mut Vec<FlameTongue>,
) {
    out.clear();
    if settings.max_tongues == 0 || settings.validate().is_err() {
        return;
    }
    let len = cloth
        .position
        .len()
        .min(cloth.temperature.len())
        .min(cloth.state.len());
    let burning = (0..len)
        .filter(|&i| cloth.intensity(i) > 0.0 && cloth.position[i].is_finite())
        .count();
    if burning == 0 {
        return;
    }
    let stride = burning.div_ceil(settings.max_tongues);
    let area = if cloth.area_per_particle.is_finite() {
        cloth.area_per_particle.max(0.0)
    } else {
        0.0
    };
    let footprint = settings.width * settings.height;
    let coverage = (area * stride as f32 / footprint).min(stride as f32);
    let up = air.up.normalize_or(Vec3::Y);
    let mut seen = 0usize;
    for i in 0..len {
        let intensity = cloth.intensity(i);
        let root = cloth.position[i];
        if intensity == 0.0 || !root.is_finite() {
            continue;
        }
        let skip = !seen.is_multiple_of(stride);
        seen += 1;
        if skip {
            continue;
        }
        let moving = air.wind + flow(root).filter(|v| v.is_finite()).unwrap_or(Vec3::ZERO);
        out.push(FlameTongue {
            root,
            axis: lean(up, settings.gas_speed, moving),
            height: settings.height * (1.0 + 2.0 * intensity) / 3.0,
            half_width: 0.5 * settings.width,
            strength: intensity * coverage,
            phase: phase_of(i as u32),
        });
    }
}

/// The direction a flame points: its gas rising at `gas_speed` along `up`, carried by the air
/// moving at `air` (m/s). Never lower than 30° above the horizontal (a flame's own buoyancy
/// keeps it rising in any wind a cloth burns in).
fn lean(up: Vec3, gas_speed: f32, air: Vec3) -> Vec3 {
    let direction = (up * gas_speed + air).normalize_or(up);
    let rise = direction.dot(up);
    const MIN_RISE: f32 = 0.5; // sin 30°
    if rise >= MIN_RISE {
        return direction;
    }
    let sideways = (direction - up * rise).normalize_or(Vec3::ZERO);
    (up * MIN_RISE + sideways * (1.0 - MIN_RISE * MIN_RISE).sqrt()).normalize_or(up)
}

/// A well-mixed number in [0, 1) for particle `i` (integer hash, after Wang).
fn phase_of(i: u32) -> f32 {
    let mut x = i.wrapping_mul(0x9e37_79b9) ^ 0x5bd1_e995;
    x ^= x >> 15;
    x = x.wrapping_mul(0x2c1b_3c6d);
    x ^= x >> 12;
    x = x.wrapping_mul(0x297a_2d39);
    x ^= x >> 15;
    (x >> 8) as f32 / (1u32 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::BurnState;

    /// A flat square patch of `n x n` particles at `spacing`, in the x-y plane, rows from `y0`
    /// up; particles below `burning_below` (m) burn at full intensity.
    struct Patch {
        position: Vec<Vec3>,
        temperature: Vec<f32>,
        state: Vec<BurnState>,
        spacing: f32,
    }

    impl Patch {
        fn new(size: f32, spacing: f32, burning_below: f32) -> Self {
            let n = (size / spacing).round() as usize;
            let mut patch = Self {
                position: Vec::new(),
                temperature: Vec::new(),
                state: Vec::new(),
                spacing,
            };
            for row in 0..n {
                for column in 0..n {
                    let p = Vec3::new(
                        (column as f32 + 0.5) * spacing,
                        (row as f32 + 0.5) * spacing,
                        0.0,
                    );
                    let burning = p.y < burning_below;
                    patch.position.push(p);
                    patch.temperature.push(if burning { 500.0 } else { 20.0 });
                    patch.state.push(if burning {
                        BurnState::Ignited
                    } else {
                        BurnState::Intact
                    });
                }
            }
            patch
        }

        fn cloth(&self) -> BurningCloth<'_> {
            BurningCloth {
                position: &self.position,
                temperature: &self.temperature,
                state: &self.state,
                newly_burnt: &[],
                ignition_temperature: 250.0,
                burnt_temperature: 500.0,
                area_per_particle: self.spacing * self.spacing,
            }
        }
    }

    fn tongues(patch: &Patch, air: &Air, settings: &TongueSettings) -> Vec<FlameTongue> {
        let mut out = Vec::new();
        gather_tongues(&patch.cloth(), air, |_| None, settings, &mut out);
        out
    }

    fn light(tongues: &[FlameTongue]) -> f32 {
        tongues.iter().map(|t| t.strength).sum()
    }

    #[test]
    fn a_cloth_with_nothing_burning_has_no_flames() {
        let patch = Patch::new(0.5, 0.05, -1.0);
        assert!(tongues(&patch, &Air::default(), &TongueSettings::DEFAULT).is_empty());
    }

    #[test]
    fn every_burning_particle_carries_one_upright_tongue_in_still_air() {
        let patch = Patch::new(0.5, 0.05, 0.1);
        let out = tongues(&patch, &Air::default(), &TongueSettings::DEFAULT);
        assert_eq!(out.len(), 20, "two burning rows of ten");
        for tongue in &out {
            assert!(tongue.root.y < 0.1);
            assert!((tongue.axis - Vec3::Y).length() < 1e-6);
            // Full intensity: the full height.
            assert!((tongue.height - TongueSettings::DEFAULT.height).abs() < 1e-6);
            assert!((0.0..1.0).contains(&tongue.phase));
        }
    }

    #[test]
    fn the_light_of_a_burning_area_does_not_depend_on_the_spacing() {
        // 0.1 m of a 0.6 m wide cloth burns: 0.06 m², which is 6.7 tongue footprints.
        let expected = 0.6 * 0.1 / (0.06 * 0.15);
        for spacing in [0.005, 0.01, 0.02] {
            let patch = Patch::new(0.6, spacing, 0.1);
            let total = light(&tongues(&patch, &Air::default(), &TongueSettings::DEFAULT));
            assert!(
                (total / expected - 1.0).abs() < 0.02,
                "spacing {spacing}: light {total}, expected {expected}"
            );
        }
    }

    #[test]
    fn past_the_cap_fewer_stronger_tongues_give_the_same_light() {
        let patch = Patch::new(0.6, 0.005, 0.1);
        let all = tongues(&patch, &Air::default(), &TongueSettings::DEFAULT);
        let capped = TongueSettings {
            max_tongues: 500,
            ..TongueSettings::DEFAULT
        };
        let few = tongues(&patch, &Air::default(), &capped);
        assert!(all.len() > 2000);
        assert!(few.len() <= 500 && few.len() > 400);
        assert!((light(&few) / light(&all) - 1.0).abs() < 0.01);
        assert!(tongues(&patch, &Air::default(), &TongueSettings::NONE).is_empty());
    }

    #[test]
    fn tongues_lean_downwind_and_never_below_thirty_degrees() {
        let patch = Patch::new(0.2, 0.05, 0.1);
        let breeze = Air {
            wind: Vec3::new(1.5, 0.0, 0.0),
            ..Air::default()
        };
        let out = tongues(&patch, &breeze, &TongueSettings::DEFAULT);
        // Wind equal to the gas speed: 45° downwind.
        let expected = Vec3::new(1.0, 1.0, 0.0).normalize();
        assert!(out.iter().all(|t| (t.axis - expected).length() < 1e-5));
        let gale = Air {
            wind: Vec3::new(-50.0, -10.0, 0.0),
            ..Air::default()
        };
        for tongue in tongues(&patch, &gale, &TongueSettings::DEFAULT) {
            assert!((tongue.axis.length() - 1.0).abs() < 1e-5);
            assert!((tongue.axis.y - 0.5).abs() < 1e-5, "{:?}", tongue.axis);
            assert!(tongue.axis.x < -0.8);
        }
    }

    #[test]
    fn the_plume_bends_tongues_where_it_blows() {
        let patch = Patch::new(0.2, 0.05, 0.1);
        let mut out = Vec::new();
        let sideways = |p: Vec3| (p.x > 0.1).then_some(Vec3::new(0.0, 0.0, 1.5));
        let settings = TongueSettings::DEFAULT;
        gather_tongues(
            &patch.cloth(),
            &Air::default(),
            sideways,
            &settings,
            &mut out,
        );
        for tongue in &out {
            if tongue.root.x > 0.1 {
                assert!(tongue.axis.z > 0.7);
            } else {
                assert_eq!(tongue.axis, Vec3::Y);
            }
        }
    }

    #[test]
    fn weaker_burning_gives_shorter_dimmer_tongues_and_bad_particles_none() {
        let mut patch = Patch::new(0.2, 0.05, 0.1);
        patch.temperature[0] = 250.0; // just ignited: intensity 0.1
        patch.position[1] = Vec3::NAN;
        let out = tongues(&patch, &Air::default(), &TongueSettings::DEFAULT);
        assert_eq!(out.len(), 7);
        let weak = out.iter().find(|t| t.root == patch.position[0]).unwrap();
        let strong = out.iter().find(|t| t.root == patch.position[2]).unwrap();
        assert!(weak.height < 0.5 * strong.height);
        assert!((weak.strength / strong.strength - 0.1).abs() < 1e-5);
        assert!(out.iter().all(|t| t.root.is_finite()));
    }

    #[test]
    fn invalid_settings_are_rejected_and_draw_nothing() {
        let bad = TongueSettings {
            width: f32::NAN,
            ..TongueSettings::DEFAULT
        };
        assert_eq!(bad.validate().unwrap_err().0, "tongues.width");
        let patch = Patch::new(0.2, 0.05, 0.1);
        assert!(tongues(&patch, &Air::default(), &bad).is_empty());
    }

    #[test]
    fn phases_are_spread_over_the_unit_interval() {
        let phases: Vec<f32> = (0..1000).map(phase_of).collect();
        assert!(phases.iter().all(|p| (0.0..1.0).contains(p)));
        let mean = phases.iter().sum::<f32>() / 1000.0;
        assert!((mean - 0.5).abs() < 0.03);
        let low = phases.iter().filter(|&&p| p < 0.25).count();
        assert!((200..300).contains(&low));
    }
}
