//! Error against run time: every integrator on reference problems with known answers, at a
//! sweep of time steps, timed honestly (median of repeated runs after a warm-up).
//!
//! | problem | reference | error |
//! |---|---|---|
//! | spring | one 1 kg mass on a 100 N/m spring: `x = x₀ cos ωt` | max \|x − x_exact\| over 1 s, m |
//! | free fall | one particle, gravity only: `y = −g t²/2` | \|y − y_exact\| at 1 s, m |
//! | swinging cloth | a hanging cloth pushed into a swing; RK4 at a step 4× smaller than the smallest swept | RMS position error at 1 s, m |
//! | cloth at rest | a cloth hanging from its top edge, settled for 2 s under heavy drag: over the next 1 s the pins carry its weight on average | \|support − weight\| / weight |
//! | heat diffusion | a Gaussian hot spot spreading on the grid: `A s²/(s²+2αt) e^(−r²/2(s²+2αt))` | max \|T − T_exact\| / A at 2 s |
//!
//! The swinging cloth's reference is RK4 at a quarter of the smallest swept step, not 64×
//! smaller: in f32 the 1 m scene's round-off grows with the number of steps. Measured on the
//! 16 × 16 cloth: RK4 at 1/480, 1/3840 and 1/15 360 s agree to 3·10⁻⁶ m RMS, while RK4 at
//! 1/245 760 s is 1.6·10⁻⁴ m from all three.
//!
//! Cloth problems run in substeps of the swept step, with no Provot correction, no tethers
//! and no blow-up guard, so each integrator is measured on its own; a run that goes non-finite or
//! leaves the scene is kept and marked as blown up. The heat problem sweeps the grid spacing
//! (the explicit conduction step follows from it), not the time step.
//!
//! Cost: what a game would pay per simulated second. A game runs the per-frame phases (heat,
//! combustion, pieces, culling, and a solver's per-frame set-up) once per 1/60 s frame and
//! the integrator once per substep, so a cloth run at a step `h` below 1/60 s is stepped as
//! a game steps it: frames of 1/60 s, each of `1/(60 h)` substeps of exactly `h`. Its cost is
//! the wall time of those frames' steps. (Charging every swept step with a frame's work
//! would narrow the gaps between methods.)

use crate::sim::conduction::{Air, conduction_step};
use crate::sim::forces::ForceParams;
use crate::sim::integrate::{IntegratorWorkspace, integrate};
use crate::sim::springs::{SpringCoefficients, spring_force};
use crate::sim::{
    BurnMaterial, BurnState, ClothBuilder, ClothSim, GuardSettings, Integrator, Particles,
    PhysicalHeat, SpringKind, Springs,
};
use glam::{Affine3A, Vec3};
use std::fmt::Write as _;
use std::time::Instant;

/// A reference problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Problem {
    /// One mass on a spring against the exact cosine.
    Spring,
    /// One particle falling against the exact parabola.
    FreeFall,
    /// A swinging cloth against an RK4 solution at a 4× finer step.
    SwingingCloth,
    /// A settled cloth: support force at the pins against its weight.
    ClothAtRest,
    /// Heat spreading on the grid against the analytic Gaussian.
    HeatDiffusion,
}

impl Problem {
    /// Every problem, in report order.
    pub const ALL: [Self; 5] = [
        Self::Spring,
        Self::FreeFall,
        Self::SwingingCloth,
        Self::ClothAtRest,
        Self::HeatDiffusion,
    ];

    /// Short name, used in file names.
    pub fn name(self) -> &'static str {
        match self {
            Self::Spring => "spring",
            Self::FreeFall => "free_fall",
            Self::SwingingCloth => "swinging_cloth",
            Self::ClothAtRest => "cloth_at_rest",
            Self::HeatDiffusion => "heat_diffusion",
        }
    }

    /// What the error measures.
    pub fn error_label(self) -> &'static str {
        match self {
            Self::Spring => "max position error over 1 s (m)",
            Self::FreeFall => "position error at 1 s (m)",
            Self::SwingingCloth => "RMS position error at 1 s (m)",
            Self::ClothAtRest => "|support - weight| / weight",
            Self::HeatDiffusion => "max |T - exact| / amplitude at 2 s",
        }
    }

    /// Errors below this are f32 round-off, not the method's truncation error: 1e-5 of the
    /// problem's scale (0.1 m amplitude, 4.9 m fall, 0.75 m cloth, relative force, relative
    /// temperature). Orders are fitted only over errors above it.
    pub fn roundoff_floor(self) -> f64 {
        match self {
            Self::Spring => 1e-6,
            Self::FreeFall => 4.9e-5,
            Self::SwingingCloth => 7.5e-6,
            Self::ClothAtRest | Self::HeatDiffusion => 1e-5,
        }
    }

    /// What the sweep varies.
    pub fn parameter_label(self) -> &'static str {
        match self {
            Self::HeatDiffusion => "grid spacing (m)",
            _ => "time step (s)",
        }
    }
}

/// One run of one method on one problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// The problem.
    pub problem: Problem,
    /// The method's name.
    pub method: &'static str,
    /// The swept parameter: time step (s), or grid spacing (m) for heat.
    pub parameter: f32,
    /// Error in the problem's measure; NaN when the run blew up.
    pub error: f64,
    /// Wall-clock seconds per simulated second (median of the repeats).
    pub cost: f64,
    /// True when the run went non-finite or left the scene.
    pub blew_up: bool,
}

/// What to sweep and how often to time it.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// Time steps, s.
    pub steps: Vec<f32>,
    /// Grid spacings of the heat problem, m.
    pub heat_spacings: Vec<f32>,
    /// Particles per side of the cloth problems.
    pub cloth_size: u32,
    /// Timed repeats per point (after one untimed warm-up); the median is reported.
    pub repeats: usize,
    /// Integrators to compare.
    pub integrators: Vec<Integrator>,
}

impl Sweep {
    /// The full report: steps from 1/30 s to 1/3840 s, 16×16 cloth, 5 repeats.
    pub fn full() -> Self {
        Self {
            steps: (0..8).map(|k| 1.0 / (30.0 * 2f32.powi(k))).collect(),
            heat_spacings: vec![0.04, 0.02, 0.01, 0.005, 0.0025],
            cloth_size: 16,
            repeats: 5,
            integrators: Integrator::ALL.to_vec(),
        }
    }

    /// A sweep small enough for the test suite.
    pub fn tiny() -> Self {
        Self {
            steps: vec![1.0 / 480.0, 1.0 / 960.0],
            heat_spacings: vec![0.04, 0.02],
            cloth_size: 5,
            repeats: 1,
            integrators: vec![Integrator::SymplecticEuler, Integrator::Xpbd],
        }
    }
}

/// Median wall time of `repeats` runs of `run` after one warm-up, and the warm-up's result.
fn timed<T>(repeats: usize, mut run: impl FnMut() -> T) -> (T, f64) {
    let result = run();
    let mut times: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let start = Instant::now();
            core::hint::black_box(run());
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    (result, times[times.len() / 2])
}

/// Median over `repeats` runs (after one warm-up) of the cost a cloth run reports, and the
/// warm-up's result.
fn timed_cloth<T>(repeats: usize, mut run: impl FnMut() -> (T, GameCost)) -> (T, f64) {
    let (result, _) = run();
    let mut costs: Vec<f64> = (0..repeats.max(1))
        .map(|_| core::hint::black_box(run()).1.seconds)
        .collect();
    costs.sort_by(f64::total_cmp);
    (result, costs[costs.len() / 2])
}

/// The frame a game steps its cloths at, s.
pub const GAME_FRAME: f32 = 1.0 / 60.0;

/// The frame and substeps a game would run substeps of `h` seconds with: frames of
/// [`GAME_FRAME`] made of whole substeps of `h`, or one step of `h` when `h` is longer.
pub fn frame_for(h: f32) -> (f32, u32) {
    if h < GAME_FRAME {
        let substeps = (GAME_FRAME / h).round().max(1.0) as u32;
        (substeps as f32 * h, substeps)
    } else {
        (h, 1)
    }
}

/// The wall time a cloth run's steps took: every phase of every frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GameCost {
    /// Wall time, s.
    pub seconds: f64,
}

impl GameCost {
    fn add(&mut self, report: &crate::sim::StepReport) {
        self.seconds += report.times.total().as_secs_f64();
    }
}

fn single_particle(position: Vec3, velocity: Vec3) -> Particles {
    Particles {
        position: vec![Vec3::ZERO, position],
        velocity: vec![Vec3::ZERO, velocity],
        mass: vec![1.0, 1.0],
        inv_mass: vec![0.0, 1.0],
        temperature: vec![20.0; 2],
        state: vec![BurnState::Intact; 2],
        burning_for: vec![0.0; 2],
        anchor: vec![Vec3::ZERO; 2],
        external_force: vec![Vec3::ZERO; 2],
    }
}

/// Largest error over 1 s of a 1 kg mass on a 100 N/m spring released from 0.1 m.
pub fn spring_error(integrator: Integrator, h: f32) -> f64 {
    let k = 100.0;
    // The pinned end sits at −1 m so the moving mass stays near 0, where f32 is finest.
    let mut particles = single_particle(Vec3::new(0.1, 0.0, 0.0), Vec3::ZERO);
    particles.position[0] = Vec3::new(-1.0, 0.0, 0.0);
    let mut springs = Springs::default();
    springs.push(0, 1, 1.0, SpringKind::Structural);
    let params = ForceParams {
        gravity: Vec3::ZERO,
        drag_per_mass: 0.0,
        coefficients: SpringCoefficients {
            stiffness: [k; 3],
            damping: [0.0; 3],
            ..SpringCoefficients::default()
        },
        ..ForceParams::default()
    };
    let mut workspace = IntegratorWorkspace::default();
    let steps = (1.0 / h).round() as usize;
    let mut worst = 0.0f64;
    for step in 1..=steps {
        integrate(
            integrator,
            &mut particles,
            &springs,
            &params,
            &mut workspace,
            h,
        );
        let exact = 0.1 * (10.0 * f64::from(step as f32 * h)).cos();
        let x = f64::from(particles.position[1].x);
        if !x.is_finite() {
            return f64::NAN;
        }
        worst = worst.max((x - exact).abs());
    }
    worst
}

/// Position error after 1 s of free fall from rest.
pub fn free_fall_error(integrator: Integrator, h: f32) -> f64 {
    let mut particles = single_particle(Vec3::ZERO, Vec3::ZERO);
    let springs = Springs::default();
    let params = ForceParams {
        drag_per_mass: 0.0,
        ..ForceParams::default()
    };
    let mut workspace = IntegratorWorkspace::default();
    let steps = (1.0 / h).round() as usize;
    for _ in 0..steps {
        integrate(
            integrator,
            &mut particles,
            &springs,
            &params,
            &mut workspace,
            h,
        );
    }
    let t = f64::from(steps as f32 * h);
    let exact = -0.5 * f64::from(params.gravity.y.abs()) * t * t;
    let y = f64::from(particles.position[1].y);
    if y.is_finite() {
        (y - exact).abs()
    } else {
        f64::NAN
    }
}

/// The report's cloth: [`BurnMaterial::CLOTH`] with springs as stiff in compression as in
/// tension ([`BurnMaterial::with_linear_springs`]), the linear mass-spring model: a spring
/// softer when compressed has a kink in its force at its rest length, which would cap every
/// method's order and hide the differences the report measures.
pub const LINEAR_CLOTH: BurnMaterial = BurnMaterial::CLOTH.with_linear_springs();

/// A cloth stepped in substeps of `h` ([`frame_for`]), no Provot, no tethers, no guard.
fn raw_cloth(builder: ClothBuilder, integrator: Integrator, h: f32) -> ClothSim {
    let mut sim = ClothSim::new(
        &builder,
        LINEAR_CLOTH,
        Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0)),
    )
    .expect("report scenes are valid");
    sim.update_settings(|settings| {
        let solver = &mut settings.solver;
        solver.integrator = integrator;
        solver.substeps = Some(frame_for(h).1);
        solver.provot = None;
        solver.tether_stretch = None;
        solver.proximity_radius_factor = 0.0;
        solver.guard = GuardSettings {
            enabled: false,
            ..GuardSettings::default()
        };
    })
    .expect("report settings are valid");
    sim
}

/// The swinging cloth: `size`² particles 5 cm apart, pinned at the top corners, every
/// particle given 0.5 m/s sideways, to be stepped in substeps of `h`.
pub fn swinging_cloth(size: u32, integrator: Integrator, h: f32) -> ClothSim {
    let mut sim = raw_cloth(
        ClothBuilder::grid(size, size, 0.05).pin_top_corners(),
        integrator,
        h,
    );
    for v in &mut sim.particles.velocity {
        *v = Vec3::new(0.0, 0.0, 0.5);
    }
    sim
}

/// Runs `sim` (built for substeps of `h`) for `seconds` in frames of [`frame_for`]`(h)`,
/// adding to `cost`; false if it blew up on the way.
fn run_for(sim: &mut ClothSim, seconds: f32, h: f32, cost: &mut GameCost) -> bool {
    let frame = frame_for(h).0;
    let frames = (seconds / frame).round() as usize;
    for _ in 0..frames {
        let report = sim.step(frame);
        cost.add(&report);
        if !sim.particles.is_finite() {
            return false;
        }
    }
    // Leaving a 1 m scene by 100 m is blowing up too.
    sim.particles.position.iter().all(|p| p.length() < 100.0)
}

/// Positions of the swinging cloth after 1 s, with steps of `h`, and what the run cost.
pub fn swinging_cloth_run(
    size: u32,
    integrator: Integrator,
    h: f32,
) -> (Option<Vec<Vec3>>, GameCost) {
    let mut sim = swinging_cloth(size, integrator, h);
    let mut cost = GameCost::default();
    let finished = run_for(&mut sim, 1.0, h, &mut cost);
    (finished.then(|| sim.particles.position.clone()), cost)
}

/// Positions of the swinging cloth after 1 s, with steps of `h`.
pub fn swinging_cloth_positions(size: u32, integrator: Integrator, h: f32) -> Option<Vec<Vec3>> {
    swinging_cloth_run(size, integrator, h).0
}

fn rms_difference(a: &[Vec3], b: &[Vec3]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(a, b)| f64::from(a.distance_squared(*b)))
        .sum();
    (sum / a.len().max(1) as f64).sqrt()
}

/// Air drag while the cloth at rest settles, N·s/m³ (10× the material's).
pub const SETTLING_AIR_DRAG: f32 = 5.0;

/// Relative error of the support force of a cloth hanging from its top edge: settled for 2 s
/// with steps of `h` under heavy air drag ([`SETTLING_AIR_DRAG`]), then the force the pins
/// carry (their springs' pull and their own weight) averaged over 1 s with the material's
/// drag, against the total weight. The mean support differs from the weight by the change of
/// momentum over that second, which the settling makes negligible (below 10⁻⁶ of the weight
/// for RK4 at 1/480 s; without it, 10⁻³ after 2 s and 3·10⁻⁵ after 4 s), so what remains
/// is the method's own error: an explicit method's equilibrium balances the spring forces
/// exactly, a method that does not solve its constraints fully (XPBD with one pass per
/// substep) carries a different load.
pub fn cloth_at_rest_error(size: u32, integrator: Integrator, h: f32) -> f64 {
    cloth_at_rest_run(size, integrator, h).0
}

/// [`cloth_at_rest_error`] and what the run cost (3 simulated seconds).
pub fn cloth_at_rest_run(size: u32, integrator: Integrator, h: f32) -> (f64, GameCost) {
    let mut cost = GameCost::default();
    let mut sim = raw_cloth(
        ClothBuilder::grid(size, size, 0.05).pin_top_edge(),
        integrator,
        h,
    );
    // Settle under 10× the air drag (about critical damping of the slowest swing), then
    // measure with the material's own drag.
    let material = *sim.material();
    let settling = BurnMaterial {
        air_drag: SETTLING_AIR_DRAG,
        ..material
    };
    sim.set_material(settling).expect("settling drag is valid");
    if !run_for(&mut sim, 2.0, h, &mut cost) {
        return (f64::NAN, cost);
    }
    sim.set_material(material).expect("the material was valid");
    let pinned_springs: Vec<usize> = (0..sim.springs.len())
        .filter(|&s| {
            sim.particles.is_pinned(sim.springs.a[s] as usize)
                || sim.particles.is_pinned(sim.springs.b[s] as usize)
        })
        .collect();
    let weight: f64 = sim
        .particles
        .mass
        .iter()
        .map(|&m| f64::from(m * sim.environment().gravity.length()))
        .sum();
    // Sampled at the end of each frame, as a game would read it.
    let frame = frame_for(h).0;
    let frames = (1.0 / frame).round() as usize;
    let mut support = 0.0f64;
    for _ in 0..frames {
        let report = sim.step(frame);
        cost.add(&report);
        if !sim.particles.is_finite() {
            return (f64::NAN, cost);
        }
        support += f64::from(support_force(&sim, &pinned_springs).y);
    }
    (((support / frames as f64 - weight) / weight).abs(), cost)
}

/// The force the world applies to the pinned particles: minus the pull of the springs in
/// `springs` on them, minus their own weight.
fn support_force(sim: &ClothSim, springs: &[usize]) -> Vec3 {
    let p = &sim.particles;
    let gravity = sim.environment().gravity;
    let coefficients =
        SpringCoefficients::from_material(sim.material(), sim.topology.particle_mass);
    let mut support = Vec3::ZERO;
    for &s in springs {
        let (a, b) = (sim.springs.a[s] as usize, sim.springs.b[s] as usize);
        let force_on_a = spring_force(
            p.position[a],
            p.position[b],
            p.velocity[a],
            p.velocity[b],
            sim.springs.rest_length[s],
            coefficients.law(sim.springs.kind[s]),
        );
        if p.is_pinned(a) {
            support -= force_on_a;
        }
        if p.is_pinned(b) {
            support += force_on_a;
        }
    }
    for i in 0..p.len() {
        if p.is_pinned(i) {
            support -= gravity * p.mass[i];
        }
    }
    support
}

/// Maximum error, relative to the amplitude, of a Gaussian hot spot (σ = 5 cm, 500 °C)
/// after spreading for 2 s with diffusivity 2·10⁻⁴ m²/s on a 0.64 m grid of `spacing`, with
/// time steps of dx²/(8α).
pub fn heat_diffusion_error(spacing: f32) -> f64 {
    let n = ((0.64 / spacing).round() as u32 + 1).max(3);
    let parts = ClothBuilder::grid(n, n, spacing)
        .build(&BurnMaterial::CLOTH, Affine3A::IDENTITY)
        .expect("heat grid is valid");
    let p = &parts.particles;
    let centre = p.position[(n as usize / 2) * n as usize + n as usize / 2];
    let (alpha, s, amplitude, t_end) = (2e-4f64, 0.05f64, 500.0f64, 2.0f32);
    let gaussian = |x: Vec3, width: f64| {
        20.0 + amplitude * s * s / width
            * (-f64::from((x - centre).length_squared()) / (2.0 * width)).exp()
    };
    let mut temperature: Vec<f32> = p
        .position
        .iter()
        .map(|&x| gaussian(x, s * s) as f32)
        .collect();
    let params = PhysicalHeat {
        diffusivity: alpha as f32,
        convection: 0.0,
        cooling: 0.0,
        burn_heating: 0.0,
    };
    let air = Air {
        temperature: 20.0,
        up: Vec3::Y,
    };
    let mut delta = Vec::new();
    // A time step in fixed proportion to dx² (half the stability limit), so the time and
    // space errors shrink together as O(dx²).
    let steps = (f64::from(t_end) / (0.125 * f64::from(spacing * spacing) / alpha)).ceil() as usize;
    let h = t_end / steps as f32;
    for _ in 0..steps {
        conduction_step(
            &parts.springs,
            &p.position,
            &p.mass,
            &mut temperature,
            &p.state,
            &params,
            air,
            &mut delta,
            h,
        );
    }
    let width = s * s + 2.0 * alpha * f64::from(t_end);
    let worst = p
        .position
        .iter()
        .zip(&temperature)
        .map(|(&x, &t)| (f64::from(t) - gaussian(x, width)).abs())
        .fold(0.0, f64::max);
    worst / amplitude
}

/// The heat problem's method name.
pub const HEAT_METHOD: &str = "explicit conduction";

/// Step of the swinging cloth's RK4 reference: a quarter of the smallest swept step.
pub const REFERENCE_STEP_DIVISOR: f32 = 4.0;

/// Runs the whole sweep. Cloth problems are timed per simulated second; the swinging
/// cloth's reference is RK4 at [`REFERENCE_STEP_DIVISOR`] times smaller than the smallest
/// swept step.
pub fn run(sweep: &Sweep) -> Vec<Sample> {
    let mut samples = Vec::new();
    let smallest = sweep.steps.iter().copied().fold(f32::INFINITY, f32::min);
    let reference = swinging_cloth_positions(
        sweep.cloth_size,
        Integrator::Rk4,
        smallest / REFERENCE_STEP_DIVISOR,
    )
    .expect("the fine RK4 reference is stable");
    for &integrator in &sweep.integrators {
        for &h in &sweep.steps {
            let method = integrator.name();
            let mut push = |problem, (error, seconds): (f64, f64), simulated: f64| {
                let blew_up = !error.is_finite();
                samples.push(Sample {
                    problem,
                    method,
                    parameter: h,
                    error: if blew_up { f64::NAN } else { error },
                    cost: seconds / simulated,
                    blew_up,
                });
            };
            push(
                Problem::Spring,
                timed(sweep.repeats, || spring_error(integrator, h)),
                1.0,
            );
            push(
                Problem::FreeFall,
                timed(sweep.repeats, || free_fall_error(integrator, h)),
                1.0,
            );
            // Cloth runs report their own game cost per simulated second (see the module
            // docs), so they are pushed per 1 simulated second.
            let (positions, seconds) = timed_cloth(sweep.repeats, || {
                swinging_cloth_run(sweep.cloth_size, integrator, h)
            });
            let error = positions.map_or(f64::NAN, |p| rms_difference(&p, &reference));
            push(Problem::SwingingCloth, (error, seconds), 1.0);
            push(
                Problem::ClothAtRest,
                timed_cloth(sweep.repeats, || {
                    cloth_at_rest_run(sweep.cloth_size, integrator, h)
                }),
                3.0,
            );
        }
    }
    for &spacing in &sweep.heat_spacings {
        let (error, seconds) = timed(sweep.repeats, || heat_diffusion_error(spacing));
        samples.push(Sample {
            problem: Problem::HeatDiffusion,
            method: HEAT_METHOD,
            parameter: spacing,
            error,
            cost: seconds / 2.0,
            blew_up: !error.is_finite(),
        });
    }
    samples
}

/// Least-squares slope of log(error) against log(parameter) over the samples of one problem
/// and method that did not blow up and lie above `floor` (f32 rounding); `None` with fewer
/// than two such points.
pub fn fitted_order(samples: &[Sample], problem: Problem, method: &str, floor: f64) -> Option<f64> {
    let points: Vec<(f64, f64)> = samples
        .iter()
        .filter(|s| s.problem == problem && s.method == method && !s.blew_up && s.error > floor)
        .map(|s| (f64::from(s.parameter).ln(), s.error.ln()))
        .collect();
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The largest step (from 1/30 s, halving) at which the swinging cloth of `size`² particles
/// at game stiffness runs 2 s in substeps of that step and stays finite with no spring
/// stretched past twice its rest length. `None` if even 1/7680 s fails.
pub fn largest_stable_step(size: u32, integrator: Integrator) -> Option<f32> {
    (0..9).map(|k| 1.0 / (30.0 * 2f32.powi(k))).find(|&h| {
        let mut sim = swinging_cloth(size, integrator, h);
        run_for(&mut sim, 2.0, h, &mut GameCost::default())
            && sim
                .springs
                .max_stretch(&sim.particles.position, &sim.particles.state, |_| true)
                <= 2.0
    })
}

/// The cheapest run of `problem` whose error is at most `target` and that did not blow up:
/// the work-precision answer to "what is the least I can pay for this accuracy". Runs whose
/// cost is within 10 % of the cheapest count as equally cheap (timing noise is about that),
/// and the most accurate of them is returned.
pub fn cheapest(samples: &[Sample], problem: Problem, target: f64) -> Option<&Sample> {
    let meets = |s: &&Sample| s.problem == problem && !s.blew_up && s.error <= target;
    let least = samples
        .iter()
        .filter(meets)
        .map(|s| s.cost)
        .min_by(f64::total_cmp)?;
    samples
        .iter()
        .filter(meets)
        .filter(|s| s.cost <= least * 1.1)
        .min_by(|a, b| a.error.total_cmp(&b.error))
}

/// Error targets of the "cheapest run" table.
pub const ERROR_TARGETS: [f64; 4] = [1e-1, 1e-2, 1e-3, 1e-4];

/// The samples as CSV, one row per sample.
pub fn csv(samples: &[Sample]) -> String {
    let mut out =
        String::from("problem,method,parameter,error,seconds_per_simulated_second,blew_up\n");
    for s in samples {
        let _ = writeln!(
            out,
            "{},{},{:e},{:e},{:e},{}",
            s.problem.name(),
            s.method,
            s.parameter,
            s.error,
            s.cost,
            s.blew_up
        );
    }
    out
}

/// A Markdown report: per problem a table of error and cost per method and parameter, the
/// fitted orders, and the largest stable steps.
pub fn markdown(samples: &[Sample], stable: &[(Integrator, Option<f32>)]) -> String {
    let mut out = String::new();
    for problem in Problem::ALL {
        let rows: Vec<&Sample> = samples.iter().filter(|s| s.problem == problem).collect();
        if rows.is_empty() {
            continue;
        }
        let _ = writeln!(
            out,
            "### {}\n\nError: {}. Cost: wall-clock ms per simulated second (median).\n",
            problem.name().replace('_', " "),
            problem.error_label()
        );
        let mut parameters: Vec<f32> = rows.iter().map(|s| s.parameter).collect();
        parameters.sort_by(|a, b| b.total_cmp(a));
        parameters.dedup();
        let mut methods: Vec<&str> = rows.iter().map(|s| s.method).collect();
        methods.dedup();
        let _ = write!(out, "| method | order |");
        for p in &parameters {
            let _ = write!(out, " {} |", format_parameter(problem, *p));
        }
        let _ = write!(out, "\n|---|---|");
        for _ in &parameters {
            out.push_str("---|");
        }
        out.push('\n');
        for method in methods {
            let order = fitted_order(samples, problem, method, problem.roundoff_floor())
                .map_or("–".to_owned(), |o| format!("{o:.2}"));
            let _ = write!(out, "| {method} | {order} |");
            for p in &parameters {
                match rows
                    .iter()
                    .find(|s| s.method == method && s.parameter == *p)
                {
                    Some(s) if s.blew_up => {
                        let _ = write!(out, " blew up ({:.2} ms) |", s.cost * 1e3);
                    }
                    Some(s) => {
                        let _ = write!(out, " {:.1e} ({:.2} ms) |", s.error, s.cost * 1e3);
                    }
                    None => out.push_str(" |"),
                }
            }
            out.push('\n');
        }
        out.push('\n');
    }
    out.push_str(
        "### cheapest run per error target\n\n\
         The run with the least wall time per simulated second whose error is within the target \
         (runs within 10 % of that cost count as ties; the most accurate tie is shown).\n\n\
         | problem |",
    );
    for target in ERROR_TARGETS {
        let _ = write!(out, " error ≤ {target:.0e} |");
    }
    out.push_str("\n|---|");
    for _ in ERROR_TARGETS {
        out.push_str("---|");
    }
    out.push('\n');
    for problem in Problem::ALL {
        if !samples.iter().any(|s| s.problem == problem) {
            continue;
        }
        let _ = write!(out, "| {} |", problem.name().replace('_', " "));
        for target in ERROR_TARGETS {
            match cheapest(samples, problem, target) {
                Some(s) => {
                    let _ = write!(
                        out,
                        " {} at {} ({:.2} ms) |",
                        s.method,
                        format_parameter(problem, s.parameter),
                        s.cost * 1e3
                    );
                }
                None => out.push_str(" none swept |"),
            }
        }
        out.push('\n');
    }
    out.push('\n');
    if !stable.is_empty() {
        out.push_str(
            "### largest stable step, swinging cloth at game stiffness\n\n\
             One substep per step, 2 s, finite and no spring past 2× its rest length.\n\n\
             | method | largest stable step | substeps per 1/60 s frame |\n|---|---|---|\n",
        );
        for (integrator, step) in stable {
            let (step, substeps) = match step {
                Some(h) => (
                    format!("1/{:.0} s", 1.0 / h),
                    format!("{}", ((1.0 / 60.0) / h).ceil().max(1.0)),
                ),
                None => ("below 1/7680 s".to_owned(), "> 128".to_owned()),
            };
            let _ = writeln!(out, "| {} | {step} | {substeps} |", integrator.name());
        }
    }
    out
}

fn format_parameter(problem: Problem, p: f32) -> String {
    match problem {
        Problem::HeatDiffusion => format!("dx {:.1} mm", p * 1e3),
        _ => format!("1/{:.0} s", 1.0 / p),
    }
}

/// Writes `accuracy.csv` and `accuracy.md` into `dir` (created if missing) and returns their
/// paths.
pub fn write_tables(
    dir: &std::path::Path,
    samples: &[Sample],
    stable: &[(Integrator, Option<f32>)],
) -> std::io::Result<[std::path::PathBuf; 2]> {
    std::fs::create_dir_all(dir)?;
    let csv_path = dir.join("accuracy.csv");
    std::fs::write(&csv_path, csv(samples))?;
    let md_path = dir.join("accuracy.md");
    std::fs::write(&md_path, markdown(samples, stable))?;
    Ok([csv_path, md_path])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cheapest_run_meets_the_target_and_skips_blow_ups() {
        let sample = |method, error: f64, cost, blew_up| Sample {
            problem: Problem::Spring,
            method,
            parameter: 0.01,
            error,
            cost,
            blew_up,
        };
        let samples = [
            sample("slow", 1e-4, 1.0, false),
            sample("fast", 1e-2, 0.1, false),
            sample("broken", f64::NAN, 0.01, true),
            sample("middle", 1e-3, 0.5, false),
        ];
        assert_eq!(
            cheapest(&samples, Problem::Spring, 1e-2).unwrap().method,
            "fast"
        );
        assert_eq!(
            cheapest(&samples, Problem::Spring, 1e-3).unwrap().method,
            "middle"
        );
        assert_eq!(
            cheapest(&samples, Problem::Spring, 1e-4).unwrap().method,
            "slow"
        );
        assert!(cheapest(&samples, Problem::Spring, 1e-5).is_none());
        // Within 10 % of the cheapest, the more accurate run wins.
        let tied = [
            sample("noisy", 1e-2, 1.00, false),
            sample("accurate", 1e-3, 1.05, false),
        ];
        assert_eq!(
            cheapest(&tied, Problem::Spring, 1e-1).unwrap().method,
            "accurate"
        );
        assert!(cheapest(&samples, Problem::FreeFall, 1.0).is_none());
    }

    #[test]
    fn reference_problems_converge_to_their_exact_answers() {
        // Spring and free fall: symplectic Euler's first-order error halves with the step.
        let coarse = spring_error(Integrator::SymplecticEuler, 1.0 / 200.0);
        let fine = spring_error(Integrator::SymplecticEuler, 1.0 / 400.0);
        assert!((coarse / fine - 2.0).abs() < 0.3, "{coarse} {fine}");
        // Free fall: symplectic Euler is off by g·h·t/2, RK4 exact to rounding.
        let h = 1.0 / 100.0;
        let error = free_fall_error(Integrator::SymplecticEuler, h);
        assert!((error - 9.81 * 0.01 / 2.0).abs() < 1e-3, "{error}");
        assert!(free_fall_error(Integrator::Rk4, h) < 1e-5);
        // Heat: halving the spacing cuts the error about fourfold (second order).
        let (e1, e2) = (heat_diffusion_error(0.02), heat_diffusion_error(0.01));
        assert!(e2 < e1 / 3.0, "{e1} {e2}");
    }

    #[test]
    fn a_settled_cloth_hangs_on_its_pins_with_its_weight() {
        let error = cloth_at_rest_error(8, Integrator::SymplecticEuler, 1.0 / 600.0);
        assert!(error < 0.02, "support off by {error}");
    }

    #[test]
    fn orders_are_fitted_from_log_log_slopes() {
        let samples: Vec<Sample> = [0.1f32, 0.05, 0.025]
            .iter()
            .map(|&h| Sample {
                problem: Problem::Spring,
                method: "m",
                parameter: h,
                error: 3.0 * f64::from(h).powi(2),
                cost: 1.0,
                blew_up: false,
            })
            .collect();
        let order = fitted_order(&samples, Problem::Spring, "m", 0.0).unwrap();
        assert!((order - 2.0).abs() < 1e-6);
        assert_eq!(fitted_order(&samples[..1], Problem::Spring, "m", 0.0), None);
    }
}
