"""The thesis 001 humanoid arm as geometry: link lengths, landmark points, mirroring.

A :class:`TorsoArm` wraps a chain in the form of thesis 001 Table 2.1 (torso
joint + 7-DOF arm, modified DH) and names the points the inverse kinematics
works with:

* the neck ``B`` = base origin, on the torso axis (base ``+y``);
* the shoulder ``S`` = origin of frame 2, ``S(theta_1) = L0 (cos theta_1, 0, -sin theta_1)``
  ([001 eqs. 3.15-3.17] at ``L1 = 0``);
* the elbow ``E`` = origin of frame 4, ``|E - S| = L1``;
* the wrist ``W`` = origin of frame 6, where the axes of joints 6, 7 and 8
  meet; ``|W - E| = l_ew = sqrt(L2^2 + L3^2)`` (section 3.4.2).

The left arm is the right arm mirrored in the plane ``x = 0``
(:func:`redkin.models.humanoid_left_arm`): every left-arm problem is solved
as the right-arm problem of the mirror image, with ``theta_1 -> -theta_1``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.models import humanoid_right_arm
from redkin.torso_arm._kernel_tools import flat, shoulder_points

Side = Literal["right", "left"]

#: Frame indices (in :meth:`SerialChain.frames`) of the shoulder, elbow and wrist points.
SHOULDER_FRAME, ELBOW_FRAME, WRIST_FRAME = 2, 4, 6

#: Reflection of world coordinates in the plane x = 0 (right arm <-> left arm).
MIRROR = np.diag([-1.0, 1.0, 1.0])

_TABLE_ALPHA = np.array([-1, -1, -1, -1, 1, 1, 1, -1]) * np.pi / 2
_TABLE_OFFSET = np.array([-1, -1, -1, -1, 1, -1, 0, 0]) * np.pi / 2
_TABLE_SIGN = np.array([1, 1, -1, 1, 1, -1, 1, -1])


@dataclass(frozen=True)
class TorsoArm:
    """One arm (with the shared torso joint) of the thesis 001 humanoid.

    Parameters
    ----------
    right_chain : SerialChain
        The right arm in the form of Table 2.1 (any positive lengths, any tool).
    side : {"right", "left"}
        Which arm this object solves for; the left arm is the mirror image.
    """

    right_chain: SerialChain
    side: Side = "right"

    def __post_init__(self) -> None:
        if self.side not in ("right", "left"):
            raise RedkinError(f"side must be 'right' or 'left', got {self.side!r}")
        chain = self.right_chain
        same = (
            chain.n == 8
            and chain.convention == "mdh"
            and np.allclose(chain.alpha, _TABLE_ALPHA)
            and np.allclose(chain.offset, _TABLE_OFFSET)
            and np.array_equal(chain.sign, _TABLE_SIGN)
            and np.allclose(chain.a[[0, 1, 2, 3, 4, 6, 7]], 0.0)
            and np.allclose(chain.d[[0, 2, 4, 6, 7]], 0.0)
            and np.allclose(chain.base, np.eye(4))
        )
        if not same:
            raise RedkinError(
                f"right_chain must have the structure of thesis 001 Table 2.1 (8 joints, modified DH, "
                f"identity base), got {chain.name!r}"
            )
        lengths = (self.L0, self.L1, self.L2, self.L3)
        if min(lengths) <= 0:
            raise RedkinError(f"link lengths L0..L3 must be positive, got {lengths}")

    # lengths of Table 2.1 / section 5.1
    @property
    def L0(self) -> float:
        """Neck-to-shoulder length (``d_2``)."""
        return float(self.right_chain.d[1])

    @property
    def L1(self) -> float:
        """Upper-arm length (``d_4``)."""
        return float(self.right_chain.d[3])

    @property
    def L2(self) -> float:
        """Elbow offset (``a_5``)."""
        return float(self.right_chain.a[5])

    @property
    def L3(self) -> float:
        """Forearm length (``d_6``)."""
        return float(self.right_chain.d[5])

    @property
    def forearm(self) -> float:
        """``l_ew = sqrt(L2^2 + L3^2)`` (section 3.4.2)."""
        return float(np.hypot(self.L2, self.L3))

    @property
    def delta(self) -> float:
        """``delta = atan(L2 / L3)`` (section 3.4.2)."""
        return float(np.arctan2(self.L2, self.L3))

    @property
    def chain(self) -> SerialChain:
        """The chain of this side: the right chain, or its mirror image in ``x = 0`` with the torso joint shared."""
        if self.side == "right":
            return self.right_chain
        return self.right_chain.mirrored(normal=(1.0, 0.0, 0.0), flip_joints=[0])

    def to_right(self, points: np.ndarray) -> np.ndarray:
        """World points of this side expressed for the right-arm problem (mirror for the left)."""
        return points if self.side == "right" else points @ MIRROR

    def from_right(self, points: np.ndarray) -> np.ndarray:
        """Right-arm points mapped back to this side's world."""
        return self.to_right(points)

    def shoulder(self, theta1: ArrayLike) -> np.ndarray:
        """Right-arm shoulder ``S(theta_1) = L0 (cos theta_1, 0, -sin theta_1)``, shape ``(..., 3)``
        (the kernel :func:`redkin.torso_arm._kernel_tools.shoulder_point` over the batch)."""
        shape, (flat_theta1,) = flat((theta1, 0))
        out = np.empty((flat_theta1.shape[0], 3))
        shoulder_points(self.L0, flat_theta1, out)
        return out.reshape(shape + (3,))


def humanoid_arm(side: Side = "right", tool_length: float = 0.0) -> TorsoArm:
    """The thesis 001 arm of ``side`` (section 5.1 lengths and limits) with a tool of ``tool_length`` metres."""
    return TorsoArm(humanoid_right_arm(tool_length), side)
