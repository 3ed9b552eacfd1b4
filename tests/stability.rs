//! The stability matrix's verdicts, checked: where the default integrator must hold, where
//! explicit methods must fail, and that the guard keeps every case finite.

use bevy_burning_cloth::report::stability::{Cell, StabilityCase, cases, markdown, run};
use bevy_burning_cloth::sim::Integrator;

const STEPS: u32 = 120;

fn case(name: &str) -> StabilityCase {
    cases()
        .into_iter()
        .find(|c| c.name.starts_with(name))
        .unwrap_or_else(|| panic!("no case {name}"))
}

fn cell(name: &str, integrator: Integrator) -> Cell {
    let case = case(name);
    Cell {
        raw: run(&case, integrator, STEPS, false),
        guarded: run(&case, integrator, STEPS, true),
    }
}

#[test]
fn the_guard_keeps_every_case_finite_with_the_default_integrator() {
    for case in cases() {
        let guarded = run(&case, Integrator::default(), STEPS, true);
        assert!(guarded.finite, "{}: {guarded:?}", case.name);
    }
}

#[test]
fn the_default_integrator_holds_every_case_without_the_guard() {
    // XPBD: every non-burning case, stiff and extreme ones included, stays finite with no
    // energy gain above 1 % of the scale, and the guard has nothing to do.
    for case in cases().iter().filter(|c| !c.burning) {
        let cell = cell(&case.name, Integrator::default());
        assert!(cell.stable(0.01), "{}: {:?}", case.name, cell.raw);
        assert_eq!(cell.guarded.repairs, 0, "{}", case.name);
    }
}

#[test]
fn symplectic_euler_is_finite_and_energy_bounded_within_its_limit() {
    // Non-burning cases whose step the automatic substeps can bring within the
    // stability limit: energy never rises above its start by more than 1 % of the scale.
    for name in [
        "stiffness 1e1",
        "stiffness 1e2",
        "stiffness 1e3",
        "structural/bend ratio 1e0",
        "structural/bend ratio 1e6",
        "step 0.1x",
        "step 0.5x",
        "step 1x",
        "heavy weight",
        "all particles pinned",
        "none pinned",
        "coincident particles",
    ] {
        let cell = cell(name, Integrator::SymplecticEuler);
        assert!(cell.stable(0.01), "{name}: {:?}", cell.raw);
        assert_eq!(
            cell.guarded.repairs, 0,
            "{name}: the guard had nothing to do"
        );
    }
}

#[test]
fn explicit_methods_fail_past_their_stability_limit_and_the_guard_catches_it() {
    // 10x the Gershgorin limit, stiffness beyond 64 substeps, and 1e-6 kg particles: the
    // raw solver blows up in the first step; guarded, the cloth stays finite. (The matrix
    // turns off the switch to XPBD past the cap, to show the method itself.)
    for name in [
        "step 10x",
        "stiffness 1e5",
        "stiffness 1e7",
        "particle mass 1e-6",
    ] {
        let cell = cell(name, Integrator::SymplecticEuler);
        assert_eq!(cell.raw.failed_at, Some(0), "{name}: {:?}", cell.raw);
        assert!(cell.guarded.finite && cell.guarded.repairs > 0, "{name}");
    }
}

#[test]
fn the_papers_explicit_euler_gains_energy_where_symplectic_euler_does_not() {
    let explicit = cell("stiffness 1e3", Integrator::ExplicitEuler);
    let symplectic = cell("stiffness 1e3", Integrator::SymplecticEuler);
    assert!(explicit.raw.energy_gain > 1.0, "{:?}", explicit.raw);
    assert!(symplectic.raw.energy_gain < 0.01, "{:?}", symplectic.raw);
}

#[test]
fn xpbd_holds_the_stiff_cases_every_explicit_method_fails() {
    // 1e5 and 1e7 N/m need far more than 64 explicit substeps; XPBD takes 10.
    for name in [
        "stiffness 1e5",
        "stiffness 1e7",
        "step 10x",
        "particle mass 1e-6",
    ] {
        let cell = cell(name, Integrator::Xpbd);
        assert!(cell.raw.finite, "{name}: {:?}", cell.raw);
        assert!(cell.raw.max_stretch < 1.15, "{name}: {:?}", cell.raw);
        assert_eq!(cell.guarded.repairs, 0, "{name}");
    }
}

#[test]
fn the_table_names_every_case_and_integrator() {
    let case = case("all particles pinned");
    let rows = vec![(
        case.name.clone(),
        case.burning,
        Integrator::ALL
            .iter()
            .map(|&i| Cell {
                raw: run(&case, i, 5, false),
                guarded: run(&case, i, 5, true),
            })
            .collect(),
    )];
    let table = markdown(&rows, 5);
    for integrator in Integrator::ALL {
        assert!(table.contains(integrator.name()));
    }
    assert!(table.contains("| all particles pinned |"));
    assert_eq!(
        table.matches("finite, 0 repaired").count(),
        Integrator::ALL.len()
    );
}
