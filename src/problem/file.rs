//! What a problem *file* leaves out: every field has a default (the paper's worked example), so a
//! file cut short or missing a section still loads, and would run the paper's numbers under
//! the user's name without a word. [`Problem::load`](super::Problem::load) reads the file's own
//! table here first: an empty file is refused, a missing `name` is the file's stem (so a
//! nameless file never writes over `results/paper/`), and a missing `[cat]`, `[drop]` or
//! `[manoeuvre]` section, a missing `drop.height`, a section that holds no field or a last line
//! without its line break (a file cut short) is warned of, with the value the default puts
//! there; so is a half's number that `[cat]` leaves to the default, one it gives that no half
//! uses (both `[cat.front]` and `[cat.rear]` give their own), and a `[cat.legs]` number that both
//! pairs of legs replace.

use super::cat::ROD_KEYS;
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
    // An empty `[actuator]` says ideal motors (and is how catflip writes a problem without
    // limits); any other section is empty only by accident.
    for section in empty_sections(table, "").into_iter().filter(|s| s != "actuator") {
        if !overridden(overrides, &section) {
            out.push(format!(
                "the file's [{section}] section holds no field: was the file cut short? (every field of it takes its default)"
            ));
        }
    }
    // The halves as the overrides leave them (one can give a whole section, `cat={…}`); an
    // override that cannot apply is refused later, naming itself.
    let mut merged = table.clone();
    for assignment in overrides {
        let _ = super::overrides::apply(&mut merged, assignment);
    }
    out.extend(halves(&merged));
    if !text.is_empty() && !text.ends_with('\n') {
        out.push(
            "the file does not end with a line break: was it cut short? (every field it leaves out takes its default)"
                .to_string(),
        );
    }
    Ok(out)
}

/// The dotted names of the sections of `table` (under `prefix`) that hold no field.
fn empty_sections(table: &toml::Table, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (key, value) in table {
        if let Some(inner) = value.as_table() {
            let name = format!("{prefix}{key}");
            if inner.is_empty() {
                out.push(name);
            } else {
                out.extend(empty_sections(inner, &format!("{name}.")));
            }
        }
    }
    out
}

/// The halves' numbers the file leaves to the defaults, or gives where no half uses them, in
/// `table` (the file's with the overrides applied) when it has a `[cat]` section (given by the
/// file or by an override inside it; the section's absence alone is warned of on its own): each of `mass`,
/// `length` and `radius` that `[cat]` does not give but a half without its own takes from the
/// default, and each that `[cat]` gives, other than the default, but both `[cat.front]` and
/// `[cat.rear]` give their own of (a problem catflip writes back gives every `[cat]` number, the
/// defaults included, so those are not warned of). Likewise each `[cat.legs]` number that both
/// `[cat.legs.front]` and `[cat.legs.rear]` give their own of (the legs have no defaults).
fn halves(table: &toml::Table) -> Vec<String> {
    let Some(cat) = table.get("cat").and_then(|c| c.as_table()) else { return Vec::new() };
    let default = crate::model::Cylinder::default();
    let mut out = Vec::new();
    for (key, value) in [("mass", default.mass), ("length", default.length), ("radius", default.radius)] {
        let takers: Vec<&str> = ["front", "rear"].into_iter().filter(|h| !gives(part(cat, h), key)).collect();
        let given = cat.get(key).and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)));
        if !gives(Some(cat), key) && !takers.is_empty() {
            let who =
                if takers.len() == 2 { "both halves take".to_string() } else { format!("cat.{} takes", takers[0]) };
            out.push(format!("the file gives no cat.{key}: {who} the default {value}"));
        } else if given.is_some_and(|g| g.to_bits() != value.to_bits()) && takers.is_empty() {
            out.push(format!(
                "cat.{key} is used by neither half: [cat.front] and [cat.rear] both give their own {key}"
            ));
        }
    }
    if let Some(legs) = part(cat, "legs") {
        for key in ROD_KEYS {
            if gives(Some(legs), key) && ["front", "rear"].into_iter().all(|p| gives(part(legs, p), key)) {
                out.push(format!(
                    "cat.legs.{key} is used by neither pair: [cat.legs.front] and [cat.legs.rear] both give their own {key}"
                ));
            }
        }
    }
    out
}

/// The section `name` inside `section`, if it has one.
fn part<'a>(section: &'a toml::Table, name: &str) -> Option<&'a toml::Table> {
    section.get(name).and_then(|h| h.as_table())
}

/// Whether `section` (if there is one) gives `key`.
fn gives(section: Option<&toml::Table>, key: &str) -> bool {
    section.is_some_and(|t| t.contains_key(key))
}

/// The `name` of a file that gives none: its stem, when that can name a results folder; else
/// the stem with each other character made `-`, said in the warning returned (`my.cat.toml` is
/// `my-cat`); refused when nothing of it can name a folder.
pub(crate) fn name_from_stem(path: &std::path::Path) -> Result<(String, Option<String>), ProblemError> {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    if names_a_folder(&stem) {
        return Ok((stem, None));
    }
    let made: String =
        stem.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '-' }).collect();
    let made = made.trim_matches('-').to_string();
    if names_a_folder(&made) && made.chars().any(|c| c.is_ascii_alphanumeric()) {
        let warning = format!(
            "the file gives no name and its stem \"{stem}\" cannot name a results folder (letters, digits, '-' and '_' only): named \"{made}\" (give name = \"...\" to choose)"
        );
        return Ok((made, Some(warning)));
    }
    Err(bad(
        "name",
        "(not given)",
        &format!(
            "the file's stem \"{stem}\" cannot name a results folder (letters, digits, '-' and '_' only): give name = \"...\""
        ),
    ))
}
