"""Arms for the arm-angle tests: the named models, and random S-R-S and offset-elbow arms."""

import numpy as np

from redkin.chain import SerialChain
from redkin.models import barrett_wam, kuka_iiwa14, pa10_7c, srs_chain
from redkin.srs.conventions import TABLE1_ALPHA

#: ``pa10``, ``iiwa``, ``wam``: the models; ``srs``: random S-R-S lengths; ``offset``: a random offset elbow.
ARM_KINDS = ("pa10", "iiwa", "wam", "srs", "offset")


def offset_elbow_chain(d_bs: float, d_se: float, d_ew: float, d_wt: float, a3: float, a4: float) -> SerialChain:
    """Paper 000 Table 1 with elbow offsets ``a_3``, ``a_4`` (the WAM has 0.045 and -0.045 m)."""
    return SerialChain(a=[0.0, 0.0, a3, a4, 0.0, 0.0, 0.0], alpha=TABLE1_ALPHA,
                       d=[d_bs, 0.0, d_se, 0.0, d_ew, 0.0, d_wt], name="offset-elbow")


def random_poses(chain: SerialChain, count: int, rng: np.random.Generator, stretched: bool = False) -> np.ndarray:
    """``count`` reachable poses of ``chain`` from joint values uniform in [-pi, pi) drawn from ``rng``.

    ``stretched``: every 50th has theta_2 = 0 and every 70th theta_6 = 0 (a stretched shoulder or wrist group).
    """
    q = rng.uniform(-np.pi, np.pi, (count, chain.n))
    if stretched:
        q[::50, 1] = 0.0
        q[::70, 5] = 0.0
    return chain.fk(q)


def wrap(angle):
    """``angle`` wrapped to [-pi, pi)."""
    return np.mod(np.asarray(angle) + np.pi, 2.0 * np.pi) - np.pi


def arm(kind: str, rng: np.random.Generator) -> SerialChain:
    """A chain of one of :data:`ARM_KINDS` (random lengths drawn from ``rng``)."""
    if kind == "srs":
        return srs_chain(*rng.uniform(0.1, 0.8, 4))
    if kind == "offset":
        return offset_elbow_chain(*rng.uniform(0.05, 0.8, 4), *rng.uniform(-0.15, 0.15, 2))
    return {"pa10": pa10_7c, "iiwa": kuka_iiwa14, "wam": barrett_wam}[kind]()


# The definitional [000 eq. 3] for the reference tests: products of Rz(theta_k) Rx(alpha_k), written here.
HALF_PI = np.pi / 2.0


def dh_rotation(theta: np.ndarray, alpha: tuple[float, ...]) -> np.ndarray:
    """``prod_k Rz(theta_k) Rx(alpha_k)`` ([000 eq. 3]) for DH angles ``theta`` of shape ``(..., K)``."""
    theta = np.asarray(theta, dtype=float)
    result = np.broadcast_to(np.eye(3), theta.shape[:-1] + (3, 3)).copy()
    for k, twist in enumerate(alpha):
        c, s = np.cos(theta[..., k]), np.sin(theta[..., k])
        ca, sa = np.cos(twist), np.sin(twist)
        step = np.zeros(theta.shape[:-1] + (3, 3))
        step[..., 0, 0], step[..., 0, 1], step[..., 0, 2] = c, -s * ca, s * sa
        step[..., 1, 0], step[..., 1, 1], step[..., 1, 2] = s, c * ca, -c * sa
        step[..., 2, 1], step[..., 2, 2] = sa, ca
        result = result @ step
    return result


def shoulder_rotation(theta: np.ndarray) -> np.ndarray:
    """``0R3`` from DH angles ``(..., 7)`` (joints 1-3)."""
    return dh_rotation(np.asarray(theta)[..., 0:3], (-HALF_PI, HALF_PI, -HALF_PI))


def wrist_rotation(theta: np.ndarray) -> np.ndarray:
    """``4R7`` from DH angles ``(..., 7)`` (joints 5-7)."""
    return dh_rotation(np.asarray(theta)[..., 4:7], (-HALF_PI, HALF_PI, 0.0))
