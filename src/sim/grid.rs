//! Building a grid cloth: particles, the paper's 12 springs per particle, triangles, pins.

use super::error::ClothError;
use super::material::BurnMaterial;
use super::particles::{BurnState, Particles};
use super::springs::{NO_SPAN, SpanRule, SpringKind, Springs};
use super::topology::{GridShape, Topology};
use bevy::reflect::{Reflect, std_traits::ReflectDefault};
use glam::{Affine3A, Vec2, Vec3};

/// Most particles one cloth may have (about 1M): beyond it a build is refused.
pub const MAX_PARTICLES: u64 = 1 << 20;

/// Which plane a grid cloth is laid out in, in the cloth's own frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Reflect)]
#[reflect(Default, Clone, Debug, PartialEq)]
pub enum GridPlane {
    /// Hanging: columns along +X, rows downward along −Y, the top edge through the origin.
    #[default]
    Vertical,
    /// Lying flat: columns along +X, rows along +Z, centred on the origin.
    Horizontal,
}

/// A region cut out of a grid cloth before it is simulated, in metres in the cloth's plane
/// measured from the top-left particle (x along the columns, y along the rows).
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub enum Cutout {
    /// A disc.
    Disc {
        /// Centre, m.
        centre: Vec2,
        /// Radius, m.
        radius: f32,
    },
    /// A triangle.
    Triangle([Vec2; 3]),
}

impl Cutout {
    /// True when `point` (m, in the cloth's plane) lies inside.
    pub fn contains(&self, point: Vec2) -> bool {
        match *self {
            Self::Disc { centre, radius } => point.distance_squared(centre) <= radius * radius,
            Self::Triangle([a, b, c]) => {
                let side = |p: Vec2, q: Vec2| (q - p).perp_dot(point - p);
                let (d1, d2, d3) = (side(a, b), side(b, c), side(c, a));
                let negative = d1 < 0.0 || d2 < 0.0 || d3 < 0.0;
                let positive = d1 > 0.0 || d2 > 0.0 || d3 > 0.0;
                !(negative && positive)
            }
        }
    }

    fn is_finite(&self) -> bool {
        match self {
            Self::Disc { centre, radius } => centre.is_finite() && radius.is_finite(),
            Self::Triangle(corners) => corners.iter().all(|c| c.is_finite()),
        }
    }
}

/// A description of a grid cloth, turned into particles and springs by [`ClothBuilder::build`].
///
/// ```
/// use bevy_burning_cloth::sim::{ClothBuilder, BurnMaterial};
/// let parts = ClothBuilder::grid(32, 32, 0.03)
///     .pin_top_corners()
///     .build(&BurnMaterial::SILK, bevy::math::Affine3A::IDENTITY)
///     .unwrap();
/// assert_eq!(parts.particles.len(), 32 * 32);
/// assert_eq!(parts.particles.pins_left(), 2);
/// ```
#[derive(Clone, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub struct ClothBuilder {
    /// Particles per row (at least 2).
    pub columns: u32,
    /// Particles per column (at least 2).
    pub rows: u32,
    /// Distance between neighbouring particles, m.
    pub spacing: f32,
    /// Pinned particles as (column, row), row 0 at the top.
    pub pins: Vec<(u32, u32)>,
    /// The plane the grid lies in.
    pub plane: GridPlane,
    /// Total mass in kg; `None` takes it from the material's areal density.
    pub total_mass: Option<f32>,
    /// Regions removed from the cloth: their particles start burnt (they count as burnt in
    /// [`Particles::burnt_fraction`]), so they take no part in forces, heat or drawing.
    pub cutouts: Vec<Cutout>,
}

/// The simulation data of a built cloth.
#[derive(Clone, Debug)]
pub struct ClothParts {
    /// Particles in world space.
    pub particles: Particles,
    /// Springs.
    pub springs: Springs,
    /// Triangles, texture coordinates and scale.
    pub topology: Topology,
}

impl ClothBuilder {
    /// A grid of `columns × rows` particles `spacing` metres apart, hanging, unpinned.
    pub fn grid(columns: u32, rows: u32, spacing: f32) -> Self {
        Self {
            columns,
            rows,
            spacing,
            pins: Vec::new(),
            plane: GridPlane::Vertical,
            total_mass: None,
            cutouts: Vec::new(),
        }
    }

    /// Cuts a region out of the cloth.
    pub fn cut_out(mut self, cutout: Cutout) -> Self {
        self.cutouts.push(cutout);
        self
    }

    /// Pins the particle at `column`, `row` (row 0 is the top).
    pub fn pin(mut self, column: u32, row: u32) -> Self {
        self.pins.push((column, row));
        self
    }

    /// Pins the two top corners, as in the paper's Figure 4.
    pub fn pin_top_corners(self) -> Self {
        let last = self.columns.saturating_sub(1);
        self.pin(0, 0).pin(last, 0)
    }

    /// Pins every `step`-th particle of the top row and the last one, like curtain rings.
    pub fn pin_top_every(mut self, step: u32) -> Self {
        let step = step.max(1);
        let last = self.columns.saturating_sub(1);
        let mut column = 0;
        while column < last {
            self.pins.push((column, 0));
            column += step;
        }
        self.pins.push((last, 0));
        self
    }

    /// Pins the whole top row.
    pub fn pin_top_edge(self) -> Self {
        self.pin_top_every(1)
    }

    /// Pins every particle: a cloth held flat in a frame (a test panel, a banner fixed to a
    /// wall) that burns but does not move.
    pub fn pin_all(mut self) -> Self {
        for row in 0..self.rows {
            for column in 0..self.columns {
                self.pins.push((column, row));
            }
        }
        self
    }

    /// Lays the grid in `plane`.
    pub fn in_plane(mut self, plane: GridPlane) -> Self {
        self.plane = plane;
        self
    }

    /// Sets the total mass in kg instead of deriving it from the material.
    pub fn with_total_mass(mut self, kilograms: f32) -> Self {
        self.total_mass = Some(kilograms);
        self
    }

    /// Width and height of the grid as built, m.
    pub fn size(&self) -> Vec2 {
        Vec2::new(
            self.columns.saturating_sub(1) as f32,
            self.rows.saturating_sub(1) as f32,
        ) * self.spacing
    }

    /// Checks the description without building it.
    pub fn validate(&self, material: &BurnMaterial) -> Result<(), ClothError> {
        if self.columns < 2 || self.rows < 2 {
            return Err(ClothError::EmptyGrid {
                columns: self.columns,
                rows: self.rows,
            });
        }
        let count = u64::from(self.columns) * u64::from(self.rows);
        if count > MAX_PARTICLES {
            return Err(ClothError::TooManyParticles {
                requested: count,
                max: MAX_PARTICLES,
            });
        }
        if !(self.spacing.is_finite() && self.spacing > 0.0) {
            return Err(ClothError::InvalidSpacing(self.spacing));
        }
        if let Some(mass) = self.total_mass
            && !(mass.is_finite() && mass > 0.0)
        {
            return Err(ClothError::InvalidMass(mass));
        }
        if let Some(&(column, row)) = self
            .pins
            .iter()
            .find(|(c, r)| *c >= self.columns || *r >= self.rows)
        {
            return Err(ClothError::PinOutOfRange {
                column,
                row,
                columns: self.columns,
                rows: self.rows,
            });
        }
        if self.cutouts.iter().any(|c| !c.is_finite()) {
            return Err(ClothError::NonFinitePoint);
        }
        material.validate()?;
        Ok(())
    }

    /// Builds the cloth with `material`, placing it in the world with `transform`.
    pub fn build(
        &self,
        material: &BurnMaterial,
        transform: Affine3A,
    ) -> Result<ClothParts, ClothError> {
        self.validate(material)?;
        if !(transform.matrix3.is_finite() && transform.translation.is_finite()) {
            return Err(ClothError::NonFiniteTransform);
        }
        let grid = GridShape {
            columns: self.columns,
            rows: self.rows,
        };
        let n = (self.columns * self.rows) as usize;
        let size = self.size();
        let total_mass = self
            .total_mass
            .unwrap_or(material.areal_density * size.x * size.y);
        let particle_mass = total_mass / n as f32;
        if !(particle_mass.is_finite() && particle_mass > 0.0) {
            return Err(ClothError::InvalidMass(total_mass));
        }

        let mut anchor = Vec::with_capacity(n);
        let mut uv = Vec::with_capacity(n);
        for row in 0..self.rows {
            for column in 0..self.columns {
                let x = column as f32 * self.spacing - 0.5 * size.x;
                let along = row as f32 * self.spacing;
                anchor.push(match self.plane {
                    GridPlane::Vertical => Vec3::new(x, -along, 0.0),
                    GridPlane::Horizontal => Vec3::new(x, 0.0, along - 0.5 * size.y),
                });
                uv.push(Vec2::new(
                    column as f32 / (self.columns - 1) as f32,
                    row as f32 / (self.rows - 1) as f32,
                ));
            }
        }
        let position: Vec<Vec3> = anchor
            .iter()
            .map(|&p| transform.transform_point3(p))
            .collect();
        let mut inv_mass = vec![1.0 / particle_mass; n];
        for &(column, row) in &self.pins {
            inv_mass[grid.index(column, row)] = 0.0;
        }
        let mut state = vec![BurnState::Intact; n];
        if !self.cutouts.is_empty() {
            for row in 0..self.rows {
                for column in 0..self.columns {
                    let point = Vec2::new(column as f32, row as f32) * self.spacing;
                    if self.cutouts.iter().any(|c| c.contains(point)) {
                        state[grid.index(column, row)] = BurnState::Burnt;
                    }
                }
            }
        }

        let springs = grid_springs(grid, &position);
        let particles = Particles {
            position,
            velocity: vec![Vec3::ZERO; n],
            mass: vec![particle_mass; n],
            inv_mass,
            temperature: vec![material.initial_temperature; n],
            state,
            burning_for: vec![0.0; n],
            anchor,
            external_force: vec![Vec3::ZERO; n],
        };
        let topology = Topology {
            triangles: grid_triangles(grid),
            uv,
            grid: Some(grid),
            spacing: self.spacing,
            particle_mass,
            heat_lattice: None,
            live_indices: Vec::new(),
        };
        let mut parts = ClothParts {
            particles,
            springs,
            topology,
        };
        super::topology::cull_triangles(
            &parts.topology.triangles,
            &parts.particles.state,
            &mut parts.topology.live_indices,
        );
        Ok(parts)
    }
}

/// The paper's springs of a grid, each stored once: structural to the east and south
/// neighbours, shear across both diagonals of every cell, bending two apart east and south.
/// An interior particle ends up with 12 springs: 4 of each kind.
fn grid_springs(grid: GridShape, position: &[Vec3]) -> Springs {
    let mut springs = Springs::default();
    let (columns, rows) = (grid.columns, grid.rows);
    let mut add = |[a, b]: [usize; 2], kind, spans: [usize; 2], rule| {
        let rest = position[a].distance(position[b]);
        let spans = spans.map(|p| if p == usize::MAX { NO_SPAN } else { p as u32 });
        springs.push_spanning([a as u32, b as u32], rest, kind, spans, rule);
    };
    let none = [usize::MAX; 2];
    for row in 0..rows {
        for column in 0..columns {
            let here = grid.index(column, row);
            if column + 1 < columns {
                let east = grid.index(column + 1, row);
                add([here, east], SpringKind::Structural, none, SpanRule::Either);
            }
            if row + 1 < rows {
                let south = grid.index(column, row + 1);
                add(
                    [here, south],
                    SpringKind::Structural,
                    none,
                    SpanRule::Either,
                );
            }
            if column + 1 < columns && row + 1 < rows {
                // Each diagonal spans the cell's other two corners. The drawn diagonal
                // (`grid_triangles`) is an edge of both triangles, each holding one of them:
                // cut once both have burnt. The other crosses it, and both triangles hold its
                // spanned corners: cut when either burns.
                let [top_left, top_right] = [here, grid.index(column + 1, row)];
                let [bottom_left, bottom_right] =
                    [grid.index(column, row + 1), grid.index(column + 1, row + 1)];
                let falling_drawn = (row + column) % 2 == 1;
                let [falling_rule, rising_rule] = if falling_drawn {
                    [SpanRule::Both, SpanRule::Either]
                } else {
                    [SpanRule::Either, SpanRule::Both]
                };
                add(
                    [top_left, bottom_right],
                    SpringKind::Shear,
                    [top_right, bottom_left],
                    falling_rule,
                );
                add(
                    [top_right, bottom_left],
                    SpringKind::Shear,
                    [top_left, bottom_right],
                    rising_rule,
                );
            }
        }
    }
    // Bending springs two apart, each spanning the particle between its ends.
    for row in 0..rows {
        for column in 0..columns {
            let here = grid.index(column, row);
            if column + 2 < columns {
                let [far, middle] = [grid.index(column + 2, row), grid.index(column + 1, row)];
                add([here, far], SpringKind::Bend, [middle; 2], SpanRule::Either);
            }
            if row + 2 < rows {
                let [far, middle] = [grid.index(column, row + 2), grid.index(column, row + 1)];
                add([here, far], SpringKind::Bend, [middle; 2], SpanRule::Either);
            }
        }
    }
    springs
}

/// Two triangles per grid cell, counter-clockwise seen from +Z for a vertical grid, with
/// the diagonal alternating so the mesh has no preferred direction.
pub(crate) fn grid_triangles(grid: GridShape) -> Vec<[u32; 3]> {
    let mut triangles = Vec::with_capacity(2 * ((grid.columns - 1) * (grid.rows - 1)) as usize);
    for row in 0..grid.rows - 1 {
        for column in 0..grid.columns - 1 {
            let top_left = grid.index(column, row) as u32;
            let top_right = grid.index(column + 1, row) as u32;
            let bottom_left = grid.index(column, row + 1) as u32;
            let bottom_right = grid.index(column + 1, row + 1) as u32;
            if (row + column) % 2 == 0 {
                triangles.push([top_left, bottom_left, top_right]);
                triangles.push([top_right, bottom_left, bottom_right]);
            } else {
                triangles.push([top_left, bottom_left, bottom_right]);
                triangles.push([top_left, bottom_right, top_right]);
            }
        }
    }
    triangles
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(builder: &ClothBuilder) -> ClothParts {
        builder
            .build(&BurnMaterial::CLOTH, Affine3A::IDENTITY)
            .unwrap()
    }

    #[test]
    fn interior_particles_have_twelve_springs_four_of_each_kind() {
        let parts = build(&ClothBuilder::grid(7, 6, 0.1));
        let grid = parts.topology.grid.unwrap();
        let mut per_particle = vec![[0u32; 3]; parts.particles.len()];
        let springs = &parts.springs;
        for s in 0..springs.len() {
            per_particle[springs.a[s] as usize][springs.kind[s] as usize] += 1;
            per_particle[springs.b[s] as usize][springs.kind[s] as usize] += 1;
        }
        assert_eq!(per_particle[grid.index(3, 3)], [4, 4, 4]);
        // A corner has 2 structural, 1 shear, 2 bending springs.
        assert_eq!(per_particle[grid.index(0, 0)], [2, 1, 2]);
        // Counts for a c × r grid.
        let (c, r) = (7, 6);
        assert_eq!(
            springs.count(SpringKind::Structural),
            (c - 1) * r + c * (r - 1)
        );
        assert_eq!(springs.count(SpringKind::Shear), 2 * (c - 1) * (r - 1));
        assert_eq!(springs.count(SpringKind::Bend), (c - 2) * r + c * (r - 2));
        assert_eq!(parts.topology.triangles.len(), 2 * (c - 1) * (r - 1));
    }

    #[test]
    fn rest_lengths_are_the_grid_distances() {
        let parts = build(&ClothBuilder::grid(4, 4, 0.5));
        let springs = &parts.springs;
        for s in 0..springs.len() {
            let expected = match springs.kind[s] {
                SpringKind::Structural => 0.5,
                SpringKind::Shear => 0.5 * 2f32.sqrt(),
                SpringKind::Bend => 1.0,
            };
            assert!((springs.rest_length[s] - expected).abs() < 1e-6);
            assert_eq!(springs.rest_length[s], springs.initial_rest_length[s]);
        }
    }

    #[test]
    fn triangles_face_forward() {
        let parts = build(&ClothBuilder::grid(5, 5, 0.1));
        let p = &parts.particles.position;
        for t in &parts.topology.triangles {
            let [a, b, c] = t.map(|i| p[i as usize]);
            assert!((b - a).cross(c - a).z > 0.0, "{t:?}");
        }
    }

    #[test]
    fn mass_comes_from_density_or_override_and_pins_are_placed() {
        let builder = ClothBuilder::grid(11, 11, 0.1).pin_top_corners();
        let parts = build(&builder);
        let total: f32 = parts.particles.mass.iter().sum();
        assert!((total - BurnMaterial::CLOTH.areal_density * 1.0).abs() < 1e-5);
        assert!(parts.particles.is_pinned(0) && parts.particles.is_pinned(10));
        assert_eq!(parts.particles.pins_left(), 2);
        let parts = build(&builder.clone().with_total_mass(2.0));
        let total: f32 = parts.particles.mass.iter().sum();
        assert!((total - 2.0).abs() < 1e-4);
    }

    #[test]
    fn the_transform_places_the_cloth() {
        let transform = Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0));
        let parts = ClothBuilder::grid(3, 3, 1.0)
            .build(&BurnMaterial::SILK, transform)
            .unwrap();
        assert_eq!(parts.particles.position[0], Vec3::new(0.0, 2.0, 3.0));
        assert_eq!(parts.particles.anchor[0], Vec3::new(-1.0, 0.0, 0.0));
    }

    #[test]
    fn cutouts_remove_particles_and_their_triangles() {
        let parts = build(
            &ClothBuilder::grid(21, 21, 0.1)
                .cut_out(Cutout::Disc {
                    centre: Vec2::new(1.0, 1.0),
                    radius: 0.25,
                })
                // Enlarged by 0.01 m so no lattice point lies exactly on an edge.
                .cut_out(Cutout::Triangle([
                    Vec2::new(-0.01, 2.01),
                    Vec2::new(0.52, 2.01),
                    Vec2::new(-0.01, 1.48),
                ])),
        );
        let grid = parts.topology.grid.unwrap();
        let state = &parts.particles.state;
        assert!(state[grid.index(10, 10)].is_burnt(), "disc centre");
        assert!(
            state[grid.index(12, 10)].is_burnt(),
            "0.2 m from the centre"
        );
        assert!(
            !state[grid.index(13, 10)].is_burnt(),
            "0.3 m from the centre"
        );
        assert!(state[grid.index(1, 19)].is_burnt(), "inside the triangle");
        assert!(!state[grid.index(5, 16)].is_burnt(), "outside the triangle");
        // Disc of radius 2.5 cells: 5 + 2 × 5 + 2 × 3 = 21 lattice points. Triangle with legs
        // of 5 cells: rows of 6, 5, 4, 3, 2, 1 points = 21.
        let burnt = state.iter().filter(|s| s.is_burnt()).count();
        assert_eq!(burnt, 21 + 21);
        for &i in &parts.topology.live_indices {
            assert!(!state[i as usize].is_burnt());
        }
    }

    #[test]
    fn invalid_input_is_an_error_not_a_panic() {
        let material = BurnMaterial::COTTON;
        let cases = [
            ClothBuilder::grid(0, 10, 0.1),
            ClothBuilder::grid(1, 10, 0.1),
            ClothBuilder::grid(10, 10, f32::NAN),
            ClothBuilder::grid(10, 10, -0.1),
            ClothBuilder::grid(10, 10, f32::INFINITY),
            ClothBuilder::grid(10, 10, 0.1).with_total_mass(-1.0),
            ClothBuilder::grid(10, 10, 0.1).with_total_mass(f32::NAN),
            ClothBuilder::grid(10, 10, 0.1).pin(10, 0),
            ClothBuilder::grid(u32::MAX, u32::MAX, 0.1),
            ClothBuilder::grid(4, 4, 0.1).cut_out(Cutout::Disc {
                centre: Vec2::NAN,
                radius: 1.0,
            }),
        ];
        for builder in cases {
            let error = builder.build(&material, Affine3A::IDENTITY).unwrap_err();
            assert!(!error.to_string().is_empty());
        }
        let mut negative = material;
        negative.areal_density = -0.2;
        let error = ClothBuilder::grid(4, 4, 0.1)
            .build(&negative, Affine3A::IDENTITY)
            .unwrap_err();
        assert!(matches!(error, ClothError::InvalidMaterial(_)), "{error}");
        let error = ClothBuilder::grid(4, 4, 0.1)
            .build(&material, Affine3A::from_translation(Vec3::NAN))
            .unwrap_err();
        assert_eq!(error, ClothError::NonFiniteTransform);
    }
}
