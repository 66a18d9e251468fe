//! The little JSON a scene page carries: strings escaped so that nothing in them can end the
//! `<script>` element they sit in, finite numbers in Rust's shortest round-trip form, and
//! long arrays of samples as base64 of little-endian floats.

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;

/// A JSON string literal. `<`, `>` and `&` are escaped too, so that the text can sit inside
/// an HTML `<script>` element.
pub(crate) fn string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '<' | '>' | '&' | '\u{2028}' | '\u{2029}' => {
                out.push_str(&format!("\\u{:04x}", c as u32));
            }
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A JSON number; callers pass finite values only (a non-finite one becomes `null`).
pub(crate) fn number(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else {
        "null".to_string()
    }
}

/// A JSON array of numbers.
pub(crate) fn numbers(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|&v| number(v)).collect();
    format!("[{}]", items.join(","))
}

/// The values as little-endian 32-bit floats, base64-encoded: positions and orientations,
/// for which single precision is far below a pixel.
pub(crate) fn f32_base64(values: &[f64]) -> String {
    let bytes: Vec<u8> = values
        .iter()
        .flat_map(|&v| (v as f32).to_le_bytes())
        .collect();
    string(&STANDARD.encode(bytes))
}

/// The values as little-endian 64-bit floats, base64-encoded: times and displayed values,
/// exactly as computed.
pub(crate) fn f64_base64(values: &[f64]) -> String {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    string(&STANDARD.encode(bytes))
}

/// A JSON object from its members, in order.
pub(crate) fn object(members: &[(&str, String)]) -> String {
    let items: Vec<String> = members
        .iter()
        .map(|(k, v)| format!("{}:{v}", string(k)))
        .collect();
    format!("{{{}}}", items.join(","))
}

/// A JSON array of already written values.
pub(crate) fn array(items: &[String]) -> String {
    format!("[{}]", items.join(","))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_cannot_close_the_script_element() {
        assert_eq!(string("a\"b\\c\n"), r#""a\"b\\c\n""#);
        assert_eq!(string("</script>"), r#""\u003c/script\u003e""#);
        assert_eq!(string("φ ≥ 0\u{1}"), "\"φ ≥ 0\\u0001\"");
        assert_eq!(number(0.1), "0.1");
        assert_eq!(number(f64::NAN), "null");
        assert_eq!(numbers(&[1.0, -2.5]), "[1.0,-2.5]");
        assert_eq!(object(&[("a", number(1.0))]), r#"{"a":1.0}"#);
        // 1.0f32 is 00 00 80 3f.
        assert_eq!(f32_base64(&[1.0]), "\"AACAPw==\"");
        assert_eq!(f64_base64(&[1.0]), "\"AAAAAAAA8D8=\"");
    }
}
