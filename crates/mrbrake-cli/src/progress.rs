//! A progress bar with rate and ETA for long studies, drawn on stderr only when it is a terminal
//! (quiet in pipes, logs and batch jobs).

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use mrbrake_explore::Progress;

/// Shows [`Progress`] reports as a bar.
pub struct ProgressDisplay {
    bar: ProgressBar,
}

impl ProgressDisplay {
    /// A bar labelled `what`; hidden when stderr is not a terminal or `quiet` is set.
    pub fn new(what: &str, quiet: bool) -> Self {
        let bar = if quiet || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::new(0);
            // The template is a constant known to be valid; fall back to the default style if not.
            if let Ok(style) = ProgressStyle::with_template(
                "{prefix} [{bar:30}] {pos}/{len} designs, {per_sec}, ETA {eta} {msg}",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_prefix(what.to_string());
            bar
        };
        Self { bar }
    }

    /// Updates the bar.
    pub fn update(&mut self, p: &Progress) {
        self.bar.set_length(p.to_compute as u64);
        self.bar.set_position(p.computed as u64);
        self.bar.set_message(format!(
            "({} reused, {} infeasible, {} failed)",
            p.reused, p.infeasible, p.failed
        ));
    }

    /// Removes the bar.
    pub fn finish(&mut self) {
        self.bar.finish_and_clear();
    }
}
