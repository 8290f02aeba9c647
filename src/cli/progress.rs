//! Progress of long work (docs/cli.md "Exit codes and progress output"): an indicatif bar on stderr when stderr is
//! a terminal; otherwise (batch jobs, CI logs) a plain line about every 5% of the work, once the
//! work has run for a second, so quick commands stay silent and long ones show they are alive.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Quiet time before the first log line (a terminal bar shows at once).
const FIRST_LINE_AFTER: Duration = Duration::from_secs(1);

/// The quiet time, or `BLOCKWORLD_PROGRESS_AFTER_MS` milliseconds when that is set (0 logs
/// every twentieth at once: for tests, and for batch logs that want every line).
fn first_line_after() -> Duration {
    std::env::var("BLOCKWORLD_PROGRESS_AFTER_MS")
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .map_or(FIRST_LINE_AFTER, Duration::from_millis)
}

/// Runs `f` with a progress callback `(done, total)` for `total` items named `unit`
/// (e.g. "scenes"), labelled `what` (the command) in log lines. The callback's own `total`
/// wins over the first guess, for work that learns its size as it goes (0 = not known yet).
pub fn with_progress<T>(
    what: &str,
    unit: &str,
    total: u64,
    f: impl FnOnce(&(dyn Fn(u64, u64) + Sync)) -> T,
) -> T {
    if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(total);
        let template = format!(
            "{{bar:40}} {{percent:>3}}% {{pos}}/{{len}} {unit}  {{per_sec}}  ETA {{eta}}  {{elapsed_precise}}"
        );
        bar.set_style(ProgressStyle::with_template(&template).expect("valid template"));
        let out = f(&|done, total| {
            bar.set_length(total);
            bar.set_position(done);
        });
        bar.finish_and_clear();
        return out;
    }
    let started = Instant::now();
    let quiet = first_line_after();
    let printed = AtomicU64::new(0);
    f(&|done, total| {
        if started.elapsed() < quiet {
            return;
        }
        let tick = twentieth(done, total);
        if tick > 0 && printed.fetch_max(tick, Ordering::Relaxed) < tick {
            let secs = started.elapsed().as_secs_f64().max(1e-9);
            eprintln!(
                "{what}: {done}/{total} {unit} ({}%), {:.1} {unit}/s",
                done * 100 / total.max(1),
                done as f64 / secs
            );
        }
    })
}

/// How many twentieths of `total` are `done` (a log line each time this grows, so one about
/// every 5% of the work however the callback's steps fall).
fn twentieth(done: u64, total: u64) -> u64 {
    (u128::from(done.min(total)) * 20 / u128::from(total.max(1))) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_lines_come_at_every_twentieth_of_the_work() {
        assert_eq!(twentieth(0, 1000), 0);
        assert_eq!(twentieth(49, 1000), 0);
        assert_eq!(twentieth(50, 1000), 1);
        assert_eq!(twentieth(1000, 1000), 20);
        assert_eq!(twentieth(3, 7), 8);
        assert_eq!(twentieth(u64::MAX, u64::MAX), 20);
        assert_eq!(twentieth(5, 0), 0);
    }
}
