//! Springs stored once each, with their own rest length: Hooke's law with damping.
//!
//! The paper kept 12 springs per particle and had to keep a particle's north spring equal
//! to its neighbour's south spring. Here each spring exists once, so the two ends share
//! one rest length by construction.

use super::BurnMaterial;
use super::front::is_shrunk_length;
use super::particles::BurnState;
use glam::Vec3;

/// The paper's three spring kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum SpringKind {
    /// Between grid neighbours (N, S, E, W): resists stretch.
    Structural = 0,
    /// Across a grid cell's diagonals: resists shear.
    Shear = 1,
    /// Two particles apart (N, S, E, W): resists bending.
    Bend = 2,
}

impl SpringKind {
    /// All kinds, in index order.
    pub const ALL: [Self; 3] = [Self::Structural, Self::Shear, Self::Bend];

    /// True for the kinds that carry heat and that Provot's correction limits.
    pub fn is_in_plane(self) -> bool {
        matches!(self, Self::Structural | Self::Shear)
    }
}

/// The springs of one cloth as a structure of arrays.
#[derive(Clone, Debug, Default)]
pub struct Springs {
    /// First particle of each spring.
    pub a: Vec<u32>,
    /// Second particle of each spring.
    pub b: Vec<u32>,
    /// Current rest length, m: shrinks as the ends heat up.
    pub rest_length: Vec<f32>,
    /// Rest length when the cloth was built, m.
    pub initial_rest_length: Vec<f32>,
    /// Kind of each spring.
    pub kind: Vec<SpringKind>,
    /// Particles each spring passes over, [`NO_SPAN`] where none: a bending spring spans the
    /// particle between its ends (grid) or the edge between its ends (mesh). When one of them
    /// burns, the cloth the spring stood for is gone and the combustion phase cuts it (moves
    /// its second end to the burnt particle, so every loop that checks its ends finds it dead).
    pub spans: Vec<[u32; 2]>,
    /// When a spring's spanned particles cut it: as soon as either burns, or once both have.
    pub span_rule: Vec<SpanRule>,
}

/// No spanned particle.
pub const NO_SPAN: u32 = u32::MAX;

/// Which burnt spanned particles cut a spring.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpanRule {
    /// Either spanned particle burning cuts it: the cloth it stands for needs both (a bending
    /// spring's middle; a grid cell's diagonal that crosses the cell's drawn diagonal, whose
    /// two triangles both hold the spanned corners; a mesh bending spring's shared edge).
    #[default]
    Either,
    /// It is cut once both have burnt: either alone leaves cloth along it (a grid cell's drawn
    /// diagonal, an edge of both the cell's triangles, each holding one spanned corner).
    Both,
}

impl Springs {
    /// Number of springs.
    pub fn len(&self) -> usize {
        self.a.len()
    }

    /// True when there is no spring.
    pub fn is_empty(&self) -> bool {
        self.a.is_empty()
    }

    /// Adds a spring between `a` and `b` with rest length `rest`.
    pub fn push(&mut self, a: u32, b: u32, rest: f32, kind: SpringKind) {
        self.a.push(a);
        self.b.push(b);
        self.rest_length.push(rest);
        self.initial_rest_length.push(rest);
        self.kind.push(kind);
        self.spans.push([NO_SPAN; 2]);
        self.span_rule.push(SpanRule::Either);
    }

    /// Adds a spring that passes over the particles `spans` (use [`NO_SPAN`] for none), cut
    /// when they burn by `rule`.
    pub fn push_spanning(
        &mut self,
        [a, b]: [u32; 2],
        rest: f32,
        kind: SpringKind,
        spans: [u32; 2],
        rule: SpanRule,
    ) {
        self.push(a, b, rest, kind);
        if let (Some(last), Some(last_rule)) = (self.spans.last_mut(), self.span_rule.last_mut()) {
            *last = spans;
            *last_rule = rule;
        }
    }

    /// Whether spring `s` is to be cut now that `burnt` (one of its spanned particles) has
    /// burnt, by its [`SpanRule`].
    pub fn cut_by(&self, s: usize, burnt: u32, state: &[BurnState]) -> bool {
        let [first, second] = self.spans[s];
        if first != burnt && second != burnt {
            return false;
        }
        match self.span_rule[s] {
            SpanRule::Either => true,
            SpanRule::Both => [first, second]
                .iter()
                .all(|&p| p != NO_SPAN && state[p as usize].is_burnt()),
        }
    }

    /// Number of springs of one kind.
    pub fn count(&self, kind: SpringKind) -> usize {
        self.kind.iter().filter(|&&k| k == kind).count()
    }

    /// True when neither end of spring `s` has burnt.
    pub fn is_live(&self, s: usize, state: &[BurnState]) -> bool {
        !state[self.a[s] as usize].is_burnt() && !state[self.b[s] as usize].is_burnt()
    }

    /// True when heat has shrunk spring `s`'s rest length below
    /// [`LIMITED_BELOW`](super::front::LIMITED_BELOW) (99 %) of the one it was built with: the
    /// springs the XPBD solver's stretch limit holds ([`is_shrunk_length`], the test the
    /// front's shrink lists them by). A trace of warmth (conduction, a plume's air over the
    /// whole cloth) shrinks a spring by less, and it does not count.
    pub fn is_shrunk(&self, s: usize) -> bool {
        is_shrunk_length(self.rest_length[s], self.initial_rest_length[s])
    }

    /// Largest length / rest-length ratio over live springs of `kinds` with a non-zero rest
    /// length (a ratio to zero means nothing), or 1 if none.
    pub fn max_stretch(
        &self,
        positions: &[Vec3],
        state: &[BurnState],
        kinds: impl Fn(SpringKind) -> bool,
    ) -> f32 {
        self.max_stretch_of(positions, state, |s| kinds(self.kind[s]))
    }

    /// Largest length / rest-length ratio over the live springs `s` with `include(s)` and a
    /// non-zero rest length, or 1 if none ([`Self::stretches`]).
    pub fn max_stretch_of(
        &self,
        positions: &[Vec3],
        state: &[BurnState],
        include: impl Fn(usize) -> bool,
    ) -> f32 {
        self.stretches(positions, state, include)
            .fold(1.0, f32::max)
    }

    /// Length / rest-length ratio of each live spring `s` with `include(s)` and a non-zero rest
    /// length, in spring order. The ratio is to the current rest length: a spring that heat
    /// has shrunk is measured against its shrunk length.
    pub fn stretches<'a>(
        &'a self,
        positions: &'a [Vec3],
        state: &'a [BurnState],
        include: impl Fn(usize) -> bool + 'a,
    ) -> impl Iterator<Item = f32> + 'a {
        (0..self.len())
            .filter(move |&s| include(s) && self.is_live(s, state) && self.rest_length[s] > 1e-9)
            .map(|s| {
                let length = positions[self.a[s] as usize].distance(positions[self.b[s] as usize]);
                length / self.rest_length[s]
            })
    }

    /// Elastic energy stored in live springs, J.
    pub fn potential_energy(
        &self,
        positions: &[Vec3],
        state: &[BurnState],
        coefficients: &SpringCoefficients,
    ) -> f32 {
        (0..self.len())
            .filter(|&s| self.is_live(s, state))
            .map(|s| {
                let length = positions[self.a[s] as usize].distance(positions[self.b[s] as usize]);
                coefficients
                    .law(self.kind[s])
                    .energy(length - self.rest_length[s])
            })
            .sum()
    }
}

/// Stiffness and damping coefficient per spring kind, indexed by `SpringKind as usize`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringCoefficients {
    /// Stiffness, N/m.
    pub stiffness: [f32; 3],
    /// Damping coefficient, N·s/m.
    pub damping: [f32; 3],
    /// Fraction of the stiffness that resists compression (dimensionless, in [0, 1]): a
    /// spring shorter than its rest length pushes with `compression × stiffness`
    /// ([`BurnMaterial::compression`]).
    pub compression: [f32; 3],
}

impl Default for SpringCoefficients {
    /// No stiffness, no damping, as stiff in compression as in tension.
    fn default() -> Self {
        Self {
            stiffness: [0.0; 3],
            damping: [0.0; 3],
            compression: [1.0; 3],
        }
    }
}

impl SpringCoefficients {
    /// Coefficients from a material, with damping set so a spring between two particles of
    /// `particle_mass` has the material's damping ratio: `c = 2 ζ sqrt(k m / 2)`.
    ///
    /// The damping coefficient is the same whether the spring is stretched or compressed.
    pub fn from_material(material: &BurnMaterial, particle_mass: f32) -> Self {
        let mut coefficients = Self::default();
        for kind in SpringKind::ALL {
            let k = material.stiffness(kind);
            coefficients.stiffness[kind as usize] = k;
            coefficients.compression[kind as usize] = material.compression(kind);
            coefficients.damping[kind as usize] =
                2.0 * material.damping_ratio * (k * particle_mass * 0.5).sqrt();
        }
        coefficients
    }

    /// The spring law of kind `kind`.
    pub fn law(&self, kind: SpringKind) -> SpringLaw {
        let k = kind as usize;
        SpringLaw {
            stiffness: self.stiffness[k],
            compression: self.compression[k],
            damping: self.damping[k],
        }
    }
}

/// One spring's law: Hooke's law, softer when compressed, with damping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringLaw {
    /// Stiffness when stretched, N/m.
    pub stiffness: f32,
    /// Fraction of the stiffness that resists compression (dimensionless).
    pub compression: f32,
    /// Damping coefficient, N·s/m.
    pub damping: f32,
}

impl SpringLaw {
    /// A spring as stiff in compression as in tension.
    pub fn symmetric(stiffness: f32, damping: f32) -> Self {
        Self {
            stiffness,
            compression: 1.0,
            damping,
        }
    }

    /// The stiffness at `extension` (length minus rest length, m; negative when compressed),
    /// N/m: `stiffness`, times `compression` when compressed.
    #[inline]
    pub fn stiffness_at(&self, extension: f32) -> f32 {
        if extension < 0.0 {
            self.stiffness * self.compression
        } else {
            self.stiffness
        }
    }

    /// The elastic force's magnitude at `extension` (m), N: pulling when positive.
    #[inline]
    pub fn elastic(&self, extension: f32) -> f32 {
        self.stiffness_at(extension) * extension
    }

    /// The elastic energy stored at `extension` (m), J.
    pub fn energy(&self, extension: f32) -> f32 {
        0.5 * self.stiffness_at(extension) * extension * extension
    }
}

/// Force on particle `a` from a damped spring to particle `b`, N.
///
/// `f_a = (k' (|d| - L) + c (v_b - v_a)·n) n` with `d = x_b - x_a`, `n = d / |d|` and `k'`
/// the stiffness, times the law's `compression` when `|d| < L`. Coincident particles have no
/// direction and get no force.
#[inline]
pub fn spring_force(
    x_a: Vec3,
    x_b: Vec3,
    v_a: Vec3,
    v_b: Vec3,
    rest_length: f32,
    law: SpringLaw,
) -> Vec3 {
    let delta = x_b - x_a;
    let length = delta.length();
    if length <= 1e-9 {
        return Vec3::ZERO;
    }
    let direction = delta / length;
    let magnitude = law.elastic(length - rest_length) + law.damping * (v_b - v_a).dot(direction);
    direction * magnitude
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stretched_spring_pulls_ends_together_with_hookes_magnitude() {
        let f = spring_force(
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::ZERO,
            1.5,
            SpringLaw::symmetric(10.0, 0.0),
        );
        // Extension 0.5 m at 10 N/m: 5 N toward b.
        assert!((f - Vec3::new(5.0, 0.0, 0.0)).length() < 1e-6);
    }

    #[test]
    fn compressed_spring_pushes_ends_apart() {
        let f = spring_force(
            Vec3::ZERO,
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::ZERO,
            Vec3::ZERO,
            1.0,
            SpringLaw::symmetric(4.0, 0.0),
        );
        assert!((f - Vec3::new(0.0, -2.0, 0.0)).length() < 1e-6);
    }

    #[test]
    fn a_compressed_spring_pushes_with_its_fraction_of_the_stiffness_a_stretched_one_pulls_with_all()
     {
        let law = SpringLaw {
            stiffness: 40.0,
            compression: 0.25,
            damping: 0.0,
        };
        let at = |length: f32| {
            spring_force(
                Vec3::ZERO,
                Vec3::new(length, 0.0, 0.0),
                Vec3::ZERO,
                Vec3::ZERO,
                1.0,
                law,
            )
        };
        // 0.1 m short: 0.25 × 40 N/m × 0.1 m = 1 N pushing a away from b.
        assert!((at(0.9) - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-5);
        // 0.1 m long: the full 4 N pulling a towards b.
        assert!((at(1.1) - Vec3::new(4.0, 0.0, 0.0)).length() < 1e-5);
        // The stored energy is the force's integral on each side.
        assert!((law.energy(-0.1) - 0.5 * 10.0 * 0.01).abs() < 1e-7);
        assert!((law.energy(0.1) - 0.5 * 40.0 * 0.01).abs() < 1e-7);
    }

    #[test]
    fn damping_opposes_separation_speed_only() {
        // At rest length, b moving away along the spring at 2 m/s, sideways at 5 m/s.
        let f = spring_force(
            Vec3::ZERO,
            Vec3::X,
            Vec3::ZERO,
            Vec3::new(2.0, 5.0, 0.0),
            1.0,
            SpringLaw::symmetric(100.0, 0.5),
        );
        assert!((f - Vec3::new(1.0, 0.0, 0.0)).length() < 1e-6);
    }

    #[test]
    fn coincident_particles_get_no_force() {
        let f = spring_force(
            Vec3::ONE,
            Vec3::ONE,
            Vec3::ZERO,
            Vec3::X,
            1.0,
            SpringLaw::symmetric(100.0, 1.0),
        );
        assert_eq!(f, Vec3::ZERO);
    }

    /// Springs 1 m long pulled to 1.2 m (the second shrunk to 0.5 m by heat) and a third to
    /// 1.1 m: each is measured against its own rest length, and the filter picks which count.
    #[test]
    fn stretch_is_measured_against_each_springs_current_rest_length() {
        let mut springs = Springs::default();
        springs.push(0, 1, 1.0, SpringKind::Structural);
        springs.push(2, 3, 1.0, SpringKind::Structural);
        springs.push(4, 5, 1.0, SpringKind::Structural);
        springs.rest_length[1] = 0.5;
        // A trace of warmth, less than 1 %, does not count as shrunk; more does.
        springs.rest_length[2] = 0.995;
        assert!(!springs.is_shrunk(2));
        springs.rest_length[2] = 0.985;
        assert!(springs.is_shrunk(2));
        springs.rest_length[2] = 1.0;
        let positions = [
            Vec3::ZERO,
            Vec3::X * 1.2,
            Vec3::Y,
            Vec3::new(1.2, 1.0, 0.0),
            Vec3::Z,
            Vec3::Z * 2.1,
        ];
        let state = [BurnState::Intact; 6];
        assert!(!springs.is_shrunk(0) && springs.is_shrunk(1));
        let unheated = springs.max_stretch_of(&positions, &state, |s| !springs.is_shrunk(s));
        let shrunk = springs.max_stretch_of(&positions, &state, |s| springs.is_shrunk(s));
        assert!((unheated - 1.2).abs() < 1e-6, "{unheated}");
        assert!((shrunk - 2.4).abs() < 1e-6, "{shrunk}");
        let all = springs.max_stretch(&positions, &state, |k| k == SpringKind::Structural);
        assert_eq!(all, shrunk);
        // Nothing selected: no stretch, and no ratio at all.
        assert_eq!(springs.max_stretch_of(&positions, &state, |_| false), 1.0);
        assert_eq!(springs.stretches(&positions, &state, |_| false).count(), 0);
        let each: Vec<f32> = springs.stretches(&positions, &state, |_| true).collect();
        assert_eq!(each.len(), 3);
        assert!(
            (each[1] - 2.4).abs() < 1e-6 && (each[2] - 1.1).abs() < 1e-6,
            "{each:?}"
        );
        // A burnt end takes a spring out: the 1.2 m one, leaving the 1.1 m one.
        let mut burnt = state;
        burnt[0] = BurnState::Burnt;
        let left = springs.max_stretch_of(&positions, &burnt, |s| !springs.is_shrunk(s));
        assert!((left - 1.1).abs() < 1e-6, "{left}");
    }

    #[test]
    fn damping_gives_the_material_damping_ratio() {
        let mut material = BurnMaterial::SILK;
        material.damping_ratio = 0.3;
        let c = SpringCoefficients::from_material(&material, 2.0);
        let k = c.stiffness[0];
        // Two equal masses: reduced mass m/2, critical damping 2 sqrt(k m/2).
        let ratio = c.damping[0] / (2.0 * (k * 1.0_f32).sqrt());
        assert!((ratio - 0.3).abs() < 1e-6);
    }
}
