#!/usr/bin/env python3
"""OMPL's BIT* on the obstacle worlds of benches/ompl_peer/worlds (the peer of rappel's ABIT*).

Usage: python3 bitstar_peer.py WORLD.json [TIME_S] [RUNS] [SEED]

Reads the same JSON world as `cargo run --release -p rappel-benches --example sampler_peer --
anytime WORLD.json`, with the same validity semantics (closed boxes and balls, closed bounds,
OMPL's discrete motion validator at `resolution` times the bounds' diagonal), and prints per run
the time to the first solution, the state-validity checks made until then (counted in the
checker; the language-neutral effort measure) and the best cost at fixed times, in the same table.

Needs `pip install ompl` (the PyPI package, OMPL 2.x with nanobind bindings). The validity
checker is a Python callback, which OMPL calls through the bindings: its cost is part of the
peer's timings (see docs/sampler.md).
"""
import json
import math
import sys
import time

from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

CHECKPOINTS = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0]
KNOWN = {"name", "lo", "hi", "boxes", "spheres", "start", "goal", "resolution"}


def load(path):
    with open(path) as f:
        w = json.load(f)
    unknown = set(w) - KNOWN
    if unknown:
        raise SystemExit(f"error: {path}: unknown fields {sorted(unknown)}")
    return w


CHECKS = [0]


def make_checker(w):
    d = len(w["lo"])
    lo, hi = w["lo"], w["hi"]
    boxes = [(b["min"], b["max"]) for b in w.get("boxes", [])]
    spheres = [(s["centre"], s["radius"] ** 2) for s in w.get("spheres", [])]

    def valid(s):
        CHECKS[0] += 1
        p = [s[i] for i in range(d)]
        for i in range(d):
            if p[i] < lo[i] or p[i] > hi[i]:
                return False
        for mn, mx in boxes:
            if all(mn[i] <= p[i] <= mx[i] for i in range(d)):
                return False
        for c, r2 in spheres:
            if sum((p[i] - c[i]) ** 2 for i in range(d)) <= r2:
                return False
        return True

    return valid


def run_once(w, budget):
    d = len(w["lo"])
    space = ob.RealVectorStateSpace(d)
    bounds = ob.RealVectorBounds(d)
    for i in range(d):
        bounds.setLow(i, w["lo"][i])
        bounds.setHigh(i, w["hi"][i])
    space.setBounds(bounds)
    si = ob.SpaceInformation(space)
    si.setStateValidityChecker(make_checker(w))
    si.setStateValidityCheckingResolution(w["resolution"])
    si.setup()
    start, goal = space.allocState(), space.allocState()
    for i in range(d):
        start[i] = w["start"][i]
        goal[i] = w["goal"][i]
    pdef = ob.ProblemDefinition(si)
    pdef.setStartAndGoalStates(start, goal)
    pdef.setOptimizationObjective(ob.PathLengthOptimizationObjective(si))
    planner = og.BITstar(si)
    planner.setProblemDefinition(pdef)
    planner.setup()
    events = []
    CHECKS[0] = 0
    t0 = time.perf_counter()

    def stop():
        now = time.perf_counter() - t0
        c = planner.bestCost().value()
        if math.isfinite(c):
            if not events or c < events[-1][1]:
                events.append((now, c, CHECKS[0]))
        return now >= budget

    planner.solve(ob.PlannerTerminationCondition(stop))
    stop()
    return events


def main():
    if len(sys.argv) < 2:
        raise SystemExit("usage: bitstar_peer.py WORLD.json [TIME_S] [RUNS] [SEED]")
    w = load(sys.argv[1])
    budget = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 10
    ou.RNG.setSeed(int(sys.argv[4]) if len(sys.argv) > 4 else 1)
    ou.setLogLevel(ou.LogLevel.LOG_WARN)
    print("seed  first_s  checks_first  " + "  ".join(f"c@{t}s" for t in CHECKPOINTS))
    for run in range(runs):
        ev = run_once(w, budget)
        first = f"{ev[0][0]:.4f}" if ev else "-"
        checks = f"{ev[0][2]}" if ev else "-"
        cols = []
        for t in CHECKPOINTS:
            best = [c for (s, c, _) in ev if s <= t]
            cols.append(f"{best[-1]:.4f}" if best else "-")
        print(f"{run:4}  {first:>7}  {checks:>12}  " + "  ".join(cols))


if __name__ == "__main__":
    main()
