//! What the commands that call a flow share: the progress bar and Ctrl-C watched as a harness
//! observer ([`Watch`]), the flows' errors as messages naming the options ([`flow_error`]),
//! and the exit statuses of a stopped run ([`Interrupted`], 130) and of a verdict that failed
//! ([`Failed`], 1).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rsts_harness::{Observer, SampleRecord};

use crate::output;

pub use crate::failure::{flow_error, Failed, Interrupted};

/// The progress bar of a run (drawn on stderr after a second, on a terminal) and its Ctrl-C:
/// the first one sets the flag the flow polls (it stops after the current piece or sample and
/// finishes its outputs), a second one exits at once ([`crate::interrupt`]).
pub struct Watch {
    bar: ProgressBar,
    shown: bool,
    started: Instant,
    stop: Arc<AtomicBool>,
    /// Samples not yet counted on the bar, and how many make a tick (a tick reads the clock:
    /// `rsts check` of f64 data ticks every few hundred samples).
    pending: u64,
    tick: u64,
}

impl Watch {
    /// A bar of `samples` samples (`None`: not known), ticked every `tick` samples.
    pub fn new(samples: Option<u64>, tick: u64) -> Self {
        let bar = ProgressBar::with_draw_target(samples, ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} comparing [{bar:40}] {pos}/{len} samples, {elapsed} ({eta} left)",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        Self {
            bar,
            shown: false,
            started: Instant::now(),
            stop: crate::interrupt::stop_gracefully(),
            pending: 0,
            tick: tick.max(1),
        }
    }

    /// Clear the bar (before the report is written).
    pub fn clear(&self) {
        self.bar.finish_and_clear();
    }
}

impl Observer for Watch {
    /// The bar does not look at the states.
    fn wants_states(&self) -> bool {
        false
    }

    fn on_sample(&mut self, _r: &SampleRecord) -> Result<(), String> {
        // Show the bar only for runs longer than a second, and only on a terminal.
        self.pending += 1;
        if self.pending >= self.tick {
            output::tick_progress_by(&self.bar, self.started, &mut self.shown, self.pending);
            self.pending = 0;
        }
        Ok(())
    }

    fn should_stop(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }
}

impl rsts_flows::check::Progress for Watch {
    fn start_pass(&mut self, samples: Option<usize>) {
        self.bar.reset();
        match samples {
            Some(n) => self.bar.set_length(n as u64),
            // A CSV stream: its length is known at its end.
            None => self.bar.unset_length(),
        }
    }
}

/// After the report: the log's size and how to open it (stderr).
pub fn log_note(path: Option<&str>, stats: Option<rsts_mcap::LogStats>) {
    if let (Some(path), Some(stats)) = (path, stats) {
        eprintln!(
            "MCAP log: {path} ({} samples, {} messages). Open it in Foxglove or Lichtblick (Open local file), or run `{} inspect {path}`.",
            stats.samples,
            stats.messages,
            crate::invocation::invocation()
        );
    }
}
