//! Progress bars for long commands (seeded starts, grading a class): drawn on a terminal's
//! stderr only, hidden in pipes and CI logs. Without the `cli` feature (the WebAssembly build
//! runs the commands in a browser, which has no terminal) the bar does nothing.

/// A bar counting `len` steps, labelled `what`.
pub struct Progress {
    #[cfg(feature = "cli")]
    bar: indicatif::ProgressBar,
}

impl Progress {
    /// A new bar: `what {pos}/{len}`.
    #[cfg_attr(not(feature = "cli"), allow(unused_variables))]
    pub fn new(what: &str, len: usize) -> Self {
        #[cfg(feature = "cli")]
        {
            let bar = indicatif::ProgressBar::new(len as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template(&format!(
                    "{what} {{pos}}/{{len}} {{wide_bar}} {{eta}}"
                ))
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            Progress { bar }
        }
        #[cfg(not(feature = "cli"))]
        Progress {}
    }

    /// One step done.
    pub fn inc(&self) {
        #[cfg(feature = "cli")]
        self.bar.inc(1);
    }

    /// All done: the bar disappears.
    pub fn finish(&self) {
        #[cfg(feature = "cli")]
        self.bar.finish_and_clear();
    }
}
