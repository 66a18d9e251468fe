//! rustc's rendered diagnostics made independent of the machine: paths outside the case file
//! become `$WORKSPACE/…`, `$RUST/…` or `$CARGO/…` with their line numbers hidden (so editing
//! the runtime does not churn every `.stderr`), the gutter is unindented to the narrowest
//! block, and the lines that only repeat the error count are dropped.
//!
//! This is trybuild's normalization at its most complete level, ported from trybuild 1.0.119
//! (`src/normalize.rs`, MIT OR Apache-2.0, by David Tolnay), so the `.stderr` files it wrote
//! stay valid byte for byte. Only the levels trybuild keeps for snapshots written by its older
//! versions are left out.

use std::cmp;
use std::mem;

/// Where the case was compiled: the names rustc may print, to be replaced.
pub struct Context<'a> {
    /// The crate name rustc compiled the case as (printed as `$CRATE`).
    pub krate: &'a str,
    /// The compile-fail package's directory, ending in `/`.
    pub source_dir: &'a str,
    /// The workspace's root directory, ending in `/`.
    pub workspace: &'a str,
    /// The case file as passed to rustc, relative to `source_dir`.
    pub input_file: &'a str,
}

/// One diagnostic's rendered text, normalized, ending in one newline (or empty when nothing of
/// it is kept, as for "aborting due to N previous errors").
pub fn diagnostic(rendered: &str, context: &Context) -> String {
    let rendered = rendered.replace("\r\n", "\n");
    let lines: Vec<&str> = rendered.lines().collect();
    let mut filter = Filter {
        all_lines: &lines,
        context,
        hide_numbers: 0,
        other_types: None,
    };
    let mut normalized = String::new();
    for index in 0..lines.len() {
        if let Some(line) = filter.apply(index) {
            normalized += &line;
            if !normalized.ends_with("\n\n") {
                normalized.push('\n');
            }
        }
    }
    trim(&unindent(&normalized))
}

/// The text without trailing whitespace, ending in one newline unless empty.
pub fn trim(text: &str) -> String {
    let mut trimmed = text.trim_end().to_owned();
    if !trimmed.is_empty() {
        trimmed.push('\n');
    }
    trimmed
}

struct Filter<'a> {
    all_lines: &'a [&'a str],
    context: &'a Context<'a>,
    /// How many of the next lines are a snippet of a file outside the case, whose line
    /// numbers are hidden.
    hide_numbers: usize,
    /// Inside a "the following types implement trait" list: how many entries so far.
    other_types: Option<usize>,
}

impl Filter<'_> {
    fn apply(&mut self, index: usize) -> Option<String> {
        let mut line = self.all_lines[index].to_owned();
        if self.hide_numbers > 0 {
            hide_leading_numbers(&mut line);
            self.hide_numbers -= 1;
        }
        let trim_start = line.trim_start();
        let indent = line.len() - trim_start.len();
        if trim_start.starts_with("--> ") || trim_start.starts_with("::: ") {
            return Some(self.location(line, index, indent));
        }
        if is_dropped(&line) {
            return None;
        }
        line.truncate(line.trim_end().len());
        if line
            .trim_start()
            .starts_with("= note: required because it appears within the type")
        {
            line = line.replace('\\', "/");
        }
        hide_count_of_others(&mut line);
        if is_long_type_name_file(&line) {
            return None;
        }
        if !self.shorten_list_of_other_types(&mut line, index, indent) {
            return None;
        }
        line = line.replace(self.context.krate, "$CRATE");
        line = replace_case_insensitive(&line, self.context.source_dir, "$DIR/");
        line = replace_case_insensitive(&line, self.context.workspace, "$WORKSPACE/");
        Some(line)
    }

    /// A `--> file:line:col` or `::: file:line:col` line: a file outside the case is named
    /// by a placeholder, and its line numbers (here and in the snippet below) are hidden.
    fn location(&mut self, mut line: String, index: usize, indent: usize) -> String {
        line = line.replace('\\', "/");
        let line_lower = line.to_ascii_lowercase();
        let source_dir = self.context.source_dir.to_ascii_lowercase();
        let workspace = self.context.workspace.to_ascii_lowercase();
        let path_start = indent + 4;
        let mut other_crate = false;
        if let Some(i) = line_lower.find(&source_dir) {
            if i == path_start {
                line.replace_range(i..i + source_dir.len(), "");
                let input_file = self.context.input_file.to_ascii_lowercase();
                if line_lower[i + source_dir.len()..].starts_with(&input_file) {
                    return line;
                }
            } else {
                line.replace_range(i..i + source_dir.len() - 1, "$DIR");
            }
            other_crate = true;
        } else if let Some(i) = line_lower.find(&workspace) {
            line.replace_range(i..i + workspace.len() - 1, "$WORKSPACE");
            other_crate = true;
        } else if !line[path_start..].starts_with('/')
            && !line[path_start..].starts_with(self.context.input_file)
            && !line[path_start..].starts_with('$')
        {
            // Cargo compiles the workspace's own crates from paths relative to its root, and
            // rustc names their files so (trybuild's copy of hamel was outside its workspace
            // and named them absolutely; the files are the same).
            line.insert_str(path_start, "$WORKSPACE/");
            other_crate = true;
        }
        if !other_crate {
            other_crate = normalize_rust_library(&mut line, indent);
        }
        if !other_crate {
            other_crate = normalize_cargo_registry(&mut line, indent);
        }
        if other_crate {
            hide_trailing_numbers(&mut line);
            self.hide_numbers = 1;
            while let Some(next_line) = self.all_lines.get(index + self.hide_numbers) {
                match next_line.trim_start().chars().next().unwrap_or_default() {
                    '0'..='9' | '|' | '.' => self.hide_numbers += 1,
                    _ => break,
                }
            }
        }
        line
    }

    /// Lists of implementing types are cut after eight entries to "and $N others", since
    /// their length depends on what else is in scope. Returns false for a line to drop.
    fn shorten_list_of_other_types(
        &mut self,
        line: &mut String,
        index: usize,
        indent: usize,
    ) -> bool {
        let trim_start = line.trim_start();
        if trim_start.starts_with("= help: the following types implement trait ")
            || trim_start.starts_with("= help: the following other types implement trait ")
        {
            self.other_types = Some(0);
        } else if let Some(count) = &mut self.other_types {
            if indent >= 12 && trim_start != "and $N others" {
                *count += 1;
                if *count == 9 {
                    if let Some(next) = self.all_lines.get(index + 1) {
                        let next_indent = next.len() - next.trim_start().len();
                        if indent == next_indent {
                            line.replace_range(indent - 2.., "and $N others");
                        }
                    }
                } else if *count > 9 {
                    return false;
                }
            } else {
                self.other_types = None;
            }
        }
        true
    }
}

/// Lines that only summarize (the error count, where to read more) or name this compiler.
fn is_dropped(line: &str) -> bool {
    let trim_start = line.trim_start();
    line.starts_with("error: aborting due to ")
        || line == "To learn more, run the command again with --verbose."
        || (trim_start.starts_with("= note: this compiler was built on 2")
            && trim_start.ends_with("; consider upgrading it if it is out of date"))
        || line.starts_with("error: Could not compile `")
        || line.starts_with("error: could not compile `")
        || line.starts_with("For more information about this error, try `rustc --explain")
        || line.starts_with("Some errors have detailed explanations:")
        || line.starts_with("For more information about an error, try `rustc --explain")
}

/// "and 12 others" → "and $N others".
fn hide_count_of_others(line: &mut String) {
    let trim_start = line.trim_start();
    if trim_start.starts_with("and ") && line.ends_with(" others") {
        let indent = line.len() - trim_start.len();
        let num_start = indent + "and ".len();
        let num_end = line.len() - " others".len();
        if num_start < num_end && line[num_start..num_end].bytes().all(|b| b.is_ascii_digit()) {
            line.replace_range(num_start..num_end, "$N");
        }
    }
}

fn is_long_type_name_file(line: &str) -> bool {
    let trimmed = line.trim_start();
    let trimmed = trimmed.strip_prefix("= note: ").unwrap_or(trimmed);
    trimmed.starts_with("the full type name has been written to")
        || trimmed.starts_with("the full name for the type has been written to")
}

/// The standard library's sources, wherever the toolchain keeps them, as `$RUST/…`.
fn normalize_rust_library(line: &mut String, indent: usize) -> bool {
    if let Some(pos) = line.find("/rustlib/src/rust/src/") {
        line.replace_range(indent + 4..pos + 17, "$RUST");
        true
    } else if let Some(pos) = line.find("/rustlib/src/rust/library/") {
        line.replace_range(indent + 4..pos + 25, "$RUST");
        true
    } else if line[indent + 4..].starts_with("/rustc/")
        && line
            .get(indent + 11..indent + 51)
            .is_some_and(is_ascii_lowercase_hex)
        && line[indent + 51..].starts_with("/library/")
    {
        line.replace_range(indent + 4..indent + 59, "$RUST");
        true
    } else {
        false
    }
}

/// A registry source path `…/registry/src/{name}-{16 hex}/crate-1.2.3/…` as
/// `$CARGO/crate-$VERSION/…`.
fn normalize_cargo_registry(line: &mut String, indent: usize) -> bool {
    let prefix = "/registry/src/";
    let Some(pos) = line.find(prefix) else {
        return false;
    };
    let rest = &line[pos + prefix.len()..];
    let Some(slash) = rest.find('/') else {
        return false;
    };
    let Some((_registry, hash)) = rest[..slash].rsplit_once('-') else {
        return false;
    };
    if hash.len() != 16 || !is_ascii_lowercase_hex(hash) {
        return false;
    }
    line.replace_range(indent + 4..pos + prefix.len() + slash, "$CARGO");
    let rest = &line[indent + 11..];
    let end_of_version = rest.find('/');
    if let Some(end_of_crate_name) = end_of_version
        .and_then(|end| rest[..end].find('.'))
        .and_then(|end| rest[..end].rfind('-'))
    {
        let end_of_version = end_of_version.unwrap_or_default();
        line.replace_range(
            indent + end_of_crate_name + 12..indent + end_of_version + 11,
            "$VERSION",
        );
    }
    true
}

fn is_ascii_lowercase_hex(s: &str) -> bool {
    s.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
}

/// "10 | T: Send," → "   | T: Send,"
fn hide_leading_numbers(line: &mut String) {
    let n = line
        .bytes()
        .take_while(|b| *b == b' ' || b.is_ascii_digit())
        .count();
    line.replace_range(..n, &" ".repeat(n));
}

/// "main.rs:22:29" → "main.rs"
fn hide_trailing_numbers(line: &mut String) {
    for _ in 0..2 {
        let digits = line.bytes().rev().take_while(u8::is_ascii_digit).count();
        if digits == 0 || !line[..line.len() - digits].ends_with(':') {
            return;
        }
        line.truncate(line.len() - digits - 1);
    }
}

/// Every occurrence of `pattern` (a directory ending in `/`) that starts a path, ignoring
/// case, replaced; the rest of that path gets forward slashes.
fn replace_case_insensitive(line: &str, pattern: &str, replacement: &str) -> String {
    let line_lower = line.to_ascii_lowercase().replace('\\', "/");
    let pattern_lower = pattern.to_ascii_lowercase().replace('\\', "/");
    let mut replaced = String::with_capacity(line.len());
    let line_lower = line_lower.as_str();
    let mut split = line_lower.split(&pattern_lower);
    let mut pos = 0;
    let mut insert_replacement = false;
    while let Some(keep) = split.next() {
        if insert_replacement {
            replaced.push_str(replacement);
            pos += pattern.len();
        }
        let mut keep = &line[pos..pos + keep.len()];
        if insert_replacement {
            let end_of_maybe_path = keep.find([' ', ':']).unwrap_or(keep.len());
            replaced.push_str(&keep[..end_of_maybe_path].replace('\\', "/"));
            pos += end_of_maybe_path;
            keep = &keep[end_of_maybe_path..];
        }
        replaced.push_str(keep);
        pos += keep.len();
        insert_replacement = true;
        // An occurrence right after a letter or digit is inside a longer name, not a path.
        if replaced.ends_with(|ch: char| ch.is_ascii_alphanumeric()) {
            if let Some(ch) = line[pos..].chars().next() {
                replaced.push(ch);
                pos += ch.len_utf8();
                split = line_lower[pos..].split(&pattern_lower);
                insert_replacement = false;
            }
        }
    }
    replaced
}

#[derive(PartialEq)]
enum IndentedLineKind {
    /// `error:`, `error[E…]:`, `warning:`, or a `note:` opening a diagnostic.
    Heading,
    /// A note (or `help:`) line inside a diagnostic.
    Note,
    /// A line of the gutter (`  |`, `12 |`, `-->`, `= note`), with its indentation.
    Code(usize),
    /// Anything else, with its indentation.
    Other(usize),
}

/// Each code block's gutter narrowed to the least indentation it needs, so that a block's
/// width does not depend on how many digits the hidden line numbers had.
fn unindent(diag: &str) -> String {
    let mut normalized = String::new();
    let mut lines = diag.lines();
    while let Some(line) = lines.next() {
        normalized.push_str(line);
        normalized.push('\n');
        if indented_line_kind(line, true, &mut false) != IndentedLineKind::Heading {
            continue;
        }
        let mut ahead = lines.clone();
        let Some(next_line) = ahead.next() else {
            continue;
        };
        let IndentedLineKind::Code(indent) = indented_line_kind(next_line, false, &mut false)
        else {
            continue;
        };
        if !next_line[indent + 1..].starts_with("--> ") {
            continue;
        }
        let mut lines_in_block = 1;
        let mut least_indent = indent;
        let mut previous_line_is_note = false;
        for line in ahead {
            match indented_line_kind(line, false, &mut previous_line_is_note) {
                IndentedLineKind::Heading => break,
                IndentedLineKind::Code(indent) => {
                    lines_in_block += 1;
                    least_indent = cmp::min(least_indent, indent);
                }
                IndentedLineKind::Note => lines_in_block += 1,
                IndentedLineKind::Other(spaces) if spaces > 10 => lines_in_block += 1,
                IndentedLineKind::Other(_) => break,
            }
        }
        previous_line_is_note = false;
        for line in lines.by_ref().take(lines_in_block) {
            match indented_line_kind(line, false, &mut previous_line_is_note) {
                IndentedLineKind::Code(_) | IndentedLineKind::Other(_) => {
                    let space = line.find(' ').unwrap_or(0);
                    normalized.push_str(&line[..space]);
                    normalized.push_str(&line[space + least_indent..]);
                }
                _ => normalized.push_str(line),
            }
            normalized.push('\n');
        }
    }
    normalized
}

fn indented_line_kind(
    line: &str,
    first_line_in_block: bool,
    previous_line_is_note: &mut bool,
) -> IndentedLineKind {
    let previous_line_was_note = mem::replace(previous_line_is_note, false);
    for heading in ["error", "warning"] {
        if line.starts_with(heading) && line[heading.len()..].starts_with([':', '[']) {
            return IndentedLineKind::Heading;
        }
    }
    if first_line_in_block && line.starts_with("note: ") {
        return IndentedLineKind::Heading;
    }
    if line.starts_with("note:")
        || line == "..."
        || line.starts_with("help:")
        || (previous_line_was_note && line.starts_with("      "))
    {
        *previous_line_is_note = true;
        return IndentedLineKind::Note;
    }
    let is_space = |b: &u8| *b == b' ';
    if let Some(rest) = line.strip_prefix("... ") {
        return IndentedLineKind::Code(rest.bytes().take_while(is_space).count());
    }
    let mut spaces = line.bytes().take_while(is_space).count();
    let digits = line[spaces..]
        .bytes()
        .take_while(u8::is_ascii_digit)
        .count();
    spaces += line[spaces + digits..].bytes().take_while(is_space).count();
    let rest = &line[digits + spaces..];
    let gutter = rest == "|" || rest.starts_with("| ");
    let suggestion = digits > 0
        && ["~", "+", "-"]
            .iter()
            .any(|mark| rest == *mark || rest.starts_with(&format!("{mark} ")));
    let location = digits == 0
        && (rest.starts_with("--> ") || rest.starts_with("::: ") || rest.starts_with("= "));
    if spaces > 0 && (gutter || suggestion || location) {
        return IndentedLineKind::Code(spaces - 1);
    }
    IndentedLineKind::Other(if digits == 0 { spaces } else { 0 })
}
