//! `geomkit`: the command-line tool over the geomkit library.
//!
//! Errors become one line `error: ...` on stderr (the causes joined with ": ") and exit code 1;
//! usage errors (an unknown option, a value that does not parse) are one line too, with exit
//! code 2. Output files are written atomically.

mod cli;
mod commands;
mod demo;
mod model;
mod npy;
mod output;
mod progress;
mod table;

use clap::Parser;
use std::io::Write;
use std::process::ExitCode;

/// clap's usage error as one line: its first paragraph (the message and, for missing
/// arguments, their names), without the usage block clap adds.
fn usage_line(err: &clap::Error) -> String {
    let text = err.render().to_string();
    let first = text.split("\n\n").next().unwrap_or_default();
    let words: Vec<&str> = first.split_whitespace().collect();
    let line = words.join(" ");
    let line = line.strip_prefix("error: ").unwrap_or(&line);
    format!("error: {line} (see --help)")
}

fn main() -> ExitCode {
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        // --help, --version, and the help of a command given without its subcommand.
        Err(e)
            if !e.use_stderr()
                || e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand =>
        {
            e.exit()
        }
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "{}", usage_line(&e));
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        cli::Command::Bezier(command) => commands::bezier::run(command),
        cli::Command::Interpolate(command) => commands::interpolate::run(command),
        cli::Command::Eval(args) => commands::eval::run(args),
        cli::Command::Pointcalc(command) => commands::pointcalc::run(command),
        cli::Command::Compose(command) => commands::compose::run(command),
        cli::Command::Render(args) => commands::render::run(args),
        cli::Command::Mesh(args) => commands::mesh::run(args),
        cli::Command::Demo(args) => demo::run(&args),
        cli::Command::Serve(args) => commands::serve::run(args),
        cli::Command::Export(args) => commands::step::export(args),
        cli::Command::Import(args) => commands::step::import(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) if output::is_broken_pipe(&err) => ExitCode::SUCCESS,
        Err(err) => {
            let message = format!("{err:#}").replace(['\n', '\r'], " ");
            let _ = writeln!(std::io::stderr(), "error: {message}");
            ExitCode::FAILURE
        }
    }
}
