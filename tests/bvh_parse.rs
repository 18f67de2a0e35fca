//! The reader accepts every lexical and structural variant real BVH files use, and keeps the
//! values exactly as written. Each test pins one variant with a tiny inline file.

use articula::io::bvh::{self, Bvh, Channel};
use articula::rotation::EulerOrder;
use std::path::Path;

const SMALL: &str = "HIERARCHY
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

fn parse(text: &str) -> Bvh {
    bvh::parse_str(text, Path::new("inline.bvh")).unwrap_or_else(|e| panic!("{e}"))
}

fn check_small(b: &Bvh) {
    assert_eq!(b.joints.len(), 2);
    assert_eq!(b.joints[0].name, "Hips");
    assert_eq!(b.joints[1].name, "Spine");
    assert_eq!(b.joints[1].parent, Some(0));
    assert_eq!(b.joints[1].offset.y, 10.0);
    assert_eq!(b.joints[1].end_sites.len(), 1);
    assert_eq!(b.joints[1].end_sites[0].y, 5.0);
    assert_eq!(b.joints[1].first_channel, 6);
    assert_eq!(b.channel_count, 9);
    assert_eq!(b.frames, 2);
    assert_eq!(b.frame_time, 0.0333333);
    assert_eq!(b.frame(1)[8], 18.0);
    assert_eq!(b.motion.len(), 18);
}

#[test]
fn small_file_structure() {
    let b = parse(SMALL);
    check_small(&b);
    assert_eq!(b.joints[0].line, 2);
    assert_eq!(b.joints[1].line, 6);
    assert_eq!(b.joints[0].euler_order(), Some(EulerOrder::ZXY));
    assert_eq!(b.joint_index("Spine"), Some(1));
}

#[test]
fn crlf_line_ends() {
    check_small(&parse(&SMALL.replace('\n', "\r\n")));
}

#[test]
fn mixed_line_ends_and_lone_cr() {
    // alternate CRLF and LF, as in cmu_05_20-mb.bvh; then a lone-CR (classic Mac) variant
    let mixed: String = SMALL
        .split('\n')
        .enumerate()
        .map(|(i, l)| {
            if i % 2 == 0 {
                format!("{l}\r\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    check_small(&parse(&mixed));
    check_small(&parse(&SMALL.replace('\n', "\r")));
}

#[test]
fn error_lines_count_crlf_as_one_line() {
    let text = SMALL.replace('\n', "\r\n").replace("7 8 9", "7 x 9");
    let e = bvh::parse_str(&text, Path::new("a.bvh")).unwrap_err();
    assert!(e.to_string().starts_with("a.bvh:19:15:"), "{e}");
}

#[test]
fn no_final_newline() {
    check_small(&parse(SMALL.trim_end()));
    check_small(&parse(SMALL.replace('\n', "\r\n").trim_end()));
}

#[test]
fn spaces_tabs_trailing_whitespace_and_blank_lines() {
    let text = SMALL
        .replace('\t', "  ")
        .replace('\n', " \t \n")
        .replace("MOTION", "\n\nMOTION")
        .replace("10 11", "\n10  \t 11");
    let b = parse(&text.replace("\n10  \t 11", "10  \t 11"));
    check_small(&b);
    // a blank line between frame lines is skipped
    check_small(&parse(&SMALL.replace("\n10 11", "\n\n10 11")));
}

#[test]
fn bom_is_skipped() {
    check_small(&parse(&format!("\u{feff}{SMALL}")));
}

#[test]
fn frame_time_without_leading_zero_and_tab_after_colon() {
    let b = parse(
        &SMALL
            .replace("Frames: 2", "Frames:\t2")
            .replace("Frame Time: 0.0333333", "Frame Time:\t.0083333"),
    );
    assert_eq!(b.frame_time, 0.0083333);
    assert_eq!(b.frames, 2);
    let b = parse(&SMALL.replace("Frames: 2", "Frames : 2"));
    assert_eq!(b.frames, 2);
}

#[test]
fn scientific_notation_and_negative_zero() {
    let b = parse(
        &SMALL
            .replace("OFFSET 0 10 0", "OFFSET 1.87007e-05 1E1 -0")
            .replace("1 2 3", "-0 -0.000000 -1.94432e-13"),
    );
    let o = b.joints[1].offset;
    assert_eq!(o.x, 1.87007e-05);
    assert_eq!(o.y, 10.0);
    assert!(o.z == 0.0 && o.z.is_sign_negative());
    let f = b.frame(0);
    assert!(f[0] == 0.0 && f[0].is_sign_negative());
    assert!(f[1] == 0.0 && f[1].is_sign_negative());
    assert_eq!(f[2], -1.94432e-13);
}

#[test]
fn six_channels_on_a_child_and_three_on_the_root() {
    let text = SMALL
        .replace(
            "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
            "CHANNELS 3 Zrotation Xrotation Yrotation",
        )
        .replace(
            "CHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd",
            "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n\t\tEnd",
        );
    let b = parse(&text);
    assert_eq!(b.joints[0].channels.len(), 3);
    assert_eq!(b.joints[1].channels.len(), 6);
    assert_eq!(b.joints[1].first_channel, 3);
    assert!(b.joints[1].has_position() && !b.joints[0].has_position());
}

#[test]
fn per_joint_rotation_orders() {
    let text = SMALL.replace(
        "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        "CHANNELS 6 Zrotation Yrotation Xrotation Xposition Yposition Zposition",
    );
    let b = parse(&text);
    assert_eq!(b.joints[0].euler_order(), Some(EulerOrder::ZYX));
    assert_eq!(b.joints[1].euler_order(), Some(EulerOrder::ZXY));
    assert_eq!(b.joints[0].channels[3], Channel::Xposition);
    // and all six orders are read from channel order
    for o in EulerOrder::ALL {
        let names: Vec<String> = o
            .axes()
            .iter()
            .map(|a| format!("{}rotation", ["X", "Y", "Z"][*a]))
            .collect();
        let t = SMALL.replace(
            "Zrotation Xrotation Yrotation\n\t\tEnd",
            &format!("{}\n\t\tEnd", names.join(" ")),
        );
        assert_eq!(parse(&t).joints[1].euler_order(), Some(o));
    }
}

#[test]
fn names_with_punctuation() {
    let b = parse(&SMALL.replace("JOINT Spine", "JOINT mixamorig:Left.Up_Leg-01"));
    assert_eq!(b.joints[1].name, "mixamorig:Left.Up_Leg-01");
}

#[test]
fn zero_length_bones_and_zero_end_sites() {
    let b = parse(
        &SMALL
            .replace("OFFSET 0 10 0", "OFFSET 0 0 0")
            .replace("OFFSET 0 5 0", "OFFSET 0 0 0"),
    );
    assert_eq!(b.joints[1].offset.norm(), 0.0);
    assert_eq!(b.joints[1].end_sites[0].norm(), 0.0);
}

#[test]
fn one_frame_take() {
    let b = parse(
        &SMALL
            .replace("Frames: 2", "Frames: 1")
            .replace("10 11 12 13 14 15 16 17 18\n", ""),
    );
    assert_eq!(b.frames, 1);
    assert_eq!(b.motion.len(), 9);
}

#[test]
fn angles_beyond_a_turn_are_kept_as_written() {
    let b = parse(&SMALL.replace("4 5 6", "573.6 -371.5 1080"));
    assert_eq!(&b.frame(0)[3..6], &[573.6, -371.5, 1080.0]);
}

#[test]
fn keywords_in_any_case_and_several_end_sites() {
    let text = SMALL
        .replace("OFFSET 0 10 0", "offset 0 10 0")
        .replace("End Site", "End site")
        .replace(
            "\t\t}\n\t}",
            "\t\t}\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 1 0 0\n\t\t}\n\t}",
        );
    let b = parse(&text);
    assert_eq!(b.joints[1].end_sites.len(), 2);
    assert_eq!(b.joints[1].end_sites[1].x, 1.0);
}

#[test]
fn a_skeleton_of_180_joints() {
    // a chain of 180 joints, each with 6 channels, 3 frames
    let n = 180;
    let mut t = String::from("HIERARCHY\n");
    for i in 0..n {
        let tabs = "\t".repeat(i);
        let kw = if i == 0 { "ROOT" } else { "JOINT" };
        t += &format!(
            "{tabs}{kw} j{i}.L\n{tabs}{{\n{tabs}\tOFFSET 0 1 0\n{tabs}\tCHANNELS 6 Xposition Yposition Zposition Xrotation Yrotation Zrotation\n"
        );
    }
    t += &format!(
        "{}End Site\n{}{{\n{}OFFSET 0 1 0\n{}}}\n",
        "\t".repeat(n),
        "\t".repeat(n),
        "\t".repeat(n + 1),
        "\t".repeat(n)
    );
    for i in (0..n).rev() {
        t += &format!("{}}}\n", "\t".repeat(i));
    }
    t += "MOTION\nFrames: 3\nFrame Time: 0.01\n";
    for k in 0..3 {
        let row: Vec<String> = (0..6 * n).map(|c| format!("{}", c + k)).collect();
        t += &row.join(" ");
        t += "\n";
    }
    let b = parse(&t);
    assert_eq!(b.joints.len(), n);
    assert_eq!(b.joints[n - 1].parent, Some(n - 2));
    assert_eq!(b.channel_count, 6 * n);
    assert_eq!(b.frame(2)[6 * n - 1], (6 * n - 1 + 2) as f64);
}

#[test]
fn non_utf8_bytes_become_replacement_characters() {
    let mut bytes = SMALL
        .replace("JOINT Spine", "JOINT Sp\u{e9}ine")
        .into_bytes();
    // turn the UTF-8 'é' (C3 A9) into Latin-1 (E9 + a space-free filler)
    let at = bytes.windows(2).position(|w| w == [0xc3, 0xa9]).unwrap();
    bytes.splice(at..at + 2, [0xe9]);
    let b = bvh::parse_bytes(&bytes, Path::new("latin1.bvh")).unwrap();
    assert_eq!(b.joints[1].name, "Sp\u{fffd}ine");
}

/// `parse_bytes` checks only a file's first 64 KiB as UTF-8 before the fast reader: a header
/// that runs past them (a joint name of tens of thousands of characters), cut anywhere — in
/// the name, inside a two-byte character, inside the frame time, in the frame lines — reads
/// as `parse_str` reads the whole text; a non-ASCII byte in the frame lines is the same error.
#[test]
fn headers_past_the_checked_start_read_as_the_whole_text() {
    let head_bytes = 1 << 16;
    for len in (head_bytes - 300..head_bytes + 20).step_by(3) {
        // about `len` bytes of name: one or two ASCII letters, then two-byte characters
        let name = format!(
            "{}{}",
            "a".repeat(len % 2 + 1),
            "\u{e9}".repeat((len - 1) / 2)
        );
        let text = SMALL.replace("JOINT Spine", &format!("JOINT {name}"));
        let b = bvh::parse_bytes(text.as_bytes(), Path::new("long.bvh")).unwrap();
        assert_eq!(b, parse(&text), "{len}");
        assert_eq!(b.frame_time, 0.0333333, "{len}");
        assert_eq!(b.joints[1].name, name, "{len}");
        let bad = text.replace(" 18\n", " 1\u{e9}\n");
        let from_bytes = bvh::parse_bytes(bad.as_bytes(), Path::new("long.bvh"));
        let from_text = bvh::parse_str(&bad, Path::new("long.bvh"));
        assert_eq!(
            from_bytes.unwrap_err().to_string(),
            from_text.unwrap_err().to_string()
        );
    }
}

#[test]
fn read_reports_missing_files_as_io_errors() {
    let e = bvh::read(Path::new("/nonexistent/take.bvh")).unwrap_err();
    assert!(matches!(e, articula::error::Error::Io { .. }), "{e}");
}

#[test]
fn channel_names_and_euler_orders() {
    assert_eq!(Channel::from_name("Xrotation"), Some(Channel::Xrotation));
    assert_eq!(Channel::from_name("ZPOSITION"), Some(Channel::Zposition));
    assert_eq!(Channel::from_name("Xrot"), None);
    // fewer than three rotation channels: no Euler order, but a valid joint
    let b = parse(
        &SMALL
            .replace(
                "CHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd",
                "CHANNELS 2 Zrotation Xposition\n\t\tEnd",
            )
            .replace("7 8 9", "7 8")
            .replace("16 17 18", "16 17"),
    );
    assert_eq!(b.joints[1].euler_order(), None);
    assert_eq!(b.joints[1].position_columns(), [Some(1), None, None]);
    // no channels at all on a joint
    let b = parse(
        &SMALL
            .replace(
                "CHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd",
                "CHANNELS 0\n\t\tEnd",
            )
            .replace(" 7 8 9", "")
            .replace(" 16 17 18", ""),
    );
    assert!(b.joints[1].channels.is_empty());
    assert_eq!(b.channel_count, 6);
}
