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
/// cosines of a point are one 8-wide loop the compiler turns into SIMD instructions; and the
/// points [`Turbulence::velocities`] takes at once.
pub const LANES: usize = 8;

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
        // Added in order from -0.0 (what `Sum` does), as `velocities` adds them.
        let component =
            |v: &[f32; LANES]| (0..LANES).fold(-0.0, |sum: f32, j| sum + v[j] * cosines[j]);
        let [vx, vy, vz] = &self.velocity;
        Vec3::new(component(vx), component(vy), component(vz))
    }

    /// [`Self::velocity`] at eight points at once, each the same to the bit: positions by
    /// axis (m) in, velocities by axis (m/s) out. The points go in the SIMD lanes, mode
    /// after mode, where `velocity` puts one point's modes in the lanes and adds them up
    /// across, one dependent addition after another: a smoke particle's eddies cost half
    /// as much this way (`stress -- --smoke-only`).
    pub fn velocities(&self, [x, y, z]: &[[f32; LANES]; 3], time: f32) -> [[f32; LANES]; 3] {
        #[cfg(target_arch = "x86_64")]
        if crate::sim::simd::avx_available() {
            // SAFETY: AVX is present on this CPU.
            #[allow(unsafe_code)]
            return unsafe { velocities_avx(self, [x, y, z], time) };
        }
        velocities_by_lane(self, [x, y, z], time)
    }
}

/// [`Turbulence::velocities`] compiled for AVX (the same operations, no fused multiply-add).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn velocities_avx(field: &Turbulence, points: [&[f32; LANES]; 3], time: f32) -> [[f32; LANES]; 3] {
    velocities_by_lane(field, points, time)
}

#[inline(always)]
fn velocities_by_lane(
    field: &Turbulence,
    [x, y, z]: [&[f32; LANES]; 3],
    time: f32,
) -> [[f32; LANES]; 3] {
    // From -0.0, mode by mode, as `velocity` adds them.
    let mut sx = [-0.0f32; LANES];
    let mut sy = [-0.0f32; LANES];
    let mut sz = [-0.0f32; LANES];
    let [kx, ky, kz] = &field.wave;
    let [vx, vy, vz] = &field.velocity;
    for j in 0..TURBULENCE_MODES {
        let shift = field.frequency[j] * time + field.phase[j];
        let (kx, ky, kz) = (kx[j], ky[j], kz[j]);
        let mut angles = [0.0f32; LANES];
        for l in 0..LANES {
            angles[l] = kx * x[l] + ky * y[l] + kz * z[l] + shift;
        }
        let c = cosines(angles);
        let (vx, vy, vz) = (vx[j], vy[j], vz[j]);
        for l in 0..LANES {
            sx[l] += vx * c[l];
            sy[l] += vy * c[l];
            sz[l] += vz * c[l];
        }
    }
    // The empty modes each add `0 × cos 0 = +0.0` in `velocity` (zero wave, frequency and
    // phase); adding it once is the same as twice (only a -0.0 sum changes).
    for l in 0..LANES {
        sx[l] += 0.0;
        sy[l] += 0.0;
        sz[l] += 0.0;
    }
    [sx, sy, sz]
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

    /// Eight points at once give what each point alone gives, to the bit: smoke moves the
    /// same whichever way its eddies are found.
    #[test]
    fn eight_points_at_once_match_one_at_a_time() {
        let check = |field: &Turbulence, points: [Vec3; LANES], time: f32| {
            let axes = [0, 1, 2].map(|k| points.map(|p| p[k]));
            let together = field.velocities(&axes, time);
            for (l, p) in points.iter().enumerate() {
                let alone = field.velocity(*p, time);
                let got = Vec3::new(together[0][l], together[1][l], together[2][l]);
                if alone.is_nan() {
                    assert!(got.is_nan(), "{p}: {got}");
                } else {
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(got), bits(alone), "{p} at {time} s");
                }
            }
        };
        for seed in 0..20 {
            let field = Turbulence::new(&mut SmallRng::seed_from_u64(seed), 0.3, 2.0);
            for i in 0..200 {
                let points: [Vec3; LANES] = core::array::from_fn(|l| {
                    let k = (i * LANES + l) as f32;
                    Vec3::new((k * 0.37).sin() * 3.0, k * 0.011, (k * 0.73).cos() - 40.0)
                });
                check(&field, points, i as f32 * 0.7);
            }
        }
        // Zero, far and non-finite points.
        let points = [
            Vec3::ZERO,
            Vec3::splat(-0.0),
            Vec3::splat(1e30),
            Vec3::splat(-3e7),
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::NAN,
            Vec3::new(0.0, f32::MIN_POSITIVE, -0.0),
            Vec3::splat(f32::MAX),
        ];
        check(&field(), points, 12.5);
    }

    #[test]
    fn bad_parameters_fall_back_to_finite_field() {
        let field = Turbulence::new(&mut SmallRng::seed_from_u64(1), f32::NAN, -1.0);
        assert!(field.velocity(Vec3::ONE, 3.0).is_finite());
    }
}
