//! `quakejoint`: the command-line interface.
//!
//! Thin by design: every command parses its arguments, calls the library
//! crates and prints. Exit codes: 0 success; 1 a run failed (or the
//! machine did: a full disk); 2 bad input (the message names the file,
//! field or value); 3 some jobs of a sweep or merge failed; 4 a run or a
//! job finished outside what the model can stand behind (flagged); 130
//! and 143 a sweep interrupted by SIGINT or SIGTERM (README, "Commands").

// The doc comments of `args` are the command's help text: the brackets in
// them are units (`[s]`), not links.
#![allow(rustdoc::broken_intra_doc_links)]

mod args;
mod calibrate;
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

/// A message with every line at most [`MAX_LINE`] characters: errors quote
/// the offending input, but never megabytes of it (see [`bounded_line`]).
fn bounded(text: &str) -> String {
    text.split_inclusive('\n')
        .map(|line| match line.strip_suffix('\n') {
            Some(l) => bounded_line(l) + "\n",
            None => bounded_line(line),
        })
        .collect()
}

/// Longest line of an error message (a backstop: the libraries quote at
/// most a short excerpt of any input, and put their guidance on lines of
/// its own).
const MAX_LINE: usize = 500;

/// A word longer than this (a path, a quoted input) is shortened in the
/// middle when its line is too long.
const MAX_WORD: usize = 80;

/// `line` within [`MAX_LINE`] characters, its cause kept: first every word
/// (a path, a token) longer than [`MAX_WORD`] loses its middle, keeping
/// its start and its end (a path keeps its file name); then, if the line
/// is still too long, its middle goes, keeping the start (what failed)
/// and the end (why).
fn bounded_line(line: &str) -> String {
    let len = |s: &str| s.chars().count();
    if len(line) <= MAX_LINE {
        return line.to_string();
    }
    let middle_out = |s: &str, keep_start: usize, keep_end: usize| -> String {
        let chars: Vec<char> = s.chars().collect();
        let left_out = chars.len() - keep_start - keep_end;
        let start: String = chars[..keep_start].iter().collect();
        let end: String = chars[chars.len() - keep_end..].iter().collect();
        format!("{start}[... {left_out} characters ...]{end}")
    };
    let words: String = line
        .split_inclusive(' ')
        .map(|w| if len(w) > MAX_WORD { middle_out(w, 30, 40) } else { w.to_string() })
        .collect();
    if len(&words) <= MAX_LINE {
        return words;
    }
    middle_out(&words, 200, 260)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_lines_keep_their_start_and_their_cause() {
        let path = format!("/data/{}/run.h5", "deep/".repeat(200));
        let line = format!("error: writing {path}: No space left on device (os error 28)");
        let b = bounded_line(&line);
        assert!(b.chars().count() <= MAX_LINE, "{b}");
        assert!(b.starts_with("error: writing /data/") && b.contains("run.h5:"), "{b}");
        assert!(b.ends_with("No space left on device (os error 28)"), "{b}");
        let many = format!("start {} cause", "word ".repeat(400));
        let b = bounded_line(&many);
        assert!(b.chars().count() <= MAX_LINE && b.starts_with("start ") && b.ends_with(" cause"), "{b}");
        assert_eq!(bounded_line("short"), "short");
        assert_eq!(bounded("a\nb\n"), "a\nb\n");
    }
}
