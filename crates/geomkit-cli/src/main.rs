//! `geomkit`: the command-line tool over the geomkit library.
//!
//! Errors become one line `error: ...` on stderr (the causes joined with ": ") and exit code 1;
//! usage errors are clap's (exit code 2). Output files are written atomically.

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

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    let result = match cli.command {
        cli::Command::Bezier(command) => commands::bezier::run(command),
        cli::Command::Interpolate(command) => commands::interpolate::run(command),
        cli::Command::Eval(args) => commands::eval::run(args),
        cli::Command::Pointcalc(command) => commands::pointcalc::run(command),
        cli::Command::Compose(command) => commands::compose::run(command),
        cli::Command::Render(args) => commands::render::run(args),
        cli::Command::Mesh(args) => commands::mesh::run(args),
        cli::Command::Demo(args) => demo::run(&args),
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
