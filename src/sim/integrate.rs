//! Time integrators behind one interface, [`integrate`].
//!
//! | method | stable when (undamped spring) | force evaluations | order |
//! |---|---|---|---|
//! | [`Integrator::ExplicitEuler`] (the paper's) | never: energy grows every step | 1 | 1 |
//! | [`Integrator::SymplecticEuler`] | ω h < 2 | 1 | 1 |
//! | [`Integrator::Verlet`] (leapfrog) | ω h < 2 | 1 | 2 (positions) |
//! | [`Integrator::Rk4`] | ω h ≤ 2.83 | 4 | 4 |
//! | [`Integrator::Xpbd`] (one iteration per substep) | always | springs as constraints, 1 pass | 1 |
//!
//! Pinned particles (`inv_mass == 0`) and burnt particles are never moved here: pins are
//! placed by [`drive_pins`], burnt particles have left the simulation.

use super::forces::{ForceModel, ForceParams};
use super::guard::GuardSettings;
use super::particles::Particles;
use super::springs::{SpringCoefficients, Springs};
use super::xpbd::{Surroundings, XpbdSolver};
use bevy::reflect::{Reflect, std_traits::ReflectDefault};
use glam::{Affine3A, Vec3};

/// Which integrator advances the cloth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Reflect)]
#[reflect(Default, Clone, Debug, PartialEq)]
pub enum Integrator {
    /// Forward Euler, `x += h v; v += h a(x, v)`: the paper's method. Adds energy every
    /// step; kept to reproduce the paper and to show why not to use it.
    ExplicitEuler,
    /// Semi-implicit (symplectic) Euler, `v += h a(x, v); x += h v`: bounded energy for
    /// `ω h < 2`, one force evaluation per step.
    SymplecticEuler,
    /// Leapfrog / Störmer–Verlet: symplectic Euler on velocities staggered half a step,
    /// second-order positions for the same cost. Velocities used by damping and read by
    /// callers lag half a step.
    Verlet,
    /// Classical fourth-order Runge–Kutta: four force evaluations per step, accurate on
    /// smooth motion, stable a little beyond symplectic Euler (ω h ≤ 2.83), slowly damping.
    Rk4,
    /// Extended position-based dynamics (Macklin et al. 2016) with one constraint pass per
    /// substep ("small steps", Macklin et al. 2019): springs are compliant distance
    /// constraints (compliance 1/k) with Macklin's damping, solved Gauss–Seidel. Stable at any
    /// stiffness and step; first order, and numerically damped at large steps. The default:
    /// its cost per frame does not grow with resolution or stiffness (see the README's
    /// accuracy and performance tables).
    #[default]
    Xpbd,
}

impl Integrator {
    /// Every integrator, for sweeps and menus.
    pub const ALL: [Self; 5] = [
        Self::ExplicitEuler,
        Self::SymplecticEuler,
        Self::Verlet,
        Self::Rk4,
        Self::Xpbd,
    ];

    /// A short human-readable name.
    pub fn name(self) -> &'static str {
        match self {
            Self::ExplicitEuler => "explicit Euler",
            Self::SymplecticEuler => "symplectic Euler",
            Self::Verlet => "Verlet (leapfrog)",
            Self::Rk4 => "RK4",
            Self::Xpbd => "XPBD",
        }
    }

    /// True for methods stable at any stiffness and step (no substeps needed for stability).
    pub fn is_unconditionally_stable(self) -> bool {
        self == Self::Xpbd
    }

    /// The order of accuracy of positions on smooth problems.
    pub fn order(self) -> u32 {
        match self {
            Self::ExplicitEuler | Self::SymplecticEuler | Self::Xpbd => 1,
            Self::Verlet => 2,
            Self::Rk4 => 4,
        }
    }
}

/// Scratch memory an integrator keeps between steps; sized on first use, then reused.
#[derive(Clone, Debug, Default)]
pub struct IntegratorWorkspace {
    force: Vec<Vec3>,
    /// RK4 stage state and sums.
    stage_position: Vec<Vec3>,
    stage_velocity: Vec<Vec3>,
    sum_velocity: Vec<Vec3>,
    sum_acceleration: Vec<Vec3>,
    /// Step size the velocities are staggered for when they hold leapfrog half-step values.
    staggered_for: Option<f32>,
    /// The XPBD solver's state.
    pub(crate) xpbd: XpbdSolver,
}

impl IntegratorWorkspace {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.force.capacity()
            + self.stage_position.capacity()
            + self.stage_velocity.capacity()
            + self.sum_velocity.capacity()
            + self.sum_acceleration.capacity())
            * size_of::<Vec3>()
            + self.xpbd.heap_bytes()
    }
}

/// Leapfrog keeps velocities half a step behind positions. Entering it (or changing `h`)
/// shifts them by the difference of half-kicks; leaving it shifts them back.
fn shift_stagger(
    integrator: Integrator,
    particles: &mut Particles,
    springs: &Springs,
    params: &ForceParams,
    workspace: &mut IntegratorWorkspace,
    h: f32,
) {
    let wanted_stagger = (integrator == Integrator::Verlet).then_some(h);
    if workspace.staggered_for == wanted_stagger {
        return;
    }
    let shift = workspace.staggered_for.unwrap_or(0.0) - wanted_stagger.unwrap_or(0.0);
    workspace.staggered_for = wanted_stagger;
    let n = particles.len();
    workspace.force.resize(n, Vec3::ZERO);
    let Particles {
        position,
        velocity,
        mass,
        inv_mass,
        state,
        external_force,
        ..
    } = particles;
    let model = ForceModel {
        mass,
        state,
        external: external_force,
        springs,
        params,
    };
    model.eval(position, velocity, &mut workspace.force);
    for i in (0..n).filter(|&i| inv_mass[i] != 0.0 && !state[i].is_burnt()) {
        velocity[i] += 0.5 * shift * workspace.force[i] * inv_mass[i];
    }
}

/// Advances free, unburnt particles by one step of size `h` seconds.
///
/// External forces in `particles.external_force` act throughout the step; the caller clears
/// them (a cloth's step clears them after its last substep). XPBD runs through
/// [`XpbdSolver`] with one substep, no collider and no guard (a cloth's step calls the solver
/// itself for all its substeps at once).
pub fn integrate(
    integrator: Integrator,
    particles: &mut Particles,
    springs: &Springs,
    params: &ForceParams,
    workspace: &mut IntegratorWorkspace,
    h: f32,
) {
    shift_stagger(integrator, particles, springs, params, workspace, h);
    if integrator == Integrator::Xpbd {
        let around = Surroundings {
            params,
            colliders: &[],
            margin: 0.0,
            guard: GuardSettings {
                enabled: false,
                ..GuardSettings::default()
            },
            tethers: None,
            stretch_limit: None,
            pool: None,
        };
        workspace
            .xpbd
            .advance(particles, springs, None, &around, h, 1);
        return;
    }
    let n = particles.len();
    workspace.force.resize(n, Vec3::ZERO);
    let Particles {
        position,
        velocity,
        mass,
        inv_mass,
        state,
        external_force,
        ..
    } = particles;
    let model = ForceModel {
        mass,
        state,
        external: external_force,
        springs,
        params,
    };
    let force = &mut workspace.force;
    let moves = |i: usize| inv_mass[i] != 0.0 && !state[i].is_burnt();
    match integrator {
        Integrator::Rk4 => {
            let stages = Rk4Buffers {
                position: &mut workspace.stage_position,
                velocity: &mut workspace.stage_velocity,
                sum_velocity: &mut workspace.sum_velocity,
                sum_acceleration: &mut workspace.sum_acceleration,
                force,
            };
            rk4_step(&model, position, velocity, inv_mass, stages, h);
            return;
        }
        Integrator::Xpbd => unreachable!("handled above"),
        _ => {}
    }
    model.eval(position, velocity, force);
    match integrator {
        Integrator::Rk4 | Integrator::Xpbd => unreachable!("handled above"),
        Integrator::ExplicitEuler => {
            for i in (0..n).filter(|&i| moves(i)) {
                position[i] += h * velocity[i];
                velocity[i] += h * force[i] * inv_mass[i];
            }
        }
        Integrator::SymplecticEuler | Integrator::Verlet => {
            for i in (0..n).filter(|&i| moves(i)) {
                velocity[i] += h * force[i] * inv_mass[i];
                position[i] += h * velocity[i];
            }
        }
    }
}

/// RK4's scratch buffers, borrowed from the workspace.
struct Rk4Buffers<'a> {
    position: &'a mut Vec<Vec3>,
    velocity: &'a mut Vec<Vec3>,
    sum_velocity: &'a mut Vec<Vec3>,
    sum_acceleration: &'a mut Vec<Vec3>,
    force: &'a mut Vec<Vec3>,
}

/// One classical RK4 step on `x' = v, v' = F(x, v) / m`. Particles that do not move keep
/// their position and velocity in every stage.
fn rk4_step(
    model: &ForceModel,
    position: &mut [Vec3],
    velocity: &mut [Vec3],
    inv_mass: &[f32],
    buffers: Rk4Buffers,
    h: f32,
) {
    let n = position.len();
    let Rk4Buffers {
        position: stage_x,
        velocity: stage_v,
        sum_velocity,
        sum_acceleration,
        force,
    } = buffers;
    for buffer in [
        &mut *stage_x,
        &mut *stage_v,
        &mut *sum_velocity,
        &mut *sum_acceleration,
    ] {
        buffer.clear();
        buffer.resize(n, Vec3::ZERO);
    }
    let moves = |i: usize| inv_mass[i] != 0.0 && !model.state[i].is_burnt();
    stage_x.copy_from_slice(position);
    stage_v.copy_from_slice(velocity);
    // Stage weights of the classical tableau: k1 + 2 k2 + 2 k3 + k4, and the offsets
    // (h/2, h/2, h) at which the next stage is evaluated.
    for (weight, next_offset) in [(1.0, 0.5 * h), (2.0, 0.5 * h), (2.0, h), (1.0, 0.0)] {
        model.eval(stage_x, stage_v, force);
        for i in (0..n).filter(|&i| moves(i)) {
            let acceleration = force[i] * inv_mass[i];
            sum_velocity[i] += weight * stage_v[i];
            sum_acceleration[i] += weight * acceleration;
            let stage_velocity = stage_v[i];
            stage_x[i] = position[i] + next_offset * stage_velocity;
            stage_v[i] = velocity[i] + next_offset * acceleration;
        }
    }
    for i in (0..n).filter(|&i| moves(i)) {
        position[i] += h / 6.0 * sum_velocity[i];
        velocity[i] += h / 6.0 * sum_acceleration[i];
    }
}

/// Places the unburnt pinned particles among `pins` at `transform × anchor` and gives each
/// the velocity of that move over `dt` seconds, so pins follow a moving cloth entity.
pub fn drive_pins(particles: &mut Particles, pins: &[u32], transform: Affine3A, dt: f32) {
    for &i in pins {
        let i = i as usize;
        if particles.is_pinned(i) && !particles.state[i].is_burnt() {
            let target = transform.transform_point3(particles.anchor[i]);
            particles.velocity[i] = if dt > 0.0 {
                (target - particles.position[i]) / dt
            } else {
                Vec3::ZERO
            };
            particles.position[i] = target;
        }
    }
}

/// Largest step for which symplectic Euler and Verlet stay stable on this cloth, s.
///
/// Gershgorin's bound on the stiffness matrix gives `ω_max² ≤ max_i 2 Σ_j k_ij / m_i`, and
/// the methods are stable for `ω h < 2`, so `h < min_i sqrt(2 m_i / Σ_j k_ij)`.
/// Returns infinity for a cloth with no spring on a free particle.
pub fn stable_time_step(
    particles: &Particles,
    springs: &Springs,
    coefficients: &SpringCoefficients,
) -> f32 {
    let mut stiffness_sum = vec![0.0f32; particles.len()];
    for s in 0..springs.len() {
        let k = coefficients.stiffness[springs.kind[s] as usize];
        stiffness_sum[springs.a[s] as usize] += k;
        stiffness_sum[springs.b[s] as usize] += k;
    }
    (0..particles.len())
        .filter(|&i| !particles.is_pinned(i) && stiffness_sum[i] > 0.0)
        .map(|i| (2.0 * particles.mass[i] / stiffness_sum[i]).sqrt())
        .fold(f32::INFINITY, f32::min)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::sim::{BurnState, SpringKind};

    /// One free particle of mass 1 kg on a structural spring to a pinned particle, no gravity.
    fn oscillator(k: f32, x0: f32) -> (Particles, Springs, ForceParams) {
        spring_to_pin(SpringKind::Structural, k, x0)
    }

    /// One free particle of mass 1 kg, `x0` m past the rest length of a spring of `kind`
    /// (`k` N/m, rest 1 m, undamped) to a pinned particle at the origin, no gravity.
    pub(crate) fn spring_to_pin(
        kind: SpringKind,
        k: f32,
        x0: f32,
    ) -> (Particles, Springs, ForceParams) {
        let particles = Particles {
            position: vec![Vec3::ZERO, Vec3::new(1.0 + x0, 0.0, 0.0)],
            velocity: vec![Vec3::ZERO; 2],
            mass: vec![1.0, 1.0],
            inv_mass: vec![0.0, 1.0],
            temperature: vec![20.0; 2],
            state: vec![BurnState::Intact; 2],
            burning_for: vec![0.0; 2],
            anchor: vec![Vec3::ZERO, Vec3::X],
            external_force: vec![Vec3::ZERO; 2],
        };
        let mut springs = Springs::default();
        springs.push(0, 1, 1.0, kind);
        let params = ForceParams {
            gravity: Vec3::ZERO,
            coefficients: SpringCoefficients {
                stiffness: [k; 3],
                damping: [0.0; 3],
                ..SpringCoefficients::default()
            },
            ..Default::default()
        };
        (particles, springs, params)
    }

    fn energy(particles: &Particles, k: f32) -> f32 {
        let x = particles.position[1].x - 1.0;
        0.5 * particles.velocity[1].length_squared() + 0.5 * k * x * x
    }

    /// Steps `particles` on the oscillator's spring `steps` times, calling `observe` with the
    /// step number (from 1) and the particles after each step.
    fn step_oscillator(
        integrator: Integrator,
        particles: &mut Particles,
        springs: &Springs,
        params: &ForceParams,
        h: f32,
        steps: usize,
        mut observe: impl FnMut(usize, &Particles),
    ) {
        let mut workspace = IntegratorWorkspace::default();
        for step in 1..=steps {
            integrate(integrator, particles, springs, params, &mut workspace, h);
            observe(step, particles);
        }
    }

    fn run(integrator: Integrator, steps: usize, h: f32) -> (f32, f32, Particles) {
        let k = 100.0;
        let (mut particles, springs, params) = oscillator(k, 0.1);
        let e0 = energy(&particles, k);
        let mut max_ratio: f32 = 1.0;
        step_oscillator(
            integrator,
            &mut particles,
            &springs,
            &params,
            h,
            steps,
            |_, p| {
                max_ratio = max_ratio.max(energy(p, k) / e0);
            },
        );
        (max_ratio, energy(&particles, k) / e0, particles)
    }

    #[test]
    fn symplectic_euler_keeps_a_lone_springs_energy_bounded_where_explicit_euler_grows() {
        // ω = 10 rad/s, h = 0.005 s: ω h = 0.05, far inside the symplectic limit of 2.
        let (symplectic_max, _, _) = run(Integrator::SymplecticEuler, 10_000, 0.005);
        let (explicit_max, explicit_final, _) = run(Integrator::ExplicitEuler, 10_000, 0.005);
        // Symplectic Euler's energy oscillates within O(ω h) of the start.
        assert!(
            symplectic_max < 1.06,
            "symplectic max ratio {symplectic_max}"
        );
        // Explicit Euler multiplies energy by (1 + ω²h²) per step: (1.0025)^10000 ≈ 7e10.
        assert!(
            explicit_final > 1.0e6,
            "explicit final ratio {explicit_final}"
        );
        assert!(explicit_max > symplectic_max);
    }

    #[test]
    fn verlet_tracks_the_exact_cosine_closely() {
        let h = 0.01;
        let steps = 100; // t = 1 s
        let (_, _, particles) = run(Integrator::Verlet, steps, h);
        let exact = 0.1 * (10.0f32 * 1.0).cos();
        let error = (particles.position[1].x - 1.0 - exact).abs();
        let (_, _, euler) = run(Integrator::SymplecticEuler, steps, h);
        let euler_error = (euler.position[1].x - 1.0 - exact).abs();
        assert!(error < 1e-3, "verlet error {error}");
        assert!(
            error < euler_error / 5.0,
            "verlet {error} vs euler {euler_error}"
        );
    }

    /// Largest error over t in [0, 1 s] of a 1 kg particle on a 100 N/m spring (ω = 10)
    /// released from 0.1 m, against the exact cosine. Positions sit near 0 so f32 resolves
    /// them finely. The maximum over the run is the global error norm: at a single instant,
    /// phase and amplitude errors of different orders can cancel.
    fn spring_error(integrator: Integrator, h: f32) -> f32 {
        let k = 100.0;
        let (mut particles, springs, params) = oscillator(k, 0.1);
        for p in &mut particles.position {
            p.x -= 1.0;
        }
        let steps = (1.0 / h).round() as usize;
        let mut worst: f32 = 0.0;
        step_oscillator(
            integrator,
            &mut particles,
            &springs,
            &params,
            h,
            steps,
            |step, p| {
                let exact = 0.1 * (10.0 * step as f32 * h).cos();
                worst = worst.max((p.position[1].x - exact).abs());
            },
        );
        worst
    }

    #[test]
    fn each_integrator_converges_at_its_theoretical_order_on_a_spring() {
        for integrator in Integrator::ALL {
            // Steps in the asymptotic range and above f32's resolution for each order.
            let steps: &[f32] = if integrator == Integrator::Rk4 {
                &[1.0 / 20.0, 1.0 / 40.0, 1.0 / 80.0]
            } else {
                &[1.0 / 200.0, 1.0 / 400.0, 1.0 / 800.0, 1.0 / 1600.0]
            };
            let errors: Vec<f32> = steps.iter().map(|&h| spring_error(integrator, h)).collect();
            let orders: Vec<f32> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
            let observed = orders.iter().sum::<f32>() / orders.len() as f32;
            let expected = integrator.order() as f32;
            assert!(
                (observed - expected).abs() <= 0.3,
                "{}: observed order {observed:.2} (errors {errors:?}), expected {expected}",
                integrator.name()
            );
        }
    }

    #[test]
    fn xpbd_stays_stable_far_beyond_the_explicit_limit() {
        // ω h = 1000 × 0.01 = 10, five times the symplectic limit of 2: explicit methods
        // blow up; XPBD's compliant constraint holds the spring near rest.
        let k = 1.0e6;
        let (mut particles, springs, params) = oscillator(k, 0.1);
        let mut workspace = IntegratorWorkspace::default();
        let h = 0.01;
        for _ in 0..1000 {
            integrate(
                Integrator::Xpbd,
                &mut particles,
                &springs,
                &params,
                &mut workspace,
                h,
            );
        }
        assert!(particles.is_finite());
        assert!(
            (particles.position[1].x - 1.0).abs() < 0.1,
            "{:?}",
            particles.position[1]
        );
        let (mut explicit, _, _) = oscillator(k, 0.1);
        let mut workspace = IntegratorWorkspace::default();
        for _ in 0..100 {
            integrate(
                Integrator::SymplecticEuler,
                &mut explicit,
                &springs,
                &params,
                &mut workspace,
                h,
            );
        }
        assert!(!explicit.is_finite() || explicit.position[1].x.abs() > 1.0e3);
    }

    #[test]
    fn pinned_and_burnt_particles_do_not_move() {
        let (mut particles, springs, mut params) = oscillator(100.0, 0.5);
        params.gravity = Vec3::new(0.0, -9.81, 0.0);
        particles.state[1] = BurnState::Burnt;
        let before = particles.position.clone();
        let mut workspace = IntegratorWorkspace::default();
        for integrator in Integrator::ALL {
            integrate(
                integrator,
                &mut particles,
                &springs,
                &params,
                &mut workspace,
                0.01,
            );
        }
        assert_eq!(particles.position, before);
    }

    #[test]
    fn pins_follow_the_transform() {
        let (mut particles, _, _) = oscillator(1.0, 0.0);
        let transform = Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0));
        drive_pins(&mut particles, &[0, 1], transform, 0.5);
        assert_eq!(particles.position[0], Vec3::new(0.0, 2.0, 0.0));
        assert_eq!(particles.velocity[0], Vec3::new(0.0, 4.0, 0.0));
        // The free particle is not a pin.
        assert_eq!(particles.position[1], Vec3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn stable_step_matches_the_single_spring_limit() {
        // One free 1 kg particle, one 100 N/m spring to a pin: ω = 10, limit h = 2/ω = 0.2.
        // The Gershgorin bound counts the spring twice on that row: h = sqrt(2/100) ≈ 0.141.
        let (particles, springs, params) = oscillator(100.0, 0.0);
        let h = stable_time_step(&particles, &springs, &params.coefficients);
        assert!((h - (2.0f32 / 100.0).sqrt()).abs() < 1e-6);
        assert!(h <= 0.2);
    }
}
