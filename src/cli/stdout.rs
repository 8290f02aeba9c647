//! Printing results on stdout the Unix way: a reader that has gone (`| head -1`, a closed pipe)
//! ends the command quietly with exit 0, while a stdout that cannot take the bytes (`> /dev/full`,
//! a full disk) is an error with exit 2 like any other failed write (README "Exit codes and progress output").
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
