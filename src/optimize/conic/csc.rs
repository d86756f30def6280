//! One sparse matrix from triplets: Clarabel's `CscMatrix::new_from_triplets` entry for entry
//! (sorted by column, then row; a repeated entry summed in the order given), by a counting sort
//! on the columns and a sort of each column's few rows, where Clarabel sorts every entry by an
//! index comparison (6 % of the spherical joint's whole optimisation on the paper's cat, measured
//! by `perf`, 2026-12-06).

use clarabel::algebra::CscMatrix;

/// The `m × n` matrix with the entries `val[e]` at `(row[e], col[e])`, repeats summed.
///
/// # Panics
/// When the three lists differ in length, or an index lies outside `m × n`.
pub(crate) fn from_triplets(m: usize, n: usize, row: &[usize], col: &[usize], val: &[f64]) -> CscMatrix<f64> {
    assert!(row.len() == col.len() && col.len() == val.len(), "triplets of one length");
    assert!(row.iter().all(|&r| r < m) && col.iter().all(|&c| c < n), "triplets within {m} × {n}");
    // Where each column's entries start in `order`, the entries in column order (as given
    // within a column: the counting sort is stable).
    let mut start = vec![0usize; n + 1];
    for &c in col {
        start[c + 1] += 1;
    }
    for c in 0..n {
        start[c + 1] += start[c];
    }
    let mut next = start.clone();
    let mut order = vec![0usize; val.len()];
    for (e, &c) in col.iter().enumerate() {
        order[next[c]] = e;
        next[c] += 1;
    }
    let mut colptr = Vec::with_capacity(n + 1);
    let mut rowval: Vec<usize> = Vec::with_capacity(val.len());
    let mut nzval: Vec<f64> = Vec::with_capacity(val.len());
    colptr.push(0);
    for c in 0..n {
        let entries = &mut order[start[c]..start[c + 1]];
        // Stable: repeats of one row keep the order given, and are summed in it.
        entries.sort_by_key(|&e| row[e]);
        let first = rowval.len();
        for &e in entries.iter() {
            match (rowval.last(), nzval.last_mut()) {
                (Some(&r), Some(sum)) if rowval.len() > first && r == row[e] => *sum += val[e],
                _ => {
                    rowval.push(row[e]);
                    nzval.push(val[e]);
                }
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(m, n, colptr, rowval, nzval)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Clarabel's own constructor and this one agree bit for bit: the same columns, rows
        /// and sums (repeats included, in any order, values of every magnitude and sign).
        #[test]
        fn the_same_matrix_as_clarabels_constructor(
            m in 1usize..12,
            n in 1usize..12,
            entries in proptest::collection::vec((0usize..12, 0usize..12, -1e6f64..1e6), 0..200),
        ) {
            let (mut row, mut col, mut val) = (Vec::new(), Vec::new(), Vec::new());
            for (r, c, v) in entries {
                row.push(r % m);
                col.push(c % n);
                val.push(v * 10f64.powi((r as i32 % 7) - 3));
            }
            let ours = from_triplets(m, n, &row, &col, &val);
            let theirs = CscMatrix::new_from_triplets(m, n, row, col, val);
            prop_assert_eq!((ours.m, ours.n), (theirs.m, theirs.n));
            prop_assert_eq!(&ours.colptr, &theirs.colptr);
            prop_assert_eq!(&ours.rowval, &theirs.rowval);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&ours.nzval), bits(&theirs.nzval));
        }
    }
}
