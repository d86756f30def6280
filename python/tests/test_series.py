"""Time series, exports and tables: the arrays are the CLI's schedule file, and they agree with
the report they come with."""

import csv
import io
import json
import warnings
import signal
import threading
import _thread
import time

import numpy as np
import pytest

import catflip
from conftest import PROBLEMS

PAPER = PROBLEMS / "paper.toml"


@pytest.fixture(scope="module")
def paper():
    return catflip.load(PAPER, {"manoeuvre.profile": "cycloidal"})


def test_series_shapes_and_ends(paper):
    m = catflip.simulate(paper)
    s = m.series
    n = len(s.t)
    assert s.q.shape == s.qd.shape == s.qdd.shape == s.tau.shape == (n, 2) and s.orientation.shape == (n, 4)
    assert s.t[0] == 0.0 and np.all(np.diff(s.t) >= 0.0)
    # Unit quaternions; the last row's twist is the engine's to about its tolerance (the file's
    # orientation is carried to at least the engine's accuracy: src/exchange/schedule_file.rs).
    np.testing.assert_allclose(np.linalg.norm(s.orientation, axis=1), 1.0, rtol=0, atol=1e-12)
    assert abs(s.twist_deg[-1] - m.twist_deg) < 1e-6, (s.twist_deg[-1], m.twist_deg)
    # The straight cat at both ends, and the sampled torques never above the report's peak.
    np.testing.assert_allclose(s.q[[0, -1]], 0.0, atol=1e-12)
    assert np.max(np.abs(s.tau)) <= m.peak_torque_nm * (1 + 1e-9)


def test_series_is_the_exported_file(paper, tmp_path):
    written = catflip.export(paper, tmp_path)
    names = sorted(p.split("/")[-1] for p in written)
    assert names == ["model.urdf", "model.xml", "problem.csv", "problem.json"]
    text = (tmp_path / "problem.csv").read_text()
    s = catflip.Series.from_csv(text)
    rows = list(csv.DictReader(io.StringIO(text)))
    assert [float(r["tau1_nm"]) for r in rows] == s.tau[:, 0].tolist()
    assert json.loads((tmp_path / "problem.json").read_text())["columns"]
    # Its dict holds every column of the file (the impulses, each row's phase and boundary were
    # left out), and its repr is a line, not its 1203 rows.
    d = s.to_dict()
    assert d["impulse1"].tolist() == [float(r["impulse1_nms"]) for r in rows]
    assert d["phase"] == [r["phase"] for r in rows] and d["boundary"] == [r["boundary"] for r in rows]
    assert len(d) == len(rows[0]), sorted(rows[0])
    assert repr(s) == f"Series({len(rows)} rows, t 0–{s.t[-1]:g} s, phases ['bend', 'twist', 'unbend'])"
    mjcf = catflip.model_files(paper)["model.xml"]
    assert "<mujoco" in mjcf and mjcf.rstrip().endswith("</mujoco>")


def test_rate_grid(paper):
    s = catflip.schedule_series(paper, rate_hz=100.0)
    ordinary = [t for t, b in zip(s.t, s.boundary) if b == ""]
    # Rows on the grid k/100 s, but the final instant (written when it is off the grid).
    assert all(abs(t * 100.0 - round(t * 100.0)) < 1e-6 for t in ordinary[:-1])


def test_optimize_series_are_the_optima(paper, tmp_path):
    opt = catflip.optimize(paper, steps_per_piece=50)
    assert opt.series, "no optimum schedule"
    for name, s in opt.series.items():
        assert np.isfinite(s.tau).all(), name
    whole = catflip.optimize_whole(paper, steps_per_piece=50)
    assert whole.solved and whole.series is not None
    assert abs(abs(whole.series.twist_deg[-1]) - 180.0) < 1e-6
    assert np.max(np.abs(whole.series.tau)) <= whole.report["peak_torque_nm"]["max"] * (1 + 1e-6)
    names = {p.split("/")[-1] for p in catflip.export(paper, tmp_path, optimum=whole)}
    assert {"whole-optimum.csv", "whole-optimum.json"} <= names
    assert json.loads((tmp_path / "whole-optimum.json").read_text())["columns"]
    assert all(json.loads(s.sidecar)["columns"] for s in opt.series.values())


def test_sweep_records_are_the_clis_table(tmp_path, cli):
    sweep = tmp_path / "tiny.toml"
    sweep.write_text(
        f'name = "tiny"\nbase = "{PAPER}"\n[[axis]]\nfield = "manoeuvre.profile"\nvalues = ["cycloidal", "poly-345"]\n'
        "[[axis]]\nfield = \"cat.radius\"\nvalues = [0.1, 0.2]\n[compute]\npeaks = true\n"
    )
    records = catflip.sweep(sweep)
    code, _, err = cli("sweep", str(sweep), "--out", str(tmp_path / "cli"), "--quiet")
    assert code == 0, err
    assert records == catflip._table.records_from_csv((tmp_path / "cli" / "tiny" / "sweep.csv").read_text())
    assert len({r["case"] for r in records}) == 4
    assert all(r["status"] == "ok" and isinstance(r["twist_deg"], float) for r in records)
    try:
        frame = catflip.frame(records)
    except ImportError:
        return  # neither pandas nor polars: the records are the table
    assert len(frame) == len(records)


def test_warnings_point_at_the_callers_line_and_a_sweeps_cases_warn(tmp_path):
    # A warning from deep in the package (simulate → its report) was attributed to the package's
    # own line; a sweep's cases' warnings were dropped.
    problem = catflip.load(PAPER)
    s = catflip.simulate(problem).series
    late = catflip.import_schedule(s.t + 0.5, s.q, s.qd, s.qdd)  # times that do not start at zero
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        catflip.simulate(problem, schedule=late)
    assert caught and all(w.filename == __file__ for w in caught), [(w.filename, str(w.message)) for w in caught]
    sweep = tmp_path / "careless.toml"
    sweep.write_text(
        f'name = "careless"\nbase = "{PROBLEMS / "script-defaults.toml"}"\n[[axis]]\nfield = "cat.mass"\nvalues = [1.0, 1000.0]\n'
        "[compute]\npeaks = true\n"
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        catflip.sweep(sweep)
    said = [str(w.message) for w in caught if issubclass(w.category, catflip.CatflipWarning)]
    assert any(m.startswith("sweep careless: 1 of its 2 cases carry warnings") and "cat.mass = 1000 kg" in m for m in said), said
    assert all(w.filename == __file__ for w in caught)


def test_interrupt_raises_at_once_and_the_gil_is_free():
    """Ctrl-C (here ``_thread.interrupt_main``) during a long call raises KeyboardInterrupt from
    inside the call; a Python thread runs meanwhile (the GIL is released)."""
    # A process started in the background by a shell without job control (`cmd &`, as a CI
    # runner may start this suite) inherits SIGINT ignored, so Python installs no handler and
    # `interrupt_main` does nothing (Python docs, `_thread.interrupt_main`). Ctrl-C at a
    # terminal reaches Python's own handler, which is the case under test: install it here.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    problem = catflip.load(PROBLEMS / "servo.toml")
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    timer = threading.Timer(0.1, _thread.interrupt_main)  # the call below takes seconds
    returned = False
    try:
        timer.start()
        catflip.optimize_whole(problem, series=False)  # seconds of work
        returned = True
        time.sleep(30)  # where the interrupt would land if the call had not been interrupted
    except KeyboardInterrupt:
        pass
    finally:
        timer.cancel()
        stop.set()
        counter.join()
        signal.signal(signal.SIGINT, previous)
    assert not returned, "the call ran to its end: the interrupt was not delivered inside it"
    assert len(ticks) >= 3, "the counting thread did not run while the call waited"  # 0 or 1 if it held the GIL
    # The package goes on working (the interrupted computation finishes in the background).
    assert catflip.simulate(problem, series=False).report["problem"] == "servo"
