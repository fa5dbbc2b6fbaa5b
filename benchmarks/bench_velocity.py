"""Time per control step of each velocity-IK method on the Barrett WAM (paper 003), beside roboticstoolbox.

Run: ``python benchmarks/bench_velocity.py``.

Peer: roboticstoolbox-python's C++ Jacobian, ``ets.jacob0(q)`` of a
``DHRobot`` built from the WAM's DH rows (``bench_chain.rtb_ets``; checked
equal to ``SerialChain.jacobian`` to 1e-12).  rtb has no singularity-
consistent step; issue 13's target is a whole SC step, Jacobian and input
checks included, within 2 x rtb's Jacobian alone.  The one-call rows are
timed in rounds of about 10 ms (``timing.best_time_short_rounds``), the
same for both libraries, in one run.

Table 1, the control-loop entry points (:mod:`redkin.velocity.controller`):
``step(q, twist)`` with the robot bound once -- input checks, compiled
Jacobian, ``D_e`` and the compiled step -- at three places: outside the
singular region (the paper's ``q0``), inside it, and inside the exact band
``|D_e| < eps / 100`` (the adjugate path, the worst case); each as a ratio
to rtb's ``jacob0``.

Table 2, the array API: one step = one 6 x 7 Jacobian (``SerialChain.jacobian``)
+ the method's bound step for a single configuration, the bound step alone,
and the bound step on a batch of 10 000 random configurations (per
configuration; the compiled steps run in parallel over the batch).  ``sc``
is the lean SC step, ``sc-exact`` the adjugate path everywhere.
"""

from __future__ import annotations

import os
import platform

import numpy as np
from bench_chain import rtb_ets, versions  # benchmarks/ is on sys.path when a script of it runs
from timing import best_time, best_time_short_rounds

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
)

BATCH = 10_000


def per_call(func, number: int) -> float:
    """Microseconds per call of ``func``: the best of five rounds of ``number`` calls."""
    return best_time(func, repeat=5, number=number) * 1e6


def short_rounds(func) -> float:
    """Microseconds per call in rounds of about 10 ms (as the peer is timed)."""
    return best_time_short_rounds(func) * 1e6


def main() -> None:
    from redkin import thread_count

    print(f"# velocity benchmark -- {platform.machine()}, {os.cpu_count()} cores ({thread_count()} redkin batch "
          f"threads), python {platform.python_version()}, numpy {np.__version__}, {versions()}, "
          f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    chain = barrett_wam()
    factor = WamFactorisation.from_chain(chain)
    q = np.radians([30.0, 20.0, 50.0, 70.0, 40.0, 100.0, 0.0])
    twist = np.array([0.15, 0.0, 0.0, 0.0, 0.1, 0.0])
    ours = short_rounds(lambda: chain.jacobian(q))
    ets = rtb_ets(chain)
    if ets is None:
        print("roboticstoolbox-python not installed: ratios skipped (pip install -e '.[bench]')")
        peer = float("nan")
    else:
        assert np.allclose(ets.jacob0(q), chain.jacobian(q), rtol=0, atol=1e-12)
        peer = short_rounds(lambda: ets.jacob0(q))
    print(f"Jacobian alone, one q: redkin SerialChain.jacobian {ours:6.2f} us, rtb ets.jacob0 (C++) {peer:6.2f} us, "
          f"ratio {ours / peer:.2f}")

    print("\nTable 1: control-loop entry points (robot bound once -> step(q, twist)), Jacobian included; "
          "ratio = step / rtb jacob0 (target: SC <= 2)")
    print(f"{'configuration':<28}{'D_e':>9}{'sc [us]':>10}{'ratio':>7}{'pinv [us]':>11}{'ratio':>7}")
    sc = SingularityConsistentController(chain, q, eps=0.1)
    pinv = PseudoinverseController(chain)
    for label, where in places(factor, q).items():
        sc_us = short_rounds(lambda: sc(where, twist))
        pinv_us = short_rounds(lambda: pinv(where, twist))
        print(f"{label:<28}{float(factor.index(where)):9.4f}{sc_us:10.2f}{sc_us / peer:7.2f}"
              f"{pinv_us:11.2f}{pinv_us / peer:7.2f}")

    batch_q = np.random.default_rng(0).uniform(-np.pi, np.pi, (BATCH, 7))
    print("\nTable 2: array API (method.bind(chain, q0) -> step(q, J, twist))")
    print(f"{'method':<14}{'step alone [us]':>17}{'with J [us]':>13}{f'batch of {BATCH} [us/q]':>24}")
    for label, solve_us, step_us, batch_us in array_api_rows(chain, factor, q, twist, batch_q):
        print(f"{label:<14}{solve_us:17.2f}{step_us:13.2f}{batch_us:24.3f}")


def places(factor: WamFactorisation, q: np.ndarray) -> dict[str, np.ndarray]:
    """The paper's ``q0`` (outside the singular region), one ``q`` inside it and one in the exact band."""
    found = {"outside region (q0)": q}
    for label, index in (("inside region, D_e = 0.05", 0.05), ("exact band, D_e = 1e-4", 1e-4)):
        found[label] = on_index(factor, q, index)
    return found


def array_api_rows(
    chain: SerialChain, factor: WamFactorisation, q: np.ndarray, twist: np.ndarray, batch_q: np.ndarray,
    calls: int = 500,
) -> list[tuple[str, float, float, float]]:
    """Rows of Table 2: per method, us of the bound step and of Jacobian + step for one ``q``, and us per ``q`` of
    a batch."""
    jac = chain.jacobian(q)
    batch_j = chain.jacobian(batch_q)
    methods = [Pseudoinverse(), DampedLeastSquares(0.05), AdaptiveDampedLeastSquares(0.05, 0.05),
               SingularityConsistent(eps=0.1, factorisation=factor),
               SingularityConsistent(eps=0.1, factorisation=factor, lean=False, label="sc-exact")]
    rows = []
    for method in methods:
        step = method.bind(chain, q)
        rows.append((
            method.label,
            per_call(lambda: step(q, jac, twist), calls),
            per_call(lambda: step(q, chain.jacobian(q), twist), calls),
            per_call(lambda: step(batch_q, batch_j, twist), 3) / len(batch_q),
        ))
    return rows


def on_index(factor: WamFactorisation, q: np.ndarray, index: float) -> np.ndarray:
    """``q`` with ``q4`` moved so that ``D_e = index`` (the branch nearest the elbow-stretch zero)."""
    amplitude = np.hypot(factor.a * (factor.d3 + factor.d5), factor.a**2 - factor.d3 * factor.d5)
    phase = np.arctan2(factor.a * (factor.d3 + factor.d5), factor.a**2 - factor.d3 * factor.d5)
    moved = q.copy()
    moved[3] = np.arcsin(index / amplitude) - phase  # D_e = amplitude sin(q4 + phase)
    return moved


if __name__ == "__main__":
    main()
