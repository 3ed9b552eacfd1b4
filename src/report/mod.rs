//! Studies of the simulation that print tables: plain Rust over [`crate::sim`], shared by the
//! report examples and the tests that check them.
//!
//! | module | what it measures |
//! |---|---|
//! | [`stability`] | every integrator against stiff and extreme cases, raw and guarded |
//! | [`accuracy`] | error against run time of every integrator on reference problems |
//! | [`spread`] | fire spread speed by direction, material, heat model and grid spacing |

pub mod accuracy;
pub mod spread;
pub mod stability;
