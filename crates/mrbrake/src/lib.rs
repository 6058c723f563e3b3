//! mrbrake: design, simulate and characterise magnetorheological (MR) fluid brakes for haptic
//! devices — the one crate a Rust program (and the Python binding) depends on.
//!
//! This crate re-exports mrbrake's library crates under short names, as ripgrep's `grep` crate
//! does for its parts; each module's own documentation is the reference. Its own code is what
//! needs several of them at once: [`problem_file`] picks the physics of a `fem solve` problem
//! file (magnetics or heat) and solves it, for the CLI and the Python package alike.
//!
//! # Brief overview
//!
//! Two data flows, one crate per stage:
//!
//! ```text
//! spec (TOML) ─► geometry ─► mesh ─► field (A_phi, B) ─► torque ─► design studies
//!   design        design      fem     magnetics           design    explore (+ optim, store)
//!
//! rig logs (CSV) ─► identification ─► models ─► controller ─► haptic simulation
//!   sim::rig          sysid             sysid     control       sim::haptic
//! ```
//!
//! - [`units`]: quantities with unit suffixes (`22.5mm`, `0.46T`) parsed to SI.
//! - [`materials`]: B-H curves, MR-fluid yield stress and viscosity, copper wire, with provenance.
//! - [`fem`]: the physics-free finite-element core (mesh, basis, assembly of user forms,
//!   constraints, sparse solves, Newton).
//! - [`magnetics`]: axisymmetric non-linear magnetostatics (A_phi) on the core, post-processing;
//!   magnetodynamics (transient eddy currents, coil circuits, time-harmonic and small-signal).
//! - [`heat`]: axisymmetric heat conduction on the same core (steady, transient, Joule coupling).
//! - [`design`]: brake specifications, geometry, the thesis's closed forms, the brake analysis.
//! - [`optim`], [`store`], [`explore`]: optimisers, the results store, design studies.
//! - [`uq`]: uncertainty quantification: input laws, scrambled Sobol' propagation, bands,
//!   polynomial-chaos Sobol' indices, bounded least-squares calibration with identifiability.
//! - [`sysid`]: characterisation logs, hysteresis fits, frequency responses, transfer functions.
//! - [`control`]: the `no_std` real-time directional brake controller.
//! - [`sim`]: the virtual test rig and the haptic simulation.
//! - [`device`]: a designed brake as a device: the brake model file its analyses predict.
//! - [`report`]: plots and report composition shared by the front ends.
//! - [`problem_file`]: any problem file of `mrbrake fem solve`, solved by its physics.
//! - [`observe`]: the one observer shape (per step, point, generation or design, with a stop
//!   request) of every iterative algorithm.
//! - [`error`]: the [`ErrorKind`] every library error reports ([`Kind`]), from which front ends
//!   choose exit codes and exceptions.
//!
//! ```
//! use mrbrake::units::{Dimension, parse};
//! // 22.5 mm in SI, and the initial permeability of the thesis's flux-path steel.
//! assert!((parse("22.5mm", Dimension::Length)? - 0.0225).abs() < 1e-15);
//! let steel = mrbrake::materials::library::get("steel-1008")?;
//! let curve = steel.magnetic.bh_curve().expect("a tabulated B-H curve");
//! assert!(curve.initial_relative_permeability() > 100.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod problem_file;

pub use mrbrake_control as control;
pub use mrbrake_design as design;
pub use mrbrake_device as device;
pub use mrbrake_error as error;
pub use mrbrake_explore as explore;
pub use mrbrake_fem as fem;
pub use mrbrake_heat as heat;
pub use mrbrake_magnetics as magnetics;
pub use mrbrake_materials as materials;
pub use mrbrake_observe as observe;
pub use mrbrake_optim as optim;
pub use mrbrake_report as report;
pub use mrbrake_sim as sim;
pub use mrbrake_store as store;
pub use mrbrake_sysid as sysid;
pub use mrbrake_units as units;
pub use mrbrake_uq as uq;

pub use mrbrake_error::{ErrorKind, Kind};
