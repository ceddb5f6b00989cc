//! ProgressReporter of long renders (CPU and GPU report through the same callback): a bar on a terminal,
//! or plain lines for logs and scripts.

use std::time::{Duration, Instant};

use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum ProgressMode {
    /// A bar on stderr when it is a terminal, once a render has run for a second.
    #[default]
    Auto,
    /// A line `progress: P% (done of total pixel-samples)` on stderr as soon as the first work
    /// is done and at each further whole percent (for logs and scripts).
    Lines,
    /// Nothing.
    None,
}

/// Reports progress the way `mode` says.
pub struct ProgressReporter {
    mode: ProgressMode,
    bar: ProgressBar,
    start: Instant,
    shown: bool,
    /// Lines mode: the last percentage printed.
    last_percent: Option<u64>,
}

impl ProgressReporter {
    pub fn new(label: &str, mode: ProgressMode) -> Self {
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{msg} [{bar:40}] {percent:>3}% {elapsed} (eta {eta})")
                .expect("valid template")
                .progress_chars("=> "),
        );
        bar.set_message(label.to_owned());
        Self {
            mode,
            bar,
            start: Instant::now(),
            shown: false,
            last_percent: None,
        }
    }

    pub fn update(&mut self, done: u64, total: u64) {
        match self.mode {
            ProgressMode::Auto => {
                self.bar.set_length(total);
                self.bar.set_position(done);
                if !self.shown && self.start.elapsed() > Duration::from_secs(1) && done < total {
                    self.bar.set_draw_target(ProgressDrawTarget::stderr());
                    self.shown = true;
                }
            }
            ProgressMode::Lines => {
                let percent = done * 100 / total.max(1);
                if done > 0 && self.last_percent.is_none_or(|p| percent > p) {
                    eprintln!("progress: {percent}% ({done} of {total} pixel-samples)");
                    self.last_percent = Some(percent);
                }
            }
            ProgressMode::None => {}
        }
    }

    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}
