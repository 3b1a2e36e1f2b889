//! Short forms of user text echoed in error messages, so that a 50 MB key or path in a
//! scene file gives a one-line error, not 100 MB on stderr.
//!
//! A string longer than [`MAX_ECHO_CHARS`] characters is shown as its first
//! [`MAX_ECHO_CHARS`] characters, `…` and its size: `aaaa…aaaa… (52428800 bytes)`.

use std::borrow::Cow;

/// Most characters of a user string that a message shows.
pub(crate) const MAX_ECHO_CHARS: usize = 40;

/// Most characters of a file path that a message shows.
const MAX_PATH_CHARS: usize = 256;

/// Most bytes of a whole message (after its quoted parts are shortened) that a message shows
/// before `… (N bytes)`.
const MAX_MESSAGE_BYTES: usize = 1024;

/// Most bytes of a field path (after its segments are shortened) that a message shows before
/// `… (N bytes)`.
const MAX_FIELD_BYTES: usize = 256;

/// Most names a list in a message shows before `… and N more`.
const MAX_LISTED: usize = 16;

/// `text` as it is when short (or already cut by this function), else its first
/// [`MAX_ECHO_CHARS`] characters, `…` and its size in bytes.
pub(crate) fn short(text: &str) -> Cow<'_, str> {
    match text.char_indices().nth(MAX_ECHO_CHARS) {
        Some((end, _)) if is_cut_suffix(&text[end..]) => Cow::Borrowed(text),
        _ => cut(text, MAX_ECHO_CHARS),
    }
}

/// Whether `tail` is the `… (N bytes)` that [`cut`] appends.
fn is_cut_suffix(tail: &str) -> bool {
    tail.strip_prefix("… (")
        .and_then(|t| t.strip_suffix(" bytes)"))
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// `path` as shown in messages: up to [`MAX_PATH_CHARS`] characters, then `…` and its size.
pub(crate) fn short_path(path: &std::path::Path) -> String {
    cut(&path.to_string_lossy(), MAX_PATH_CHARS).into_owned()
}

/// `text` cut to its first `max` bytes (less, to end on a character boundary), with
/// `… (N bytes)` appended when it was cut.
fn cut_bytes(text: &str, max: usize) -> Cow<'_, str> {
    if text.len() <= max {
        return Cow::Borrowed(text);
    }
    let end = (0..=max).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
    Cow::Owned(format!("{}… ({} bytes)", &text[..end], text.len()))
}

/// `text` cut after `max` characters, with `… (N bytes)` appended when it was cut.
fn cut(text: &str, max: usize) -> Cow<'_, str> {
    match text.char_indices().nth(max) {
        None => Cow::Borrowed(text),
        Some((end, _)) => Cow::Owned(format!("{}… ({} bytes)", &text[..end], text.len())),
    }
}

/// Shortens every part of `message` quoted with backticks or double quotes (how `toml` and
/// this crate quote keys, names and values) and then cuts the message as a whole to its first
/// [`MAX_MESSAGE_BYTES`] bytes (on a character boundary) followed by `… (N bytes)`.
pub(crate) fn short_message(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(MAX_MESSAGE_BYTES + 64));
    let mut rest = message;
    while let Some(open) = rest.find(['`', '"']) {
        let quote = rest[open..].chars().next().unwrap_or('"');
        out.push_str(&rest[..=open]);
        let after = &rest[open + 1..];
        match after.find(quote) {
            Some(close) => {
                out.push_str(&short(&after[..close]));
                out.push(quote);
                rest = &after[close + 1..];
            }
            None => {
                out.push_str(&short(after));
                rest = "";
            }
        }
    }
    out.push_str(rest);
    match cut_bytes(&out, MAX_MESSAGE_BYTES) {
        Cow::Borrowed(_) => out,
        Cow::Owned(cut) => cut,
    }
}

/// Shortens each dotted segment of a field path such as `materials.NAME.albedo`, then cuts
/// the path to its first [`MAX_FIELD_BYTES`] bytes followed by `… (N bytes)`.
pub(crate) fn short_field(field: &str) -> String {
    let joined = field.split('.').map(short).collect::<Vec<_>>().join(".");
    cut_bytes(&joined, MAX_FIELD_BYTES).into_owned()
}

/// `names` joined by `, `, each shortened, at most [`MAX_LISTED`] of them, then `… and N more`.
pub(crate) fn short_list(names: &[String]) -> String {
    let mut shown: Vec<Cow<'_, str>> = names.iter().take(MAX_LISTED).map(|n| short(n)).collect();
    if names.len() > MAX_LISTED {
        shown.push(Cow::Owned(format!("… and {} more", names.len() - MAX_LISTED)));
    }
    shown.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_text_is_cut_with_its_size() {
        assert_eq!(short("gold"), "gold");
        let long = "k".repeat(50_000_000);
        assert_eq!(short(&long), format!("{}… (50000000 bytes)", "k".repeat(40)));
        assert_eq!(short(&short(&long)), short(&long), "a cut string is not cut again");
        let wide = "é".repeat(41);
        assert_eq!(short(&wide), format!("{}… (82 bytes)", "é".repeat(40)));
    }

    #[test]
    fn quoted_parts_and_fields_are_cut() {
        let key = "x".repeat(1000);
        let msg = short_message(&format!("unknown field `{key}`, expected one of `a`, `b`"));
        assert_eq!(msg, format!("unknown field `{}… (1000 bytes)`, expected one of `a`, `b`", "x".repeat(40)));
        let msg = short_message(&format!("unknown material \"{key}"));
        assert!(msg.len() < 100, "{msg}");
        let long = "y ".repeat(10_000);
        assert_eq!(short_message(&long), format!("{}… (20000 bytes)", &long[..MAX_MESSAGE_BYTES]));
        let wide = "é".repeat(1000);
        let cut = short_message(&wide);
        assert!(cut.starts_with(&"é".repeat(MAX_MESSAGE_BYTES / 2)) && cut.ends_with("… (2000 bytes)"), "{cut}");
        let dotted = "a.".repeat(1000);
        assert_eq!(short_field(&dotted), format!("{}… (2000 bytes)", &dotted[..MAX_FIELD_BYTES]));
        assert_eq!(short_field(&format!("materials.{key}.albedo")), format!("materials.{}.albedo", short(&key)));
        let names: Vec<String> = (0..20).map(|i| i.to_string()).collect();
        assert!(short_list(&names).ends_with("15, … and 4 more"));
    }
}
