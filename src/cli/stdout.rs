//! Printing results on stdout the Unix way: a reader that has gone (`| head -1`, a closed pipe)
//! ends the command quietly with exit 0, while a stdout that cannot take the bytes (`> /dev/full`,
//! a full disk) is an error with exit 2 like any other failed write (docs/cli.md "Exit codes and progress output").
//! `println!` would panic in both cases, so every command prints through [`outln!`] and [`out!`].

use std::io::Write;

/// The reader of stdout has gone (EPIPE): not a failure of the command, which stops quietly.
#[derive(Debug, thiserror::Error)]
#[error("stdout was closed by its reader")]
pub struct StdoutClosed;

/// Writes formatted text to stdout and flushes it; a broken pipe becomes [`StdoutClosed`],
/// any other error "writing to stdout: ..." (so `> /dev/full` fails at once, not at exit).
pub fn write_stdout(text: std::fmt::Arguments) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_fmt(text)
        .and_then(|()| out.flush())
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::BrokenPipe => anyhow::Error::new(StdoutClosed),
            _ => anyhow::Error::new(e).context("writing to stdout"),
        })
}

/// `true` when the error only says that stdout's reader has gone.
pub fn is_stdout_closed(err: &anyhow::Error) -> bool {
    err.chain().any(|c| c.is::<StdoutClosed>())
}

/// The safety net for any `println!` left (a command another branch adds): the standard
/// library panics with "failed printing to stdout"; this hook turns that panic into the same
/// outcome as [`write_stdout`] (quiet exit 0 for a closed pipe, exit 2 with the error
/// otherwise) and leaves every other panic to the default hook. Install it first in `main`.
pub fn exit_cleanly_on_stdout_panics() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        let Some(cause) = payload.strip_prefix("failed printing to stdout: ") else {
            return default(info);
        };
        if cause.contains("Broken pipe") {
            std::process::exit(0);
        }
        eprintln!("error: writing to stdout\n  caused by: {cause}");
        std::process::exit(2);
    }));
}

/// `println!` that returns `anyhow::Result<()>` instead of panicking (see the module doc).
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::cli::stdout::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that returns `anyhow::Result<()>` instead of panicking (see the module doc).
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::stdout::write_stdout(format_args!($($arg)*))
    };
}
