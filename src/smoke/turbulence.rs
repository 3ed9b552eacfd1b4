//! A divergence-free turbulence field ("curl noise") for smoke to ride on.
//!
//! The field is the curl of a vector potential made of a few plane waves,
//! `ψ(p, t) = Σⱼ dⱼ sin(kⱼ·p + ωⱼ t + φⱼ)`, so
//! `u(p, t) = ∇ × ψ = Σⱼ cos(kⱼ·p + ωⱼ t + φⱼ) (kⱼ × dⱼ)`.
//! Each term's divergence is `−sin(…) kⱼ·(kⱼ × dⱼ) = 0`, so the field is divergence-free
//! exactly (Bridson et al., *Curl-Noise for Procedural Fluid Flow*, 2007, with plane waves
//! instead of gradient noise). Smoke following it swirls and curls without bunching up or
//! thinning out, and evaluating it costs a few cosines per particle.

use glam::Vec3;
use rand::{Rng, RngExt};

/// Number of plane waves in the field.
pub const TURBULENCE_MODES: usize = 6;

/// One plane wave of the vector potential.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Mode {
    /// Wave vector, rad/m.
    wave: Vec3,
    /// `wave × direction`, scaled so the field has unit RMS speed.
    velocity: Vec3,
    /// Angular frequency, rad/s.
    frequency: f32,
    /// Phase, rad.
    phase: f32,
}

/// A divergence-free velocity field of unit RMS speed (scale it by the speed you want).
#[derive(Clone, Debug, PartialEq)]
pub struct Turbulence {
    modes: [Mode; TURBULENCE_MODES],
}

impl Turbulence {
    /// A field whose eddies are about `wavelength` metres across and change over about
    /// `1 / rate` seconds, drawn from `rng`. Non-finite or non-positive values fall back to
    /// 0.5 m and 1 /s.
    pub fn new(rng: &mut impl Rng, wavelength: f32, rate: f32) -> Self {
        let wavelength = if wavelength.is_finite() && wavelength > 0.0 {
            wavelength
        } else {
            0.5
        };
        let rate = if rate.is_finite() && rate >= 0.0 {
            rate
        } else {
            1.0
        };
        let base = core::f32::consts::TAU / wavelength;
        // cos² averages 1/2 over space, and a random direction's component across k has
        // mean square 2/3: scale so Σ E[|u|²] = 1.
        let norm = (3.0 / TURBULENCE_MODES as f32).sqrt();
        let modes = core::array::from_fn(|_| {
            let direction_k = random_unit(rng);
            let wave = direction_k * base * rng.random_range(0.7..1.4);
            let direction = random_unit(rng);
            Mode {
                wave,
                velocity: direction_k.cross(direction) * norm,
                frequency: rate * rng.random_range(0.5..1.5),
                phase: rng.random_range(0.0..core::f32::consts::TAU),
            }
        });
        Self { modes }
    }

    /// Air velocity at `position` (m) and `time` (s), m/s for a unit-speed field.
    #[inline]
    pub fn velocity(&self, position: Vec3, time: f32) -> Vec3 {
        let mut velocity = Vec3::ZERO;
        for mode in &self.modes {
            let angle = mode.wave.dot(position) + mode.frequency * time + mode.phase;
            velocity += mode.velocity * angle.cos();
        }
        velocity
    }
}

/// A direction drawn uniformly from the unit sphere.
pub(crate) fn random_unit(rng: &mut impl Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let length_squared = v.length_squared();
        if length_squared > 1e-4 && length_squared <= 1.0 {
            return v / length_squared.sqrt();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand::rngs::SmallRng;

    fn field() -> Turbulence {
        Turbulence::new(&mut SmallRng::seed_from_u64(7), 0.4, 1.0)
    }

    /// Central-difference divergence is zero up to truncation error, while the field's
    /// derivatives themselves are of order k = 2π/λ.
    #[test]
    fn field_is_divergence_free() {
        let field = field();
        let h = 1e-3;
        let mut largest_divergence = 0.0f32;
        let mut largest_derivative = 0.0f32;
        for i in 0..200 {
            let p = Vec3::new(
                (i as f32 * 0.37).sin(),
                (i as f32 * 0.11).cos() * 2.0,
                i as f32 * 0.013,
            );
            let t = i as f32 * 0.05;
            let dx = (field.velocity(p + Vec3::X * h, t) - field.velocity(p - Vec3::X * h, t))
                / (2.0 * h);
            let dy = (field.velocity(p + Vec3::Y * h, t) - field.velocity(p - Vec3::Y * h, t))
                / (2.0 * h);
            let dz = (field.velocity(p + Vec3::Z * h, t) - field.velocity(p - Vec3::Z * h, t))
                / (2.0 * h);
            largest_divergence = largest_divergence.max((dx.x + dy.y + dz.z).abs());
            largest_derivative = largest_derivative.max(dx.abs().max_element());
        }
        assert!(
            largest_derivative > 1.0,
            "field is not varying: {largest_derivative}"
        );
        assert!(
            largest_divergence < 1e-2 * largest_derivative,
            "divergence {largest_divergence} vs derivatives {largest_derivative}"
        );
    }

    /// The mean square speed over many points is about 1.
    #[test]
    fn field_has_unit_rms_speed() {
        let mut mean_square = 0.0;
        let samples = 20;
        for seed in 0..samples {
            let field = Turbulence::new(&mut SmallRng::seed_from_u64(seed), 0.4, 1.0);
            for i in 0..500 {
                let p = Vec3::new(i as f32 * 0.173, (i * 7 % 13) as f32 * 0.29, 0.0);
                mean_square += field.velocity(p, 0.0).length_squared();
            }
        }
        mean_square /= (samples * 500) as f32;
        assert!(
            (0.6..1.5).contains(&mean_square),
            "mean square {mean_square}"
        );
    }

    #[test]
    fn bad_parameters_fall_back_to_finite_field() {
        let field = Turbulence::new(&mut SmallRng::seed_from_u64(1), f32::NAN, -1.0);
        assert!(field.velocity(Vec3::ONE, 3.0).is_finite());
    }
}
