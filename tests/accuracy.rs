//! The accuracy report runs end to end on a tiny sweep and writes its tables.

use bevy_burning_cloth::report::accuracy::{self, Problem, Sweep};
use bevy_burning_cloth::sim::Integrator;

#[test]
fn a_tiny_sweep_writes_a_non_empty_csv_and_table() {
    let sweep = Sweep::tiny();
    let samples = accuracy::run(&sweep);
    // Every problem, every method, every step (heat: every spacing).
    let cloth_rows = 4 * sweep.integrators.len() * sweep.steps.len();
    assert_eq!(samples.len(), cloth_rows + sweep.heat_spacings.len());
    for sample in &samples {
        assert!(sample.cost > 0.0, "{sample:?}");
        assert!(sample.blew_up || sample.error.is_finite(), "{sample:?}");
    }
    // At 1/480 s symplectic Euler is inside its stability limit on every problem.
    assert!(
        samples
            .iter()
            .filter(|s| s.method == Integrator::SymplecticEuler.name())
            .all(|s| !s.blew_up)
    );
    let stable = [(
        Integrator::Xpbd,
        accuracy::largest_stable_step(5, Integrator::Xpbd),
    )];
    let dir = std::env::temp_dir().join(format!("bbc-accuracy-{}", std::process::id()));
    let [csv, md] = accuracy::write_tables(&dir, &samples, &stable).unwrap();
    let csv = std::fs::read_to_string(csv).unwrap();
    assert_eq!(csv.lines().count(), samples.len() + 1);
    assert!(csv.lines().any(|l| l.starts_with("heat_diffusion,")));
    let md = std::fs::read_to_string(md).unwrap();
    for problem in Problem::ALL {
        assert!(
            md.contains(&problem.name().replace('_', " ")),
            "{problem:?} missing"
        );
    }
    std::fs::remove_dir_all(dir).ok();
}

/// XPBD holds a cloth 100× stiffer than the explicit step allows: at a 1/60 s step with
/// one substep, (ω h)² is 100 times the symplectic limit of 4.
#[test]
fn xpbd_stays_finite_on_a_cloth_100x_stiffer_than_the_explicit_limit() {
    use bevy::math::{Affine3A, Vec3};
    use bevy_burning_cloth::sim::{BurnMaterial, ClothBuilder, ClothSim, GuardSettings};
    let builder = ClothBuilder::grid(10, 10, 0.05).pin_top_corners();
    let h = 1.0 / 60.0f32;
    let probe = ClothSim::new(&builder, BurnMaterial::CLOTH, Affine3A::IDENTITY).unwrap();
    let mass = probe.topology.particle_mass;
    // Stiffness whose ω = sqrt(k / (m/2)) gives (ω h)² = 100 × 4, ignoring the Gershgorin
    // factor for several springs per particle (which only makes it stiffer still).
    let k = 400.0 / (h * h) * mass / 2.0;
    let material = BurnMaterial {
        structural_stiffness: k,
        shear_stiffness: k,
        bend_stiffness: k,
        ..BurnMaterial::CLOTH
    };
    for integrator in [Integrator::Xpbd, Integrator::SymplecticEuler] {
        let mut sim = ClothSim::new(&builder, material, Affine3A::IDENTITY).unwrap();
        sim.update_settings(|s| {
            s.solver.integrator = integrator;
            s.solver.substeps = Some(1);
            s.solver.provot = None;
            s.solver.guard = GuardSettings {
                enabled: false,
                ..GuardSettings::default()
            };
        })
        .unwrap();
        for v in &mut sim.particles.velocity {
            *v = Vec3::new(0.0, 0.0, 0.5);
        }
        let mut finite = true;
        for _ in 0..600 {
            sim.step(h);
            finite &= sim.particles.is_finite()
                && sim.particles.position.iter().all(|p| p.length() < 100.0);
        }
        match integrator {
            Integrator::Xpbd => assert!(finite, "XPBD blew up"),
            _ => assert!(
                !finite,
                "symplectic Euler should blow up here (test too soft)"
            ),
        }
    }
}
