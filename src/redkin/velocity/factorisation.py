"""Singularities that factor through one parameter: ``det J_i = D_e D_i`` ([003 eqs. 19-20], section 3.3).

The proposed method needs a *singularity index* ``D_e(q)`` common to every
column minor ``det J_i`` of the 6 x 7 Jacobian, and the remaining factors
``D_i = det J_i / D_e``.  This module gives

* :class:`WamFactorisation` -- a Barrett-WAM-shaped arm (paper 003 Table 1, standard DH),
  ``D_e = a (d3 + d5) C4 + (a^2 - d3 d5) S4`` and every ``D_i`` in closed form,
  in any description of the arm,
* :class:`NumericalFactorisation` -- any arm with a known index function:
  ``D_i = det J_i / D_e``, and at (or very near) ``D_e = 0`` the limit of that
  ratio by l'Hopital along the gradient of ``D_e``,
* :class:`ElbowSine` -- the index ``sin(theta_4 - phi)`` of S-R-S arms and offset elbows,
* :func:`singularity_factorisation` -- the one that fits a chain, found from its geometry,
* :func:`check_single_parameter` -- a numerical test of whether an index
  really factors every ``det J_i`` (S-R-S arms with ``sin q4``: yes; the WAM
  with its ``D_e``: yes; the WAM with ``sin q4``: no).

Any description.  The index is found on the arm's paper 000 Table 1 form
(:func:`redkin.srs.srs_geometry`, :func:`redkin.srs.conventions.table1_form`),
whatever the description's twists, zero pose, joint senses, base and tool
frames or DH convention.  That form has the same joint values ``q`` and the
same pose for every ``q``; its DH angles are ``theta = offset + sign * q``.
So the two Jacobians are equal, ``J(q) = J_T1(theta(q)) diag(sign)``, where
``J_T1`` is the Jacobian in ``theta`` of the Table 1 rows (the world frame and
the tool point do not change a 6 x 6 minor: they multiply it by a
determinant 1), and

    det J_i(q) = det J_i^T1(theta) prod_{j != i} sign_j.

On the Table 1 form the shoulder-wrist distance is ``|x_sw|^2 = C + R
cos(theta_4 - phi)`` (:class:`redkin.srs.geometry.ElbowEquation`).  With the
shoulder and the wrist spherical, every minor ``det J_i`` has the factor
``d |x_sw|^2 / d theta_4 = -R sin(theta_4 - phi)``: the wrist centre's
velocity from joint 4 is the only one with a component along ``x_sw``
(and likewise the shoulder's, seen from the wrist).  On the WAM
(``a_3 = a``, ``a_4 = -a``) that factor is ``D_e = a (d3 + d5) cos theta_4 +
(a^2 - d3 d5) sin theta_4 = -(R / 2) sin(theta_4 - phi)``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from math import cos, sin
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.srs.geometry import SRSGeometry, srs_geometry
from redkin.velocity.cofactors import column_minors

#: Largest ``|a_3 + a_4| / |a_3|`` of the Table 1 form for the WAM's closed form (``a_4 = -a_3``).  Tight: the closed
#: form is exact only for ``a_4 = -a_3``; the form itself rounds ``a_3``, ``a_4`` to about 1e-16 relative.
_WAM_TOLERANCE = 1e-9
_PLAIN_JOINTS = np.array([np.zeros(7), np.ones(7)])  # offset 0, sign +1: theta = q
_PLAIN_JOINTS.setflags(write=False)


def wam_singularity_index(q: ArrayLike, a: float, d3: float, d5: float, offset: ArrayLike | None = None,
                          sign: ArrayLike | None = None) -> np.ndarray:
    """``D_e = a (d3 + d5) cos theta_4 + (a^2 - d3 d5) sin theta_4`` (paper 003 section 3.3), shape ``(...)``.

    Zero exactly at the elbow-stretch singularity (the workspace boundary).

    Parameters
    ----------
    q : array_like, shape (..., 7)
        Joint values.
    a, d3, d5 : float
        The elbow offset and the upper-arm and forearm lengths of paper 003 Table 1.
    offset, sign : array_like, shape (7,), optional
        ``theta = offset + sign * q`` (default 0 and +1: ``q`` are the DH angles of Table 1).
    """
    return _wam(q, a, d3, d5, offset, sign)[0]


def wam_cofactors(q: ArrayLike, a: float, d3: float, d5: float, offset: ArrayLike | None = None,
                  sign: ArrayLike | None = None) -> np.ndarray:
    """Closed-form ``D_i`` with ``det J_i = D_e D_i`` for the Barrett WAM [003 eq. 19], shape ``(..., 7)``.

    Derived with sympy (development aid, not a dependency) from the geometric
    Jacobian of paper 003 Table 1: every minor contains ``D_e`` as a factor.
    ``det J_i`` does not depend on the reference point, the base frame, ``d7``,
    ``q1`` or ``q7``.  ``D_4 = 0``: with the elbow joint fixed the remaining
    six joints are always singular (shoulder and wrist both spherical).  With
    ``theta = offset + sign * q`` (see :func:`wam_singularity_index`) each
    ``D_i`` is multiplied by ``prod_{j != i} sign_j``, the sign its minor
    takes from the other columns.
    """
    return _wam(q, a, d3, d5, offset, sign)[1]


def _wam(q: ArrayLike, a: float, d3: float, d5: float, offset: ArrayLike | None,
         sign: ArrayLike | None) -> tuple[np.ndarray, np.ndarray]:
    """``D_e`` (...) and ``D_i`` (..., 7) from the kernel :func:`_wam_index_and_factors`."""
    joints = _PLAIN_JOINTS
    if offset is not None or sign is not None:
        joints = np.array([_PLAIN_JOINTS[0] if offset is None else np.asarray(offset, dtype=float).reshape(7),
                           _PLAIN_JOINTS[1] if sign is None else np.asarray(sign, dtype=float).reshape(7)])
    return _wam_joints(q, a, d3, d5, joints)


def _wam_joints(q: ArrayLike, a: float, d3: float, d5: float, joints: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_wam` with ``joints`` = ``(offset, sign)`` as one C-contiguous (2, 7) array."""
    values = np.asarray(q, dtype=float)
    flat = np.ascontiguousarray(values.reshape(-1, values.shape[-1]))
    index, factors = np.empty(flat.shape[0]), np.empty((flat.shape[0], 7))
    _wam_index_and_factors(flat, float(a), float(d3), float(d5), joints, index, factors)
    return index.reshape(values.shape[:-1]), factors.reshape(values.shape[:-1] + (7,))


@kernel
def _wam_index_and_factors(q, a, d3, d5, joints, index, factors):
    """``D_e`` into ``index`` (N,) and ``D_i`` into ``factors`` (N, 7) for each row of ``q`` (N, 7) [003 eq. 19].

    The closed form is in the DH angles ``theta = offset + sign * q`` (``joints``
    = ``(offset, sign)``, (2, 7)); ``D_i`` takes the sign ``prod_{j != i} sign_j``
    of its minor's other columns.
    """
    offset, sign = joints[0], joints[1]
    turned = 1.0
    for k in range(7):
        turned *= sign[k]
    for b in range(q.shape[0]):
        t2, t3, t4 = offset[1] + sign[1] * q[b, 1], offset[2] + sign[2] * q[b, 2], offset[3] + sign[3] * q[b, 3]
        t5, t6 = offset[4] + sign[4] * q[b, 4], offset[5] + sign[5] * q[b, 5]
        s2, s3, s4, s5, s6 = sin(t2), sin(t3), sin(t4), sin(t5), sin(t6)
        c2, c3, c4, c5, c6 = cos(t2), cos(t3), cos(t4), cos(t5), cos(t6)
        index[b] = a * (d3 + d5) * c4 + (a * a - d3 * d5) * s4
        shoulder = a * (c4 - 1.0) - d5 * s4
        wrist = a * (c4 - 1.0) - d3 * s4
        factors[b, 0] = shoulder * s6 * c3
        factors[b, 1] = shoulder * s2 * s3 * s6
        factors[b, 2] = (a * s2 * s4 - a * c2 * c3 * c4 + a * c2 * c3 + d3 * s2 + d5 * s2 * c4 + d5 * s4 * c2 * c3) * s6
        factors[b, 3] = 0.0
        factors[b, 4] = (-a * s4 * s6 + a * c4 * c5 * c6 - a * c5 * c6 - d3 * s4 * c5 * c6 - d3 * s6 * c4
                         - d5 * s6) * s2
        factors[b, 5] = -wrist * s2 * s5 * s6
        factors[b, 6] = -wrist * s2 * c5
        for i in range(7):
            factors[b, i] *= turned * sign[i]  # prod_{j != i} sign_j, as sign_i^2 = 1


@runtime_checkable
class Factorisation(Protocol):
    """A singularity factorisation (the plug-in of the SC method, a ``Protocol`` like
    :class:`redkin.velocity.methods.Method`): ``index(q)`` -> ``D_e`` ``(...)``;
    ``factors(q, jacobian)`` -> ``D_i`` ``(..., n)``.

    ``jacobian`` is the Jacobian at ``q`` where the caller holds it, or
    ``None`` (the control loop's exact path): then a factorisation that needs
    it builds it.
    """

    def index(self, q: np.ndarray) -> np.ndarray: ...

    def factors(self, q: np.ndarray, jacobian: np.ndarray | None) -> np.ndarray: ...


@dataclass(frozen=True)
class WamFactorisation(Factorisation):
    """Closed-form ``D_e`` and ``D_i`` of a Barrett-WAM-shaped arm [003 eq. 19], in any description.

    The closed form (:func:`wam_singularity_index`, :func:`wam_cofactors`) is
    in the DH angles ``theta`` of paper 003 Table 1; ``offset`` and ``sign``
    map a description's joint values to them, ``theta = offset + sign * q``
    (the arm's Table 1 form, see the module docstring).

    Attributes
    ----------
    a, d3, d5 : float
        Elbow offset (``a_3 = a``, ``a_4 = -a``), upper arm and forearm of the Table 1 form, in metres.
    offset, sign : tuple of 7 floats
        ``theta = offset + sign * q``; default 0 and +1 (the chain is the Table 1 rows themselves, as
        :func:`redkin.models.barrett_wam`).
    """

    a: float
    d3: float
    d5: float
    offset: Sequence[float] = (0.0,) * 7
    sign: Sequence[float] = (1.0,) * 7
    _joints: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        offset = tuple(float(v) for v in np.ravel(np.asarray(self.offset, dtype=float)))
        sign = tuple(float(v) for v in np.ravel(np.asarray(self.sign, dtype=float)))
        if len(offset) != 7 or not np.all(np.isfinite(offset)):
            raise RedkinError(f"offset must be 7 finite angles (theta = offset + sign * q), got {list(offset)}")
        if len(sign) != 7 or any(s not in (1.0, -1.0) for s in sign):
            raise RedkinError(f"sign must be 7 entries of +1 or -1 (theta = offset + sign * q), got {list(sign)}")
        object.__setattr__(self, "offset", offset)
        object.__setattr__(self, "sign", sign)
        joints = np.array([offset, sign])
        joints.setflags(write=False)
        object.__setattr__(self, "_joints", joints)

    @classmethod
    def from_chain(cls, chain: SerialChain) -> WamFactorisation:
        """The closed form for a chain that describes a Barrett-WAM-shaped arm, in any description.

        The arm must be in the arm-angle class with an offset elbow
        (:func:`redkin.srs.srs_geometry`) whose Table 1 form has ``a_4 =
        -a_3 != 0`` (relative tolerance 1e-9): paper 003's rows up to the
        description (URDF frames, twists of either sign, zero pose, joint
        senses, modified DH, base and tool).

        Raises
        ------
        ValueError
            For any other chain (one line, with the reason).
        """
        geometry, reason = _geometry(chain)
        if geometry is not None:
            reason = _not_wam_shaped(geometry)
        if geometry is None or reason:
            raise RedkinError(
                f"chain {chain.name!r} does not have the Barrett WAM DH pattern of paper 003 Table 1 in any "
                f"description (an offset elbow with a_4 = -a_3): {reason}; use NumericalFactorisation with your own "
                "index")
        table1 = geometry.chain
        return cls(a=geometry.a3, d3=geometry.d_se, d5=geometry.d_ew, offset=tuple(table1.offset),
                   sign=tuple(table1.sign))

    def index(self, q: np.ndarray) -> np.ndarray:
        return _wam_joints(q, self.a, self.d3, self.d5, self._joints)[0]

    def factors(self, q: np.ndarray, jacobian: np.ndarray | None = None) -> np.ndarray:
        return _wam_joints(q, self.a, self.d3, self.d5, self._joints)[1]


def _geometry(chain: SerialChain) -> tuple[SRSGeometry | None, str]:
    """The arm-angle geometry of a 7-joint chain (with its Table 1 form), or ``None`` and why not."""
    try:
        return srs_geometry(chain), ""
    except ValueError as exc:  # not in the arm-angle class (NotArmAngleClassError), with the reason
        return None, str(exc).splitlines()[0] if str(exc) else type(exc).__name__


def _not_wam_shaped(geometry: SRSGeometry) -> str:
    """Why an arm-angle-class arm is not shaped like the WAM (``a_4 = -a_3 != 0``), or ``""`` if it is."""
    a3, a4 = geometry.a3, geometry.a4
    if not geometry.offset_elbow:
        return "its elbow has no offset (an S-R-S arm)"
    if abs(a3 + a4) > _WAM_TOLERANCE * abs(a3):
        return f"its elbow offsets are a_3 = {a3:.6g} m, a_4 = {a4:.6g} m"
    return ""


@dataclass(frozen=True)
class NumericalFactorisation(Factorisation):
    """``D_i = det J_i / D_e`` for any chain with a user-given index ``D_e(q)`` [003 eq. 19].

    Where ``|D_e| < near_zero`` the ratio is 0/0; there ``D_i`` is taken as
    the l'Hopital limit along the unit gradient ``u`` of ``D_e``:
    ``(det J_i(q + h u) - det J_i(q - h u)) / (D_e(q + h u) - D_e(q - h u))``.
    Valid only if the index really factors the minors
    (see :func:`check_single_parameter`).
    """

    chain: SerialChain
    index_function: Callable[[np.ndarray], np.ndarray]
    near_zero: float = 1e-6
    step: float = 1e-5

    def index(self, q: np.ndarray) -> np.ndarray:
        return np.asarray(self.index_function(q), dtype=float)

    def factors(self, q: np.ndarray, jacobian: np.ndarray | None = None) -> np.ndarray:
        q = self.chain.check_q(q)
        jac = self.chain.jacobian(q) if jacobian is None else jacobian
        index = self.index(q)
        minors = column_minors(jac)
        small = np.abs(index) < self.near_zero
        ratio = minors / np.where(small, 1.0, index)[..., None]
        if np.any(small):
            u = _index_gradient(self.index_function, q, self.step)
            u = u / np.maximum(np.linalg.norm(u, axis=-1, keepdims=True), 1e-300)
            plus, minus = q + self.step * u, q - self.step * u
            d_minor = column_minors(self.chain.jacobian(plus)) - column_minors(self.chain.jacobian(minus))
            d_index = self.index(plus) - self.index(minus)
            limit = d_minor / d_index[..., None]
            ratio = np.where(small[..., None], limit, ratio)
        return ratio


@dataclass(frozen=True)
class ElbowSine:
    """``D_e = sin(theta_4 - phi)``, the elbow index of S-R-S arms (``phi = 0``; paper 003 section 3.3) and of
    offset elbows, with ``theta_4 = offset + sign * q_4``.

    Zero where the shoulder-wrist distance ``|x_sw|^2 = C + R cos(theta_4 -
    phi)`` is longest or shortest (:class:`redkin.srs.geometry.ElbowEquation`):
    the elbow is stretched or folded, joint 4 cannot move the wrist centre
    towards the shoulder, and every column minor vanishes.  ``offset``,
    ``sign`` and ``phi`` are those of the arm's Table 1 form (see the module
    docstring); on a chain in another description ``sin(theta_4 - phi)`` is
    evaluated at that form's ``theta_4``.
    """

    offset: float
    sign: float
    phase: float = 0.0

    def __call__(self, q: np.ndarray) -> np.ndarray:
        return np.sin(self.offset + self.sign * np.asarray(q, dtype=float)[..., 3] - self.phase)


def singularity_factorisation(chain: SerialChain, seed: int | np.random.Generator = 0) -> Factorisation:
    """The factorisation ``det J_i = D_e D_i`` [003 eq. 19] of a 7-joint chain, found from its geometry.

    In whatever description the chain comes (DH or modified DH, any twists,
    zero pose, joint senses, base and tool; a URDF), an arm of the arm-angle
    class (:func:`redkin.srs.srs_geometry`: shoulder and wrist spherical, an
    elbow with or without offsets) is read on its paper 000 Table 1 form:

    * a WAM-shaped offset elbow (``a_4 = -a_3``) gets the closed form
      :class:`WamFactorisation` at the form's ``theta(q)``, with the column
      signs of the description;
    * any other elbow gets ``D_e = sin(theta_4 - phi)`` (:class:`ElbowSine`,
      ``phi = 0`` for an S-R-S arm), used through :class:`NumericalFactorisation`
      once :func:`check_single_parameter` confirms that it divides every minor.

    Any other chain gets ``sin(theta_4)`` of its own DH angles, on the same
    condition.  ``D_e`` is unique up to a constant factor; its sign follows the
    description's joint senses, and the SC method's ``b_ep`` (the sign of
    ``D_e`` at the start) makes the motion independent of that sign.

    Raises
    ------
    ValueError
        If the chain does not have 7 joints, or if no index factors its
        minors (its singularities do not go through one parameter, e.g. an
        offset wrist, as on the European Robotic Arm); one line.
    """
    if chain.n != 7:
        raise RedkinError(f"chain must have 7 joints (a 6 x 7 Jacobian), got {chain.n} ({chain.name!r})")
    geometry, _ = _geometry(chain)
    if geometry is not None and not _not_wam_shaped(geometry):
        return WamFactorisation.from_chain(chain)
    if geometry is not None:
        table1 = geometry.chain
        elbow = ElbowSine(float(table1.offset[3]), float(table1.sign[3]), geometry.elbow_equation.phase)
    else:
        elbow = ElbowSine(float(chain.offset[3]), float(chain.sign[3]))
    if check_single_parameter(chain, elbow, seed=seed).factors:
        return NumericalFactorisation(chain, elbow)
    raise RedkinError(
        f"chain {chain.name!r}: its singularities do not factor through one parameter "
        "(neither the Barrett WAM closed form nor the elbow index sin(theta_4 - phi) divides every column minor "
        "det J_i), so the singularity-consistent method has no index D_e for it"
    )


def _index_gradient(
    index_function: Callable[[np.ndarray], np.ndarray], q: np.ndarray, step: float = 1e-6
) -> np.ndarray:
    """Central-difference gradient of an index function, shape ``(..., n)``."""
    q = np.asarray(q, dtype=float)
    n = q.shape[-1]
    grad = np.empty(q.shape)
    for k in range(n):
        e = np.zeros(n)
        e[k] = step
        grad[..., k] = (np.asarray(index_function(q + e)) - np.asarray(index_function(q - e))) / (2.0 * step)
    return grad


@dataclass(frozen=True)
class FactorCheck:
    """Outcome of :func:`check_single_parameter`.

    ``factors`` is true when, on every sampled point of ``D_e = 0``, the
    Jacobian is rank deficient (all minors vanish) and every ratio
    ``det J_i / D_e`` has the same limit from both sides (``worst_ratio_jump``
    is the largest difference between the two sides relative to the largest ratio).
    """

    factors: bool
    samples: int
    worst_minor_on_set: float
    worst_ratio_jump: float


def check_single_parameter(
    chain: SerialChain,
    index_function: Callable[[np.ndarray], np.ndarray],
    samples: int = 32,
    seed: int | np.random.Generator = 0,
    tolerance: float = 1e-5,
) -> FactorCheck:
    """Test numerically whether ``D_e`` factors every column minor: ``det J_i = D_e D_i`` (paper 003 section 3.3).

    Random configurations are moved onto ``D_e = 0`` by Newton steps along
    the gradient.  There, the minors must vanish (relative to their size at
    the start) and ``det J_i / D_e`` evaluated at ``+-h`` along the gradient
    must agree (a simple common zero, no other factor changing sign) and
    stay bounded (no higher-order zero of ``D_e``).
    """
    # A chain singular everywhere (every minor 0 at a random configuration) gives 0 / 0 here: NaN, and not
    # factored, without numpy's warning reaching the caller.
    with np.errstate(divide="ignore", invalid="ignore"):
        rng = np.random.default_rng(seed)
        q = rng.uniform(-np.pi, np.pi, (samples, chain.n))
        scale = np.max(np.abs(column_minors(chain.jacobian(q))), axis=-1)
        for _ in range(50):
            value = np.asarray(index_function(q), dtype=float)
            grad = _index_gradient(index_function, q)
            norm2 = np.maximum(np.sum(grad * grad, axis=-1), 1e-300)
            q = q - (value / norm2)[..., None] * grad
        value = np.asarray(index_function(q), dtype=float)
        on_set = np.abs(value) < 1e-10
        grad = _index_gradient(index_function, q)
        unit = grad / np.maximum(np.linalg.norm(grad, axis=-1, keepdims=True), 1e-300)
        h = 1e-4
        worst_minor = float(np.max(np.abs(column_minors(chain.jacobian(q))).max(axis=-1) / scale))
        def ratios_at(distance: float) -> np.ndarray:
            qh = q + distance * unit
            return column_minors(chain.jacobian(qh)) / np.asarray(index_function(qh))[..., None]

        near_plus, near_minus, far = ratios_at(h), ratios_at(-h), ratios_at(10.0 * h)
        # A common simple zero leaves det J_i / D_e continuous (jump O(h)) and
        # bounded; a minor that vanishes without the factor makes the ratio flip
        # sign (jump ~ its size), an index vanishing to higher order makes it blow up.
        size = max(float(np.max(np.abs(near_plus))), float(np.max(np.abs(near_minus))), 1e-300)
        worst_jump = float(np.max(np.abs(near_plus - near_minus)) / size)
        growth = size / max(float(np.max(np.abs(far))), 1e-300)
    factors = bool(np.all(on_set) and worst_minor < tolerance and worst_jump < 100.0 * h and growth < 2.0)
    return FactorCheck(factors=factors, samples=samples, worst_minor_on_set=worst_minor, worst_ratio_jump=worst_jump)
