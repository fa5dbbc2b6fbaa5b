"""The one place that knows the classes of arm: which :class:`~redkin.arms.protocol.ArmKind` answers for a chain.

:func:`redkin.arms.classify.arm_angle_class` names a chain's class once; :data:`KINDS` maps that name to the
implementation, built from the chain converted once to the form its kernels take.  A new class is one module and
one line here.
"""

from __future__ import annotations

from collections.abc import Callable

from redkin.arms.classify import FRANKA, GENERAL, NEARLY_SRS, OFFSET_ELBOW, SRS
from redkin.arms.protocol import ArmKind
from redkin.chain import SerialChain


def _srs(chain: SerialChain, kind: str, tolerance: float) -> ArmKind:
    from redkin.arms.srs_kind import SRSKind
    from redkin.srs.geometry import srs_geometry

    return SRSKind(kind, srs_geometry(chain))


def _franka(chain: SerialChain, kind: str, tolerance: float) -> ArmKind:
    from redkin.arms.franka_kind import FrankaKind
    from redkin.franka.geometry import franka_geometry

    return FrankaKind(kind, franka_geometry(chain))


def _nearly(chain: SerialChain, kind: str, tolerance: float) -> ArmKind:
    from redkin.arms.nearly_kind import NearlyKind
    from redkin.srs.nearly import nearly_srs

    return NearlyKind(kind, nearly_srs(chain, tolerance), tolerance)


def _general(chain: SerialChain, kind: str, tolerance: float) -> ArmKind:
    general = ArmKind()
    general.kind, general.chain = kind, chain
    return general


#: Per class name of :func:`redkin.arms.classify.arm_angle_class`, how its implementation is built from the chain.
KINDS: dict[str, Callable[[SerialChain, str, float], ArmKind]] = {
    SRS: _srs,
    OFFSET_ELBOW: _srs,
    FRANKA: _franka,
    NEARLY_SRS: _nearly,
    GENERAL: _general,
}


def kind_of(chain: SerialChain, tolerance: float) -> tuple[ArmKind, Callable[[], str]]:
    """The implementation of ``chain``'s class, and a function that words the reason it is of that class in one
    line (:func:`redkin.arms.classify.class_and_reason`)."""
    from redkin.arms.classify import class_and_reason

    kind, reason = class_and_reason(chain, tolerance)
    return KINDS[kind](chain, kind, tolerance), reason
