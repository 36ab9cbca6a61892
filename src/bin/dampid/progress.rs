//! Progress bars on stderr (indicatif), hidden when stderr is not a terminal: the
//! library reports `progress(done, total)`, this file draws it.

use std::path::Path;

use dampid::model_file::{Job, Options};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar on stderr, hidden when stderr is not a terminal.
pub(crate) fn progress_bar(message: &'static str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template("{msg:>10} [{bar:40}] {percent:>3}% ({eta} left)")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
    bar.set_style(style);
    bar.set_message(message);
    bar
}

/// `progress(done, total)` drawn on `bar` (hidden when stderr is not a terminal).
pub(crate) fn on_bar(bar: &ProgressBar) -> impl Fn(u64, u64) + Sync + '_ {
    move |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    }
}

/// Loads a model file with a progress bar over simulating or reading its records.
pub(crate) fn load(path: &Path) -> anyhow::Result<Job> {
    let bar = progress_bar("records");
    let job = dampid::model_file::load(
        path,
        Options {
            progress: &on_bar(&bar),
            ..Default::default()
        },
    );
    bar.finish_and_clear();
    Ok(job?)
}
