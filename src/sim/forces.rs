//! Forces on cloth particles: gravity, damped springs, air drag against the wind, and
//! forces added from outside. A burnt particle feels nothing and pulls on nothing.

use super::particles::BurnState;
use super::springs::{SpringCoefficients, Springs, spring_force};
use glam::Vec3;

/// Parameters of the force model that do not change within a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceParams {
    /// Gravitational acceleration, m/s².
    pub gravity: Vec3,
    /// Wind velocity, m/s: drag pulls particles toward it.
    pub wind: Vec3,
    /// Air drag per unit mass, 1/s: `f = -drag × m × (v - wind)`.
    pub drag_per_mass: f32,
    /// Spring stiffness and damping per kind.
    pub coefficients: SpringCoefficients,
}

impl Default for ForceParams {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            wind: Vec3::ZERO,
            drag_per_mass: 0.0,
            coefficients: SpringCoefficients::default(),
        }
    }
}

/// Everything the force evaluation reads besides positions and velocities.
///
/// Integrators evaluate forces at trial states, so positions and velocities are passed to
/// [`ForceModel::eval`] separately.
#[derive(Clone, Copy)]
pub struct ForceModel<'a> {
    /// Particle masses, kg.
    pub mass: &'a [f32],
    /// Particle burn states.
    pub state: &'a [BurnState],
    /// Forces added from outside for this step, N.
    pub external: &'a [Vec3],
    /// The springs.
    pub springs: &'a Springs,
    /// Constant parameters.
    pub params: &'a ForceParams,
}

impl ForceModel<'_> {
    /// Writes gravity, air drag and external forces (everything but the springs) into
    /// `out`, N; zero for burnt particles. Position-based solvers handle springs themselves.
    pub fn eval_without_springs(&self, velocity: &[Vec3], out: &mut [Vec3]) {
        let params = self.params;
        for i in 0..out.len() {
            out[i] = if self.state[i].is_burnt() {
                Vec3::ZERO
            } else {
                let m = self.mass[i];
                m * params.gravity - params.drag_per_mass * m * (velocity[i] - params.wind)
                    + self.external[i]
            };
        }
    }

    /// Writes the total force on every particle into `out`, N. Burnt particles get zero,
    /// and no spring with a burnt end contributes.
    pub fn eval(&self, position: &[Vec3], velocity: &[Vec3], out: &mut [Vec3]) {
        self.eval_without_springs(velocity, out);
        let springs = self.springs;
        let coefficients = &self.params.coefficients;
        for s in 0..springs.len() {
            let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
            if self.state[a].is_burnt() || self.state[b].is_burnt() {
                continue;
            }
            let f = spring_force(
                position[a],
                position[b],
                velocity[a],
                velocity[b],
                springs.rest_length[s],
                coefficients.law(springs.kind[s]),
            );
            out[a] += f;
            out[b] -= f;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::SpringKind;

    fn two_particles_one_spring() -> (Vec<f32>, Springs, ForceParams) {
        let mut springs = Springs::default();
        springs.push(0, 1, 1.0, SpringKind::Structural);
        let params = ForceParams {
            gravity: Vec3::new(0.0, -10.0, 0.0),
            coefficients: SpringCoefficients {
                stiffness: [100.0; 3],
                damping: [0.0; 3],
                ..SpringCoefficients::default()
            },
            ..Default::default()
        };
        (vec![0.5, 2.0], springs, params)
    }

    #[test]
    fn gravity_and_spring_sum_on_each_end() {
        let (mass, springs, params) = two_particles_one_spring();
        let state = [BurnState::Intact; 2];
        let external = [Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)];
        let model = ForceModel {
            mass: &mass,
            state: &state,
            external: &external,
            springs: &springs,
            params: &params,
        };
        let x = [Vec3::ZERO, Vec3::new(0.0, 1.2, 0.0)];
        let mut f = [Vec3::ZERO; 2];
        model.eval(&x, &[Vec3::ZERO; 2], &mut f);
        // Spring stretched 0.2 m at 100 N/m: 20 N pulling the ends together.
        assert!((f[0] - Vec3::new(0.0, -5.0 + 20.0, 0.0)).length() < 1e-4);
        assert!((f[1] - Vec3::new(1.0, -20.0 - 20.0, 0.0)).length() < 1e-4);
    }

    #[test]
    fn burnt_particle_feels_no_force_and_exerts_none() {
        let (mass, springs, params) = two_particles_one_spring();
        let state = [BurnState::Intact, BurnState::Burnt];
        let external = [Vec3::ZERO, Vec3::new(7.0, 0.0, 0.0)];
        let model = ForceModel {
            mass: &mass,
            state: &state,
            external: &external,
            springs: &springs,
            params: &params,
        };
        let x = [Vec3::ZERO, Vec3::new(0.0, 3.0, 0.0)];
        let mut f = [Vec3::ONE; 2];
        model.eval(&x, &[Vec3::ZERO; 2], &mut f);
        assert_eq!(f[1], Vec3::ZERO);
        assert!(
            (f[0] - Vec3::new(0.0, -5.0, 0.0)).length() < 1e-5,
            "{:?}",
            f[0]
        );
    }

    #[test]
    fn drag_pulls_toward_the_wind_velocity() {
        let (mass, springs, mut params) = two_particles_one_spring();
        params.gravity = Vec3::ZERO;
        params.drag_per_mass = 2.0;
        params.wind = Vec3::new(3.0, 0.0, 0.0);
        let state = [BurnState::Intact; 2];
        let model = ForceModel {
            mass: &mass,
            state: &state,
            external: &[Vec3::ZERO; 2],
            springs: &springs,
            params: &params,
        };
        let x = [Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)];
        let mut f = [Vec3::ZERO; 2];
        model.eval(&x, &[Vec3::ZERO; 2], &mut f);
        assert!((f[0] - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-5);
        assert!((f[1] - Vec3::new(12.0, 0.0, 0.0)).length() < 1e-5);
    }
}
