"""Shared fixtures: the repository's problems and the CLI binary the package is compared with.

The CLI is ``target/release/catflip`` at the repository root (``.ci/run`` builds it before the
package), or the path in ``CATFLIP_CLI``; tests that need it are skipped, with a message, when it
is absent.
"""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PROBLEMS = ROOT / "problems"
#: Keys whose values are wall-clock times, which no two runs share.
CLOCK_KEYS = {"run_time_s", "solve_time_s", "seconds"}


def cli_path() -> Path:
    return Path(os.environ.get("CATFLIP_CLI", ROOT / "target" / "release" / "catflip"))


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI; returns ``(exit code, stdout, stderr)``."""
    path = cli_path()
    if not path.exists():
        pytest.skip(f"the catflip CLI is not built at {path} (cargo build --release, or set CATFLIP_CLI)")

    def run(*args: str):
        p = subprocess.run([str(path), *args], capture_output=True, text=True, cwd=ROOT)
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    """Runs the CLI with ``--json``; returns the parsed report (the exit code is not checked: an
    optimum not found exits non-zero after printing its report)."""

    def run(*args: str):
        code, out, err = cli(*args, "--json")
        assert out, f"catflip {' '.join(args)} --json printed nothing (exit {code}): {err}"
        return json.loads(out)

    return run


def without_clock(value):
    """``value`` with every wall-clock field removed, recursively."""
    if isinstance(value, dict):
        return {k: without_clock(v) for k, v in value.items() if k not in CLOCK_KEYS}
    if isinstance(value, list):
        return [without_clock(v) for v in value]
    return value


def cli_error(stderr: str) -> str:
    """The CLI's error line without its ``error: `` prefix."""
    lines = [line for line in stderr.splitlines() if line.startswith("error: ")]
    assert len(lines) == 1, f"expected one error line, got: {stderr!r}"
    return lines[0][len("error: ") :]
