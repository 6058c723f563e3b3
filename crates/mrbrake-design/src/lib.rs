//! MR brake design: brake specifications, the geometry builder, meshing, the field analysis of a
//! brake, the thesis's closed-form torque models and coil formulas, and design studies.
//!
//! Brief overview, in data-flow order: [`spec`] reads a brake spec (TOML; the configuration carries
//! its working surfaces) and validates it once, assembling its [`geometry`] (tagged regions, fluid
//! gaps, coils) on the way; [`mesh_build`] meshes it (or [`geo_export`] writes a Gmsh `.geo`);
//! [`analysis`] solves the field over a current sweep and reduces it to torques, coil and
//! mechanics; [`response`] predicts how fast the torque follows the current (eddy currents in
//! the flux path, the coil circuit); [`hysteresis`] predicts the torque–current loop from the
//! steel's magnetic hysteresis and [`demag`] the remanent torque that demagnetising release
//! waveforms leave; [`formula`] holds the thesis's closed-form models; [`study`] re-runs the
//! thesis's comparison tables. Errors are one [`DesignError`], whose variants keep their kind (the
//! spec's invalid fields as a list, the solver's and mesher's errors wrapped typed).

pub mod analysis;
pub mod demag;
pub mod drag;
mod error;
pub mod forc;
pub mod formula;
pub mod geo_export;
pub mod geometry;
pub mod hysteresis;
pub mod material_factors;
pub mod mesh_build;
pub mod response;
pub mod spec;
pub mod study;
pub mod thermal;

pub use error::DesignError;
