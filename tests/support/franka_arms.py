"""Franka-class arms for the tests of :mod:`redkin.franka`: the models, random arms, and one arm in other conventions.

A random arm is written first in the solver's own standard DH form (paper 000 Table 1's twists, ``a = (0, 0, a_3,
a_4, 0, a_6, 0)``, ``d = (d_1, 0, d_3, 0, d_5, d_6, d_7)``), then rewritten as a user might: other zero offsets,
reversed joint senses, modified DH, every common normal turned over, other base and tool frames, or a URDF whose
joint frames are turned about their axes.  Each rewriting is the same arm: the tests check that by FK, not by
trusting these functions.
"""

from __future__ import annotations

import numpy as np

from redkin.chain import SerialChain
from redkin.franka import BRANCHES, FrankaGeometry
from redkin.srs.conventions import TABLE1_ALPHA
from tests.support.urdf_reference import urdf

#: The models of the class (``get_robot`` names).
MODELS = ("franka-panda", "franka-fr3", "ufactory-xarm7")
#: The rewritings of :func:`other_conventions`.
CONVENTIONS = ("zero offsets", "reversed senses", "modified DH", "flipped normals", "base and tool", "all at once")


def form_chain(d1: float, a3: float, d3: float, a4: float, d5: float, a6: float, d6: float = 0.0, d7: float = 0.0,
               name: str = "franka-class") -> SerialChain:
    """The solver's standard DH form with these lengths (``d_7``: the flange along axis 7)."""
    return SerialChain(a=[0.0, 0.0, a3, a4, 0.0, a6, 0.0], alpha=TABLE1_ALPHA, d=[d1, 0.0, d3, 0.0, d5, d6, d7],
                       name=name)


def random_arm(rng: np.random.Generator, zero_elbow: bool = False, zero_d6: bool = False) -> SerialChain:
    """A Franka-class arm with random lengths: ``a_6 != 0`` of either sign, elbow offsets of either sign (both 0
    with ``zero_elbow``), ``d_6`` random (0 with ``zero_d6``)."""
    d1, d3, d5 = rng.uniform(0.1, 0.6, 3)
    a3, a4 = (0.0, 0.0) if zero_elbow else rng.uniform(-0.15, 0.15, 2)
    a6 = rng.choice([-1.0, 1.0]) * rng.uniform(0.02, 0.15)
    d6 = 0.0 if zero_d6 else rng.uniform(-0.1, 0.1)
    return form_chain(d1, a3, d3, a4, d5, a6, d6, rng.uniform(-0.2, 0.2))


def random_pose(rng: np.random.Generator) -> np.ndarray:
    """A random proper rigid transform with a translation of up to 0.5 m in each coordinate."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = q, rng.uniform(-0.5, 0.5, 3)
    return pose


def _chain(chain: SerialChain, **changes) -> SerialChain:
    fields = dict(a=chain.a, alpha=chain.alpha, d=chain.d, convention=chain.convention, offset=chain.offset,
                  sign=chain.sign, lower=chain.lower, upper=chain.upper, base=chain.base, tool=chain.tool,
                  name=chain.name)
    fields.update(changes)
    return SerialChain(**fields)


def modified_dh(chain: SerialChain) -> SerialChain:
    """A standard DH chain as modified DH rows: ``Rz Tz Tx Rx`` regrouped as ``Rx Tx Rz Tz``, the last ``Tx Rx``
    moved into the tool."""
    if chain.convention != "dh":
        raise ValueError("modified_dh rewrites a standard DH chain")
    last = np.eye(4)
    last[0, 3] = chain.a[-1]
    c, s = np.cos(chain.alpha[-1]), np.sin(chain.alpha[-1])
    last[1:3, 1:3] = [[c, -s], [s, c]]
    return _chain(chain, a=np.r_[0.0, chain.a[:-1]], alpha=np.r_[0.0, chain.alpha[:-1]], convention="mdh",
                  tool=last @ chain.tool)


def other_conventions(chain: SerialChain, rng: np.random.Generator) -> dict[str, SerialChain]:
    """The same standard DH arm rewritten each way of :data:`CONVENTIONS` (random offsets, senses and frames)."""
    shift = rng.uniform(-np.pi, np.pi, 7)
    senses = rng.choice([-1.0, 1.0], 7)
    senses[0] = -1.0  # at least one joint reversed
    zero_offsets = _chain(chain, offset=chain.offset - chain.sign * shift)  # q' = q + shift
    reversed_senses = _chain(chain, sign=chain.sign * senses)  # q' = senses * q
    flipped = _chain(chain, a=-chain.a, alpha=-chain.alpha)  # every common normal turned over
    moved = _chain(chain, base=_random_frame(rng), tool=_random_frame(rng))
    everything = modified_dh(_chain(chain, offset=chain.offset - chain.sign * shift, sign=chain.sign * senses,
                                    a=-chain.a, alpha=-chain.alpha, base=_random_frame(rng), tool=_random_frame(rng)))
    return dict(zip(CONVENTIONS, (zero_offsets, reversed_senses, modified_dh(chain), flipped, moved, everything)))


def _random_frame(rng: np.random.Generator) -> np.ndarray:
    frame = random_pose(rng)
    frame[:3, 3] *= 0.4
    return frame


def urdf_of(chain: SerialChain, turns: np.ndarray, axes: np.ndarray, name: str = "franka-class") -> str:
    """A URDF of a standard DH chain (zero offsets, senses +1, identity base) whose joint frame ``k`` is turned by
    ``turns[k]`` about its axis and whose axis is ``0 0 axes[k]``; the chain's tool is the last, fixed joint.

    At joint values ``q`` its tip (link ``l8``) is the chain's ``fk(axes * q)``.
    """
    rows = list(zip(chain.a, chain.alpha, chain.d))
    joints, previous = [], 0.0
    for k in range(7):  # joint k + 1 sits where DH row k ends: Rz(theta) Tz(d) Tx(a) Rx(alpha) of row k - 1 before it
        a, alpha, d = rows[k - 1] if k else (0.0, 0.0, 0.0)
        xyz = f"{a * np.cos(previous):.17g} {-a * np.sin(previous):.17g} {d:.17g}"
        joints.append(("revolute", xyz, _rpy(_rz(-previous) @ _rx(alpha) @ _rz(turns[k])), f"0 0 {axes[k]:g}"))
        previous = turns[k]
    a, alpha, d = rows[6]
    end = np.eye(4)
    end[:3, :3] = _rz(-previous) @ _rx(alpha)
    end[:3, 3] = [a * np.cos(previous), -a * np.sin(previous), d]
    end = end @ chain.tool
    joints.append(("fixed", " ".join(f"{v:.17g}" for v in end[:3, 3]), _rpy(end[:3, :3]), ""))
    return urdf(joints, name=name).replace('lower="-2" upper="2.5"', 'lower="-3" upper="3"')


def _rz(t: float) -> np.ndarray:
    return np.array([[np.cos(t), -np.sin(t), 0.0], [np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])


def _rx(t: float) -> np.ndarray:
    return np.array([[1.0, 0.0, 0.0], [0.0, np.cos(t), -np.sin(t)], [0.0, np.sin(t), np.cos(t)]])


def _rpy(r: np.ndarray) -> str:
    """URDF's ``rpy`` of a rotation (``R = Rz(yaw) Ry(pitch) Rx(roll)``)."""
    pitch = np.arcsin(-np.clip(r[2, 0], -1.0, 1.0))
    roll, yaw = np.arctan2(r[2, 1], r[2, 2]), np.arctan2(r[1, 0], r[0, 0])
    return f"{roll:.17g} {pitch:.17g} {yaw:.17g}"


def form_angles(geometry: FrankaGeometry, q: np.ndarray) -> np.ndarray:
    """The DH angles ``theta`` of the solver's form at the chain's joint values ``q`` (..., 7)."""
    return geometry.form.dh_angles(np.asarray(q, dtype=float))


def branch_index(geometry: FrankaGeometry, q: np.ndarray) -> np.ndarray:
    """Index into :data:`BRANCHES` of the branch of joint values ``q`` (..., 7) as redkin.franka.ik's docstring
    names it, read in the solver's form: the signs of ``sin theta_2``, ``theta_4 - phi`` (wrapped) and ``cos
    theta_5``, each turned over where the form's zero of that joint is nearer ``pi`` (``branch_senses``).  On the
    models (zero offsets 0 or pi) these are the signs of ``q_2`` and ``cos q_5``."""
    theta = form_angles(geometry, q)
    phi = geometry.kernel_arm[9]
    elbow = np.mod(theta[..., 3] - phi + np.pi, 2.0 * np.pi) - np.pi
    signs = np.stack([np.sin(theta[..., 1]), elbow, np.cos(theta[..., 4])], axis=-1)
    signs = np.where(signs >= 0.0, 1, -1) * geometry.branch_senses.astype(int)
    table = {branch: k for k, branch in enumerate(BRANCHES)}
    flat = signs.reshape(-1, 3)
    return np.array([table[tuple(row)] for row in flat.tolist()]).reshape(signs.shape[:-1])
