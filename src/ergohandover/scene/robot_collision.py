"""Contacts of the robot (one multi-link body: stand, lift, two arms) with itself and others.

Contact is ``getClosestPoints`` on the collision meshes; penetration deeper than
:data:`PENETRATION` counts (shallower is GJK noise on meshes). Adjacent links overlap at their
joint by design and are never tested against each other; neither are siblings (the two fingers
of a hand, which slide against each other). Link pairs whose bounding boxes do not overlap are
skipped before the exact test, so a pose costs a few exact queries, not hundreds.
"""

from __future__ import annotations

import itertools

PENETRATION = 1e-3  # deeper than this is a collision [m]


def self_collision_pairs(p, body: int, client: int) -> list[tuple[int, int]]:
    """Link pairs of ``body`` that can collide: both have a shape, neither is the other's
    nearest shaped ancestor, and they are not siblings under one shaped parent."""
    n = p.getNumJoints(body, physicsClientId=client)
    shaped = {i for i in range(-1, n)
              if p.getCollisionShapeData(body, i, physicsClientId=client)}
    parent = {i: p.getJointInfo(body, i, physicsClientId=client)[16] for i in range(n)}

    def shaped_parent(i: int) -> int:
        i = parent[i]
        while i not in shaped and i != -1:
            i = parent[i]
        return i

    return [(a, b) for a, b in itertools.combinations(sorted(shaped), 2)
            if a != shaped_parent(b) and (a == -1 or shaped_parent(a) != shaped_parent(b))]


def _boxes(p, body: int, links, client: int) -> dict[int, tuple]:
    return {i: p.getAABB(body, i, physicsClientId=client) for i in links}


def _overlap(a, b) -> bool:
    return all(a[0][k] <= b[1][k] and b[0][k] <= a[1][k] for k in range(3))


def deepest_self_penetration(p, body: int, pairs, client: int) -> float:
    """The deepest penetration between any two links of ``pairs`` [m] (0 when none)."""
    boxes = _boxes(p, body, {i for pair in pairs for i in pair}, client)
    deepest = 0.0
    for a, b in pairs:
        if not _overlap(boxes[a], boxes[b]):
            continue
        for point in p.getClosestPoints(body, body, 0.0, linkIndexA=a, linkIndexB=b,
                                        physicsClientId=client):
            deepest = max(deepest, -point[8])
    return deepest


def clearance(p, body: int, other: int, client: int, within: float = 1.0) -> float:
    """The smallest distance between ``body`` and ``other`` [m] (negative when they
    interpenetrate); ``within`` when nothing is nearer than that."""
    points = p.getClosestPoints(body, other, within, physicsClientId=client)
    return float(min((point[8] for point in points), default=within))


def touches(p, body: int, other: int, client: int) -> bool:
    """Does any link of ``body`` penetrate ``other`` deeper than :data:`PENETRATION`?"""
    return any(point[8] < -PENETRATION
               for point in p.getClosestPoints(body, other, 0.0, physicsClientId=client))
