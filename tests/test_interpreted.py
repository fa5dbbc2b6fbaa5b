"""Kernels run as Python (redkin._compiled.interpreted) give what they give compiled, bit for bit (issue 42).

``redkin fk``, ``jacobian``, ``ik``/``arm-angles`` on one pose of an exact closed form, ``ik`` on one pose of a
nearly S-R-S arm (until its self-motion is compiled) or of the numerical solver, and ``path`` on a short path of an
exact class run the kernels' Python functions instead of loading numba (0.4 s of every warm command, and tens of
seconds of compiling on a fresh install).  The law: in a fresh process, before numba is loaded, the chain's FK and
Jacobian, ``Arm.ik`` at several values of the parameter (a nearly S-R-S arm's too), the numerical solver,
``Arm.analyse`` of every branch and short paths (S-R-S, offset elbow and the Franka class) give results that equal,
number for number, what the same calls give once numba is loaded (:func:`redkin._compiled.use_compiled`).  The
configurations are random within the limits and, on purpose, degenerate: all zeros (a straight shoulder and wrist),
the stretched elbow, every joint at a limit, and a pose moved out of reach.  A fresh process is needed: once numba is
loaded in a process (the suite's own has it), kernels run compiled whatever the context.
"""

from __future__ import annotations

import ast
import subprocess
import sys

import numpy as np
import pytest

#: Each call in the child: the arm, its configurations, and what is compared.  The child prints one literal line:
#: whether numba was loaded before the compiled pass, how many values were compared, and the mismatches.
CHILD = r'''
import dataclasses, sys
import numpy as np
from redkin import models
from redkin.arms import arm
from redkin._compiled import interpreted, numba_loaded, use_compiled
from redkin.numerical import ik

NAME, RANDOM, ANALYSED, PATHS, NUMERICAL, SEED = sys.argv[1], *map(int, sys.argv[2:7])
chain = getattr(models, NAME.replace("-", "_"))()
rng = np.random.default_rng(SEED)
lower, upper = np.maximum(chain.lower, -np.pi), np.minimum(chain.upper, np.pi)  # a joint without limits: a turn
straight = np.zeros(chain.n)
stretched = rng.uniform(lower, upper)
stretched[3] = np.clip(0.0, lower[3], upper[3])
configurations = [straight, stretched, lower.copy(), upper.copy(), *rng.uniform(lower, upper, (RANDOM, chain.n))]
values = np.array([-2.5, -0.4, 0.3, 1.7])


def flat(value, path=""):
    """(path, value) pairs of everything an answer holds, arrays and numbers alike."""
    if dataclasses.is_dataclass(value):
        names = [field.name for field in dataclasses.fields(value) if not field.name.startswith("_")]
        names += [name for name in ("parameter", "reach", "reason") if hasattr(type(value), name)]  # computed
        for name in names:
            yield from flat(getattr(value, name), f"{path}.{name}")
    elif isinstance(value, dict):
        for key in sorted(value, key=str):
            yield from flat(value[key], f"{path}[{key!r}]")
    elif isinstance(value, (tuple, list)) and not (value and isinstance(value[0], (int, float, bool, str))):
        for k, item in enumerate(value):
            yield from flat(item, f"{path}[{k}]")
    elif hasattr(value, "_asdict"):
        yield from flat(value._asdict(), path)
    else:
        yield path, value


def answers():
    global rng_path
    rng_path = np.random.default_rng(SEED + 1)
    classified = arm(chain)  # classifying runs kernels too
    out = []
    for k, q in enumerate(configurations):
        pose = chain.fk(q)
        out += [(f"fk {k}", pose), (f"jacobian {k}", chain.jacobian(q)), (f"limits {k}", chain.within_limits(q))]
        far = pose.copy()
        far[:3, 3] += 5.0
        for label, target in (("pose", pose), ("far", far)):
            out += list(flat(classified.ik(target, values), f"ik {label} {k}"))
            if k < NUMERICAL:  # redkin ik without a parameter runs the numerical solver as Python on one pose
                out += list(flat(ik(chain, target, rng=k), f"numerical {label} {k}"))
        if k < ANALYSED:
            out += list(flat(classified.analyse(pose), f"analyse {k}"))
    if PATHS:  # redkin path runs as Python on short paths (the Franka class: until compiled): 12 waypoints
        from redkin.paths import resolve_path

        for k, q in enumerate(configurations[4:4 + PATHS]):
            along = q + np.linspace(0.0, 1.0, 12)[:, None] * rng_path.uniform(-0.3, 0.3, chain.n)
            out += list(flat(resolve_path(chain, chain.fk(along), 0.1), f"path {k}"))
    return out


with interpreted():
    python = answers()
loaded = numba_loaded() or "numba" in sys.modules
use_compiled()
compiled = answers()
mismatches = []
for (path, a), (other, b) in zip(python, compiled):
    same = path == other
    if same and isinstance(a, np.ndarray):
        same = a.shape == b.shape and (np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"))
    elif same:
        same = (a == b) or (a != a and b != b)
    if not same:
        mismatches.append(path)
print((loaded, len(python), len(compiled), mismatches[:10]))
'''

ARMS = [  # (model, random configurations, configurations analysed, paths, configurations solved numerically):
    # the Franka class's analysis is ~0.6 s; a nearly S-R-S arm's analysis follows its self-motion (compiled only),
    # its closed form at one value runs as Python where redkin ik does not follow it (one pose)
    ("kuka-iiwa14", 16, 8, 2, 6),
    ("pa10-7c", 8, 4, 1, 2),
    ("barrett-wam", 8, 4, 1, 2),
    ("franka-panda", 8, 2, 1, 2),
    ("ufactory-xarm7", 4, 1, 0, 2),
    ("kinova-gen3", 0, 0, 0, 2),
]


@pytest.mark.parametrize(("name", "random", "analysed", "paths", "numerical"), ARMS)
def test_kernels_as_python_equal_the_compiled_kernels(name, random, analysed, paths, numerical):
    result = subprocess.run([sys.executable, "-c", CHILD, name, str(random), str(analysed), str(paths),
                             str(numerical), "42"], capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    loaded, count, compiled_count, mismatches = ast.literal_eval(result.stdout.strip().splitlines()[-1])
    assert not loaded  # the first pass ran without numba
    assert count == compiled_count and count > 10 * (random + 4)
    assert mismatches == []


def test_a_batch_within_interpreted_runs_in_the_calling_thread():
    """The pool's helper threads are not inside the caller's context: as Python, a batch is not split (a helper
    would have loaded numba)."""
    from redkin import _compiled

    calls = []

    def chunk(start, stop, out):
        calls.append((start, stop))
        out[start:stop] = 1.0

    out = np.zeros(4 * _compiled.PARALLEL_BATCH)
    loaded = _compiled._numba_loaded
    try:
        _compiled._numba_loaded = False  # as in a process that has not loaded numba
        with _compiled.interpreted():
            _compiled.run_batch(chunk, len(out), out)
    finally:
        _compiled._numba_loaded = loaded
    assert calls == [(0, len(out))] and out.all()


#: ``redkin robots`` (every model classified) and ``robots --show`` of example files of every class, first as Python,
#: then compiled, in one fresh process: the printed JSON is the same, character for character.
ROBOTS = r"""
import contextlib, io, sys
from redkin._compiled import interpreted, numba_loaded, use_compiled
from redkin.numerical import ik
from redkin.cli.main import main

COMMANDS = [["robots", "--json"]] + [["robots", "--show", name, "--json"] for name in sys.argv[1:]]


def printed():
    out = []
    for argv in COMMANDS:
        text = io.StringIO()
        with contextlib.redirect_stdout(text):
            assert main(argv) == 0
        out.append(text.getvalue())
    return out


with interpreted():
    python = printed()
loaded = numba_loaded() or "numba" in sys.modules
use_compiled()
print((loaded, [k for k, (a, b) in enumerate(zip(python, printed())) if a != b], len(python)))
"""


def test_robots_as_python_prints_what_it_prints_compiled():
    """``redkin robots`` runs as Python (the classification of every model, nearly S-R-S arms included)."""
    files = ["gen3.urdf", "jaco2.urdf", "iiwa14_rosi.urdf", "sawyer.urdf", "fr3.urdf", "xarm7.urdf", "iiwa14.urdf"]
    result = subprocess.run([sys.executable, "-c", ROBOTS, *files], capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    loaded, differing, count = ast.literal_eval(result.stdout.strip().splitlines()[-1])
    assert not loaded and differing == [] and count == len(files) + 1


#: One pose's S-R-S IK and a Franka-class arm's q7 sets as Python, counting the calls that pass through a kernel's
#: :class:`redkin._compiled.Kernel` wrapper: only the calls from Python code outside the kernels do.
TWINS = r"""
import numpy as np
from redkin import models, srs, franka
from redkin._compiled import Kernel, interpreted, numba_loaded

calls = []
wrapped = Kernel.__call__


def counted(self, *args):
    calls.append(self.__qualname__)
    return wrapped(self, *args)


Kernel.__call__ = counted
iiwa, fr3 = models.kuka_iiwa14(), models.franka_fr3()
q = np.array([0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1])
with interpreted():
    entries = [len(calls)]
    solutions = srs.ik_all_branches(iiwa, iiwa.fk(q), 0.4)
    entries.append(len(calls))
    sets = franka.feasible_q7(fr3, fr3.fk(q))
    entries.append(len(calls))
print((numba_loaded(), entries, bool(np.isfinite(solutions).all(axis=1).any()), len(sets.branches)))
"""


def test_a_kernel_run_as_python_calls_its_callees_without_the_wrapper():
    """Within interpreted(), a kernel's Python run calls its callees' Python functions directly (their twins, whose
    globals hold twins), not through each callee's Kernel wrapper (0.15 us a call, millions of calls in a nearly
    S-R-S arm's sets): the wrapper sees only the few calls from Python code outside the kernels."""
    result = subprocess.run([sys.executable, "-c", TWINS], capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    loaded, entries, solved, branches = ast.literal_eval(result.stdout.strip().splitlines()[-1])
    assert not loaded and solved and branches == 8
    ik_calls, sets_calls = entries[1] - entries[0], entries[2] - entries[1]
    assert 1 <= ik_calls <= 5 and 1 <= sets_calls <= 40, entries  # before the twins: thousands
