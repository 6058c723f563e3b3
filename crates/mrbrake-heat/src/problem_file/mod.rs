//! The `physics = "heat"` problem files of `mrbrake fem solve`.
