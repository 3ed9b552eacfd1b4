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
        // At 1/480 s and finer every method is inside its stability limit on every problem.
        assert!(!sample.blew_up && sample.error.is_finite(), "{sample:?}");
    }
    let error = |problem: Problem, method: Integrator, parameter: f32| {
        samples
            .iter()
            .find(|s| s.problem == problem && s.method == method.name() && s.parameter == parameter)
            .unwrap_or_else(|| panic!("no sample for {problem:?} {method:?} {parameter}"))
            .error
    };
    let [coarse, fine] = [sweep.steps[0], sweep.steps[1]];
    // Symplectic Euler falling from rest for 1 s lands `g h T / 2` from the exact parabola.
    for h in [coarse, fine] {
        let analytic = 9.81 * f64::from(h) * 1.0 / 2.0;
        let measured = error(Problem::FreeFall, Integrator::SymplecticEuler, h);
        assert!(
            (measured / analytic - 1.0).abs() < 0.02,
            "free fall at h = {h}: {measured} m, analytic {analytic} m"
        );
    }
    // It is first order: halving the step halves the error.
    for problem in [Problem::Spring, Problem::FreeFall] {
        let ratio = error(problem, Integrator::SymplecticEuler, coarse)
            / error(problem, Integrator::SymplecticEuler, fine);
        assert!(
            (1.8..2.2).contains(&ratio),
            "{problem:?}: error ratio {ratio} for half the step"
        );
    }
    // The heat equation's discretisation is second order in space: half the spacing, at
    // least a quarter of the error.
    let heat = |spacing: f32| {
        samples
            .iter()
            .find(|s| s.problem == Problem::HeatDiffusion && s.parameter == spacing)
            .expect("a heat sample")
            .error
    };
    let [wide, narrow] = [sweep.heat_spacings[0], sweep.heat_spacings[1]];
    assert!(
        heat(narrow) <= heat(wide) / 4.0,
        "heat error {} at {wide} m, {} at {narrow} m",
        heat(wide),
        heat(narrow)
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

/// A spring shorter than its rest length pushes with its compression fraction of its
/// stiffness, under XPBD and symplectic Euler alike: a 2 x 2 cloth pinned along its top, with
/// gravity pointing up (so the weight of each bottom particle pushes it towards its pin),
/// settles with its two upright springs `m g / (r k)` short of their rest length, `r` the
/// fraction (the bottom spring keeps its length by symmetry; the shear springs are made too
/// soft to matter). At 1 % of cotton's 30 N/m a spring gives a hundred times as far to a push
/// as to a pull.
#[test]
fn a_compressed_spring_settles_where_its_softer_stiffness_carries_the_weight() {
    use bevy::math::{Affine3A, Vec3};
    use bevy_burning_cloth::sim::{BurnMaterial, ClothBuilder, ClothSim};
    let spacing = 0.05;
    let builder = ClothBuilder::grid(2, 2, spacing).pin_top_edge();
    for fraction in [0.01f32, 0.1, 1.0] {
        let material = BurnMaterial {
            structural_compression_fraction: fraction,
            shear_stiffness: 1e-6,
            ..BurnMaterial::COTTON
        };
        for integrator in [Integrator::Xpbd, Integrator::SymplecticEuler] {
            let mut sim = ClothSim::new(&builder, material, Affine3A::IDENTITY).unwrap();
            sim.update_settings(|s| {
                s.solver.integrator = integrator;
                s.environment.gravity = Vec3::new(0.0, 9.81, 0.0);
            })
            .unwrap();
            // Little air drag: XPBD's implicit drag also slows the substep's gravity increment,
            // so a cloth at rest carries `1 / (1 + h × drag per mass)` of its weight (0.9 %
            // with cotton's drag at 360 substeps a second; 0.09 % with this).
            sim.set_material(BurnMaterial {
                air_drag: 0.05,
                ..material
            })
            .unwrap();
            for _ in 0..600 {
                sim.step(1.0 / 60.0);
            }
            for (top, bottom) in [(0, 2), (1, 3)] {
                let mass = sim.particles.mass[bottom];
                let expected = mass * 9.81 / (fraction * material.structural_stiffness);
                let p = &sim.particles.position;
                let shortened = spacing - p[top].distance(p[bottom]);
                assert!(
                    (shortened / expected - 1.0).abs() < 0.01,
                    "{integrator:?}, fraction {fraction}: {shortened} m short, expected {expected} m"
                );
            }
        }
    }
}
