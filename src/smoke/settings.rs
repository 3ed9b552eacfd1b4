//! Parameters of an emitter: one set per particle kind, plus pool size, seed and air.

use super::pool::SmokeKind;
use super::tongues::TongueSettings;
use core::fmt;

/// How one kind of particle is born, moves, and looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KindSettings {
    /// Birth rate. Flames and smoke: particles per second per square metre of cloth burning
    /// at full intensity. Embers: particles per square metre of cloth that burns away (so a
    /// fine cloth throws as many sparks from a hole as a coarse one, not more per particle).
    pub rate: f32,
    /// Shortest and longest lifetime, s; each particle draws one in between.
    pub lifetime: [f32; 2],
    /// Initial speed along world up, m/s.
    pub rise_speed: f32,
    /// Random initial velocity added in every direction, up to this speed, m/s.
    pub spread_speed: f32,
    /// Sprite half-size at birth and at death, m.
    pub size: [f32; 2],
    /// Upward acceleration per 1000 °C above ambient, m/s² (hot gas rises).
    pub buoyancy: f32,
    /// Fraction of gravity acting on the particle (embers have weight, gas does not).
    pub gravity_scale: f32,
    /// Rate at which the particle's velocity relaxes to the air's (wind plus turbulence), 1/s.
    pub drag: f32,
    /// RMS speed of the turbulence the particle is carried by, m/s.
    pub turbulence: f32,
    /// Rate at which the particle cools towards ambient, 1/s.
    pub cooling: f32,
    /// Linear RGBA colour at birth and at death; alpha fades in over the first tenth of life.
    pub colour: [[f32; 4]; 2],
}

impl KindSettings {
    /// Flames: flamelets that break off the tongues' tips, short-lived, bright, rising fast.
    pub const FLAME: Self = Self {
        rate: 300.0,
        lifetime: [0.15, 0.35],
        rise_speed: 0.9,
        spread_speed: 0.15,
        size: [0.035, 0.01],
        buoyancy: 5.0,
        gravity_scale: 0.0,
        drag: 3.0,
        turbulence: 0.25,
        cooling: 1.5,
        colour: [[1.0, 0.45, 0.08, 0.7], [0.7, 0.1, 0.02, 0.0]],
    };

    /// Smoke: long-lived, grey, expanding and fading, curling in the turbulence.
    pub const SMOKE: Self = Self {
        rate: 700.0,
        lifetime: [2.5, 4.5],
        rise_speed: 0.4,
        spread_speed: 0.1,
        size: [0.04, 0.26],
        buoyancy: 4.0,
        gravity_scale: 0.0,
        drag: 1.5,
        turbulence: 0.35,
        cooling: 0.6,
        colour: [[0.16, 0.15, 0.14, 0.55], [0.45, 0.45, 0.46, 0.0]],
    };

    /// Embers: small sparks where cloth burns away (1 200 per square metre: 1.5 per particle
    /// of a cloth 35 mm apart), floating up while hot, falling later.
    pub const EMBER: Self = Self {
        rate: 1200.0,
        lifetime: [1.0, 2.5],
        rise_speed: 0.5,
        spread_speed: 0.6,
        size: [0.009, 0.004],
        buoyancy: 3.0,
        gravity_scale: 0.35,
        drag: 1.0,
        turbulence: 0.4,
        cooling: 0.8,
        colour: [[1.0, 0.7, 0.25, 1.0], [0.6, 0.08, 0.0, 0.0]],
    };

    /// No particles of this kind.
    pub const NONE: Self = Self {
        rate: 0.0,
        ..Self::FLAME
    };

    /// Checks every field; `kind` names the kind in the error.
    pub fn validate(&self, kind: SmokeKind) -> Result<(), SmokeSettingsError> {
        let error = |field, value, requirement| SmokeSettingsError {
            kind: Some(kind),
            field,
            value,
            requirement,
        };
        let non_negative = [
            ("rate", self.rate),
            ("rise_speed", self.rise_speed),
            ("spread_speed", self.spread_speed),
            ("size[0]", self.size[0]),
            ("size[1]", self.size[1]),
            ("drag", self.drag),
            ("turbulence", self.turbulence),
            ("cooling", self.cooling),
        ];
        for (field, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(error(field, value, "finite and >= 0"));
            }
        }
        for (field, value) in [
            ("buoyancy", self.buoyancy),
            ("gravity_scale", self.gravity_scale),
        ] {
            if !value.is_finite() || value.abs() > 1e3 {
                return Err(error(field, value, "finite, magnitude <= 1000"));
            }
        }
        let [shortest, longest] = self.lifetime;
        if !(shortest.is_finite() && shortest > 0.0) {
            return Err(error("lifetime[0]", shortest, "finite and > 0"));
        }
        if !(longest.is_finite() && longest >= shortest) {
            return Err(error("lifetime[1]", longest, "finite and >= lifetime[0]"));
        }
        for value in self.colour.iter().flatten() {
            if !(value.is_finite() && *value >= 0.0) {
                return Err(error("colour", *value, "finite and >= 0"));
            }
        }
        Ok(())
    }
}

/// Largest pool an emitter may ask for.
pub const MAX_SMOKE_CAPACITY: usize = 1 << 20;

/// Everything an emitter needs: the three kinds, pool size, seed and turbulence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmokeSettings {
    /// Flames, smoke and embers, in the order of [`SmokeKind::ALL`].
    pub kind: [KindSettings; 3],
    /// Pool capacity: the most particles alive at once.
    pub capacity: usize,
    /// Seed of the emitter's random numbers: the same seed and burn give the same particles.
    pub seed: u64,
    /// Air temperature, °C: particles cool towards it and are buoyant above it.
    pub ambient_temperature: f32,
    /// Particles are born up to this far from the burning cloth particle, m.
    pub birth_radius: f32,
    /// Size of the turbulence's eddies, m.
    pub eddy_size: f32,
    /// How fast the turbulence changes, 1/s.
    pub eddy_rate: f32,
    /// The flame tongues drawn along the burning front ([`TongueSettings::NONE`]: none).
    pub tongues: TongueSettings,
}

impl Default for SmokeSettings {
    fn default() -> Self {
        Self {
            kind: [
                KindSettings::FLAME,
                KindSettings::SMOKE,
                KindSettings::EMBER,
            ],
            capacity: 4096,
            seed: 0x5eed_f1a3,
            ambient_temperature: 20.0,
            birth_radius: 0.015,
            eddy_size: 0.6,
            eddy_rate: 0.8,
            tongues: TongueSettings::DEFAULT,
        }
    }
}

impl SmokeSettings {
    /// The settings of one kind.
    pub fn of(&self, kind: SmokeKind) -> &KindSettings {
        &self.kind[kind as usize]
    }

    /// The settings of one kind, mutable.
    pub fn of_mut(&mut self, kind: SmokeKind) -> &mut KindSettings {
        &mut self.kind[kind as usize]
    }

    /// Sets the pool capacity.
    pub fn with_capacity(mut self, capacity: usize) -> Self {
        self.capacity = capacity;
        self
    }

    /// Sets the seed.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Replaces one kind's settings ([`KindSettings::NONE`] turns the kind off).
    pub fn with_kind(mut self, kind: SmokeKind, settings: KindSettings) -> Self {
        *self.of_mut(kind) = settings;
        self
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<(), SmokeSettingsError> {
        for kind in SmokeKind::ALL {
            self.of(kind).validate(kind)?;
        }
        let error = |field, value, requirement| SmokeSettingsError {
            kind: None,
            field,
            value,
            requirement,
        };
        if self.capacity == 0 || self.capacity > MAX_SMOKE_CAPACITY {
            return Err(error(
                "capacity",
                self.capacity as f32,
                "between 1 and MAX_SMOKE_CAPACITY",
            ));
        }
        if !crate::sim::material::valid_temperature(self.ambient_temperature) {
            return Err(error(
                "ambient_temperature",
                self.ambient_temperature,
                "finite, between -273.15 and 1e5 °C",
            ));
        }
        for (field, value) in [
            ("birth_radius", self.birth_radius),
            ("eddy_rate", self.eddy_rate),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(error(field, value, "finite and >= 0"));
            }
        }
        if !(self.eddy_size.is_finite() && self.eddy_size > 0.0) {
            return Err(error("eddy_size", self.eddy_size, "finite and > 0"));
        }
        self.tongues
            .validate()
            .map_err(|(field, value, requirement)| error(field, value, requirement))
    }
}

/// A smoke setting with an unusable value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmokeSettingsError {
    /// The kind the field belongs to, if any.
    pub kind: Option<SmokeKind>,
    /// The field.
    pub field: &'static str,
    /// The rejected value.
    pub value: f32,
    /// What the field must be.
    pub requirement: &'static str,
}

impl fmt::Display for SmokeSettingsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(kind) = self.kind {
            write!(f, "{kind:?} ")?;
        }
        write!(
            f,
            "{} = {} must be {}",
            self.field, self.value, self.requirement
        )
    }
}

impl std::error::Error for SmokeSettingsError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid() {
        SmokeSettings::default().validate().unwrap();
        KindSettings::NONE.validate(SmokeKind::Flame).unwrap();
    }

    #[test]
    fn bad_values_are_named() {
        let mut settings = SmokeSettings::default();
        settings.of_mut(SmokeKind::Smoke).lifetime = [2.0, 1.0];
        let error = settings.validate().unwrap_err();
        assert_eq!(error.field, "lifetime[1]");
        assert_eq!(error.kind, Some(SmokeKind::Smoke));
        let settings = SmokeSettings::default().with_capacity(0);
        assert_eq!(settings.validate().unwrap_err().field, "capacity");
        let mut settings = SmokeSettings::default();
        settings.of_mut(SmokeKind::Ember).rate = f32::NAN;
        assert!(
            settings
                .validate()
                .unwrap_err()
                .to_string()
                .contains("Ember rate")
        );
        let settings = SmokeSettings {
            ambient_temperature: -400.0,
            ..SmokeSettings::default()
        };
        assert!(settings.validate().is_err());
    }
}
