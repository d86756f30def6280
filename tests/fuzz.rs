//! Fuzz the problem file and `--set` with hostile values on the real keys (proptest): no
//! panic, and every rejection is one line that names the field as the user writes it (the
//! dotted key, e.g. `cat.mass`). A fast sample runs in CI; 10⁵ inputs per property run with
//! `cargo test --release --test fuzz -- --ignored`. The file surfaces added since (schedule files,
//! sweep files, shard manifests) are fuzzed in `tests/fuzz_files.rs`.

use std::cell::Cell;

use catflip::problem::Problem;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

/// Every key of a problem file, dotted, with a valid value in TOML syntax.
const KEYS: [(&str, &str); 21] = [
    ("name", "\"fuzz\""),
    ("cat.mass", "1.0"),
    ("cat.length", "1.0"),
    ("cat.radius", "0.1"),
    ("drop.height", "10.0"),
    ("drop.gravity", "9.8"),
    ("manoeuvre.theta_deg", "45.0"),
    ("manoeuvre.phases", "[0.2, 0.6, 0.2]"),
    ("manoeuvre.profile", "\"cycloidal\""),
    ("manoeuvre.circulation", "\"paper\""),
    ("manoeuvre.bend_path", "\"joint-circle\""),
    ("exact.tolerance", "1e-10"),
    ("exact.torque_samples", "400"),
    ("rapier.dt", "5e-4"),
    ("rapier.cross_mass_fraction", "1e-6"),
    ("optimize.nodes", "101"),
    ("optimize.boundary", "\"rest-to-rest\""),
    ("optimize.rate_limit", "10.0"),
    ("optimize.jerk_limit", "1e4"),
    ("optimize.smoothness", "0.0"),
    ("optimize.refine_iterations", "4"),
];

/// Hostile values in TOML syntax (some are not TOML at all).
const HOSTILE: [&str; 34] = [
    "nan",
    "+nan",
    "-nan",
    "inf",
    "-inf",
    "\"NaN\"",
    "\"inf\"",
    "1e308",
    "1.7976931348623157e308",
    "-1e308",
    "4.9e-324",
    "2.2250738585072014e-308",
    "1e-320",
    "0",
    "0.0",
    "-0.0",
    "-1",
    "-1e-300",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551616",
    "true",
    "\"\"",
    "\"\\u0000\"",
    "\"\u{FFFD}\u{FFFD}\\u00ff\"",
    "\"paper\\nname\"",
    "[]",
    "[1, 2, 3, 4]",
    "[\"a\", 1]",
    "[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]",
    "{ a = 1 }",
    "{ a = { b = { c = { d = { e = 1 } } } } }",
    "1979-05-27T07:32:00Z",
    "'''multi\nline'''",
];

fn paper() -> String {
    std::fs::read_to_string("problems/paper.toml").expect("problems/paper.toml is in the repository")
}

/// A document with every key at its valid value except `bad`, written as `key = value` under
/// its section.
fn document(bad: Option<(&str, &str)>, extra: &[(String, String)]) -> String {
    let mut sections: Vec<(String, Vec<String>)> = vec![(String::new(), Vec::new())];
    let mut put = |key: &str, value: &str| {
        let (section, leaf) = key.rsplit_once('.').unwrap_or(("", key));
        let i = match sections.iter().position(|(s, _)| s == section) {
            Some(i) => i,
            None => {
                sections.push((section.to_string(), Vec::new()));
                sections.len() - 1
            }
        };
        sections[i].1.push(format!("{leaf} = {value}"));
    };
    for (key, good) in KEYS {
        put(key, bad.filter(|(k, _)| *k == key).map_or(good, |(_, v)| v));
    }
    for (k, v) in extra {
        put(k, v);
    }
    sections
        .iter()
        .map(|(s, lines)| if s.is_empty() { lines.join("\n") } else { format!("[{s}]\n{}", lines.join("\n")) })
        .collect::<Vec<_>>()
        .join("\n\n")
}

/// The error's text when `text` with `overrides` is refused, after checking it is one line.
fn refusal(text: &str, overrides: &[String]) -> Result<Option<String>, TestCaseError> {
    match Problem::from_toml(text, "fuzz.toml", overrides) {
        Ok(p) => {
            let numbers =
                [p.cat.mass, p.cat.length, p.cat.radius, p.drop.height, p.drop.gravity, p.manoeuvre.theta_deg];
            prop_assert!(numbers.iter().all(|x| x.is_finite() && *x > 0.0), "accepted {numbers:?}");
            Ok(None)
        }
        Err(e) => {
            let s = e.to_string();
            prop_assert!(!s.contains('\n') && !s.is_empty(), "not one line: {s:?}");
            Ok(Some(s))
        }
    }
}

fn hostile() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => proptest::sample::select(HOSTILE.to_vec()).prop_map(str::to_string),
        1 => any::<f64>().prop_map(|x| format!("{x:e}")),
        1 => any::<i64>().prop_map(|x| x.to_string()),
        1 => proptest::collection::vec(any::<u8>(), 0..24).prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
        1 => "[a-z\"'\\[\\]{}=.,#\\\\ ]{0,16}",
    ]
}

fn key() -> impl Strategy<Value = &'static str> {
    proptest::sample::select(KEYS.iter().map(|(k, _)| *k).collect::<Vec<_>>())
}

/// One hostile value on one key, in the file: refused with the key named, or accepted.
fn file_property(cases: u32) {
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let (accepted, refused) = (Cell::new(0u32), Cell::new(0u32));
    runner
        .run(&(key(), hostile()), |(key, value)| {
            let text = document(Some((key, &value)), &[]);
            if text.parse::<toml::Table>().is_err() {
                // Not TOML at all: refused with the line, still one line.
                prop_assert!(refusal(&text, &[])?.is_some());
                return Ok(());
            }
            match refusal(&text, &[])? {
                None => accepted.set(accepted.get() + 1),
                Some(s) => {
                    refused.set(refused.get() + 1);
                    prop_assert!(s.contains(key), "{key} = {value}: the refusal does not name {key}: {s}");
                }
            }
            Ok(())
        })
        .expect("every hostile file value is refused in one line naming its field, or accepted with valid numbers");
    println!("file: {cases} inputs, {} accepted, {} refused naming the field", accepted.get(), refused.get());
}

/// One hostile `--set key=value` on the paper's problem: refused naming the key, or accepted.
fn set_property(cases: u32) {
    let base = paper();
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let (accepted, refused) = (Cell::new(0u32), Cell::new(0u32));
    runner
        .run(&(key(), hostile()), |(key, value)| {
            match refusal(&base, &[format!("{key}={value}")])? {
                None => accepted.set(accepted.get() + 1),
                Some(s) => {
                    refused.set(refused.get() + 1);
                    prop_assert!(s.contains(key), "--set {key}={value}: the refusal does not name {key}: {s}");
                }
            }
            Ok(())
        })
        .expect("every hostile --set is refused in one line naming its field, or accepted with valid numbers");
    println!("--set: {cases} inputs, {} accepted, {} refused naming the field", accepted.get(), refused.get());
}

/// Whole random documents: many hostile keys at once, unknown keys, nonsense overrides. Only
/// "no panic, one line" can be asked of them.
fn document_property(cases: u32) {
    let mut runner = TestRunner::new(Config { cases, failure_persistence: None, ..Config::default() });
    let extra = proptest::collection::vec(
        (prop_oneof![key().prop_map(str::to_string), "[a-z]{1,6}(\\.[a-z]{1,6}){0,3}", "[^=]{0,12}"], hostile()),
        0..6,
    );
    let overrides = proptest::collection::vec(
        prop_oneof![(key(), hostile()).prop_map(|(k, v)| format!("{k}={v}")), ".{0,24}"],
        0..4,
    );
    runner
        .run(&(extra, overrides), |(extra, overrides)| {
            let text = document(None, &extra);
            refusal(&text, &overrides)?;
            Ok(())
        })
        .expect("no random document panics, and every refusal is one line");
    println!("documents: {cases} inputs without a panic");
}

#[test]
fn hostile_file_values_are_refused_naming_the_field() {
    file_property(2_000);
}

#[test]
fn hostile_overrides_are_refused_naming_the_field() {
    set_property(2_000);
}

#[test]
fn random_documents_never_panic() {
    document_property(2_000);
}

#[test]
#[ignore = "10⁵ inputs per property: cargo test --release --test fuzz -- --ignored"]
fn fuzz_one_hundred_thousand() {
    file_property(100_000);
    set_property(100_000);
    document_property(100_000);
}
