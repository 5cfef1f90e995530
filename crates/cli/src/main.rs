//! `quakejoint`: the command-line interface.
//!
//! Thin by design: every command parses its arguments, calls the library
//! crates and prints. Exit codes: 0 success, 1 a run failed, 2 bad input
//! (the message names the file, field or value).

mod args;
mod commands;
mod continuation;
mod interrupt;
mod output;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = match args::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version print in full; errors quote bounded input
            let text = e.render().to_string();
            if e.use_stderr() {
                eprint!("{}", bounded(&text));
            } else {
                print!("{text}");
            }
            return ExitCode::from(e.exit_code() as u8);
        }
    };
    let json = cli.command.json();
    match commands::run(cli) {
        Ok(code) => code,
        Err(err) => {
            let text = bounded(&message(&err));
            let code = commands::exit_code(&err);
            eprintln!("error: {text}");
            if json {
                // a reader of stdout gets one JSON object either way
                println!("{}", serde_json::json!({"error": text, "exit_code": code}));
            }
            ExitCode::from(code)
        }
    }
}

/// A message with every line cut to [`MAX_LINE`] characters: errors quote
/// the offending input, but never megabytes of it.
fn bounded(text: &str) -> String {
    text.split_inclusive('\n').map(|line| quakejoint_motion::excerpt(line, MAX_LINE)).collect()
}

/// Longest line of an error message (a backstop: the libraries quote at
/// most a short excerpt of any input, and their guidance must not be cut).
const MAX_LINE: usize = 1500;

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
