//! The keystroke notation of the `key` command: characters stand for themselves, special keys
//! are written `<Name>` (`<Enter>`, `<Esc>`, `<Tab>`, `<S-Tab>`, `<Space>`, `<BS>`, `<Del>`,
//! `<Up>`, `<Down>`, `<Left>`, `<Right>`, `<Home>`, `<End>`, `<PgUp>`, `<PgDn>`, `<lt>` for a
//! literal `<`, `<C-x>` for Ctrl+x).

use crate::session::SessionError;
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// Parses the `key` notation into key events.
pub fn parse_keys(s: &str) -> Result<Vec<KeyEvent>, SessionError> {
    let mut out = vec![];
    let mut rest = s;
    while let Some(c) = rest.chars().next() {
        if c == '<'
            && let Some(end) = rest.find('>')
            && end > 1
        {
            let name = &rest[1..end];
            out.push(named(name).ok_or_else(|| {
                SessionError::Command(format!(
                    "unknown key <{name}> (expected <Enter>, <Esc>, <Tab>, <S-Tab>, <Space>, \
                     <BS>, <Del>, <Up>, <Down>, <Left>, <Right>, <Home>, <End>, <PgUp>, \
                     <PgDn>, <lt> or <C-x>)"
                ))
            })?);
            rest = &rest[end + 1..];
            continue;
        }
        out.push(KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE));
        rest = &rest[c.len_utf8()..];
    }
    Ok(out)
}

fn named(name: &str) -> Option<KeyEvent> {
    let plain = |code| Some(KeyEvent::new(code, KeyModifiers::NONE));
    match name {
        "Enter" | "CR" => plain(KeyCode::Enter),
        "Esc" => plain(KeyCode::Esc),
        "Tab" => plain(KeyCode::Tab),
        "S-Tab" => Some(KeyEvent::new(KeyCode::BackTab, KeyModifiers::SHIFT)),
        "Space" => plain(KeyCode::Char(' ')),
        "BS" => plain(KeyCode::Backspace),
        "Del" => plain(KeyCode::Delete),
        "Up" => plain(KeyCode::Up),
        "Down" => plain(KeyCode::Down),
        "Left" => plain(KeyCode::Left),
        "Right" => plain(KeyCode::Right),
        "Home" => plain(KeyCode::Home),
        "End" => plain(KeyCode::End),
        "PgUp" => plain(KeyCode::PageUp),
        "PgDn" => plain(KeyCode::PageDown),
        "lt" => plain(KeyCode::Char('<')),
        _ => {
            let c = name.strip_prefix("C-")?;
            let mut chars = c.chars();
            let ch = chars.next()?;
            if chars.next().is_some() {
                return None;
            }
            Some(KeyEvent::new(KeyCode::Char(ch), KeyModifiers::CONTROL))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notation_round_trips_the_common_keys() {
        let k = parse_keys(":frame 3<Enter><C-c><lt>x").unwrap();
        assert_eq!(k.len(), 12);
        assert_eq!(k[0].code, KeyCode::Char(':'));
        assert_eq!(k[6].code, KeyCode::Char(' '));
        assert_eq!(k[8].code, KeyCode::Enter);
        assert_eq!(k[9].modifiers, KeyModifiers::CONTROL);
        assert_eq!(k[10].code, KeyCode::Char('<'));
        assert!(parse_keys("<Bogus>").is_err());
        // a lone '<' is a character
        assert_eq!(parse_keys("<").unwrap()[0].code, KeyCode::Char('<'));
    }
}
