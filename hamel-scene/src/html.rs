//! The scene page: one HTML file with its style, its data, three.js and the viewer inlined,
//! so that it opens from disk with no network.

/// The page, with `<!--hamel:name-->` where each part goes.
const PAGE: &str = include_str!("assets/page.html");
const STYLE: &str = include_str!("assets/viewer.css");
const VIEWER: &str = include_str!("assets/viewer.js");
/// three.js, vendored unchanged from the npm package (see `three/README.md`).
const THREE_CORE: &str = include_str!("three/three.core.min.js");
const THREE_MODULE: &str = include_str!("three/three.module.min.js");
const THREE_ORBIT: &str = include_str!("three/OrbitControls.js");

/// The page for this title and data (a JSON object, already escaped for a script element).
pub(crate) fn page(title: &str, data: &str) -> String {
    let title = escape_text(title);
    fill(
        PAGE,
        &[
            ("title", &title),
            ("style", STYLE),
            ("data", data),
            ("three-core", THREE_CORE),
            ("three-module", THREE_MODULE),
            ("three-orbit", THREE_ORBIT),
            ("viewer", VIEWER),
        ],
    )
}

/// The template with each `<!--hamel:name-->` replaced by its part. Parts are not searched
/// for markers in turn, so nothing inside three.js or the data is ever replaced.
fn fill(template: &str, parts: &[(&str, &str)]) -> String {
    let size = template.len() + parts.iter().map(|(_, p)| p.len()).sum::<usize>();
    let mut out = String::with_capacity(size);
    let mut rest = template;
    while let Some(at) = rest.find("<!--hamel:") {
        out.push_str(&rest[..at]);
        let marker = &rest[at..];
        let Some(end) = marker.find("-->") else {
            break;
        };
        let name = &marker["<!--hamel:".len()..end];
        match parts.iter().find(|(n, _)| *n == name) {
            Some((_, part)) => out.push_str(part),
            None => out.push_str(&marker[..end + 3]),
        }
        rest = &marker[end + 3..];
    }
    out.push_str(rest);
    out
}

/// Text for an HTML element's content.
fn escape_text(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_marker_is_filled_and_no_part_can_end_its_script_element() {
        let page = page("a <b> & c", "{}");
        assert!(!page.contains("<!--hamel:"), "a marker was left unfilled");
        assert!(page.contains("<title>a &lt;b&gt; &amp; c</title>"));
        // A script element's text ends at the first `</script`, in any case: none of the
        // inlined scripts may contain one (nor `<!--`, which changes how it is parsed).
        for (name, part) in [
            ("viewer.js", VIEWER),
            ("three.core.min.js", THREE_CORE),
            ("three.module.min.js", THREE_MODULE),
            ("OrbitControls.js", THREE_ORBIT),
        ] {
            let lower = part.to_ascii_lowercase();
            assert!(!lower.contains("</script"), "{name} contains </script");
            assert!(!lower.contains("<!--"), "{name} contains <!--");
        }
        // The viewer rewrites these import names; a three.js without them fails loudly in the
        // page, and here first.
        assert_eq!(
            THREE_MODULE.matches("from\"./three.core.min.js\"").count(),
            2
        );
        assert_eq!(THREE_ORBIT.matches("from 'three'").count(), 1);
        assert!(
            VIEWER.contains("'\"./three.core.min.js\"'") && VIEWER.contains("\"from 'three'\"")
        );
    }

    #[test]
    fn markers_inside_parts_are_left_alone() {
        let filled = fill("a<!--hamel:x-->b<!--hamel:y-->", &[("x", "<!--hamel:y-->")]);
        assert_eq!(filled, "a<!--hamel:y-->b<!--hamel:y-->");
    }
}
