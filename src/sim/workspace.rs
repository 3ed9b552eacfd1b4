//! One cloth's private working memory: derived parameters and every scratch buffer the
//! phases reuse, so stepping does not allocate after the first steps.

use super::anchors::Anchors;
use super::derived::DerivedParams;
use super::flame::Flames;
use super::front::Front;
use super::guard::BlowUpGuard;
use super::heat::HeatWorkspace;
use super::integrate::{IntegratorWorkspace, stable_time_step};
use super::particles::Particles;
use super::provot::ProvotWorkspace;
use super::settings::ClothSettings;
use super::springs::Springs;
use super::topology::Topology;

/// Scratch memory and derived parameters of one cloth. Made by [`ClothWorkspace::new`] when
/// the cloth is built and told about settings changes by [`ClothWorkspace::settings_changed`].
#[derive(Clone, Debug)]
pub struct ClothWorkspace {
    /// Parameters derived from the settings in use.
    pub(crate) derived: DerivedParams,
    pub(crate) integrator: IntegratorWorkspace,
    pub(crate) provot: ProvotWorkspace,
    pub(crate) heat: HeatWorkspace,
    pub(crate) guard: BlowUpGuard,
    pub(crate) anchors: Anchors,
    pub(crate) front: Front,
    /// Scratch of the physical heat model.
    pub(crate) conduction: Vec<f32>,
    /// The flames at the burning edge (physical heat model).
    pub(crate) flames: Flames,
    /// The cloth's stable symplectic step, s, computed on first use after a material change.
    stable_step: Option<f32>,
}

impl ClothWorkspace {
    /// A workspace for a cloth of this `topology` stepped with validated `settings`.
    pub fn new(settings: &ClothSettings, topology: &Topology) -> Self {
        Self {
            derived: DerivedParams::new(settings, topology),
            integrator: IntegratorWorkspace::default(),
            provot: ProvotWorkspace::default(),
            heat: HeatWorkspace::default(),
            guard: BlowUpGuard::default(),
            anchors: Anchors::default(),
            front: Front::default(),
            conduction: Vec::new(),
            flames: Flames::default(),
            stable_step: None,
        }
    }

    /// Re-derives the parameters after the settings changed (`material_changed` also forgets
    /// the cached stable step, which depends on stiffness).
    pub fn settings_changed(
        &mut self,
        settings: &ClothSettings,
        topology: &Topology,
        material_changed: bool,
    ) {
        self.derived = DerivedParams::new(settings, topology);
        if material_changed {
            self.stable_step = None;
        }
    }

    /// The parameters derived from the settings in use.
    pub fn derived(&self) -> &DerivedParams {
        &self.derived
    }

    /// The cloth's stable symplectic step (s), computed once per material and cached. Masses
    /// and springs changed from outside (not by burning) need [`Self::forget_stable_step`].
    pub fn stable_step(&mut self, particles: &Particles, springs: &Springs) -> f32 {
        let coefficients = &self.derived.force.coefficients;
        *self
            .stable_step
            .get_or_insert_with(|| stable_time_step(particles, springs, coefficients))
    }

    /// Forgets what the workspace worked out about the cloth's burning and hanging (which
    /// particles are on fire or gone, which springs shrink, what is drawn, what hangs from
    /// what): the next step works it out anew from the cloth's data, reusing the memory.
    pub fn restart(&mut self) {
        self.front.restart();
        self.flames.clear();
        self.anchors.invalidate();
        self.stable_step = None;
    }

    /// Forgets the cached stable step (after masses or springs were edited by hand).
    pub fn forget_stable_step(&mut self) {
        self.stable_step = None;
    }

    /// Heap memory held by every buffer, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        self.integrator.heap_bytes()
            + self.provot.heap_bytes()
            + self.heat.heap_bytes()
            + self.guard.heap_bytes()
            + self.anchors.heap_bytes()
            + self.front.heap_bytes()
            + self.conduction.capacity() * size_of::<f32>()
            + self.flames.heap_bytes()
    }
}
