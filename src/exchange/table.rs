//! Tidy CSV tables written with the `csv` crate (quoting, escaping and line ends done right),
//! for every table `catflip` writes: one header row, then one row per record.

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotes_fields_that_need_it() {
        let text =
            csv_table(&["name", "value"], [vec!["a,b".to_string(), "1".into()], vec!["c\"d".into(), "2".into()]]);
        assert_eq!(text, "name,value\n\"a,b\",1\n\"c\"\"d\",2\n");
    }
}
