"""Every number the package returns is the CLI's (``--json``) for the same problem: the paper's
problem and two others, every command, compared as dicts (floats exactly equal: both are the same
library function's output; only wall-clock fields are left out)."""

import warnings

import pytest

import catflip
from conftest import PROBLEMS, without_clock

NAMES = ["paper", "servo", "cone-calibrated"]


@pytest.fixture(scope="module", params=NAMES)
def case(request):
    path = PROBLEMS / f"{request.param}.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        return str(path.relative_to(PROBLEMS.parent)), catflip.load(path)


def same(python, cli):
    assert without_clock(python) == without_clock(cli)


@pytest.mark.parametrize("engine", ["exact", "rapier"])
def test_simulate(case, engine, cli_json):
    path, problem = case
    same(catflip.simulate(problem, engine, series=False).report, cli_json("simulate", path, "--engine", engine))


def test_compare(case, cli_json):
    path, problem = case
    same(catflip.compare(problem), cli_json("compare", path))


def test_compare_verify(cli_json):
    path = "problems/paper.toml"
    report = catflip.compare(catflip.load(PROBLEMS / "paper.toml"), verify=True)
    same(report, cli_json("compare", path, "--verify"))
    assert [r["verdict"] for r in report["rapier"]] == ["verified"] * 9


def test_optimize(case, cli_json):
    path, problem = case
    same(catflip.optimize(problem, series=False).report, cli_json("optimize", path))


def test_optimize_whole(case, cli_json):
    path, problem = case
    same(catflip.optimize_whole(problem, series=False).report, cli_json("optimize", path, "--whole"))


def test_overrides_are_the_clis(cli_json):
    problem = catflip.load(PROBLEMS / "paper.toml", {"manoeuvre.profile": "cycloidal", "drop.height": 5.0})
    cli = cli_json("simulate", "problems/paper.toml", "--set", "manoeuvre.profile=cycloidal", "--set", "drop.height=5")
    same(catflip.simulate(problem, series=False).report, cli)


def test_a_dict_and_a_toml_string_load_the_files_problem():
    path = PROBLEMS / "servo.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        from_file = catflip.load(path)
        from_text = catflip.loads(path.read_text())
        from_dict = catflip.from_dict(from_file.to_dict())
    assert from_text.to_dict() == from_file.to_dict()
    assert from_dict.to_dict() == from_file.to_dict()


def test_imported_arrays_are_the_clis_schedule_file(tmp_path, cli_json):
    """A schedule handed over as numpy arrays is evaluated as the same columns in a CSV file are
    by ``simulate --schedule`` (both engines)."""
    import numpy as np

    problem = catflip.load(PROBLEMS / "paper.toml", {"manoeuvre.profile": "cycloidal"})
    s = catflip.schedule_series(problem, steps_per_piece=60)
    file = tmp_path / "given.csv"
    table = np.column_stack([s.t, s.q, s.qd, s.qdd])
    lines = ["t,q1,q2,qd1,qd2,qdd1,qdd2"] + [",".join(repr(float(x)) for x in row) for row in table]
    file.write_text("\n".join(lines) + "\n")
    schedule = catflip.import_schedule(s.t, s.q, s.qd, s.qdd, name=str(file))
    assert schedule.rows == len(s.t) and schedule.interpolation == "quintic-hermite"
    for engine in ["exact", "rapier"]:
        cli = cli_json("simulate", "problems/paper.toml", "--set", "manoeuvre.profile=cycloidal", "--schedule", str(file), "--engine", engine)
        same(catflip.simulate(problem, engine, schedule=schedule).report, cli)
        same(catflip.simulate(problem, engine, schedule=catflip.read_schedule(file)).report, cli)


@pytest.mark.parametrize("name", ["kane-scher", "unequal-halves"])
def test_other_cat_models_give_the_clis_numbers(name, cli_json):
    """The exact engine's simulate and compare on Kane and Scher's cat and on unequal halves."""
    path = f"problems/{name}.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        problem = catflip.load(PROBLEMS / f"{name}.toml")
    same(catflip.simulate(problem, series=False).report, cli_json("simulate", path))
    same(catflip.compare(problem), cli_json("compare", path))


def test_compare_models_gives_the_clis_numbers(cli_json):
    """Each model's whole optimum, as ``catflip compare-models --json`` (a coarse spline, so that
    it solves in a second; the command line is the CLI's own and left out)."""
    sets = {"optimize.whole.control_points": 40, "optimize.whole.switch_refinements": 0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        problem = catflip.load(PROBLEMS / "kane-scher.toml", sets)
        python = catflip.compare_models(problem)
    cli = cli_json("compare-models", "problems/kane-scher.toml", *[a for k, v in sets.items() for a in ("--set", f"{k}={v}")])
    assert [(r["key"], r["motors"]) for r in python["rows"]] == [("universal", 2), ("no-twist", 2), ("spherical", 3)]
    assert python["cheapest"] in ("universal", "no-twist", "spherical")
    # The one field that differs: what made it (the CLI's command line, the package's call).
    assert python.pop("command") == 'catflip.compare_models(problem "kane-scher") (Python)'
    assert cli.pop("command").startswith("cargo run --release -- compare-models problems/kane-scher.toml")
    same(python, cli)


def test_a_problem_pickles_to_the_same_problem():
    # multiprocessing hands a Problem to its workers by pickle (it raised TypeError).
    import pickle

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        problem = catflip.load(PROBLEMS / "unequal-halves.toml", {"cat.rear.mass": 1.3})
    back = pickle.loads(pickle.dumps(problem))
    assert back.name == problem.name and back.to_dict() == problem.to_dict()
    twist = [catflip.simulate(p, series=False).report["twist_deg"] for p in (back, problem)]
    assert twist[0] == twist[1]
