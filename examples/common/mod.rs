//! What the examples beyond the numbered ladder share: reading a problem from the command line.

use std::path::Path;

use catflip::problem::Problem;

/// The problem named on the command line (`[PROBLEM.toml] [--set KEY=VALUE ...]`, `default`
/// without a path), with its overrides, and its path.
pub fn problem_from_args(default: &str) -> anyhow::Result<(String, Problem)> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (path, rest) = match args.split_first() {
        Some((first, rest)) if !first.starts_with("--") => (first.clone(), rest),
        _ => (default.to_string(), &args[..]),
    };
    let sets: Vec<String> = rest.iter().filter(|a| *a != "--set").cloned().collect();
    let problem = Problem::load(Path::new(&path), &sets)?;
    Ok((path, problem))
}
