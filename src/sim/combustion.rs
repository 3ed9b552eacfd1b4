//! Putting a fire out, and what a combustion update changed. Ignition, burning away and
//! shrinking run over the burning front ([`super::front`]).

use super::material::{BurnMaterial, valid_temperature};
use super::particles::BurnState;
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

/// The temperature [`extinguish`] cools to by default: nine tenths of the way from the
/// material's initial to its ignition temperature, so doused cloth stays scorched and
/// charred where it was hot but does not burn.
pub fn extinguished_temperature(material: &BurnMaterial) -> f32 {
    material.initial_temperature
        + 0.9 * (material.ignition_temperature - material.initial_temperature)
}

/// Whether `p` is within `radius` of `centre` (every point is within `None`).
pub fn in_region(region: Option<(Vec3, f32)>, p: Vec3) -> bool {
    region.is_none_or(|(centre, radius)| p.distance_squared(centre) <= radius * radius)
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
        if *s == BurnState::Burnt || !in_region(region, *p) {
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

#[cfg(test)]
mod tests {
    use super::*;

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
        // Nothing cooled is above ignition any more; the one outside the region still is.
        assert!(
            temperature[..2]
                .iter()
                .all(|&t| t <= m.ignition_temperature)
        );
        assert!(temperature[2] > m.ignition_temperature);
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
}
