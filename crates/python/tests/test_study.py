"""Studies: the same rows job by job whichever executor runs them; a failed job is recorded."""

from __future__ import annotations

import pytest
import rappel
from conftest import FIXTURES
from rappel import study


def jobs():
    js = [
        study.Job("plan", study.strip(12, seed, friction=mu), tags={"strip": seed, "mu": mu})
        for seed in (1, 2, 3)
        for mu in (0.2, 0.6)
    ]
    js.append(study.Job("plan", FIXTURES / "thesis-fig-2-7.ron", {"classes": 2}, tags={"strip": None}))
    js.append(study.Job("plan", FIXTURES / "no-such-file.ron", tags={"strip": None}))
    js.append(study.Job("stability", FIXTURES / "plan" / "multi-plane.ron", {"grid": 4.0}))
    js.append(study.Job("navigate", FIXTURES / "paton" / "ledge.ron", {"iterations": 50, "time": 600}, seed=3))
    return js


@pytest.fixture(scope="module")
def serial_rows():
    return study.run(jobs(), "serial")


def test_serial_rows(serial_rows):
    rows = serial_rows
    assert [r["job"] for r in rows] == list(range(len(rows)))
    failed = rows[7]
    assert not failed["ok"] and failed["error_type"] == "ScenarioError" and "no-such-file" in failed["error"]
    assert all(r["ok"] for i, r in enumerate(rows) if i != 7)
    # Each row's report is the report of the job run directly.
    direct = rappel.plan(study.strip(12, 2, friction=0.6).scenario())
    assert rows[3]["report"] == direct.to_dict()
    assert rows[3]["feasible"] == direct.feasible and rows[3]["mu"] == 0.6
    # Friction changes the plans: the sweep is not the same job six times.
    assert rows[0]["report"] != rows[1]["report"]
    assert rows[9]["seed"] == 3 and rows[9]["report"]["seed"] == 3


def test_processes_equal_serial(serial_rows):
    rows = study.run(jobs(), "processes", workers=2)
    assert study.strip_wall_clock(rows) == study.strip_wall_clock(serial_rows)


def test_unknown_executor_and_command():
    with pytest.raises(rappel.InputError):
        study.run([], "threads")
    rows = study.run([study.Job("fly", FIXTURES / "thesis-fig-2-7.ron")])
    assert rows[0]["error_type"] == "InputError"


def test_frame(serial_rows):
    pd = pytest.importorskip("pandas")
    df = study.to_frame(serial_rows)
    assert isinstance(df, pd.DataFrame) and len(df) == len(serial_rows)
    assert "report" not in df.columns and "feasible" in df.columns


def test_ray_equals_serial(serial_rows):
    ray = pytest.importorskip("ray")
    assert hasattr(ray, "remote"), f"`import ray` found {ray.__path__}, not Ray (run pytest outside /tmp)"
    try:
        rows = study.run(jobs(), "ray", ray_init={"num_cpus": 2, "include_dashboard": False})
    finally:
        ray.shutdown()
    assert study.strip_wall_clock(rows) == study.strip_wall_clock(serial_rows)
