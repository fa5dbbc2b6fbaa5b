"""Serial-chain speed beside the peers: FK and Jacobian of one configuration, batch FK, cold start (issue 13).

Run:  python benchmarks/bench_chain.py [--skip-cold]

Arms: the PA10-7C (standard DH) and the Franka Panda (modified DH, flange
tool), each as redkin's model and, built from the same numbers, as

* roboticstoolbox-python: a ``DHRobot`` of ``RevoluteDH`` / ``RevoluteMDH``
  links with the tool, converted once with ``.ets()``; its C++ methods on
  numpy arrays: ``ets.eval(q)`` (4x4 array) and ``ets.jacob0(q)``, and
  ``ets.fkine(Q)`` for a batch (C++ loop, returns an ``SE3`` of N poses);
* pinocchio: a ``Model`` of revolute joints placed as the chain's joint
  frames at q = 0, with an operational frame at the tool;
  ``framesForwardKinematics`` and the frame's ``homogeneous`` 4x4 for FK,
  ``computeFrameJacobian(..., LOCAL_WORLD_ALIGNED)`` (world axes, linear
  rows first, as redkin's) for the Jacobian.

Each peer's FK and Jacobian are checked equal to redkin's (1e-12) before
timing.  One-call rows are timed in rounds of about 10 ms
(``timing.best_time_short_rounds``), the same for every library, and are
redkin's public API, validation included.  A peer that is not installed is
skipped with a line (``pip install -e ".[bench]"``).

Cold start: a fresh numba cache directory (``NUMBA_CACHE_DIR``) in a new
process, the first FK, Jacobian and frames calls of one configuration and of
a batch on both conventions (everything compiled), then the same in a second
process (loaded from the cache); and ``redkin fk`` on a warm cache.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np
from timing import best_time, best_time_short_rounds  # benchmarks/timing.py (the script's folder is on sys.path)

from redkin.chain import SerialChain
from redkin.models import franka_panda, pa10_7c

BATCH = 1_000_000
FIRST_CALLS = """
import time
start = time.perf_counter()
import numpy as np
from redkin.models import franka_panda, pa10_7c
for arm in (pa10_7c(), franka_panda()):
    one, many = np.zeros(7), np.random.default_rng(0).uniform(-1, 1, (1000, 7))
    for method in (arm.fk, arm.jacobian, arm.frames):
        method(one), method(many)
print(time.perf_counter() - start)
"""


def loop_over_joints_fk(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """Baseline: batched 4x4 DH matrices per joint (standard DH), multiplied with np.matmul."""
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


def rtb_ets(chain: SerialChain):
    """roboticstoolbox's ETS of ``chain`` (a DHRobot of the same DH rows and tool, converted once), or None."""
    try:
        import roboticstoolbox as rtb
        from spatialmath import SE3
    except ImportError:
        return None
    link = rtb.RevoluteDH if chain.convention == "dh" else rtb.RevoluteMDH
    links = [link(d=chain.d[i], a=chain.a[i], alpha=chain.alpha[i], offset=chain.offset[i]) for i in range(chain.n)]
    assert np.all(chain.sign == 1.0) and np.array_equal(chain.base, np.eye(4))
    return rtb.DHRobot(links, tool=SE3(chain.tool, check=False), name=chain.name).ets()


def pinocchio_model(chain: SerialChain):
    """pinocchio's model and data of ``chain`` and the id of its tool frame, or None.

    Joint ``i``'s frame at q = 0 is the chain frame its axis belongs to, turned
    by the offset (standard DH: ``frame_{i-1} Rz(offset_i)``; modified DH:
    ``frame_i Tz(-d_i)``); each joint is placed relative to the previous one.
    """
    try:
        import pinocchio as pin
    except ImportError:
        return None
    frames = chain.frames(np.zeros(chain.n))
    joints = []
    for i in range(chain.n):
        if chain.convention == "dh":
            c, s = np.cos(chain.offset[i]), np.sin(chain.offset[i])
            turn = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
            joints.append(frames[i] @ turn)
        else:
            down = np.eye(4)
            down[2, 3] = -chain.d[i]
            joints.append(frames[i + 1] @ down)
    model = pin.Model()
    parent, previous = 0, np.eye(4)
    for i, joint in enumerate(joints):
        axis = pin.JointModelRZ() if chain.sign[i] > 0 else pin.JointModelRevoluteUnaligned(0.0, 0.0, -1.0)
        parent = model.addJoint(parent, axis, pin.SE3(np.linalg.solve(previous, joint)), f"joint{i + 1}")
        previous = joint
    tool = model.addFrame(pin.Frame("tool", parent, pin.SE3(np.linalg.solve(previous, frames[-1])),
                                    pin.FrameType.OP_FRAME))
    return pin, model, model.createData(), tool


def peer_rows(chain: SerialChain, q1: np.ndarray, batch: np.ndarray, fk1: float, jac1: float, ours_batch: float):
    rows = []
    ets = rtb_ets(chain)
    if ets is None:
        rows.append(("roboticstoolbox-python", "not installed", "skipped (pip install roboticstoolbox-python)"))
    else:
        assert np.allclose(ets.eval(q1), chain.fk(q1), rtol=0, atol=1e-12)
        assert np.allclose(ets.jacob0(q1), chain.jacobian(q1), rtol=0, atol=1e-12)
        fk = best_time_short_rounds(lambda: ets.eval(q1))
        jac = best_time_short_rounds(lambda: ets.jacob0(q1))
        few = batch[:100_000]
        fkine = best_time(lambda: ets.fkine(few), repeat=3) / len(few) * len(batch)
        rows.append(("  roboticstoolbox ETS eval (C++), one configuration", f"{fk * 1e6:8.2f} us",
                     f"redkin / rtb {fk1 / fk:.2f}"))
        rows.append(("  roboticstoolbox ETS jacob0 (C++), one configuration", f"{jac * 1e6:8.2f} us",
                     f"redkin / rtb {jac1 / jac:.2f}"))
        rows.append(("  roboticstoolbox ETS fkine, batch (from 100 000)", f"{fkine * 1e3:8.1f} ms",
                     f"{len(batch) / fkine / 1e6:.2f} M configs/s; redkin is {fkine / ours_batch:.0f}x faster"))
    model = pinocchio_model(chain)
    if model is None:
        rows.append(("pinocchio", "not installed", "skipped (pip install pin)"))
    else:
        pin, pmodel, data, tool = model
        local = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

        def fk_pin(q):
            pin.framesForwardKinematics(pmodel, data, q)
            return data.oMf[tool].homogeneous

        assert np.allclose(fk_pin(q1), chain.fk(q1), rtol=0, atol=1e-12)
        assert np.allclose(pin.computeFrameJacobian(pmodel, data, q1, tool, local), chain.jacobian(q1), rtol=0,
                           atol=1e-12)
        fk = best_time_short_rounds(lambda: fk_pin(q1))
        jac = best_time_short_rounds(lambda: pin.computeFrameJacobian(pmodel, data, q1, tool, local))
        few = batch[:100_000]
        loop = best_time(lambda: [fk_pin(q) for q in few], repeat=3) / len(few) * len(batch)
        rows.append(("  pinocchio framesForwardKinematics + 4x4, one configuration", f"{fk * 1e6:8.2f} us",
                     f"redkin / pinocchio {fk1 / fk:.2f}"))
        rows.append(("  pinocchio computeFrameJacobian, one configuration", f"{jac * 1e6:8.2f} us",
                     f"redkin / pinocchio {jac1 / jac:.2f}"))
        rows.append(("  pinocchio, batch as a Python loop (from 100 000)", f"{loop * 1e3:8.1f} ms",
                     f"{len(batch) / loop / 1e6:.2f} M configs/s (no batched call in Python)"))
    return rows


def arm_rows(chain: SerialChain, rng: np.random.Generator) -> list[tuple[str, str, str]]:
    q1 = rng.uniform(-1, 1, chain.n)
    batch = rng.uniform(-1, 1, (BATCH, chain.n))
    fk1 = best_time_short_rounds(lambda: chain.fk(q1))
    jac1 = best_time_short_rounds(lambda: chain.jacobian(q1))
    ours_batch = best_time(lambda: chain.fk(batch), repeat=5)
    jac_batch = best_time(lambda: chain.jacobian(batch), repeat=3)
    rows = [
        (f"{chain.name} ({chain.convention})", "", ""),
        ("  redkin fk, one configuration", f"{fk1 * 1e6:8.2f} us", ""),
        ("  redkin jacobian, one configuration", f"{jac1 * 1e6:8.2f} us", ""),
        (f"  redkin fk, batch of 10^{round(np.log10(BATCH))}", f"{ours_batch * 1e3:8.1f} ms",
         f"{BATCH / ours_batch / 1e6:.2f} M configs/s"),
        (f"  redkin jacobian, batch of 10^{round(np.log10(BATCH))}", f"{jac_batch * 1e3:8.1f} ms",
         f"{BATCH / jac_batch / 1e6:.2f} M configs/s"),
    ]
    if chain.convention == "dh":
        few = batch[:100_000]
        assert np.allclose(loop_over_joints_fk(chain, few[:100]), chain.fk(few[:100]), rtol=0, atol=1e-12)
        loop = best_time(lambda: loop_over_joints_fk(chain, few), repeat=3) / len(few) * len(batch)
        rows.append(("  numpy loop-over-joints fk, batch (from 100 000)", f"{loop * 1e3:8.1f} ms",
                     f"redkin is {loop / ours_batch:.0f}x faster"))
    return rows + peer_rows(chain, q1, batch, fk1, jac1, ours_batch)


def start_rows() -> list[tuple[str, str, str]]:
    """First calls with a fresh numba cache (compiling), then cached; ``redkin fk`` on a warm cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        cold, warm = (float(subprocess.run([sys.executable, "-c", FIRST_CALLS], env=env, capture_output=True,
                                           text=True, check=True).stdout) for _ in range(2))
    command = ["redkin", "fk", "pa10-7c", "0", "0", "0", "0", "0", "0", "0"]
    subprocess.run(command, capture_output=True, check=True)  # warm the default cache
    cli = []
    for _ in range(5):
        start = time.perf_counter()
        subprocess.run(command, capture_output=True, check=True)
        cli.append(time.perf_counter() - start)
    return [
        ("cold start: import + first calls, fresh cache (compiles)", f"{cold:8.2f} s", "target <= 10 s"),
        ("the same, cached", f"{warm:8.2f} s", ""),
        ("redkin fk pa10-7c (a process), warm cache, best of 5", f"{min(cli):8.2f} s",
         f"median {np.median(cli):.2f} s"),
    ]


def versions() -> str:
    import numba

    names = [f"numba {numba.__version__}"]
    for module, label in (("roboticstoolbox", "roboticstoolbox-python"), ("pinocchio", "pinocchio")):
        try:
            names.append(f"{label} {__import__(module).__version__}")
        except ImportError:
            pass
    return ", ".join(names)


def main() -> None:
    from redkin import thread_count

    rng = np.random.default_rng(0)
    rows = arm_rows(pa10_7c(), rng) + arm_rows(franka_panda(), rng)
    if "--skip-cold" not in sys.argv:
        rows += start_rows()
    print(f"# chain benchmark -- {platform.machine()}, {os.cpu_count()} cores "
          f"({thread_count()} redkin batch threads), python {platform.python_version()}, "
          f"numpy {np.__version__}, {versions()}, {time.strftime('%Y-%m-%d')}, load average {os.getloadavg()[0]:.2f}")
    width = max(len(r[0]) for r in rows)
    for name, value, note in rows:
        print(f"{name:<{width}}  {value:>12}  {note}")


if __name__ == "__main__":
    main()
