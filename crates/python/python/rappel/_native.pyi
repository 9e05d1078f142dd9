"""Type stubs of the extension module ``rappel._native`` (the Rust side of the package).

Users call the functions of :mod:`rappel`, which wrap these and parse their JSON into typed
reports; the signatures here are the raw ones.
"""

from os import PathLike
from typing import List, Optional, Sequence, Tuple, Union

__version__: str
SCHEMA_VERSION: int
MAX_CLASSES: int

_Path = Union[str, PathLike[str]]

class RappelError(Exception): ...
class ScenarioError(RappelError): ...
class InputError(RappelError): ...
class PlanningError(RappelError): ...
class BudgetExceeded(RappelError): ...
class StoppedError(RappelError): ...
class InternalError(RappelError): ...
class NotSettled(RappelError): ...

class Scenario:
    @staticmethod
    def load(path: _Path) -> Scenario: ...
    @staticmethod
    def from_json(text: str) -> Scenario: ...
    @staticmethod
    def from_ron(text: str) -> Scenario: ...
    def to_json(self) -> str: ...
    def to_ron(self) -> str: ...
    def save(self, path: _Path) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def path(self) -> Optional[str]: ...

class CancelFlag:
    """A flag another thread sets (``cancel()``) to stop a long call cleanly."""
    def __init__(self) -> None: ...
    def cancel(self) -> None: ...
    def is_cancelled(self) -> bool: ...
    def reset(self) -> None: ...

def plan(
    scenario: Scenario,
    classes: int,
    max_length_factor: Optional[float],
    simple_only: bool,
    max_expansions: str,
    time_limit: Optional[float],
    cancel: Optional[CancelFlag],
    reachable_areas: bool,
) -> str: ...
def query(
    scenario: Optional[Scenario],
    map_path: Optional[_Path],
    pairs: Optional[List[float]],
    pairs_path: Optional[_Path],
    classes: int,
    repeat: int,
    max_expansions: str,
    time_limit: Optional[float],
    cancel: Optional[CancelFlag],
) -> str: ...
def stability(
    scenario: Scenario,
    grid: float,
    tension_limit: Optional[float],
    time_limit: Optional[float],
    cancel: Optional[CancelFlag],
) -> str: ...
def dem_file(
    path: _Path,
    out: Optional[_Path],
    hmin: Optional[float],
    hmax: Optional[float],
    theta_max: Optional[float],
    friction: Optional[float],
    max_cells: Optional[int],
) -> Tuple[str, Scenario]: ...
def dem_grid(
    heights: bytes,
    nrows: int,
    ncols: int,
    cell_x: float,
    cell_y: float,
    west: float,
    north: float,
    name: str,
    crs: Optional[str],
    out: Optional[_Path],
    hmin: Optional[float],
    hmax: Optional[float],
    theta_max: Optional[float],
    friction: Optional[float],
) -> Tuple[str, Scenario]: ...
def settle(
    path: _Path,
    at: Tuple[float, float],
    yaw: float,
    robot_name: str,
    anchor: Optional[Tuple[float, float, float]],
    field: Optional[float],
) -> str: ...
def settle_map(
    path: _Path,
    x: Optional[Tuple[float, float]],
    y: Optional[Tuple[float, float]],
    step: float,
    yaw: float,
    start: Optional[Tuple[float, float]],
    root: Optional[Tuple[float, float, float]],
    test: Optional[int],
    robot_name: str,
    field: Optional[float],
    time_limit: Optional[float],
    cancel: Optional[CancelFlag],
) -> str: ...
def navigate(
    path: _Path,
    seed: int,
    test: int,
    iterations: int,
    time: Optional[float],
    held: bool,
    shadow: bool,
    field: Optional[float],
    time_limit: Optional[float],
    cancel: Optional[CancelFlag],
) -> str: ...
def track(
    path: _Path,
    robot1_path: Optional[_Path],
    robot1: Optional[Sequence[Tuple[float, float]]],
    robot2_path: Optional[_Path],
    robot2: Optional[Sequence[Tuple[float, float]]],
) -> str: ...
def online(
    prior: Scenario,
    truth: Scenario,
    sensor_range: Optional[float],
    step: Optional[float],
    max_steps: Optional[int],
    classes: Optional[int],
    switch_to_shorter: bool,
    time_limit: Optional[float],
    cancel: Optional[CancelFlag],
) -> str: ...
def crater_strip(obstacles: int, seed: int, width: float) -> Scenario: ...
def star(vertices: int) -> Scenario: ...
