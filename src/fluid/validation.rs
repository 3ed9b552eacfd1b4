//! The plume against known answers: incompressibility after projection, buoyancy's sign,
//! advection by a uniform wind, conservation in a sealed box, walls and determinism.

use super::grid::Stagger;
use super::plume::Plume;
use super::pressure::Walls;
use super::settings::PlumeSettings;
use glam::Vec3;

const DT: f32 = 1.0 / 60.0;

/// Still air with no forces of its own: what is put in only moves.
fn passive() -> PlumeSettings {
    PlumeSettings {
        resolution: [24, 24, 24],
        cell_size: 0.1,
        buoyancy: 0.0,
        vorticity: 0.0,
        damping: 0.0,
        cooling: 0.0,
        smoke_decay: 0.0,
        ..Default::default()
    }
}

/// A Gaussian blob of `amount` per cell at its centre around `centre` (m), radius `radius`.
fn blob(plume: &Plume, centre: Vec3, radius: f32, amount: f32) -> Vec<f32> {
    let shape = *plume.shape();
    let mut field = vec![0.0; shape.cells()];
    for k in 0..shape.dims[2] {
        for j in 0..shape.dims[1] {
            for i in 0..shape.dims[0] {
                let p = shape.position(i, j, k, Stagger::CENTRE);
                let d2 = p.distance_squared(centre) / (radius * radius);
                field[shape.index(i, j, k)] = amount * (-d2).exp();
            }
        }
    }
    field
}

/// The field-weighted centre of a cell field, m.
fn centroid(plume: &Plume, field: &[f32]) -> Vec3 {
    let shape = *plume.shape();
    let mut sum = Vec3::ZERO;
    let mut weight = 0.0;
    for k in 0..shape.dims[2] {
        for j in 0..shape.dims[1] {
            for i in 0..shape.dims[0] {
                let w = field[shape.index(i, j, k)].abs();
                sum += shape.position(i, j, k, Stagger::CENTRE) * w;
                weight += w;
            }
        }
    }
    sum / weight
}

/// The default plume `steps` frames after a hot blob (`[radius, excess]`, m and K) was put
/// at `centre` (m) in still air.
fn rising(centre: Vec3, [radius, excess]: [f32; 2], steps: usize) -> Plume {
    let mut plume = Plume::new(PlumeSettings::default(), Vec3::ZERO).unwrap();
    let hot = blob(&plume, centre, radius, excess);
    plume.temperature_mut().copy_from_slice(&hot);
    for _ in 0..steps {
        plume.step(DT, Vec3::ZERO, Vec3::Y);
    }
    plume
}

/// A pseudo-random number in [−1, 1] from an index.
fn noise(i: usize) -> f32 {
    let x = (i as u64)
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((x >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
}

#[test]
fn projection_leaves_the_velocity_divergence_free_to_the_stated_tolerance() {
    for walls in [Walls::OPEN, {
        let mut w = Walls::OPEN;
        w.0[1][0] = super::Wall::Closed;
        w
    }] {
        let settings = PlumeSettings { walls, ..passive() };
        let mut plume = Plume::new(settings, Vec3::ZERO).unwrap();
        for (axis, faces) in plume.velocity_mut().iter_mut().enumerate() {
            for (f, u) in faces.iter_mut().enumerate() {
                *u = noise(f * 3 + axis);
            }
        }
        let before = plume.max_divergence();
        assert!(before > 100.0 * settings.tolerance, "{before}");
        let report = plume.step(DT, Vec3::ZERO, Vec3::Y);
        assert!(
            report.max_divergence <= settings.tolerance,
            "max |div u| = {} 1/s after projection, tolerance {} ({:?})",
            report.max_divergence,
            settings.tolerance,
            report.solve
        );
    }
}

#[test]
fn a_hot_blob_rises_and_a_cold_blob_sinks() {
    for (excess, sign) in [(300.0, 1.0), (-150.0, -1.0)] {
        let settings = PlumeSettings {
            buoyancy: PlumeSettings::default().buoyancy,
            ..passive()
        };
        let mut plume = Plume::new(settings, Vec3::ZERO).unwrap();
        let centre = Vec3::splat(1.2);
        let hot = blob(&plume, centre, 0.2, excess);
        plume.temperature_mut().copy_from_slice(&hot);
        let start = centroid(&plume, plume.temperature());
        for _ in 0..30 {
            plume.step(DT, Vec3::ZERO, Vec3::Y);
        }
        let moved = centroid(&plume, plume.temperature()) - start;
        let velocity = plume.velocity_at(centre);
        assert!(
            sign * moved.y > 0.5 * plume.shape().cell,
            "ΔT {excess} K: the blob moved {moved} in 0.5 s"
        );
        assert!(sign * velocity.y > 0.1, "velocity at the blob {velocity}");
        // It moves along up only (symmetric blob, symmetric box).
        assert!(moved.x.abs() < 0.1 * moved.y.abs() && moved.z.abs() < 0.1 * moved.y.abs());
    }
}

#[test]
fn a_smoke_blob_moves_with_a_uniform_wind_by_wind_times_time_within_a_cell() {
    let mut plume = Plume::new(passive(), Vec3::ZERO).unwrap();
    let smoke = blob(&plume, Vec3::new(0.8, 1.2, 0.9), 0.2, 1.0);
    plume.smoke_mut().copy_from_slice(&smoke);
    let wind = Vec3::new(1.0, 0.0, 0.5);
    let start = centroid(&plume, plume.smoke());
    let steps = 45;
    for _ in 0..steps {
        plume.step(DT, wind, Vec3::Y);
    }
    let moved = centroid(&plume, plume.smoke()) - start;
    let expected = wind * DT * steps as f32;
    assert!(
        moved.distance(expected) < plume.shape().cell,
        "moved {moved}, expected {expected}"
    );
}

#[test]
fn advection_conserves_smoke_in_a_sealed_box_within_eight_percent() {
    // Semi-Lagrangian advection with trilinear interpolation is not conservative: its
    // interpolated velocity is not exactly divergence-free. Measured: 5.8 % lost over one
    // second of a 1.5 rad/s swirl of a blob three cells in radius.
    let settings = PlumeSettings {
        walls: Walls::CLOSED,
        ..passive()
    };
    let mut plume = Plume::new(settings, Vec3::ZERO).unwrap();
    // A swirl about the box's vertical axis, made divergence-free by one projection.
    let shape = *plume.shape();
    let axis = Vec3::new(1.2, 0.0, 1.2);
    for a in [0, 2] {
        let dims = shape.face_dims(a);
        let faces = &mut plume.velocity_mut()[a];
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let p = shape.position(i, j, k, Stagger::face(a)) - axis;
                    let swirl = Vec3::new(-p.z, 0.0, p.x) * 1.5;
                    faces[i + dims[0] * (j + dims[1] * k)] = swirl[a];
                }
            }
        }
    }
    plume.step(1e-6, Vec3::ZERO, Vec3::Y);
    let smoke = blob(&plume, Vec3::new(1.65, 1.2, 1.2), 0.3, 1.0);
    plume.smoke_mut().copy_from_slice(&smoke);
    let total = plume.total_smoke();
    let start = centroid(&plume, plume.smoke());
    for _ in 0..60 {
        plume.step(DT, Vec3::ZERO, Vec3::Y);
    }
    let after = plume.total_smoke();
    let error = (after - total).abs() / total;
    assert!(
        error < 0.08,
        "smoke {total} -> {after} ({:.2} %)",
        100.0 * error
    );
    // And it really moved: the swirl carried it round.
    let moved = centroid(&plume, plume.smoke()).distance(start);
    assert!(moved > 0.3, "the blob moved only {moved} m");
}

#[test]
fn hot_air_spreads_sideways_under_a_ceiling() {
    let spread = |ceiling: bool| {
        let settings = PlumeSettings {
            buoyancy: PlumeSettings::default().buoyancy,
            ..passive()
        };
        let mut plume = Plume::new(settings, Vec3::ZERO).unwrap();
        if ceiling {
            plume.set_solids(|p| p.y > 1.6);
        }
        for _ in 0..120 {
            plume.add_heat(Vec3::new(1.2, 0.4, 1.2), 400.0);
            plume.step(DT, Vec3::ZERO, Vec3::Y);
        }
        // Faces into the ceiling carry no air.
        if ceiling {
            let above = plume.velocity_at(Vec3::new(1.2, 1.65, 1.2));
            assert_eq!(above, Vec3::ZERO);
        }
        plume.temperature_at(Vec3::new(0.5, 1.5, 1.2))
    };
    let open = spread(false);
    let under = spread(true);
    assert!(
        under > 2.0 * open.max(0.1),
        "0.7 m to the side, just under the ceiling: {under} K, with no ceiling {open} K"
    );
}

#[test]
fn the_same_input_gives_the_same_air_bit_for_bit_on_any_number_of_threads() {
    use bevy::tasks::{TaskPool, TaskPoolBuilder};
    // 40³: big enough that the pressure sweeps split over the pool too.
    let settings = PlumeSettings {
        resolution: [40; 3],
        cell_size: 0.064,
        ..PlumeSettings::default()
    };
    let run = |pool: Option<&TaskPool>| {
        let mut plume = Plume::new(settings, Vec3::ZERO).unwrap();
        for step in 0..20 {
            plume.add_heat(Vec3::new(1.28, 0.3 + 0.01 * step as f32, 1.2), 500.0);
            plume.add_smoke(Vec3::new(1.28, 0.3, 1.2), 0.01);
            plume.step_on(DT, Vec3::new(0.2, 0.0, 0.0), Vec3::Y, pool);
        }
        (
            plume.temperature().to_vec(),
            plume.velocity().clone(),
            plume.smoke().to_vec(),
        )
    };
    let serial = run(None);
    assert!(serial == run(None));
    for threads in [1, 3] {
        let pool = TaskPoolBuilder::new().num_threads(threads).build();
        assert!(serial == run(Some(&pool)), "{threads} threads differ");
    }
}

#[test]
fn still_cold_air_costs_nothing_and_wakes_when_fed() {
    let settings = PlumeSettings {
        resolution: [16, 16, 16],
        ..Default::default()
    };
    let mut plume = Plume::new(settings, Vec3::ZERO).unwrap();
    assert!(!plume.step(DT, Vec3::ZERO, Vec3::Y).stepped);
    plume.add_heat(Vec3::splat(1.0), 100.0);
    assert!(plume.step(DT, Vec3::ZERO, Vec3::Y).stepped);
    // Bad input is ignored, not spread.
    plume.add_heat(Vec3::NAN, 100.0);
    plume.add_heat(Vec3::ONE, f32::INFINITY);
    plume.add_smoke(Vec3::splat(1e9), 1.0);
    for _ in 0..10 {
        plume.step(DT, Vec3::ZERO, Vec3::Y);
    }
    assert!(plume.temperature().iter().all(|t| t.is_finite()));
    assert!(plume.velocity().iter().flatten().all(|u| u.is_finite()));
    // Left alone, the air cools and settles, and steps stop.
    let mut settled_after = None;
    for step in 0..1200 {
        plume.step(DT, Vec3::ZERO, Vec3::Y);
        if plume.is_quiet() {
            settled_after = Some(step);
            break;
        }
    }
    assert!(settled_after.is_some(), "{:?}", plume.report());
}

#[test]
fn moving_the_box_carries_the_air_with_it() {
    let mut plume = Plume::new(passive(), Vec3::ZERO).unwrap();
    plume.add_heat(Vec3::new(1.25, 1.25, 1.25), 1000.0);
    let before = plume.temperature_at(Vec3::new(1.25, 1.25, 1.25));
    assert!(plume.move_towards(Vec3::new(0.31, 0.0, -0.19)));
    assert_eq!(plume.shape().origin, Vec3::new(0.3, 0.0, -0.2));
    let after = plume.temperature_at(Vec3::new(1.25, 1.25, 1.25));
    assert!(
        (after - before).abs() < 1e-3 * before,
        "{before} -> {after}"
    );
}

#[test]
fn the_air_at_a_point_is_its_velocity_and_temperature_there_and_nothing_outside() {
    let centre = Vec3::new(1.2, 0.6, 1.2);
    let plume = rising(centre, [0.3, 200.0], 20);
    let size = plume.shape().size();
    for (i, point) in [
        centre,
        centre + Vec3::new(0.13, 0.41, -0.07),
        Vec3::splat(0.01),
    ]
    .into_iter()
    .chain((0..20).map(|i| Vec3::new(noise(i), noise(i + 50), noise(i + 99)).abs() * size))
    .enumerate()
    {
        let (velocity, temperature) = plume.air_at(point).expect("inside the box");
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        assert_eq!(bits(velocity), bits(plume.velocity_at(point)), "point {i}");
        assert_eq!(temperature.to_bits(), plume.temperature_at(point).to_bits());
    }
    assert!(plume.velocity_at(centre).y > 0.1, "the hot air rises");
    for outside in [Vec3::splat(-0.01), size + Vec3::X, Vec3::NAN] {
        assert_eq!(plume.air_at(outside), None);
    }
}

#[test]
fn the_plume_blows_on_and_heats_a_big_cloth_the_same_on_any_number_of_threads() {
    use super::coupling::{blow_and_heat, blow_and_heat_on};
    use crate::sim::{BurnMaterial, ClothBuilder, ClothSim};
    use bevy::tasks::TaskPoolBuilder;
    let plume = rising(Vec3::new(1.2, 0.8, 1.2), [0.4, 300.0], 10);
    // 180 x 180 particles (three parts' worth), 7.5 mm apart, over the hot air.
    let cloth = ClothSim::new(
        &ClothBuilder::grid(180, 180, 0.0075).pin_top_corners(),
        BurnMaterial::COTTON,
        glam::Affine3A::from_translation(Vec3::new(0.6, 1.6, 1.2)),
    )
    .unwrap();
    let material = *cloth.material();
    let ambient = material.initial_temperature;
    let mut serial = cloth.particles.clone();
    let report = blow_and_heat(&plume, &mut serial, &material, ambient, true, DT);
    let inside = cloth
        .particles
        .position
        .iter()
        .filter(|p| plume.shape().contains(**p));
    assert_eq!(
        report.inside as usize,
        inside.count(),
        "counts the particles in the box"
    );
    assert!(report.inside > 20_000);
    assert!(
        report.heated > 1000,
        "the hot air warms the cloth above it: {report:?}"
    );
    let bits = |p: &crate::sim::Particles| {
        let force = p
            .external_force
            .iter()
            .flat_map(|f| f.to_array())
            .map(f32::to_bits);
        let temperature = p.temperature.iter().map(|t| t.to_bits());
        force.chain(temperature).collect::<Vec<_>>()
    };
    for threads in [1, 3] {
        let pool = TaskPoolBuilder::new().num_threads(threads).build();
        let mut split = cloth.particles.clone();
        let again = blow_and_heat_on(
            &plume,
            &mut split,
            &material,
            [ambient, DT],
            true,
            Some(&pool),
        );
        assert_eq!(again, report, "{threads} threads");
        assert!(bits(&split) == bits(&serial), "{threads} threads differ");
    }
}
