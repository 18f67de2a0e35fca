//! Malformed BVH input is an `Error::Parse` naming the file, the line and column, and what was
//! expected, never a panic. One test case per kind of damage, each pinning the line and the
//! message; then a property test: random byte mutations of a valid file never panic.

use articula::error::Error;
use articula::io::bvh;
use proptest::prelude::*;
use std::path::Path;

/// A valid file; the cases below damage one thing each. Line numbers in comments.
const GOOD: &str = "HIERARCHY
ROOT Hips
{
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
\tJOINT Spine
\t{
\t\tOFFSET 0 10 0
\t\tCHANNELS 3 Zrotation Xrotation Yrotation
\t\tEnd Site
\t\t{
\t\t\tOFFSET 0 5 0
\t\t}
\t}
}
MOTION
Frames: 2
Frame Time: 0.0333333
1 2 3 4 5 6 7 8 9
10 11 12 13 14 15 16 17 18
";

/// (line, column, message) of the parse error of `text`.
fn error_of(text: &str) -> (usize, usize, String) {
    match bvh::parse_str(text, Path::new("bad.bvh")) {
        Ok(_) => panic!("accepted malformed input:\n{text}"),
        Err(Error::Parse { at, message }) => {
            assert_eq!(at.file, Path::new("bad.bvh"));
            (at.line, at.column, message)
        }
        Err(e) => panic!("not a parse error: {e}"),
    }
}

/// Asserts that `text` fails on `line` with a message containing every one of `needles`.
fn fails(text: &str, line: usize, needles: &[&str]) {
    let (l, c, m) = error_of(text);
    assert_eq!(l, line, "wrong line for: {m}");
    assert!(c >= 1);
    for n in needles {
        assert!(m.contains(n), "message '{m}' lacks '{n}'");
    }
}

fn good_is_good() -> bool {
    bvh::parse_str(GOOD, Path::new("good.bvh")).is_ok()
}

#[test]
fn the_base_file_is_valid() {
    assert!(good_is_good());
}

#[test]
fn empty_file() {
    fails("", 1, &["empty file", "HIERARCHY"]);
    fails(" \n\t\n", 3, &["empty file"]);
}

#[test]
fn missing_hierarchy() {
    fails(
        &GOOD.replacen("HIERARCHY\n", "", 1),
        1,
        &["expected HIERARCHY", "ROOT"],
    );
}

#[test]
fn missing_root() {
    fails(
        &GOOD.replace("ROOT Hips", "JOINT Hips"),
        2,
        &["expected ROOT", "JOINT"],
    );
}

#[test]
fn root_without_a_name() {
    let (l, c, m) = error_of(&GOOD.replace("ROOT Hips", "ROOT"));
    assert_eq!((l, c), (2, 5));
    assert!(m.contains("expected a joint name after ROOT"), "{m}");
}

#[test]
fn name_with_a_blank() {
    fails(
        &GOOD.replace("JOINT Spine", "JOINT Spine 2"),
        6,
        &["expected '{'", "'2'"],
    );
}

#[test]
fn missing_open_brace() {
    fails(
        &GOOD.replacen("{\n\tOFFSET 0 0 0", "\tOFFSET 0 0 0", 1),
        3,
        &["expected '{'", "OFFSET"],
    );
}

#[test]
fn missing_offset() {
    fails(
        &GOOD.replace("\t\tOFFSET 0 10 0\n", ""),
        9,
        &["expected OFFSET", "Spine"],
    );
}

#[test]
fn offset_with_two_numbers() {
    let (l, c, m) = error_of(&GOOD.replace("OFFSET 0 10 0", "OFFSET 0 10"));
    assert_eq!((l, c), (8, 14));
    assert!(
        m.contains("expected 3 numbers after OFFSET of joint 'Spine', found 2"),
        "{m}"
    );
}

#[test]
fn offset_with_four_numbers() {
    fails(
        &GOOD.replace("OFFSET 0 10 0", "OFFSET 0 10 0 4"),
        8,
        &["found a fourth", "'4'"],
    );
}

#[test]
fn non_numeric_offset() {
    let (l, c, m) = error_of(&GOOD.replace("OFFSET 0 10 0", "OFFSET 0 ten 0"));
    assert_eq!((l, c), (8, 12));
    assert!(
        m.contains("expected a number for the OFFSET y of joint 'Spine', found 'ten'"),
        "{m}"
    );
}

#[test]
fn duplicate_offset() {
    fails(
        &GOOD.replace(
            "\t\tOFFSET 0 10 0\n",
            "\t\tOFFSET 0 10 0\n\t\tOFFSET 0 1 0\n",
        ),
        9,
        &["second OFFSET", "Spine"],
    );
}

#[test]
fn missing_channels() {
    fails(
        &GOOD.replace("\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n", ""),
        9,
        &["expected CHANNELS", "Spine"],
    );
}

#[test]
fn duplicate_channels_line() {
    fails(
        &GOOD.replace(
            "\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n",
            "\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n\t\tCHANNELS 0\n",
        ),
        10,
        &["second CHANNELS"],
    );
}

#[test]
fn channel_count_not_a_number() {
    fails(
        &GOOD.replace("CHANNELS 3 Zrot", "CHANNELS three Zrot"),
        9,
        &["expected a channel count from 0 to 6", "'three'"],
    );
}

#[test]
fn channel_count_above_six() {
    fails(
        &GOOD.replace("CHANNELS 3 Zrot", "CHANNELS 7 Zrot"),
        9,
        &["from 0 to 6", "'7'"],
    );
}

#[test]
fn channel_count_larger_than_the_list() {
    fails(
        &GOOD.replace("CHANNELS 3 Zrot", "CHANNELS 4 Zrot"),
        9,
        &["CHANNELS 4", "lists only 3"],
    );
}

#[test]
fn channel_count_smaller_than_the_list() {
    fails(
        &GOOD.replace("CHANNELS 3 Zrot", "CHANNELS 2 Zrot"),
        9,
        &["more than 2", "'Yrotation'"],
    );
}

#[test]
fn unknown_channel() {
    let (l, c, m) = error_of(&GOOD.replace(
        "Xrotation Yrotation\n\t\tEnd",
        "Xrotation Wrotation\n\t\tEnd",
    ));
    assert_eq!((l, c), (9, 34));
    assert!(
        m.contains("unknown channel 'Wrotation'") && m.contains("expected Xposition"),
        "{m}"
    );
}

#[test]
fn channel_listed_twice() {
    fails(
        &GOOD.replace(
            "Zrotation Xrotation Yrotation\n\t\tEnd",
            "Zrotation Xrotation Zrotation\n\t\tEnd",
        ),
        9,
        &["Zrotation listed twice"],
    );
}

#[test]
fn duplicate_joint_names() {
    fails(
        &GOOD.replace("JOINT Spine", "JOINT Hips"),
        6,
        &["duplicate joint name 'Hips'", "line 2"],
    );
}

#[test]
fn end_site_with_channels() {
    fails(
        &GOOD.replace(
            "\t\t\tOFFSET 0 5 0\n",
            "\t\t\tOFFSET 0 5 0\n\t\t\tCHANNELS 3 Xrotation Yrotation Zrotation\n",
        ),
        13,
        &["End Site cannot have CHANNELS"],
    );
}

#[test]
fn end_site_with_a_child() {
    fails(
        &GOOD.replace(
            "\t\t\tOFFSET 0 5 0\n",
            "\t\t\tOFFSET 0 5 0\n\t\t\tJOINT Toe\n",
        ),
        13,
        &["End Site cannot have children"],
    );
}

#[test]
fn end_site_without_offset() {
    fails(
        &GOOD.replace("\t\t\tOFFSET 0 5 0\n", ""),
        12,
        &["expected OFFSET in the End Site of joint 'Spine'"],
    );
}

#[test]
fn end_without_site() {
    fails(
        &GOOD.replace("End Site", "End Effector"),
        10,
        &["expected 'End Site'", "'End Effector'"],
    );
}

#[test]
fn unexpected_keyword_in_a_joint() {
    fails(
        &GOOD.replace("\t\tEnd Site", "\t\tBONE\n\t\tEnd Site"),
        10,
        &[
            "expected OFFSET, CHANNELS, JOINT, End Site or '}'",
            "'BONE'",
        ],
    );
}

#[test]
fn unbalanced_braces_missing_close() {
    // one '}' short: MOTION appears inside the root's body
    fails(
        &GOOD.replacen("\t}\n}\n", "\t}\n", 1),
        15,
        &["found 'MOTION'", "in joint 'Hips'"],
    );
}

#[test]
fn unbalanced_braces_extra_close() {
    fails(
        &GOOD.replacen("}\nMOTION", "}\n}\nMOTION", 1),
        16,
        &["expected MOTION after the hierarchy", "'}'"],
    );
}

#[test]
fn truncated_hierarchy() {
    let cut = &GOOD[..GOOD.find("\t}\n}").unwrap()];
    fails(
        cut,
        14,
        &[
            "unexpected end of file",
            "'}' in joint 'Spine'",
            "unbalanced",
        ],
    );
}

#[test]
fn second_root() {
    let text = GOOD.replacen(
        "MOTION",
        "ROOT Other\n{\n\tOFFSET 0 0 0\n\tCHANNELS 0\n}\nMOTION",
        1,
    );
    fails(&text, 16, &["a second ROOT"]);
}

#[test]
fn missing_motion() {
    let text = &GOOD[..GOOD.find("MOTION").unwrap()];
    fails(text, 16, &["missing MOTION section"]);
}

#[test]
fn missing_frames_line() {
    fails(
        &GOOD.replace("Frames: 2\n", ""),
        17,
        &["expected 'Frames:' after MOTION", "'Frame'"],
    );
}

#[test]
fn frames_not_a_number() {
    fails(
        &GOOD.replace("Frames: 2", "Frames: two"),
        17,
        &["expected a whole number of frames", "'two'"],
    );
    fails(
        &GOOD.replace("Frames: 2", "Frames: -2"),
        17,
        &["whole number", "'-2'"],
    );
}

#[test]
fn zero_frames() {
    fails(
        &GOOD.replace("Frames: 2", "Frames: 0"),
        17,
        &["at least 1 frame"],
    );
}

#[test]
fn frames_without_colon() {
    fails(
        &GOOD.replace("Frames: 2", "Frames 2"),
        17,
        &["expected ':' after Frames", "'2'"],
    );
}

#[test]
fn missing_frame_time() {
    fails(
        &GOOD.replace("Frame Time: 0.0333333\n", ""),
        18,
        &["expected Frame", "'1'"],
    );
}

#[test]
fn zero_frame_time() {
    fails(
        &GOOD.replace("Frame Time: 0.0333333", "Frame Time: 0"),
        18,
        &["positive frame time", "'0'"],
    );
}

#[test]
fn negative_frame_time() {
    fails(
        &GOOD.replace("Frame Time: 0.0333333", "Frame Time: -0.01"),
        18,
        &["positive frame time", "'-0.01'"],
    );
}

#[test]
fn non_numeric_frame_time() {
    fails(
        &GOOD.replace("Frame Time: 0.0333333", "Frame Time: fast"),
        18,
        &["expected a number for the frame time", "'fast'"],
    );
}

#[test]
fn values_on_the_frame_time_line() {
    fails(
        &GOOD.replace("Frame Time: 0.0333333\n", "Frame Time: 0.0333333 1 2"),
        18,
        &["after the frame time"],
    );
}

#[test]
fn frame_line_with_too_few_values() {
    let (l, c, m) = error_of(&GOOD.replace("1 2 3 4 5 6 7 8 9", "1 2 3 4 5 6 7 8"));
    assert_eq!((l, c), (19, 16));
    assert!(
        m.contains("frame 1 (line 19) has 8 values, expected 9"),
        "{m}"
    );
}

#[test]
fn frame_line_with_too_many_values() {
    let (l, c, m) = error_of(&GOOD.replace(
        "10 11 12 13 14 15 16 17 18",
        "10 11 12 13 14 15 16 17 18 19",
    ));
    assert_eq!((l, c), (20, 28));
    assert!(
        m.contains("frame 2 (line 20) has more than 9 values"),
        "{m}"
    );
}

#[test]
fn non_numeric_value() {
    let (l, c, m) = error_of(&GOOD.replace("13 14", "13 1,4"));
    assert_eq!((l, c), (20, 13));
    assert!(
        m.contains("expected a number for a channel value, found '1,4'"),
        "{m}"
    );
}

#[test]
fn nan_and_infinities() {
    for bad in ["NaN", "nan", "inf", "-inf", "infinity", "1e999"] {
        let (l, _, m) = error_of(&GOOD.replace("13 14", &format!("13 {bad}")));
        assert_eq!(l, 20);
        assert!(m.contains("finite number") && m.contains(bad), "{m}");
    }
}

#[test]
fn truncated_motion() {
    let text = GOOD.replace("10 11 12 13 14 15 16 17 18\n", "");
    fails(
        &text,
        20,
        &["MOTION is truncated", "expected 2 frame lines", "found 1"],
    );
}

#[test]
fn truncated_last_frame_line() {
    let text = GOOD.replace("10 11 12 13 14 15 16 17 18\n", "10 11 12");
    fails(&text, 20, &["frame 2 (line 20) has 3 values, expected 9"]);
}

#[test]
fn more_frame_lines_than_declared() {
    fails(
        &format!("{GOOD}1 1 1 1 1 1 1 1 1\n"),
        21,
        &["more frame lines than 'Frames: 2'"],
    );
}

#[test]
fn error_display_names_file_line_and_column() {
    let e = bvh::parse_str(&GOOD.replace("13 14", "13 x"), Path::new("dir/take.bvh")).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("dir/take.bvh:20:13: expected a number"),
        "{e}"
    );
}

#[test]
fn huge_declared_frame_count_is_an_error_not_an_allocation() {
    fails(
        &GOOD.replace("Frames: 2", "Frames: 18446744073709551615"),
        17,
        &["Frames: 18446744073709551615"],
    );
    fails(
        &GOOD.replace("Frames: 2", "Frames: 99999999999999999999999"),
        17,
        &["whole number"],
    );
}

#[test]
fn deep_nesting_does_not_overflow_the_stack() {
    let mut t = String::from("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n");
    for i in 0..100_000 {
        t += &format!("JOINT j{i}\n{{\nOFFSET 0 0 0\nCHANNELS 0\n");
    }
    // never closed: the error comes at the end of the file
    let (l, _, m) = error_of(&t);
    assert_eq!(l, 5 + 4 * 100_000 + 1);
    assert!(m.contains("unexpected end of file"), "{m}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// Any byte mutation (replace, insert, delete, up to 8 of them) of a valid file gives a
    /// parse result or a parse error, never a panic; errors carry a line inside the file.
    #[test]
    fn random_mutations_never_panic(
        edits in proptest::collection::vec((any::<u16>(), any::<u8>(), 0u8..3), 1..8)
    ) {
        let mut bytes = GOOD.as_bytes().to_vec();
        for (at, byte, kind) in edits {
            let at = at as usize % (bytes.len() + 1);
            match kind {
                0 if at < bytes.len() => bytes[at] = byte,
                1 => bytes.insert(at, byte),
                _ if at < bytes.len() => { bytes.remove(at); }
                _ => {}
            }
        }
        let lines = bytes.iter().filter(|&&b| b == b'\n' || b == b'\r').count() + 1;
        match bvh::parse_bytes(&bytes, Path::new("fuzz.bvh")) {
            Ok(b) => {
                prop_assert_eq!(b.motion.len(), b.frames * b.channel_count);
                prop_assert!(b.motion.iter().all(|v| v.is_finite()));
            }
            Err(Error::Parse { at, .. }) => prop_assert!(at.line >= 1 && at.line <= lines),
            Err(e) => prop_assert!(false, "unexpected error kind: {}", e),
        }
    }
}

#[test]
fn root_inside_a_joint() {
    fails(
        &GOOD.replace("JOINT Spine", "ROOT Spine"),
        6,
        &["ROOT inside joint 'Hips'"],
    );
}

#[test]
fn frame_time_without_colon() {
    fails(
        &GOOD.replace("Frame Time: 0.0333333", "Frame Time 0.0333333"),
        18,
        &["expected ':' after Time"],
    );
}

#[test]
fn file_ends_after_end() {
    let cut = &GOOD[..GOOD.find("End Site").unwrap() + 3];
    fails(cut, 10, &["unexpected end of file", "Site"]);
}

#[test]
fn end_site_missing_its_brace() {
    fails(
        &GOOD.replace("End Site\n\t\t{", "End Site\n"),
        12,
        &["expected '{' after End Site", "'OFFSET'"],
    );
}

#[test]
fn a_skeleton_without_channels_never_allocates_for_its_declared_frames() {
    // 'Frames: 1000000000' with no channel: no byte of the file bounds the count (this
    // aborted allocating 16 GB in the rest-frame scan)
    let t = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n\
             MOTION\nFrames: 1000000000\nFrame Time: 0.01\n";
    let (l, _, m) = error_of(t);
    assert_eq!(l, 12);
    assert!(m.contains("no channels"), "{m}");
}

#[test]
fn control_characters_are_refused_by_code_point_never_echoed() {
    // an ESC in a joint name reached the terminal as an escape sequence in the error
    let t = GOOD.replace("JOINT Spine", "JOINT Sp\u{1b}]0;pwned\u{7}ine");
    let (l, c, m) = error_of(&t);
    assert_eq!((l, c), (6, 10));
    assert!(m.contains("U+001B") && !m.contains('\u{1b}'), "{m}");
    // a NUL in the motion
    let t = GOOD.replace("10 11 12", "10 \0 12");
    let (l, _, m) = error_of(&t);
    assert_eq!(l, 20);
    assert!(m.contains("U+0000"), "{m}");
}
