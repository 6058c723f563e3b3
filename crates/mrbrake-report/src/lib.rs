//! Reports for mrbrake: text, JSON, plots (SVG/PNG via plotters) and output folders, composed once
//! for every front end.
//!
//! Brief overview: [`write_atomic`] writes any output file through a temporary file and a rename,
//! so a reader never sees half a file; [`chart`] draws XY line/scatter charts (linear or log axes,
//! one or several stacked panels) that the Bode, hysteresis, torque–current and time-history plots
//! build on, and [`field_map`] the |B| map with flux lines. The reports:
//!
//! * [`analysis`]: a brake analysis (text; torque–current, gap and field-map plots);
//! * [`demag`]: the demagnetising release waveforms judged on the predicted hysteresis loop;
//! * [`formula`]: the thesis's closed-form torque and coil models;
//! * [`geometry`]: a brake geometry exported for Gmsh;
//! * [`materials`]: the material library (list, curves, provenance);
//! * [`study`]: sweeps, optimisations and their output folder, store merges, the thesis's tables;
//! * [`identification`]: characterisation, frequency response, transfer-function estimate;
//! * [`rig`]: the virtual rig's output folder;
//! * [`haptic`]: the haptic simulation (wall runs, Z-width map);
//! * [`fem`]: magnetic solves of problem files (`fem solve`: static, transient, harmonic);
//! * [`heat`]: heat solves (`fem solve` with `physics = "heat"`);
//! * [`response`]: a brake's predicted step and frequency response (`mrbrake response`);
//! * [`thermal`]: a brake's temperatures, warm-up and current rating (`mrbrake thermal`);
//! * [`uncertainty`]: an uncertainty propagation's bands and sensitivities (`mrbrake
//!   uncertainty`: JSON, text, the torque band and tornado plots, the document `mrbrake report`
//!   reads back);
//! * [`html`]: self-contained HTML reports of a design, a study and a characterisation.
//!
//! The command-line program only parses, calls and prints or writes what these compose (as
//! `String`s, `serde_json::Value`s, figures and folders), so every front end (CLI, Python, HTML)
//! shares one presentation.

pub mod analysis;
pub mod atomic;
pub mod bode;
pub mod calibration;
pub mod chart;
pub mod demag;
pub mod fem;
pub mod field_map;
pub mod formula;
pub mod geometry;
pub mod haptic;
pub mod heat;
pub mod html;
pub mod hysteresis;
pub mod identification;
pub mod materials;
pub mod operator;
pub mod pareto;
pub mod plot_format;
pub mod predicted_loop;
pub mod reference;
pub mod response;
pub mod rig;
pub mod study;
pub mod thermal;
pub mod uncertainty;
pub mod wording;

pub use atomic::write_atomic;

/// Errors of this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// Writing an output file failed (directory missing, permission, disk full).
    #[error("cannot write '{path}'")]
    Io {
        /// The file that could not be written.
        path: std::path::PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The data cannot be plotted (empty, non-finite, or a non-positive value on a log axis).
    #[error("cannot plot: {0}")]
    Data(String),
    /// The plotting backend failed.
    #[error("plotting failed: {0}")]
    Backend(String),
    /// A plot path names a format that is not drawn (see [`plot_format`]).
    #[error(
        "'{}': unsupported plot format; use one of the extensions {}",
        path.display(),
        plot_format::SUPPORTED_EXTENSIONS
    )]
    PlotFormat {
        /// The plot path given.
        path: std::path::PathBuf,
    },
    /// An output folder could not be created.
    #[error("cannot create output folder '{}'", path.display())]
    Folder {
        /// The folder.
        path: std::path::PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// A report could not be turned into JSON (a bug: every report serialises).
    #[error("cannot compose the JSON report")]
    Json(#[from] serde_json::Error),
    /// Records of a results store could not be written as CSV.
    #[error(transparent)]
    Store(#[from] mrbrake_store::StoreError),
    /// A model drawn beside the data (a transfer function) could not be built.
    #[error(transparent)]
    Model(#[from] mrbrake_sysid::SysidError),
    /// An input document (an `uncertainty --json` file given to `mrbrake report`) cannot be read
    /// or is not such a document.
    #[error("'{}': {detail}", path.display())]
    Document {
        /// The file.
        path: std::path::PathBuf,
        /// What is wrong.
        detail: String,
        /// The read error, when reading failed.
        #[source]
        source: Option<std::io::Error>,
    },
    /// The analysis of a design page failed (`html::request`).
    #[error(transparent)]
    Design(#[from] Box<mrbrake_design::DesignError>),
    /// The thermal analysis of a design page failed.
    #[error(transparent)]
    Thermal(#[from] Box<mrbrake_design::thermal::ThermalError>),
    /// The store or problem of a study page cannot be read.
    #[error(transparent)]
    Study(#[from] Box<mrbrake_explore::ExploreError>),
}

impl From<mrbrake_design::DesignError> for ReportError {
    fn from(e: mrbrake_design::DesignError) -> Self {
        Self::Design(Box::new(e))
    }
}

impl From<mrbrake_design::thermal::ThermalError> for ReportError {
    fn from(e: mrbrake_design::thermal::ThermalError) -> Self {
        Self::Thermal(Box::new(e))
    }
}

impl From<mrbrake_explore::ExploreError> for ReportError {
    fn from(e: mrbrake_explore::ExploreError) -> Self {
        Self::Study(Box::new(e))
    }
}

impl mrbrake_error::Kind for ReportError {
    /// An output path that cannot be written takes the kind of its I/O error (a missing directory
    /// or a denied permission is input); unplottable data is input; a backend failure is internal;
    /// a store's error keeps its own kind.
    fn kind(&self) -> mrbrake_error::ErrorKind {
        use mrbrake_error::{ErrorKind, Kind};
        match self {
            Self::Io { source, .. } | Self::Folder { source, .. } => Kind::kind(source),
            Self::Data(_) | Self::PlotFormat { .. } => ErrorKind::Input,
            Self::Document { source, .. } => source.as_ref().map_or(ErrorKind::Input, Kind::kind),
            Self::Backend(_) | Self::Json(_) => ErrorKind::Internal,
            Self::Store(e) => e.kind(),
            Self::Model(e) => e.kind(),
            Self::Design(e) => e.kind(),
            Self::Thermal(e) => e.kind(),
            Self::Study(e) => e.kind(),
        }
    }
}
