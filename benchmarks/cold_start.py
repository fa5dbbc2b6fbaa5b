"""Cold start: the first call of every compiled path of redkin in a new process with an empty numba cache, in seconds.

Run:  python benchmarks/cold_start.py [--repeat N] [--processes P]

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
are listed.  With ``--processes P`` the sections run in P processes at once
(what ``redkin compile`` does, one per core): each section's times are then
its own process's, and the total's CPU time the first process's alone.

Run:  python benchmarks/cold_start.py --commands [--repeat N]

Issue 42's targets, per command: ``redkin fk``, ``redkin ik`` (at an arm
angle, ``--psi``; ``--q7`` on the Panda), ``redkin arm-angles`` and
``redkin path`` (a 0.1 m line of 21 waypoints between two key poses, the
same rotation, ``--max-step 0.1``) on the KUKA iiwa14, the Franka Panda
and the Kinova Gen3 (nearly S-R-S), and ``fk`` and ``ik`` (numerical, no
redundancy parameter) on the example Sawyer URDF (``ik`` and
``arm-angles`` on the branch of the pose's joint values); and in a cell
(:data:`CELL`: a table, a post and a lamp, each named model with its
built-in body, the Sawyer with :data:`SAWYER_BODY`) ``ik --scene``,
``arm-angles --scene`` and ``path --scene`` on the iiwa14 and the Panda and
``ik --scene`` on the Sawyer (its numerical collision-free search), each
run once cold, in its own new process with a fresh, empty
``NUMBA_CACHE_DIR``, then once warm on the cache it filled.  A cold run that
ran as Python starts ``redkin compile --background`` into its cache (its
process id in the note on stderr): the warm run waits for it to end, so
that it reads what that compile wrote and no compile runs beside the next
command (the seconds waited are listed).  The commands
run through the ``redkin`` console script installed beside this Python (no
shell shim), with ``REDKIN_COMPILE_NOTICE`` unset, so the compile notice is
said: the last progress line on stderr (``redkin: 34 kernels compiled in
8.5 s``) gives the kernels the run compiled and redkin's own seconds spent
compiling (``+K warm``: a warm run that compiled K kernels too).  Wall
seconds are the parent's clock around the process; CPU seconds, user +
system of the process from ``getrusage(RUSAGE_CHILDREN)``.  In the same loop
``python -c "import numpy"`` is timed (warm, best of 5).  Targets: the cold
run of each command <= 5 s wall; the warm ``redkin fk`` <= 3 x the numpy
import.  With ``--repeat N`` the whole loop is run N times (fresh caches
each time), each run's figures are listed, and a target is met only where
every run meets it (``met k/N`` says how many did otherwise).
"""

from __future__ import annotations

import json
import os
import platform
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FIRST_CALLS = r"""
import json, sys, time
wall, cpu = time.perf_counter(), time.process_time()
import redkin.warm_up
sections = [("import", time.perf_counter() - wall, time.process_time() - cpu)]
sections += redkin.warm_up.warm_up(processes=int(sys.argv[1]))
print(json.dumps(sections + [("total", time.perf_counter() - wall, time.process_time() - cpu)]))
"""


def run(cache: str, processes: int = 1) -> list[tuple[str, float, float]]:
    """The sections' seconds (wall, CPU) of one run of :data:`FIRST_CALLS` with ``NUMBA_CACHE_DIR=cache``, in
    ``processes`` processes (``redkin compile --processes``; the total's CPU is then the first process's only)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    result = subprocess.run([sys.executable, "-c", FIRST_CALLS, str(processes)], env=env, capture_output=True,
                            text=True)
    if result.returncode != 0:
        raise SystemExit(result.stderr)
    return [tuple(pair) for pair in json.loads(result.stdout.strip().splitlines()[-1])]


def main() -> None:
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 1
    processes = int(sys.argv[sys.argv.index("--processes") + 1]) if "--processes" in sys.argv else 1
    print(f"# cold start -- {platform.machine()}, {os.cpu_count()} cores, python {platform.python_version()}, "
          f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}; {processes} compiling process(es)")
    colds = []
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as cache:
            colds.append(run(cache, processes))
            warm = run(cache, processes)
    print(f"{'section':<14} {'cold wall (s)':>14} {'cold CPU (s)':>13} {'warm wall (s)':>14}")
    for k, (name, seconds, _) in enumerate(warm):
        wall = " ".join(f"{c[k][1]:.1f}" for c in colds)
        cpu = " ".join(f"{c[k][2]:.1f}" for c in colds)
        print(f"{name:<14} {wall:>14} {cpu:>13} {seconds:>14.2f}")


#: One pose per robot that its arm reaches (the FK of the joint values in the comment), as ``redkin fk`` prints it:
#: position, then the rotation matrix row by row.
POSES = {
    # redkin fk kuka-iiwa14 0.3 0.6 0.1 -1.2 0.2 0.8 0.1
    "kuka-iiwa14": ((0.6381709826119824, 0.2669762474599886, 0.5119319922031215),
                    (-0.8807776534506888, -0.2330330642808526, 0.41222119806455193,
                     -0.07165378667210072, 0.9260924975255713, 0.3704300485684159,
                     -0.4680774081681869, 0.2967292991578789, -0.8323792783243865)),
    # redkin fk franka-panda 0.3 -0.4 0.2 -2.0 0.1 1.8 0.7 (branch --+)
    "franka-panda": ((0.38233526759649805, 0.2373543867249343, 0.6356972449498293),
                     (0.9649746194587141, -0.20807926597837778, 0.15977172112238652,
                      -0.22664507493838287, -0.9679410592381081, 0.10826872053914952,
                      0.13212113308129403, -0.14068804110836533, -0.9811986961275511)),
    # redkin fk kinova-gen3 0.3 0.6 0.1 -1.2 0.2 0.8 0.1 (nearly S-R-S: its closed form polished on the real arm)
    "kinova-gen3": ((0.08199414787611689, -0.038629829126462185, 1.0553268325600618),
                    (0.7870320078140184, 0.601142727432298, 0.13859307317284392,
                     -0.5833013577253026, 0.7982721858147811, -0.15007012837440406,
                     -0.20084856173757853, 0.03726846669437255, 0.9789131302818432)),
    # redkin fk src/redkin/examples/sawyer.urdf 0.3 0.6 0.1 -1.2 0.2 0.8 0.1 (no closed form: the numerical solver)
    "sawyer": ((0.7770231936358508, 0.3799276753970007, 0.3111209882907043),
               (0.3586897366819385, -0.22902409034358126, 0.9049252117392558,
                -0.9173318358368944, 0.09292797177634121, 0.38712620038128226,
                -0.17275409042669532, -0.9689749006573032, -0.17675877951890984)),
}
#: What each robot of :data:`POSES` is called on the command line (the Sawyer: the example URDF).
ROBOT_ARGUMENT = {"sawyer": str(Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / "sawyer.urdf")}
#: The joint values of each pose of :data:`POSES` (``redkin fk`` takes them).
JOINTS = {"kuka-iiwa14": (0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1), "franka-panda": (0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.7),
          "kinova-gen3": (0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1), "sawyer": (0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1)}
#: The redundancy parameter ``ik`` is given on each robot (none on the Sawyer: ``ik`` solves it numerically); the
#: branch ``ik`` and ``arm-angles`` are given (the Panda's joint values are on --+, where its default +++ has no
#: feasible q7 at this pose).
PARAMETER = {"kuka-iiwa14": ["--psi", "0.5"], "franka-panda": ["--q7", "0.7"], "kinova-gen3": ["--psi", "0.5"],
             "sawyer": []}
BRANCH = {"kuka-iiwa14": [], "franka-panda": ["--branch=--+"], "kinova-gen3": [], "sawyer": []}
#: How far the path's second key pose lies from the first along -y (m), the rotation kept; ``--step`` 0.005 m.
PATH_LENGTH = 0.1
COMMANDS = ("fk", "ik", "arm-angles", "path", "ik --scene", "arm-angles --scene", "path --scene")
#: The commands each robot runs (the Sawyer has no redundancy parameter: no arm-angles, and its path is not timed;
#: the Gen3 is not run in the cell).
ROBOT_COMMANDS = {"sawyer": ("fk", "ik", "ik --scene"), "kinova-gen3": ("fk", "ik", "arm-angles", "path")}
#: The cell of the ``--scene`` commands (:data:`CELL_COMMANDS`): a table under the workspace, a post and a lamp;
#: the named models use their built-in bodies, the Sawyer the capsules of :data:`SAWYER_BODY`.
CELL = """margin: 0.01
obstacles:
  - {name: table, type: box, center: [0.6, 0, -0.05], size: [1.2, 1.0, 0.1]}
  - {name: post, type: capsule, a: [0.5, -0.35, 0], b: [0.5, -0.35, 1.0], radius: 0.04}
  - {name: lamp, type: sphere, center: [0.3, -0.4, 0.9], radius: 0.1}
"""
SAWYER_BODY = """capsules:
  right_l1: [{a: [0, 0, 0], b: [0, 0, 0.15], radius: 0.06}]
  right_l2: [{a: [0, 0, 0], b: [0, 0, 0.3], radius: 0.06}]
  right_l3: [{a: [0, 0, 0], b: [0, 0, 0.15], radius: 0.06}]
  right_l4: [{a: [0, 0, 0], b: [0, 0, 0.3], radius: 0.05}]
  right_l5: [{a: [0, 0, 0], b: [0, 0, 0.1], radius: 0.05}]
"""
#: Issue 42's targets: the first call of a command on a fresh cache, wall seconds; warm fk over the numpy import.
COLD_TARGET = 5.0
FK_RATIO_TARGET = 3.0
PROGRESS = re.compile(r"redkin: (\d+) kernels? compiled in ([0-9.]+) s")
#: The note of a run that started a background compile (:func:`redkin.cli.common.compiling_later`): its process id.
BACKGROUND = re.compile(r"compiling in the background now \(process (\d+),")
#: A background compile still running after this many seconds is not waited for further.
BACKGROUND_WAIT = 600.0


def redkin_command() -> list[str]:
    """The ``redkin`` console script installed beside this Python (no shell shim in between), else the same entry
    point through ``python -c``."""
    script = Path(sys.executable).with_name("redkin")
    if script.exists():
        return [str(script)]
    return [sys.executable, "-c", "from redkin.cli.main import main; raise SystemExit(main())"]


def command_args(command: str, robot: str, keys: str, work: str = "") -> list[str]:
    """The arguments of ``redkin COMMAND`` on ``robot``; ``keys``: the JSON file of the path's two key poses; a
    command ending in ``--scene`` is the command in the cell of :func:`write_cell`'s files in ``work``."""
    if command.endswith(" --scene"):
        cell = ["--scene", os.path.join(work, "cell.yaml")]
        if robot == "sawyer":
            cell += ["--body", os.path.join(work, "sawyer-body.yaml")]
        return command_args(command.removesuffix(" --scene"), robot, keys) + cell
    position, rotation = POSES[robot]
    pose = ["--position", *map(repr, position), "--rotation", *map(repr, rotation)]
    name = ROBOT_ARGUMENT.get(robot, robot)
    if command == "fk":
        return ["fk", name, *map(repr, JOINTS[robot])]
    if command == "ik":
        return ["ik", name, *pose, *PARAMETER[robot], *BRANCH[robot]]
    if command == "arm-angles":
        return ["arm-angles", name, *pose, *BRANCH[robot]]
    return ["path", name, "--through", keys, "--step", "0.005", "--max-step", "0.1"]


def write_keys(robot: str, path: str) -> None:
    """The path's two key poses as 4x4 lists in a JSON file: :data:`POSES`, then moved by :data:`PATH_LENGTH`."""
    position, rotation = POSES[robot]
    first = [[*rotation[3 * i:3 * i + 3], position[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]]
    second = [row[:] for row in first]
    second[1][3] -= PATH_LENGTH
    Path(path).write_text(json.dumps([first, second]))


def write_cell(work: str) -> None:
    """The files of the ``--scene`` commands in ``work``: ``cell.yaml`` (:data:`CELL`) and ``sawyer-body.yaml``."""
    Path(work, "cell.yaml").write_text(CELL)
    Path(work, "sawyer-body.yaml").write_text(SAWYER_BODY)


def timed(argv: list[str], cache: str | None = None) -> tuple[float, float, str]:
    """Run ``argv`` to its end (``NUMBA_CACHE_DIR=cache``, ``REDKIN_COMPILE_NOTICE`` unset): wall seconds, CPU
    seconds (user + system, ``getrusage(RUSAGE_CHILDREN)``) and its stderr; stop with the stderr if it fails."""
    env = {k: v for k, v in os.environ.items() if k != "REDKIN_COMPILE_NOTICE"}
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = cache
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(argv, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(argv)} exited with {result.returncode}:\n{result.stderr}")
    return wall, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime, result.stderr


def kernels(stderr: str) -> tuple[int, float]:
    """The kernels compiled and redkin's compile seconds, from the last progress line on ``stderr`` (0, 0.0: none)."""
    matches = PROGRESS.findall(stderr)
    return (int(matches[-1][0]), float(matches[-1][1])) if matches else (0, 0.0)


def background_waited(stderr: str) -> float:
    """Wait for the background compile a run started (its process id from the note on ``stderr``; none: 0 s) to
    end, at most :data:`BACKGROUND_WAIT` seconds; the seconds waited.  Linux: ended means ``/proc/PID`` is gone or
    the process a zombie."""
    match = BACKGROUND.search(stderr)
    if match is None:
        return 0.0
    status = Path("/proc") / match.group(1) / "stat"
    start = time.perf_counter()
    while time.perf_counter() - start < BACKGROUND_WAIT:
        try:
            state = status.read_text().rsplit(")", 1)[1].split()[0]
        except (OSError, IndexError):
            break
        if state == "Z":
            break
        time.sleep(0.2)
    return time.perf_counter() - start


def run_commands() -> dict:
    """One pass of every command on every robot, cold on a fresh cache each, then warm on it; and the numpy import.

    Returns ``{"numpy": seconds, (command, robot): {"cold": (wall, cpu), "kernels": (count, seconds),
    "background": seconds waited for the background compile, "warm": wall, "warm_kernels": count}}``.
    """
    figures: dict = {}
    with tempfile.TemporaryDirectory() as work:
        write_cell(work)
        for robot in POSES:
            keys = os.path.join(work, f"{robot}-keys.json")
            write_keys(robot, keys)
            for command in ROBOT_COMMANDS.get(robot, COMMANDS):
                argv = redkin_command() + command_args(command, robot, keys, work)
                with tempfile.TemporaryDirectory() as cache:
                    wall, cpu, stderr = timed(argv, cache)
                    waited = background_waited(stderr)
                    warm, _, warm_stderr = timed(argv, cache)
                    background_waited(warm_stderr)  # one the warm run started (its kernels still not cached)
                figures[command, robot] = {"cold": (wall, cpu), "kernels": kernels(stderr), "background": waited,
                                           "warm": warm, "warm_kernels": kernels(warm_stderr)[0]}
                print(f"  {command} {robot}: cold {wall:.1f} s, {kernels(stderr)[0]} kernels, background compile "
                      f"{waited:.0f} s more, warm {warm:.2f} s", file=sys.stderr, flush=True)
    figures["numpy"] = min(timed([sys.executable, "-c", "import numpy"])[0] for _ in range(5))
    return figures


def verdict(passed: list[bool]) -> str:
    """``met`` where every run passed, ``missed`` where none did, else how many did."""
    return "met" if all(passed) else "missed" if not any(passed) else f"met {sum(passed)}/{len(passed)}"


def main_commands(repeat: int) -> None:
    """``--commands``: the table of issue 42's per-command cold and warm starts (module docstring)."""
    import numba

    print(f"# cold start per command -- {platform.machine()}, {os.cpu_count()} cores, "
          f"python {platform.python_version()}, numba {numba.__version__}, "
          f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(f"# {' '.join(redkin_command())}; each command cold in a fresh NUMBA_CACHE_DIR, then warm on it")
    runs = [run_commands() for _ in range(repeat)]
    print(f"# load average at the end {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    numpy = " ".join(f"{r['numpy']:.3f}" for r in runs)
    print(f"python -c 'import numpy' (warm, best of 5): {numpy} s")
    print()
    print("| command | robot | cold wall (s) | cold CPU (s) | kernels compiled (compile s) | background compile after "
          "it (s) | warm wall (s) | cold <= 5 s | warm fk <= 3 x numpy import |")
    print("|---|---|---|---|---|---|---|---|---|")
    for command in COMMANDS:
        for robot in POSES:
            if command not in ROBOT_COMMANDS.get(robot, COMMANDS):
                continue
            rows = [r[command, robot] for r in runs]
            cold = " ".join(f"{row['cold'][0]:.1f}" for row in rows)
            cpu = " ".join(f"{row['cold'][1]:.1f}" for row in rows)
            count = " ".join(f"{row['kernels'][0]} ({row['kernels'][1]:.1f})" +
                             (f" +{row['warm_kernels']} warm" if row["warm_kernels"] else "") for row in rows)
            background = " ".join(f"{row['background']:.0f}" for row in rows)
            warm = " ".join(f"{row['warm']:.2f}" for row in rows)
            cold_ok = verdict([row["cold"][0] <= COLD_TARGET for row in rows])
            if command == "fk":
                ratios = [row["warm"] / r["numpy"] for row, r in zip(rows, runs)]
                fk = f"{' '.join(f'{x:.1f} x' for x in ratios)}: {verdict([x <= FK_RATIO_TARGET for x in ratios])}"
            else:
                fk = ""
            print(f"| `{command}` | {robot} | {cold} | {cpu} | {count} | {background} | {warm} | {cold_ok} | {fk} |")


if __name__ == "__main__":
    if "--commands" in sys.argv:
        main_commands(int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 1)
    else:
        main()
