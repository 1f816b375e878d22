//! The progress bar (indicatif) over [`monitor_host::Progress`].

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar on standard error (hidden when it is not a terminal).
pub struct Bar(ProgressBar);

impl Bar {
    /// A bar with no length yet.
    pub fn new() -> Self {
        let bar = ProgressBar::new(0);
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} routes {elapsed_precise} eta {eta}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Bar(bar)
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.0.finish_and_clear();
    }
}

impl Default for Bar {
    fn default() -> Self {
        Bar::new()
    }
}

impl monitor_host::Progress for Bar {
    fn start(&self, routes: usize) {
        self.0.set_length(routes as u64);
    }

    fn route_done(&self) {
        self.0.inc(1);
    }
}
