"""Cold start: the first call of every compiled path of redkin in a new process with an empty numba cache, in seconds.

Run:  python benchmarks/cold_start.py [--repeat N]

A new process with a fresh ``NUMBA_CACHE_DIR`` imports redkin and runs
:func:`redkin.warm_up.warm_up` (what ``redkin compile`` runs): each public
function that runs a compiled kernel, once on one item and once on a batch
of 1000, section by section (the chain, S-R-S IK, the S-R-S feasible sets
and their uses, the torso arm, the velocity steps, the virtual arms).  Every
kernel is compiled there once and written to the cache.  The same script
then runs again on that cache (warm: loading, not compiling).  Each line
prints the seconds spent in that section, wall-clock and the process's CPU
time (compiling is serial: on an idle machine the two agree, on a busy one
the CPU time is the steadier measure of the compile bill); the last line,
the total from before ``import redkin`` to the end.  With ``--repeat N`` the
cold run is made N times (a fresh directory each time) and each run's times
are listed.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile

FIRST_CALLS = r"""
import json, time
wall, cpu = time.perf_counter(), time.process_time()
import redkin.warm_up
sections = [("import", time.perf_counter() - wall, time.process_time() - cpu)] + redkin.warm_up.warm_up()
print(json.dumps(sections + [("total", time.perf_counter() - wall, time.process_time() - cpu)]))
"""


def run(cache: str) -> list[tuple[str, float, float]]:
    """The sections' seconds (wall, CPU) of one run of :data:`FIRST_CALLS` with ``NUMBA_CACHE_DIR=cache``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    result = subprocess.run([sys.executable, "-c", FIRST_CALLS], env=env, capture_output=True, text=True)
    if result.returncode != 0:
        raise SystemExit(result.stderr)
    return [tuple(pair) for pair in json.loads(result.stdout.strip().splitlines()[-1])]


def main() -> None:
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 1
    print(f"# cold start -- {platform.machine()}, {os.cpu_count()} cores, python {platform.python_version()}, "
          f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    colds = []
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as cache:
            colds.append(run(cache))
            warm = run(cache)
    print(f"{'section':<14} {'cold wall (s)':>14} {'cold CPU (s)':>13} {'warm wall (s)':>14}")
    for k, (name, seconds, _) in enumerate(warm):
        wall = " ".join(f"{c[k][1]:.1f}" for c in colds)
        cpu = " ".join(f"{c[k][2]:.1f}" for c in colds)
        print(f"{name:<14} {wall:>14} {cpu:>13} {seconds:>14.2f}")


if __name__ == "__main__":
    main()
