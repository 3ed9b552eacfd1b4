//! Extended position-based dynamics with small steps: the default solver.
//!
//! Each frame of `dt` seconds runs a fixed number of substeps of `h = dt / n` (Macklin et al.
//! 2019, "Small Steps in Physics Simulation"); each substep predicts positions from velocities
//! and outside forces, projects every spring once as a compliant distance constraint with
//! Macklin's damping (Macklin et al. 2016; the bending springs, the softest, in every other
//! substep when the frame's substeps pair up, with the compliance of both), holds the springs heat has shrunk to Provot's
//! limit ([`StretchLimit`]), applies tethers and colliders, and takes the velocity from the
//! corrections. Stable at any stiffness and step; first order.
//!
//! | piece | what it holds |
//! |---|---|
//! | [`lanes`] | a grid's particles in quarter grids and its springs in long lanes, in bands |
//! | `kernel` | the projection loops over plain `f32` arrays, four springs at a time |
//! | `adjacency` | each particle's springs, so a burn or a pin touches only those |
//! | `stretch_limit` | Provot's limit on the heated springs, sorted into the grid's bands |
//! | `staggered` | arrays that start at chosen offsets within a page, so loads and stores to separate arrays do not alias |
//! | [`XpbdSolver`] | a cloth's state as separate arrays, and the substep loop |
//!
//! Where its accuracy ends: one constraint pass per substep does not solve stiff springs
//! exactly, so a long stiff cloth stretches more under its weight than the force model says
//! (tethers bound that), and shrinking springs would stretch the cloth around them rather
//! than pull it in (the stretch limit on them fixes that; see the README's accuracy report).

mod adjacency;
mod kernel;
pub mod lanes;
mod solver;
mod staggered;
mod stretch_limit;

pub use solver::{StretchLimit, Surroundings, XpbdSolver};
