//! Closed-form models (to be written).
