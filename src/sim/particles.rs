//! Cloth particles as a structure of arrays.

use glam::Vec3;

/// How far a particle has burnt.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum BurnState {
    /// Below its ignition temperature and never burnt.
    #[default]
    Intact,
    /// At or above its ignition temperature: it pushes heat and smokes.
    Ignited,
    /// Above the burnt temperature: removed from forces, heat and the mesh, for good.
    Burnt,
}

impl BurnState {
    /// True once the particle has burnt away.
    pub fn is_burnt(self) -> bool {
        self == Self::Burnt
    }

    /// True while the particle is on fire.
    pub fn is_ignited(self) -> bool {
        self == Self::Ignited
    }
}

/// The particles of one cloth. Every array has the same length; index `i` is particle `i`.
///
/// Positions are in world space (metres), velocities in m/s, masses in kg, temperatures
/// in °C. A particle with `inv_mass == 0` is pinned: it follows its anchor and nothing
/// else moves it.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    /// World positions, m.
    pub position: Vec<Vec3>,
    /// Velocities, m/s.
    pub velocity: Vec<Vec3>,
    /// Masses, kg (pinned particles keep theirs, for the weight they carry).
    pub mass: Vec<f32>,
    /// Inverse masses, 1/kg; zero for pinned particles.
    pub inv_mass: Vec<f32>,
    /// Temperatures, °C.
    pub temperature: Vec<f32>,
    /// Burn states.
    pub state: Vec<BurnState>,
    /// Seconds each particle has been on fire, s: zero while intact, counting up while
    /// ignited, kept once burnt (how long it burnt). The burn-out
    /// ([`BurnMaterial::burn_time`](super::BurnMaterial::burn_time)) and the shader's char read it.
    pub burning_for: Vec<f32>,
    /// Positions in the cloth's own frame when it was built, m. Pinned particles are placed
    /// at `transform × anchor` every step, so pins follow the cloth entity.
    pub anchor: Vec<Vec3>,
    /// Forces added from outside the solver for the next step, N (gameplay forces, wind
    /// gusts). They act throughout the next step (every substep) and are cleared after it.
    pub external_force: Vec<Vec3>,
}

impl Particles {
    /// Number of particles (burnt ones included).
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// True when the cloth has no particle at all.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// True for a pinned particle (burnt or not).
    pub fn is_pinned(&self, index: usize) -> bool {
        self.inv_mass[index] == 0.0
    }

    /// Number of particles in a burn state.
    pub fn count(&self, state: BurnState) -> usize {
        self.state.iter().filter(|&&s| s == state).count()
    }

    /// Fraction of particles burnt away, in [0, 1].
    pub fn burnt_fraction(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        self.count(BurnState::Burnt) as f32 / self.len() as f32
    }

    /// Number of pinned particles that have not burnt.
    pub fn pins_left(&self) -> usize {
        (0..self.len())
            .filter(|&i| self.is_pinned(i) && !self.state[i].is_burnt())
            .count()
    }

    /// Total mass of unburnt particles, kg.
    pub fn live_mass(&self) -> f32 {
        self.mass
            .iter()
            .zip(&self.state)
            .filter(|(_, s)| !s.is_burnt())
            .map(|(m, _)| m)
            .sum()
    }

    /// Mass-weighted centre of the unburnt particles in `indices`, or `None` if all burnt.
    pub fn centre_of_mass(&self, indices: impl IntoIterator<Item = usize>) -> Option<Vec3> {
        let (mut sum, mut mass) = (Vec3::ZERO, 0.0);
        for i in indices {
            if !self.state[i].is_burnt() {
                sum += self.position[i] * self.mass[i];
                mass += self.mass[i];
            }
        }
        (mass > 0.0).then(|| sum / mass)
    }

    /// Kinetic energy of the unburnt free particles, J.
    pub fn kinetic_energy(&self) -> f32 {
        (0..self.len())
            .filter(|&i| !self.state[i].is_burnt() && !self.is_pinned(i))
            .map(|i| 0.5 * self.mass[i] * self.velocity[i].length_squared())
            .sum()
    }

    /// Lowest and highest temperature of unburnt particles, °C.
    pub fn temperature_range(&self) -> Option<(f32, f32)> {
        self.temperature
            .iter()
            .zip(&self.state)
            .filter(|(_, s)| !s.is_burnt())
            .map(|(&t, _)| t)
            .fold(None, |range, t| match range {
                None => Some((t, t)),
                Some((lo, hi)) => Some((lo.min(t), hi.max(t))),
            })
    }

    /// True when every position, velocity and temperature is finite.
    pub fn is_finite(&self) -> bool {
        self.position.iter().all(|p| p.is_finite())
            && self.velocity.iter().all(|v| v.is_finite())
            && self.temperature.iter().all(|t| t.is_finite())
    }
}
