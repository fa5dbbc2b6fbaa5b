"""Time per control step of each velocity-IK method on the Barrett WAM (paper 003).

Table 1, the array API: one step = one 6 x 7 Jacobian (``SerialChain.jacobian``)
+ the method's solve for a single configuration, plus the solve alone and a
batched solve (per configuration, 1000 random configurations).  ``sc`` is the
lean SC step, ``sc-exact`` the 49-determinant cofactor path.  The lean SC
method's bound step is the one-configuration controller, so its batched solve
is the batched form of the same formula,
:func:`~redkin.velocity.lean_step.lean_singularity_consistent` (one SVD per
configuration).

Table 2, the control-loop entry points (:mod:`redkin.velocity.controller`):
``step(q, twist)`` with the robot bound once -- input check, compiled Jacobian,
``D_e``, blend and one LAPACK ``dgelss`` solve -- at three places: outside the
singular region (the paper's ``q0``), inside it, and inside the exact-fallback
band ``|D_e| < eps / 100`` (the worst case).  Target from issue 5: an SC step
under 50 us, reported beside the pseudoinverse step.
Run: ``python benchmarks/bench_velocity.py``.
"""

from __future__ import annotations

import os

import numpy as np

from redkin.chain import SerialChain
from redkin.models import barrett_wam
from redkin.velocity import (
    AdaptiveDampedLeastSquares,
    DampedLeastSquares,
    Pseudoinverse,
    PseudoinverseController,
    SingularityConsistent,
    SingularityConsistentController,
    WamFactorisation,
    lean_singularity_consistent,
)
from redkin.velocity.methods import Method, Step
from timing import best_time  # benchmarks/timing.py (the script's folder is on sys.path)


def per_call(func, number: int) -> float:
    """Microseconds per call of ``func``: the best of five rounds of ``number`` calls."""
    return best_time(func, repeat=5, number=number) * 1e6


def main() -> None:
    print(f"load average (1, 5, 15 min): {' '.join(f'{v:.2f}' for v in os.getloadavg())}, {os.cpu_count()} cores")
    chain = barrett_wam()
    factor = WamFactorisation.from_chain(chain)
    q = np.radians([30.0, 20.0, 50.0, 70.0, 40.0, 100.0, 0.0])
    twist = np.array([0.15, 0.0, 0.0, 0.0, 0.1, 0.0])
    batch_q = np.random.default_rng(0).uniform(-np.pi, np.pi, (1000, 7))
    print(f"Jacobian alone, one q: SerialChain.jacobian {per_call(lambda: chain.jacobian(q), 2000):6.1f} us")
    print("\nTable 1: array API (method.bind(chain, q0) -> step(q, J, twist))")
    print(f"{'method':<14}{'solve [us]':>12}{'step [us]':>12}{'batched solve [us/q]':>22}")
    for label, solve_us, step_us, batch_us in array_api_rows(chain, factor, q, twist, batch_q):
        print(f"{label:<14}{solve_us:12.1f}{step_us:12.1f}{batch_us:22.2f}")

    print("\nTable 2: control-loop entry points (robot bound once -> step(q, twist)), Jacobian included")
    sc = SingularityConsistentController(chain, q, eps=0.1)
    pinv = PseudoinverseController(chain)
    places = {"outside region (q0)": q}
    for label, index in (("inside region, D_e = 0.05", 0.05), ("fallback band, D_e = 1e-4", 1e-4)):
        places[label] = on_index(factor, q, index)
    print(f"{'configuration':<28}{'D_e':>9}{'sc step [us]':>15}{'pinv step [us]':>16}")
    for label, where in places.items():
        sc_us = per_call(lambda: sc(where, twist), 2000)
        pinv_us = per_call(lambda: pinv(where, twist), 2000)
        print(f"{label:<28}{float(factor.index(where)):9.4f}{sc_us:15.1f}{pinv_us:16.1f}")
    print("target: SC step < 50 us (1 kHz loop x 20)")


def array_api_rows(
    chain: SerialChain, factor: WamFactorisation, q: np.ndarray, twist: np.ndarray, batch_q: np.ndarray,
    calls: int = 500,
) -> list[tuple[str, float, float, float]]:
    """Table 1 rows: per method, us of the solve and of Jacobian + solve for one ``q``, and us per ``q`` of a batch."""
    jac = chain.jacobian(q)
    batch_j = chain.jacobian(batch_q)
    methods = [Pseudoinverse(), DampedLeastSquares(0.05), AdaptiveDampedLeastSquares(0.05, 0.05),
               SingularityConsistent(eps=0.1, factorisation=factor),
               SingularityConsistent(eps=0.1, factorisation=factor, lean=False, label="sc-exact")]
    rows = []
    for method in methods:
        step = method.bind(chain, q)
        batched = batched_step(method, chain, q)
        rows.append((
            method.label,
            per_call(lambda: step(q, jac, twist), calls),
            per_call(lambda: step(q, chain.jacobian(q), twist), calls),
            per_call(lambda: batched(batch_q, batch_j, twist), 3) / len(batch_q),
        ))
    return rows


def batched_step(method: Method, chain: SerialChain, q0: np.ndarray) -> Step:
    """``method``'s ``step(q, J, twist)`` for a batch of configurations.

    The lean SC method steps through the one-configuration controller
    (``SingularityConsistentController``); its batched form is
    ``lean_singularity_consistent``, with the same ``b_ep``.  Every other
    method's bound step takes batches as it is.
    """
    if not (isinstance(method, SingularityConsistent) and method.lean):
        return method.bind(chain, q0)
    factor = method.resolve(chain)
    controller = SingularityConsistentController(chain, q0, method.eps, factor, method.direction)
    return lambda q, jac, twist: lean_singularity_consistent(
        jac, twist, factor.index(q), lambda: factor.factors(q, jac), method.eps, controller.direction,
        method.self_motion, method.modify_rotation,
    )


def on_index(factor: WamFactorisation, q: np.ndarray, index: float) -> np.ndarray:
    """``q`` with ``q4`` moved so that ``D_e = index`` (the branch nearest the elbow-stretch zero)."""
    amplitude = np.hypot(factor.a * (factor.d3 + factor.d5), factor.a**2 - factor.d3 * factor.d5)
    phase = np.arctan2(factor.a * (factor.d3 + factor.d5), factor.a**2 - factor.d3 * factor.d5)
    moved = q.copy()
    moved[3] = np.arcsin(index / amplitude) - phase  # D_e = amplitude sin(q4 + phase)
    return moved


if __name__ == "__main__":
    main()
