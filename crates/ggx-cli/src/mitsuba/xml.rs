//! A minimal XML writer for Mitsuba scene files: nested elements with attributes, comments and
//! four-space indentation; every attribute value and comment is escaped, so material names from
//! the scene file cannot break the document.

use std::fmt::Write as _;

/// An XML document being written, element by element.
#[derive(Debug, Default)]
pub struct Xml {
    /// The text so far.
    text: String,
    /// Names of the open elements, innermost last.
    open: Vec<&'static str>,
}

impl Xml {
    /// A document that starts with the XML declaration.
    pub fn new() -> Self {
        Self { text: "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n".to_owned(), open: Vec::new() }
    }

    /// Indentation of the next line: four spaces per open element.
    fn indent(&mut self) {
        for _ in 0..self.open.len() {
            self.text.push_str("    ");
        }
    }

    /// `<tag a="v" ...` without the closing bracket.
    fn start(&mut self, tag: &'static str, attrs: &[(&str, &str)]) {
        self.indent();
        self.text.push('<');
        self.text.push_str(tag);
        for (name, value) in attrs {
            // Writing to a String cannot fail.
            let _ = write!(self.text, " {name}=\"{}\"", escape(value));
        }
    }

    /// Opens `<tag attrs>`; [`Self::close`] closes it.
    pub fn open(&mut self, tag: &'static str, attrs: &[(&str, &str)]) {
        self.start(tag, attrs);
        self.text.push_str(">\n");
        self.open.push(tag);
    }

    /// An empty element `<tag attrs/>`.
    pub fn leaf(&mut self, tag: &'static str, attrs: &[(&str, &str)]) {
        self.start(tag, attrs);
        self.text.push_str("/>\n");
    }

    /// Closes the innermost open element (nothing when none is open).
    pub fn close(&mut self) {
        if let Some(tag) = self.open.pop() {
            self.indent();
            let _ = writeln!(self.text, "</{tag}>");
        }
    }

    /// `<!-- text -->`, with `--` (not allowed inside comments) written as `- -`.
    pub fn comment(&mut self, text: &str) {
        self.indent();
        let safe = escape(text).replace("--", "- -");
        let _ = writeln!(self.text, "<!-- {} -->", safe.trim_end_matches('-'));
    }

    /// The document, every open element closed.
    pub fn finish(mut self) -> String {
        while !self.open.is_empty() {
            self.close();
        }
        self.text
    }
}

/// `s` with `&`, `<`, `>`, `"` and `'` replaced by their entities, and control characters
/// other than tab, line feed and carriage return (not allowed in XML 1.0) by `?`.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if c.is_control() => out.push('?'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nests_escapes_and_closes() {
        let mut x = Xml::new();
        x.open("scene", &[("version", "3.0.0")]);
        x.comment("a -- b <c>-");
        x.open("bsdf", &[("type", "diffuse"), ("id", "a\"b&<c>'")]);
        x.leaf("rgb", &[("name", "reflectance"), ("value", "0.5, 0.5, 0.5")]);
        let text = x.finish();
        assert_eq!(
            text,
            "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<scene version=\"3.0.0\">\n    <!-- a - - b &lt;c&gt; -->\n    \
             <bsdf type=\"diffuse\" id=\"a&quot;b&amp;&lt;c&gt;&apos;\">\n        \
             <rgb name=\"reflectance\" value=\"0.5, 0.5, 0.5\"/>\n    </bsdf>\n</scene>\n"
        );
        assert_eq!(escape("x\u{1}y\tz"), "x?y\tz");
    }
}
