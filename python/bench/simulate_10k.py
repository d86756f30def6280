"""How much the Python package adds to a call: N calls of ``catflip.simulate(problem,
series=False)`` against N calls of the same work in Rust (examples/simulate_10k.rs: the library's
``simulate`` on the resolved problem, bare and with its JSON serialisation), on one problem.
Timing only, not a test; prints one JSON line with the ratios.

    python python/bench/simulate_10k.py [PROBLEM [N [ROUNDS]]]

Run from the repository root after ``cargo build --release --example simulate_10k`` and the
package's install (README, "Python"). Both sides load and resolve the problem once, outside the
timed loops; the Python call also starts a worker thread and turns the report into a dict. The N
calls are made in ROUNDS (default 10) alternating rounds, Rust then Python, so that a machine
shared with other work slows both sides alike; the ratio is of the totals, and the per-round
ratios' median and range are printed beside it.
"""

import json
import statistics
import subprocess
import sys
import time
import warnings

import catflip


def rust_round(problem_path: str, n: int) -> dict:
    out = subprocess.run(
        ["target/release/examples/simulate_10k", problem_path, str(n)], check=True, capture_output=True, text=True
    ).stdout
    return json.loads(out)


def main() -> None:
    problem_path = sys.argv[1] if len(sys.argv) > 1 else "problems/paper.toml"
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 10_000
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 10
    per_round = n // rounds
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        problem = catflip.load(problem_path)
        catflip.simulate(problem, series=False)  # resolves the problem once, as the Rust side does
        rust, rust_json, python = [], [], []
        for _ in range(rounds):
            r = rust_round(problem_path, per_round)
            rust.append(r["rust_s"])
            rust_json.append(r["rust_json_s"])
            start = time.perf_counter()
            for _ in range(per_round):
                catflip.simulate(problem, series=False)
            python.append(time.perf_counter() - start)
    ratios = [p / r for p, r in zip(python, rust)]
    calls = per_round * rounds
    print(
        json.dumps(
            {
                "problem": problem_path,
                "calls": calls,
                "rounds": rounds,
                "rust_s": sum(rust),
                "rust_json_s": sum(rust_json),
                "python_s": sum(python),
                "python_per_call_s": sum(python) / calls,
                "rust_per_call_s": sum(rust) / calls,
                "ratio_to_rust": sum(python) / sum(rust),
                "ratio_to_rust_with_json": sum(python) / sum(rust_json),
                "round_ratio_median": statistics.median(ratios),
                "round_ratio_range": [min(ratios), max(ratios)],
            }
        )
    )


if __name__ == "__main__":
    main()
