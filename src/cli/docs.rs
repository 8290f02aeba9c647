//! `blockworld docs cli`: the command-line reference (docs/cli.md) generated from the clap
//! definitions themselves, so the page cannot drift from the parser: `make docs` writes it and
//! `tests/cli_docs.rs` fails when the committed page differs from what this prints.

use clap::{Arg, CommandFactory};
use std::fmt::Write;

/// The page's hand-written part: what a user does with the command line, exit codes and
/// progress output. The generated reference of every command follows it.
const INTRO: &str = include_str!("cli_intro.md");

/// Options of `blockworld docs`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Which page to print.
    #[command(subcommand)]
    pub page: Page,
}

/// The generated pages.
#[derive(Debug, clap::Subcommand)]
pub enum Page {
    /// docs/cli.md: every command and flag, from the clap definitions.
    Cli,
}

/// Runs `blockworld docs`: prints the page on standard output.
pub fn run(args: Args) -> anyhow::Result<()> {
    match args.page {
        Page::Cli => outln!("{}", cli_page().trim_end())?,
    }
    Ok(())
}

/// The whole docs/cli.md page.
pub fn cli_page() -> String {
    let mut command = crate::cli::Cli::command();
    command.build();
    let mut page = String::from(INTRO.trim_end());
    page.push_str("\n\n## Commands\n\n");
    for sub in visible_subcommands(&command) {
        let _ = writeln!(
            page,
            "- [`blockworld {0}`](#blockworld-{0}): {1}",
            sub.get_name(),
            about(sub)
        );
    }
    write_command(&mut page, &command, "blockworld");
    page
}

/// Subcommands a user sees (`help` and hidden ones left out).
fn visible_subcommands(command: &clap::Command) -> impl Iterator<Item = &clap::Command> {
    command
        .get_subcommands()
        .filter(|s| !s.is_hide_set() && s.get_name() != "help")
}

/// The one-line description of a command.
fn about(command: &clap::Command) -> String {
    command
        .get_about()
        .map(|a| a.to_string())
        .unwrap_or_default()
}

/// One command's section (usage, arguments, options), then its subcommands' sections.
fn write_command(page: &mut String, command: &clap::Command, path: &str) {
    let heading = if path == "blockworld" {
        "Global options"
    } else {
        path
    };
    let _ = writeln!(page, "\n## {heading}\n");
    if path != "blockworld" {
        let text = command
            .get_long_about()
            .or(command.get_about())
            .map(|a| a.to_string())
            .unwrap_or_default();
        let _ = writeln!(page, "{}\n", text.trim());
    }
    let mut usage_command = command.clone();
    let usage = usage_command.render_usage().to_string();
    let usage = usage.trim_start_matches("Usage: ").trim();
    let _ = writeln!(page, "```text\n{usage}\n```");
    let arguments: Vec<&Arg> = command
        .get_arguments()
        .filter(|a| !a.is_hide_set() && !matches!(a.get_id().as_str(), "help" | "version"))
        .filter(|a| path == "blockworld" || !a.is_global_set())
        .collect();
    if !arguments.is_empty() {
        page.push('\n');
    }
    for arg in arguments {
        write_argument(page, arg);
    }
    for sub in visible_subcommands(command) {
        write_command(page, sub, &format!("{path} {}", sub.get_name()));
    }
}

/// One argument as a list item: its spelling, its help, its default and its values.
fn write_argument(page: &mut String, arg: &Arg) {
    let help = arg
        .get_long_help()
        .or(arg.get_help())
        .map(|h| h.to_string())
        .unwrap_or_default();
    let mut text = help.trim().replace('\n', "\n  ");
    if !text.is_empty() && !text.ends_with('.') {
        text.push('.');
    }
    let is_flag = matches!(
        arg.get_action(),
        clap::ArgAction::SetTrue | clap::ArgAction::SetFalse | clap::ArgAction::Count
    );
    let defaults: Vec<String> = arg
        .get_default_values()
        .iter()
        .map(|v| v.to_string_lossy().into_owned())
        .collect();
    if !defaults.is_empty() && !is_flag {
        let _ = write!(text, " Default: `{}`.", defaults.join(","));
    }
    let values: Vec<String> = arg
        .get_possible_values()
        .iter()
        .filter(|v| !v.is_hide_set())
        .map(|v| format!("`{}`", v.get_name()))
        .collect();
    if !values.is_empty() && !is_flag {
        let _ = write!(text, " Values: {}.", values.join(", "));
    }
    let _ = writeln!(page, "- `{}`: {}", spelling(arg), text.trim());
}

/// How an argument is typed: `<SCENE>`, `-o, --output <OUTPUT>`, `--rgb`.
fn spelling(arg: &Arg) -> String {
    let value = arg
        .get_value_names()
        .and_then(|names| names.first())
        .map(|n| n.to_string())
        .unwrap_or_else(|| arg.get_id().as_str().to_uppercase());
    if arg.is_positional() {
        return format!("<{value}>");
    }
    let mut s = String::new();
    if let Some(short) = arg.get_short() {
        let _ = write!(s, "-{short}");
    }
    if let Some(long) = arg.get_long() {
        if !s.is_empty() {
            s.push_str(", ");
        }
        let _ = write!(s, "--{long}");
    }
    if arg.get_action().takes_values() {
        let _ = write!(s, " <{value}>");
    }
    s
}
