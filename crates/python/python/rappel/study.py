"""Monte Carlo studies: many independent jobs, one table of results, three executors.

A :class:`Job` is a scenario (or a scene file), a command (``"plan"``, ``"query"``,
``"stability"``, ``"navigate"``, ...), its keyword options and a seed, plus free ``tags`` that
become columns. :func:`run` runs a list of jobs on an executor and returns a list of dicts, one
per job in job order (and :func:`to_frame` makes a pandas DataFrame of it when pandas is
installed)::

    from rappel import study
    jobs = [study.Job("plan", study.strip(obstacles=20, seed=s), tags={"seed": s}) for s in range(100)]
    rows = study.run(jobs, executor="processes")      # or "serial", or "ray"

Executors, behind one interface (``executor=`` a name or an :class:`Executor`):

- ``"serial"``: one job after another in this process;
- ``"processes"``: a pool of local worker processes (``workers=``, default the CPU count);
- ``"ray"``: Ray tasks; ``ray.init()`` is called when Ray is not initialised yet, which connects
  to the cluster named by ``RAY_ADDRESS`` or starts a local one (``ray_init=`` passes arguments,
  e.g. ``{"num_cpus": 2}``). Ray is imported only then (``pip install ray``).

Results are identical job by job whichever executor runs them: a job's row depends only on the
job (planning is deterministic; sampling is seeded by the job's seed). The only fields that
differ between runs are wall-clock measurements, named in :data:`WALL_CLOCK_FIELDS`. A job
that fails records its error (``ok`` False, ``error``, ``error_type``) without stopping the
study.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

#: Report fields that are wall-clock measurements (differ between runs of the same job).
WALL_CLOCK_FIELDS = frozenset(
    {"median_ns", "first_solution_s", "elapsed_s", "elapsed_us", "wall_s", "time_us", "seconds"}
)


@dataclasses.dataclass
class Job:
    """One job of a study.

    Attributes:
        command: ``"plan"``, ``"query"``, ``"stability"``, ``"navigate"``, ``"settle"``,
            ``"settle_map"``, ``"track"``, ``"online"`` or ``"dem"`` (the functions of
            :mod:`rappel` of those names).
        scenario: what the command's first argument is: a :class:`rappel.Scenario`, a file
            path, a dict in the scenario schema, or a :class:`Strip` (generated on the worker).
        options: the command's keyword arguments (``classes=``, ``time_limit=``, ...).
        seed: the job's seed; passed as ``seed=`` to commands that take one (``navigate``).
        tags: free values copied into the job's row (the study's parameters).
    """

    command: str
    scenario: Any
    options: Dict[str, Any] = dataclasses.field(default_factory=dict)
    seed: Optional[int] = None
    tags: Dict[str, Any] = dataclasses.field(default_factory=dict)


@dataclasses.dataclass(frozen=True)
class Strip:
    """A generated crater strip (``rappel gen-map``), made on the worker from its seed, so a
    job travels as a few numbers. ``friction`` overrides the plane's wheel friction."""

    obstacles: int
    seed: int
    width: float = 200.0
    friction: Optional[float] = None

    def scenario(self) -> Any:
        """The strip as a :class:`rappel.Scenario`."""
        import rappel

        s = rappel.generate.crater_strip(self.obstacles, self.seed, width=self.width)
        if self.friction is None:
            return s
        d = s.to_dict()
        for p in d["terrain"]["planes"]:
            p["friction"] = self.friction
        return rappel.Scenario.from_dict(d)


def strip(obstacles: int, seed: int, width: float = 200.0, friction: Optional[float] = None) -> Strip:
    """A :class:`Strip` (a generated crater strip made on the worker)."""
    return Strip(obstacles, seed, width, friction)


def _summary(command: str, d: Dict[str, Any]) -> Dict[str, Any]:
    """A few columns of a report worth a table: deterministic values only."""
    if command == "plan":
        classes = d["classes"]
        chosen = d["chosen"]
        friction = d.get("friction")
        feasible = (friction or {}).get("chosen") is not None if friction is not None else chosen is not None
        return {
            "feasible": feasible,
            "classes": len(classes),
            "shortest_m": classes[0]["length_m"] if classes else None,
            "chosen_rank": None if chosen is None else chosen["rank"],
            "stop_reason": None if d.get("stop_reason") is None else d["stop_reason"]["kind"],
        }
    if command == "query":
        ans = d["answers"]
        return {
            "pairs": len(ans),
            "connected": sum(1 for a in ans if a["lengths_m"]),
            "errors": sum(1 for a in ans if a["error"] is not None),
        }
    if command == "stability":
        return {"stable": d["stable"], "assessed": d["assessed"]}
    if command == "navigate":
        return {k: d.get(k) for k in ("found", "cost", "stopped_by")}
    return {}


def run_job(job: Job) -> Dict[str, Any]:
    """Runs one job here and now and returns its row (never raises for the job's own errors)."""
    import rappel

    row: Dict[str, Any] = dict(job.tags)
    row.update({"command": job.command, "seed": job.seed})
    try:
        fn = getattr(rappel, job.command, None)
        if job.command not in COMMANDS or fn is None:
            raise rappel.InputError(
                f"command {job.command!r}: one of {', '.join(sorted(COMMANDS))}"
            )
        target = job.scenario.scenario() if isinstance(job.scenario, Strip) else job.scenario
        options = dict(job.options)
        if job.seed is not None and job.command in SEEDED:
            options.setdefault("seed", job.seed)
        result = fn(target, **options)
        report = result.report if hasattr(result, "report") and not hasattr(result, "to_json") else result
        d = report.to_dict()
        row.update({"ok": True, "error": None, "error_type": None})
        row.update(_summary(job.command, d))
        row["report"] = d
    except Exception as e:  # noqa: BLE001 - a failed job is recorded, the study goes on
        row.update({"ok": False, "error": str(e), "error_type": type(e).__name__, "report": None})
    return row


#: The commands a job may name.
COMMANDS = frozenset(
    {"plan", "query", "stability", "navigate", "settle", "settle_map", "track", "online", "dem"}
)
#: Commands that take ``seed=``.
SEEDED = frozenset({"navigate"})


class Executor:
    """Runs jobs: ``map(jobs)`` returns their rows in job order. Subclass to add an executor."""

    name = "executor"

    def map(self, jobs: Sequence[Job], progress: Optional[Callable[[int], None]] = None) -> List[Dict[str, Any]]:
        """The rows of ``jobs`` in order; ``progress(done)`` after each."""
        raise NotImplementedError


class Serial(Executor):
    """One job after another in this process."""

    name = "serial"

    def map(self, jobs, progress=None):
        rows = []
        for j in jobs:
            rows.append(run_job(j))
            if progress:
                progress(len(rows))
        return rows


class Processes(Executor):
    """A pool of local worker processes (``spawn``: no state inherited from the caller)."""

    name = "processes"

    def __init__(self, workers: Optional[int] = None, chunksize: Optional[int] = None) -> None:
        self.workers = workers or os.cpu_count() or 1
        self.chunksize = chunksize

    def map(self, jobs, progress=None):
        import concurrent.futures as cf
        import multiprocessing

        ctx = multiprocessing.get_context("spawn")
        chunk = self.chunksize or max(1, len(jobs) // (4 * self.workers))
        rows: List[Dict[str, Any]] = []
        with cf.ProcessPoolExecutor(max_workers=self.workers, mp_context=ctx) as pool:
            for row in pool.map(run_job, jobs, chunksize=chunk):
                rows.append(row)
                if progress:
                    progress(len(rows))
        return rows


class Ray(Executor):
    """Ray tasks, one per batch of jobs; ``ray.init(**ray_init)`` when Ray is not initialised
    (connecting to ``RAY_ADDRESS`` or starting a local instance)."""

    name = "ray"

    def __init__(self, ray_init: Optional[Dict[str, Any]] = None, batch: Optional[int] = None) -> None:
        self.ray_init = dict(ray_init or {})
        self.batch = batch

    def map(self, jobs, progress=None):
        try:
            import ray
        except ImportError as e:
            raise ImportError("the Ray executor needs Ray: pip install ray") from e
        if not hasattr(ray, "remote"):
            # A directory named `ray` on sys.path (Ray's own /tmp/ray session folder, when Python
            # runs from /tmp) imports as an empty namespace package.
            raise ImportError(f"`import ray` found {getattr(ray, '__path__', ray)}, not Ray: pip install ray")
        if not ray.is_initialized():
            ray.init(**self.ray_init)
        task = ray.remote(_run_batch)
        cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
        size = self.batch or max(1, len(jobs) // (4 * cpus))
        batches = [list(jobs[i : i + size]) for i in range(0, len(jobs), size)]
        refs = [task.remote(b) for b in batches]
        index = {r: i for i, r in enumerate(refs)}
        out: List[Optional[List[Dict[str, Any]]]] = [None] * len(refs)
        pending, done = list(refs), 0
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            for r in ready:
                out[index[r]] = ray.get(r)
                done += len(out[index[r]])
                if progress:
                    progress(done)
        return [row for b in out for row in b]


def _run_batch(jobs: List[Job]) -> List[Dict[str, Any]]:
    return [run_job(j) for j in jobs]


def executor(name: Union[str, Executor], **kwargs: Any) -> Executor:
    """The executor named ``"serial"``, ``"processes"`` or ``"ray"`` (keyword arguments go to
    its constructor), or ``name`` itself when it is an :class:`Executor`."""
    if isinstance(name, Executor):
        return name
    table = {"serial": Serial, "processes": Processes, "ray": Ray}
    if name not in table:
        import rappel

        raise rappel.InputError(f"executor {name!r}: 'serial', 'processes' or 'ray'")
    return table[name](**kwargs)


def _bar(total: int, stream=None) -> Callable[[int], None]:
    stream = stream or sys.stderr
    start = time.monotonic()

    def show(done: int) -> None:
        width = 30
        filled = int(width * done / max(total, 1))
        rate = done / max(time.monotonic() - start, 1e-9)
        end = "\n" if done >= total else "\r"
        stream.write(f"[{'#' * filled}{'.' * (width - filled)}] {done}/{total} jobs, {rate:.1f}/s{end}")
        stream.flush()

    return show


def run(
    jobs: Iterable[Job],
    executor: Union[str, Executor] = "serial",
    *,
    progress: Union[bool, Callable[[int], None]] = False,
    **executor_options: Any,
) -> List[Dict[str, Any]]:
    """Runs ``jobs`` on ``executor`` and returns one row (a dict) per job, in job order.

    Each row holds the job's ``tags``, ``command``, ``seed``, ``ok``, ``error``, ``error_type``,
    a few summary columns of its report (``feasible``, ``shortest_m``, ... for ``plan``) and the
    whole ``report`` as a dict (the CLI's ``--json``). ``progress=True`` draws a bar on stderr
    (or pass a callable taking the count of jobs done). ``executor_options`` go to the
    executor's constructor (``workers=`` for processes, ``ray_init=`` for Ray).
    """
    jobs = list(jobs)
    ex = globals()["executor"](executor, **executor_options)
    cb = _bar(len(jobs)) if progress is True else (progress or None)
    rows = ex.map(jobs, cb)
    for i, row in enumerate(rows):
        row["job"] = i
    return rows


def to_frame(rows: List[Dict[str, Any]], report: bool = False):
    """The rows as a pandas DataFrame (pandas needed); without the ``report`` column unless
    ``report`` is True."""
    import pandas as pd

    cols = [{k: v for k, v in r.items() if report or k != "report"} for r in rows]
    return pd.DataFrame(cols).set_index("job")


def strip_wall_clock(value: Any) -> Any:
    """``value`` with every :data:`WALL_CLOCK_FIELDS` entry removed, recursively: what two
    executors' rows must agree on."""
    if isinstance(value, dict):
        return {k: strip_wall_clock(v) for k, v in value.items() if k not in WALL_CLOCK_FIELDS}
    if isinstance(value, list):
        return [strip_wall_clock(v) for v in value]
    return value
