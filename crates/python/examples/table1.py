"""Paton's Table I over seeds (Paton §VI-A, test 1 on the ledge scene): the tethered rover planned
by ABIT* once per seed, on any executor. Prints the found fraction and the mean first-solution
iteration, and the wall time.

    python crates/python/examples/table1.py --executor ray --seeds 20
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from rappel import study

SCENE = Path(__file__).resolve().parents[3] / "fixtures" / "paton" / "ledge.ron"


def jobs(seeds: int, iterations: int):
    return [
        study.Job("navigate", str(SCENE), {"test": 1, "iterations": iterations, "time": 600}, seed=s,
                  tags={"test": 1})
        for s in range(seeds)
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--executor", default="serial", choices=["serial", "processes", "ray"])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--iterations", type=int, default=750)
    ap.add_argument("--check", action="store_true",
                    help="exit 1 unless every job ran and every seed found a path (Paton: 100 of 100)")
    args = ap.parse_args()
    options = {"ray_init": {"num_cpus": 2, "include_dashboard": False}} if args.executor == "ray" else {}
    t0 = time.monotonic()
    rows = study.run(jobs(args.seeds, args.iterations), args.executor, progress=True, **options)
    wall = time.monotonic() - t0
    ok = [r for r in rows if r["ok"]]
    found = [r for r in ok if r["found"]]
    firsts = [r["report"]["first_solution_iteration"] for r in found]
    print(f"Table I test 1: found {len(found)}/{len(rows)}, failed jobs {len(rows) - len(ok)}")
    if firsts:
        print(f"first solution after {statistics.mean(firsts):.1f} iterations (mean)")
    print(f"wall time {wall:.2f} s on the {args.executor} executor")
    if args.check and (len(ok) != len(rows) or len(found) != len(rows)):
        raise SystemExit(f"check failed: {len(found)} of {len(rows)} seeds found a path")


if __name__ == "__main__":
    main()
