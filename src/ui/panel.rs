//! The panel's widgets and the systems that act on its toggles.

use super::ClothPanel;
use super::params::{
    GRAVITY, MATERIAL_FIELDS, PHYSICAL_HEAT, PROVOT_MAX_STRETCH, PROVOT_PASSES, PanelValues,
    SUBSTEP_RATE, SUBSTEPS, WIND,
};
use crate::plugin::{
    ClothEnvironment, ClothInUse, ClothParticles, ClothSimulationControl, ClothSolver,
    ClothSprings, ClothStatus, ClothStepTiming, ClothTopology, Extinguish, Ignite,
};
use crate::render::{BurningClothMaterial, ClickToIgnite};
use crate::sim::{
    BurnMaterial, BurnState, ClothBuilder, HeatModel, Integrator, PhysicalHeat, ProvotSettings,
    SpringKind,
};
use bevy::diagnostic::DiagnosticsStore;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};

/// What the panel reads and writes.
#[derive(SystemParam)]
pub(super) struct PanelParams<'w, 's> {
    commands: Commands<'w, 's>,
    panel: ResMut<'w, ClothPanel>,
    control: ResMut<'w, ClothSimulationControl>,
    timing: Res<'w, ClothStepTiming>,
    environment: ResMut<'w, ClothEnvironment>,
    click: Option<ResMut<'w, ClickToIgnite>>,
    cloths: Query<
        'w,
        's,
        (
            Entity,
            Option<&'static Name>,
            Option<&'static BurnMaterial>,
            Option<&'static ClothSolver>,
            &'static ClothInUse,
            &'static ClothParticles,
            &'static ClothSprings,
            &'static ClothTopology,
            &'static ClothStatus,
        ),
    >,
    builders: Query<'w, 's, &'static mut ClothBuilder>,
    mesh_builders: Query<'w, 's, &'static mut crate::sim::MeshClothBuilder>,
    #[cfg(feature = "smoke")]
    smoke: Query<'w, 's, &'static mut crate::smoke::SmokeEmitter>,
    #[cfg(feature = "fluid")]
    fire: Option<ResMut<'w, crate::fluid::FirePlume>>,
    diagnostics: Option<Res<'w, DiagnosticsStore>>,
    #[cfg(feature = "material_assets")]
    material_files: Query<'w, 's, &'static crate::material_file::BurnMaterialFile>,
    #[cfg(feature = "material_assets")]
    asset_server: Option<Res<'w, AssetServer>>,
}

fn cloth_label(entity: Entity, name: Option<&Name>) -> String {
    match name {
        Some(name) => name.to_string(),
        None => format!("cloth {}", entity.index()),
    }
}

/// Draws the panel and applies what was done in it.
pub(super) fn draw_panel(mut contexts: EguiContexts, mut p: PanelParams) -> Result {
    let ctx = contexts.ctx_mut()?;
    if !p.panel.open {
        p.panel.screen_rect = None;
        return Ok(());
    }
    let screen_height = ctx.content_rect().height();
    let shown = egui::Window::new("Burning cloth")
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
        .fixed_size([300.0, (screen_height - 64.0).max(120.0)])
        .resizable(false)
        .vscroll(true)
        .show(ctx, |ui| panel_contents(ui, &mut p));
    p.panel.screen_rect = shown.map(|shown| {
        let rect = shown.response.rect;
        Rect::new(rect.min.x, rect.min.y, rect.max.x, rect.max.y)
    });
    Ok(())
}

fn panel_contents(ui: &mut egui::Ui, p: &mut PanelParams) {
    // Which cloth.
    let selected = p.panel.selected;
    let selected_label = selected
        .and_then(|e| p.cloths.get(e).ok())
        .map_or("none".to_owned(), |c| cloth_label(c.0, c.1));
    egui::ComboBox::from_label("cloth")
        .selected_text(selected_label)
        .show_ui(ui, |ui| {
            for (entity, name, ..) in &p.cloths {
                if ui
                    .selectable_label(selected == Some(entity), cloth_label(entity, name))
                    .clicked()
                {
                    p.panel.selected = Some(entity);
                    p.panel.burnt_history.clear();
                }
            }
        });
    actions(ui, p);
    ui.separator();
    let Some(entity) = p.panel.selected.filter(|&e| p.cloths.contains(e)) else {
        ui.label("No cloth: spawn one with a ClothBuilder.");
        return;
    };
    statistics(ui, p, entity);
    timings(ui, p.diagnostics.as_deref());
    #[cfg(feature = "fluid")]
    if let Some(fire) = &mut p.fire {
        fire_air(ui, fire);
    }
    views(ui, p);
    parameters(ui, p, entity);
}

fn actions(ui: &mut egui::Ui, p: &mut PanelParams) {
    ui.horizontal_wrapped(|ui| {
        let label = if p.control.paused { "resume" } else { "pause" };
        if ui.button(label).clicked() {
            p.control.paused = !p.control.paused;
            p.control.pending_steps = 0;
        }
        if ui
            .add_enabled(p.control.paused, egui::Button::new("step"))
            .clicked()
        {
            p.control.step_once();
        }
        if ui.button("reset").clicked() {
            for mut builder in &mut p.builders {
                builder.set_changed();
            }
            for mut builder in &mut p.mesh_builders {
                builder.set_changed();
            }
            #[cfg(feature = "smoke")]
            for mut emitter in &mut p.smoke {
                emitter.clear();
            }
            p.panel.burnt_history.clear();
        }
        if let Some(entity) = p.panel.selected
            && let Ok((_, _, _, _, _, particles, ..)) = p.cloths.get(entity)
        {
            if ui.button("ignite random").clicked() {
                let unburnt: usize = particles
                    .state
                    .iter()
                    .filter(|&&s| s != BurnState::Burnt)
                    .count();
                if unburnt > 0 {
                    let k = p.panel.random_below(unburnt);
                    let index = particles
                        .state
                        .iter()
                        .enumerate()
                        .filter(|(_, s)| **s != BurnState::Burnt)
                        .nth(k)
                        .map(|(i, _)| i);
                    if let Some(index) = index {
                        p.commands.trigger(Ignite::particle(entity, index));
                    }
                }
            }
            if ui.button("extinguish").clicked() {
                p.commands.trigger(Extinguish::all(entity));
            }
        }
    });
    if let Some(click) = &mut p.click {
        let mut enabled = click.enabled;
        if ui.checkbox(&mut enabled, "clicks ignite").changed() {
            click.enabled = enabled;
        }
    }
}

fn statistics(ui: &mut egui::Ui, p: &mut PanelParams, entity: Entity) {
    let Ok((_, _, _, _, in_use, particles, springs, topology, status)) = p.cloths.get(entity)
    else {
        return;
    };
    egui::CollapsingHeader::new("statistics")
        .default_open(true)
        .show(ui, |ui| {
            let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
            for (t, s) in particles.temperature.iter().zip(&particles.state) {
                if *s != BurnState::Burnt {
                    low = low.min(*t);
                    high = high.max(*t);
                }
            }
            // Structural springs apart by whether heat has shrunk them (by over 1 %): a shrunk
            // spring that the cold cloth around holds open is stretched against its shrunk
            // length (the crumpling at the front), which is not the cloth giving way.
            // `None` when there is no such spring.
            let structural_stretch = |shrunk: bool| {
                springs
                    .stretches(&particles.position, &particles.state, |s| {
                        springs.kind[s] == SpringKind::Structural && springs.is_shrunk(s) == shrunk
                    })
                    .reduce(f32::max)
            };
            let (unheated_stretch, shrunk_stretch) =
                (structural_stretch(false), structural_stretch(true));
            let energy = crate::sim::energy::cloth_energy(
                particles,
                springs,
                in_use.material(),
                topology,
                in_use.environment(),
            );
            name_value_grid(ui, "cloth statistics", |row| {
                row(
                    "particles alive",
                    format!(
                        "{} of {}",
                        status.particles - status.burnt,
                        status.particles
                    ),
                );
                row(
                    "ignited / burnt",
                    format!("{} / {}", status.ignited, status.burnt),
                );
                row("triangles drawn", status.live_triangles.to_string());
                #[cfg(feature = "smoke")]
                if let Ok(emitter) = p.smoke.get(entity) {
                    row(
                        "smoke particles",
                        format!("{} of {}", emitter.pool().live(), emitter.pool().capacity()),
                    );
                }
                let step = p.timing.last_step.as_secs_f64() * 1e3;
                row("step (all cloths)", format!("{step:.2} ms"));
                row(
                    "per substep",
                    format!(
                        "{:.1} µs x {}",
                        p.timing.per_substep().as_secs_f64() * 1e6,
                        p.timing.substeps
                    ),
                );
                let unheated_stretch = unheated_stretch.unwrap_or(1.0);
                row("max stretch, unheated", format!("{unheated_stretch:.3}"));
                if let Some(shrunk_stretch) = shrunk_stretch {
                    row("max stretch, shrunk", format!("{shrunk_stretch:.3}"));
                }
                row("energy", format!("{energy:.3} J"));
                if low <= high {
                    row("temperature", format!("{low:.0} to {high:.0} °C"));
                }
                row("repairs", status.repairs.to_string());
            });
            ui.label(format!(
                "burnt fraction: {:.0} %",
                100.0 * status.burnt_fraction()
            ));
            burnt_plot(ui, &p.panel.burnt_history);
        });
}

/// Every `burning_cloth/…` Bevy diagnostic (the numbers `LogDiagnosticsPlugin` logs), smoothed,
/// sorted by name.
fn timings(ui: &mut egui::Ui, store: Option<&DiagnosticsStore>) {
    let Some(store) = store else {
        return;
    };
    egui::CollapsingHeader::new("timings").show(ui, |ui| {
        let mut ours: Vec<_> = store
            .iter()
            .filter_map(|d| {
                let name = d.path().as_str().strip_prefix("burning_cloth/")?;
                Some((name, d.smoothed()?, d.suffix.as_ref()))
            })
            .collect();
        ours.sort_by(|a, b| a.0.cmp(b.0));
        name_value_grid(ui, "diagnostics", |row| {
            for (name, value, suffix) in ours {
                let value = if suffix.is_empty() {
                    format!("{value:.0}")
                } else {
                    format!("{value:.2} {suffix}")
                };
                row(&name.replace('_', " "), value);
            }
        });
    });
}

/// A striped two-column grid of names and values; `rows` adds them through `row`.
fn name_value_grid(ui: &mut egui::Ui, id: &str, rows: impl FnOnce(&mut dyn FnMut(&str, String))) {
    egui::Grid::new(id)
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            let mut row = |name: &str, value: String| {
                ui.label(name);
                ui.label(value);
                ui.end_row();
            };
            rows(&mut row);
        });
}

/// The fire's air: whether there is a plume, its box, what its latest step did, and its
/// settings to edit.
#[cfg(feature = "fluid")]
fn fire_air(ui: &mut egui::Ui, fire: &mut ResMut<crate::fluid::FirePlume>) {
    egui::CollapsingHeader::new("fire's air").show(ui, |ui| {
        plume_statistics(ui, fire);
        // Written only when edited, so the resource is not marked changed every frame.
        if let Some(settings) = plume_settings(ui, fire.settings())
            && let Err(error) = fire.set_settings(settings)
        {
            bevy::log::warn!("plume settings refused: {error}");
        }
    });
}

/// The plume's settings: cells a side (a new grid restarts the air) and its rates (taken at
/// once), each edit clamped and validated ([`edit_plume`](super::plume_params::edit_plume)).
/// Returns the edited settings, if there was an edit.
#[cfg(feature = "fluid")]
fn plume_settings(
    ui: &mut egui::Ui,
    in_use: &crate::fluid::PlumeSettings,
) -> Option<crate::fluid::PlumeSettings> {
    use super::plume_params::{PLUME_CELLS, PLUME_FIELDS, edit_plume};
    let shown = egui::CollapsingHeader::new("plume settings").show(ui, |ui| {
        let in_use = *in_use;
        let mut edited = in_use;
        let mut cells = in_use.resolution[0];
        ui.add(egui::Slider::new(&mut cells, PLUME_CELLS).text("cells a side"))
            .on_hover_text("a new grid restarts the air, still, in a box of the same size");
        for field in &PLUME_FIELDS {
            field_slider(ui, field, &mut edited);
        }
        if edited == in_use && cells == in_use.resolution[0] {
            return None;
        }
        edit_plume(edited, cells, &in_use)
            .map_err(|error| bevy::log::warn!("plume settings refused: {error}"))
            .ok()
    });
    shown.body_returned.flatten()
}

/// What the plume is and what its latest step did.
#[cfg(feature = "fluid")]
fn plume_statistics(ui: &mut egui::Ui, fire: &crate::fluid::FirePlume) {
    let Some(plume) = fire.plume() else {
        ui.label("no plume yet: it is built on the first fire");
        return;
    };
    let shape = plume.shape();
    let report = plume.report();
    let cells = shape.cells();
    name_value_grid(ui, "plume statistics", |row| {
        let [nx, ny, nz] = shape.dims;
        row(
            "grid",
            format!("{nx} x {ny} x {nz} of {:.0} cm", shape.cell * 100.0),
        );
        if plume.is_quiet() {
            row("state", "still (no work)".to_owned());
            return;
        }
        row(
            "step",
            format!("{:.2} ms", fire.last_step.as_secs_f64() * 1e3),
        );
        row(
            "cells advected",
            format!(
                "{} ({:.0} %)",
                report.active_cells,
                100.0 * report.active_cells as f64 / cells.max(1) as f64
            ),
        );
        row("CG iterations", report.solve.iterations.to_string());
        row(
            "divergence left",
            format!("{:.3} /s", report.max_divergence),
        );
        row(
            "hottest air",
            format!("{:.0} K above", report.max_temperature),
        );
        row("fastest air", format!("{:.2} m/s", report.max_speed));
    });
}

/// The burnt fraction over the last [`HISTORY_LENGTH`](super::HISTORY_LENGTH) samples.
fn burnt_plot(ui: &mut egui::Ui, history: &[f32]) {
    let size = egui::vec2(ui.available_width().max(120.0), 56.0);
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_gray(24));
    if history.len() < 2 {
        return;
    }
    let step = rect.width() / (super::HISTORY_LENGTH - 1) as f32;
    let points: Vec<egui::Pos2> = history
        .iter()
        .enumerate()
        .map(|(i, f)| {
            egui::pos2(
                rect.left() + i as f32 * step,
                rect.bottom() - f.clamp(0.0, 1.0) * rect.height(),
            )
        })
        .collect();
    painter.add(egui::Shape::line(
        points,
        egui::Stroke::new(1.5, egui::Color32::from_rgb(255, 140, 40)),
    ));
}

fn views(ui: &mut egui::Ui, p: &mut PanelParams) {
    egui::CollapsingHeader::new("views")
        .default_open(true)
        .show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.checkbox(&mut p.panel.heat_map, "heat map");
                ui.checkbox(&mut p.panel.show_springs, "springs");
                ui.checkbox(&mut p.panel.show_pins, "pins");
            });
        });
}

fn parameters(ui: &mut egui::Ui, p: &mut PanelParams, entity: Entity) {
    let Ok((_, _, material, solver, cloth, ..)) = p.cloths.get(entity) else {
        return;
    };
    // The components hold the latest edit (possibly not yet taken into use); start from them
    // so an edit in progress is not reset every frame.
    let in_use = PanelValues {
        material: material.copied().unwrap_or(*cloth.material()),
        solver: solver.map_or(*cloth.solver(), |s| s.0),
        environment: p.environment.0,
    };
    let mut edited = in_use;
    material_widgets(ui, &mut edited.material, |_ui| {
        #[cfg(feature = "material_assets")]
        super::material_save::save_row(
            _ui,
            &mut p.panel,
            entity,
            &in_use.material,
            p.material_files.get(entity).ok(),
            p.asset_server.as_deref(),
        );
    });
    solver_widgets(ui, &mut edited.solver);
    world_widgets(ui, &mut edited.environment);
    if let Some(error) = &p.panel.last_error {
        ui.colored_label(egui::Color32::from_rgb(255, 120, 90), error);
    }
    if edited == in_use {
        return;
    }
    match edited.apply(&in_use) {
        Ok(values) => {
            p.panel.last_error = None;
            if values.material != in_use.material {
                p.commands.entity(entity).insert(values.material);
            }
            if values.solver != in_use.solver {
                p.commands.entity(entity).insert(ClothSolver(values.solver));
            }
            if values.environment != in_use.environment {
                p.environment.0 = values.environment;
            }
        }
        Err(error) => p.panel.last_error = Some(error),
    }
}

/// A slider over one field of `value`, labelled with its name and unit.
fn field_slider<T>(ui: &mut egui::Ui, field: &super::params::FieldRange<T>, value: &mut T) {
    let text = if field.unit.is_empty() {
        field.label.to_owned()
    } else {
        format!("{} ({})", field.label, field.unit)
    };
    ui.add(
        egui::Slider::new((field.field)(value), field.range.clone())
            .logarithmic(field.logarithmic)
            .text(text),
    );
}

fn slider(ui: &mut egui::Ui, value: &mut f32, range: std::ops::RangeInclusive<f32>, label: &str) {
    ui.add(egui::Slider::new(value, range).text(label));
}

/// The material's preset and sliders, then `below` (the file row) in the same section.
fn material_widgets(
    ui: &mut egui::Ui,
    material: &mut BurnMaterial,
    below: impl FnOnce(&mut egui::Ui),
) {
    egui::CollapsingHeader::new("material").show(ui, |ui| {
        egui::ComboBox::from_label("preset")
            .selected_text(material.name)
            .show_ui(ui, |ui| {
                for preset in BurnMaterial::PRESETS {
                    if ui
                        .selectable_label(material.name == preset.name, preset.name)
                        .clicked()
                    {
                        *material = preset;
                    }
                }
            });
        for field in &MATERIAL_FIELDS {
            field_slider(ui, field, material);
        }
        below(ui);
    });
}

fn solver_widgets(ui: &mut egui::Ui, solver: &mut crate::sim::SolverSettings) {
    egui::CollapsingHeader::new("solver").show(ui, |ui| {
        egui::ComboBox::from_label("integrator")
            .selected_text(solver.integrator.name())
            .show_ui(ui, |ui| {
                for integrator in Integrator::ALL {
                    ui.selectable_value(&mut solver.integrator, integrator, integrator.name());
                }
            });
        let mut automatic = solver.substeps.is_none();
        if ui.checkbox(&mut automatic, "automatic substeps").changed() {
            solver.substeps = if automatic { None } else { Some(8) };
        }
        match &mut solver.substeps {
            Some(substeps) => {
                ui.add(egui::Slider::new(substeps, SUBSTEPS).text("substeps"));
            }
            None => {
                ui.add(
                    egui::Slider::new(&mut solver.substep_rate, SUBSTEP_RATE)
                        .logarithmic(true)
                        .text("substep rate (Hz)"),
                );
            }
        }
        let mut provot = solver.provot.is_some();
        if ui.checkbox(&mut provot, "Provot correction").changed() {
            solver.provot = provot.then(ProvotSettings::default);
        }
        if let Some(settings) = &mut solver.provot {
            slider(
                ui,
                &mut settings.max_stretch,
                PROVOT_MAX_STRETCH,
                "max stretch (0.1 = 10 %)",
            );
            ui.add(egui::Slider::new(&mut settings.passes, PROVOT_PASSES).text("passes"));
        }
        let mut physical = matches!(solver.heat_model, HeatModel::Physical(_));
        if ui.checkbox(&mut physical, "physical heat model").changed() {
            solver.heat_model = if physical {
                HeatModel::PHYSICAL
            } else {
                HeatModel::Paper
            };
        }
        if let HeatModel::Physical(PhysicalHeat {
            diffusivity,
            convection,
            cooling,
            burn_heating,
        }) = &mut solver.heat_model
        {
            ui.add(
                egui::Slider::new(diffusivity, PHYSICAL_HEAT[0].clone())
                    .logarithmic(true)
                    .text("diffusivity (m²/s)"),
            );
            slider(
                ui,
                convection,
                PHYSICAL_HEAT[1].clone(),
                "upward bias (1/s)",
            );
            slider(ui, cooling, PHYSICAL_HEAT[2].clone(), "cooling (1/s)");
            slider(
                ui,
                burn_heating,
                PHYSICAL_HEAT[3].clone(),
                "burn heating (°C/s)",
            );
        }
    });
}

fn world_widgets(ui: &mut egui::Ui, environment: &mut crate::sim::Environment) {
    egui::CollapsingHeader::new("wind and gravity").show(ui, |ui| {
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            slider(
                ui,
                &mut environment.wind[axis],
                WIND,
                &format!("wind {name} (m/s)"),
            );
        }
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            slider(
                ui,
                &mut environment.gravity[axis],
                GRAVITY,
                &format!("gravity {name} (m/s²)"),
            );
        }
    });
}

/// Puts the panel's heat-map switch on every cloth's material.
pub(super) fn apply_heat_map(
    panel: Res<ClothPanel>,
    cloths: Query<&MeshMaterial3d<BurningClothMaterial>, With<ClothParticles>>,
    mut materials: ResMut<Assets<BurningClothMaterial>>,
) {
    let wanted = if panel.heat_map { 1.0 } else { 0.0 };
    for handle in &cloths {
        let differs = materials
            .get(&handle.0)
            .is_some_and(|m| m.extension.look.heat_map != wanted);
        if differs && let Some(mut material) = materials.get_mut(&handle.0) {
            material.extension.look.heat_map = wanted;
        }
    }
}

/// Draws the selected cloth's live springs and pins.
pub(super) fn draw_gizmos(
    panel: Res<ClothPanel>,
    cloths: Query<(&ClothParticles, &ClothSprings)>,
    mut gizmos: Gizmos,
) {
    let Some((particles, springs)) = panel.selected.and_then(|e| cloths.get(e).ok()) else {
        return;
    };
    if panel.show_springs {
        for s in 0..springs.len() {
            if !springs.is_live(s, &particles.state) {
                continue;
            }
            let colour = match springs.kind[s] {
                SpringKind::Structural => Color::srgb(0.2, 0.8, 1.0),
                SpringKind::Shear => Color::srgba(0.4, 1.0, 0.4, 0.5),
                SpringKind::Bend => Color::srgba(1.0, 0.5, 1.0, 0.35),
            };
            let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
            gizmos.line(particles.position[a], particles.position[b], colour);
        }
    }
    if panel.show_pins {
        for i in 0..particles.len() {
            if particles.is_pinned(i) && particles.state[i] != BurnState::Burnt {
                gizmos.sphere(
                    Isometry3d::from_translation(particles.position[i]),
                    0.015,
                    Color::srgb(1.0, 0.9, 0.1),
                );
            }
        }
    }
}
