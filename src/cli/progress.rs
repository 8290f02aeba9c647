//! Progress of long work (README "Exit codes and progress output"): an indicatif bar on stderr when stderr is
//! a terminal; otherwise (batch jobs, CI logs) a plain line about every 5% of the work, once the
//! work has run for a second, so quick commands stay silent and long ones show they are alive.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Quiet time before the first log line (a terminal bar shows at once).
const FIRST_LINE_AFTER: Duration = Duration::from_secs(1);

/// Runs `f` with a progress callback `(done, total)` for `total` items named `unit`
/// (e.g. "scenes"), labelled `what` (the command) in log lines.
pub fn with_progress<T>(
    what: &str,
    unit: &str,
    total: u64,
    f: impl FnOnce(&(dyn Fn(u64, u64) + Sync)) -> T,
) -> T {
    if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(total);
        let template = format!(
            "{{bar:40}} {{pos}}/{{len}} {unit}  {{per_sec}}  ETA {{eta}}  {{elapsed_precise}}"
        );
        bar.set_style(ProgressStyle::with_template(&template).expect("valid template"));
        let out = f(&|done, _| bar.set_position(done));
        bar.finish_and_clear();
        return out;
    }
    let step = (total / 20).max(1);
    let started = Instant::now();
    let last = AtomicU64::new(0);
    f(&|done, total| {
        let due = done % step == 0 || done == total;
        if !due || started.elapsed() < FIRST_LINE_AFTER {
            return;
        }
        if last.fetch_max(done, Ordering::Relaxed) < done {
            let secs = started.elapsed().as_secs_f64().max(1e-9);
            eprintln!(
                "{what}: {done}/{total} {unit}, {:.1} {unit}/s",
                done as f64 / secs
            );
        }
    })
}
