//! Simple colliders the cloth rests on: spheres, capsules (a rod, a rail), planes (a floor).
//!
//! After each substep's integration and Provot correction, every free unburnt particle
//! inside a collider (plus a margin) is pushed out along the surface normal; its velocity
//! loses the part going into the surface, and its sliding part loses `friction` of itself per
//! [`FRICTION_PERIOD`] of contact (so the same over a frame whatever the substep count).
//! Colliders are rigid (their transform's scale is ignored).

use super::particles::Particles;
use bevy::reflect::Reflect;
use glam::{Affine3A, Vec3};

/// The shape of a collider in its own frame.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub enum ColliderShape {
    /// A ball of `radius` metres around the origin.
    Sphere {
        /// Radius, m.
        radius: f32,
    },
    /// A capsule along the local Y axis from `-half_length` to `half_length`, m.
    Capsule {
        /// Half the length of the axis segment, m.
        half_length: f32,
        /// Radius, m.
        radius: f32,
    },
    /// The half-space below the local XZ plane: particles stay on the +Y side.
    Plane,
}

impl ColliderShape {
    /// True for finite, non-negative dimensions.
    pub fn is_valid(&self) -> bool {
        match *self {
            Self::Sphere { radius } => radius.is_finite() && radius >= 0.0,
            Self::Capsule {
                half_length,
                radius,
            } => {
                half_length.is_finite() && half_length >= 0.0 && radius.is_finite() && radius >= 0.0
            }
            Self::Plane => true,
        }
    }
}

/// A collider placed in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldCollider {
    /// Shape in the collider's frame.
    pub shape: ColliderShape,
    /// World from collider frame (rigid).
    pub transform: Affine3A,
    /// Fraction of the sliding velocity removed per [`FRICTION_PERIOD`] of contact, in [0, 1].
    pub friction: f32,
}

impl WorldCollider {
    /// Signed distance from `point` to the surface and the outward unit normal there.
    pub fn distance(&self, point: Vec3) -> (f32, Vec3) {
        let origin = Vec3::from(self.transform.translation);
        match self.shape {
            ColliderShape::Sphere { radius } => {
                let offset = point - origin;
                let length = offset.length();
                let normal = if length > 1e-9 {
                    offset / length
                } else {
                    Vec3::Y
                };
                (length - radius, normal)
            }
            ColliderShape::Capsule {
                half_length,
                radius,
            } => {
                let axis = Vec3::from(self.transform.matrix3.y_axis).normalize_or(Vec3::Y);
                let along = (point - origin).dot(axis).clamp(-half_length, half_length);
                let offset = point - (origin + axis * along);
                let length = offset.length();
                let normal = if length > 1e-9 {
                    offset / length
                } else {
                    axis.any_orthonormal_vector()
                };
                (length - radius, normal)
            }
            ColliderShape::Plane => {
                let normal = Vec3::from(self.transform.matrix3.y_axis).normalize_or(Vec3::Y);
                ((point - origin).dot(normal), normal)
            }
        }
    }
}

/// The contact time a collider's `friction` is stated for: one frame at 60 Hz, s.
pub const FRICTION_PERIOD: f32 = 1.0 / 60.0;

/// The share of its sliding velocity a particle in contact keeps over a substep of `h`
/// seconds, when it loses `friction` of it per [`FRICTION_PERIOD`]: `(1 − friction)^(h / T)`.
/// A friction outside [0, 1] is clamped; NaN counts as none.
pub fn sliding_kept(friction: f32, h: f32) -> f32 {
    let friction = if friction.is_nan() {
        0.0
    } else {
        friction.clamp(0.0, 1.0)
    };
    (1.0 - friction).powf(h.max(0.0) / FRICTION_PERIOD)
}

/// Pushes every free, unburnt particle out of every collider to at least `margin` metres
/// from its surface, removing inward velocity and, over this substep of `h` seconds, the
/// collider's friction of the sliding velocity ([`sliding_kept`]).
pub fn resolve_collisions(
    particles: &mut Particles,
    colliders: &[WorldCollider],
    margin: f32,
    h: f32,
) {
    if colliders.is_empty() {
        return;
    }
    for i in 0..particles.len() {
        if particles.inv_mass[i] == 0.0 || particles.state[i].is_burnt() {
            continue;
        }
        for collider in colliders {
            let (distance, normal) = collider.distance(particles.position[i]);
            if distance >= margin || distance.is_nan() {
                continue;
            }
            particles.position[i] += normal * (margin - distance);
            let velocity = particles.velocity[i];
            let normal_speed = velocity.dot(normal);
            let tangential = velocity - normal * normal_speed;
            let kept = sliding_kept(collider.friction, h);
            particles.velocity[i] = tangential * kept + normal * normal_speed.max(0.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{BurnMaterial, ClothBuilder, ClothSim, GridPlane};

    #[test]
    fn distances_to_each_shape() {
        let sphere = WorldCollider {
            shape: ColliderShape::Sphere { radius: 1.0 },
            transform: Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
            friction: 0.0,
        };
        let (d, n) = sphere.distance(Vec3::new(0.0, 4.0, 0.0));
        assert!((d - 1.0).abs() < 1e-6 && (n - Vec3::Y).length() < 1e-6);
        // A capsule lying along X (local Y rotated onto X).
        let rod = WorldCollider {
            shape: ColliderShape::Capsule {
                half_length: 1.0,
                radius: 0.1,
            },
            transform: Affine3A::from_rotation_z(-core::f32::consts::FRAC_PI_2),
            friction: 0.0,
        };
        let (d, n) = rod.distance(Vec3::new(0.5, 0.6, 0.0));
        assert!(
            (d - 0.5).abs() < 1e-5 && (n - Vec3::Y).length() < 1e-5,
            "{d} {n}"
        );
        let (d, _) = rod.distance(Vec3::new(3.0, 0.0, 0.0));
        assert!((d - 1.9).abs() < 1e-5, "past the end cap: {d}");
        let floor = WorldCollider {
            shape: ColliderShape::Plane,
            transform: Affine3A::from_translation(Vec3::new(0.0, -1.0, 0.0)),
            friction: 0.5,
        };
        assert!((floor.distance(Vec3::new(5.0, -3.0, 2.0)).0 + 2.0).abs() < 1e-6);
    }

    #[test]
    fn a_dropped_cloth_comes_to_rest_on_the_floor_not_through_it() {
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(10, 10, 0.05).in_plane(GridPlane::Horizontal),
            BurnMaterial::COTTON,
            Affine3A::from_translation(Vec3::new(0.0, 0.5, 0.0)),
        )
        .unwrap();
        sim.colliders.push(WorldCollider {
            shape: ColliderShape::Plane,
            transform: Affine3A::IDENTITY,
            friction: 0.3,
        });
        for _ in 0..240 {
            sim.step(1.0 / 60.0);
        }
        let margin = sim.collision_margin();
        for p in &sim.particles.position {
            assert!(p.y >= margin - 1e-4, "below the floor: {p}");
            assert!(p.y < margin + 0.01, "not resting: {p}");
        }
    }

    /// A rod's grip per 1/60 s: what 0.8 per substep was at six substeps a frame.
    const ROD_FRICTION: f32 = 0.99;

    #[test]
    fn a_cloth_dropped_on_a_rod_drapes_over_it() {
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(15, 15, 0.04).in_plane(GridPlane::Horizontal),
            BurnMaterial::SILK,
            Affine3A::from_translation(Vec3::new(0.0, 0.3, 0.0)),
        )
        .unwrap();
        let rod = WorldCollider {
            shape: ColliderShape::Capsule {
                half_length: 1.0,
                radius: 0.03,
            },
            transform: Affine3A::from_rotation_x(core::f32::consts::FRAC_PI_2),
            friction: ROD_FRICTION,
        };
        sim.colliders.push(rod);
        for _ in 0..180 {
            sim.step(1.0 / 60.0);
        }
        let margin = sim.collision_margin();
        let centre = sim.topology.grid.unwrap().index(7, 7);
        let y = sim.particles.position[centre].y;
        assert!(
            (y - (0.03 + margin)).abs() < 0.01,
            "the middle rests on the rod: {y}"
        );
        let corner = sim.particles.position[0].y;
        assert!(corner < y - 0.1, "the sides hang down: {corner} vs {y}");
        for &p in &sim.particles.position {
            assert!(rod.distance(p).0 >= margin - 1e-3);
        }
    }

    /// Mean horizontal speed of a cloth resting on a floor of `friction` after it is pushed
    /// sideways at 1 m/s and left for three frames, stepped at `substep_rate` (XPBD) or by
    /// symplectic Euler.
    fn sliding_speed(friction: f32, substep_rate: f32, integrator: crate::sim::Integrator) -> f32 {
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(8, 8, 0.05).in_plane(GridPlane::Horizontal),
            BurnMaterial::COTTON,
            Affine3A::from_translation(Vec3::new(0.0, 0.02, 0.0)),
        )
        .unwrap();
        sim.update_settings(|s| {
            s.solver.integrator = integrator;
            s.solver.substep_rate = substep_rate;
        })
        .unwrap();
        sim.colliders.push(WorldCollider {
            shape: ColliderShape::Plane,
            transform: Affine3A::IDENTITY,
            friction,
        });
        for _ in 0..60 {
            sim.step(1.0 / 60.0);
        }
        sim.particles.velocity.fill(Vec3::X);
        for _ in 0..3 {
            sim.step(1.0 / 60.0);
        }
        let v = &sim.particles.velocity;
        v.iter().map(|v| v.x).sum::<f32>() / v.len() as f32
    }

    #[test]
    fn friction_takes_the_same_share_per_second_at_any_substep_count() {
        use crate::sim::Integrator;
        // 10 % per 1/60 s over three frames keeps 0.9³ = 0.729 of what sliding without
        // friction keeps (air drag and the cloth's own motion are the same in both).
        for (rate, integrator) in [
            (360.0, Integrator::Xpbd),
            (1440.0, Integrator::Xpbd),
            (360.0, Integrator::SymplecticEuler),
        ] {
            let ratio = sliding_speed(0.1, rate, integrator) / sliding_speed(0.0, rate, integrator);
            assert!(
                (ratio - 0.729).abs() < 0.03,
                "{integrator:?} at {rate} substeps/s kept {ratio} of its sliding speed"
            );
        }
        assert_eq!(sliding_kept(0.5, FRICTION_PERIOD), 0.5);
        assert_eq!(sliding_kept(f32::NAN, 0.01), 1.0);
        assert_eq!(sliding_kept(2.0, 0.01), 0.0);
    }
}
