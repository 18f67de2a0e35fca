//! Random key and mouse streams never panic the UI: a seeded generator (deterministic, so a
//! failure reproduces) sends a few thousand events, drawing after each, at 80×24 and 200×60.
//! The workbench stays consistent: the frame within the take, the selection a coordinate.

use articula::session::{Command, Workbench};
use articula::tui::{Ui, draw};
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

/// xorshift64*: a tiny deterministic generator.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

const CHARS: &str = "qhjkl[]{}gG<>r?:+-= xset body.mas80 selct LeftLg.Xrotain fme1234567890#\"";

fn random_key(rng: &mut Rng) -> KeyEvent {
    let code = match rng.below(10) {
        0 => [
            KeyCode::Enter,
            KeyCode::Esc,
            KeyCode::Tab,
            KeyCode::BackTab,
            KeyCode::Backspace,
            KeyCode::Up,
            KeyCode::Down,
            KeyCode::Left,
            KeyCode::Right,
            KeyCode::Home,
            KeyCode::End,
            KeyCode::PageUp,
            KeyCode::Delete,
            KeyCode::F(1),
        ][rng.below(14)],
        _ => KeyCode::Char(CHARS.chars().nth(rng.below(CHARS.chars().count())).unwrap()),
    };
    let modifiers = if rng.below(50) == 0 {
        KeyModifiers::CONTROL
    } else {
        KeyModifiers::NONE
    };
    KeyEvent::new(code, modifiers)
}

fn fuzz(seed: u64, events: usize, width: u16, height: u16) {
    fuzz_on(&["load demo:walk"], seed, events, width, height);
}

fn fuzz_on(setup: &[&str], seed: u64, events: usize, width: u16, height: u16) {
    let mut rng = Rng(seed);
    let mut ui = Ui::headless(width, height);
    let mut wb = Workbench::default();
    for line in setup {
        let cmd: Command = articula::session::parse_line(line, 1).unwrap().unwrap();
        ui.exec(&mut wb, &cmd);
        assert!(ui.error.is_none(), "{line}: {:?}", ui.error);
    }
    let mut term = Terminal::new(TestBackend::new(width, height)).unwrap();
    for i in 0..events {
        if rng.below(40) == 0 {
            let kind = match rng.below(4) {
                0 => MouseEventKind::Down(MouseButton::Left),
                1 => MouseEventKind::Drag(MouseButton::Left),
                2 => MouseEventKind::ScrollDown,
                _ => MouseEventKind::ScrollUp,
            };
            let m = MouseEvent {
                kind,
                column: rng.below(width as usize + 5) as u16,
                row: rng.below(height as usize + 5) as u16,
                modifiers: KeyModifiers::NONE,
            };
            ui.handle_mouse(&mut wb, m);
        } else {
            let k = random_key(&mut rng);
            ui.handle_key(&mut wb, k);
        }
        if rng.below(10) == 0 {
            ui.tick(&mut wb, rng.below(100) as f64 / 100.0);
        }
        // quitting is allowed; start over so the stream keeps exercising the UI
        if ui.quit {
            ui.quit = false;
        }
        term.draw(|f| draw::draw(&ui, &wb, f)).unwrap();
        assert!(
            wb.frame < wb.frames().max(1),
            "event {i}: frame {}",
            wb.frame
        );
        if let (Some(sel), Some(r)) = (&wb.selection, wb.latest_results()) {
            assert!(
                r.model.v_index(sel).is_some()
                    || articula::session::workbench::is_anatomical(r, sel),
                "event {i}: selection {sel}"
            );
        }
    }
}

#[test]
fn random_keys_at_80x24_never_panic() {
    fuzz(0x9E37_79B9_7F4A_7C15, 3000, 80, 24);
}

#[test]
fn random_keys_at_200x60_never_panic() {
    fuzz(0xD1B5_4A32_D192_ED03, 2000, 200, 60);
}

#[test]
fn random_keys_on_a_robot_arm_never_panic() {
    let dh = concat!(env!("CARGO_MANIFEST_DIR"), "/data/stanford.toml");
    fuzz_on(
        &[
            &format!("load {dh}"),
            "trajectory 0,0,0.3,0,0,0 1,-1,0.6,1,1,1 over 0.5 at 100",
        ],
        0x5DEE_CE66_D1CE_4E5B,
        1500,
        80,
        24,
    );
}
