"""Serial-chain speed: single-call FK and Jacobian latency, batch FK throughput (PA10-7C).

Run:  python benchmarks/bench_chain.py
Compares, in the same run, redkin's closed-form column propagation with a
straightforward numpy implementation that builds one (N, 4, 4) DH matrix per
joint and multiplies the stacks, and with roboticstoolbox-python where it is
installed (`pip install roboticstoolbox-python`; skipped with a line if not).
"""

from __future__ import annotations

import platform
import time

import numpy as np

from redkin.models import pa10_7c
from timing import best_time  # benchmarks/timing.py (the script's folder is on sys.path)


def loop_over_joints_fk(chain, q: np.ndarray) -> np.ndarray:
    """Baseline: batched 4x4 DH matrices per joint, multiplied with np.matmul."""
    theta = chain.offset + chain.sign * q
    pose = np.broadcast_to(chain.base, q.shape[:-1] + (4, 4)).copy()
    for i in range(chain.n):
        ct, st = np.cos(theta[..., i]), np.sin(theta[..., i])
        ca, sa = np.cos(chain.alpha[i]), np.sin(chain.alpha[i])
        a = np.zeros(q.shape[:-1] + (4, 4))
        a[..., 0, 0], a[..., 0, 1], a[..., 0, 2], a[..., 0, 3] = ct, -st * ca, st * sa, chain.a[i] * ct
        a[..., 1, 0], a[..., 1, 1], a[..., 1, 2], a[..., 1, 3] = st, ct * ca, -ct * sa, chain.a[i] * st
        a[..., 2, 1], a[..., 2, 2], a[..., 2, 3] = sa, ca, chain.d[i]
        a[..., 3, 3] = 1.0
        pose = pose @ a
    return pose @ chain.tool


def main() -> None:
    chain = pa10_7c()
    rng = np.random.default_rng(0)
    q1 = rng.uniform(-1, 1, 7)
    batch = rng.uniform(-1, 1, (100_000, 7))
    assert np.allclose(loop_over_joints_fk(chain, batch[:100]), chain.fk(batch[:100]))

    rows = []
    fk1 = best_time(lambda: chain.fk(q1), number=2000)
    jac1 = best_time(lambda: chain.jacobian(q1), number=2000)
    ours_batch = best_time(lambda: chain.fk(batch), repeat=5)
    loop_batch = best_time(lambda: loop_over_joints_fk(chain, batch), repeat=5)
    rows.append(("redkin fk, one configuration", f"{fk1 * 1e6:8.1f} us", ""))
    rows.append(("redkin jacobian, one configuration", f"{jac1 * 1e6:8.1f} us", ""))
    rows.append(("redkin fk, batch of 100 000", f"{ours_batch * 1e3:8.1f} ms", f"{batch.shape[0] / ours_batch / 1e6:.2f} M configs/s"))
    rows.append(("numpy loop-over-joints fk, batch of 100 000", f"{loop_batch * 1e3:8.1f} ms",
                 f"redkin is {loop_batch / ours_batch:.1f}x faster"))

    try:
        import roboticstoolbox as rtb

        robot = rtb.DHRobot(
            [rtb.RevoluteDH(d=chain.d[i], a=chain.a[i], alpha=chain.alpha[i]) for i in range(7)], name="pa10"
        )
        ets = robot.ets()  # the C++ path of roboticstoolbox; DHRobot.fkine is pure Python
        assert np.allclose(ets.eval(q1), chain.fk(q1))
        rtb_fk = best_time(lambda: ets.eval(q1), number=2000)
        rtb_jac = best_time(lambda: ets.jacob0(q1), number=2000)
        rtb_batch = best_time(lambda: ets.fkine(batch), repeat=3)
        rows.append(("roboticstoolbox ETS eval (C++), one configuration", f"{rtb_fk * 1e6:8.1f} us", f"redkin/rtb time ratio {fk1 / rtb_fk:.2f}"))
        rows.append(("roboticstoolbox ETS jacob0 (C++), one configuration", f"{rtb_jac * 1e6:8.1f} us", f"redkin/rtb time ratio {jac1 / rtb_jac:.2f}"))
        rows.append(("roboticstoolbox ETS fkine, batch of 100 000", f"{rtb_batch * 1e3:8.1f} ms", f"redkin is {rtb_batch / ours_batch:.1f}x faster"))
    except ImportError:
        rows.append(("roboticstoolbox-python", "not installed", "skipped (pip install roboticstoolbox-python)"))

    print(f"# PA10-7C chain benchmark -- {platform.processor() or platform.machine()}, "
          f"python {platform.python_version()}, numpy {np.__version__}, {time.strftime('%Y-%m-%d')}")
    width = max(len(r[0]) for r in rows)
    for name, value, note in rows:
        print(f"{name:<{width}}  {value:>12}  {note}")


if __name__ == "__main__":
    main()
