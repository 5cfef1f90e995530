//! `quakejoint`: the command-line interface.
//!
//! Thin by design: every command parses its arguments, calls the library
//! crates and prints. Exit codes: 0 success, 1 a run failed, 2 bad input
//! (the message names the file, field or value).

mod commands;
mod output;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = commands::Cli::parse();
    match commands::run(cli) {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {}", message(&err));
            ExitCode::from(commands::exit_code(&err))
        }
    }
}

/// The error and its causes, each cause once: the library errors already
/// quote their source in their own message.
fn message(err: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in err.chain() {
        let part = cause.to_string();
        if !text.contains(&part) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&part);
        }
    }
    text
}
