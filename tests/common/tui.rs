//! The terminal UI driven headless, for the TUI tests: keys pressed through the key handler,
//! the screen drawn into ratatui's `TestBackend`.

use articula::session::{Command, Workbench};
use articula::tui::keys::parse_keys;
use articula::tui::{Ui, draw};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;

/// `keys` (the session's `key` syntax: characters, `<Enter>`, `<Esc>`, …) pressed in order.
pub fn press(ui: &mut Ui, wb: &mut Workbench, keys: &str) {
    for k in parse_keys(keys).unwrap() {
        ui.handle_key(wb, k);
    }
}

/// The screen at `w × h` as drawn (cells with their styles).
pub fn buffer(ui: &Ui, wb: &Workbench, w: u16, h: u16) -> Buffer {
    let mut term = Terminal::new(TestBackend::new(w, h)).unwrap();
    term.draw(|f| draw::draw(ui, wb, f)).unwrap();
    term.backend().buffer().clone()
}

/// The screen at `w × h` as text.
pub fn screen(ui: &Ui, wb: &Workbench, w: u16, h: u16) -> String {
    draw::buffer_text(&buffer(ui, wb, w, h))
}

/// The demo walk loaded into `wb` in a headless `width × height` interface without colours.
pub fn demo_in(width: u16, height: u16, mut wb: Workbench) -> (Ui, Workbench) {
    let mut ui = Ui::headless(width, height);
    ui.color = false;
    ui.exec(
        &mut wb,
        &Command::Load {
            path: "demo:walk".into(),
            name: None,
        },
    );
    assert!(ui.error.is_none(), "{:?}", ui.error);
    (ui, wb)
}
