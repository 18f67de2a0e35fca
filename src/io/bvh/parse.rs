//! The BVH reader: a hand-written tokenizer and an iterative (no recursion, so no stack
//! overflow on deep or hostile input) recursive-descent parser of the grammar
//!
//! ```text
//! file      = "HIERARCHY" "ROOT" name joint-body "MOTION"
//!             "Frames:" count "Frame Time:" seconds frame-line{count}
//! joint-body= "{" ("OFFSET" x y z | "CHANNELS" n channel{n} | "JOINT" name joint-body
//!             | "End" "Site" "{" "OFFSET" x y z "}")* "}"
//! ```
//!
//! with one frame line per frame, holding exactly the total channel count of values. The
//! hierarchy is free-form apart from three line rules: a joint name sits on its ROOT/JOINT
//! line, the channel names on their CHANNELS line, the three numbers on their OFFSET line.
//! Frame lines are read by `super::frames` (one pass over the bytes, in parallel chunks), or,
//! when that reader gives up, here with `str::parse::<f64>` on slices of the input, which
//! finds and reports what is wrong.

use super::{Bvh, BvhJoint, Channel};
use crate::error::Error;
use nalgebra::Vector3;
use std::collections::HashSet;
use std::path::Path;

/// Reads and parses the BVH file at `path` (bytes that are not UTF-8 are replaced, see
/// [`parse_bytes`]).
pub fn read(path: &Path) -> Result<Bvh, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_bytes(&bytes, path)
}

/// Parses BVH bytes; invalid UTF-8 sequences (e.g. Latin-1 joint names) become U+FFFD, which
/// can only affect names. `file` is used in error messages only.
///
/// Only the text before the frame lines is checked as UTF-8 on the way to the fast reader:
/// the frame reader takes ASCII only (a byte from 0x80 on stops it), so the frame lines,
/// most of a file, need no second pass. When the fast reader gives up, the whole text is
/// checked and read as before.
pub fn parse_bytes(bytes: &[u8], file: &Path) -> Result<Bvh, Error> {
    let body = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    let retry = match head_text(body) {
        Some(head) => match fast(head, body, file) {
            Ok(bvh) => return Ok(bvh),
            Err(retry) => retry,
        },
        None => Retry::Whole,
    };
    match (std::str::from_utf8(bytes), retry) {
        (Ok(text), Retry::Careful) => careful(text.strip_prefix('\u{feff}').unwrap_or(text), file),
        (Ok(text), Retry::Whole) => parse_str(text, file),
        (Err(_), _) => parse_str(&String::from_utf8_lossy(bytes), file),
    }
}

/// Bytes of a file checked as UTF-8 for the fast reader's hierarchy and MOTION header (far
/// more than any header holds; a longer one sends the file to the whole-text path).
const HEAD_BYTES: usize = 1 << 16;

/// The first [`HEAD_BYTES`] of `bytes` (fewer, to end on a whole character) as text; `None`
/// when they are not UTF-8.
fn head_text(bytes: &[u8]) -> Option<&str> {
    let head = &bytes[..bytes.len().min(HEAD_BYTES)];
    match std::str::from_utf8(head) {
        Ok(text) => Some(text),
        // cut inside a character: the text up to it
        Err(e) if e.error_len().is_none() => std::str::from_utf8(&head[..e.valid_up_to()]).ok(),
        Err(_) => None,
    }
}

/// Parses BVH text. `file` is used in error messages only.
///
/// Two readers: the fast one (`fast`) reads the frame lines with `super::frames` and gives
/// up at anything unusual; the careful one (`careful`) then reads the whole text again and
/// says exactly what is wrong. Both give the same `Bvh` for any text both accept.
pub fn parse_str(text: &str, file: &Path) -> Result<Bvh, Error> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    match fast(text, text.as_bytes(), file) {
        Ok(bvh) => Ok(bvh),
        Err(_) => careful(text, file),
    }
}

/// Why the fast reader gave up, and what to do next.
enum Retry {
    /// Its text ended before the frame lines began: read the whole text.
    Whole,
    /// Anything else: the careful reader on the whole text.
    Careful,
}

/// The hierarchy and the MOTION header by the careful reader on `head` (the start of `text`,
/// as text), the frame lines of `text` by `super::frames`; a `Retry` at any error or anything
/// the frame reader does not expect.
fn fast(head: &str, text: &[u8], file: &Path) -> Result<Bvh, Retry> {
    // a token that reaches the end of `head` may go on in `text`: only a header read from
    // bytes before that end is the file's
    let cut = if head.len() < text.len() {
        Retry::Whole
    } else {
        Retry::Careful
    };
    let mut lx = Lexer::new(head, file);
    let Ok(joints) = hierarchy(&mut lx) else {
        return Err(cut);
    };
    let channel_count = joints.iter().map(|j| j.channels.len()).sum();
    let Ok((frames, frame_time)) = motion_header(&mut lx, channel_count) else {
        return Err(cut);
    };
    if lx.pos == head.len() && head.len() < text.len() {
        return Err(Retry::Whole);
    }
    // the frame reader accepts no control character; the header is checked here
    control_characters(&head[..lx.pos], file).map_err(|_| Retry::Careful)?;
    let (motion, decimals) =
        super::frames::read(&text[lx.pos..], frames, channel_count).ok_or(Retry::Careful)?;
    Ok(Bvh {
        joints,
        frame_time,
        frames,
        channel_count,
        motion,
        first_frame: 0,
        decimals,
    })
}

/// The careful reader: every check, every error message with its file, line and column.
fn careful(text: &str, file: &Path) -> Result<Bvh, Error> {
    control_characters(text, file)?;
    let mut lx = Lexer::new(text, file);
    let joints = hierarchy(&mut lx)?;
    let channel_count = joints.iter().map(|j| j.channels.len()).sum();
    let (frames, frame_time) = motion_header(&mut lx, channel_count)?;
    let (motion, decimals) = frame_lines(&mut lx, frames, channel_count)?;
    Ok(Bvh {
        joints,
        frame_time,
        frames,
        channel_count,
        motion,
        first_frame: 0,
        decimals,
    })
}

/// Refuses a control character (other than tab, CR and LF) anywhere in the text: no BVH holds
/// one, and echoed in a message or a joint name it would reach the user's terminal as an
/// escape sequence (a colour change, a window title). The message names it by code point.
fn control_characters(text: &str, file: &Path) -> Result<(), Error> {
    let bad = |c: char| c.is_control() && !matches!(c, '\t' | '\r' | '\n');
    let Some(at) = text.find(bad) else {
        return Ok(());
    };
    let before = &text[..at];
    let line = 1 + before.matches('\n').count() + before.matches('\r').count()
        - before.matches("\r\n").count();
    let line_start = before.rfind(['\n', '\r']).map_or(0, |i| i + 1);
    let column = text[line_start..at].chars().count() + 1;
    let c = text[at..].chars().next().unwrap_or('\0');
    Err(Error::parse(
        file,
        line,
        column,
        format!(
            "a control character (U+{:04X}) where BVH has text: is this a BVH file?",
            c as u32
        ),
    ))
}

/// A token: a run of non-blank characters, with where it starts.
#[derive(Clone, Copy)]
struct Tok<'a> {
    text: &'a str,
    line: usize,
    line_start: usize,
    start: usize,
}

impl Tok<'_> {
    fn is(&self, keyword: &str) -> bool {
        self.text.eq_ignore_ascii_case(keyword)
    }
}

struct Lexer<'a> {
    src: &'a str,
    /// Byte offset of the next unread character.
    pos: usize,
    /// 1-based line of `pos`.
    line: usize,
    /// Byte offset where line `line` starts.
    line_start: usize,
    file: &'a Path,
}

/// Blank characters that do not end a line.
fn is_inline_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | 0x0b | 0x0c)
}

fn is_blank(b: u8) -> bool {
    is_inline_blank(b) || b == b'\n' || b == b'\r'
}

impl<'a> Lexer<'a> {
    fn new(src: &'a str, file: &'a Path) -> Self {
        Lexer {
            src,
            pos: 0,
            line: 1,
            line_start: 0,
            file,
        }
    }

    fn bytes(&self) -> &'a [u8] {
        self.src.as_bytes()
    }

    /// Skips blanks and line ends (LF, CRLF or a lone CR each end one line).
    fn skip_blank(&mut self) {
        let b = self.bytes();
        while self.pos < b.len() {
            match b[self.pos] {
                b'\n' => self.newline(self.pos + 1),
                b'\r' if b.get(self.pos + 1) == Some(&b'\n') => self.newline(self.pos + 2),
                b'\r' => self.newline(self.pos + 1),
                c if is_inline_blank(c) => self.pos += 1,
                _ => break,
            }
        }
    }

    fn newline(&mut self, next: usize) {
        self.pos = next;
        self.line += 1;
        self.line_start = next;
    }

    /// Skips blanks without crossing a line end.
    fn skip_inline_blank(&mut self) {
        let b = self.bytes();
        while self.pos < b.len() && is_inline_blank(b[self.pos]) {
            self.pos += 1;
        }
    }

    fn take_word(&mut self) -> Tok<'a> {
        let b = self.bytes();
        let start = self.pos;
        while self.pos < b.len() && !is_blank(b[self.pos]) {
            self.pos += 1;
        }
        Tok {
            text: &self.src[start..self.pos],
            line: self.line,
            line_start: self.line_start,
            start,
        }
    }

    /// The next token anywhere, or `None` at the end of the input.
    fn next(&mut self) -> Option<Tok<'a>> {
        self.skip_blank();
        (self.pos < self.src.len()).then(|| self.take_word())
    }

    /// The next token on the current line, or `None` at its end.
    fn next_inline(&mut self) -> Option<Tok<'a>> {
        self.skip_inline_blank();
        (self.pos < self.src.len() && !is_blank(self.bytes()[self.pos])).then(|| self.take_word())
    }

    fn column(&self, line_start: usize, at: usize) -> usize {
        self.src[line_start..at].chars().count() + 1
    }

    fn error_at(&self, tok: &Tok, message: impl Into<String>) -> Error {
        Error::parse(
            self.file,
            tok.line,
            self.column(tok.line_start, tok.start),
            message,
        )
    }

    /// An error at the current position (end of a line, end of the file).
    fn error_here(&self, message: impl Into<String>) -> Error {
        Error::parse(
            self.file,
            self.line,
            self.column(self.line_start, self.pos),
            message,
        )
    }

    /// The next token, or an "unexpected end of file, expected ..." error.
    fn expect_any(&mut self, expected: &str) -> Result<Tok<'a>, Error> {
        self.next()
            .ok_or_else(|| self.error_here(format!("unexpected end of file: expected {expected}")))
    }

    /// The next token, which must be `keyword` (ASCII case ignored).
    fn expect_keyword(&mut self, keyword: &str, context: &str) -> Result<Tok<'a>, Error> {
        let tok = self.expect_any(&format!("{keyword} {context}"))?;
        if tok.is(keyword) {
            Ok(tok)
        } else {
            Err(self.error_at(
                &tok,
                format!("expected {keyword} {context}, found '{}'", tok.text),
            ))
        }
    }

    /// A keyword ending in ':' (`Frames:`), written with or without blanks before the colon.
    fn expect_label(&mut self, label: &str, context: &str) -> Result<(), Error> {
        let expected = format!("'{label}:' {context}");
        let tok = self.expect_any(&expected)?;
        let text = tok.text;
        let has_label = text.len() >= label.len()
            && text.is_char_boundary(label.len())
            && text[..label.len()].eq_ignore_ascii_case(label);
        if has_label && text.len() == label.len() + 1 && text.ends_with(':') {
            return Ok(());
        }
        if has_label && text.len() == label.len() {
            if let Some(colon) = self.next_inline() {
                if colon.text == ":" {
                    return Ok(());
                }
                return Err(self.error_at(
                    &colon,
                    format!("expected ':' after {label}, found '{}'", colon.text),
                ));
            }
            return Err(self.error_here(format!("expected ':' after {label}")));
        }
        Err(self.error_at(&tok, format!("expected {expected}, found '{text}'")))
    }

    fn number(&self, tok: &Tok, what: &str) -> Result<f64, Error> {
        match tok.text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.error_at(
                tok,
                format!(
                    "expected a finite number for {what}, found '{}' (NaN and infinities are \
                     not allowed)",
                    tok.text
                ),
            )),
            Err(_) => Err(self.error_at(
                tok,
                format!("expected a number for {what}, found '{}'", tok.text),
            )),
        }
    }

    /// The three numbers of an OFFSET line (the OFFSET token already read).
    fn offset_values(&mut self, owner: &str) -> Result<Vector3<f64>, Error> {
        let mut v = Vector3::zeros();
        for (n, axis) in ["x", "y", "z"].into_iter().enumerate() {
            let what = format!("the OFFSET {axis} of {owner}");
            let tok = self.next_inline().ok_or_else(|| {
                self.error_here(format!(
                    "expected 3 numbers after OFFSET of {owner}, found {n}"
                ))
            })?;
            v[n] = self.number(&tok, &what)?;
        }
        if let Some(extra) = self.next_inline() {
            return Err(self.error_at(
                &extra,
                format!(
                    "expected 3 numbers after OFFSET of {owner}, found a fourth: '{}'",
                    extra.text
                ),
            ));
        }
        Ok(v)
    }

    /// A joint name on the line of its ROOT/JOINT keyword.
    fn joint_name(&mut self, keyword: &Tok) -> Result<Tok<'a>, Error> {
        let name = self.next_inline().ok_or_else(|| {
            self.error_here(format!("expected a joint name after {}", keyword.text))
        })?;
        if name.text == "{" || name.text == "}" {
            return Err(self.error_at(
                &name,
                format!(
                    "expected a joint name after {}, found '{}'",
                    keyword.text, name.text
                ),
            ));
        }
        if let Some(extra) = self.next_inline()
            && extra.text != "{"
        {
            return Err(self.error_at(
                &extra,
                format!(
                    "expected '{{' after joint name '{}', found '{}' (names cannot contain blanks)",
                    name.text, extra.text
                ),
            ));
        }
        Ok(name)
    }
}

/// What the parser is inside of.
#[derive(Clone, Copy)]
enum Open {
    /// The body of `joints[.0]`.
    Joint(usize),
    /// An End Site of `joints[.0]`, with its OFFSET once read.
    EndSite(usize, Option<Vector3<f64>>),
}

/// Per joint, what its body has declared so far.
#[derive(Default, Clone, Copy)]
struct Seen {
    offset: bool,
    channels: bool,
}

/// `HIERARCHY ROOT ...`: the joints in file order, ending after the root's closing brace.
fn hierarchy<'a>(lx: &mut Lexer<'a>) -> Result<Vec<BvhJoint>, Error> {
    let first = lx.next().ok_or_else(|| {
        lx.error_here("empty file: expected HIERARCHY (a BVH file starts with HIERARCHY)")
    })?;
    if !first.is("HIERARCHY") {
        return Err(lx.error_at(
            &first,
            format!(
                "expected HIERARCHY at the start of a BVH file, found '{}'",
                first.text
            ),
        ));
    }
    let root_kw = lx.expect_keyword("ROOT", "after HIERARCHY")?;
    let mut joints: Vec<BvhJoint> = Vec::new();
    let mut seen: Vec<Seen> = Vec::new();
    let mut names: HashSet<&'a str> = HashSet::new();
    let mut first_channel = 0;
    let mut stack: Vec<Open> = Vec::new();
    open_joint(
        lx,
        &root_kw,
        None,
        &mut joints,
        &mut seen,
        &mut names,
        &mut stack,
    )?;

    while let Some(&top) = stack.last() {
        let context = match top {
            Open::Joint(j) => format!("in joint '{}'", joints[j].name),
            Open::EndSite(j, _) => format!("in the End Site of joint '{}'", joints[j].name),
        };
        let tok = lx.expect_any(&format!("'}}' {context} (unbalanced braces)"))?;
        match top {
            Open::Joint(j) => {
                let name = joints[j].name.clone();
                if tok.is("OFFSET") {
                    if seen[j].offset {
                        return Err(lx.error_at(&tok, format!("second OFFSET {context}")));
                    }
                    seen[j].offset = true;
                    joints[j].offset = lx.offset_values(&format!("joint '{name}'"))?;
                } else if tok.is("CHANNELS") {
                    if seen[j].channels {
                        return Err(lx.error_at(&tok, format!("second CHANNELS {context}")));
                    }
                    seen[j].channels = true;
                    joints[j].channels = channels(lx, &tok, &name)?;
                    joints[j].first_channel = first_channel;
                    first_channel += joints[j].channels.len();
                } else if tok.is("JOINT") || tok.is("End") || tok.text == "}" {
                    if !seen[j].offset {
                        return Err(lx.error_at(
                            &tok,
                            format!("expected OFFSET {context} before '{}'", tok.text),
                        ));
                    }
                    if !seen[j].channels {
                        return Err(lx.error_at(
                            &tok,
                            format!("expected CHANNELS {context} before '{}'", tok.text),
                        ));
                    }
                    if tok.is("JOINT") {
                        open_joint(
                            lx,
                            &tok,
                            Some(j),
                            &mut joints,
                            &mut seen,
                            &mut names,
                            &mut stack,
                        )?;
                    } else if tok.is("End") {
                        let site = lx.expect_any("Site after End")?;
                        if !site.is("Site") {
                            return Err(lx.error_at(
                                &site,
                                format!("expected 'End Site', found 'End {}'", site.text),
                            ));
                        }
                        let brace = lx.expect_any("'{' after End Site")?;
                        if brace.text != "{" {
                            return Err(lx.error_at(
                                &brace,
                                format!("expected '{{' after End Site, found '{}'", brace.text),
                            ));
                        }
                        stack.push(Open::EndSite(j, None));
                    } else {
                        stack.pop();
                    }
                } else if tok.is("ROOT") {
                    return Err(lx.error_at(
                        &tok,
                        format!(
                            "ROOT inside joint '{name}': expected JOINT (or a '}}' is missing)"
                        ),
                    ));
                } else {
                    return Err(lx.error_at(
                        &tok,
                        format!(
                            "expected OFFSET, CHANNELS, JOINT, End Site or '}}' {context}, found '{}'",
                            tok.text
                        ),
                    ));
                }
            }
            Open::EndSite(j, offset) => {
                if tok.is("OFFSET") {
                    if offset.is_some() {
                        return Err(lx.error_at(&tok, format!("second OFFSET {context}")));
                    }
                    let owner = format!("the End Site of '{}'", joints[j].name);
                    let o = lx.offset_values(&owner)?;
                    if let Some(last) = stack.last_mut() {
                        *last = Open::EndSite(j, Some(o));
                    }
                } else if tok.text == "}" {
                    let Some(o) = offset else {
                        return Err(
                            lx.error_at(&tok, format!("expected OFFSET {context} before '}}'"))
                        );
                    };
                    joints[j].end_sites.push(o);
                    stack.pop();
                } else if tok.is("CHANNELS") {
                    return Err(lx.error_at(
                        &tok,
                        format!("an End Site cannot have CHANNELS ({context}): make it a JOINT"),
                    ));
                } else if tok.is("JOINT") || tok.is("End") {
                    return Err(lx.error_at(
                        &tok,
                        format!(
                            "an End Site cannot have children ({context}): expected OFFSET or '}}'"
                        ),
                    ));
                } else {
                    return Err(lx.error_at(
                        &tok,
                        format!("expected OFFSET or '}}' {context}, found '{}'", tok.text),
                    ));
                }
            }
        }
    }
    Ok(joints)
}

/// Reads `name {` after ROOT/JOINT `kw` and opens the joint's body.
fn open_joint<'a>(
    lx: &mut Lexer<'a>,
    kw: &Tok,
    parent: Option<usize>,
    joints: &mut Vec<BvhJoint>,
    seen: &mut Vec<Seen>,
    names: &mut HashSet<&'a str>,
    stack: &mut Vec<Open>,
) -> Result<(), Error> {
    let name = lx.joint_name(kw)?;
    if !names.insert(name.text) {
        let first_line = joints
            .iter()
            .find(|j| j.name == name.text)
            .map_or(0, |j| j.line);
        return Err(lx.error_at(
            &name,
            format!(
                "duplicate joint name '{}' (first defined on line {first_line}): joint names \
                 must be unique",
                name.text
            ),
        ));
    }
    let brace = lx.expect_any(&format!("'{{' after joint '{}'", name.text))?;
    if brace.text != "{" {
        return Err(lx.error_at(
            &brace,
            format!(
                "expected '{{' after joint '{}', found '{}'",
                name.text, brace.text
            ),
        ));
    }
    joints.push(BvhJoint {
        name: name.text.to_string(),
        parent,
        offset: Vector3::zeros(),
        channels: Vec::new(),
        first_channel: 0,
        end_sites: Vec::new(),
        line: kw.line,
    });
    seen.push(Seen::default());
    stack.push(Open::Joint(joints.len() - 1));
    Ok(())
}

/// `n name{n}` after CHANNELS: a count in 0..=6 and that many distinct channel names, all on
/// the CHANNELS line.
fn channels(lx: &mut Lexer, kw: &Tok, joint: &str) -> Result<Vec<Channel>, Error> {
    let count_tok = lx.next_inline().ok_or_else(|| {
        lx.error_here(format!(
            "expected a channel count after CHANNELS of joint '{joint}'"
        ))
    })?;
    let count = match count_tok.text.parse::<usize>() {
        Ok(n) if n <= 6 => n,
        _ => {
            return Err(lx.error_at(
                &count_tok,
                format!(
                    "expected a channel count from 0 to 6 after CHANNELS of joint '{joint}', found '{}'",
                    count_tok.text
                ),
            ));
        }
    };
    let mut out = Vec::with_capacity(count);
    for n in 0..count {
        let tok = lx.next_inline().ok_or_else(|| {
            lx.error_here(format!(
                "CHANNELS {count} of joint '{joint}' lists only {n} channel names on line {}",
                kw.line
            ))
        })?;
        let c = Channel::from_name(tok.text).ok_or_else(|| {
            lx.error_at(
                &tok,
                format!(
                    "unknown channel '{}' in joint '{joint}': expected Xposition, Yposition, \
                     Zposition, Xrotation, Yrotation or Zrotation",
                    tok.text
                ),
            )
        })?;
        if out.contains(&c) {
            return Err(lx.error_at(
                &tok,
                format!("channel {} listed twice in joint '{joint}'", c.name()),
            ));
        }
        out.push(c);
    }
    if let Some(extra) = lx.next_inline() {
        return Err(lx.error_at(
            &extra,
            format!(
                "CHANNELS {count} of joint '{joint}' lists more than {count} names: unexpected '{}'",
                extra.text
            ),
        ));
    }
    Ok(out)
}

/// `MOTION Frames: n Frame Time: t`.
fn motion_header(lx: &mut Lexer, channel_count: usize) -> Result<(usize, f64), Error> {
    let tok = lx.next().ok_or_else(|| {
        lx.error_here("missing MOTION section: expected MOTION after the hierarchy")
    })?;
    if tok.is("ROOT") {
        return Err(lx.error_at(
            &tok,
            "a second ROOT: articula reads one skeleton per file (expected MOTION)",
        ));
    }
    if !tok.is("MOTION") {
        return Err(lx.error_at(
            &tok,
            format!("expected MOTION after the hierarchy, found '{}'", tok.text),
        ));
    }
    lx.expect_label("Frames", "after MOTION")?;
    let n_tok = lx.expect_any("the number of frames after 'Frames:'")?;
    let frames = match n_tok.text.parse::<usize>() {
        Ok(0) => {
            return Err(lx.error_at(&n_tok, "expected at least 1 frame, found 'Frames: 0'"));
        }
        // a skeleton without channels has nothing in its frame lines, so no byte of the file
        // bounds the declared count: what would every frame hold?
        Ok(_) if channel_count == 0 => {
            return Err(lx.error_at(
                &n_tok,
                "the skeleton has no channels (CHANNELS 0 on every joint): its frames hold no \
                 motion; expected at least one joint with channels",
            ));
        }
        Ok(n) if n.checked_mul(channel_count).is_some() => n,
        Ok(_) => {
            return Err(lx.error_at(&n_tok, format!("'Frames: {}' is too large", n_tok.text)));
        }
        Err(_) => {
            return Err(lx.error_at(
                &n_tok,
                format!(
                    "expected a whole number of frames after 'Frames:', found '{}'",
                    n_tok.text
                ),
            ));
        }
    };
    lx.expect_keyword("Frame", "(of 'Frame Time:') after the Frames line")?;
    lx.expect_label("Time", "after 'Frame'")?;
    let t_tok = lx.expect_any("the frame time in seconds after 'Frame Time:'")?;
    let t = lx.number(&t_tok, "the frame time")?;
    if t <= 0.0 {
        return Err(lx.error_at(
            &t_tok,
            format!(
                "expected a positive frame time in seconds, found '{}'",
                t_tok.text
            ),
        ));
    }
    if let Some(extra) = lx.next_inline() {
        return Err(lx.error_at(
            &extra,
            format!(
                "unexpected '{}' after the frame time: frame values start on the next line",
                extra.text
            ),
        ));
    }
    Ok((frames, t))
}

/// `frames` lines of `channel_count` values each (blank lines between them are skipped).
/// The frame lines' values and the decimal places each was written with
/// ([`super::decimals_of`]).
fn frame_lines(
    lx: &mut Lexer,
    frames: usize,
    channel_count: usize,
) -> Result<(Vec<f64>, Vec<u8>), Error> {
    let total = frames.saturating_mul(channel_count);
    // never trust the declared count for the allocation: each value takes ≥ 2 bytes
    let mut motion = Vec::with_capacity(total.min(lx.src.len() / 2 + 1));
    let mut decimals = Vec::with_capacity(motion.capacity());
    if channel_count > 0 {
        for f in 0..frames {
            lx.skip_blank();
            if lx.pos >= lx.src.len() {
                return Err(lx.error_here(format!(
                    "MOTION is truncated: expected {frames} frame lines ('Frames: {frames}'), found {f}"
                )));
            }
            let line = lx.line;
            for c in 0..channel_count {
                let Some(tok) = lx.next_inline() else {
                    return Err(lx.error_here(format!(
                        "frame {} (line {line}) has {c} values, expected {channel_count} (one per channel)",
                        f + 1
                    )));
                };
                let v = lx.number(&tok, "a channel value")?;
                motion.push(v);
                decimals.push(super::decimals_of(tok.text));
            }
            if let Some(extra) = lx.next_inline() {
                return Err(lx.error_at(
                    &extra,
                    format!(
                        "frame {} (line {line}) has more than {channel_count} values, expected {channel_count} (one per channel)",
                        f + 1
                    ),
                ));
            }
        }
    }
    if let Some(extra) = lx.next() {
        return Err(lx.error_at(
            &extra,
            format!(
                "more frame lines than 'Frames: {frames}': unexpected '{}'",
                extra.text
            ),
        ));
    }
    Ok((motion, decimals))
}
