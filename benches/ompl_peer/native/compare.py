#!/usr/bin/env python3
"""Summarises the native OMPL comparison (benches/ompl_peer/native.sh; docs/sampler.md).

Usage: compare.py ROWS.tsv

ROWS.tsv holds the rows of `sampler_peer native` (side rappel) and `ompl_peer run` (side ompl)
under one header. Prints, per world and planner (ABIT* against ABIT*, BIT* against BIT*), for
each side: runs solved, the median and quartiles of CPU time and of state checks to the first
solution, the median and quartiles of the batches sampled to the first solution, and the median
best cost at each CPU-time checkpoint; then the ratios rappel / OMPL of those medians, the
two-sided p-value of a Mann-Whitney U test of the checks to the first solution (normal
approximation with tie correction: are the two sides' distributions different, or are the
medians apart by seed luck?), and whether rappel meets the issue's goal on that row (no more
checks, no more CPU time to the first solution, no worse median cost at any checkpoint). A run
without a solution counts as infinite time, checks, batches and cost, so medians include
failures. Standard library only.
Exits 1 if a row is malformed, a side or a planner is missing, or a path check failed.
"""
import csv
import math
import sys

PLANNERS = [("abit", "ABIT*"), ("bit", "BIT*")]
SIDES = [("rappel", "rappel"), ("ompl", "OMPL")]


def quantile(xs, q):
    """Linear interpolation between order statistics (numpy's default); inf-safe."""
    xs = sorted(xs)
    pos = q * (len(xs) - 1)
    lo, hi = math.floor(pos), math.ceil(pos)
    if lo == hi or xs[lo] == xs[hi]:
        return xs[lo]
    if math.isinf(xs[hi]):
        return math.inf
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def num(s):
    return math.inf if s == "-" else float(s)


def fmt(x, digits=2):
    if math.isinf(x):
        return "-"
    if abs(x) >= 1000:
        return f"{x:,.0f}"
    return f"{x:.{digits}f}"


def mann_whitney_p(xs, ys):
    """Two-sided p-value of the Mann-Whitney U test, normal approximation with tie correction
    (infinite values rank last, tied with each other)."""
    n1, n2 = len(xs), len(ys)
    n = n1 + n2
    if n1 == 0 or n2 == 0:
        return math.nan
    pooled = sorted([(x, 0) for x in xs] + [(y, 1) for y in ys])
    r1, ties, i = 0.0, 0, 0
    while i < n:
        j = i
        while j < n and pooled[j][0] == pooled[i][0]:
            j += 1
        rank = (i + 1 + j) / 2  # average rank of positions i+1..j
        r1 += rank * sum(1 for t in range(i, j) if pooled[t][1] == 0)
        ties += (j - i) ** 3 - (j - i)
        i = j
    u = r1 - n1 * (n1 + 1) / 2
    var = n1 * n2 / 12 * ((n + 1) - ties / (n * (n - 1)))
    if var <= 0:
        return 1.0
    z = (u - n1 * n2 / 2) / math.sqrt(var)
    return math.erfc(abs(z) / math.sqrt(2))


def ratio(a, b):
    if math.isinf(a) and math.isinf(b):
        return "-"
    if math.isinf(a):
        return "inf"
    if math.isinf(b) or b == 0:
        return "0" if a == 0 else "-"
    return f"{a / b:.2f}"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: compare.py ROWS.tsv")
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    if not rows:
        sys.exit(f"error: {sys.argv[1]}: no rows")
    header = list(rows[0].keys())
    cps = [h for h in header if h.startswith("c@")]
    bad = [r for r in rows if r["path_check"] not in ("ok", "-")]
    for r in bad:
        print(f"PATH CHECK FAILED: {r['side']} {r['planner']} {r['world']} seed {r['seed']}: "
              f"{r['path_check']}")
    worlds = list(dict.fromkeys(r["world"] for r in rows))
    missing = False
    print(f"Medians [quartiles] over the seeds; a run without a solution counts as infinite ('-').")
    print(f"CPU time is process CPU time (clock_gettime(CLOCK_PROCESS_CPUTIME_ID)); cost is path length.\n")
    cols = ["planner", "side", "solved", "first-solution CPU ms", "checks to first",
            "batches to first"] + [
        f"cost {c[2:]}" for c in cps
    ]
    print("| world | " + " | ".join(cols) + " |")
    print("|---" * (len(cols) + 1) + "|")
    verdicts = []
    for w in worlds:
        for p, pname in PLANNERS:
            med = {}
            for s, sname in SIDES:
                rs = [r for r in rows if r["world"] == w and r["planner"] == p and r["side"] == s]
                if not rs:
                    print(f"error: no rows for {s} {p} on {w}", file=sys.stderr)
                    missing = True
                    continue
                solved = sum(r["solved"] == "yes" for r in rs)
                cpu = [num(r["first_cpu_ms"]) for r in rs]
                checks = [num(r["checks_first"]) for r in rs]
                batches = [num(r["batches_first"]) for r in rs]
                costs = [quantile([num(r[c]) for r in rs], 0.5) for c in cps]
                med[s] = (quantile(cpu, 0.5), quantile(checks, 0.5), costs, checks)
                q = lambda xs, d: (f"{fmt(quantile(xs, 0.5), d)} "
                                   f"[{fmt(quantile(xs, 0.25), d)}, {fmt(quantile(xs, 0.75), d)}]")
                print(f"| {w} | {pname} | {sname} | {solved}/{len(rs)} | {q(cpu, 2)} | {q(checks, 0)} | "
                      f"{q(batches, 0)} | "
                      + " | ".join(fmt(c, 3) for c in costs) + " |")
            if len(med) == 2:
                a, b = med["rappel"], med["ompl"]
                p_checks = mann_whitney_p(a[3], b[3])
                print(f"| {w} | {pname} | rappel / OMPL | | {ratio(a[0], b[0])} | {ratio(a[1], b[1])} "
                      f"(p {p_checks:.2f}) | | "
                      + " | ".join(ratio(x, y) for x, y in zip(a[2], b[2])) + " |")
                cost_ok = all(x <= y for x, y in zip(a[2], b[2]))
                verdicts.append((w, pname, a[1] <= b[1], a[0] <= b[0], cost_ok))
    print("\nThe issue's goal, per world (rappel against OMPL, same planner, medians):\n")
    print("| world | planner | checks to first <= OMPL | CPU to first <= OMPL | cost <= OMPL at every checkpoint |")
    print("|---|---|---|---|---|")
    yn = lambda b: "yes" if b else "**no**"
    for w, p, c, t, k in verdicts:
        print(f"| {w} | {p} | {yn(c)} | {yn(t)} | {yn(k)} |")
    if bad or missing:
        sys.exit(1)


if __name__ == "__main__":
    main()
