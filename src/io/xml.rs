//! The few pieces every XML writer of articula shares (URDF, MJCF): numbers in their shortest
//! exact form, escaped attribute values and comment text. Writing is string formatting; reading
//! XML is `roxmltree`'s job elsewhere.

use nalgebra::Vector3;

/// Shortest exact decimal form of `x` ([`Shortest`](super::shortest::Shortest)), `-0` written
/// as `0`, `1.0` as `1`.
pub fn num(x: f64) -> String {
    let x = if x == 0.0 { 0.0 } else { x };
    super::shortest::plain(x)
}

/// `x y z`, each by [`num`].
pub fn vec3(v: &Vector3<f64>) -> String {
    format!("{} {} {}", num(v.x), num(v.y), num(v.z))
}

/// `xs` by [`num`], separated by spaces.
pub fn nums(xs: &[f64]) -> String {
    xs.iter().map(|&x| num(x)).collect::<Vec<_>>().join(" ")
}

/// Escapes an XML attribute value.
pub fn attr(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Text safe inside `<!-- … -->` (no `--`, which XML forbids there).
pub fn comment(s: &str) -> String {
    let mut t = s.to_string();
    while t.contains("--") {
        t = t.replace("--", "- -");
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_shortest_and_round_trip() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(0.1 + 0.2), "0.30000000000000004");
        let x = 1.0 / 3.0;
        assert_eq!(num(x).parse::<f64>().unwrap(), x);
    }

    #[test]
    fn attributes_and_comments_are_escaped() {
        assert_eq!(attr("a<\"b\">&"), "a&lt;&quot;b&quot;&gt;&amp;");
        assert_eq!(comment("a---b--c"), "a- - -b- -c");
        assert!(!comment("----").contains("--"));
    }
}
