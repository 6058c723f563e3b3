//! Surrogate-assisted (Bayesian) optimisation (work in progress).
pub mod gp;
mod local;
