//! `--set key=value` overrides, applied to a problem file's TOML table before it is parsed.
//!
//! The key is a dotted path (`manoeuvre.profile`), missing sections are created; the value is
//! TOML (`1e-3`, `[0.2, 0.6, 0.2]`, `"cone"`), and a bare word is taken as a string.

use super::error::ProblemError;

/// Applies one `key=value` assignment to `table`.
pub(super) fn apply(table: &mut toml::Table, assignment: &str) -> Result<(), ProblemError> {
    let fail =
        |reason: &str| ProblemError::BadOverride { assignment: assignment.to_string(), reason: reason.to_string() };
    let (key, raw) = assignment.split_once('=').ok_or_else(|| fail("expected key=value"))?;
    let key = key.trim();
    let raw = raw.trim();
    let path: Vec<&str> = key.split('.').collect();
    if key.is_empty() || path.iter().any(|p| p.is_empty()) {
        return Err(fail("the key must be a dotted path such as manoeuvre.profile"));
    }
    let value = parse_value(raw);
    let (last, parents) = path.split_last().ok_or_else(|| fail("empty key"))?;
    let mut node = table;
    for part in parents {
        let entry = node.entry(part.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        node = entry.as_table_mut().ok_or_else(|| fail(&format!("`{part}` is not a section")))?;
    }
    if let (toml::Value::Table(set), Some(toml::Value::Table(given))) = (&value, node.get(*last)) {
        // The file's fields the new section leaves out (those it gives are replaced, not lost).
        let fields: Vec<&str> = given.keys().map(String::as_str).filter(|k| !set.contains_key(*k)).collect();
        if !fields.is_empty() {
            return Err(fail(&format!(
                "it replaces the whole [{key}] section, whose other fields ({}) would fall back to their defaults: set its fields one by one, as {key}.<field>=…",
                fields.join(", ")
            )));
        }
    }
    node.insert(last.to_string(), value);
    Ok(())
}

/// Refuses a key set twice among a user's overrides (the last would win without a word). The
/// library applies overrides in order, the last winning (a stress test varies a value by
/// appending one); a problem the user wrote asks this first.
pub(super) fn refuse_repeats(overrides: &[String]) -> Result<(), ProblemError> {
    let key = |a: &str| a.split_once('=').map_or(a, |(k, _)| k).trim().to_string();
    for (i, later) in overrides.iter().enumerate() {
        let k = key(later);
        // The same key, or one inside a section another sets whole (`cat.front={…}`).
        let inside = |a: &str, b: &str| a == b || a.starts_with(&format!("{b}."));
        if let Some(first) = overrides[..i].iter().find(|f| inside(&k, &key(f)) || inside(&key(f), &k)) {
            return Err(ProblemError::BadOverride {
                assignment: later.to_string(),
                reason: format!("{k} is set twice (first by --set {first}): give it once"),
            });
        }
    }
    Ok(())
}

/// A TOML value from an override's right-hand side; a bare word is a string.
fn parse_value(raw: &str) -> toml::Value {
    let doc = format!("v = {raw}");
    doc.parse::<toml::Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(raw.to_string()))
}
