//! The provenance header of generated reports: version, date, machine
//! ([`crate::measure::machine`]), settings, command.

use std::time::{SystemTime, UNIX_EPOCH};

/// A UTC timestamp `YYYY-MM-DD HH:MM:SS UTC` of now (civil-from-days, H. Hinnant's algorithm).
pub fn utc_now() -> String {
    let secs = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02} UTC", rem / 3600, rem % 3600 / 60, rem % 60)
}

/// How every report's provenance line starts; [`crate::report::owned`] knows catflip's reports
/// by it.
pub const REGENERATE: &str = "Regenerate with `";

/// The line that says how to regenerate a report: `Regenerate with `COMMAND`.`
pub fn regenerate_line(command: &str) -> String {
    format!("{REGENERATE}{command}`.")
}

/// The Markdown provenance header of a report.
pub fn header(title: &str, command: &str, settings_toml: &str) -> String {
    format!(
        "# {title}\n\n{}\n\n| | |\n|---|---|\n| catflip | {} |\n| date | {} |\n| machine | {} |\n| build | {} |\n\n<details><summary>Problem and settings</summary>\n\n```toml\n{}```\n\n</details>\n\n",
        regenerate_line(command),
        env!("CARGO_PKG_VERSION"),
        utc_now(),
        crate::measure::machine::machine(),
        if cfg!(debug_assertions) { "debug" } else { "release" },
        settings_toml
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn timestamp_has_the_expected_shape() {
        let s = super::utc_now();
        assert_eq!(s.len(), 23, "{s}");
        assert!(s.starts_with("20") && s.ends_with(" UTC"), "{s}");
    }
}
