//! Parameters derived from a cloth's settings and shape: computed once when the material,
//! the solver or the environment change, never inside a step.

use super::forces::ForceParams;
use super::heat::HeatParams;
use super::lattice::GRID_PUSH_NEIGHBOURS;
use super::material::{BurnMaterial, REFERENCE_SPACING};
use super::settings::{ClothSettings, Environment, HeatModel};
use super::springs::SpringCoefficients;
use super::topology::Topology;

/// What the phases of a step read besides the cloth itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DerivedParams {
    /// Gravity, wind, drag and spring coefficients.
    pub force: ForceParams,
    /// The heat model's rates, world up and proximity reach.
    pub heat: HeatParams,
}

impl DerivedParams {
    /// Derives every parameter from validated `settings` for a cloth of this `topology`.
    pub fn new(settings: &ClothSettings, topology: &Topology) -> Self {
        Self {
            force: force_params(&settings.material, topology, &settings.environment),
            heat: heat_params(settings, topology),
        }
    }
}

/// Force parameters of a cloth for a material and environment: drag per unit mass from the
/// material's drag per area and areal density, spring damping from its damping ratio and the
/// cloth's typical particle mass.
pub fn force_params(
    material: &BurnMaterial,
    topology: &Topology,
    environment: &Environment,
) -> ForceParams {
    ForceParams {
        gravity: environment.gravity,
        wind: environment.wind,
        drag_per_mass: material.drag_per_mass(),
        coefficients: SpringCoefficients::from_material(material, topology.particle_mass),
    }
}

/// Heat parameters of a cloth: the material's push rates scaled from
/// [`REFERENCE_SPACING`] to the cloth's spacing, the proximity reach from the solver's
/// factor and the cloth's spacing, world up, and the physical model's parameters if chosen.
pub fn heat_params(settings: &ClothSettings, topology: &Topology) -> HeatParams {
    let mut params = HeatParams::from_material(
        &settings.material,
        settings.solver.proximity_radius_factor * topology.spacing,
    );
    // The material's push rates are per neighbour at the reference spacing: scaled to this
    // cloth's, the front crosses the same metres per second at any resolution. A mesh is
    // measured by its rows' spacing and its particles' neighbours (`sim::lattice`): a
    // triangulated grid's particle has 6 where a grid's has 8, and its fire climbed at 72 %
    // of the grid's speed before.
    let (row_spacing, neighbours) = topology
        .heat_lattice
        .map_or((topology.spacing, GRID_PUSH_NEIGHBOURS), |lattice| {
            (lattice.row_spacing, lattice.push_neighbours)
        });
    let per_neighbour = if row_spacing.is_finite() && row_spacing > 0.0 {
        REFERENCE_SPACING / row_spacing
    } else {
        1.0
    };
    let fewer_neighbours = if neighbours.is_finite() && neighbours > 0.0 {
        GRID_PUSH_NEIGHBOURS / neighbours
    } else {
        1.0
    };
    params.spread_rate *= per_neighbour * fewer_neighbours;
    params.proximity_rate *= per_neighbour;
    // The paper model's self-heating too: a burning particle's temperature is what it pushes
    // with, so it must rise by the same amount while the front crosses one neighbour, whose
    // time is proportional to the spacing. Unscaled, a coarse grid's pushers grew hotter per
    // crossing and its fronts ran faster (silk's downward front 45 mm/s at 50 mm against 33
    // at 5 mm). The physical model has its own burn rates and does not read this.
    params.self_heating_rate *= per_neighbour;
    params.up = settings.environment.unit_up();
    if let HeatModel::Physical(physical) = settings.solver.heat_model {
        params.physical = Some(physical);
    }
    params
}
