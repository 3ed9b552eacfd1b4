//! The physical heat model: conduction along the cloth, upward convection, cooling to the
//! air, and heat released by burning.
//!
//! For particle `i` with mass `mᵢ` (heat capacity `c·mᵢ`) and structural neighbours `j`
//! at rest distance `lᵢⱼ`:
//!
//! `mᵢ dTᵢ/dt = Σⱼ m̄ᵢⱼ (α/lᵢⱼ² + c·(L_ref/lᵢⱼ)·max(ûᵢⱼ·up, 0)·[Tᵢ > Tⱼ]) (Tⱼ − Tᵢ) + mᵢ q [ignited] − mᵢ κ (Tᵢ − T_air)`
//!
//! - conduction with diffusivity `α` (m²/s, [`PhysicalHeat::diffusivity`]): on a square grid of
//!   spacing `dx` this is the 5-point Laplacian, so `∂T/∂t = α∇²T` (checked against the spreading
//!   Gaussian);
//! - convection at rate `c` (1/s for links [`REFERENCE_SPACING`] long, `c·L_ref/lᵢⱼ` for a
//!   link `lᵢⱼ` long, an upwind transport at `c·L_ref` m/s whatever the spacing): hot air
//!   carries heat from a particle to a cooler one above it, in proportion to how vertical
//!   the link is — fire climbs, as in the paper, but heat moves rather than being created;
//! - heat release `q` (°C/s, [`PhysicalHeat::burn_heating`]) while a particle is ignited;
//! - cooling at rate `κ` (1/s) towards the air temperature.
//!
//! Each exchange is a flux between two particles, so with no burning and no cooling `Σ mᵢTᵢ` is
//! conserved to rounding (insulated edges). Burnt particles take no part. The explicit update is
//! stable and never overshoots when `h ≤ mᵢ / Σⱼ m̄ᵢⱼ rateᵢⱼ` for every particle;
//! [`conduction_step`] splits `h` into as many substeps as that needs (cooling is applied exactly,
//! as an exponential).

use super::material::{MAX_TEMPERATURE, REFERENCE_SPACING};
use super::particles::BurnState;
use super::settings::PhysicalHeat;
use super::springs::{SpringKind, Springs};
use glam::Vec3;

/// The air around a cloth as the physical model sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Air {
    /// Air temperature, °C: particles cool towards it.
    pub temperature: f32,
    /// World up, unit vector: heat climbs along it.
    pub up: Vec3,
}

/// Exchange rate of one structural spring, 1/s per unit mass, or `None` for springs that do
/// not conduct (not structural, or touching a burnt particle).
#[inline]
fn exchange_rate(
    springs: &Springs,
    s: usize,
    position: &[Vec3],
    temperature: Option<&[f32]>,
    state: &[BurnState],
    heat: &PhysicalHeat,
    up: Vec3,
) -> Option<(usize, usize, f32)> {
    if springs.kind[s] != SpringKind::Structural {
        return None;
    }
    let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
    if state[a].is_burnt() || state[b].is_burnt() {
        return None;
    }
    let rest = springs.initial_rest_length[s];
    if rest <= 0.0 {
        return None;
    }
    let mut rate = heat.diffusivity / (rest * rest);
    if heat.convection > 0.0 {
        // The hotter end's heat climbs if the cooler end is above it. `temperature` `None`:
        // the larger of the two orientations (a bound that holds however they flip).
        let rise = (position[b] - position[a]).normalize_or_zero().dot(up);
        let climb = match temperature {
            Some(t) if t[a] >= t[b] => rise.max(0.0),
            Some(_) => (-rise).max(0.0),
            None => rise.abs(),
        };
        rate += heat.convection * (REFERENCE_SPACING / rest) * climb;
    }
    Some((a, b, rate))
}

/// The largest stable, non-overshooting explicit step for the exchange terms, s (infinite
/// when nothing exchanges heat), whichever way each spring's ends are hot and cold (so it
/// holds when they swap within a frame). `scratch` is reused.
pub fn conduction_stable_step(
    springs: &Springs,
    position: &[Vec3],
    mass: &[f32],
    state: &[BurnState],
    heat: &PhysicalHeat,
    up: Vec3,
    scratch: &mut Vec<f32>,
) -> f32 {
    scratch.clear();
    scratch.resize(mass.len(), 0.0);
    for s in 0..springs.len() {
        if let Some((a, b, rate)) = exchange_rate(springs, s, position, None, state, heat, up) {
            let shared = 0.5 * (mass[a] + mass[b]);
            scratch[a] += rate * shared / mass[a];
            scratch[b] += rate * shared / mass[b];
        }
    }
    let fastest = scratch.iter().copied().fold(0.0f32, f32::max);
    if fastest > 0.0 {
        1.0 / fastest
    } else {
        f32::INFINITY
    }
}

/// Most substeps one [`conduction_step`] takes; past it each substep is longer than stable and
/// the exchange is limited so it stays monotone.
pub const MAX_CONDUCTION_SUBSTEPS: u32 = 1000;

/// Advances temperatures `h` seconds under the physical model, in as many explicit substeps
/// as stability needs (at most [`MAX_CONDUCTION_SUBSTEPS`]; past it, each particle's exchange
/// is limited to the range of its own and its neighbours' temperatures, so no particle
/// overshoots). Returns the substeps used. `scratch` is reused (three arrays of one value per
/// particle: the exchange and the neighbours' lowest and highest temperatures).
#[allow(clippy::too_many_arguments)]
pub fn conduction_step(
    springs: &Springs,
    position: &[Vec3],
    mass: &[f32],
    temperature: &mut [f32],
    state: &[BurnState],
    heat: &PhysicalHeat,
    air: Air,
    scratch: &mut Vec<f32>,
    h: f32,
) -> u32 {
    if !(h.is_finite() && h > 0.0) {
        return 0;
    }
    let stable = conduction_stable_step(springs, position, mass, state, heat, air.up, scratch);
    let wanted = if stable.is_finite() {
        (h / (0.9 * stable)).ceil()
    } else {
        1.0
    };
    let substeps = (wanted as u32).clamp(1, MAX_CONDUCTION_SUBSTEPS);
    let limited = wanted > MAX_CONDUCTION_SUBSTEPS as f32;
    let sub_h = h / substeps as f32;
    let keep = (-heat.cooling * sub_h).exp();
    let n = temperature.len();
    for _ in 0..substeps {
        scratch.clear();
        scratch.resize(3 * n, 0.0);
        let (delta, range) = scratch.split_at_mut(n);
        let (lo, hi) = range.split_at_mut(n);
        if limited {
            lo.copy_from_slice(temperature);
            hi.copy_from_slice(temperature);
        }
        for s in 0..springs.len() {
            if let Some((a, b, rate)) =
                exchange_rate(springs, s, position, Some(temperature), state, heat, air.up)
            {
                let flux = rate * 0.5 * (mass[a] + mass[b]) * (temperature[b] - temperature[a]);
                delta[a] += flux;
                delta[b] -= flux;
                if limited {
                    lo[a] = lo[a].min(temperature[b]);
                    hi[a] = hi[a].max(temperature[b]);
                    lo[b] = lo[b].min(temperature[a]);
                    hi[b] = hi[b].max(temperature[a]);
                }
            }
        }
        for i in 0..n {
            if state[i].is_burnt() {
                continue;
            }
            let mut t = temperature[i] + sub_h * delta[i] / mass[i];
            if limited {
                t = t.max(lo[i]).min(hi[i]);
            }
            if state[i].is_ignited() {
                t += heat.burn_heating * sub_h;
            }
            t = air.temperature + (t - air.temperature) * keep;
            if t.is_finite() {
                temperature[i] = t.min(MAX_TEMPERATURE);
            }
        }
    }
    substeps
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{BurnMaterial, ClothBuilder};
    use glam::Affine3A;

    fn flat_grid(n: u32, spacing: f32) -> crate::sim::ClothParts {
        ClothBuilder::grid(n, n, spacing)
            .build(&BurnMaterial::CLOTH, Affine3A::IDENTITY)
            .unwrap()
    }

    fn diffusion_only(diffusivity: f32) -> PhysicalHeat {
        PhysicalHeat {
            diffusivity,
            convection: 0.0,
            cooling: 0.0,
            burn_heating: 0.0,
        }
    }

    const AIR: Air = Air {
        temperature: 20.0,
        up: Vec3::Y,
    };

    /// Insulated edges, no burning, no cooling: Σ mᵢTᵢ is conserved, with convection too.
    #[test]
    fn heat_is_conserved() {
        let parts = flat_grid(20, 0.05);
        let p = &parts.particles;
        let mut temperature: Vec<f32> = (0..p.len())
            .map(|i| 20.0 + ((i * 37) % 101) as f32 * 5.0)
            .collect();
        let mut mass = p.mass.clone();
        mass[3] *= 4.0;
        let params = PhysicalHeat {
            convection: 3.0,
            ..diffusion_only(1e-3)
        };
        let total = |t: &[f32]| -> f64 {
            t.iter()
                .zip(&mass)
                .map(|(t, m)| f64::from(*t) * f64::from(*m))
                .sum()
        };
        let before = total(&temperature);
        let mut delta = Vec::new();
        for _ in 0..200 {
            conduction_step(
                &parts.springs,
                &p.position,
                &mass,
                &mut temperature,
                &p.state,
                &params,
                AIR,
                &mut delta,
                1.0 / 60.0,
            );
        }
        let after = total(&temperature);
        assert!(
            ((after - before) / before).abs() < 1e-5,
            "{before} -> {after}"
        );
        // And it did spread: the hottest particle cooled.
        assert!(temperature.iter().copied().fold(0.0, f32::max) < 20.0 + 500.0);
    }

    /// A Gaussian bump spreads as `A s²/(s² + 2αt) exp(−r²/(2(s² + 2αt)))`.
    #[test]
    fn a_gaussian_spreads_as_the_heat_equation_says() {
        let n = 61;
        let dx = 0.01;
        let parts = flat_grid(n, dx);
        let p = &parts.particles;
        let centre = p.position[(n as usize / 2) * n as usize + n as usize / 2];
        let (alpha, s, amplitude, t_end) = (1e-4f32, 0.04f32, 500.0f32, 2.0f32);
        let mut temperature: Vec<f32> = p
            .position
            .iter()
            .map(|x| 20.0 + amplitude * (-(x - centre).length_squared() / (2.0 * s * s)).exp())
            .collect();
        let mut delta = Vec::new();
        let params = diffusion_only(alpha);
        let steps = 120;
        for _ in 0..steps {
            conduction_step(
                &parts.springs,
                &p.position,
                &p.mass,
                &mut temperature,
                &p.state,
                &params,
                AIR,
                &mut delta,
                t_end / steps as f32,
            );
        }
        let width = s * s + 2.0 * alpha * t_end;
        let mut worst = 0.0f32;
        for (x, t) in p.position.iter().zip(&temperature) {
            let exact = 20.0
                + amplitude * s * s / width
                    * (-(x - centre).length_squared() / (2.0 * width)).exp();
            worst = worst.max((t - exact).abs());
        }
        // The peak falls from 500 to 222; the grid solution is within 1% of the amplitude.
        assert!(worst < 0.01 * amplitude, "max error {worst} °C");
    }

    #[test]
    fn heat_climbs_and_burnt_particles_are_insulated() {
        let parts = flat_grid(5, 0.05);
        let p = &parts.particles;
        // Grid rows run downward in world space: row 0 is the top.
        let centre = 2 * 5 + 2;
        let (above, below) = (5 + 2, 3 * 5 + 2);
        let mut temperature = vec![20.0; p.len()];
        temperature[centre] = 800.0;
        let mut state = p.state.clone();
        let burnt = 2 * 5 + 3;
        state[burnt] = BurnState::Burnt;
        temperature[burnt] = 5.0;
        let params = PhysicalHeat {
            convection: 5.0,
            ..diffusion_only(1e-4)
        };
        let mut delta = Vec::new();
        conduction_step(
            &parts.springs,
            &p.position,
            &p.mass,
            &mut temperature,
            &state,
            &params,
            AIR,
            &mut delta,
            0.05,
        );
        assert!(p.position[above].y > p.position[below].y);
        assert!(temperature[above] > temperature[below] + 1.0);
        assert_eq!(temperature[burnt], 5.0);
    }

    /// A 1 mm grid at 20 °C with one particle at 1000 °C after `h` seconds of pure
    /// diffusion at `diffusivity`: the temperatures and the substeps used.
    fn hot_spot_after(diffusivity: f32, h: f32) -> (Vec<f32>, u32) {
        let parts = flat_grid(8, 0.001);
        let p = &parts.particles;
        let mut temperature = vec![20.0; p.len()];
        temperature[27] = 1000.0;
        let mut scratch = Vec::new();
        let used = conduction_step(
            &parts.springs,
            &p.position,
            &p.mass,
            &mut temperature,
            &p.state,
            &diffusion_only(diffusivity),
            AIR,
            &mut scratch,
            h,
        );
        (temperature, used)
    }

    #[test]
    fn stiff_step_is_split_and_stays_monotone() {
        let (temperature, used) = hot_spot_after(1e-3, 0.1);
        assert!(used > 1);
        assert!(
            temperature
                .iter()
                .all(|t| (20.0 - 1e-3..=1000.0).contains(t))
        );
    }

    #[test]
    fn a_step_past_the_substep_cap_stays_monotone() {
        // A diffusivity of 1e-2 m²/s for a whole second: about 10⁵ substeps would be stable,
        // far past the cap.
        let (temperature, used) = hot_spot_after(1e-2, 1.0);
        assert_eq!(used, MAX_CONDUCTION_SUBSTEPS);
        for t in &temperature {
            assert!(
                (20.0 - 1e-3..=1000.0 + 1e-3).contains(t),
                "{t} outside 20..1000"
            );
        }
    }
}
