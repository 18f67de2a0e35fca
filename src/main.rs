//! The `articula` binary: clap flags → library calls. Nothing else lives here.

mod batch;
mod cli;

use clap::Parser;
use std::process::ExitCode;

/// mimalloc, not the system allocator, for the binary (and the Python module,
/// python/src/lib.rs; the library's tests keep the system's, the alloc-counting tests set
/// their own). A take's stages allocate a few tables of
/// megabytes and thousands of rows, run after run in the workbench and in `bench`: glibc gives
/// such blocks back to the kernel at each free and faults their pages in again at the next
/// run (a tenth of a minute take's time, `perf record`), and with two threads the derivatives
/// stage took longer than with one. mimalloc keeps freed pages for reuse. Measured
/// in docs/performance.md ("The allocator", stop 37). Results are the same bits.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

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
