"""rappel: motion planning for tethered (rappelling) robots, from Python.

Numpy in, numpy out. A :class:`Scenario` comes from a file, a dict in the scenario schema
(``docs/scenario-format.md``) or numpy arrays; each use case is one function returning a typed
report whose ``to_dict()`` equals the CLI's ``--json`` for the same input::

    import rappel
    s = rappel.Scenario.from_arrays(boundary=[[0, 0], [10, 0], [10, 20], [0, 20]],
                                    obstacles=[[[4, 8], [6, 8], [5, 10]]],
                                    start=(5, 19), goal=(5, 1), planes=[(20, 0, 45, 0.4)])
    r = rappel.plan(s, time_limit=1.0)
    print(r.verdict, r.chosen.ascent.shape)

Long calls release the GIL, take ``time_limit=`` (seconds) and ``cancel=`` (a
:class:`CancelFlag` another thread sets), and stop cleanly on Ctrl-C (``KeyboardInterrupt`` is
raised once the search has stopped). Errors are subclasses of :class:`RappelError` carrying the
CLI's ``error:`` message. Studies over many seeds: :mod:`rappel.study`.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, Iterable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import (
    BudgetExceeded,
    CancelFlag,
    InputError,
    InternalError,
    PlanningError,
    RappelError,
    ScenarioError,
    StoppedError,
)
from ._reports import (
    Anchor,
    ClassReport,
    DemReport,
    GenericReport,
    PairReport,
    PlanReport,
    QueryReport,
    Report,
    StabilityReport,
)

__version__: str = _native.__version__
SCHEMA_VERSION: int = _native.SCHEMA_VERSION

PathLike = Union[str, "os.PathLike[str]"]

__all__ = [
    "Anchor",
    "BudgetExceeded",
    "CancelFlag",
    "ClassReport",
    "DemReport",
    "DemResult",
    "GenericReport",
    "InputError",
    "InternalError",
    "PairReport",
    "PlanReport",
    "PlanningError",
    "QueryReport",
    "RappelError",
    "Report",
    "Scenario",
    "ScenarioError",
    "StabilityReport",
    "StoppedError",
    "dem",
    "plan",
    "query",
    "stability",
]


def _json_default(o: Any) -> Any:
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.generic):
        return o.item()
    raise TypeError(f"{type(o).__name__} is not a scenario value")


def _ring(name: str, a: Any) -> list:
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 3:
        raise InputError(f"{name}: an (n, 2) array of at least 3 points, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name}: every coordinate must be finite")
    return arr.tolist()


def _point(name: str, p: Any) -> list:
    arr = np.asarray(p, dtype=np.float64)
    if arr.shape != (2,):
        raise InputError(f"{name}: a point (x, y), got shape {arr.shape}")
    return arr.tolist()


class Scenario:
    """A planning scenario (``docs/scenario-format.md``), validated when made.

    Make one with :meth:`load` (a ``.ron`` or ``.json`` file), :meth:`from_dict` (the schema as a
    dict, numpy arrays allowed for point lists) or :meth:`from_arrays` (boundary and obstacles as
    ``(n, 2)`` arrays, planes as rows ``(y_top, y_bottom, slope_deg, friction)``). An invalid
    scenario raises :class:`ScenarioError` naming the field, vertex or line.
    """

    __slots__ = ("_native",)

    def __init__(self, native: "_native.Scenario") -> None:
        self._native = native

    @staticmethod
    def load(path: PathLike) -> "Scenario":
        """Reads and validates a scenario file (RON or JSON, by extension)."""
        return Scenario(_native.Scenario.load(os.fspath(path)))

    @staticmethod
    def from_dict(d: Dict[str, Any]) -> "Scenario":
        """A scenario from a dict with the file format's schema (points as ``[x, y]``; numpy
        arrays are accepted wherever a list of points is)."""
        try:
            text = json.dumps(d, default=_json_default)
        except (TypeError, ValueError) as e:
            raise ScenarioError(f"scenario dict: {e}") from None
        return Scenario(_native.Scenario.from_json(text))

    @staticmethod
    def from_json(text: str) -> "Scenario":
        """A scenario from JSON text (the file format)."""
        return Scenario(_native.Scenario.from_json(text))

    @staticmethod
    def from_ron(text: str) -> "Scenario":
        """A scenario from RON text (the file format)."""
        return Scenario(_native.Scenario.from_ron(text))

    @staticmethod
    def from_arrays(
        boundary: Any,
        start: Sequence[float],
        goal: Sequence[float],
        obstacles: Iterable[Any] = (),
        planes: Any = (),
        robot: Optional[Dict[str, Any]] = None,
        name: str = "",
        description: Optional[str] = None,
    ) -> "Scenario":
        """A scenario from numpy arrays.

        - ``boundary``: ``(n, 2)`` float array, the outer boundary (either orientation);
        - ``obstacles``: a sequence of ``(m, 2)`` arrays, the tether obstacles;
        - ``start``, ``goal``: points ``(x, y)`` in the unfolded frame (``y`` up the slope);
        - ``planes``: a ``(k, 4)`` array or rows ``(y_top, y_bottom, slope_deg, friction)``, top first;
        - ``robot``: the ``robot`` section as a dict (``model``, ``mass_kg``, ``tether_length_m``,
          ``clearance_m``), defaults when None.
        """
        d: Dict[str, Any] = {
            "name": name,
            "map": {
                "boundary": _ring("boundary", boundary),
                "obstacles": [_ring(f"obstacles[{i}]", o) for i, o in enumerate(obstacles)],
            },
            "start": _point("start", start),
            "goal": _point("goal", goal),
        }
        if description is not None:
            d["description"] = description
        rows = np.asarray(planes, dtype=np.float64)
        if rows.size:
            if rows.ndim != 2 or rows.shape[1] != 4:
                raise InputError(
                    f"planes: a (k, 4) array of y_top, y_bottom, slope_deg, friction, got shape {rows.shape}"
                )
            d["terrain"] = {
                "planes": [
                    {"y_top": r[0], "y_bottom": r[1], "slope_deg": r[2], "friction": r[3]}
                    for r in rows.tolist()
                ]
            }
        if robot is not None:
            d["robot"] = dict(robot)
        return Scenario.from_dict(d)

    def to_dict(self) -> Dict[str, Any]:
        """The scenario in the file format's schema, as a dict."""
        return json.loads(self._native.to_json())

    def to_json(self) -> str:
        """The scenario as JSON text (the file format)."""
        return self._native.to_json()

    def to_ron(self) -> str:
        """The scenario as RON text (the file format)."""
        return self._native.to_ron()

    def save(self, path: PathLike) -> None:
        """Writes the scenario (format by extension), atomically."""
        self._native.save(os.fspath(path))

    @property
    def name(self) -> str:
        """The scenario's name."""
        return self._native.name

    @property
    def path(self) -> Optional[str]:
        """The file the scenario was read from, or None."""
        p = self._native.path
        return None if p is None else str(p)

    @property
    def boundary(self) -> np.ndarray:
        """The map boundary as an ``(n, 2)`` float64 array."""
        return np.asarray(self.to_dict()["map"]["boundary"], dtype=np.float64)

    @property
    def obstacles(self) -> list:
        """The obstacles, each an ``(m, 2)`` float64 array."""
        return [np.asarray(o, dtype=np.float64) for o in self.to_dict()["map"]["obstacles"]]

    @property
    def planes(self) -> np.ndarray:
        """The terrain planes as a ``(k, 4)`` array: ``y_top, y_bottom, slope_deg, friction``."""
        ps = self.to_dict().get("terrain", {}).get("planes", [])
        return np.asarray(
            [[p["y_top"], p["y_bottom"], p["slope_deg"], p["friction"]] for p in ps], dtype=np.float64
        ).reshape(-1, 4)

    def __repr__(self) -> str:
        return repr(self._native)

    def __reduce__(self):
        # Pickled as its JSON text (and its path, so messages keep naming the file): scenarios
        # travel to worker processes and Ray tasks.
        return (_scenario_from_pickle, (self.to_json(), self.path))


def _scenario_from_pickle(text: str, path: Optional[str]) -> Scenario:
    if path is not None and os.path.exists(path):
        try:
            s = Scenario.load(path)
            if s.to_json() == text:
                return s
        except RappelError:
            pass
    return Scenario.from_json(text)


ScenarioLike = Union[Scenario, PathLike, Dict[str, Any]]


def as_scenario(s: ScenarioLike) -> Scenario:
    """A :class:`Scenario` from a scenario, a file path or a dict."""
    if isinstance(s, Scenario):
        return s
    if isinstance(s, dict):
        return Scenario.from_dict(s)
    if isinstance(s, (str, os.PathLike)):
        return Scenario.load(s)
    raise InputError(f"a Scenario, a scenario file path or a dict, not {type(s).__name__}")


def _budget(max_expansions: Union[int, str]) -> str:
    if isinstance(max_expansions, bool):
        raise InputError("max_expansions: 'auto' or a positive number")
    return str(max_expansions)


def plan(
    scenario: ScenarioLike,
    *,
    classes: int = 5,
    max_length_factor: Optional[float] = None,
    simple_only: bool = False,
    max_expansions: Union[int, str] = "auto",
    time_limit: Optional[float] = None,
    cancel: Optional[CancelFlag] = None,
    reachable_areas: bool = False,
) -> PlanReport:
    """Plans a tethered descent (thesis Ch. 2): homotopy classes shortest first, ascent
    feasibility, and the chosen ascent/descent pair. ``rappel plan FILE --json``.

    Args:
        scenario: a :class:`Scenario`, a scenario file path, or a dict in the scenario schema.
        classes: how many homotopy classes to list, shortest first (1 to 1000).
        max_length_factor: list only classes at most this factor longer than the shortest (>= 1).
        simple_only: list only simple classes (no tether winds around an obstacle).
        max_expansions: the funnel expansion budget, ``"auto"`` (scaled to the map) or a count.
        time_limit: stop the whole plan after this many seconds; the report says so.
        cancel: a :class:`CancelFlag`; setting it from another thread stops the search.
        reachable_areas: report each anchor reachable set's area (a polygon overlay per anchor).

    Returns:
        A :class:`PlanReport`: ``classes`` (each with ``points``, an ``(n, 2)`` array),
        ``chosen`` (ascent and descent arrays), ``feasible``, ``verdict``, ``stop_reason``.
        A scenario without a feasible class is an answer (``feasible`` False), not an error.

    Raises:
        ScenarioError: the scenario is invalid. InputError: an option is out of range.
        PlanningError: the map does not triangulate or the planes or robot are unusable.
        KeyboardInterrupt: Ctrl-C, after the search has stopped cleanly.
    """
    s = as_scenario(scenario)
    text = _native.plan(
        s._native,
        int(classes),
        max_length_factor,
        bool(simple_only),
        _budget(max_expansions),
        time_limit,
        cancel,
        bool(reachable_areas),
    )
    return PlanReport(text)


def _pairs_array(pairs: Any) -> list:
    a = np.asarray(pairs, dtype=np.float64)
    if a.ndim == 3 and a.shape[1:] == (2, 2):
        a = a.reshape(-1, 4)
    if a.ndim != 2 or a.shape[1] != 4:
        raise InputError(
            f"pairs: an (n, 4) array of start x, start y, goal x, goal y (or (n, 2, 2)), got shape {a.shape}"
        )
    return a.reshape(-1).tolist()


def query(
    map: Union[Scenario, PathLike, Dict[str, Any]],
    pairs: Any,
    *,
    classes: int = 1,
    repeat: int = 1,
    max_expansions: Union[int, str] = "auto",
    time_limit: Optional[float] = None,
    cancel: Optional[CancelFlag] = None,
    errors: str = "raise",
) -> QueryReport:
    """Many start/goal pairs on one map, the BTM built once: each pair's shortest length (or
    its ``classes`` shortest classes) and the median time of its query. ``rappel query MAP
    --pairs PAIRS --json``.

    Args:
        map: a :class:`Scenario`, a dict, or a scenario or map-only file path.
        pairs: an ``(n, 4)`` array ``[sx, sy, gx, gy]`` (or ``(n, 2, 2)``), or a pairs file path.
        classes: classes per pair (1 to 100). repeat: runs per query (median time reported).
        max_expansions, time_limit, cancel: as for :func:`plan`.
        errors: ``"raise"`` (the default, as the CLI exits 2) raises the first pair's error
            (:class:`BudgetExceeded` for a spent budget, :class:`StoppedError` for a time limit or
            cancel, :class:`InputError` otherwise) with the report as ``.report``; ``"report"``
            returns the report with each pair's ``error``.
    """
    if errors not in ("raise", "report"):
        raise InputError(f"errors={errors!r}: 'raise' or 'report'")
    scenario = None
    map_path = None
    if isinstance(map, (str, os.PathLike)):
        map_path = os.fspath(map)
    else:
        scenario = as_scenario(map)._native
    if isinstance(pairs, (str, os.PathLike)):
        flat, pairs_path = None, os.fspath(pairs)
    else:
        flat, pairs_path = _pairs_array(pairs), None
    text = _native.query(
        scenario,
        map_path,
        flat,
        pairs_path,
        int(classes),
        int(repeat),
        _budget(max_expansions),
        time_limit,
        cancel,
    )
    report = QueryReport(text)
    if errors == "raise":
        for a in report.answers:
            if a["error"] is not None:
                kind = (a.get("stop_reason") or {}).get("kind")
                cls = {
                    "expansions": BudgetExceeded,
                    "time_limit": StoppedError,
                    "cancelled": StoppedError,
                }.get(kind, InputError)
                e = cls(a["error"])
                e.report = report
                raise e
    return report


def stability(
    scenario: ScenarioLike,
    *,
    grid: float = 1.0,
    tension_limit: Optional[float] = None,
    time_limit: Optional[float] = None,
    cancel: Optional[CancelFlag] = None,
) -> StabilityReport:
    """Where the robot can stand on the scenario's planes (Kumar Fig. 5): the wheel/tether QP,
    or the tension-limited LP with ``tension_limit`` (N). ``rappel stability FILE --json``.

    Args:
        scenario: a :class:`Scenario`, a file path or a dict; it needs terrain planes.
        grid: the grid step of the poses, m.
        tension_limit: judge with the tension-limited LP at this tether tension, N.
        time_limit, cancel: as for :func:`plan`; a stopped map is partial (``stopped_by``).
    """
    s = as_scenario(scenario)
    return StabilityReport(
        _native.stability(s._native, float(grid), tension_limit, time_limit, cancel)
    )


class DemResult:
    """What :func:`dem` returns: the ``report`` (:class:`DemReport`, the CLI's ``rappel dem
    --json``) and the ingested ``scenario`` (:class:`Scenario`)."""

    def __init__(self, report: DemReport, scenario: Scenario) -> None:
        self.report = report
        self.scenario = scenario

    def to_dict(self) -> Dict[str, Any]:
        """The report's dict."""
        return self.report.to_dict()

    def __repr__(self) -> str:
        return f"DemResult({self.scenario!r})"


def _geotransform(gt: Any) -> Tuple[float, float, float, float]:
    """``(cell_x, cell_y, west, north)`` of a north-up geotransform: GDAL's 6-tuple
    ``(x0, dx, 0, y0, 0, dy)`` with ``dy < 0``, or a rasterio/affine ``Affine``."""
    if hasattr(gt, "to_gdal"):
        gt = gt.to_gdal()
    t = [float(v) for v in gt]
    if len(t) != 6:
        raise InputError(f"geotransform: GDAL's 6 numbers (x0, dx, 0, y0, 0, dy), got {len(t)}")
    x0, dx, r1, y0, r2, dy = t
    if r1 != 0.0 or r2 != 0.0:
        raise InputError("geotransform: a rotated grid is not supported (its rotation terms must be 0)")
    if not (dx > 0.0 and dy < 0.0):
        raise InputError(
            f"geotransform: a north-up grid needs dx > 0 and dy < 0, got dx {dx}, dy {dy}"
        )
    return dx, -dy, x0, y0


def dem(
    source: Union[PathLike, np.ndarray],
    *,
    geotransform: Any = None,
    name: str = "dem",
    crs: Optional[str] = None,
    nodata: Optional[float] = None,
    out: Optional[PathLike] = None,
    hmin: Optional[float] = None,
    hmax: Optional[float] = None,
    theta_max: Optional[float] = None,
    friction: Optional[float] = None,
    max_cells: Optional[int] = None,
) -> DemResult:
    """Turns a digital elevation model into a planning scenario (thesis §2.1.2-2.1.3, §2.5.2).
    ``rappel dem FILE --out OUT --json``.

    Args:
        source: a DEM file (``.asc`` or ``.tif``), or a 2-D numpy height array (rows north to
            south, as rasterio reads them; NaN or ``nodata`` = unknown).
        geotransform: for an array: GDAL's ``(x0, dx, 0, y0, 0, dy)`` or a rasterio ``Affine``
            (``dataset.transform``), north-up.
        name: for an array: names it in messages and as the scenario's name.
        crs: for an array: its coordinate reference system (kept in the georeference).
        nodata: for an array: the value that means unknown.
        out: also save the scenario here (``.ron`` or ``.json``); the report names it.
        hmin, hmax, theta_max, friction: the ingest's obstacle heights (m), obstacle slope
            (degrees) and wheel friction, as ``--hmin`` etc.
        max_cells: the readers' cell cap (files only).
    """
    outp = None if out is None else os.fspath(out)
    if isinstance(source, (str, os.PathLike)):
        text, native = _native.dem_file(
            os.fspath(source), outp, hmin, hmax, theta_max, friction, max_cells
        )
    else:
        h = np.array(source, dtype=np.float64)
        if h.ndim != 2:
            raise InputError(f"heights: a 2-D array (rows north to south), got {h.ndim} dimensions")
        if geotransform is None:
            raise InputError("geotransform: needed with a height array (GDAL's 6 numbers or an Affine)")
        if max_cells is not None:
            raise InputError("max_cells: for DEM files; an array is already in memory")
        if nodata is not None:
            h[h == nodata] = np.nan
        cell_x, cell_y, west, north = _geotransform(geotransform)
        text, native = _native.dem_grid(
            np.ascontiguousarray(h, dtype="<f8").tobytes(),
            h.shape[0],
            h.shape[1],
            cell_x,
            cell_y,
            west,
            north,
            name,
            crs,
            outp,
            hmin,
            hmax,
            theta_max,
            friction,
        )
    return DemResult(DemReport(text), Scenario(native))


from ._native import NotSettled  # noqa: E402
from ._reports import (  # noqa: E402
    NavigateReport,
    OnlineReport,
    SettleMapReport,
    SettleReport,
    TrackReport,
)
from . import generate  # noqa: E402

__all__ += [
    "NavigateReport",
    "NotSettled",
    "OnlineReport",
    "SettleMapReport",
    "SettleReport",
    "TrackReport",
    "generate",
    "navigate",
    "online",
    "settle",
    "settle_map",
    "track",
]


def _pair(name: str, v: Any, n: int) -> Optional[tuple]:
    if v is None:
        return None
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (n,):
        raise InputError(f"{name}: {n} numbers, got {a.size}")
    return tuple(float(x) for x in a)


def settle(
    ground: PathLike,
    at: Sequence[float],
    yaw: float,
    *,
    robot: str = "axel",
    anchor: Optional[Sequence[float]] = None,
    field: Optional[float] = None,
) -> SettleReport:
    """Settles Axel (or ``robot="four-wheel"``) on 3D ground at ground point ``at`` = ``(x, y)``
    heading ``yaw`` degrees (Paton §IV-A). ``rappel settle FILE --at X,Y --yaw DEG --json``.

    Args:
        ground: a Paton scene (``.ron``) or a DEM (``.asc``/``.tif``) or a mesh file.
        anchor: the tether's anchor ``(x, y, z)``: the report then judges stability.
        field: settle through the ground's sparse distance field at this resolution, m.

    Raises:
        NotSettled: the robot does not settle there (the CLI's ``not settled: ...``, exit 1).
    """
    return SettleReport(
        _native.settle(
            os.fspath(ground), _pair("at", at, 2), float(yaw), robot, _pair("anchor", anchor, 3), field
        )
    )


def settle_map(
    ground: PathLike,
    *,
    x: Optional[Sequence[float]] = None,
    y: Optional[Sequence[float]] = None,
    step: float = 0.25,
    yaw: float = 0.0,
    start: Optional[Sequence[float]] = None,
    root: Optional[Sequence[float]] = None,
    test: Optional[int] = None,
    robot: str = "axel",
    field: Optional[float] = None,
    time_limit: Optional[float] = None,
    cancel: Optional[CancelFlag] = None,
) -> SettleMapReport:
    """A stability map of settled poses with predicted anchor histories (Paton Fig. 8).
    ``rappel settle-map FILE --json``. The report's ``stable``, ``margin`` and ``settled`` are
    2-D arrays of shape ``(ny, nx)``.

    Args:
        ground: a Paton scene (``.ron``; the ranges, start and tests default to the scene's) or a
            DEM (then ``x``, ``y``, ``start`` and ``root`` are needed).
        x, y: the ranges ``(min, max)``. step: the grid step, m. yaw: the heading, degrees.
        start: where the tether's shortest paths start. root: the root anchor ``(x, y, z)``, or
        test: the scene's test ``N`` (its anchor).
        time_limit, cancel: as for :func:`plan`; a stopped map is partial (``stopped_by``).
    """
    return SettleMapReport(
        _native.settle_map(
            os.fspath(ground),
            _pair("x", x, 2),
            _pair("y", y, 2),
            float(step),
            float(yaw),
            _pair("start", start, 2),
            _pair("root", root, 3),
            test,
            robot,
            field,
            time_limit,
            cancel,
        )
    )


def navigate(
    scene: PathLike,
    *,
    seed: int,
    test: int = 1,
    iterations: int = 1000,
    time: Optional[float] = None,
    held: bool = False,
    shadow: bool = False,
    field: Optional[float] = None,
    time_limit: Optional[float] = None,
    cancel: Optional[CancelFlag] = None,
) -> NavigateReport:
    """Plans the tethered rover's path on a Paton scene with ABIT* (Paton §V-VI).
    ``rappel navigate SCENE --seed S --json``. The same seed gives the same path (when the
    iteration limit, not the ``time`` budget, ends the search).

    Args:
        scene: a Paton scene file (``.ron``). seed: the sampler's seed.
        test: the scene's test ``N`` (its anchor). iterations: the sampler's iteration limit.
        time: the sampler's own time budget, s. held: keep the tether within the boom's reach.
        shadow: sample in the tether's shadow. field: distances through the sparse field, m.
        time_limit, cancel: as for :func:`plan`.
    """
    return NavigateReport(
        _native.navigate(
            os.fspath(scene), int(seed), int(test), int(iterations), time, bool(held), bool(shadow),
            field, time_limit, cancel,
        )
    )


def _path_arg(name: str, v: Any):
    if isinstance(v, (str, os.PathLike)):
        return os.fspath(v), None
    a = np.asarray(v, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 2:
        raise InputError(f"{name}: an (n, 2) array or a path file, got shape {a.shape}")
    return None, [tuple(r) for r in a.tolist()]


def track(scenario: PathLike, robot1: Any, robot2: Any) -> TrackReport:
    """Two robots on one tether on multi-slope terrain: tether tracking and Robot 2's stability
    (Kumar). ``rappel track SCENARIO --robot1 P1 --robot2 P2 --json``.

    Args:
        scenario: the multi-slope terrain file (JSON, ``fixtures/tracking``).
        robot1, robot2: each robot's path, an ``(n, 2)`` array or a path file (JSON).
    """
    f1, p1 = _path_arg("robot1", robot1)
    f2, p2 = _path_arg("robot2", robot2)
    return TrackReport(_native.track(os.fspath(scenario), f1, p1, f2, p2))


def online(
    prior: ScenarioLike,
    truth: ScenarioLike,
    *,
    sensor_range: Optional[float] = None,
    step: Optional[float] = None,
    max_steps: Optional[int] = None,
    classes: Optional[int] = None,
    switch_to_shorter: bool = False,
    time_limit: Optional[float] = None,
    cancel: Optional[CancelFlag] = None,
) -> OnlineReport:
    """Online planning (thesis §3.5, online paper §III): descend by the prior map's plan while
    the true map is discovered. ``rappel online PRIOR --truth TRUE --json``.

    Args:
        prior, truth: scenarios (objects, files or dicts) with the same start, goal, terrain and robot.
        sensor_range, step, max_steps, classes: the simulation's options (the CLI's defaults when None).
        switch_to_shorter: switch to a shorter class when one opens.
        time_limit, cancel: as for :func:`plan`.
    """
    return OnlineReport(
        _native.online(
            as_scenario(prior)._native,
            as_scenario(truth)._native,
            sensor_range,
            step,
            max_steps,
            classes,
            bool(switch_to_shorter),
            time_limit,
            cancel,
        )
    )
