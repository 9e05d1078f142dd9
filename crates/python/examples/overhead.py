"""The engine's overhead per job: many tiny jobs (a plan on a four-vertex map, well under a
millisecond of planning) on each executor, wall time per job beside the serial executor's.

    python crates/python/examples/overhead.py --jobs 2000 --executors serial processes ray
"""

from __future__ import annotations

import argparse
import time

import rappel
from rappel import study

TINY = {
    "map": {"boundary": [[0, 0], [10, 0], [10, 20], [0, 20]], "obstacles": [[[4, 8], [6, 8], [5, 10]]]},
    "start": [5, 19],
    "goal": [5, 1],
    "terrain": {"planes": [{"y_top": 20, "y_bottom": 0, "slope_deg": 45, "friction": 0.4}]},
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=2000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--executors", nargs="+", default=["serial", "processes"])
    args = ap.parse_args()
    scenario = rappel.Scenario.from_dict(TINY)
    jobs = [study.Job("plan", scenario, {"classes": 1}, tags={"i": i}) for i in range(args.jobs)]
    base = None
    for name in args.executors:
        options = {}
        if name == "processes":
            options = {"workers": args.workers}
        if name == "ray":
            import ray

            ray.init(num_cpus=args.workers, include_dashboard=False)
            study.run(jobs[:10], "ray")  # workers started before the clock
        t0 = time.monotonic()
        rows = study.run(jobs, name, **options)
        per_job_ms = (time.monotonic() - t0) / len(jobs) * 1000
        assert all(r["ok"] for r in rows)
        if base is None:
            base = per_job_ms
        print(f"{name:10s} {per_job_ms:7.3f} ms a job (wall / jobs), serial {base:.3f} ms")
        if name == "ray":
            ray.shutdown()


if __name__ == "__main__":
    main()
