"""A sweep of ``plan`` over generated crater strips and wheel friction coefficients, on any
executor: the feasible fraction per friction coefficient.

    python crates/python/examples/strip_sweep.py --executor processes --seeds 50
"""

from __future__ import annotations

import argparse
import time
from collections import defaultdict

from rappel import study


def jobs(seeds: int, obstacles: int, frictions):
    return [
        study.Job("plan", study.strip(obstacles, seed, friction=mu), {"classes": 3},
                  tags={"strip": seed, "mu": mu})
        for seed in range(seeds)
        for mu in frictions
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--executor", default="serial", choices=["serial", "processes", "ray"])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--obstacles", type=int, default=50)
    ap.add_argument("--friction", type=float, nargs="+", default=[0.2, 0.4, 0.6, 0.8])
    ap.add_argument("--check", action="store_true",
                    help="exit 1 unless every job ran and feasibility never falls as friction rises")
    args = ap.parse_args()
    options = {"ray_init": {"num_cpus": 2, "include_dashboard": False}} if args.executor == "ray" else {}
    t0 = time.monotonic()
    rows = study.run(jobs(args.seeds, args.obstacles, args.friction), args.executor, progress=True, **options)
    wall = time.monotonic() - t0
    by_mu = defaultdict(list)
    for r in rows:
        by_mu[r["mu"]].append(bool(r.get("feasible")))
    for mu, f in sorted(by_mu.items()):
        print(f"mu {mu:.2f}: feasible {sum(f)}/{len(f)}")
    print(f"{len(rows)} jobs, wall time {wall:.2f} s on the {args.executor} executor")
    if args.check:
        failed = [r for r in rows if not r["ok"]]
        counts = [sum(f) for _, f in sorted(by_mu.items())]
        # More wheel friction widens every friction cone: a class feasible at mu stays feasible.
        if failed or counts != sorted(counts):
            raise SystemExit(f"check failed: {len(failed)} failed jobs, feasible counts {counts}")


if __name__ == "__main__":
    main()
