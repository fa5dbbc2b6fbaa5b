"""Time per control step of each velocity-IK method on the Barrett WAM (paper 003).

One step = one 6 x 7 Jacobian (``SerialChain.jacobian``) + the method's solve,
for a single configuration (the control-loop case), plus the solve alone and
a batched solve (per configuration).  ``sc`` is the lean SC step (one SVD,
:mod:`redkin.velocity.lean_step`), ``sc-exact`` the 49-determinant cofactor
path; the last column uses the scalar single-q Jacobian ``SingleJacobian``.  Target from issue 5: an SC step under
50 us.  Run: ``python benchmarks/bench_velocity.py``.
"""

from __future__ import annotations

import timeit

import numpy as np

from redkin.models import barrett_wam
from redkin.velocity import (
    AdaptiveDampedLeastSquares,
    DampedLeastSquares,
    Pseudoinverse,
    SingleJacobian,
    SingularityConsistent,
    WamFactorisation,
)


def per_call(func, number: int) -> float:
    return min(timeit.repeat(func, number=number, repeat=5)) / number * 1e6


def main() -> None:
    chain = barrett_wam()
    factor = WamFactorisation.from_chain(chain)
    q = np.radians([30.0, 20.0, 50.0, 70.0, 40.0, 100.0, 0.0])
    twist = np.array([0.15, 0.0, 0.0, 0.0, 0.1, 0.0])
    jac = chain.jacobian(q)
    batch_q = np.random.default_rng(0).uniform(-np.pi, np.pi, (1000, 7))
    batch_j = chain.jacobian(batch_q)
    methods = [Pseudoinverse(), DampedLeastSquares(0.05), AdaptiveDampedLeastSquares(0.05, 0.05),
               SingularityConsistent(eps=0.1, factorisation=factor),
               SingularityConsistent(eps=0.1, factorisation=factor, lean=False, label="sc-exact")]
    single = SingleJacobian(chain)
    jac_us = per_call(lambda: chain.jacobian(q), 2000)
    single_us = per_call(lambda: single(q), 2000)
    print(f"Jacobian alone (SerialChain.jacobian, one q): {jac_us:8.1f} us")
    print(f"Jacobian alone (SingleJacobian, one q):       {single_us:8.1f} us")
    print(f"{'method':<14}{'solve [us]':>12}{'step [us]':>12}{'step, SingleJacobian [us]':>27}"
          f"{'batched solve [us/q]':>22}")
    for method in methods:
        step = method.bind(chain, q)
        solve_us = per_call(lambda: step(q, jac, twist), 500)
        step_us = per_call(lambda: step(q, chain.jacobian(q), twist), 500)
        lean_us = per_call(lambda: step(q, single(q), twist), 500)
        batch_us = per_call(lambda: step(batch_q, batch_j, twist), 3) / len(batch_q)
        print(f"{method.label:<14}{solve_us:12.1f}{step_us:12.1f}{lean_us:27.1f}{batch_us:22.2f}")
    print("target: SC step < 50 us (1 kHz loop x 20)")


if __name__ == "__main__":
    main()
