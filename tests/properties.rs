//! Property tests: random valid and invalid parameters and ignition points never panic and
//! never leave a non-finite value after stepping with the default integrator.

use bevy::math::{Affine3A, Vec3};
use bevy_burning_cloth::sim::{BurnMaterial, ClothBuilder, ClothSim};
use proptest::prelude::*;

/// Any f32 at all, weighted toward the troublesome ones.
fn any_float() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -1.0e3f32..1.0e3,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(0.0f32),
        1 => Just(-0.0f32),
        1 => prop::num::f32::ANY,
    ]
}

fn material() -> impl Strategy<Value = BurnMaterial> {
    (
        0usize..5,
        prop::collection::vec(any_float(), 6),
        prop::collection::vec(prop::bool::weighted(0.15), 6),
    )
        .prop_map(|(preset, values, replace)| {
            let mut m = BurnMaterial::PRESETS[preset];
            let fields: [&mut f32; 6] = [
                &mut m.areal_density,
                &mut m.structural_stiffness,
                &mut m.bend_stiffness,
                &mut m.ignition_temperature,
                &mut m.heat_spread_rate,
                &mut m.shrink_factor,
            ];
            for ((field, value), replace) in fields.into_iter().zip(values).zip(replace) {
                if replace {
                    *field = value;
                }
            }
            m
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_cloths_and_ignitions_stay_finite(
        columns in prop_oneof![9 => 2u32..12, 1 => 0u32..2],
        rows in prop_oneof![9 => 2u32..12, 1 => 0u32..2],
        spacing in prop_oneof![8 => 0.005f32..0.5, 1 => any_float()],
        material in material(),
        ignite_index in 0usize..200,
        ignite_point in (any_float(), any_float(), any_float()),
        temperature in any_float(),
    ) {
        let builder = ClothBuilder::grid(columns, rows, spacing).pin_top_corners();
        let Ok(mut sim) = ClothSim::new(&builder, material, Affine3A::IDENTITY) else {
            // Refused with an error: that is the contract for invalid input.
            return Ok(());
        };
        let _ = sim.ignite(ignite_index);
        let _ = sim.ignite_nearest(Vec3::new(ignite_point.0, ignite_point.1, ignite_point.2));
        let _ = bevy_burning_cloth::sim::ignition::heat_particle(&mut sim.particles, 0, temperature);
        for _ in 0..90 {
            sim.step(1.0 / 60.0);
        }
        prop_assert!(sim.particles.is_finite());
        for &l in &sim.springs.rest_length {
            prop_assert!(l.is_finite() && l >= 0.0);
        }
    }

    #[test]
    fn invalid_materials_are_refused_with_a_named_field(material in material()) {
        match material.validate() {
            Ok(()) => {
                prop_assert!(material.areal_density.is_finite() && material.areal_density > 0.0);
                prop_assert!(material.ignition_temperature < material.burnt_temperature);
            }
            Err(error) => prop_assert!(!error.field.is_empty()),
        }
    }
}
