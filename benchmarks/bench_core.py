"""Issue 13's targets for the compiled core, measured in one run beside the peers, as ratios.

Run:  python benchmarks/bench_core.py [--skip-cold]

One row per target of issue 13: redkin's public API (input checks
included) against the peer named in the row, both timed in the same process
in rounds of about 10 ms (``timing.best_time_short_rounds``), so both are
equally exposed to other load; batches are the best of three calls.  Peers,
each in its best documented configuration (``pip install -e ".[bench]"``;
a missing peer is reported and its ratios skipped):

* ssik 8.2, KUKA iiwa14 (the arm it ships prebuilt, which is redkin's
  ``kuka_iiwa14``): the prepared native C++ ``Solver`` of
  ``ssik.prebuilt.kuka.iiwa14_ik``, ``solve(T, respect_limits=0)``, which
  returns 16 swivel angles x 8 branches; "ssik's time for 8 solutions" is
  its time per pose / 16.
* roboticstoolbox-python 1.5: ``ets.eval(q)`` and ``ets.jacob0(q)`` (C++) of
  a ``DHRobot`` of the same DH rows converted once with ``.ets()``
  (``bench_chain.rtb_ets``).

The cold-start rows (issue 23) run a new process with an empty numba cache
(``NUMBA_CACHE_DIR``) that imports redkin and makes the first call of every
compiled path (:func:`redkin.warm_up.warm_up`, what ``redkin compile`` runs;
``cold_start.py`` lists its sections), then the same again with that cache
filled; then ``redkin reproduce 000`` on another fresh cache (the first section
a newcomer runs).  The command-line rows time whole processes, best of five,
each beside ``python -c "import numpy"`` timed in the same loop.  The steady
batch row makes five consecutive calls of 2x10^5 iiwa poses x 8 branches in
one process and gives each call's rate.  The batch FK and Jacobian rows (issue 42) do the same for 10^6 iiwa
configurations, fresh and into one ``out=`` buffer, beside the two limits measured in the same run: the arithmetic
(one thread's CPU time per configuration, doubled for two cores) and the memory (the bytes each configuration
reads and writes at the bandwidth of a numpy copy).
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np
from bench_chain import rtb_ets, versions  # benchmarks/ is on sys.path when a script of it runs
from timing import best_time, best_time_short_rounds

from redkin.models import barrett_wam, kuka_iiwa14, pa10_7c
from redkin.srs import feasible_arm_angles, feasible_pieces, feasible_pieces_all_branches, ik_all_branches
from redkin.velocity import SingularityConsistentController


def microseconds(function) -> float:
    return best_time_short_rounds(function) * 1e6


def ssik_solver():
    """ssik's prepared native solver of the iiwa14, or None."""
    try:
        from ssik import _native
        from ssik.prebuilt.kuka import iiwa14_ik
    except ImportError:
        return None
    if not _native.native_available():
        return None
    return _native._solver(_native._load_ext(), iiwa14_ik._KB, iiwa14_ik.SOLVER_NAME)


def serial_cpu_rows(arm, q: np.ndarray, poses: np.ndarray) -> list[tuple[str, str, str, str]]:
    """CPU time per item of the serial batch loops on one thread: what two free cores give is twice its inverse.

    The parallel loops' wall time depends on what else runs on the machine;
    this bound does not (beyond what a busy sibling core costs).
    """
    from redkin import _compiled as compiled

    threshold = compiled.PARALLEL_BATCH
    compiled.PARALLEL_BATCH = len(q) + 1  # serial loops only
    try:
        def cpu(function, count: int) -> float:
            function()
            best = float("inf")
            for _ in range(5):
                start = time.process_time()
                function()
                best = min(best, time.process_time() - start)
            return best / count
        fk = cpu(lambda: arm.fk(q), len(q))
        ik8 = cpu(lambda: ik_all_branches(arm, poses, 0.3), len(poses))
        few = poses[:50_000]
        one = cpu(lambda: feasible_pieces(arm, few, "+-+"), len(few))
        eight = cpu(lambda: feasible_pieces_all_branches(arm, few), 8 * len(few))
    finally:
        compiled.PARALLEL_BATCH = threshold
    return [
        ("  serial CPU per pose, 8 branches (one thread)", f"{ik8 * 1e9:.0f} ns",
         f"2 free cores: {16 / ik8 / 1e6:.1f} M/s", ""),
        ("  serial CPU per pose-branch, one branch's feasible set", f"{one * 1e9:.0f} ns",
         f"2 free cores: {2 / one / 1e6:.2f} M/s", ""),
        ("  serial CPU per pose-branch, all 8 branches' sets", f"{eight * 1e9:.0f} ns",
         f"2 free cores: {2 / eight / 1e6:.2f} M/s", ""),
        ("  serial CPU per configuration, FK", f"{fk * 1e9:.0f} ns", f"2 free cores: {2 / fk / 1e6:.1f} M/s", ""),
    ]


def copy_bandwidth() -> float:
    """The machine's memory bandwidth as numpy's copy of 256 MB into another 256 MB sees it, best of five [GB/s,
    bytes read plus bytes written]: the physical limit of a batch that only streams its inputs and outputs."""
    source = np.ones(32_000_000)
    target = np.empty_like(source)
    seconds = best_time(lambda: np.copyto(target, source), repeat=5)
    return 2.0 * source.nbytes / seconds / 1e9


def fk_jacobian_rows(chain, bandwidth: float, count: int = 1_000_000) -> list[tuple[str, str, str, str]]:
    """Batch FK and Jacobians of ``count`` configurations of ``chain``, five calls in a row each way (a fresh result,
    and into one ``out=`` buffer), against the two physical limits measured in the same run: the arithmetic (one
    thread's CPU time per configuration, serial, so two free cores do twice its inverse) and the memory (the bytes
    each configuration reads and writes, 7 joint values and the 4x4 pose or the 6x7 Jacobian, at the copy
    bandwidth of :func:`copy_bandwidth`)."""
    from redkin import _compiled as compiled

    q = np.random.default_rng(1).uniform(-2.0, 2.0, (count, chain.n))
    rows = [("memory bandwidth, numpy copy of 256 MB (read + write)", f"{bandwidth:.1f} GB/s", "", "")]
    for label, call, shape in (("FK", chain.fk, (4, 4)), ("Jacobian", chain.jacobian, (6, chain.n))):
        threshold = compiled.PARALLEL_BATCH
        compiled.PARALLEL_BATCH = count + 1  # one thread: the arithmetic's time per configuration
        try:
            serial = q[:max(1, count // 10)]
            call(serial)
            cpu = min(_cpu_seconds(lambda: call(serial)) for _ in range(3)) / len(serial)
        finally:
            compiled.PARALLEL_BATCH = threshold
        arithmetic = 2.0 / cpu / 1e6  # M/s on two free cores
        bytes_each = 8 * (chain.n + int(np.prod(shape)))
        memory = bandwidth * 1e9 / bytes_each / 1e6
        buffer = np.empty((count, *shape))
        for way, out in (("a fresh result each call", None), ("into one out= buffer", buffer)):
            rates = []
            for _ in range(5):
                start = time.perf_counter()
                call(q, out=out)
                rates.append(count / (time.perf_counter() - start) / 1e6)
            rows.append((f"batch {label}, {count:.0e} configurations, 5 calls, {way}",
                         " ".join(f"{r:.1f}" for r in rates) + " M/s",
                         f"slowest {min(rates) / arithmetic:.2f} x arithmetic", ""))
        rows.append((f"  {label} limits: arithmetic on 2 cores ({cpu * 1e9:.0f} ns a configuration on one)",
                     f"{arithmetic:.1f} M/s", f"memory ({bytes_each} B each) {memory:.0f} M/s",
                     f"{memory / arithmetic:.0f} x above the arithmetic"))
    return rows


def _cpu_seconds(function) -> float:
    start = time.process_time()
    function()
    return time.process_time() - start


def _process_seconds(command: list[str], env: dict | None = None) -> float:
    start = time.perf_counter()
    subprocess.run(command, capture_output=True, env=env)
    return time.perf_counter() - start


def command_line_rows() -> list[tuple[str, str, str, str]]:
    """``redkin --help``, an argument error and a warm ``redkin fk``, each best of five beside ``import numpy``."""
    numpy_only = [sys.executable, "-c", "import numpy"]
    subprocess.run(["redkin", "fk", "pa10-7c", *["0.1"] * 7], capture_output=True)  # the cache filled
    rows = []
    for label, command, target in (
        ("redkin --help", ["redkin", "--help"], 2.0),
        ("an argument error (redkin fk)", ["redkin", "fk"], 2.0),
        ("warm redkin fk pa10-7c 0.1 x 7", ["redkin", "fk", "pa10-7c", *["0.1"] * 7], 3.0),
    ):
        ours, base = [], []
        for _ in range(5):
            ours.append(_process_seconds(command))
            base.append(_process_seconds(numpy_only))
        rows.append((label, f"{min(ours):.3f} s", f"{min(ours) / min(base):.2f} x import numpy",
                     f"<= {target:g} x import numpy"))
    return rows


def cold_rows() -> list[tuple[str, str, str, str]]:
    """The first call of every compiled path on a fresh cache, then filled; the first reproduce section, fresh."""
    from cold_start import run

    rows = []
    with tempfile.TemporaryDirectory() as cache:
        cold, warm = run(cache)[-1], run(cache)[-1]
    rows.append(("cold start: every compiled path once, fresh cache (wall, CPU)", f"{cold[1]:.1f} s, {cold[2]:.1f} s",
                 "", "<= 10 s"))
    rows.append(("  the same in a new process, cache filled", f"{warm[1]:.2f} s", "", ""))
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        seconds = _process_seconds(["redkin", "reproduce", "000", "--quiet", "--out", out], env)
    rows.append(("first redkin reproduce 000, fresh cache", f"{seconds:.1f} s", "", ""))
    return rows


def main() -> None:
    from redkin import thread_count

    print(f"# issue 13 targets -- {platform.machine()}, {os.cpu_count()} cores ({thread_count()} redkin batch "
          f"threads), python {platform.python_version()}, numpy {np.__version__}, "
          f"{versions()}, load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    rows: list[tuple[str, str, str, str]] = []
    rng = np.random.default_rng(0)

    # --- S-R-S IK and feasible sets beside ssik (iiwa14, same poses)
    iiwa = kuka_iiwa14()
    targets = iiwa.fk(rng.uniform(-2.0, 2.0, (10, 7)))
    solver = ssik_solver()
    ssik8 = float("nan")
    if solver is None:
        rows.append(("ssik", "not installed or no native extension", "", "skipped"))
    else:
        ssik8 = np.mean([microseconds(lambda: solver.solve(t, 0)) for t in targets]) / 16.0
        rows.append(("ssik 8.2 native C++ IK, 8 solutions (1/16 of one call)", f"{ssik8:.2f} us", "", ""))
    ours = np.mean([microseconds(lambda: ik_all_branches(iiwa, t, 0.3)) for t in targets])
    rows.append(("one pose, 8 branches: ik_all_branches(chain, pose, psi)", f"{ours:.2f} us",
                 f"{ours / ssik8:.2f} x ssik 8 solutions", "<= 0.25"))
    one = np.mean([microseconds(lambda: feasible_pieces(iiwa, t, "+-+")) for t in targets])
    rows.append(("one pose, feasible set of one branch: feasible_pieces", f"{one:.2f} us",
                 f"{one / ssik8:.2f} x ssik 8 solutions", "<= 1"))
    arcs = np.mean([microseconds(lambda: feasible_arm_angles(iiwa, t, "+-+")) for t in targets])
    rows.append(("  the same as ArcSets: feasible_arm_angles", f"{arcs:.2f} us", f"{arcs / ssik8:.2f} x", ""))
    every = np.mean([microseconds(lambda: feasible_pieces_all_branches(iiwa, t)) for t in targets])
    rows.append(("one pose, all 8 branches' feasible sets: feasible_pieces_all_branches", f"{every:.2f} us",
                 f"{every / ssik8:.2f} x ssik 8 solutions", "<= 4"))

    # --- batches (PA10, both cores)
    pa10 = pa10_7c().with_limits(np.full(7, -2.5), np.full(7, 2.5))
    q_batch = rng.uniform(-np.pi, np.pi, (1_000_000, 7))
    poses = pa10.fk(q_batch)
    seconds = best_time(lambda: ik_all_branches(pa10, poses, 0.3), repeat=3)
    rows.append(("batch of 10^6 poses x 8 branches", f"{8 / seconds:.1f} M solutions/s", "", ">= 20 M/s"))
    few = poses[:200_000]
    seconds = best_time(lambda: feasible_pieces(pa10, few, "+-+"), repeat=3)
    rows.append(("batch feasible sets (2x10^5 poses, one branch)", f"{len(few) / seconds / 1e6:.2f} M pose-branches/s",
                 "", ">= 1 M/s"))

    rows.extend(serial_cpu_rows(pa10, q_batch[:200_000], poses[:200_000]))

    # --- FK, Jacobian, SC step beside roboticstoolbox
    plain = pa10_7c()
    q = rng.uniform(-1, 1, 7)
    fk, jac = microseconds(lambda: plain.fk(q)), microseconds(lambda: plain.jacobian(q))
    ets = rtb_ets(plain)
    rtb_fk = rtb_jac = float("nan")
    if ets is None:
        rows.append(("roboticstoolbox-python", "not installed", "", "skipped"))
    else:
        rtb_fk, rtb_jac = microseconds(lambda: ets.eval(q)), microseconds(lambda: ets.jacob0(q))
    rows.append(("FK, one configuration (PA10)", f"{fk:.2f} us", f"{fk / rtb_fk:.2f} x rtb ETS eval", "<= 1"))
    rows.append(("Jacobian, one configuration (PA10)", f"{jac:.2f} us", f"{jac / rtb_jac:.2f} x rtb ETS jacob0",
                 "<= 1"))
    seconds = best_time(lambda: plain.fk(q_batch), repeat=3)
    rows.append(("batch FK, 10^6 configurations", f"{1.0 / seconds:.1f} M/s", "", ">= 10 M/s"))
    wam = barrett_wam()
    q_wam = np.radians([30.0, 20.0, 50.0, 70.0, 40.0, 100.0, 0.0])
    twist = np.array([0.15, 0.0, 0.0, 0.0, 0.1, 0.0])
    controller = SingularityConsistentController(wam, q_wam, eps=0.1)
    step = microseconds(lambda: controller(q_wam, twist))
    wam_ets = rtb_ets(wam)
    wam_jac = float("nan") if wam_ets is None else microseconds(lambda: wam_ets.jacob0(q_wam))
    rows.append(("SC control step, Jacobian included (WAM)", f"{step:.2f} us", f"{step / wam_jac:.2f} x rtb jacob0",
                 "<= 2"))

    iiwa_poses = iiwa.fk(rng.uniform(-2.0, 2.0, (200_000, 7)))
    buffer = np.empty((len(iiwa_poses), 8, 7))
    for label, out in (("a fresh result each call", None), ("into one out= buffer", buffer)):
        rates = []
        for _ in range(5):
            start = time.perf_counter()
            ik_all_branches(iiwa, iiwa_poses, 0.3, out=out)
            rates.append(8 * len(iiwa_poses) / (time.perf_counter() - start) / 1e6)
        per_solution = 1.0 / min(rates)  # microseconds, the slowest call
        rows.append((f"batch IK, 2x10^5 iiwa poses x 8, 5 calls in a row, {label}",
                     " ".join(f"{r:.1f}" for r in rates) + " M/s",
                     f"slowest {per_solution / (ssik8 / 8.0):.3f} x ssik per solution", "<= 0.02 every call"))

    rows.extend(fk_jacobian_rows(iiwa, copy_bandwidth()))
    rows.extend(command_line_rows())
    if "--skip-cold" not in sys.argv:
        rows.extend(cold_rows())

    width = max(len(r[0]) for r in rows)
    print(f"\n{'measurement':<{width}}  {'redkin':>26}  {'ratio':>28}  target")
    for label, value, ratio, target in rows:
        print(f"{label:<{width}}  {value:>26}  {ratio:>28}  {target}")


if __name__ == "__main__":
    main()
