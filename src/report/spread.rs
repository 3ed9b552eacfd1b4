//! Fire spread speed: how fast the burning front crosses a vertical panel upward, sideways
//! and downward, and how long it takes to climb 127 mm of a strip held at 45° (the test of
//! 16 CFR 1610), for each material, heat model and grid spacing, beside published figures.
//!
//! Each case runs a [`ClothSim`] as a game would (default solver, 1/60 s frames):
//! - **Vertical panel**: 1 m × 1 m, held flat in its frame (every particle pinned, as the
//!   measured panels are), one particle lit at its centre. A direction's speed is
//!   `0.3 m / (t(0.4 m) − t(0.1 m))`, where `t(d)` is when the particle `d` away from the lit one along the grid (in the cloth's own, rest coordinates)
//!   first ignites. Starting at 0.1 m leaves out the ignition transient.
//! - **45° strip** (16 CFR 1610): 50 mm wide, 160 mm long, every particle held in its frame,
//!   tilted 45° from the vertical, its bottom row lit. The result is the time for the front
//!   to reach 127 mm up the strip along its centre line (interpolated between rows); the
//!   standard classes plain fabric as normal flammability at 3.5 s or more.
//!
//! A case stops when every mark is reached, when nothing is burning any more, or at the time
//! limit; a mark never reached is reported as `None`.

use crate::sim::{
    BurnMaterial, BurnState, ClothBuilder, ClothError, ClothSim, HeatModel, MeshClothBuilder,
    MeshPins,
};
use glam::{Affine3A, Quat, Vec3};

/// One frame, s.
pub const FRAME: f32 = 1.0 / 60.0;
/// Where the vertical panel's speed is measured between, m from the lit particle.
pub const MARKS: (f32, f32) = (0.1, 0.4);
/// How far up the 45° strip the standard times the flame, m.
pub const STRIP_MARK: f32 = 0.127;
/// The standard's threshold: a flame time at or above this is normal flammability, s.
pub const NORMAL_FLAMMABILITY: f32 = 3.5;

/// Speeds of the front across a vertical panel, m/s (`None`: it never got from one mark to
/// the other within the time limit).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PanelSpread {
    /// Straight up.
    pub up: Option<f32>,
    /// Sideways.
    pub sideways: Option<f32>,
    /// Straight down.
    pub down: Option<f32>,
    /// Simulated time the case ran, s.
    pub simulated: f32,
}

/// A case of the study: a material, a heat model and a grid spacing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpreadCase {
    /// The material.
    pub material: BurnMaterial,
    /// The heat model.
    pub heat_model: HeatModel,
    /// Distance between neighbouring particles, m.
    pub spacing: f32,
}

/// A case's results.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpreadRow {
    /// The case.
    pub case: SpreadCase,
    /// The vertical panel.
    pub panel: PanelSpread,
    /// Time for the front to climb [`STRIP_MARK`] up the 45° strip, s.
    pub strip_time: Option<f32>,
}

/// A published spread figure to print beside the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Published {
    /// The material's name, as in its preset.
    pub material: &'static str,
    /// Upward, sideways and downward speeds on a vertical panel, m/s, where measured.
    pub speeds: [Option<f32>; 3],
    /// Where the figures come from.
    pub source: &'static str,
}

/// The figures the study is compared with.
pub const PUBLISHED: [Published; 2] = [
    Published {
        material: "cotton",
        speeds: [Some(0.090), Some(0.011), Some(0.002)],
        source: "vertical cotton panels: Mathur, Vikas and Kale, flame spread on textiles",
    },
    Published {
        material: "paper",
        speeds: [None, Some(0.004), None],
        source: "80 g/m² paper, horizontal spread from mass burning rates (Thomas and Law)",
    },
];

/// Grid index of a particle `columns` wide, at (`column`, `row`).
fn index(columns: u32, column: u32, row: u32) -> usize {
    (row * columns + column) as usize
}

/// Runs the vertical panel for `case`, for at most `limit` simulated seconds.
pub fn vertical_panel(case: &SpreadCase, limit: f32) -> Result<PanelSpread, ClothError> {
    let n = (1.0 / case.spacing).round() as u32 + 1;
    // Held flat, every particle pinned, as the measured panels are held in frames: a panel
    // hanging free crumples and swings, and its fire runs along folds at other angles.
    let builder = ClothBuilder::grid(n, n, case.spacing).pin_all();
    let mut sim = ClothSim::new(
        &builder,
        case.material,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )?;
    sim.update_settings(|s| s.solver.heat_model = case.heat_model)?;
    let centre = n / 2;
    let steps = |distance: f32| (distance / case.spacing).round() as u32;
    let (near, far) = (steps(MARKS.0), steps(MARKS.1));
    let distance = (far - near) as f32 * case.spacing;
    // Marks: [up, sideways, down] × [near, far].
    let marks = [
        [(centre, centre - near), (centre, centre - far)],
        [(centre + near, centre), (centre + far, centre)],
        [(centre, centre + near), (centre, centre + far)],
    ]
    .map(|pair| pair.map(|(column, row)| index(n, column, row)));
    sim.ignite(index(n, centre, centre))?;
    let times = run_until(&mut sim, &marks.concat(), limit);
    Ok(times.panel_spread(|_| distance))
}

/// A flat square mesh `side` m wide in the world's XY plane, centred on the origin, every
/// vertex pinned: vertices `spacing` m apart (rounded to fit), the inner ones moved by up to
/// `jitter` times the spacing in each direction (a fixed pseudo-random pattern; 0 leaves it
/// regular), each cell split along alternating diagonals: a game's imported mesh, made
/// flammable.
pub fn square_mesh(side: f32, spacing: f32, jitter: f32) -> MeshClothBuilder {
    let n = ((side / spacing).round() as u32).max(1) + 1;
    let step = side / (n - 1) as f32;
    // A hash of the vertex's place, in [-1, 1): the same mesh on every run.
    let offset = |column: u32, row: u32, salt: u32| {
        let mut h = column.wrapping_mul(0x9E37_79B1) ^ row.wrapping_mul(0x85EB_CA77) ^ salt;
        h ^= h >> 15;
        h = h.wrapping_mul(0x2C1B_3C6D);
        h ^= h >> 12;
        (h & 0xFFFF) as f32 / 32768.0 - 1.0
    };
    let mut positions = Vec::with_capacity((n * n) as usize);
    for row in 0..n {
        for column in 0..n {
            let edge = row == 0 || column == 0 || row + 1 == n || column + 1 == n;
            let (dx, dy) = if edge {
                (0.0, 0.0)
            } else {
                (offset(column, row, 1), offset(column, row, 2))
            };
            positions.push(Vec3::new(
                (column as f32 + jitter * dx) * step - 0.5 * side,
                0.5 * side - (row as f32 + jitter * dy) * step,
                0.0,
            ));
        }
    }
    let mut triangles = Vec::with_capacity((2 * (n - 1) * (n - 1)) as usize);
    for row in 0..n - 1 {
        for column in 0..n - 1 {
            let [a, b, c, d] = [
                index(n, column, row),
                index(n, column + 1, row),
                index(n, column, row + 1),
                index(n, column + 1, row + 1),
            ]
            .map(|i| i as u32);
            if (row + column) % 2 == 0 {
                triangles.extend([[a, c, d], [a, d, b]]);
            } else {
                triangles.extend([[a, c, b], [b, c, d]]);
            }
        }
    }
    MeshClothBuilder::new(positions, triangles).with_pins(MeshPins::custom(|_, _| true))
}

/// Runs the vertical panel for `case` on a 1 m [`square_mesh`] instead of a grid, with
/// `jitter`. A direction's speed is the distance between the particles nearest the two
/// marks over the time between their catches.
pub fn mesh_panel(case: &SpreadCase, jitter: f32, limit: f32) -> Result<PanelSpread, ClothError> {
    let parts = square_mesh(1.0, case.spacing, jitter).build(
        &case.material,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )?;
    let mut sim = ClothSim::from_parts(parts, case.material, Affine3A::IDENTITY);
    sim.update_settings(|s| s.solver.heat_model = case.heat_model)?;
    let centre = Vec3::new(0.0, 2.0, 0.0);
    let lit = sim.ignite_nearest(centre)?;
    let nearest = |point: Vec3| {
        let position = &sim.particles.position;
        (0..position.len())
            .min_by(|&i, &j| {
                position[i]
                    .distance_squared(point)
                    .total_cmp(&position[j].distance_squared(point))
            })
            .unwrap_or(lit)
    };
    let directions = [Vec3::Y, Vec3::X, -Vec3::Y];
    let marks = directions.map(|d| [nearest(centre + MARKS.0 * d), nearest(centre + MARKS.1 * d)]);
    let times = run_until(&mut sim, &marks.concat(), limit);
    let position = &sim.particles.position;
    Ok(times.panel_spread(|d| {
        let [near, far] = marks[d];
        position[near].distance(position[far])
    }))
}

/// Runs the 45° strip for `case` and returns the time for the front to climb
/// [`STRIP_MARK`] up its centre line, s, if it does within `limit` s.
pub fn inclined_strip(case: &SpreadCase, limit: f32) -> Result<Option<f32>, ClothError> {
    let columns = (0.05 / case.spacing).round() as u32 + 1;
    let rows = (0.16 / case.spacing).round() as u32 + 1;
    let builder = ClothBuilder::grid(columns, rows, case.spacing).pin_all();
    // Rows run down the strip; tilt it 45° about the horizontal axis across it.
    let tilt = Quat::from_rotation_x(core::f32::consts::FRAC_PI_4);
    let mut sim = ClothSim::new(
        &builder,
        case.material,
        Affine3A::from_rotation_translation(tilt, Vec3::new(0.0, 1.0, 0.0)),
    )?;
    sim.update_settings(|s| s.solver.heat_model = case.heat_model)?;
    let bottom = rows - 1;
    for column in 0..columns {
        sim.ignite(index(columns, column, bottom))?;
    }
    // The centre line from the bottom up: each row's distance from the lit edge.
    let centre = columns / 2;
    let line: Vec<usize> = (0..rows)
        .rev()
        .map(|row| index(columns, centre, row))
        .collect();
    let reach = ((STRIP_MARK / case.spacing).ceil() as usize).min(line.len() - 1);
    let times = run_until(&mut sim, &line[..=reach], limit);
    // Interpolate the time at the mark between the rows either side of it.
    let below = ((STRIP_MARK / case.spacing).floor() as usize).min(reach);
    Ok(match (times.at[below], times.at[reach]) {
        (Some(a), Some(b)) if reach > below => {
            let fraction = STRIP_MARK / case.spacing - below as f32;
            Some(a + (b - a) * fraction)
        }
        (Some(a), _) if reach == below => Some(a),
        _ => None,
    })
}

/// When each watched particle first ignited, s.
struct IgnitionTimes {
    at: Vec<Option<f32>>,
    simulated: f32,
}

impl IgnitionTimes {
    /// A panel's three speeds, m/s, from times watched as [up, sideways, down] × [near, far]
    /// marks, `distance(d)` apart in direction `d` (m).
    fn panel_spread(&self, distance: impl Fn(usize) -> f32) -> PanelSpread {
        let speed = |d: usize| match (self.at[2 * d], self.at[2 * d + 1]) {
            (Some(start), Some(end)) if end > start => Some(distance(d) / (end - start)),
            _ => None,
        };
        PanelSpread {
            up: speed(0),
            sideways: speed(1),
            down: speed(2),
            simulated: self.simulated,
        }
    }
}

/// Steps `sim` in frames until every particle of `watched` has ignited, nothing burns any
/// more, or `limit` s have passed.
fn run_until(sim: &mut ClothSim, watched: &[usize], limit: f32) -> IgnitionTimes {
    let mut at = vec![None; watched.len()];
    let frames = (limit / FRAME).ceil() as u32;
    let mut simulated = 0.0;
    for frame in 1..=frames {
        sim.step(FRAME);
        simulated = frame as f32 * FRAME;
        let state = &sim.particles.state;
        for (time, &i) in at.iter_mut().zip(watched) {
            if time.is_none() && state[i] != BurnState::Intact {
                *time = Some(simulated);
            }
        }
        if at.iter().all(Option::is_some) || !state.contains(&BurnState::Ignited) {
            break;
        }
    }
    IgnitionTimes { at, simulated }
}

/// Runs every case: both studies for each.
pub fn study(cases: &[SpreadCase], limit: f32) -> Result<Vec<SpreadRow>, ClothError> {
    cases
        .iter()
        .map(|case| {
            Ok(SpreadRow {
                case: *case,
                panel: vertical_panel(case, limit)?,
                strip_time: inclined_strip(case, limit)?,
            })
        })
        .collect()
}

/// How far the mesh study moves a [`square_mesh`]'s vertices, in spacings.
pub const MESH_JITTER: f32 = 0.25;

/// A case of the mesh study: the vertical panel on a grid and on a mesh of irregular
/// triangles of the same size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshRow {
    /// The case (its spacing is the mesh's).
    pub case: SpreadCase,
    /// The grid panel ([`vertical_panel`]).
    pub grid: PanelSpread,
    /// The mesh panel ([`mesh_panel`] with [`MESH_JITTER`]).
    pub mesh: PanelSpread,
}

/// Runs the mesh study: cotton under both heat models at each of `spacings` (m), on a grid
/// and on a mesh of irregular triangles, at most `limit` simulated seconds each.
pub fn mesh_study(spacings: &[f32], limit: f32) -> Result<Vec<MeshRow>, ClothError> {
    let mut rows = Vec::new();
    for heat_model in [HeatModel::Paper, HeatModel::PHYSICAL] {
        for &spacing in spacings {
            let case = SpreadCase {
                material: BurnMaterial::COTTON,
                heat_model,
                spacing,
            };
            rows.push(MeshRow {
                case,
                grid: vertical_panel(&case, limit)?,
                mesh: mesh_panel(&case, MESH_JITTER, limit)?,
            });
        }
    }
    Ok(rows)
}

/// The mesh study as a Markdown table.
pub fn mesh_markdown(rows: &[MeshRow]) -> String {
    let mut out = format!(
        "Meshes: the vertical panel as a `MeshClothBuilder` mesh of irregular triangles \
         (vertices moved by up to {MESH_JITTER} of the spacing, cells split along alternating \
         diagonals) beside the grid of the same spacing, cotton, mm/s.\n\n\
         | heat model | spacing mm | grid up | mesh up | grid sideways | mesh sideways | grid down | mesh down |\n\
         |---|---|---|---|---|---|---|---|\n"
    );
    for row in rows {
        let model = model_name(row.case.heat_model);
        let [grid, mesh] = [row.grid, row.mesh];
        out.push_str(&format!(
            "| {model} | {:.1} | {} | {} | {} | {} | {} | {} |\n",
            row.case.spacing * 1000.0,
            millimetres_per_second(grid.up),
            millimetres_per_second(mesh.up),
            millimetres_per_second(grid.sideways),
            millimetres_per_second(mesh.sideways),
            millimetres_per_second(grid.down),
            millimetres_per_second(mesh.down),
        ));
    }
    out
}

/// The cases of the full study: every preset, both heat models (the physical one with
/// [`crate::sim::PhysicalHeat::GAME`]), each spacing (m).
pub fn cases(spacings: &[f32]) -> Vec<SpreadCase> {
    let mut cases = Vec::new();
    for material in BurnMaterial::PRESETS {
        for heat_model in [HeatModel::Paper, HeatModel::PHYSICAL] {
            for &spacing in spacings {
                cases.push(SpreadCase {
                    material,
                    heat_model,
                    spacing,
                });
            }
        }
    }
    cases
}

/// A heat model's name in the tables.
fn model_name(heat_model: HeatModel) -> &'static str {
    match heat_model {
        HeatModel::Paper => "paper",
        HeatModel::Physical(_) => "physical",
    }
}

/// A speed in mm/s: whole numbers, one decimal below 10 mm/s (where a rounding would hide a
/// third of the value).
fn millimetres_per_second(speed: Option<f32>) -> String {
    speed.map_or_else(
        || "never".to_owned(),
        |v| match v * 1000.0 {
            mm if mm < 10.0 => format!("{mm:.1}"),
            mm => format!("{mm:.0}"),
        },
    )
}

/// The study as a Markdown table, with the published figures after it.
pub fn markdown(rows: &[SpreadRow], limit: f32) -> String {
    let mut out = format!(
        "Vertical panel 1 m x 1 m held flat in a frame, lit at its centre: speed between \
         {:.1} m and {:.1} m from the lit particle, mm/s (\"never\": not within {limit:.0} s). \
         45° strip (16 CFR 1610): time to climb {:.0} mm, s (normal flammability at {NORMAL_FLAMMABILITY} s \
         or more).\n\n",
        MARKS.0,
        MARKS.1,
        STRIP_MARK * 1000.0
    );
    out.push_str("| material | heat model | spacing mm | up mm/s | sideways mm/s | down mm/s | up / down | 45° strip, s to 127 mm |\n");
    out.push_str("|---|---|---|---|---|---|---|---|\n");
    for row in rows {
        let model = model_name(row.case.heat_model);
        let ratio = match (row.panel.up, row.panel.down) {
            (Some(up), Some(down)) => format!("{:.1}", up / down),
            _ => "-".to_owned(),
        };
        let strip = row
            .strip_time
            .map_or_else(|| "never".to_owned(), |t| format!("{t:.1}"));
        out.push_str(&format!(
            "| {} | {model} | {:.1} | {} | {} | {} | {ratio} | {strip} |\n",
            row.case.material.name,
            row.case.spacing * 1000.0,
            millimetres_per_second(row.panel.up),
            millimetres_per_second(row.panel.sideways),
            millimetres_per_second(row.panel.down),
        ));
    }
    out.push_str("\nPublished:\n\n| material | up mm/s | sideways mm/s | down mm/s | source |\n|---|---|---|---|---|\n");
    for published in PUBLISHED {
        let [up, sideways, down] = published
            .speeds
            .map(|s| s.map_or_else(|| "-".to_owned(), |v| format!("{:.0}", v * 1000.0)));
        out.push_str(&format!(
            "| {} | {up} | {sideways} | {down} | {} |\n",
            published.material, published.source
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::flame::spread_speed;

    fn case(spacing: f32) -> SpreadCase {
        SpreadCase {
            material: BurnMaterial::PAPER,
            heat_model: HeatModel::Paper,
            spacing,
        }
    }

    #[test]
    fn fire_climbs_faster_than_it_spreads_sideways_or_down() {
        let spread = vertical_panel(&case(0.05), 30.0).unwrap();
        let (up, sideways, down) = (
            spread.up.expect("climbs"),
            spread.sideways.expect("spreads sideways"),
            spread.down.expect("spreads down"),
        );
        assert!(up > sideways && up > down, "{spread:?}");
    }

    #[test]
    fn the_strip_is_timed_once_the_front_passes_the_mark() {
        let time = inclined_strip(&case(0.025), 30.0).unwrap().expect("burns");
        // The front cannot reach 127 mm before the rows below it have ignited: at least
        // one frame per row.
        let rows = (STRIP_MARK / 0.025).floor();
        assert!(time >= rows * FRAME && time < 30.0, "{time}");
    }

    #[test]
    fn the_paper_model_spreads_alike_from_50_mm_to_5_mm_spacing() {
        // Issue #16 asks for each direction's speed within 15 % across 5 to 50 mm. Before the
        // push was scaled per metre, cotton's front climbed 171 mm/s at 50 mm and 95 mm/s at
        // 25 mm: a fixed number of particles per second. A catch is dated within its frame
        // (`HeatWorkspace::apply`); before, a particle started pushing a frame late, and on
        // the 5 mm grid, whose front crosses a cell in two or three frames, cotton climbed at
        // 89 mm/s against 99 at 50 mm (silk 137 against 176). Self-heating is scaled like the
        // push; before, silk's downward front ran 45 / 36 / 33 mm/s at 50 / 12.5 / 5 mm.
        // Measured (spread_report): cotton up 96 / 104 / 99, sideways 33 / 34 / 33, down
        // 21 / 22 / 21 mm/s; silk up 170 / 176 / 159, sideways 68 / 70 / 67, down
        // 40 / 41 / 40 mm/s at 50 / 12.5 / 5 mm.
        for material in [BurnMaterial::COTTON, BurnMaterial::SILK] {
            let at = |spacing| {
                vertical_panel(
                    &SpreadCase {
                        material,
                        heat_model: HeatModel::Paper,
                        spacing,
                    },
                    60.0,
                )
                .unwrap()
            };
            let runs = [at(0.05), at(0.0125), at(0.005)];
            for (direction, speeds) in [
                ("up", runs.map(|r| r.up)),
                ("sideways", runs.map(|r| r.sideways)),
                ("down", runs.map(|r| r.down)),
            ] {
                let speeds = speeds.map(|v| v.expect("spreads"));
                let mean = speeds.iter().sum::<f32>() / 3.0;
                for v in speeds {
                    assert!(
                        (v / mean - 1.0).abs() <= 0.15,
                        "{}: {direction}: {speeds:?} m/s at 50, 12.5 and 5 mm",
                        material.name
                    );
                }
            }
        }
    }

    #[test]
    fn a_mesh_burns_as_fast_as_a_grid_at_any_triangle_size() {
        // Issue #16: a `Flammable` mesh's fire must not depend on its triangles' size. Each
        // direction within 15 % of the 25 mm grid's speed, on meshes of 25 and 12.5 mm of
        // irregular triangles (vertices moved by up to a quarter of the spacing), both heat
        // models. The paper model climbed at 75 mm/s against the grid's 104 before its push
        // was scaled by the mesh's row spacing and neighbour count (`sim::lattice`); the
        // physical model climbed at 45 against 90 before its flame carried where its front
        // started in a straight line (`sim::flame`): along links alone its front followed
        // edges off the vertical, where cotton's ellipse, 8 times taller than wide, is slow.
        for heat_model in [HeatModel::Paper, HeatModel::PHYSICAL] {
            let jitter = MESH_JITTER;
            let at = |spacing| SpreadCase {
                material: BurnMaterial::COTTON,
                heat_model,
                spacing,
            };
            let grid = vertical_panel(&at(0.025), 240.0).unwrap();
            for spacing in [0.025, 0.0125] {
                let mesh = mesh_panel(&at(spacing), jitter, 240.0).unwrap();
                for (direction, g, m) in [
                    ("up", grid.up, mesh.up),
                    ("sideways", grid.sideways, mesh.sideways),
                    ("down", grid.down, mesh.down),
                ] {
                    let (g, m) = (g.expect("grid spreads"), m.expect("mesh spreads"));
                    assert!(
                        (m / g - 1.0).abs() <= 0.15,
                        "{heat_model:?} {direction} at {spacing} m: mesh {m} against grid {g} m/s"
                    );
                }
            }
        }
    }

    #[test]
    fn a_point_fire_on_irregular_triangles_grows_as_the_measured_ellipse() {
        // The physical model's front from one lit patch, on a held cotton mesh 0.6 m square
        // of 25 mm triangles moved by up to a quarter of their size: a particle at `x`
        // catches no sooner than a flame could reach it in a straight line from the nearest
        // lit particle `p` at the measured speed toward it, `|x − p| / v(direction)` (Richards'
        // ellipse through 90 / 11 / 2 mm/s), and in every direction no later than 15 % after.
        // Along links alone the front on these triangles climbed at 45 mm/s, half the
        // measured speed: the links run off the vertical, where cotton's ellipse (8 times
        // taller than wide) is slow.
        // On regular triangles too, whose links point in only six directions.
        for jitter in [0.0, 0.25] {
            point_fire_grows_as_the_ellipse(jitter);
        }
    }

    fn point_fire_grows_as_the_ellipse(jitter: f32) {
        let material = BurnMaterial::COTTON;
        let parts = square_mesh(0.6, 0.025, jitter)
            .build(&material, Affine3A::IDENTITY)
            .unwrap();
        let mut sim = ClothSim::from_parts(parts, material, Affine3A::IDENTITY);
        sim.update_settings(|s| s.solver.heat_model = HeatModel::PHYSICAL)
            .unwrap();
        let start = sim.particles.position.clone();
        sim.ignite_nearest(Vec3::new(0.0, -0.15, 0.0)).unwrap();
        let n = start.len();
        let mut caught = vec![f32::INFINITY; n];
        let frames = 9 * 60;
        for frame in 1..=frames {
            sim.step(FRAME);
            for (i, state) in sim.particles.state.iter().enumerate() {
                if *state != BurnState::Intact && caught[i].is_infinite() {
                    caught[i] = frame as f32 * FRAME;
                }
            }
        }
        let lit: Vec<usize> = (0..n).filter(|&i| caught[i] <= FRAME).collect();
        assert!(!lit.is_empty());
        let straight = |x: Vec3| {
            lit.iter()
                .map(|&p| {
                    let d = x - start[p];
                    d.length() / spread_speed(&material, d.normalize_or_zero().dot(Vec3::Y))
                })
                .fold(f32::INFINITY, f32::min)
        };
        let mut checked = 0;
        for i in 0..n {
            let soonest = straight(start[i]);
            let took = caught[i] - FRAME;
            assert!(
                took >= soonest - 2.0 * FRAME,
                "jitter {jitter}: {} caught after {took} s, a flame needs {soonest} s",
                start[i]
            );
            if (1.0..8.0).contains(&soonest) {
                checked += 1;
                assert!(
                    took <= 1.15 * soonest + 2.0 * FRAME,
                    "jitter {jitter}: {} caught after {took} s, a flame needs {soonest} s",
                    start[i]
                );
            }
        }
        assert!(checked > 30, "{checked} particles checked");
    }

    #[test]
    fn the_physical_model_catches_from_one_click_on_a_fine_grid() {
        // Lit at one particle, a 12.5 mm cotton panel under the physical model never caught
        // (issue #16): the particle's heat flowed to its neighbours before it could ignite
        // them. An ignition now lights the 3 cm patch a flame would touch.
        let spread = vertical_panel(
            &SpreadCase {
                material: BurnMaterial::COTTON,
                heat_model: HeatModel::PHYSICAL,
                spacing: 0.0125,
            },
            20.0,
        )
        .unwrap();
        assert!(spread.up.is_some(), "{spread:?}");
    }

    #[test]
    fn a_case_that_cannot_burn_reports_never() {
        let mut cold = case(0.05);
        cold.material.heat_spread_rate = 0.0;
        cold.material.self_heating_rate = 0.0;
        let spread = vertical_panel(&cold, 2.0).unwrap();
        assert_eq!(
            (spread.up, spread.sideways, spread.down),
            (None, None, None)
        );
    }
}
