"""Exceptions: one class per concern, the CLI's ``error:`` message, never a panic."""

from __future__ import annotations

import numpy as np
import pytest
import rappel
from conftest import FIXTURES


def cli_error(stderr: str) -> str:
    lines = [l for l in stderr.splitlines() if l.startswith("error: ")]
    assert len(lines) == 1, stderr
    return lines[0][len("error: "):]


def test_hierarchy():
    for cls in (rappel.ScenarioError, rappel.InputError, rappel.PlanningError,
                rappel.BudgetExceeded, rappel.StoppedError, rappel.InternalError, rappel.NotSettled):
        assert issubclass(cls, rappel.RappelError) and issubclass(cls, Exception)
    assert len({rappel.ScenarioError, rappel.InputError, rappel.PlanningError,
                rappel.BudgetExceeded, rappel.StoppedError}) == 5


@pytest.mark.parametrize(
    "text",
    [
        # An unknown field.
        '(map: (boundary: [(0, 0), (10, 0), (10, 10), (0, 10)]), start: (5, 9), goal: (5, 1), colour: 3)',
        # An obstacle crossing the boundary.
        '(map: (boundary: [(0, 0), (10, 0), (10, 10), (0, 10)], obstacles: [[(8, 4), (12, 4), (10, 6)]]), start: (5, 9), goal: (5, 1))',
        # A start outside the map.
        '(map: (boundary: [(0, 0), (10, 0), (10, 10), (0, 10)]), start: (50, 9), goal: (5, 1))',
        # Not RON at all.
        'map = [1, 2',
    ],
)
def test_bad_scenario_file_same_message_as_cli(cli, tmp_path, text):
    path = tmp_path / "bad.ron"
    path.write_text(text)
    code, _, stderr = cli("plan", path)
    assert code == 2
    with pytest.raises(rappel.ScenarioError) as e:
        rappel.plan(path)
    assert str(e.value) == cli_error(stderr)
    with pytest.raises(rappel.ScenarioError):
        rappel.Scenario.load(path)


def test_bad_dicts_and_arrays():
    with pytest.raises(rappel.ScenarioError, match="colour"):
        rappel.Scenario.from_dict({"map": {"boundary": [[0, 0], [1, 0], [0, 1]]}, "start": [0.1, 0.1],
                                   "goal": [0.2, 0.2], "colour": 1})
    with pytest.raises(rappel.ScenarioError):
        rappel.Scenario.from_dict({"map": {"boundary": [[0, 0], [1, 0], [0, 1]]}})
    with pytest.raises(rappel.InputError, match=r"boundary: an \(n, 2\) array"):
        rappel.Scenario.from_arrays(np.zeros((4, 3)), start=(0, 0), goal=(1, 1))
    with pytest.raises(rappel.InputError, match="finite"):
        rappel.Scenario.from_arrays([[0, 0], [1, np.nan], [0, 1]], start=(0, 0), goal=(1, 1))
    with pytest.raises(rappel.InputError, match="planes"):
        rappel.Scenario.from_arrays([[0, 0], [10, 0], [0, 10]], start=(1, 1), goal=(2, 2), planes=[1, 2, 3])
    with pytest.raises(rappel.ScenarioError):
        rappel.Scenario.load(FIXTURES / "no-such-file.ron")
    with pytest.raises(rappel.InputError):
        rappel.plan(42)


def test_bad_options():
    s = FIXTURES / "thesis-fig-2-7.ron"
    with pytest.raises(rappel.InputError, match="classes=0"):
        rappel.plan(s, classes=0)
    with pytest.raises(rappel.InputError, match="at most 1000"):
        rappel.plan(s, classes=1001)
    with pytest.raises(rappel.InputError, match="time_limit=-1"):
        rappel.plan(s, time_limit=-1)
    with pytest.raises(rappel.InputError, match="time_limit=NaN"):
        rappel.plan(s, time_limit=float("nan"))
    with pytest.raises(rappel.InputError, match="max_expansions"):
        rappel.plan(s, max_expansions="lots")
    with pytest.raises(rappel.InputError, match="max_length_factor"):
        rappel.plan(s, max_length_factor=0.5)
    with pytest.raises(rappel.InputError, match="pairs"):
        rappel.query(s, np.zeros((3, 3)))
    with pytest.raises(rappel.InputError, match="geotransform"):
        rappel.dem(np.zeros((4, 4)))
    with pytest.raises(rappel.InputError, match="north-up"):
        rappel.dem(np.zeros((4, 4)), geotransform=(0, 1, 0, 0, 0, 1))
    with pytest.raises(rappel.InputError, match="robot"):
        rappel.settle(FIXTURES / "paton" / "ledge.ron", at=(0, 0), yaw=0, robot="tank")


def test_budget_exceeded_same_message_as_cli(cli):
    m, p = FIXTURES / "thesis-fig-2-7.ron", FIXTURES / "queries" / "fig-2-7-pairs.json"
    code, _, stderr = cli("query", m, "--pairs", p, "--max-expansions", "1")
    assert code == 2
    with pytest.raises(rappel.BudgetExceeded) as e:
        rappel.query(m, p, max_expansions=1)
    assert str(e.value) == cli_error(stderr)
    # The partial report travels with the exception, and errors="report" returns it.
    assert isinstance(e.value.report, rappel.QueryReport)
    r = rappel.query(m, p, max_expansions=1, errors="report")
    assert any(err is not None for err in r.errors)


def test_cancelled_query_is_stopped_error():
    flag = rappel.CancelFlag()
    flag.cancel()
    with pytest.raises(rappel.StoppedError, match="a cancel request"):
        rappel.query(FIXTURES / "thesis-fig-2-7.ron", FIXTURES / "queries" / "fig-2-7-pairs.json", cancel=flag)


def test_dem_errors_same_message_as_cli(cli, tmp_path):
    missing = tmp_path / "missing.asc"
    code, _, stderr = cli("dem", missing, "--out", tmp_path / "s.ron")
    assert code == 2
    with pytest.raises(rappel.PlanningError) as e:
        rappel.dem(missing, out=tmp_path / "s.ron")
    assert str(e.value) == cli_error(stderr)
    with pytest.raises(rappel.InputError, match="unknown scenario format"):
        rappel.dem(missing, out=tmp_path / "s.txt")


def test_not_settled_is_the_cli_s_no(tmp_path):
    import json
    import subprocess
    from conftest import _bin

    # Over the scene's edge: the wheels find no ground (the CLI's clean "no", exit 1).
    scene = FIXTURES / "paton" / "ledge.ron"
    args = [str(_bin()), "settle", str(scene), "--at", "17.7,19.9", "--yaw", "90"]
    p = subprocess.run(args, capture_output=True, text=True)
    assert p.returncode == 1
    with pytest.raises(rappel.NotSettled) as e:
        rappel.settle(scene, at=(17.7, 19.9), yaw=90)
    assert str(e.value) == p.stdout.strip()
    # --json says the same as a report.
    j = subprocess.run(args + ["--json"], capture_output=True, text=True)
    assert j.returncode == 1
    report = json.loads(j.stdout)
    assert report["report"] == "settle_not_settled"
    assert "not settled: " + report["reason"] == str(e.value)
    # Far off the ground is bad input in both (exit 2, InputError).
    far = subprocess.run(args[:3] + ["--at", "500,500", "--yaw", "0"], capture_output=True, text=True)
    assert far.returncode == 2 and "outside the ground" in far.stderr
    with pytest.raises(rappel.InputError, match="outside the ground"):
        rappel.settle(scene, at=(500, 500), yaw=0)
