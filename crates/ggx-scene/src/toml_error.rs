//! Converts `toml` errors (syntax, serde type/missing/unknown-field) into located
//! [`SceneError`]s, recovering the field path from the error's byte span.

use std::ops::Range;

use toml::de::{DeTable, DeValue};

use crate::error::{ErrorKind, SceneError, Source};

/// A located [`SceneError`] for a `toml` deserialisation error.
pub(crate) fn convert(source: Source<'_>, error: &toml::de::Error) -> SceneError {
    let span = error.span().unwrap_or(0..0);
    let (kind, field) = match DeTable::parse(source.text) {
        Err(_) => (ErrorKind::Syntax, String::new()),
        // An empty span is toml's marker for the document itself (a missing top-level key).
        Ok(_) if span.is_empty() => (ErrorKind::Schema, String::new()),
        Ok(doc) => (ErrorKind::Schema, table_path(doc.get_ref(), &span).unwrap_or_default()),
    };
    source.error(span, &field, kind, error.message().trim())
}

/// The dotted path of the deepest key or value whose span contains `span`'s start. Tables
/// from `[header]`s span only their header, so every entry is searched, deepest first.
fn table_path(table: &DeTable<'_>, span: &Range<usize>) -> Option<String> {
    table.iter().find_map(|(key, value)| {
        let name = key.get_ref().to_string();
        let inner = value_path(value.get_ref(), span).map(|rest| join(&name, &rest));
        inner.or_else(|| (covers(&key.span(), span) || covers(&value.span(), span)).then_some(name))
    })
}

fn value_path(value: &DeValue<'_>, span: &Range<usize>) -> Option<String> {
    match value {
        DeValue::Table(table) => table_path(table, span),
        DeValue::Array(items) => items.iter().enumerate().find_map(|(i, item)| {
            let inner = value_path(item.get_ref(), span).map(|rest| join(&format!("[{i}]"), &rest));
            inner.or_else(|| covers(&item.span(), span).then(|| format!("[{i}]")))
        }),
        _ => None,
    }
}

fn covers(outer: &Range<usize>, inner: &Range<usize>) -> bool {
    outer.start <= inner.start && inner.start < outer.end
}

fn join(head: &str, rest: &str) -> String {
    if rest.starts_with('[') { format!("{head}{rest}") } else { format!("{head}.{rest}") }
}
