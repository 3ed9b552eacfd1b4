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

/// Lanes the modes are evaluated in at once: the modes and two empty ones, so the angles and
/// cosines of a point are one 8-wide loop the compiler turns into SIMD instructions.
const LANES: usize = 8;

/// A divergence-free velocity field of unit RMS speed (scale it by the speed you want).
///
/// The plane waves are stored by component, each array padded with empty modes (zero wave
/// and velocity) to eight entries, so a point's six angles are one SIMD loop.
#[derive(Clone, Debug, PartialEq)]
pub struct Turbulence {
    /// Wave vectors by component, rad/m.
    wave: [[f32; LANES]; 3],
    /// `wave × direction` by component, scaled so the field has unit RMS speed.
    velocity: [[f32; LANES]; 3],
    /// Angular frequencies, rad/s.
    frequency: [f32; LANES],
    /// Phases, rad.
    phase: [f32; LANES],
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
        let mut field = Self {
            wave: [[0.0; LANES]; 3],
            velocity: [[0.0; LANES]; 3],
            frequency: [0.0; LANES],
            phase: [0.0; LANES],
        };
        for j in 0..TURBULENCE_MODES {
            let direction_k = random_unit(rng);
            let wave = direction_k * base * rng.random_range(0.7..1.4);
            let direction = random_unit(rng);
            let velocity = direction_k.cross(direction) * norm;
            for axis in 0..3 {
                field.wave[axis][j] = wave[axis];
                field.velocity[axis][j] = velocity[axis];
            }
            field.frequency[j] = rate * rng.random_range(0.5..1.5);
            field.phase[j] = rng.random_range(0.0..core::f32::consts::TAU);
        }
        field
    }

    /// Air velocity at `position` (m) and `time` (s), m/s for a unit-speed field.
    #[inline]
    pub fn velocity(&self, position: Vec3, time: f32) -> Vec3 {
        let [kx, ky, kz] = &self.wave;
        let angles: [f32; LANES] = core::array::from_fn(|j| {
            kx[j] * position.x
                + ky[j] * position.y
                + kz[j] * position.z
                + (self.frequency[j] * time + self.phase[j])
        });
        let cosines = cosines(angles);
        let component = |v: &[f32; LANES]| (0..LANES).map(|j| v[j] * cosines[j]).sum::<f32>();
        let [vx, vy, vz] = &self.velocity;
        Vec3::new(component(vx), component(vy), component(vz))
    }
}

/// `cos` of eight angles (rad) at once: within 2.2e-7 of the exact cosine of the f32 angle
/// up to |x| = 1e4 rad, 1.7e-5 at 1e5 (where f32 angles are 8e-3 rad apart), and in
/// `[−1, 1]` for any finite input. One loop of plain arithmetic the compiler vectorises,
/// where the C library's `cosf` is a call per angle (six a smoke particle a frame).
///
/// `cos` is even, so `|x|` is reduced by whole turns (Cody–Waite: `2π` split in two parts so
/// the product with the turn count is exact) to `r` in `[0, π]`, and `cos r = −sin(r − π/2)`
/// with the sine's Taylor polynomial to degree 11 on `[−π/2, π/2]` (truncation below 6e-8).
/// Turns are rounded with the `1.5 × 2²³` trick, since x86-64's baseline has no rounding
/// instruction; past `2²²` turns the reduced angle is clamped into range.
#[inline(always)]
fn cosines(x: [f32; LANES]) -> [f32; LANES] {
    const ROUND: f32 = 12_582_912.0; // 1.5 × 2²³
    // 2π = TURN_HIGH + TURN_LOW, TURN_HIGH with 8 significant bits so that `n × TURN_HIGH`
    // is exact for every n below 2¹⁶.
    const TURN_HIGH: f32 = 6.281_25;
    const TURN_LOW: f32 = 1.935_307_2e-3;
    const INVERSE_TURN: f32 = 1.0 / core::f32::consts::TAU;
    core::array::from_fn(|l| {
        let a = x[l].abs();
        let turns = (a * INVERSE_TURN + ROUND) - ROUND;
        let r = ((a - turns * TURN_HIGH) - turns * TURN_LOW)
            .abs()
            .min(core::f32::consts::PI);
        let s = r - core::f32::consts::FRAC_PI_2;
        let s2 = s * s;
        let sine = s
            * (1.0
                + s2 * (-1.0 / 6.0
                    + s2 * (1.0 / 120.0
                        + s2 * (-1.0 / 5040.0
                            + s2 * (1.0 / 362_880.0 + s2 * (-1.0 / 39_916_800.0))))));
        -sine
    })
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

    /// The eight-wide cosine against the C library's, over the angles smoke meets (points
    /// metres from the origin at eddy wavenumbers, phases, an hour of time) and far past them.
    #[test]
    fn cosines_match_the_library_cosine() {
        let mut worst: f32 = 0.0;
        for i in 0..20_000 {
            let x = (i as f32 - 10_000.0) * 0.013_7;
            let angles: [f32; LANES] = core::array::from_fn(|l| x * (1.0 + l as f32 * 7.3));
            let got = cosines(angles);
            for (angle, c) in angles.iter().zip(got) {
                let error = (c - angle.cos()).abs();
                // Where f32 spaces angles 2e-7 rad or more apart the exact cosine of the
                // stored angle and ours differ by the reduction's round-off, a few ulp of x.
                let allowed = 4e-7 + 4.0 * f32::EPSILON * angle.abs();
                assert!(error <= allowed, "cos({angle}) = {} got {c}", angle.cos());
                worst = worst.max(error);
            }
        }
        assert!(worst < 1e-4, "worst {worst}");
        let extremes = [
            1e30,
            -1e30,
            f32::MAX,
            1e8,
            3.0e7,
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
        ];
        let padded: [f32; LANES] = core::array::from_fn(|l| extremes[l]);
        for c in cosines(padded) {
            assert!((-1.0..=1.0).contains(&c), "{c}");
        }
    }

    #[test]
    fn bad_parameters_fall_back_to_finite_field() {
        let field = Turbulence::new(&mut SmallRng::seed_from_u64(1), f32::NAN, -1.0);
        assert!(field.velocity(Vec3::ONE, 3.0).is_finite());
    }
}
