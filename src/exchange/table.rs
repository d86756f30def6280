//! Tidy CSV tables written with the `csv` crate (quoting, escaping and line ends done right),
//! for every table `catflip` writes: one header row, then one row per record; and, for every CSV
//! file `catflip` reads, the line a record or an error is on ([`record_line`]) and the reader's
//! message without its own position ([`error_message`]).

/// A CSV text with `header` and `rows` (each row a sequence of already formatted fields).
pub fn csv_table<R>(header: &[&str], rows: impl IntoIterator<Item = R>) -> String
where
    R: IntoIterator,
    R::Item: AsRef<[u8]>,
{
    let mut w = csv::Writer::from_writer(Vec::new());
    // Writing into memory cannot fail: the only I/O is appending to a `Vec`.
    let bytes = w
        .write_record(header)
        .and_then(|()| rows.into_iter().try_for_each(|r| w.write_record(r)))
        .map_err(|e| e.to_string())
        .and_then(|()| w.into_inner().map_err(|e| e.to_string()));
    match bytes {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => unreachable!("a CSV written into memory failed: {e}"),
    }
}

/// The line of `text` (1 = the first) where the record the `csv` reader placed at `position`
/// begins, whatever the line ends (`\n`, `\r\n` or `\r`).
///
/// The reader's own [`csv::Position::line`] counts `\n` bytes up to where it stopped, which is
/// not where the record is: after a `\r\n` it stops between the `\r` and the `\n` (one line
/// short), and the blank and comment lines it skips before a record are not yet read (the
/// position is theirs). So the line is counted from the byte offset, after the line ends, blank
/// lines and lines starting with `comment` (the reader's comment byte, if any; the reader ends a
/// comment at `\n` only) that the reader skips there.
pub fn record_line(text: &[u8], position: &csv::Position, comment: Option<u8>) -> u64 {
    let mut at = usize::try_from(position.byte()).map_or(text.len(), |b| b.min(text.len()));
    loop {
        while matches!(text.get(at), Some(b'\r' | b'\n')) {
            at += 1;
        }
        match (text.get(at), comment) {
            // The reader ends a comment at `\n` only.
            (Some(&b), Some(c)) if b == c => {
                at += text[at..].iter().position(|&b| b == b'\n').unwrap_or(text.len() - at);
            }
            _ => break,
        }
    }
    let before = &text[..at];
    let lone_cr = before.windows(2).filter(|w| w[0] == b'\r' && w[1] != b'\n').count()
        + usize::from(before.last() == Some(&b'\r'));
    let ends = before.iter().filter(|&&b| b == b'\n').count() + lone_cr;
    ends as u64 + 1
}

/// The `csv` reader's message for `e` without the position it appends (the caller names the
/// line, by [`record_line`]).
pub fn error_message(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths { expected_len, len, .. } => {
            format!("{len} fields where the header has {expected_len}")
        }
        csv::ErrorKind::Utf8 { .. } => "not valid UTF-8".into(),
        _ => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line of each record (and of the error, if any) read from `text` as
    /// [`crate::exchange::import`] reads a schedule.
    fn lines(text: &str) -> Vec<u64> {
        let mut rd = csv::ReaderBuilder::new().comment(Some(b'#')).from_reader(text.as_bytes());
        rd.records()
            .map(|r| match r {
                Ok(r) => r.position().map_or(0, |p| record_line(text.as_bytes(), p, Some(b'#'))),
                Err(e) => e.position().map_or(0, |p| record_line(text.as_bytes(), p, Some(b'#'))),
            })
            .collect()
    }

    #[test]
    fn records_are_on_the_file_s_own_lines_whatever_the_line_ends() {
        let lf = "t,q\n0,0\n1,1\n2,2\n";
        assert_eq!(lines(lf), [2, 3, 4]);
        assert_eq!(lines(&lf.replace('\n', "\r\n")), [2, 3, 4]);
        assert_eq!(lines(&lf.replace('\n', "\r")), [2, 3, 4]);
        // Blank and comment lines before a record are skipped, and counted.
        let skipped = "t,q\n0,0\n# a note\n\n1,1\n";
        assert_eq!(lines(skipped), [2, 5]);
        assert_eq!(lines(&skipped.replace('\n', "\r\n")), [2, 5]);
        assert_eq!(lines("t,q\r0,0\r\r\r1,1\r"), [2, 5]);
        // A short row is refused on its own line.
        assert_eq!(lines("t,q\r\n0,0\r\n1\r\n"), [2, 3]);
    }

    #[test]
    fn quotes_fields_that_need_it() {
        let text =
            csv_table(&["name", "value"], [vec!["a,b".to_string(), "1".into()], vec!["c\"d".into(), "2".into()]]);
        assert_eq!(text, "name,value\n\"a,b\",1\n\"c\"\"d\",2\n");
    }
}
