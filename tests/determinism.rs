//! Determinism: the same problem gives bit-identical JSON on rerun, timing fields aside
//! (`*_time_s` and `seconds`: wall-clock times, which are measurements of the machine, not results),
//! whatever the number of threads the run's parallel parts get.

use std::path::{Path, PathBuf};

use catflip::engines::circulation::Resolved;
use catflip::problem::Problem;

/// The JSON value with every wall-clock field (`run_time_s`, `solve_time_s`, …) removed.
fn without_timing(v: serde_json::Value) -> serde_json::Value {
    match v {
        serde_json::Value::Object(m) => m
            .into_iter()
            .filter(|(k, _)| !(k.ends_with("time_s") || k == "seconds"))
            .map(|(k, v)| (k, without_timing(v)))
            .collect(),
        serde_json::Value::Array(a) => a.into_iter().map(without_timing).collect(),
        other => other,
    }
}

fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the run wrote its folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn paper_run_gives_identical_json_twice_on_one_and_on_two_threads() {
    let problem = Problem::load(Path::new("problems/paper.toml"), &[]).expect("the paper's problem loads");
    let root = std::env::temp_dir().join(format!("catflip-determinism-{}", std::process::id()));
    let outs: Vec<PathBuf> = [("a", 1), ("b", 2)]
        .iter()
        .map(|&(run, threads)| {
            let out = root.join(run);
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
            pool.install(|| {
                let r = Resolved::new(&problem).expect("the paper's problem resolves");
                catflip::report::run::run(&r, "determinism test", &out).expect("the run succeeds").dir
            })
        })
        .collect();
    let (a, b) = (json_files(&outs[0]), json_files(&outs[1]));
    assert!(a.len() >= 4, "{a:?}");
    assert_eq!(
        a.iter().map(|p| p.file_name()).collect::<Vec<_>>(),
        b.iter().map(|p| p.file_name()).collect::<Vec<_>>()
    );
    for (x, y) in a.iter().zip(&b) {
        let read = |p: &Path| -> serde_json::Value {
            serde_json::from_str(&std::fs::read_to_string(p).expect("readable JSON")).expect("valid JSON")
        };
        let (vx, vy) = (without_timing(read(x)), without_timing(read(y)));
        // Bit-identical: the serialised text (shortest round-trip floats) must match exactly.
        assert_eq!(vx.to_string(), vy.to_string(), "{} differs between runs", x.display());
    }
    // The animation too: frames drawn in parallel, one palette.
    let gif = |d: &Path| std::fs::read(d.join("plots/flip.gif")).expect("the animation was written");
    assert!(gif(&outs[0]) == gif(&outs[1]), "flip.gif differs between one and two threads");
    let _ = std::fs::remove_dir_all(&root);
}
