//! Maps an error chain to the process exit code: 2 for bad input, 1 for numerical or internal failure.

use mrbrake_error::Kind as _;

/// An error the command itself found in its input (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// Exit code for an error: 2 if anything in the chain is an input error, else 1.
pub fn code_for(err: &anyhow::Error) -> i32 {
    for cause in err.chain() {
        let input = cause.downcast_ref::<InputError>().is_some()
            || cause.downcast_ref::<mrbrake_units::UnitError>().is_some()
            || cause
                .downcast_ref::<std::io::Error>()
                .is_some_and(|e| e.kind() == std::io::ErrorKind::NotFound)
            || cause
                .downcast_ref::<mrbrake_materials::MaterialError>()
                .is_some_and(|e| e.is_input_error())
            || cause.downcast_ref::<mrbrake_fem::FemError>().is_some_and(|e| e.is_input_error())
            || cause
                .downcast_ref::<mrbrake_magnetics::MagneticsError>()
                .is_some_and(|e| e.is_input_error())
            || cause
                .downcast_ref::<mrbrake_design::DesignError>()
                .is_some_and(|e| e.is_input_error())
            || cause
                .downcast_ref::<mrbrake_sysid::SysidError>()
                .is_some_and(|e| e.is_input_error())
            || cause.downcast_ref::<mrbrake_sim::SimError>().is_some_and(|e| e.is_input_error())
            || cause
                .downcast_ref::<mrbrake_report::ReportError>()
                .is_some_and(|e| e.is_input_error())
            || cause
                .downcast_ref::<mrbrake_store::StoreError>()
                .is_some_and(|e| e.is_input_error())
            || cause
                .downcast_ref::<mrbrake_explore::ExploreError>()
                .is_some_and(|e| e.is_input_error());
        if input {
            return 2;
        }
    }
    1
}
