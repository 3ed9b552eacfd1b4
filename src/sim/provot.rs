//! Provot's (1995) correction: no structural or shear spring may stretch beyond
//! `(1 + τ)` times its rest length.
//!
//! After each integration step, each over-stretched spring moves its ends toward each other
//! by the excess, split by inverse mass (half each for equal masses, all of it to the free end
//! when the other is pinned, none when both are pinned). This is position-based dynamics with
//! the inequality constraint `|x_ab| - (1 + τ) L ≤ 0`, run as Gauss–Seidel passes.

use super::particles::Particles;
use super::springs::Springs;
use bevy::reflect::Reflect;
use glam::Vec3;

/// Relative excess below which a spring counts as within the limit (round-off).
pub const STRETCH_TOLERANCE: f32 = 1e-5;

/// Settings of Provot's correction.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub struct ProvotSettings {
    /// Largest allowed relative stretch τ (0.1 = 10 %, Provot's value).
    pub max_stretch: f32,
    /// Gauss–Seidel passes per step; passes stop early once no spring exceeds the limit.
    pub passes: u32,
    /// Also change velocities by the correction over the step (`v += Δx / h`), so the
    /// removed stretch does not come back as speed.
    pub correct_velocities: bool,
}

impl Default for ProvotSettings {
    fn default() -> Self {
        Self {
            max_stretch: 0.1,
            passes: 4,
            correct_velocities: true,
        }
    }
}

/// What a correction did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ProvotReport {
    /// Passes run.
    pub passes: u32,
    /// Springs corrected in the last pass run (0 means the limit holds everywhere).
    pub corrected_in_last_pass: u32,
}

/// Scratch memory for the velocity correction.
#[derive(Clone, Debug, Default)]
pub struct ProvotWorkspace {
    before: Vec<Vec3>,
}

impl ProvotWorkspace {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        self.before.capacity() * size_of::<Vec3>()
    }
}

/// Applies Provot's correction to structural and shear springs with both ends unburnt.
/// `h` is the step just taken (s), used for the velocity correction.
pub fn provot_correct(
    particles: &mut Particles,
    springs: &Springs,
    settings: &ProvotSettings,
    workspace: &mut ProvotWorkspace,
    h: f32,
) -> ProvotReport {
    let limit_factor = 1.0 + settings.max_stretch.max(0.0);
    if settings.correct_velocities {
        workspace.before.clear();
        workspace.before.extend_from_slice(&particles.position);
    }
    let mut report = ProvotReport::default();
    for _ in 0..settings.passes {
        report.passes += 1;
        report.corrected_in_last_pass = 0;
        for s in 0..springs.len() {
            if !springs.kind[s].is_in_plane() {
                continue;
            }
            let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
            if particles.state[a].is_burnt() || particles.state[b].is_burnt() {
                continue;
            }
            let (w_a, w_b) = (particles.inv_mass[a], particles.inv_mass[b]);
            let w_sum = w_a + w_b;
            if w_sum <= 0.0 {
                continue;
            }
            let delta = particles.position[b] - particles.position[a];
            let length = delta.length();
            let limit = limit_factor * springs.rest_length[s];
            // A relative tolerance keeps round-off from counting as a violation forever.
            if length <= limit * (1.0 + STRETCH_TOLERANCE) || length <= 1e-9 {
                continue;
            }
            let correction = delta * ((length - limit) / (length * w_sum));
            particles.position[a] += correction * w_a;
            particles.position[b] -= correction * w_b;
            report.corrected_in_last_pass += 1;
        }
        if report.corrected_in_last_pass == 0 {
            break;
        }
    }
    if settings.correct_velocities && h > 0.0 {
        for (i, before) in workspace.before.iter().enumerate() {
            particles.velocity[i] += (particles.position[i] - *before) / h;
        }
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{BurnState, SpringKind};

    fn chain(positions: &[Vec3], inv_mass: &[f32]) -> (Particles, Springs) {
        let n = positions.len();
        let particles = Particles {
            position: positions.to_vec(),
            velocity: vec![Vec3::ZERO; n],
            mass: vec![1.0; n],
            inv_mass: inv_mass.to_vec(),
            temperature: vec![20.0; n],
            state: vec![BurnState::Intact; n],
            burning_for: vec![0.0; n],
            anchor: positions.to_vec(),
            external_force: vec![Vec3::ZERO; n],
        };
        let mut springs = Springs::default();
        for i in 0..n - 1 {
            springs.push(i as u32, i as u32 + 1, 1.0, SpringKind::Structural);
        }
        (particles, springs)
    }

    #[test]
    fn equal_masses_each_move_half_the_excess() {
        let (mut particles, springs) = chain(&[Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)], &[1.0, 1.0]);
        let settings = ProvotSettings {
            max_stretch: 0.1,
            passes: 1,
            correct_velocities: false,
        };
        provot_correct(
            &mut particles,
            &springs,
            &settings,
            &mut ProvotWorkspace::default(),
            0.01,
        );
        // Excess 2.0 - 1.1 = 0.9: each end moves 0.45.
        assert!((particles.position[0].x - 0.45).abs() < 1e-6);
        assert!((particles.position[1].x - 1.55).abs() < 1e-6);
    }

    #[test]
    fn a_pinned_end_never_moves_and_the_free_end_takes_all() {
        let (mut particles, springs) = chain(&[Vec3::ZERO, Vec3::new(0.0, -3.0, 0.0)], &[0.0, 1.0]);
        provot_correct(
            &mut particles,
            &springs,
            &ProvotSettings::default(),
            &mut ProvotWorkspace::default(),
            0.01,
        );
        assert_eq!(particles.position[0], Vec3::ZERO);
        assert!((particles.position[1].y + 1.1).abs() < 1e-6);
        // The velocity correction equals the move over the step.
        assert!((particles.velocity[1].y - 1.9 / 0.01).abs() < 1e-2);
    }

    #[test]
    fn enough_passes_leave_no_spring_above_the_limit() {
        // A chain of 20 particles hanging from a pin, every link stretched to 1.8.
        let positions: Vec<Vec3> = (0..20)
            .map(|i| Vec3::new(0.0, -1.8 * i as f32, 0.0))
            .collect();
        let mut inv_mass = vec![1.0; 20];
        inv_mass[0] = 0.0;
        let (mut particles, springs) = chain(&positions, &inv_mass);
        let settings = ProvotSettings {
            max_stretch: 0.1,
            passes: 2_000,
            correct_velocities: false,
        };
        let report = provot_correct(
            &mut particles,
            &springs,
            &settings,
            &mut ProvotWorkspace::default(),
            0.01,
        );
        assert_eq!(report.corrected_in_last_pass, 0, "{report:?}");
        let stretch = springs.max_stretch(&particles.position, &particles.state, |_| true);
        assert!(
            stretch <= 1.1 * (1.0 + STRETCH_TOLERANCE),
            "max stretch {stretch}"
        );
        assert!(report.passes < 2_000, "converged early: {report:?}");
        assert_eq!(particles.position[0], Vec3::ZERO);
    }

    #[test]
    fn bending_springs_and_burnt_ends_are_left_alone() {
        let (mut particles, mut springs) = chain(
            &[Vec3::ZERO, Vec3::X * 5.0, Vec3::X * 10.0],
            &[1.0, 1.0, 1.0],
        );
        springs.kind[0] = SpringKind::Bend;
        particles.state[2] = BurnState::Burnt;
        let before = particles.position.clone();
        provot_correct(
            &mut particles,
            &springs,
            &ProvotSettings::default(),
            &mut ProvotWorkspace::default(),
            0.01,
        );
        assert_eq!(particles.position, before);
    }
}
