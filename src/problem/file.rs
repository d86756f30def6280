//! What a problem *file* leaves out: every field has a default (the paper's worked example), so a
//! file cut short or missing a section still loads, and would run the paper's numbers under
//! the user's name without a word. [`Problem::load`](super::Problem::load) reads the file's own
//! table here first: an empty file is refused, a missing `name` is the file's stem (so a
//! nameless file never writes over `results/paper/`), and a missing `[cat]`, `[drop]` or
//! `[manoeuvre]` section, a missing `drop.height` or a last line without its line break (a file
//! cut short) is warned of, with the value the default puts there.

use super::{bad, names_a_folder, CatSection, Drop, Manoeuvre, ProblemError};

/// The sections that define the problem, each with its default's fields as the file would
/// write them (`{ height = 10.0, … }`).
fn sections() -> [(&'static str, String); 3] {
    fn fields(section: impl serde::Serialize) -> String {
        toml::Value::try_from(section).map_or_else(|_| "the paper's values".into(), |v| v.to_string())
    }
    [
        ("cat", fields(CatSection::default())),
        ("drop", fields(Drop::default())),
        ("manoeuvre", fields(Manoeuvre::default())),
    ]
}

/// Whether an override (`key=value`) sets `key` or a field inside it.
fn overridden(overrides: &[String], key: &str) -> bool {
    overrides.iter().any(|o| {
        let k = o.split_once('=').map_or(o.as_str(), |(k, _)| k).trim();
        k == key || k.starts_with(&format!("{key}."))
    })
}

/// Whether the file's table or an override gives `name`.
pub(crate) fn names_itself(table: &toml::Table, overrides: &[String]) -> bool {
    table.contains_key("name") || overridden(overrides, "name")
}

/// What the file at `origin`, holding `text` parsed as `table`, leaves to the defaults, as
/// warnings; refused when it holds nothing at all.
pub(crate) fn omissions(
    text: &str,
    table: &toml::Table,
    origin: &str,
    overrides: &[String],
) -> Result<Vec<String>, ProblemError> {
    if table.is_empty() {
        return Err(ProblemError::Parse {
            origin: origin.to_string(),
            message: "the file holds no field (it is empty or all comments): it would run the paper's worked example, which is problems/paper.toml".into(),
        });
    }
    let mut out = Vec::new();
    for (section, default) in sections() {
        if !table.contains_key(section) && !overridden(overrides, section) {
            out.push(format!("the file has no [{section}] section: its defaults are used, {default}"));
        }
    }
    let has = |section: &str, key: &str| {
        table.get(section).and_then(|s| s.as_table()).is_some_and(|s| s.contains_key(key))
            || overridden(overrides, &format!("{section}.{key}"))
    };
    if table.contains_key("drop") && !has("drop", "height") {
        out.push(format!("the file gives no drop.height: the default {} m is used", Drop::default().height));
    }
    if !text.is_empty() && !text.ends_with('\n') {
        out.push(
            "the file does not end with a line break: was it cut short? (every field it leaves out takes its default)"
                .to_string(),
        );
    }
    Ok(out)
}

/// The `name` of a file that gives none: its stem, when that can name a results folder.
pub(crate) fn name_from_stem(path: &std::path::Path) -> Result<String, ProblemError> {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    if names_a_folder(&stem) {
        Ok(stem)
    } else {
        Err(bad(
            "name",
            "(not given)",
            &format!(
                "the file's stem \"{stem}\" cannot name a results folder (letters, digits, '-' and '_' only): give name = \"...\""
            ),
        ))
    }
}
