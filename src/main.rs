//! The `articula` binary: clap flags → library calls. Nothing else lives here.

mod batch;
mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse_from(batch::with_command_separator(std::env::args_os().collect()));
    match cli::run(args) {
        Ok(code) => code,
        Err(err) => {
            // print the whole error chain, ripgrep-style, without repeating a cause whose
            // text the line above already shows (typed errors often embed their source)
            let mut last = err.to_string();
            eprintln!("articula: error: {last}");
            for cause in err.chain().skip(1) {
                let text = cause.to_string();
                if !last.contains(&text) {
                    eprintln!("  caused by: {text}");
                }
                last = text;
            }
            ExitCode::from(2)
        }
    }
}
