"""Each binding against the CLI's ``--json`` on the same input, numpy round trips and
determinism."""

from __future__ import annotations

import json

import numpy as np
import pytest
import rappel
from conftest import FIXTURES, no_clock

PLAN_FIXTURES = sorted((FIXTURES / "plan").glob("*.ron")) + [FIXTURES / "thesis-fig-2-7.ron"]


@pytest.mark.parametrize("path", PLAN_FIXTURES, ids=lambda p: p.name)
def test_plan_equals_cli(cli, path):
    code, expected, _ = cli("plan", path)
    report = rappel.plan(path)
    assert report.to_dict() == expected
    # The exit code is the report's answer: 0 feasible, 1 a clean no.
    assert code == (0 if report.feasible else 1)
    # Convenience attributes agree with the dict.
    for c, d in zip(report.classes, expected["classes"]):
        assert c.points.dtype == np.float64 and c.points.shape == (len(d["points"]), 2)
        np.testing.assert_array_equal(c.points, np.asarray(d["points"]))
        assert c.length_m == d["length_m"]
    if expected["chosen"] is not None:
        np.testing.assert_array_equal(report.chosen.ascent, np.asarray(expected["chosen"]["ascent"]))


def test_plan_options_equal_cli(cli):
    path = FIXTURES / "thesis-fig-2-7.ron"
    _, expected, _ = cli("plan", path, "--classes", "3", "--simple-only", "--max-expansions", "500")
    got = rappel.plan(path, classes=3, simple_only=True, max_expansions=500)
    assert got.to_dict() == expected


def test_scenario_sources_agree():
    path = FIXTURES / "thesis-fig-2-7.ron"
    from_file = rappel.Scenario.load(path)
    d = from_file.to_dict()
    from_dict = rappel.Scenario.from_dict(d)
    assert from_dict.to_dict() == d
    from_arrays = rappel.Scenario.from_arrays(
        boundary=np.asarray(d["map"]["boundary"]),
        obstacles=[np.asarray(o) for o in d["map"]["obstacles"]],
        start=np.asarray(d["start"]),
        goal=d["goal"],
        planes=from_file.planes,
        robot=d["robot"],
        name=d["name"],
        description=d.get("description"),
    )
    assert from_arrays.to_dict() == d
    # The same plan whichever way the scenario came (the report names the scenario, not the file).
    assert rappel.plan(from_arrays).to_dict() == rappel.plan(from_file).to_dict()


def test_numpy_round_trip():
    boundary = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 20.0], [0.0, 20.0]])
    rock = np.array([[4.0, 8.0], [6.0, 8.0], [5.0, 10.0]])
    s = rappel.Scenario.from_arrays(boundary, start=(5, 19), goal=(5, 1), obstacles=[rock],
                                    planes=[(20, 0, 45, 0.4)])
    np.testing.assert_array_equal(s.boundary, boundary)
    np.testing.assert_array_equal(s.obstacles[0], rock)
    np.testing.assert_array_equal(s.planes, [[20, 0, 45, 0.4]])
    r = rappel.plan(s, time_limit=5.0)
    assert r.feasible and r.chosen is not None
    assert r.chosen.ascent.dtype == np.float64 and r.chosen.ascent.shape[1] == 2
    np.testing.assert_array_equal(r.chosen.ascent[0], [5, 1])  # the ascent starts at the goal
    # Pickling (how studies ship scenarios) keeps the scenario.
    import pickle

    assert pickle.loads(pickle.dumps(s)).to_dict() == s.to_dict()


def test_same_input_same_answer():
    s = rappel.generate.crater_strip(30, 7)
    a, b = rappel.plan(s), rappel.plan(s)
    assert a.to_json() == b.to_json()
    assert rappel.generate.crater_strip(30, 7).to_dict() == s.to_dict()
    assert rappel.generate.crater_strip(30, 8).to_dict() != s.to_dict()


def test_query_equals_cli(cli):
    map_path, pairs_path = FIXTURES / "thesis-fig-2-7.ron", FIXTURES / "queries" / "fig-2-7-pairs.json"
    code, expected, _ = cli("query", map_path, "--pairs", pairs_path, "--classes", "2")
    got = rappel.query(map_path, pairs_path, classes=2, errors="report")
    assert no_clock(got.to_dict()) == no_clock(expected)
    # Pairs as an (n, 4) array on a Scenario give the same answers.
    pairs = json.loads(pairs_path.read_text())
    arr = np.asarray([[*p["start"], *p["goal"]] for p in pairs])
    again = rappel.query(rappel.Scenario.load(map_path), arr, classes=2, errors="report")
    assert no_clock(again.to_dict()) == no_clock(expected)
    assert len(got.lengths) == len(pairs)
    assert code in (0, 1) if all(e is None for e in got.errors) else code == 2


def test_stability_equals_cli(cli):
    path = FIXTURES / "plan" / "multi-plane.ron"
    code, expected, _ = cli("stability", path, "--grid", "2")
    got = rappel.stability(path, grid=2.0)
    assert got.to_dict() == expected
    assert got.points.shape == (len(expected["dots"]), 2)
    assert int(got.stable.sum()) == expected["stable"]
    assert code == 0


def test_dem_file_and_array_equal_cli(cli, tmp_path):
    asc = FIXTURES / "terrain" / "mars_hirise_dteec_010228_1490_crop.asc"
    out = tmp_path / "dem.ron"
    code, expected, _ = cli("dem", asc, "--out", out)
    assert code == 0
    cli_scenario = rappel.Scenario.load(out).to_dict()
    out2 = tmp_path / "dem2.ron"
    got = rappel.dem(asc, out=out2)
    d = got.to_dict()
    assert d.pop("scenario") == str(out2)
    expected.pop("scenario")
    assert d == expected
    assert got.scenario.to_dict() == cli_scenario
    # The same grid as a numpy array with its geotransform: the same planes, counts, start, goal.
    header, heights = _read_asc(asc)
    gt = (header["xllcorner"], header["cellsize"], 0.0,
          header["yllcorner"] + header["nrows"] * header["cellsize"], 0.0, -header["cellsize"])
    arr = rappel.dem(heights, geotransform=gt, nodata=header.get("nodata_value"), name="crop")
    a = arr.to_dict()
    for key in ("planes", "counts", "start", "goal", "fall_line_azimuth_deg"):
        assert a[key] == expected[key], key
    s = arr.scenario.to_dict()
    assert s["map"] == cli_scenario["map"] and s["terrain"] == cli_scenario["terrain"]


def _read_asc(path):
    header = {}
    lines = path.read_text().split("\n")
    i = 0
    while lines[i].split() and lines[i].split()[0][0].isalpha():
        k, v = lines[i].split()[:2]
        header[k.lower()] = float(v)
        i += 1
    header["nrows"] = int(header["nrows"])
    values = np.asarray(" ".join(lines[i:]).split(), dtype=np.float64)
    h = values.reshape(header["nrows"], int(header["ncols"]))
    assert "xllcorner" in header, "this test reads corner-registered grids"
    return header, h


def test_settle_equals_cli(cli):
    scene = FIXTURES / "paton" / "ledge.ron"
    code, expected, _ = cli("settle", scene, "--at", "-1,0", "--yaw", "0")
    got = rappel.settle(scene, at=(-1, 0), yaw=0)
    assert got.to_dict() == expected
    assert got.contacts.shape[1] == 3
    assert code == 0


def test_settle_map_equals_cli(cli):
    scene = FIXTURES / "paton" / "ledge.ron"
    code, expected, _ = cli("settle-map", scene, "--test", "1", "--step", "1")
    got = rappel.settle_map(scene, test=1, step=1.0)
    assert no_clock(got.to_dict()) == no_clock(expected)
    assert got.stable.shape == (expected["ny"], expected["nx"])
    assert int(got.stable.sum()) == expected["stable"]


def test_navigate_equals_cli_and_is_seeded(cli):
    scene = FIXTURES / "paton" / "ledge.ron"
    code, expected, _ = cli("navigate", scene, "--seed", "2", "--iterations", "200", "--time", "600")
    got = rappel.navigate(scene, seed=2, iterations=200, time=600)
    assert no_clock(got.to_dict()) == no_clock(expected)
    again = rappel.navigate(scene, seed=2, iterations=200, time=600)
    assert no_clock(again.to_dict()) == no_clock(got.to_dict())
    assert got.path.shape[1] == 3


def test_track_equals_cli(cli):
    t = FIXTURES / "tracking"
    code, expected, _ = cli("track", t / "kumar.json", "--robot1", t / "robot1-fixed.json",
                            "--robot2", t / "robot2-descent.json")
    got = rappel.track(t / "kumar.json", t / "robot1-fixed.json", t / "robot2-descent.json")
    assert got.to_dict() == expected
    assert code == (0 if got.stable else 1)
    # Paths as arrays.
    p1 = np.asarray(json.loads((t / "robot1-fixed.json").read_text()), dtype=float)
    p2 = np.asarray(json.loads((t / "robot2-descent.json").read_text()), dtype=float)
    if p1.ndim == 2 and p2.ndim == 2:
        assert rappel.track(t / "kumar.json", p1, p2).to_dict() == expected


def test_online_equals_cli(cli):
    o = FIXTURES / "online"
    prior, truth = o / "case-1-blocked-flat.prior.ron", o / "case-1-blocked-flat.ron"
    code, expected, _ = cli("online", prior, "--truth", truth)
    got = rappel.online(prior, truth)
    assert no_clock(got.to_dict()) == no_clock(expected)
    assert code == (0 if got.reached else 1)


def test_help_tells_what_to_pass():
    doc = rappel.plan.__doc__
    for word in ("scenario", "classes", "time_limit", "cancel", "PlanReport", "Raises"):
        assert word in doc
    assert "(n, 2)" in rappel.Scenario.from_arrays.__doc__
