//! Where in a model file an error is: one mechanism that gives every error without a
//! position the line and column of the key it concerns, instead of special cases.
//!
//! An error names what it concerns in its data: a setting's name (`InvalidParameter`,
//! `InvalidChoice`, `Missing`: `cycles`, `harmonics`, `lower bound of 'c'`), a
//! coefficient (`UnknownCoefficient`, `InfeasibleBounds`, `DuplicateCoefficient`: the key
//! that names it in `bounds`, `fixed` or a constraint's `terms`), or an empty list
//! (`Empty`: the damping model is `terms`). [`key_of`] reads that key, [`find_key`] finds
//! its first occurrence in the document (toml's spanned parse of the text, every key at
//! any depth, inline tables included), searching first the section the error came from,
//! then the sections in [`SECTIONS`] order, then anywhere. The error becomes
//! [`Error::ModelFile`] at that line and column, keeping the typed error as its cause; an
//! error whose key is not in the file keeps the file's name without a position (never
//! `file:0:0`).

use toml::de::{DeTable, DeValue};

use crate::error::Error;

/// The sections searched, in order, for a key an error names without its section.
const SECTIONS: &[&str] = &[
    "identification",
    "design",
    "non_periodic",
    "harmonic_approximation",
    "pod",
    "simulation",
    "string_simulation",
    "stepped_sine",
    "data",
    "system",
    "terms",
    "matrices",
    "units",
];

/// Setting names of the library that a model file spells otherwise.
const ALIASES: &[(&str, &str)] = &[("count", "windows"), ("design start", "start")];

/// The key an error concerns (module doc), if it names one.
pub(super) fn key_of(error: &Error) -> Option<String> {
    let setting = |name: &str| -> String {
        // `lower bound of 'c'`, `multiplier of 'x' in …`: the quoted name is the key.
        // `'p.exponent'` (a term's estimated parameter): the parameter's key.
        if let Some((_, rest)) = name.split_once('\'')
            && let Some((quoted, _)) = rest.split_once('\'')
        {
            return quoted.rsplit('.').next().unwrap_or(quoted).to_string();
        }
        let name = ALIASES
            .iter()
            .find(|(library, _)| *library == name)
            .map_or(name, |(_, key)| key);
        // `harmonic_approximation.dof`, `string_simulation.amplitudes`: the last part.
        name.rsplit('.').next().unwrap_or(name).to_string()
    };
    match error {
        Error::InvalidParameter { name, .. }
        | Error::InvalidChoice { name, .. }
        | Error::Missing { name, .. } => Some(setting(name)),
        Error::UnknownCoefficient { name, .. }
        | Error::InfeasibleBounds { name, .. }
        | Error::DuplicateCoefficient { name } => Some(name.clone()),
        Error::Empty { what } if what.contains("damping model") => Some("terms".into()),
        Error::ModelFile {
            cause: Some(cause), ..
        } => key_of(cause),
        _ => None,
    }
}

/// The byte offset of the first occurrence of `key` in `text` (document order), within
/// `section` if given and present there, else in the sections of [`SECTIONS`] in order,
/// else anywhere; `None` when the text does not parse or has no such key.
pub(super) fn find_key(text: &str, section: Option<&str>, key: &str) -> Option<usize> {
    let document = DeTable::parse(text).ok()?;
    let root = document.get_ref();
    let in_section = |name: &str| {
        root.iter()
            .find(|(k, _)| k.get_ref().as_ref() == name)
            .and_then(|(_, value)| first_in(value, key))
    };
    if let Some(offset) = section.and_then(in_section) {
        return Some(offset);
    }
    if let Some(offset) = root
        .iter()
        .find(|(k, _)| k.get_ref().as_ref() == key)
        .map(|(k, _)| k.span().start)
    {
        return Some(offset);
    }
    SECTIONS
        .iter()
        .find_map(|name| in_section(name))
        .or_else(|| first_in_table(root, key))
}

/// The byte offset of the first occurrence of `key` in the table whose span (its
/// header `[design]`, `[[terms]]`, or an inline table) is `span`: after the header and
/// before the next header, if any.
pub(super) fn find_key_within(
    text: &str,
    span: std::ops::Range<usize>,
    key: &str,
) -> Option<usize> {
    let document = DeTable::parse(text).ok()?;
    let mut found = Vec::new();
    every_in_table(document.get_ref(), key, &mut found);
    let mut headers = Vec::new();
    headers_in_table(document.get_ref(), text, &mut headers);
    let end = if text.get(span.clone()).is_some_and(|s| s.starts_with('{')) {
        span.end
    } else {
        headers
            .into_iter()
            .filter(|h| *h >= span.end)
            .min()
            .unwrap_or(text.len())
    };
    found
        .into_iter()
        .filter(|o| (span.start..end).contains(o))
        .min()
}

/// The start of every table header (`[a]`, `[[a]]`, `[a.b]`) in `table`, at any depth.
fn headers_in_table(table: &DeTable<'_>, text: &str, headers: &mut Vec<usize>) {
    for (_, value) in table {
        headers_in(value, text, headers);
    }
}

fn headers_in(value: &toml::Spanned<DeValue<'_>>, text: &str, headers: &mut Vec<usize>) {
    match value.get_ref() {
        DeValue::Table(table) => {
            if text[value.span()].starts_with('[') {
                headers.push(value.span().start);
            }
            headers_in_table(table, text, headers);
        }
        DeValue::Array(items) => items.iter().for_each(|v| headers_in(v, text, headers)),
        _ => {}
    }
}

fn every_in_table(table: &DeTable<'_>, key: &str, found: &mut Vec<usize>) {
    for (k, v) in table {
        if k.get_ref().as_ref() == key {
            found.push(k.span().start);
        }
        every_in(v, key, found);
    }
}

fn every_in(value: &toml::Spanned<DeValue<'_>>, key: &str, found: &mut Vec<usize>) {
    match value.get_ref() {
        DeValue::Table(table) => every_in_table(table, key, found),
        DeValue::Array(items) => items.iter().for_each(|v| every_in(v, key, found)),
        _ => {}
    }
}

/// The first offset of `key` inside `value` (a table or array, at any depth).
fn first_in(value: &toml::Spanned<DeValue<'_>>, key: &str) -> Option<usize> {
    match value.get_ref() {
        DeValue::Table(table) => first_in_table(table, key),
        DeValue::Array(items) => items.iter().filter_map(|v| first_in(v, key)).min(),
        _ => None,
    }
}

fn first_in_table(table: &DeTable<'_>, key: &str) -> Option<usize> {
    table
        .iter()
        .filter_map(|(k, v)| {
            if k.get_ref().as_ref() == key {
                Some(k.span().start)
            } else {
                first_in(v, key)
            }
        })
        .min()
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "dofs = 2\n\n[identification]\ncycles = 0\nbounds = { c = { lower = 1.0 } }\n\n[simulation]\ncoefficients = { c = 0.1 }\n";

    fn line(offset: usize) -> usize {
        TEXT[..offset].matches('\n').count() + 1
    }

    #[test]
    fn keys_are_found_in_their_section_first() {
        assert_eq!(find_key(TEXT, None, "cycles").map(line), Some(4));
        assert_eq!(
            find_key(TEXT, Some("identification"), "c").map(line),
            Some(5)
        );
        assert_eq!(find_key(TEXT, Some("simulation"), "c").map(line), Some(8));
        assert_eq!(find_key(TEXT, None, "dofs").map(line), Some(1));
        assert_eq!(find_key(TEXT, None, "nothing"), None);
        assert_eq!(find_key("[broken", None, "dofs"), None);
    }

    #[test]
    fn keys_are_found_in_the_table_of_a_header() {
        let text = "[[terms]]\nkind = \"a\"\nx = 1\n\n[[terms]]\nkind = \"b\"\n\n[design]\npicks = 0\nstart = [[1], [2]]\n";
        let line = |o: usize| text[..o].matches('\n').count() + 1;
        assert_eq!(find_key_within(text, 0..9, "kind").map(line), Some(2));
        assert_eq!(find_key_within(text, 22..31, "kind").map(line), Some(6));
        assert_eq!(find_key_within(text, 22..31, "x"), None);
        assert_eq!(find_key_within(text, 44..52, "picks").map(line), Some(9));
    }

    #[test]
    fn errors_name_their_keys() {
        let key = |e: Error| key_of(&e);
        assert_eq!(
            key(Error::invalid("cycles", 0.0, "")),
            Some("cycles".into())
        );
        assert_eq!(
            key(Error::invalid("count", 0.0, "")),
            Some("windows".into())
        );
        assert_eq!(
            key(Error::invalid("lower bound of 'c'", 0.0, "")),
            Some("c".into())
        );
        assert_eq!(
            key(Error::invalid("harmonic_approximation.dof", 0.0, "")),
            Some("dof".into())
        );
        assert_eq!(
            key(Error::Empty {
                what: "the damping model".into()
            }),
            Some("terms".into())
        );
        assert_eq!(key(Error::Cancelled { what: "x".into() }), None);
    }
}
