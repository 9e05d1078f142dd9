"""Generated scenarios (``rappel gen-map``): random crater strips from a seed, and one long star
obstacle (a large map for long plans)."""

from __future__ import annotations

from . import _native


def crater_strip(obstacles: int, seed: int, *, width: float = 200.0):
    """A random crater strip with ``obstacles`` non-overlapping convex obstacles from ``seed``,
    ``width`` metres wide, on one 45-degree plane (mu 0.4): the same seed, the same map."""
    from . import Scenario

    return Scenario(_native.crater_strip(int(obstacles), int(seed), float(width)))


def star(vertices: int):
    """One star obstacle of ``vertices`` vertices (even, at least 6): long tethers, long plans."""
    from . import Scenario

    return Scenario(_native.star(int(vertices)))
