#!/usr/bin/env bash
# The Python package's checks (README, "Python"), run by .ci/run after the Rust steps and runnable
# alone from anywhere: `bash python/test.sh`. In a fresh virtual environment it installs the
# package with the README's one command (`pip install ./python`: maturin builds the abi3 wheel in
# target/), then runs the pytest suite (against target/release/catflip, built first), the
# examples (MuJoCo's and pyBullet's replays when `pip install mujoco pybullet` works) and clippy
# on the binding crate.
# Without python3 (or its venv module) it says so and exits 0, except under CI=true, where
# a missing Python is a failure.
set -euo pipefail
cd "$(dirname "$0")/.."
skip() {
    if [ -n "${CI:-}" ]; then
        echo "python/test.sh: $1; CI must run the Python package's tests" >&2
        exit 1
    fi
    echo "python/test.sh: skipping the Python package: $1"
    exit 0
}
# `step LABEL COMMAND…` runs a step and prints how long it took (the added CI time, by step).
step() {
    local label=$1 start=$SECONDS
    shift
    "$@" || return $?
    echo "python/test.sh: $label took $((SECONDS - start)) s"
}
command -v python3 > /dev/null || skip "python3 is not installed"
python3 -c "import venv, ensurepip" 2> /dev/null || skip "python3 has no venv/ensurepip module"
venv=$(mktemp -d)
trap 'rm -rf "$venv"' EXIT
python3 -m venv "$venv"
step "installing pytest and numpy" "$venv/bin/pip" install --quiet --disable-pip-version-check pytest numpy || skip "pip cannot install pytest and numpy"
step "building the CLI" cargo build --release --bin catflip --example simulate_10k
step "pip install ./python" "$venv/bin/pip" install --quiet --disable-pip-version-check ./python
# From the repository root, so that `import catflip` is the installed package (python/catflip/
# alone lacks the compiled half).
step pytest "$venv/bin/pytest" -q -p no:cacheprovider python/tests
step "installing mujoco" "$venv/bin/pip" install --quiet --disable-pip-version-check mujoco || echo "python/test.sh: mujoco not installable; its example will say so"
step "installing pybullet" "$venv/bin/pip" install --quiet --disable-pip-version-check pybullet || echo "python/test.sh: pybullet not installable; its example will say so"
for example in python/examples/[0-9]*.py; do
    step "$example" "$venv/bin/python" "$example"
done
# The replay again on unequal halves (each half its own link in the MJCF).
step "MuJoCo's replay of unequal halves" "$venv/bin/python" python/examples/02_mujoco_replay.py problems/unequal-halves.toml
PYO3_PYTHON="$venv/bin/python" step "clippy on the binding" cargo clippy -p catflip-python --all-targets -- -D warnings
