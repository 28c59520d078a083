"""Support players onto support positions: REFERENCE §7.10's dynamic-programming mapping (after UT Austin
Villa, "Positioning to Win").

Why DP: the exhaustive search over n! mappings is 3.6 million for 10 support players; the DP builds the best
mapping of every subset of players onto the first k positions from the best mappings of the (k-1)-subsets,
n·2^(n-1) evaluations (5120 for 10). The cost of a mapping is the sum of its walking distances plus a penalty
for each pair of straight paths that cross (two robots walking into each other); as REFERENCE notes, the
collision term voids the optimality guarantee, so the DP's result is the best among the mappings it builds
(it is optimal for the distance sum alone, which the tests check against brute force).

Positions and players are team-frame points [m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence

Point = tuple[float, float]
#: Added to a mapping's cost for each pair of paths that cross [m].
CROSSING_PENALTY_M = 2.0


def _crosses(a: Point, b: Point, c: Point, d: Point) -> bool:
    """Segments a-b and c-d intersect properly."""
    def side(p: Point, q: Point, r: Point) -> float:
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    return (side(a, b, c) * side(a, b, d) < 0.0) and (side(c, d, a) * side(c, d, b) < 0.0)


def assign(players: Sequence[Point], positions: Sequence[Point],
           crossing_penalty_m: float = CROSSING_PENALTY_M) -> list[int]:
    """Position index for each player (same order as ``players``); ``len(positions)`` must equal
    ``len(players)``.

    Raises:
        ValueError: different numbers of players and positions, or more than 16 (2^16 subsets).
    """
    n = len(players)
    if n != len(positions):
        raise ValueError(f"{n} players but {len(positions)} positions: the mapping needs one each")
    if n > 16:
        raise ValueError(f"{n} players: the subset DP is meant for at most 16")
    if n == 0:
        return []
    distance = [[math.hypot(p[0] - q[0], p[1] - q[1]) for q in positions] for p in players]
    # best[mask] = (cost, mapping as tuple of (player, position) pairs) for the players in ``mask`` mapped onto
    # positions 0..popcount(mask)-1.
    best: dict[int, tuple[float, tuple[tuple[int, int], ...]]] = {0: (0.0, ())}
    for k in range(n):
        layer: dict[int, tuple[float, tuple[tuple[int, int], ...]]] = {}
        for mask, (cost, pairs) in best.items():
            for player in range(n):
                if mask & (1 << player):
                    continue
                extra = distance[player][k]
                if crossing_penalty_m:
                    path = (players[player], positions[k])
                    extra += crossing_penalty_m * sum(
                        1 for other, position in pairs
                        if _crosses(path[0], path[1], players[other], positions[position]))
                candidate = (cost + extra, pairs + ((player, k),))
                key = mask | (1 << player)
                if key not in layer or candidate[0] < layer[key][0]:
                    layer[key] = candidate
        best = layer
    _, pairs = best[(1 << n) - 1]
    out = [0] * n
    for player, position in pairs:
        out[player] = position
    return out


def mapping_cost(players: Sequence[Point], positions: Sequence[Point], mapping: Sequence[int],
                 crossing_penalty_m: float = CROSSING_PENALTY_M) -> float:
    """The cost ``assign`` minimises, for any mapping (player i -> positions[mapping[i]])."""
    cost = sum(math.hypot(p[0] - positions[m][0], p[1] - positions[m][1]) for p, m in zip(players, mapping))
    paths = [(p, positions[m]) for p, m in zip(players, mapping)]
    crossings = sum(1 for i in range(len(paths)) for j in range(i + 1, len(paths))
                    if _crosses(*paths[i], *paths[j]))
    return cost + crossing_penalty_m * crossings


__all__ = ["CROSSING_PENALTY_M", "assign", "mapping_cost"]
