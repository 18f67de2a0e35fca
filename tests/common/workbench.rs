//! A workbench over the repository's files and the session lines applied to it, for the
//! session tests.

use articula::session::{Command, Workbench, parse_line};
use std::path::Path;

/// A workbench reading inputs from the repository and writing outputs under `out`.
pub fn wb_in(out: &Path) -> Workbench {
    Workbench::new(
        std::sync::Arc::new(articula::session::Builtin),
        super::repo("."),
        out,
    )
}

/// `line` parsed and applied: its message, or the error as text.
pub fn apply(wb: &mut Workbench, line: &str) -> Result<String, String> {
    let cmd: Command = parse_line(line, 1)
        .map_err(|e| e.to_string())?
        .expect("a command");
    wb.apply(&cmd).map(|o| o.message).map_err(|e| e.to_string())
}

/// [`apply`], which must succeed.
pub fn ok(wb: &mut Workbench, line: &str) -> String {
    apply(wb, line).unwrap_or_else(|e| panic!("{line}: {e}"))
}

/// [`apply`], which must fail: the error.
pub fn fails(wb: &mut Workbench, line: &str) -> String {
    match apply(wb, line) {
        Ok(m) => panic!("{line}: passed ({m})"),
        Err(e) => e,
    }
}
