"""The command line imports only what it uses (issue 23: a command line that starts fast).

``redkin --help``, each command's ``--help`` and an argument error import none of numba, scipy, matplotlib, the Dask
stack or the compiled kernels; ``redkin fk`` and ``redkin jacobian`` import the chain and its kernels, run them as
Python and load neither numba nor scipy, and nothing of the other methods.
These tests check what a fresh process imports, never how long it takes: timings belong in benchmarks/.
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from redkin import get_robot
from redkin._compiled import use_compiled
from redkin.cli.explore import _PAGE_KERNELS as PAGE_KERNELS
from redkin.cli.main import _COMMANDS
from redkin.cli.path import _FRANKA_PATH_KERNELS as FRANKA_PATH_KERNELS
from redkin.cli.srs import _SMALL_BATCH as SMALL_BATCH
from tests.support.cli import run

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "redkin"
EXAMPLES = PACKAGE / "examples"

#: Libraries a parser must not need (llvmlite comes only with numba).
HEAVY = ("numba", "llvmlite", "scipy", "matplotlib", "dask", "distributed", "zarr", "xarray")

#: The redkin packages of the methods other than the chain: ``redkin fk`` needs none of them.
OTHER_METHODS = ("redkin.srs", "redkin.torso_arm", "redkin.velocity", "redkin.virtual_arms", "redkin.workspace",
                 "redkin.explore", "redkin.plot", "redkin.reproduce")

#: The modules of :data:`OTHER_METHODS` a parser reads: ``redkin.reproduce`` lists its sections' keys (and imports
#: no section).
READ_BY_HELP = {"redkin.reproduce", "redkin.reproduce.provenance"}

#: Argument lists that end before any command runs: help, and mistakes argparse refuses.
BEFORE_ANY_WORK = [
    [], ["--help"], ["--version"], ["--bogus"],
    *([command, "--help"] for command in _COMMANDS), ["torso-arm", "ik", "--help"], ["torso-arm", "map", "--help"],
    ["fk"], ["fk", "pa10-7c", "zero"], ["ik", "pa10-7c", "--bogus"], ["track", "barrett-wam", "--method", "bogus"],
    ["workspace", "pa10-7c"], ["torso-arm", "map"], ["reproduce", "--bogus"], ["no-such-command"],
]


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports_compiled(tree: ast.Module) -> bool:
    """Whether a module imports ``redkin._compiled`` when it loads (at its top level; a handler that imports it when
    it runs, as ``redkin compile`` does, loads no kernel before then)."""
    for node in tree.body:
        if isinstance(node, ast.Import) and any(alias.name == "redkin._compiled" for alias in node.names):
            return True
        if isinstance(node, ast.ImportFrom) and (node.module == "redkin._compiled" or (
                node.module == "redkin" and any(alias.name == "_compiled" for alias in node.names))):
            return True
    return False


#: ``redkin._compiled`` and every module that imports it: the modules that define or call compiled kernels (every
#: kernel is made by ``redkin._compiled.kernel``, so no kernel loads without them).
KERNEL_MODULES = {"redkin._compiled"} | {
    _module_name(path) for path in PACKAGE.rglob("*.py") if _imports_compiled(ast.parse(path.read_text("utf-8")))
}


def _run(code: str) -> list:
    """The lines ``code`` prints in a fresh interpreter, each read as a Python literal."""
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return [ast.literal_eval(line) for line in result.stdout.splitlines() if line.startswith("(")]


def _modules_after(argv_lists: list[list[str]]) -> list[tuple[list[str], int, set[str]]]:
    """For each argument list in turn, in one fresh process: main's exit code and every module loaded so far.

    One process serves them all: a module loaded by one call stays loaded for the next, so the first call that
    loads a forbidden module is the one named when a check fails (all before it loaded none).
    """
    code = "\n".join([
        "import contextlib, io, sys",
        "from redkin.cli.main import main",
        f"for argv in {argv_lists!r}:",
        "    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):",
        "        try:",
        "            code = main(argv)",
        "        except SystemExit as exc:",
        "            code = exc.code",
        "    print((argv, code, sorted(sys.modules)))",
    ])
    return [(argv, code, set(modules)) for argv, code, modules in _run(code)]


def _forbidden(modules: set[str], names: set[str] | tuple[str, ...]) -> list[str]:
    """The modules among ``modules`` that are one of ``names`` or inside one of them."""
    return sorted(m for m in modules if any(m == name or m.startswith(name + ".") for name in names))


def test_help_and_argument_errors_import_no_heavy_library_and_no_kernel():
    runs = _modules_after(BEFORE_ANY_WORK)
    assert [argv for argv, _, _ in runs] == BEFORE_ANY_WORK
    for argv, code, modules in runs:
        assert code in (0, 2), (argv, code)
        assert _forbidden(modules, HEAVY) == [], argv
        assert _forbidden(modules, KERNEL_MODULES) == [], argv
        # of the methods, only the registry of reproduce's sections, which gives the help their keys
        assert set(_forbidden(modules, ("redkin.chain", "redkin.models", *OTHER_METHODS))) <= READ_BY_HELP, argv


def test_the_kernel_modules_are_found():
    """The list above is not empty by mistake: the chain's and the S-R-S kernels are in it."""
    assert {"redkin._chain_kernels", "redkin.chain", "redkin.srs._ik_kernels"} <= KERNEL_MODULES


def test_fk_and_jacobian_run_the_chain_kernels_without_numba():
    """One configuration's pose or Jacobian runs the chain's kernels as Python (redkin._compiled.interpreted):
    numba, llvmlite and scipy are not loaded (issue 42: numba's import was most of a warm ``redkin fk``)."""
    q = ["0.3", "0.6", "0.1", "-1.2", "0.2", "0.8", "0.1"]
    runs = _modules_after([["fk", "pa10-7c", *q], ["jacobian", "franka-panda", *q, "--manipulability"],
                           ["fk", "kuka-iiwa14", *q, "--json"]])
    for argv, code, modules in runs:
        assert code == 0, argv
        assert {"redkin.chain", "redkin._chain_kernels", "redkin.models"} <= modules, argv  # it did compute
        assert _forbidden(modules, HEAVY) == [], (argv, _forbidden(modules, HEAVY)[:5])
        assert _forbidden(modules, OTHER_METHODS) == [], argv
        assert _forbidden(modules, KERNEL_MODULES - {"redkin._compiled", "redkin._chain_kernels", "redkin.chain"}) == []


def _key_poses(folder, length: float):
    """A path's two key poses in ``folder/keys.npy``: the tool pointing down at (0.4, 0.1, 0.5), then moved
    ``length`` along y."""
    keys = folder / "keys.npy"
    target = np.eye(4)
    target[:3, 3] = [0.4, 0.1, 0.5]
    target[:3, :3] = np.diag([1.0, -1.0, -1.0])
    moved = target.copy()
    moved[1, 3] += length
    np.save(keys, np.stack([target, moved]))
    return keys


def test_small_work_of_a_closed_form_loads_neither_numba_nor_scipy(tmp_path):
    """``redkin ik`` at an arm angle (S-R-S) or a q7 (the Franka class) on one pose or a batch of at most 256,
    ``arm-angles`` on one pose and ``path`` on a short path of an S-R-S arm run the kernels as Python: neither numba
    nor scipy is loaded (issue 42; importing scipy.optimize for the Franka class's optimal q7 was half of its
    ``arm-angles``)."""

    pose = ["--position", "0.4", "0.1", "0.5", "--rotation", "1", "0", "0", "0", "-1", "0", "0", "0", "-1"]
    keys = _key_poses(tmp_path, 0.05)
    poses = tmp_path / "poses.npy"
    np.save(poses, np.stack([get_robot("kuka-iiwa14").fk(np.full(7, 0.3))] * SMALL_BATCH))
    runs = _modules_after([["ik", "kuka-iiwa14", *pose, "--psi", "0.3"], ["ik", "franka-panda", *pose, "--q7", "0.3"],
                           ["ik", "kuka-iiwa14", "--poses", str(poses), "--psi", "0.3"],
                           ["path", "kuka-iiwa14", "--through", str(keys), "--step", "0.01", "--max-step", "0.1"],
                           ["arm-angles", "barrett-wam", *pose], ["arm-angles", "franka-fr3", *pose]])
    for argv, code, modules in runs:
        assert code in (0, 1), argv  # 1: no solution of +++ at that value, an answer
        assert {"redkin.srs._ik_kernels", "redkin.franka"} & modules, argv  # it did solve
        assert _forbidden(modules, ("numba", "llvmlite")) == [], argv
        assert _forbidden(modules, ("scipy",)) == [], (argv, _forbidden(modules, ("scipy",))[:5])


def test_robots_classifies_without_numba():
    """``redkin robots --show`` classifies the robot with the kernels run as Python."""
    [(_, code, modules)] = _modules_after([["robots", "--show", "kuka-iiwa14"]])
    assert code == 0 and "redkin.arms.classify" in modules
    assert _forbidden(modules, ("numba", "llvmlite", "scipy")) == [], _forbidden(modules, HEAVY)[:5]


def test_large_work_runs_compiled(tmp_path):
    """A batch of more than 256 poses, a nearly S-R-S arm's self-motion (asked with --every-solution) and the
    numerical solver on a batch or with more than the default starts load numba: Python would be slow."""
    pose = ["--position", "0.4", "0.1", "0.5", "--rotation", "1", "0", "0", "0", "-1", "0", "0", "0", "-1"]
    poses = tmp_path / "poses.npy"
    target = np.eye(4)
    target[:3, 3] = [0.4, 0.1, 0.5]
    target[:3, :3] = np.diag([1.0, -1.0, -1.0])
    np.save(poses, np.stack([target] * (SMALL_BATCH + 1)))
    for argv in (["ik", "kuka-iiwa14", "--poses", str(poses), "--psi", "0.3"],
                 ["ik", "kinova-gen3", *pose, "--psi", "0.3", "--every-solution"],
                 ["ik", "kuka-iiwa14", "--poses", str(poses)], ["ik", "kuka-iiwa14", *pose, "--restarts", "1000"]):
        [(_, code, modules)] = _modules_after([argv])
        assert code in (0, 1) and "numba" in modules, argv


def test_import_redkin_is_light_and_its_names_load_on_first_use():
    code = "\n".join([
        "import sys, redkin",
        "print(tuple(sorted(sys.modules)))",
        "from redkin import SerialChain, get_robot, RedkinError",
        "print((SerialChain.__module__, get_robot.__module__, RedkinError.__module__, redkin.__version__))",
        "print((sorted(set(redkin.__all__) - set(dir(redkin))), hasattr(redkin, 'no_such_name')))",
    ])
    modules, names, missing = _run(code)
    assert _forbidden(set(modules), HEAVY) == [] and _forbidden(set(modules), KERNEL_MODULES) == []
    assert names[:3] == ("redkin.chain", "redkin.models", "redkin.errors") and isinstance(names[3], str)
    assert missing == ([], False)


def _cached_then_run(argv: list[str], environment: dict[str, str], kernels: tuple[str, ...] = FRANKA_PATH_KERNELS,
                     output: bool = False) -> tuple:
    """In one fresh process: whether ``kernels`` (``module.function`` names) are cached before it runs, then
    ``main(argv)``'s exit code, the modules loaded and its stderr (and its stdout where ``output``)."""
    code = "\n".join([
        "import contextlib, io, sys",
        "from redkin.cli.common import kernels_compiled",
        f"cached = kernels_compiled({kernels!r})",
        "from redkin.cli.main import main",
        "out, err = io.StringIO(), io.StringIO()",
        "with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):",
        "    code = main(" + repr(argv) + ")",
        "print((cached, code, sorted(sys.modules), err.getvalue(), out.getvalue()))",
    ])
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            env={**os.environ, **environment})
    cached, code, modules, err, out = ast.literal_eval(result.stdout.splitlines()[-1])
    return (cached, code, set(modules), err, out) if output else (cached, code, set(modules), err)


def test_a_short_franka_path_runs_as_python_until_its_kernels_are_cached(tmp_path):
    """``path`` on at most 32 waypoints of the Franka class runs as Python (and says so) while its kernels are not in
    numba's cache, and compiled once they are: on a fresh NUMBA_CACHE_DIR, then on the ambient cache (either way)."""
    keys = _key_poses(tmp_path, 0.03)
    argv = ["path", "franka-panda", "--through", str(keys), "--step", "0.01", "--max-step", "0.2"]
    cached, code, modules, err = _cached_then_run(argv, {"NUMBA_CACHE_DIR": str(tmp_path / "fresh")})
    assert (cached, code) == (False, 0)
    assert _forbidden(modules, ("numba", "llvmlite")) == [] and "redkin.franka" in modules
    assert "runs as Python" in err and "redkin compile" in err
    cached, code, modules, err = _cached_then_run(argv, {})
    assert code == 0 and ("numba" in modules) == cached and ("runs as Python" in err) == (not cached)


def test_one_pose_of_a_nearly_arm_or_the_numerical_solver_runs_as_python_on_a_fresh_cache(tmp_path, capsys):
    """``ik`` on one pose of a nearly S-R-S arm at an arm angle runs its closed form as Python while the self-motion's
    kernels are not cached (about a minute of compiling), says on stderr that a second solution of the branch was
    not looked for, and gives ``others: null``; the numerical solver on one pose runs as Python whatever the cache.
    Each answer is the compiled one, number for number (this process runs compiled)."""
    from redkin.cli.srs import _SELF_MOTION_KERNELS
    from redkin.closed_form import ik

    q = np.array([0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1])
    fresh = {"NUMBA_CACHE_DIR": str(tmp_path / "fresh")}
    for robot, extra in (("kinova-gen3", ["--psi", "0.5", "--all"]), (str(EXAMPLES / "sawyer.urdf"), [])):
        pose = get_robot(robot).fk(q)
        argv = ["ik", robot, "--position", *map(repr, pose[:3, 3].tolist()), "--rotation",
                *map(repr, pose[:3, :3].ravel().tolist()), *extra, "--json"]
        cached, code, modules, err, out = _cached_then_run(argv, fresh, _SELF_MOTION_KERNELS, output=True)
        assert (cached, code) == (False, 0) and _forbidden(modules, ("numba", "llvmlite")) == [], robot
        python = json.loads(out)
        use_compiled()
        if extra:  # the nearly arm: the closed form's solutions, a second one of a branch not looked for
            assert "not checked whether a branch has a second solution at this psi" in err
            assert [s["others"] for s in python["solutions"]] == [None] * 8
            compiled = ik(get_robot(robot), pose, psi=0.5)
            assert np.all(compiled.exists) and [s["within_limits"] for s in python["solutions"]] == \
                compiled.within_limits.tolist()
            assert np.array_equal([s["q"] for s in python["solutions"]], compiled.q)
        else:
            compiled_code, compiled_out, _ = run(capsys, argv)
            assert compiled_code == 0 and err == "" and python == json.loads(compiled_out)


def test_a_path_of_many_waypoints_runs_as_python_until_its_kernels_are_cached(tmp_path, capsys):
    """``path`` on 33-1000 waypoints of an S-R-S arm, and on up to 500 of the Franka class, runs as Python (and says
    so) while its kernels are not in numba's cache, and gives the compiled answer number for number; a longer path
    runs compiled whatever the cache holds."""
    fresh = {"NUMBA_CACHE_DIR": str(tmp_path / "fresh"), "REDKIN_BACKGROUND_COMPILE": "0"}
    for robot, length in (("kuka-iiwa14", 0.1), ("franka-panda", 0.05)):
        keys = _key_poses(tmp_path, length)
        argv = ["path", robot, "--through", str(keys), "--step", "0.001", "--max-step", "0.1", "--json"]
        cached, code, modules, err, out = _cached_then_run(argv, fresh, output=True)
        assert (cached, code) == (False, 0) and 32 < len(json.loads(out)["q"]) <= 500, robot
        assert _forbidden(modules, ("numba", "llvmlite")) == [] and "runs as Python" in err, robot
        use_compiled()
        compiled_code, compiled_out, _ = run(capsys, argv)
        assert compiled_code == code and json.loads(out) == json.loads(compiled_out), robot
    longer = ["path", "kuka-iiwa14", "--through", str(_key_poses(tmp_path, 0.1001)), "--step", "0.0001",
              "--max-step", "0.1"]  # 1002 waypoints
    [(_, code, modules)] = _modules_after([longer])
    assert code == 0 and "numba" in modules


def test_one_pose_in_a_cell_runs_as_python_and_gives_the_compiled_answer(tmp_path, capsys):
    """``ik`` on one pose with ``--scene`` (the numerical solver's collision-free search on the Sawyer with a body
    file; the iiwa14's closed form at an arm angle with its built-in body), ``arm-angles --scene`` on one pose of an
    exact class (the iiwa14's and the Panda's collision-free sets) and ``path --scene`` on 21 waypoints of the iiwa14,
    while their kernels are not cached, run as Python on a fresh cache: numba is not loaded (they compiled for 12-30
    s before), and the answer is the compiled one, number for number."""
    scene = tmp_path / "cell.yaml"
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: table, type: box, center: [0.6, 0, -0.05], size: [1.2, 1.0, 0.1]}\n"
                     "  - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.0], radius: 0.04}\n"
                     "  - {name: lamp, type: sphere, center: [0.3, -0.4, 0.9], radius: 0.1}\n")
    body = tmp_path / "body.yaml"
    body.write_text("capsules:\n" + "".join(f"  right_l{k}: [{{a: [0, 0, 0], b: [0, 0, 0.2], radius: 0.06}}]\n"
                                              for k in range(1, 6)))
    sawyer = str(EXAMPLES / "sawyer.urdf")
    pose = get_robot(sawyer).fk(np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1]))
    where = ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist())]
    fresh = {"NUMBA_CACHE_DIR": str(tmp_path / "fresh"), "REDKIN_BACKGROUND_COMPILE": "0"}
    down = ["--position", "0.5", "0.1", "0.4", "--rotation", "1", "0", "0", "0", "-1", "0", "0", "0", "-1"]
    for argv in (["ik", sawyer, *where, "--scene", str(scene), "--body", str(body), "--count", "2", "--json"],
                 ["ik", "kuka-iiwa14", *down, "--psi", "0.3", "--scene", str(scene), "--all", "--json"],
                 ["arm-angles", "kuka-iiwa14", *down, "--scene", str(scene), "--json"],
                 ["arm-angles", "franka-panda", *down, "--scene", str(scene), "--json"],
                 ["path", "kuka-iiwa14", "--through", str(_key_poses(tmp_path, 0.1)), "--step", "0.005", "--max-step",
                  "0.1", "--scene", str(scene), "--json"]):
        _, code, modules, _, out = _cached_then_run(argv, fresh, output=True)
        assert code in (0, 1) and _forbidden(modules, ("numba", "llvmlite")) == [], argv[1]
        assert "redkin.collision.clearance" in modules  # it did measure the cell
        use_compiled()
        compiled_code, compiled_out, _ = run(capsys, argv)
        assert compiled_code == code and json.loads(out) == json.loads(compiled_out), argv[1]


def test_kernels_cached_tells_a_compiled_kernel_from_one_not_compiled(tmp_path):
    """:func:`redkin._compiled.kernels_cached` reads numba's index file and redkin's stamp without loading numba: a
    kernel is cached once a process has compiled it into the folder, and not after the stamp changes (the next
    compiled call would empty the folder)."""
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    ask = ("import sys\nfrom redkin._compiled import kernels_cached\nfrom redkin._pose_kernels import pose_defect\n"
           "print((kernels_cached(pose_defect), 'numba' in sys.modules))\n")
    compile_it = ask + "import numpy as np\npose_defect(np.eye(4))\n"

    def run(code: str) -> tuple[bool, bool]:
        result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                                env=environment)
        return ast.literal_eval(result.stdout.splitlines()[-1])

    assert run(compile_it) == (False, False)
    assert run(ask) == (True, False)
    for stamp in tmp_path.rglob("redkin-kernels.stamp"):
        stamp.write_text("another version")
    assert run(ask) == (False, False)


@pytest.mark.parametrize(("robot", "q"), [("kuka-iiwa14", [0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1]),
                                          ("franka-panda", [0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.7])])
def test_an_explorer_page_runs_as_python_until_its_kernels_are_cached_and_is_the_same_page(tmp_path, robot, q):
    """``explore`` at a pose of an exact class runs as Python (and says so) on a fresh NUMBA_CACHE_DIR and writes the
    page this process writes with the kernels compiled, byte for byte; on the ambient cache it runs compiled
    exactly when the page's kernels are cached."""
    from redkin.explore import explorer_data, explorer_html

    page = tmp_path / "page.html"
    argv = ["explore", robot, "--q", *map(str, q), "--out", str(page)]
    cached, code, modules, err = _cached_then_run(argv, {"NUMBA_CACHE_DIR": str(tmp_path / "fresh")},
                                                  PAGE_KERNELS["q7" if robot.startswith("franka") else "psi"])
    assert (cached, code) == (False, 0)
    assert _forbidden(modules, ("numba", "llvmlite")) == [] and "runs as Python" in err
    chain = get_robot(robot)
    compiled = explorer_html(explorer_data(chain, chain.fk(np.array(q)), None, q=np.array(q)), degrees=False)
    assert page.read_text(encoding="utf-8") == compiled
    cached, code, modules, err = _cached_then_run([*argv[:-1], str(tmp_path / "again.html")], {},
                                                  PAGE_KERNELS["q7" if robot.startswith("franka") else "psi"])
    assert code == 0 and ("numba" in modules) == cached and ("runs as Python" in err) == (not cached)


def test_a_mesh_is_covered_compiled(tmp_path):
    """Covering a mesh runs compiled even in a command that runs small work as Python: it takes seconds compiled and
    minutes as Python (20 s for one 2257-vertex link of the xArm7).  A fresh process runs ``arm-angles`` on the iiwa14
    with link 3 a mesh file, and records whether numba was loaded once each mesh was covered (``ik`` on one pose in
    a cell otherwise runs as Python: the test above)."""
    trimesh = pytest.importorskip("trimesh")
    from redkin.examples import resolve

    (tmp_path / "meshes").mkdir()
    trimesh.creation.capsule(height=0.2, radius=0.06).export(tmp_path / "meshes" / "link_3.stl")
    urdf = tmp_path / "iiwa.urdf"
    urdf.write_text(resolve("iiwa14.urdf").read_text().replace(
        '<link name="lbr_iiwa_link_3"/>', '<link name="lbr_iiwa_link_3"><collision><geometry><mesh filename='
        '"meshes/link_3.stl"/></geometry></collision></link>'))
    scene = tmp_path / "cell.yaml"
    scene.write_text("margin: 0.01\nobstacles:\n  - {name: ball, type: sphere, center: [2, 2, 2], radius: 0.1}\n")
    argv = ["arm-angles", str(urdf), "--position", "0.4", "0.1", "0.5", "--rotation", "1", "0", "0", "0", "-1", "0",
            "0", "0", "-1", "--scene", str(scene)]
    code = "\n".join([
        "import contextlib, io",
        "from redkin._compiled import numba_loaded",
        "from redkin.collision import mesh_cache",
        "seen = []",
        "original = mesh_cache.covering_capsules",
        "def covering(*args, **kwargs):",
        "    covers = original(*args, **kwargs)",
        "    seen.append(numba_loaded())",
        "    return covers",
        "mesh_cache.covering_capsules = covering",
        "from redkin.cli.main import main",
        "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):",
        f"    result = main({argv!r})",
        "print((result, seen))",
    ])
    environment = {**os.environ, "REDKIN_CACHE_DIR": str(tmp_path / "covers")}  # no cover kept from another run
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=environment)
    assert ast.literal_eval(done.stdout.splitlines()[-1]) == (0, [True])
