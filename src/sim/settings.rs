//! What a cloth is stepped with: the solver, the heat model, the world around it, and the
//! three together as [`ClothSettings`], validated as one.

use super::error::ClothError;
use super::guard::GuardSettings;
use super::integrate::Integrator;
use super::material::BurnMaterial;
use super::provot::ProvotSettings;
use bevy::reflect::{Reflect, std_traits::ReflectDefault};
use glam::Vec3;

/// How the cloth is stepped: integrator, substeps, constraints, proximity heating.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub struct SolverSettings {
    /// The time integrator.
    pub integrator: Integrator,
    /// Substeps per fixed step. `None` picks them: for XPBD, [`Self::substep_rate`]; for the
    /// force-based integrators, enough for stability from the cloth's stiffest spring and
    /// lightest particle (see [`stable_time_step`](super::integrate::stable_time_step)), up to
    /// [`Self::max_substeps`].
    pub substeps: Option<u32>,
    /// Upper bound on automatic substeps.
    pub max_substeps: u32,
    /// XPBD's automatic substeps per second of simulated time, Hz: its fixed budget ("small
    /// steps"), the same at any resolution and stiffness. The default 360 Hz is 6 substeps
    /// per 1/60 s or 1/64 s step: enough to keep the structural stretch of a hanging
    /// 256 × 256 cotton curtain under 10 % with the default tethers (`examples/stress.rs`).
    pub substep_rate: f32,
    /// The grid spacing [`Self::substep_rate`] is meant for, m, or `None` (default) for the
    /// fixed budget. With `Some(reference)`, a cloth of spacing `l` runs XPBD at
    /// `substep_rate × reference / l` (up to [`Self::max_substeps`]): one projection a
    /// substep then holds a spring as firmly on a fine grid as on the reference one, so a
    /// fine cloth crumples and hangs as a reference one does, at a cost per particle that
    /// grows as `1 / l` (README, Crumpling by spacing: 360 Hz at 25 mm crumples a heated block
    /// to 0.48 of its width at 25 mm and 0.49 at 5 mm, where the fixed budget gives 0.62).
    pub substep_rate_spacing: Option<f32>,
    /// When a force-based integrator with automatic substeps would need more than
    /// [`Self::max_substeps`] to be stable (a stiff or fine cloth), step that cloth with XPBD
    /// instead, at [`Self::substep_rate`]; [`StepReport::integrator`](super::StepReport::integrator)
    /// says which ran. `false` keeps the chosen integrator at its cap, where the blow-up guard
    /// has to catch it.
    pub stiff_fallback: bool,
    /// Fraction of the stability limit an automatic substep may use, in (0, 1].
    pub stability_safety: f32,
    /// Provot's stretch limit, or `None` to turn it off. The force-based integrators apply
    /// it after every substep to every in-plane spring, up to `passes` times; XPBD, whose
    /// constraints and [`Self::tether_stretch`] hold the rest of the cloth, after every
    /// substep to the springs heat has shrunk, in up to `passes` rounds over all of them
    /// (stopping after a round that corrects nothing), so a burning cloth crumples rather
    /// than stretches.
    pub provot: Option<ProvotSettings>,
    /// XPBD's tethers (long-range attachments): no particle gets farther from the pin it
    /// hangs from than its distance through the cloth times `1 + tether_stretch` (0.05 is
    /// 5 %). They keep a long cloth from sagging past its springs' stretch when one
    /// constraint pass per substep cannot carry its weight down; `None` turns them off.
    pub tether_stretch: Option<f32>,
    /// Proximity heating radius as a multiple of the grid spacing; 0 turns it off.
    pub proximity_radius_factor: f32,
    /// Distance particles keep from colliders, as a multiple of the grid spacing.
    pub collision_margin_factor: f32,
    /// The blow-up guard's limits.
    pub guard: GuardSettings,
    /// Which heat model spreads the fire.
    pub heat_model: HeatModel,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            integrator: Integrator::default(),
            substeps: None,
            max_substeps: 64,
            substep_rate: 360.0,
            substep_rate_spacing: None,
            stiff_fallback: true,
            stability_safety: 0.8,
            provot: Some(ProvotSettings::default()),
            tether_stretch: Some(0.03),
            proximity_radius_factor: 0.6,
            collision_margin_factor: 0.3,
            guard: GuardSettings::default(),
            heat_model: HeatModel::Paper,
        }
    }
}

impl SolverSettings {
    /// Checks every setting for a usable value.
    pub fn validate(&self) -> Result<(), ClothError> {
        let invalid = |name, value| Err(ClothError::InvalidSetting { name, value });
        if self.substeps == Some(0) {
            return invalid("substeps", 0.0);
        }
        if self.max_substeps == 0 {
            return invalid("max_substeps", 0.0);
        }
        if !(self.substep_rate.is_finite() && self.substep_rate > 0.0) {
            return invalid("substep_rate", self.substep_rate);
        }
        if let Some(spacing) = self.substep_rate_spacing
            && !(spacing.is_finite() && spacing > 0.0)
        {
            return invalid("substep_rate_spacing", spacing);
        }
        if !(self.stability_safety > 0.0 && self.stability_safety <= 1.0) {
            return invalid("stability_safety", self.stability_safety);
        }
        if !(self.proximity_radius_factor.is_finite() && self.proximity_radius_factor >= 0.0) {
            return invalid("proximity_radius_factor", self.proximity_radius_factor);
        }
        if !(self.collision_margin_factor.is_finite() && self.collision_margin_factor >= 0.0) {
            return invalid("collision_margin_factor", self.collision_margin_factor);
        }
        if !(self.guard.max_speed.is_finite() && self.guard.max_speed > 0.0) {
            return invalid("guard.max_speed", self.guard.max_speed);
        }
        if let Some(provot) = self.provot
            && !(provot.max_stretch.is_finite() && provot.max_stretch >= 0.0)
        {
            return invalid("provot.max_stretch", provot.max_stretch);
        }
        if let Some(stretch) = self.tether_stretch
            && !(stretch.is_finite() && stretch >= 0.0)
        {
            return invalid("tether_stretch", stretch);
        }
        self.heat_model.validate()
    }

    /// XPBD's automatic substeps per second for a cloth of grid spacing `spacing` (m), Hz:
    /// [`Self::substep_rate`], scaled by [`Self::substep_rate_spacing`]` / spacing` when that
    /// is set (and the spacing is a positive length).
    pub fn xpbd_rate(&self, spacing: f32) -> f32 {
        match self.substep_rate_spacing {
            Some(reference) if spacing.is_finite() && spacing > 0.0 => {
                self.substep_rate * reference / spacing
            }
            _ => self.substep_rate,
        }
    }

    /// How a fixed step of `dt` seconds is run, given the cloth's stable step `stable` (s)
    /// and its grid spacing `spacing` (m): the fixed count if one is set; for XPBD,
    /// [`Self::xpbd_rate`]; for a force-based integrator, the fewest substeps keeping each
    /// within `stability_safety × stable`, or, when that is more than
    /// [`Self::max_substeps`], XPBD if [`Self::stiff_fallback`] is on (else the cap).
    pub fn plan(&self, dt: f32, stable: f32, spacing: f32) -> StepPlan {
        let cap = self.max_substeps.max(1);
        let plan = |integrator, substeps: u32| StepPlan {
            integrator,
            substeps: substeps.clamp(1, cap),
        };
        if let Some(n) = self.substeps {
            // A count the user chose is kept, beyond the automatic cap too.
            return StepPlan {
                integrator: self.integrator,
                substeps: n.max(1),
            };
        }
        // Small tolerance so 1/60 s at 360 Hz is 6 substeps, not 7 by round-off.
        let at_rate = |rate: f32| {
            let n = (dt * rate - 1e-3).ceil();
            if n.is_finite() { n as u32 } else { cap }
        };
        let rate = self.xpbd_rate(spacing);
        if self.integrator.is_unconditionally_stable() {
            return plan(self.integrator, at_rate(rate));
        }
        let allowed = self.stability_safety * stable;
        if !(allowed.is_finite() && allowed > 0.0) {
            return plan(self.integrator, 1);
        }
        let needed = (dt / allowed).ceil();
        if needed.is_finite() && needed <= cap as f32 {
            plan(self.integrator, needed as u32)
        } else if self.stiff_fallback {
            plan(Integrator::Xpbd, at_rate(rate))
        } else {
            plan(self.integrator, cap)
        }
    }
}

/// How one fixed step is run: which integrator, how many substeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepPlan {
    /// The integrator that runs the step (the chosen one, or XPBD as the stiff fallback).
    pub integrator: Integrator,
    /// Substeps, at least 1.
    pub substeps: u32,
}

/// How heat moves through a cloth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Default, Clone, Debug, PartialEq)]
pub enum HeatModel {
    /// The paper's model: burning particles push heat to their neighbours, weighted
    /// upward; heat only grows (see [`super::heat`]).
    #[default]
    Paper,
    /// A heat equation on the cloth: conduction, upward convection, cooling to the air and
    /// heat from burning; heat is conserved by the exchanges (see [`super::conduction`]). The
    /// air is at the material's `initial_temperature`.
    Physical(PhysicalHeat),
}

/// The physical heat model's parameters (see [`super::conduction`]).
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub struct PhysicalHeat {
    /// Thermal diffusivity along the cloth, m²/s.
    pub diffusivity: f32,
    /// Rate at which heat climbs from a hot particle to a cooler one directly above, 1/s, for
    /// particles `REFERENCE_SPACING` (3 cm) apart; scaled by `REFERENCE_SPACING / link length`
    /// so heat climbs the same metres per second at any spacing.
    pub convection: f32,
    /// Cooling towards the air, 1/s.
    pub cooling: f32,
    /// Heat released by a burning particle, °C/s: it must outpace what the particle passes
    /// on, or the fire goes out.
    pub burn_heating: f32,
}

impl PhysicalHeat {
    /// Values for real fabric: the flame at the burning edge carries the fire, at the
    /// material's measured spread speeds ([`super::flame`]); conduction along the cloth is a
    /// fabric's (a conductivity of about 0.05 W/(m·K) over a volumetric heat capacity of about
    /// 5e5 J/(m³·K): 1e-7 m²/s, a few millimetres in a minute); no extra upward transport
    /// (the flame already climbs faster than it spreads); cooling to still air at 0.05 /s;
    /// a burning particle reaches the burnt temperature in about a second. The same values
    /// spread fire at the same speed at any spacing (`examples/spread_report.rs`).
    pub const GAME: Self = Self {
        diffusivity: 1e-7,
        convection: 0.0,
        cooling: 0.05,
        burn_heating: 1000.0,
    };

    /// The four parameters in the order diffusivity, convection, cooling, burn heating.
    pub fn to_array(self) -> [f32; 4] {
        [
            self.diffusivity,
            self.convection,
            self.cooling,
            self.burn_heating,
        ]
    }

    /// Parameters from [`Self::to_array`]'s order.
    pub fn from_array([diffusivity, convection, cooling, burn_heating]: [f32; 4]) -> Self {
        Self {
            diffusivity,
            convection,
            cooling,
            burn_heating,
        }
    }
}

impl HeatModel {
    /// The physical model with [`PhysicalHeat::GAME`].
    pub const PHYSICAL: Self = Self::Physical(PhysicalHeat::GAME);

    fn validate(&self) -> Result<(), ClothError> {
        if let Self::Physical(heat) = self {
            let names = [
                "heat_model.diffusivity",
                "heat_model.convection",
                "heat_model.cooling",
                "heat_model.burn_heating",
            ];
            for (name, value) in names.into_iter().zip(heat.to_array()) {
                if !(value.is_finite() && (0.0..=1e5).contains(&value)) {
                    return Err(ClothError::InvalidSetting { name, value });
                }
            }
        }
        Ok(())
    }
}

/// The world around the cloths.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub struct Environment {
    /// Gravitational acceleration, m/s².
    pub gravity: Vec3,
    /// Wind velocity, m/s.
    pub wind: Vec3,
    /// World up, a unit vector: heat rises along it.
    pub up: Vec3,
}

impl Default for Environment {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            wind: Vec3::ZERO,
            up: Vec3::Y,
        }
    }
}

impl Environment {
    /// Checks that every vector is finite and `up` is not zero.
    pub fn validate(&self) -> Result<(), ClothError> {
        if !(self.gravity.is_finite() && self.wind.is_finite() && self.up.is_finite())
            || self.up.length_squared() < 1e-12
        {
            return Err(ClothError::NonFinitePoint);
        }
        Ok(())
    }

    /// World up as a unit vector (`+Y` if `up` cannot be normalised).
    pub fn unit_up(&self) -> Vec3 {
        self.up.normalize_or(Vec3::Y)
    }
}

/// Everything a cloth is stepped with: its material, its solver and the world around it.
/// The simulation only ever holds validated settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Default, Clone, Debug, PartialEq)]
pub struct ClothSettings {
    /// The material.
    pub material: BurnMaterial,
    /// The solver.
    pub solver: SolverSettings,
    /// Gravity, wind and up.
    pub environment: Environment,
}

impl ClothSettings {
    /// Checks the material, the solver and the environment.
    pub fn validate(&self) -> Result<(), ClothError> {
        self.material.validate()?;
        self.solver.validate()?;
        self.environment.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn automatic_substeps_respect_the_stability_limit() {
        let solver = SolverSettings {
            integrator: Integrator::SymplecticEuler,
            ..SolverSettings::default()
        };
        let substeps = |dt, stable| solver.plan(dt, stable, 0.03).substeps;
        assert_eq!(substeps(1.0 / 60.0, 1.0), 1);
        let n = substeps(1.0 / 60.0, 1.0e-3);
        assert!((1.0 / 60.0) / n as f32 <= 0.8e-3, "{n}");
        assert_eq!(substeps(1.0, f32::NAN), 1);
        let fixed = SolverSettings {
            substeps: Some(7),
            ..solver
        };
        assert_eq!(fixed.plan(1.0, 1e-9, 0.03).substeps, 7);
    }

    #[test]
    fn a_force_based_integrator_past_its_cap_falls_back_to_xpbd() {
        let solver = SolverSettings {
            integrator: Integrator::SymplecticEuler,
            ..SolverSettings::default()
        };
        // 1e-9 s stable step: 1.7e7 substeps needed at 1/60 s.
        let plan = solver.plan(1.0 / 60.0, 1e-9, 0.03);
        assert_eq!(plan.integrator, Integrator::Xpbd);
        assert_eq!(plan.substeps, 6, "360 Hz at 1/60 s");
        let capped = SolverSettings {
            stiff_fallback: false,
            ..solver
        };
        let plan = capped.plan(1.0 / 60.0, 1e-9, 0.03);
        assert_eq!(plan.integrator, Integrator::SymplecticEuler);
        assert_eq!(plan.substeps, solver.max_substeps);
    }

    #[test]
    fn xpbd_substeps_follow_the_rate_not_the_stiffness() {
        let solver = SolverSettings::default();
        assert_eq!(solver.integrator, Integrator::Xpbd);
        for stable in [1.0, 1e-3, 1e-9, f32::NAN] {
            assert_eq!(solver.plan(1.0 / 60.0, stable, 0.03).substeps, 6);
            assert_eq!(solver.plan(1.0 / 64.0, stable, 0.03).substeps, 6);
            assert_eq!(solver.plan(1.0 / 30.0, stable, 0.03).substeps, 12);
        }
        assert_eq!(solver.plan(1e-6, 1.0, 0.03).substeps, 1);
        assert_eq!(solver.plan(1e9, 1.0, 0.03).substeps, solver.max_substeps);
    }

    #[test]
    fn a_rate_meant_for_a_spacing_scales_with_the_cloths() {
        let solver = SolverSettings {
            substep_rate_spacing: Some(0.025),
            ..SolverSettings::default()
        };
        // 360 Hz at 25 mm: 6 substeps a 1/60 s frame there, 12 at 12.5 mm, 30 at 5 mm, and
        // the cap at 1 mm; a coarser cloth gets fewer, down to one.
        let substeps = |spacing| solver.plan(1.0 / 60.0, 1.0, spacing).substeps;
        assert_eq!(substeps(0.025), 6);
        assert_eq!(substeps(0.0125), 12);
        assert_eq!(substeps(0.005), 30);
        assert_eq!(substeps(0.001), solver.max_substeps);
        assert_eq!(substeps(0.05), 3);
        assert_eq!(substeps(10.0), 1);
        // A spacing that is no length leaves the rate as set.
        for spacing in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(substeps(spacing), 6, "spacing {spacing}");
        }
        // Without a reference the budget is fixed, whatever the spacing.
        let fixed = SolverSettings::default();
        assert_eq!(fixed.plan(1.0 / 60.0, 1.0, 0.005).substeps, 6);
        for bad in [0.0, -0.01, f32::NAN, f32::INFINITY] {
            let invalid = SolverSettings {
                substep_rate_spacing: Some(bad),
                ..SolverSettings::default()
            };
            assert!(matches!(
                invalid.validate(),
                Err(ClothError::InvalidSetting {
                    name: "substep_rate_spacing",
                    ..
                })
            ));
        }
    }

    #[test]
    fn invalid_settings_name_the_field() {
        let solver = SolverSettings {
            heat_model: HeatModel::Physical(PhysicalHeat {
                cooling: f32::NAN,
                ..PhysicalHeat::GAME
            }),
            ..SolverSettings::default()
        };
        assert!(matches!(
            solver.validate(),
            Err(ClothError::InvalidSetting {
                name: "heat_model.cooling",
                ..
            })
        ));
        let settings = ClothSettings {
            environment: Environment {
                up: Vec3::ZERO,
                ..Environment::default()
            },
            ..ClothSettings::default()
        };
        assert_eq!(settings.validate(), Err(ClothError::NonFinitePoint));
    }
}
