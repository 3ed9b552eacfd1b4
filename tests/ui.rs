//! The control panel's apply path, driven without widgets: every edit is clamped to the
//! sliders' ranges and validated, and no edit, however extreme, makes the cloth non-finite.
#![cfg(feature = "egui")]

use bevy::math::{Affine3A, Vec3};
use bevy_burning_cloth::sim::{
    BurnMaterial, ClothBuilder, ClothSettings, ClothSim, HeatModel, Integrator, PhysicalHeat,
    ProvotSettings,
};
use bevy_burning_cloth::ui::params::SUBSTEP_RATE;
use bevy_burning_cloth::ui::{MATERIAL_FIELDS, PanelValues};

const EXTREMES: [f32; 10] = [
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::MAX,
    -f32::MAX,
    0.0,
    -1.0,
    1e-30,
    1e30,
    f32::MIN_POSITIVE,
];

#[test]
fn extreme_panel_edits_mid_burn_are_clamped_or_refused_and_the_cloth_stays_finite() {
    let mut sim = ClothSim::new(
        &ClothBuilder::grid(12, 12, 0.04).pin_top_corners(),
        BurnMaterial::COTTON,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )
    .unwrap();
    sim.ignite(70).unwrap();
    for _ in 0..30 {
        sim.step(1.0 / 60.0);
    }
    let mut in_use = PanelValues {
        material: *sim.material(),
        solver: *sim.solver(),
        environment: *sim.environment(),
    };
    let (mut applied, mut refused) = (0, 0);
    for round in 0..80 {
        let x = EXTREMES[round % EXTREMES.len()];
        let mut edit = in_use;
        for (j, field) in MATERIAL_FIELDS.iter().enumerate() {
            if (round + j) % 3 == 0 {
                *(field.field)(&mut edit.material) = x;
            }
        }
        edit.environment.wind = Vec3::splat(x);
        edit.environment.gravity.y = if round % 2 == 0 { x } else { -x };
        edit.solver.integrator = Integrator::ALL[round % Integrator::ALL.len()];
        edit.solver.substeps = [None, Some(0), Some(u32::MAX), Some(3)][round % 4];
        edit.solver.substep_rate = x;
        edit.solver.provot = (round % 5 != 0).then(|| ProvotSettings {
            max_stretch: x,
            passes: [0, 1, u32::MAX][round % 3],
            ..ProvotSettings::default()
        });
        edit.solver.heat_model = if round % 2 == 0 {
            HeatModel::Physical(PhysicalHeat::from_array([x; 4]))
        } else {
            HeatModel::Paper
        };
        match edit.apply(&in_use) {
            Ok(values) => {
                // Whatever was asked, what is applied lies in the panel's ranges.
                for field in &MATERIAL_FIELDS {
                    let mut material = values.material;
                    let v = *(field.field)(&mut material);
                    assert!(field.range.contains(&v), "{} = {v}", field.label);
                }
                assert!(values.environment.wind.is_finite());
                assert!(
                    SUBSTEP_RATE.contains(&values.solver.substep_rate),
                    "substep rate {}",
                    values.solver.substep_rate
                );
                in_use = values;
                applied += 1;
            }
            Err(_) => refused += 1,
        }
        sim.set_settings(ClothSettings {
            material: in_use.material,
            solver: in_use.solver,
            environment: in_use.environment,
        })
        .expect("what the panel applies is valid");
        for _ in 0..5 {
            sim.step(1.0 / 60.0);
        }
        assert!(sim.particles.is_finite(), "round {round}: {in_use:?}");
        assert!(sim.particles.temperature.iter().all(|t| t.is_finite()));
    }
    assert!(
        applied > 40,
        "only {applied} of 80 edits applied ({refused} refused)"
    );
}

/// What the panel shows for `material` with the default solver and environment.
fn defaults_with(material: BurnMaterial) -> PanelValues {
    PanelValues {
        material,
        solver: Default::default(),
        environment: Default::default(),
    }
}

#[test]
fn an_edit_elsewhere_keeps_provots_limit() {
    // Provot's limit is a relative stretch (0.1 = 10 %). The panel's range once read it as a
    // multiple of the rest length (1.01 to 2), so any edit at all clamped the default 0.1 up
    // to 1.01: springs were then let stretch to twice their length.
    let in_use = defaults_with(BurnMaterial::COTTON);
    let mut edit = in_use;
    edit.environment.wind = Vec3::new(1.0, 0.0, 0.0);
    let values = edit.apply(&in_use).unwrap();
    let limit = |v: &PanelValues| v.solver.provot.map(|p| p.max_stretch);
    assert_eq!(limit(&values), limit(&in_use));
    assert_eq!(limit(&values), Some(0.1));
}

#[test]
fn a_nan_edit_keeps_the_value_in_use() {
    let in_use = defaults_with(BurnMaterial::SILK);
    let mut edit = in_use;
    edit.material.structural_stiffness = f32::NAN;
    edit.material.areal_density = 1e9;
    edit.solver.substep_rate = f32::NAN;
    let values = edit.apply(&in_use).unwrap();
    assert_eq!(
        values.material.structural_stiffness,
        BurnMaterial::SILK.structural_stiffness
    );
    assert_eq!(values.material.areal_density, 2.0);
    assert_eq!(values.solver.substep_rate, in_use.solver.substep_rate);
}
