//! A schedule given as columns of numbers rather than a file (e.g. numpy arrays from the Python
//! package): the columns are written as the CSV text [`crate::exchange::read_schedule`] reads and
//! parsed by the same [`parse_schedule`], so every check and every message is the file's.
//!
//! Column names are those of the file (`t`, `q1`, `q2`, optionally `qd1`, `qd2`, `qdd1`,
//! `qdd2`; see [`crate::exchange::import`]); numbers are written with Rust's shortest round-trip
//! formatting, so the parser reads back the very `f64`s given (NaN and infinities as `NaN`,
//! `inf`, which it refuses by name). Row `k` (0-based) is line `k + 2` in messages (line 1 is the
//! header). Columns of unequal lengths make rows with missing fields, refused as a truncated file
//! is.

use crate::exchange::import::{parse_schedule, ImportError, ImportedSchedule};

/// The CSV text of `columns` (`(name, values)` in order): a header, then one line per row, each
/// with the fields its columns have (a column shorter than the others leaves its later rows
/// short).
pub fn columns_csv(columns: &[(&str, &[f64])]) -> String {
    let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
    let mut text = names.join(",") + "\n";
    let rows = columns.iter().map(|c| c.1.len()).max().unwrap_or(0);
    for k in 0..rows {
        let fields: Vec<String> = columns.iter().filter_map(|c| c.1.get(k)).map(|v| format!("{v:?}")).collect();
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}

/// The schedule of `columns`, named `origin` in messages ([`columns_csv`], then
/// [`parse_schedule`]).
pub fn schedule_from_columns(columns: &[(&str, &[f64])], origin: &str) -> Result<ImportedSchedule, ImportError> {
    parse_schedule(&columns_csv(columns), origin)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schedule::Trajectory;

    #[test]
    fn columns_read_back_to_the_same_numbers() {
        let t: Vec<f64> = (0..9).map(|k| k as f64 * 0.1 + 1e-17).collect();
        let q1: Vec<f64> = t.iter().map(|x| (x * 3.0).sin() / 7.0).collect();
        let q2: Vec<f64> = t.iter().map(|x| x * x / 3.0).collect();
        let s = schedule_from_columns(&[("t", &t), ("q1", &q1), ("q2", &q2)], "arrays").expect("a valid schedule");
        assert_eq!(s.rows, 9);
        for (k, &tk) in t.iter().enumerate() {
            let st = s.piece_state(0, tk - t[0]);
            assert!((st.q[0] - q1[k]).abs() <= 1e-15, "row {k}: q1 {} read back as {}", q1[k], st.q[0]);
        }
    }

    #[test]
    fn a_short_column_is_refused_as_a_truncated_file() {
        let t = [0.0, 0.1, 0.2, 0.3, 0.4];
        let e = schedule_from_columns(&[("t", &t), ("q1", &t), ("q2", &t[..3])], "arrays").unwrap_err();
        assert!(matches!(e, ImportError::Csv { line: 5, .. }), "{e}");
    }

    #[test]
    fn a_nan_is_refused_by_name() {
        let t = [0.0, 0.1, 0.2, 0.3, 0.4];
        let q = [0.0, f64::NAN, 0.0, 0.0, 0.0];
        let e = schedule_from_columns(&[("t", &t), ("q1", &q), ("q2", &t)], "arrays").unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("`q1`") && e.contains("NaN"), "{e}");
    }
}
