//! Ignition, burning away, and springs shrinking with heat.

use super::material::{BurnMaterial, valid_temperature};
use super::particles::BurnState;
use super::springs::{SpringCoefficients, Springs};
use glam::Vec3;

/// What one combustion update changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CombustionReport {
    /// Particles that went from intact to ignited.
    pub newly_ignited: u32,
    /// Particles that burnt away.
    pub newly_burnt: u32,
    /// Particles ignited after the update.
    pub ignited: u32,
}

/// Updates burn states from temperatures: a particle is ignited strictly above
/// `ignition_temperature` and burnt strictly above `burnt_temperature`. Burnt is final. An
/// ignited particle cooled below ignition goes back to intact (extinguished).
/// Indices of particles that burnt in this update are appended to `newly_burnt`.
pub fn update_burn_states(
    temperature: &[f32],
    state: &mut [BurnState],
    material: &BurnMaterial,
    newly_burnt: &mut Vec<u32>,
) -> CombustionReport {
    let mut report = CombustionReport::default();
    for (i, (t, s)) in temperature.iter().zip(state.iter_mut()).enumerate() {
        let next = match *s {
            BurnState::Burnt => BurnState::Burnt,
            _ if *t > material.burnt_temperature => BurnState::Burnt,
            _ if *t > material.ignition_temperature => BurnState::Ignited,
            _ => BurnState::Intact,
        };
        match (*s, next) {
            (BurnState::Intact, BurnState::Ignited) => report.newly_ignited += 1,
            (BurnState::Intact | BurnState::Ignited, BurnState::Burnt) => {
                report.newly_burnt += 1;
                newly_burnt.push(i as u32);
            }
            _ => {}
        }
        report.ignited += u32::from(next == BurnState::Ignited);
        *s = next;
    }
    report
}

/// The temperature [`extinguish`] cools to by default: nine tenths of the way from the
/// material's initial to its ignition temperature, so doused cloth stays scorched and
/// charred where it was hot but does not burn.
pub fn extinguished_temperature(material: &BurnMaterial) -> f32 {
    material.initial_temperature
        + 0.9 * (material.ignition_temperature - material.initial_temperature)
}

/// Puts a fire out: every unburnt particle within `radius` of `centre` (every particle with
/// `region = None`) is cooled to at most `to` (never above the material's ignition
/// temperature), and the ignited ones among them become intact. Burnt particles stay burnt.
/// Returns how many particles were cooled. A non-finite region or an invalid temperature
/// changes nothing.
pub fn extinguish(
    position: &[Vec3],
    temperature: &mut [f32],
    state: &mut [BurnState],
    material: &BurnMaterial,
    region: Option<(Vec3, f32)>,
    to: f32,
) -> u32 {
    if !valid_temperature(to) {
        return 0;
    }
    let to = to.min(material.ignition_temperature);
    if let Some((centre, radius)) = region
        && !(centre.is_finite() && radius.is_finite() && radius >= 0.0)
    {
        return 0;
    }
    let mut cooled = 0;
    for ((p, t), s) in position.iter().zip(temperature).zip(state) {
        if *s == BurnState::Burnt {
            continue;
        }
        if let Some((centre, radius)) = region
            && p.distance_squared(centre) > radius * radius
        {
            continue;
        }
        if *t > to || t.is_nan() {
            *t = to;
            cooled += 1;
        }
        if *s == BurnState::Ignited {
            *s = BurnState::Intact;
        }
    }
    cooled
}

/// Shrinks the rest length of every live spring by Larboulette's rule as the paper uses it,
/// per second of `h`:
///
/// `l ← max(l − factor × h × l_init × (ΔT_a + ΔT_b) / k, floor × l_init)`
///
/// with `ΔT = max(T − T_initial, 0)`: measured from the initial temperature so cold cloth
/// keeps its size (the paper's absolute temperatures shrink even a cold cloth slowly). A
/// spring of zero stiffness does not shrink. Rest lengths never fall below the floor.
pub fn shrink_rest_lengths(
    springs: &mut Springs,
    temperature: &[f32],
    state: &[BurnState],
    material: &BurnMaterial,
    coefficients: &SpringCoefficients,
    h: f32,
) {
    let rate = material.shrink_factor * h;
    if rate <= 0.0 {
        return;
    }
    let floor = material.min_rest_fraction;
    let t0 = material.initial_temperature;
    for s in 0..springs.len() {
        let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
        if state[a].is_burnt() || state[b].is_burnt() {
            continue;
        }
        let heat = (temperature[a] - t0).max(0.0) + (temperature[b] - t0).max(0.0);
        let k = coefficients.stiffness[springs.kind[s] as usize];
        if heat <= 0.0 || k <= 0.0 {
            continue;
        }
        let initial = springs.initial_rest_length[s];
        let shrunk = springs.rest_length[s] - rate * initial * heat / k;
        springs.rest_length[s] = shrunk.max(floor * initial);
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn extinguishing_cools_the_region_below_ignition_and_leaves_burnt_particles() {
        let m = BurnMaterial::COTTON;
        let position: Vec<Vec3> = (0..4).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
        let hot = m.ignition_temperature + 100.0;
        let mut temperature = vec![hot, hot, hot, m.burnt_temperature + 1.0];
        let mut state = vec![
            BurnState::Ignited,
            BurnState::Ignited,
            BurnState::Ignited,
            BurnState::Burnt,
        ];
        let to = extinguished_temperature(&m);
        assert!(to < m.ignition_temperature && to > m.initial_temperature);
        // Only the first two are within 1.5 m of the origin.
        let cooled = extinguish(
            &position,
            &mut temperature,
            &mut state,
            &m,
            Some((Vec3::ZERO, 1.5)),
            to,
        );
        assert_eq!(cooled, 2);
        assert_eq!(
            &state[..3],
            &[BurnState::Intact, BurnState::Intact, BurnState::Ignited]
        );
        assert_eq!(state[3], BurnState::Burnt);
        assert_eq!(temperature[0], to);
        // The state update agrees: nothing cooled re-ignites.
        let mut newly = Vec::new();
        let report = update_burn_states(&temperature, &mut state, &m, &mut newly);
        assert_eq!((report.newly_ignited, report.ignited), (0, 1));
        // A temperature above ignition is clamped to it; bad input changes nothing.
        extinguish(&position, &mut temperature, &mut state, &m, None, 5_000.0);
        assert!(
            temperature[..3]
                .iter()
                .all(|&t| t <= m.ignition_temperature)
        );
        assert_eq!(state[2], BurnState::Intact);
        let before = temperature.clone();
        assert_eq!(
            extinguish(&position, &mut temperature, &mut state, &m, None, f32::NAN),
            0
        );
        assert_eq!(
            extinguish(
                &position,
                &mut temperature,
                &mut state,
                &m,
                Some((Vec3::NAN, 1.0)),
                20.0
            ),
            0
        );
        assert_eq!(temperature, before);
    }

    use super::*;
    use crate::sim::SpringKind;

    #[test]
    fn every_material_ignites_exactly_above_its_threshold() {
        for material in BurnMaterial::PRESETS {
            let threshold = material.ignition_temperature;
            let temperature = [threshold, threshold.next_up(), threshold.next_down()];
            let mut state = [BurnState::Intact; 3];
            let report = update_burn_states(&temperature, &mut state, &material, &mut Vec::new());
            assert_eq!(
                state,
                [BurnState::Intact, BurnState::Ignited, BurnState::Intact],
                "{}",
                material.name
            );
            assert_eq!(report.newly_ignited, 1);
        }
    }

    #[test]
    fn burnt_is_final_and_reported_once() {
        let material = BurnMaterial::PAPER;
        let mut state = [BurnState::Ignited, BurnState::Intact];
        let mut burnt = Vec::new();
        let hot = [material.burnt_temperature + 1.0, 20.0];
        let report = update_burn_states(&hot, &mut state, &material, &mut burnt);
        assert_eq!(report.newly_burnt, 1);
        assert_eq!(burnt, vec![0]);
        let cold = [20.0, 20.0];
        let report = update_burn_states(&cold, &mut state, &material, &mut burnt);
        assert_eq!(state[0], BurnState::Burnt);
        assert_eq!(report.newly_burnt, 0);
        assert_eq!(burnt, vec![0]);
    }

    #[test]
    fn rest_lengths_shrink_with_heat_and_never_below_the_floor() {
        let material = BurnMaterial::SILK;
        let coefficients = SpringCoefficients::from_material(&material, 1e-4);
        let mut springs = Springs::default();
        springs.push(0, 1, 0.05, SpringKind::Structural);
        springs.push(1, 2, 0.05, SpringKind::Bend);
        let state = [BurnState::Ignited; 3];
        let cold = [material.initial_temperature; 3];
        shrink_rest_lengths(&mut springs, &cold, &state, &material, &coefficients, 0.01);
        assert_eq!(
            springs.rest_length,
            vec![0.05, 0.05],
            "cold cloth keeps its size"
        );
        let hot = [900.0; 3];
        shrink_rest_lengths(&mut springs, &hot, &state, &material, &coefficients, 0.01);
        let expected = 0.05
            - material.shrink_factor * 0.01 * 0.05 * 2.0 * (900.0 - material.initial_temperature)
                / material.structural_stiffness;
        assert!((springs.rest_length[0] - expected).abs() < 1e-7);
        for _ in 0..100_000 {
            shrink_rest_lengths(&mut springs, &hot, &state, &material, &coefficients, 0.01);
        }
        for s in 0..springs.len() {
            assert_eq!(
                springs.rest_length[s],
                material.min_rest_fraction * springs.initial_rest_length[s]
            );
        }
    }
}
