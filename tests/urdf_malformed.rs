//! Hostile or malformed URDF input is an `Error::Parse` naming the file, the line and what was
//! expected, never a panic or a stack overflow; real-world oddities (an empty `<texture/>`,
//! unknown elements of any depth) are accepted. One test per kind of damage, then a property
//! test: random byte mutations of a valid file never panic.

use articula::error::Error;
use articula::model::urdf::{UrdfOptions, parse_urdf};
use proptest::prelude::*;
use std::path::Path;

/// A valid file; the cases below damage one thing each. Line numbers in comments.
const GOOD: &str = r#"<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <inertial>
      <origin xyz="0 0 0.1" rpy="0 0 0"/>
      <mass value="2"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
  </link>
  <link name="l1">
    <inertial>
      <mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
    <visual>
      <geometry><box size="0.1 0.1 0.1"/></geometry>
    </visual>
  </link>
  <link name="l2"/>
  <joint name="j1" type="revolute">
    <parent link="base"/>
    <child link="l1"/>
    <origin xyz="0 0 0.2" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <joint name="j2" type="prismatic">
    <parent link="l1"/>
    <child link="l2"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/>
    <axis xyz="1 0 0"/>
  </joint>
</robot>
"#;

fn parse(text: &str) -> Result<articula::model::Model, Error> {
    parse_urdf(text, Path::new("bad.urdf"), &UrdfOptions::default())
}

/// (line, column, message) of the parse error of `text`.
fn error_of(text: &str) -> (usize, usize, String) {
    match parse(text) {
        Ok(_) => panic!("accepted malformed input:\n{text}"),
        Err(Error::Parse { at, message }) => {
            assert_eq!(at.file, Path::new("bad.urdf"));
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

#[test]
fn the_base_file_is_valid() {
    let m = parse(GOOD).unwrap();
    assert_eq!(m.name, "r");
    assert_eq!(m.nbodies(), 3);
}

/// Runs `f` on a thread with a 256 KiB stack: a reader that recursed per nesting level would
/// overflow it (and abort the process) long before 14,000 levels.
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap()
}

/// `depth` nested `<tag>` elements inside the base link, closed or not.
fn deep(depth: usize, tag: &str, closed: bool) -> String {
    let open = format!("<{tag}>").repeat(depth);
    let close = if closed {
        format!("</{tag}>").repeat(depth)
    } else {
        String::new()
    };
    GOOD.replacen(
        "  <link name=\"l1\">",
        &format!("  <extra>\n{open}{close}\n  </extra>\n  <link name=\"l1\">"),
        1,
    )
}

#[test]
fn deep_nesting_parses_or_fails_cleanly_on_a_small_stack() {
    for depth in [14_000, 100_000] {
        for tag in ["link", "unknown"] {
            let text = deep(depth, tag, true);
            // nested elements that are not children of <robot> are ignored, whatever they are
            let model = on_small_stack(move || parse(&text).map(|m| m.nbodies()));
            assert_eq!(model.unwrap(), 3, "{depth} {tag}");
            // unclosed: an error at the end of the text, not an abort
            let text = deep(depth, tag, false);
            let lines = text.lines().count();
            let (l, _, m) = on_small_stack(move || error_of(&text));
            assert!(l >= 10 && l <= lines, "{depth} {tag}: line {l}: {m}");
            assert!(m.contains("XML"), "{m}");
        }
    }
}

#[test]
fn deep_nesting_as_the_whole_document_fails_cleanly() {
    let text = "<robot>".repeat(100_000) + &"</robot>".repeat(100_000);
    // nested robots: the outer one has no <link>
    let (l, _, m) = on_small_stack(move || error_of(&text));
    assert_eq!(l, 1);
    assert!(m.contains("no <link>"), "{m}");
}

#[test]
fn empty_texture_and_unknown_elements_are_accepted() {
    // iCub's and Romeo's URDFs (example-robot-data) have materials with an empty <texture/>
    let text = GOOD
        .replace(
            "<robot name=\"r\">",
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n  \
             <material name=\"Grey\"><color rgba=\"0.5 0.5 0.5 1\"/><texture/></material>",
        )
        .replace(
            "</geometry>",
            "</geometry>\n      <material name=\"Grey\"><texture/></material>",
        )
        .replace(
            "</robot>",
            "  <gazebo reference=\"l1\"><mu1>0.2</mu1></gazebo>\n  \
             <transmission name=\"t\"><type>x</type></transmission>\n  \
             <xacro:property name=\"p\" value=\"1\"/>\n</robot>",
        );
    let a = parse(&text).unwrap();
    let b = parse(GOOD).unwrap();
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
}

#[test]
fn bad_numbers_name_the_joint_the_attribute_and_the_line() {
    fails(
        &GOOD.replace(
            "<origin xyz=\"0 0 0.3\" rpy=\"0 0 0\"/>",
            "<origin xyz=\"a b\" rpy=\"0 0 0\"/>",
        ),
        30,
        &["joint `j2`: <origin xyz> expects three numbers, found 'a b'"],
    );
    fails(
        &GOOD.replace("<axis xyz=\"1 0 0\"/>", "<axis xyz=\"1 0 0 0\"/>"),
        31,
        &["joint `j2`: <axis xyz> expects three numbers, found '1 0 0 0'"],
    );
    fails(
        &GOOD.replace("<mass value=\"1\"/>", "<mass value=\"1kg\"/>"),
        12,
        &["link `l1`: <mass value> expects a number, found '1kg'"],
    );
    fails(
        &GOOD.replace("iyy=\"0.1\"", "iyy=\"\""),
        7,
        &["link `base`: <inertia iyy> expects a number"],
    );
    let (l, c, _) = error_of(&GOOD.replace("iyy=\"0.1\"", "iyy=\"x\""));
    assert_eq!((l, c), (7, 47), "the column of the value");
}

#[test]
fn missing_pieces_are_named() {
    fails(
        &GOOD.replace("<parent link=\"l1\"/>", "<parent link=\"base2\"/>"),
        28,
        &["joint `j2` names parent link `base2`, which is not defined"],
    );
    fails(
        &GOOD.replace("<child link=\"l1\"/>", "<child link=\"l9\"/>"),
        22,
        &["joint `j1` names child link `l9`, which is not defined"],
    );
    fails(
        &GOOD.replace("    <parent link=\"l1\"/>\n", ""),
        27,
        &["joint `j2`: no <parent link>"],
    );
    fails(
        &GOOD.replace("<mass value=\"1\"/>", ""),
        11,
        &["link `l1`: <inertial> has no <mass value>"],
    );
    fails(
        &GOOD.replace(" type=\"prismatic\"", ""),
        27,
        &["joint `j2`: <joint type> is missing"],
    );
    fails(
        &GOOD.replace("type=\"prismatic\"", "type=\"prismatik\""),
        27,
        &["joint `j2`: unknown type 'prismatik'"],
    );
    fails(
        &GOOD.replace("<link name=\"l2\"/>", "<link name=\"l1\"/>"),
        19,
        &["link `l1` is defined twice"],
    );
    fails(
        &GOOD
            .replace("<robot name=\"r\">", "<robt name=\"r\">")
            .replace("</robot>", "</robt>"),
        2,
        &["expected a <robot> root element, found <robt>"],
    );
}

#[test]
fn trees_only() {
    // every link has a parent: a loop through the base
    fails(
        &GOOD.replace(
            "</robot>",
            "  <joint name=\"j3\" type=\"fixed\"><parent link=\"l2\"/><child link=\"base\"/></joint>\n</robot>",
        ),
        2,
        &["no root link: the joints form a loop"],
    );
    // a second parent
    let text = GOOD.replace(
        "</robot>",
        "  <link name=\"l3\"/>\n  <joint name=\"j3\" type=\"fixed\"><parent link=\"l3\"/><child link=\"l2\"/></joint>\n</robot>",
    );
    fails(
        &text,
        34,
        &["joint `j3`: link `l2` already has a parent joint"],
    );
    let text = GOOD.replace(
        "</robot>",
        "  <link name=\"l3\"/>\n  <link name=\"l4\"/>\n  \
         <joint name=\"j3\" type=\"fixed\"><parent link=\"l3\"/><child link=\"l4\"/></joint>\n  \
         <joint name=\"j4\" type=\"fixed\"><parent link=\"l4\"/><child link=\"l3\"/></joint>\n</robot>",
    );
    fails(
        &text,
        33,
        &["link `l3` is not reached from the root link `base`"],
    );
}

#[test]
fn truncated_file() {
    // cut inside the second joint's origin: the error is at the end, on line 30
    let cut = GOOD.find("<origin xyz=\"0 0 0.3\"").unwrap() + 10;
    fails(&GOOD[..cut], 30, &["not well-formed XML"]);
    // cut after a complete link: the robot element is never closed
    let cut = GOOD.find("  <link name=\"l2\"/>").unwrap();
    let (l, _, m) = error_of(&GOOD[..cut]);
    assert!(m.contains("not well-formed XML"), "{m}");
    assert!((19..=20).contains(&l), "{l}: {m}");
    fails("", 1, &["not well-formed XML"]);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// Any byte mutation (replace, insert, delete, up to 8 of them) of a valid file gives a
    /// model or a parse error, never a panic; errors carry a line inside the file.
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
        let text = String::from_utf8_lossy(&bytes);
        let lines = text.lines().count().max(1) + 1;
        match parse(&text) {
            Ok(m) => prop_assert!(m.nbodies() <= 3),
            Err(Error::Parse { at, .. }) => prop_assert!(at.line >= 1 && at.line <= lines),
            Err(e) => prop_assert!(false, "unexpected error kind: {}", e),
        }
    }
}
