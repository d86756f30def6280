"""How much the Python package adds to a call: N calls of ``catflip.simulate(problem,
series=False)`` against N calls of the same work in Rust (examples/simulate_10k.rs), on one
problem. Timing only, not a test; prints one JSON line with the ratio.

    python python/bench/simulate_10k.py [PROBLEM [N]]

Run from the repository root after ``cargo build --release --example simulate_10k`` and the
package's install (README, "Python"). Both sides load and resolve the problem once, outside the
timed loop; the Python call also starts a worker thread and turns the report into a dict.
"""

import json
import subprocess
import sys
import time
import warnings

import catflip


def main() -> None:
    problem_path = sys.argv[1] if len(sys.argv) > 1 else "problems/paper.toml"
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 10_000
    rust = json.loads(
        subprocess.run(
            ["target/release/examples/simulate_10k", problem_path, str(n)], check=True, capture_output=True, text=True
        ).stdout
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        problem = catflip.load(problem_path)
        catflip.simulate(problem, series=False)  # resolves the problem once, as the Rust side does
        start = time.perf_counter()
        for _ in range(n):
            catflip.simulate(problem, series=False)
        python_s = time.perf_counter() - start
    print(
        json.dumps(
            {
                **rust,
                "python_s": python_s,
                "python_per_call_s": python_s / n,
                "ratio_to_rust": python_s / rust["rust_s"],
                "ratio_to_rust_with_json": python_s / rust["rust_json_s"],
            }
        )
    )


if __name__ == "__main__":
    main()
