//! The picture formats a plot path may name, read from its extension.
//!
//! A plot is written as SVG or PNG; any other extension (`.pdf`, `.jpg`, none) is refused with a
//! message naming the supported ones, instead of silently writing SVG under a misleading name.
//! Front ends call [`PlotFormat::from_path`] before any work starts, so a typo costs nothing;
//! the figures' `save` functions check again.

use std::path::Path;

use crate::ReportError;

/// The format of a plot file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotFormat {
    /// Scalable vector graphics (`.svg`).
    Svg,
    /// Portable network graphics (`.png`, a bitmap).
    Png,
}

/// The extensions a plot path may have, for messages.
pub const SUPPORTED_EXTENSIONS: &str = ".svg, .png";

impl PlotFormat {
    /// The format named by `path`'s extension (case-insensitive), or
    /// [`ReportError::PlotFormat`] naming the supported extensions.
    pub fn from_path(path: &Path) -> Result<PlotFormat, ReportError> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("svg") => Ok(PlotFormat::Svg),
            Some("png") => Ok(PlotFormat::Png),
            _ => Err(ReportError::PlotFormat { path: path.to_path_buf() }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind;

    #[test]
    fn svg_and_png_are_the_formats() {
        assert_eq!(PlotFormat::from_path(Path::new("a/b.svg")).unwrap(), PlotFormat::Svg);
        assert_eq!(PlotFormat::from_path(Path::new("B.PNG")).unwrap(), PlotFormat::Png);
        for bad in ["x.pdf", "x.jpg", "x", "x.svg.gz"] {
            let e = PlotFormat::from_path(Path::new(bad)).unwrap_err();
            let message = e.to_string();
            assert!(message.contains(bad) && message.contains(".svg, .png"), "{message}");
            assert!(e.is_input_error(), "{bad}");
        }
    }
}
