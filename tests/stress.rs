//! Stress: seeded random problems spanning decades (`catflip::measure::bench::random`) — every
//! case passes its checks or is refused with a one-line reason; never a panic, a NaN or an
//! invariant broken. The fast sample runs in CI; the 10⁴ cases run with
//! `cargo test --release --test stress -- --ignored`.

use catflip::measure::bench::random::{run_many, Verdict};

fn base() -> String {
    std::fs::read_to_string("problems/paper.toml").expect("problems/paper.toml is in the repository")
}

fn check(seed: u64, count: usize) {
    let (results, tally) = run_many(&base(), seed, count);
    let failed: Vec<String> = results
        .iter()
        .filter_map(|r| match &r.verdict {
            Verdict::Failed(why) => Some(format!("case {}: {why} ({})", r.case.index, r.case.overrides.join(" "))),
            _ => None,
        })
        .collect();
    println!("seed {seed}: {tally:?}");
    assert!(failed.is_empty(), "{} failed:\n{}", failed.len(), failed.join("\n"));
    for r in &results {
        if let Verdict::Refused(why) = &r.verdict {
            let names_a_field = ["manoeuvre.", "cat.", "drop."].iter().any(|f| why.contains(f));
            assert!(!why.contains('\n') && names_a_field, "{why}");
        }
    }
    assert_eq!(tally.cases, count);
    assert!(tally.passed >= count / 2, "{tally:?}: most random cases are inside the model");
}

#[test]
fn random_sample_of_200_passes_or_is_refused_clearly() {
    check(2026, 200);
}

#[test]
#[ignore = "10⁴ cases, minutes: cargo test --release --test stress -- --ignored"]
fn random_ten_thousand_pass_or_are_refused_clearly() {
    check(11, 10_000);
}
