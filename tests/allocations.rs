//! No heap allocation per frame in steady state: a burning cloth's step, its mesh update and
//! (with feature `smoke`) its smoke, counted by a counting global allocator
//! (`allocation-counter`, which counts on the calling thread only, so tests running beside
//! this one do not disturb the count).
//!
//! The cloths step on this thread, without a task pool: with one, Bevy's scoped tasks
//! allocate their task handles (that is Bevy's executor, not the simulation).

use bevy::math::{Affine3A, Vec3};
use bevy_burning_cloth::sim::mesh::MeshData;
use bevy_burning_cloth::sim::{
    BurnMaterial, ClothBuilder, ClothSim, HeatModel, Integrator, MeshClothBuilder, MeshPins,
};

const DT: f32 = 1.0 / 60.0;

/// A 32 x 32 cotton curtain pinned at every 4th top particle, lit at the bottom centre.
fn curtain(configure: impl FnOnce(&mut ClothSim)) -> ClothSim {
    curtain_of(32, 32, configure)
}

/// A `columns` x `rows` cotton curtain at 4 cm pinned at every 4th top particle, lit at the
/// bottom centre.
fn curtain_of(columns: u32, rows: u32, configure: impl FnOnce(&mut ClothSim)) -> ClothSim {
    let mut sim = ClothSim::new(
        &ClothBuilder::grid(columns, rows, 0.04).pin_top_every(4),
        BurnMaterial::COTTON,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )
    .expect("valid cloth");
    configure(&mut sim);
    let grid = sim.topology.grid.unwrap();
    sim.ignite(grid.index(columns / 2, rows - 2)).unwrap();
    sim
}

/// A flat disc of triangles (a fan of rings) made flammable, pinned near its top.
fn disc() -> ClothSim {
    let (rings, sectors) = (12u32, 24u32);
    let mut positions = vec![Vec3::ZERO];
    for r in 1..=rings {
        for s in 0..sectors {
            let angle = s as f32 / sectors as f32 * core::f32::consts::TAU;
            let radius = 0.5 * r as f32 / rings as f32;
            positions.push(Vec3::new(radius * angle.cos(), radius * angle.sin(), 0.0));
        }
    }
    let at = |r: u32, s: u32| {
        if r == 0 {
            0
        } else {
            1 + (r - 1) * sectors + s % sectors
        }
    };
    let mut triangles = Vec::new();
    for s in 0..sectors {
        triangles.push([0, at(1, s), at(1, s + 1)]);
    }
    for r in 1..rings {
        for s in 0..sectors {
            triangles.push([at(r, s), at(r + 1, s), at(r + 1, s + 1)]);
            triangles.push([at(r, s), at(r + 1, s + 1), at(r, s + 1)]);
        }
    }
    let builder =
        MeshClothBuilder::new(positions, triangles).with_pins(MeshPins::Top { within: 0.05 });
    let parts = builder
        .build(&BurnMaterial::PAPER, Affine3A::from_translation(Vec3::Y))
        .expect("valid mesh");
    let mut sim = ClothSim::from_parts(
        parts,
        BurnMaterial::PAPER,
        Affine3A::from_translation(Vec3::Y),
    );
    sim.ignite_nearest(Vec3::new(0.0, 0.6, 0.0)).unwrap();
    sim
}

/// Runs `warm_up` frames, then counts the allocations of `frames` more: step, mesh update,
/// and smoke with feature `smoke`. Returns (allocations, particles burnt while counting).
fn allocations_per_run(mut sim: ClothSim, warm_up: u32, frames: u32) -> (u64, u32) {
    let mut mesh = MeshData::default();
    let to_local = sim.transform.inverse();
    #[cfg(feature = "smoke")]
    let mut smoke = bevy_burning_cloth::smoke::SmokeSim::new(Default::default()).unwrap();
    let mut frame = |sim: &mut ClothSim| {
        let report = sim.step(DT);
        mesh.update(
            &sim.particles,
            &sim.topology,
            sim.material(),
            to_local,
            None,
        );
        #[cfg(feature = "smoke")]
        {
            use bevy_burning_cloth::smoke::{Air, BurningCloth};
            smoke.emit(&BurningCloth::of(sim), &Air::default(), DT);
            smoke.advance(&Air::default(), DT);
        }
        report.burnt
    };
    for _ in 0..warm_up {
        frame(&mut sim);
    }
    let before = sim.outcome().report.burnt;
    let mut after = before;
    let info = allocation_counter::measure(|| {
        for _ in 0..frames {
            after = frame(&mut sim);
        }
    });
    assert!(sim.particles.is_finite());
    (info.count_total, after - before)
}

#[test]
fn a_burning_grid_cloth_allocates_nothing_per_frame() {
    let cases: [(&str, fn(&mut ClothSim)); 3] = [
        ("XPBD, paper heat", |_| {}),
        ("symplectic Euler, paper heat", |sim| {
            sim.update_settings(|s| s.solver.integrator = Integrator::SymplecticEuler)
                .unwrap();
        }),
        ("XPBD, physical heat", |sim| {
            sim.update_settings(|s| s.solver.heat_model = HeatModel::PHYSICAL)
                .unwrap();
        }),
    ];
    for (name, configure) in cases {
        // 2 s to warm up (hanging, catching fire), then 3 s of burning counted.
        let (allocations, burnt) = allocations_per_run(curtain(configure), 120, 180);
        assert!(burnt > 0, "{name}: nothing burnt while counting");
        assert_eq!(
            allocations, 0,
            "{name}: {allocations} allocations in 180 frames"
        );
    }
}

#[test]
fn a_wide_grid_whose_normals_go_by_rows_allocates_nothing_per_frame() {
    // 64 columns: the mesh update gathers its normals along the grid's rows.
    let (allocations, burnt) = allocations_per_run(curtain_of(64, 12, |_| {}), 60, 120);
    assert!(burnt > 0, "nothing burnt while counting");
    assert_eq!(allocations, 0, "{allocations} allocations in 120 frames");
}

#[test]
fn a_burning_mesh_cloth_allocates_nothing_per_frame() {
    let (allocations, burnt) = allocations_per_run(disc(), 60, 180);
    assert!(burnt > 0, "nothing burnt while counting");
    assert_eq!(allocations, 0, "{allocations} allocations in 180 frames");
}

#[test]
fn the_counter_counts() {
    // The check above could not fail if the counter saw nothing.
    let info = allocation_counter::measure(|| {
        let v: Vec<u32> = std::hint::black_box(Vec::with_capacity(16));
        drop(v);
    });
    assert_eq!(info.count_total, 1);
}
