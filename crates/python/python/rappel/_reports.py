"""Typed reports over the facade's JSON.

Every report object keeps the exact text the Rust facade produced with ``to_json()`` (the CLI's
``--json`` for the same input); ``to_dict()`` parses that text afresh, so the two cannot drift.
The attributes are conveniences over the same data: points as ``(n, 2)`` float64 numpy arrays,
lengths as floats; typed reasons (a class's verdict, an anchor's passability) as the JSON's dicts tagged by ``kind``.
"""

from __future__ import annotations

import functools
import json
from typing import Any, Dict, List, Optional

import numpy as np


def points(rows: Any) -> np.ndarray:
    """A list of ``[x, y]`` (or ``[x, y, z]``) as a float64 array of shape ``(n, 2)`` (or ``(n, 3)``)."""
    a = np.asarray(rows if rows else [], dtype=np.float64)
    if a.size == 0:
        return np.zeros((0, 2), dtype=np.float64)
    return a


class Report:
    """A report of one use case: ``to_dict()`` is ``json.loads`` of the CLI's ``--json``."""

    kind = ""

    def __init__(self, text: str) -> None:
        self._json = text
        self._parsed: Optional[Dict[str, Any]] = None

    @property
    def _data(self) -> Dict[str, Any]:
        # Parsed on first use: a plan of a thousand classes on a large map is tens of megabytes
        # of JSON, and a caller who only wanted `to_json()` should not wait for it.
        if self._parsed is None:
            d = json.loads(self._json)
            if self.kind and d.get("report") != self.kind:
                raise ValueError(f"not a {self.kind} report: {d.get('report')!r}")
            self._parsed = d
        return self._parsed

    def to_json(self) -> str:
        """The report as the CLI's ``--json`` prints it (pretty JSON in its envelope)."""
        return self._json

    def to_dict(self) -> Dict[str, Any]:
        """The report as a fresh dict: ``json.loads`` of the CLI's ``--json``."""
        return json.loads(self._json)

    def __getitem__(self, key: str) -> Any:
        return self._data[key]

    @property
    def schema_version(self) -> int:
        """The output schema's version (``docs/output-format.md``)."""
        return int(self._data["schema_version"])

    def __repr__(self) -> str:
        return f"<{type(self).__name__}>"


def _stopped(reason: Optional[Dict[str, Any]]) -> bool:
    return bool(reason) and reason.get("kind") in ("time_limit", "cancelled")


class Anchor:
    """One anchor of a class's taut tether (thesis §2.4): its point, obstacle and passability."""

    def __init__(self, d: Dict[str, Any]) -> None:
        self._d = d
        self.index: int = d["index"]
        self.point = np.asarray(d["point"], dtype=np.float64)
        self.obstacle: Optional[int] = d["obstacle"]
        self.psi_deg: float = d["psi_deg"]
        self.theta_max_deg: Optional[float] = d["theta_max_deg"]
        #: ``{"kind": "passable"}``, ``{"kind": "impassable", "reason": {...}}`` or
        #: ``{"kind": "not_reached"}`` (``docs/output-format.md``, typed reasons).
        self.passability: Any = d["passability"]
        self.waypoint = None if d["waypoint"] is None else np.asarray(d["waypoint"], dtype=np.float64)

    def to_dict(self) -> Dict[str, Any]:
        """The anchor's entry of the JSON report."""
        return dict(self._d)

    def __repr__(self) -> str:
        kind = self.passability.get("kind") if isinstance(self.passability, dict) else self.passability
        return f"Anchor({self.index}, point={self.point.tolist()}, {kind})"


class ClassReport:
    """One homotopy class, shortest first: its SHP (taut tether), anchors and feasibility."""

    def __init__(self, d: Dict[str, Any]) -> None:
        self._d = d
        self.rank: int = d["rank"]
        self.length_m: float = d["length_m"]
        self.simple: bool = d["simple"]
        self.points = points(d["points"])
        self.anchors = [Anchor(a) for a in d["anchors"]]
        self.anchor_points = points([a["point"] for a in d["anchors"]])
        self.feasible: bool = d["feasible"]
        #: ``{"kind": "feasible"}`` or ``{"kind": "blocked", "anchor": ..., "reason": {...}}``.
        self.verdict: Any = d["verdict"]
        self.waypoints = points(d["waypoints"])
        #: None, or the planner's pair failure tagged by ``kind``.
        self.pair_failure: Optional[Any] = d["pair_failure"]

    def to_dict(self) -> Dict[str, Any]:
        """The class's entry of the JSON report."""
        return json.loads(json.dumps(self._d))

    def __repr__(self) -> str:
        return f"ClassReport(rank={self.rank}, length_m={self.length_m:.3f}, feasible={self.feasible})"


class PairReport:
    """The chosen ascent/descent pair (thesis §2.4.3): two paths as ``(n, 2)`` arrays."""

    def __init__(self, d: Dict[str, Any]) -> None:
        self._d = d
        self.rank: int = d["rank"]
        self.ascent = points(d["ascent"])
        self.descent = points(d["descent"])
        self.ascent_length_m: float = d["ascent_length_m"]
        self.descent_length_m: float = d["descent_length_m"]
        self.descent_is_reversed_ascent: bool = d["descent_is_reversed_ascent"]
        self.min_anchor_distance_m: Optional[float] = d.get("min_anchor_distance_m")

    def __repr__(self) -> str:
        return f"PairReport(rank={self.rank}, ascent {self.ascent_length_m:.3f} m, descent {self.descent_length_m:.3f} m)"


class PlanReport(Report):
    """What ``rappel.plan`` returns: homotopy classes shortest first, their feasibility, the
    chosen ascent/descent pair, and why the search ended.

    Attributes: ``classes`` (list of :class:`ClassReport`, each with ``points`` an ``(n, 2)``
    array), ``chosen`` (:class:`PairReport` or None), ``feasible``, ``verdict``,
    ``termination``, ``stop_reason`` (dict or None), ``stopped`` (a time limit or cancel
    stopped the search), ``warnings``.
    """

    kind = "plan"

    @property
    def scenario(self) -> str:
        """The scenario's name."""
        return self._data["scenario"]

    @functools.cached_property
    def classes(self) -> List[ClassReport]:
        """The homotopy classes, shortest first."""
        return [ClassReport(c) for c in self._data["classes"]]

    @functools.cached_property
    def chosen(self) -> Optional[PairReport]:
        """The chosen ascent/descent pair, or None."""
        c = self._data["chosen"]
        return None if c is None else PairReport(c)

    @property
    def verdict(self) -> str:
        """One line: which class was chosen, or why none was."""
        return self._data["verdict"]

    @property
    def termination(self) -> Any:
        """Why the search ended (``class_count``, ``exhausted``, ``time_limit``...)."""
        return self._data["termination"]

    @property
    def stop_reason(self) -> Optional[Dict[str, Any]]:
        """The condition that stopped the search (budget, time limit, cancel), or None."""
        return self._data.get("stop_reason")

    @property
    def warnings(self) -> List[str]:
        """Warnings (concave plane edges, approximated robot models)."""
        return self._data["warnings"]

    @property
    def friction(self) -> Optional[Dict[str, Any]]:
        """The frictional plan, when the scenario has PTFOs."""
        return self._data.get("friction")

    @property
    def feasible(self) -> bool:
        """A feasible class with an ascent/descent pair (the frictional planner's choice when
        the scenario has PTFOs): the CLI's exit code 0."""
        if self.friction is not None:
            return self.friction.get("chosen") is not None
        return self.chosen is not None

    @property
    def stopped(self) -> bool:
        """A time limit or a cancel request stopped the search (the classes are those found before)."""
        return _stopped(self.stop_reason)

    @property
    def lengths_m(self) -> np.ndarray:
        """Every class's SHP length, shortest first."""
        return np.asarray([c["length_m"] for c in self._data["classes"]], dtype=np.float64)

    def __repr__(self) -> str:
        return f"PlanReport({self.scenario!r}, {len(self._data['classes'])} classes, feasible={self.feasible})"


class QueryReport(Report):
    """What ``rappel.query`` returns: one answer per pair, in order.

    ``lengths`` is a list of float64 arrays (each pair's class lengths, empty when not
    connected), ``shortest`` an array of each pair's shortest length (NaN when none), ``errors``
    each pair's error or None.
    """

    kind = "query"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.answers: List[Dict[str, Any]] = self._data["answers"]
        self.lengths = [np.asarray(a["lengths_m"], dtype=np.float64) for a in self.answers]
        self.shortest = np.asarray(
            [a["lengths_m"][0] if a["lengths_m"] else np.nan for a in self.answers], dtype=np.float64
        )
        self.errors: List[Optional[str]] = [a["error"] for a in self.answers]

    def __len__(self) -> int:
        return len(self.answers)

    def __repr__(self) -> str:
        return f"QueryReport({len(self.answers)} pairs)"


class StabilityReport(Report):
    """What ``rappel.stability`` returns: every assessed pose with its verdict and margin.

    ``points`` is the ``(n, 2)`` array of poses, ``stable`` a bool array, ``margin`` a float
    array (NaN where unstable), ``stopped_by`` the condition that stopped a partial map or None.
    """

    kind = "stability"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        d = self._data
        dots = d["dots"]
        self.criterion: str = d["criterion"]
        self.points = points([x["point"] for x in dots])
        self.stable = np.asarray([x["stable"] for x in dots], dtype=bool)
        self.margin = np.asarray(
            [np.nan if x["margin"] is None else x["margin"] for x in dots], dtype=np.float64
        )
        self.plane = np.asarray([x["plane"] for x in dots], dtype=np.int64)
        self.stopped_by: Optional[Dict[str, Any]] = d["stopped_by"]

    @property
    def stopped(self) -> bool:
        """The map is partial: a time limit or cancel request stopped it."""
        return self.stopped_by is not None

    def __repr__(self) -> str:
        return f"StabilityReport({int(self.stable.sum())} of {len(self.stable)} poses stable)"


class DemReport(Report):
    """What ``rappel.dem`` reports (the CLI's ``rappel dem --json``): planes, counts, start, goal."""

    kind = "dem"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        d = self._data
        self.planes: List[Dict[str, Any]] = d["planes"]
        self.start = np.asarray(d["start"], dtype=np.float64)
        self.goal = np.asarray(d["goal"], dtype=np.float64)
        self.fall_line_azimuth_deg: float = d["fall_line_azimuth_deg"]


class GenericReport(Report):
    """A report of a use case without special attributes: ``to_dict()`` and ``[key]``."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.kind = self._data.get("report", "")

    def __repr__(self) -> str:
        return f"<{self.kind} report>"


class SettleReport(Report):
    """What ``rappel.settle`` returns (``rappel settle --json``): the settled pose, its contacts
    (``contacts``, an ``(n, 3)`` array) and, with an anchor, the stability verdicts."""

    kind = "settle"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        d = self._data
        self.origin = np.asarray(d["origin"], dtype=np.float64)
        self.roll_deg: float = d["roll_deg"]
        self.pitch_deg: float = d["pitch_deg"]
        self.contacts = np.asarray(d["contacts"], dtype=np.float64).reshape(-1, 3)


class SettleMapReport(Report):
    """What ``rappel.settle_map`` returns (``rappel settle-map --json``), with the grid as 2-D
    arrays of shape ``(ny, nx)`` (row ``j`` is ``y = y_min + j * step``): ``stable`` (bool),
    ``margin`` (NaN where not settled), ``settled`` (bool), and ``x``, ``y`` the cell centres."""

    kind = "settle_map"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        d = self._data
        nx, ny = d["nx"], d["ny"]
        cells = d["cells"]
        self.nx: int = nx
        self.ny: int = ny
        self.stopped_by: Optional[Dict[str, Any]] = d.get("stopped_by")
        pose = [c["pose"] for c in cells]
        shape = (ny, nx) if len(cells) == nx * ny else (len(cells),)
        self.settled = np.asarray([p is not None for p in pose], dtype=bool).reshape(shape)
        self.stable = np.asarray([bool(p and p["stable"]) for p in pose], dtype=bool).reshape(shape)
        self.margin = np.asarray(
            [np.nan if p is None else p["margin"] for p in pose], dtype=np.float64
        ).reshape(shape)
        ground = np.asarray([c["ground"] for c in cells], dtype=np.float64).reshape(-1, 2)
        self.x = ground[:, 0].reshape(shape)
        self.y = ground[:, 1].reshape(shape)


class NavigateReport(Report):
    """What ``rappel.navigate`` returns (``rappel navigate --json``): ``found``, ``cost``, the
    ``path`` as an ``(n, 3)`` array with ``yaw_deg``, the ``anchors`` as an ``(k, 3)`` array."""

    kind = "navigate"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        d = self._data
        self.found: bool = d["found"]
        self.cost: Optional[float] = d["cost"]
        self.path = np.asarray(d["path"], dtype=np.float64).reshape(-1, 3)
        self.yaw_deg = np.asarray(d["yaw_deg"], dtype=np.float64)
        self.anchors = np.asarray(d["anchors"], dtype=np.float64).reshape(-1, 3)
        self.stopped_by: str = d["stopped_by"]
        self.stop_reason: Optional[Dict[str, Any]] = d.get("stop_reason")


class TrackReport(Report):
    """What ``rappel.track`` returns (``rappel track --json``): one entry per waypoint
    (``waypoints``) and the first unstable waypoint, if any (``stable`` is True when none)."""

    kind = "track"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.waypoints: List[Dict[str, Any]] = self._data["waypoints"]
        self.first_unstable = self._data.get("first_unstable")

    @property
    def stable(self) -> bool:
        """Robot 2 is stable at every waypoint (the CLI's exit code 0)."""
        return self.first_unstable is None


class OnlineReport(Report):
    """What ``rappel.online`` returns (``rappel online --json``): the simulation's events and
    ending; ``reached`` is True when the goal was reached."""

    kind = "online"

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.ending = self._data["ending"]
        self.stopped_by: Optional[Dict[str, Any]] = self._data.get("stopped_by")

    @property
    def reached(self) -> bool:
        """The goal was reached (the CLI's exit code 0)."""
        e = self.ending
        return e == "goal" or (isinstance(e, dict) and e.get("ending") == "goal")
