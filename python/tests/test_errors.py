"""Each class of bad input the CLI refuses is a ``catflip.CatflipError`` (a ``ValueError``) with
the CLI's message, word for word (its ``error: …`` line without the prefix); never a crash."""

import json
import warnings

import numpy as np
import pytest

import catflip
from conftest import PROBLEMS, cli_error

PAPER = "problems/paper.toml"


def refused(call) -> str:
    with pytest.raises(catflip.CatflipError) as e:
        call()
    assert isinstance(e.value, ValueError)
    return str(e.value)


def same_as_cli(cli, args, call):
    code, _, err = cli(*args)
    assert code != 0
    message = refused(call)
    assert message == cli_error(err)
    return message


@pytest.mark.parametrize(
    "text, says",
    [
        ("[cat]\nmas = 1.0\n", "unknown field `mas`"),  # unknown field
        ('[cat]\nmass = "heavy"\n', "invalid type"),  # wrong type
        ("[cat]\nmass = -1.0\n", "cat.mass = -1: must be positive"),  # out of range
        ("[manoeuvre]\nphases = [0.5, 0.6, 0.2]\n", "manoeuvre.phases"),  # out of range, a list
        ("[cat\nmass = 1.0\n", "unclosed table"),  # not TOML
    ],
)
def test_bad_problem_files(tmp_path, cli, text, says):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    message = same_as_cli(cli, ["simulate", str(path)], lambda: catflip.load(path))
    assert says in message
    # The same text as a string is refused for the same reason (named by its origin instead).
    assert refused(lambda: catflip.loads(text, origin=str(path))) == message


def test_bad_dict_value_names_the_field():
    assert refused(lambda: catflip.from_dict({"cat": {"mass": float("nan")}})) == "cat.mass = NaN: must be a finite number"


@pytest.mark.parametrize("override", ["cat.mass", "cat.mass=", "nosuch.field=1", "cat.mass=[1"])
def test_bad_overrides(cli, override):
    same_as_cli(cli, ["simulate", PAPER, "--set", override], lambda: catflip.load(PROBLEMS / "paper.toml", [override]))


def test_a_dict_override_is_written_as_toml(cli):
    same_as_cli(cli, ["simulate", PAPER, "--set", "cat.mass=-2.5"], lambda: catflip.load(PAPER, {"cat.mass": -2.5}))


def test_missing_file(cli):
    message = same_as_cli(cli, ["simulate", "problems/no-such.toml"], lambda: catflip.load("problems/no-such.toml"))
    assert "No such file" in message


def test_truncated_schedule(tmp_path, cli):
    path = tmp_path / "cut.csv"
    path.write_text("t,q1,q2\n0,0,0\n0.1,0.01,0\n0.2,0.02,0\n0.3,0.03\n")
    same_as_cli(cli, ["simulate", PAPER, "--schedule", str(path)], lambda: catflip.read_schedule(path))
    # Arrays of unequal lengths are refused naming the shorter (as a file they read as a row
    # with a field missing, which is the file's own refusal above).
    t = [0.0, 0.1, 0.2, 0.3]
    q = np.array([[0, 0], [0.01, 0], [0.02, 0], [0.03, 0]])
    message = refused(lambda: catflip.import_schedule(t, q[:3], name=str(path)))
    assert message == f"{path}: `q` has 3 rows and `t` 4: one row per time"


def test_not_finite_arrays_name_the_row_and_column():
    t = np.linspace(0, 1, 8)
    q = np.zeros((8, 2))
    q[3, 1] = np.inf
    assert refused(lambda: catflip.import_schedule(t, q)) == "<arrays>: line 5, column 3 (`q2`): inf is not finite"


def test_wrong_shape_is_refused():
    assert "shape (n, 2)" in refused(lambda: catflip.import_schedule([0, 1], [0, 1]))


@pytest.mark.parametrize("args, call", [(["optimize"], catflip.optimize)])
def test_spin_refused_by_optimize(cli, args, call):
    spin = "drop.angular_momentum=[0.0, 0.0, 0.01]"
    problem = catflip.load(PAPER, [spin])
    message = same_as_cli(cli, [args[0], PAPER, "--set", spin, *args[1:]], lambda: call(problem))
    assert "spin" in message


def test_spin_whole_optimum_series_refused_naming_the_argument():
    # `optimize --whole` plans a release with spin; its time series is the zero-momentum flip's:
    # asked for, it is refused before the solve, naming `series` (the library's refusal named
    # the CLI's files and told the user to remove the spin).
    problem = catflip.load(PAPER, ["drop.angular_momentum=[0.0, 0.0, 0.01]"])
    message = refused(lambda: catflip.optimize_whole(problem, series=True))
    assert message.startswith("series=True: the time series is the zero-momentum flip's") and "series=False" in message


def test_simulate_takes_a_spinning_release_by_default_as_the_cli_does(cli):
    # `catflip simulate` measures a release with spin; the package's default left the series in
    # and refused the call. Now the series is left out by default, and asked for, refused.
    spin = "drop.angular_momentum=[0.0, 0.0, 0.01]"
    problem = catflip.load(PAPER, [spin])
    m = catflip.simulate(problem)
    assert m.series is None
    code, out, err = cli("simulate", PAPER, "--set", spin, "--json")
    assert code == 0, err
    assert m.report["twist_deg"] == json.loads(out)["twist_deg"]
    assert "series=True" in refused(lambda: catflip.simulate(problem, series=True))


@pytest.mark.parametrize(
    "kwargs, says",
    [
        ({"rate_hz": "100"}, "rate_hz = '100': must be a finite, positive number of Hz"),
        ({"rate_hz": float("nan")}, "rate_hz = nan: must be a finite, positive number of Hz"),
        ({"steps_per_piece": -1}, "steps_per_piece = -1: must be a whole number of intervals"),
        ({"steps_per_piece": True}, "steps_per_piece = True: must be a whole number of intervals"),
        ({"steps_per_piece": 7, "rate_hz": 100.0}, "give one of them"),
    ],
)
def test_sampling_arguments_are_named_when_refused(kwargs, says):
    problem = catflip.load(PAPER)
    assert says in refused(lambda: catflip.simulate(problem, **kwargs))


def test_an_engine_that_is_not_one_is_named():
    problem = catflip.load(PAPER)
    assert refused(lambda: catflip.simulate(problem, None)) == 'engine = None: must be "exact" or "rapier"'


def test_sampling_beside_an_imported_schedule_is_refused():
    problem = catflip.load(PAPER)
    s = catflip.simulate(problem).series
    given = catflip.import_schedule(s.t, s.q, s.qd, s.qdd)
    message = refused(lambda: catflip.simulate(problem, schedule=given, rate_hz=-1, steps_per_piece=0))
    assert message.startswith("steps_per_piece = 0, rate_hz = -1: an imported schedule is measured as given"), message


def test_arrays_of_different_lengths_name_the_shorter():
    t = np.linspace(0.0, 1.0, 50)
    q = np.zeros((50, 2))
    assert "`q` has 50 rows and `t` 47: one row per time" in refused(lambda: catflip.import_schedule(t[:-3], q))
    assert "`qd` has 49 rows and `t` 50" in refused(lambda: catflip.import_schedule(t, q, q[:-1]))
    assert "`q` must hold numbers" in refused(lambda: catflip.import_schedule(t, [["a", "b"]] * 50))


def test_export_refuses_an_optimum_without_its_series_and_writes_nothing(tmp_path):
    problem = catflip.load(PAPER)
    whole = catflip.optimize_whole(problem, series=False)
    assert whole.solved
    out = tmp_path / "out"
    assert "solved without its time series" in refused(lambda: catflip.export(problem, out, optimum=whole))
    assert not out.exists()
    assert "steps_per_piece = 0" in refused(lambda: catflip.export(problem, out, steps_per_piece=0))
    assert not out.exists()


def test_a_frame_backend_that_is_not_one_is_named():
    assert "backend = 'numpy'" in refused(lambda: catflip.frame([{"a": 1}], backend="numpy"))


def test_unknown_engine():
    problem = catflip.load(PAPER)
    assert "not an engine" in refused(lambda: catflip.simulate(problem, "bullet"))


def test_gimbal_lock_refused(cli):
    args = ["--set", "manoeuvre.bend_path=cone", "--set", "manoeuvre.theta_deg=90"]
    message = same_as_cli(cli, ["simulate", PAPER, *args], lambda: catflip.simulate(catflip.load(PAPER, args[1::2])))
    assert "gimbal lock" in message


def test_bad_sweep_file(tmp_path, cli):
    path = tmp_path / "bad-sweep.toml"
    path.write_text(f'name = "x"\nbase = "{PROBLEMS / "paper.toml"}"\nbogus = 1\n')
    assert "unknown field `bogus`" in same_as_cli(cli, ["sweep", str(path)], lambda: catflip.sweep(path))


def test_missing_schedule_file(cli):
    same_as_cli(cli, ["simulate", PAPER, "--schedule", "no-such.csv"], lambda: catflip.read_schedule("no-such.csv"))


def test_still_usable_after_a_refusal():
    problem = catflip.load(PAPER)
    refused(lambda: catflip.load(PAPER, ["cat.mass=0"]))
    assert catflip.simulate(problem, series=False).report["engine"] == "exact"


@pytest.mark.parametrize(
    "args, call",
    [
        (["optimize", "problems/kane-scher.toml"], lambda p: catflip.optimize(p)),
    ],
)
def test_a_paper_only_computation_refuses_another_cat_naming_the_joint(cli, args, call):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        problem = catflip.load(PROBLEMS / "kane-scher.toml")
    message = same_as_cli(cli, args, lambda: call(problem))
    assert message.startswith('cat.joint = "no-twist"')


def test_rapier_verifies_the_no_twist_cat_and_its_files_are_a_ball_joint():
    """Rapier builds the no-twist joint (a ball joint); its model files are a ball joint in the
    MJCF and pyBullet's spherical joint in the URDF, and its schedule file adds the ball's
    columns."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", catflip.CatflipWarning)
        problem = catflip.load(PROBLEMS / "kane-scher.toml")
    assert catflip.verify(problem).report["verdict"] == "verified"
    files = catflip.model_files(problem)
    assert list(files) == ["model.urdf", "model.xml"] and 'type="ball"' in files["model.xml"]
    assert 'type="spherical"' in files["model.urdf"]
    header = catflip.schedule_series(problem).csv.splitlines()[0].split(",")
    assert header[-9:] == ["tauz_nm", "impulsez_nms", "rel_qw", "rel_qx", "rel_qy", "rel_qz",
                           "rel_wx_rad_s", "rel_wy_rad_s", "rel_wz_rad_s"]


def test_an_empty_problem_is_refused_as_the_cli_refuses_an_empty_file(tmp_path, cli):
    path = tmp_path / "empty.toml"
    path.write_text("# only a comment\n")
    message = same_as_cli(cli, ["simulate", str(path)], lambda: catflip.load(path))
    assert "holds no field" in message
    assert refused(lambda: catflip.loads("# only a comment\n", origin=str(path))) == message
    assert "holds no field" in refused(lambda: catflip.from_dict({}))
