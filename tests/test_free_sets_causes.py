"""``free_sets_of(..., causes=False)``: on every class with certified collision-free sets, the same free sets, limit
sets, evaluations and completeness as with the causes, and no removed stretch named (none solved for); and
``free_arcs_of`` (what path resolution reads) the same free sets and completeness as arrays."""

from __future__ import annotations

import numpy as np
import pytest

import redkin
from redkin.collision import builtin_body, scene_of
from redkin.collision.free_sets import free_arcs_of, free_sets_of

#: A post beside the arm, a table under its reach and a lamp above it (tests/test_collision_free_q7.py's cell).
CELL = {"margin": 0.01, "obstacles": [
    {"name": "post", "type": "capsule", "a": [0.45, 0.25, -0.2], "b": [0.45, 0.25, 1.2], "radius": 0.05},
    {"name": "table", "type": "box", "center": [0.6, 0, -0.06], "size": [1.2, 1.0, 0.1]},
    {"name": "lamp", "type": "sphere", "center": [0.2, -0.4, 0.8], "radius": 0.12}]}


@pytest.mark.parametrize("model, seed", [("kuka-iiwa14", 2), ("franka-panda", 2), ("kinova-gen3", 4)])
def test_without_causes_the_sets_are_the_same_and_nothing_is_named(model, seed):
    arm = redkin.arm(model)
    body, scene = builtin_body(model, arm.chain), scene_of(CELL)
    low, high = np.maximum(arm.chain.lower, -np.pi), np.minimum(arm.chain.upper, np.pi)
    poses = arm.fk(low + np.random.default_rng(seed).uniform(0.2, 0.8, (3, 7)) * (high - low))
    named = free_sets_of(arm, poses, body, scene)
    bare = free_sets_of(arm, poses, body, scene, causes=False)
    # the causes are there to leave out (the Gen3's joints are continuous: draw 4 meets the post)
    assert any(any(stretches) for sets in named for stretches in sets.blocked)
    for with_causes, without in zip(named, bare, strict=True):
        assert without.blocked == tuple(() for _ in without.branches)
        assert (without.evaluations, without.complete, without.parameter) == \
            (with_causes.evaluations, with_causes.complete, with_causes.parameter)
        for ours, theirs in ((without.free, with_causes.free), (without.limits, with_causes.limits)):
            for a, b in zip(ours, theirs, strict=True):
                assert np.array_equal(a.bounds, b.bounds) and np.array_equal(a.wraps, b.wraps)
    arrays = free_arcs_of(arm, poses, body, scene)
    assert arrays.complete.tolist() == [sets.complete for sets in named]
    every = arrays.arcs.split(len(poses) * len(arm.branches))
    for owner, arcs in enumerate(every):
        theirs = named[owner // len(arm.branches)].free[owner % len(arm.branches)]
        assert np.array_equal(arcs.bounds, theirs.bounds) and np.array_equal(arcs.wraps, theirs.wraps), owner
