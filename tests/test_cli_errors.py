"""A law for the whole command line: any malformed argument ends in exit code 2 and one line, never a traceback
and never a warning.

Each subcommand has a valid, cheap template; hypothesis breaks one slot of it
(a bad value of the slot's kind, a value too many or too few, an unknown
robot, branch or plane, a size out of range, a huge number such as 1e308, an
unwritable or missing path, an output file that exists, a malformed robot file
or one with NaN, inf or 1e308 in it) and the command must refuse it with
exactly one line on stderr and no warning text.

The commands run with ``main``'s own net for warnings taken away (:func:`run_cli`), so that a numpy warning
anywhere on the way is seen here: the validation at the edge must refuse the input before numpy warns.  One
test runs the real command in a subprocess, net and all, as a user does.
"""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys
import types
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import redkin.cli.main as cli_main
from redkin.cli.main import main

POSE = ["--position", "0.65", "0", "0.5", "--rotation", "-1", "0", "0", "0", "1", "0", "0", "0", "-1"]
Q7 = ["0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7"]

# Slots: (option or None for positionals, kind, values).  A template is a list of slots; rendering
# flattens them.  Kinds pick the bad values below.
TEMPLATES = {
    "fk": [(None, "word", ["fk"]), (None, "robot", ["pa10-7c"]), (None, "numbers", Q7)],
    "jacobian": [(None, "word", ["jacobian"]), (None, "robot", ["barrett-wam"]), (None, "numbers", Q7),
                 ("--manipulability", "flag", [])],
    "ik": [(None, "word", ["ik"]), (None, "robot", ["pa10-7c"]),
           ("--position", "bounded numbers", ["0.65", "0", "0.5"]),
           ("--rotation", "rotation", ["-1", "0", "0", "0", "1", "0", "0", "0", "-1"]), ("--psi", "number", ["10"]),
           ("--branch", "branch", ["-+-"]), ("--deg", "flag", [])],
    "arm-angles": [(None, "word", ["arm-angles"]), (None, "robot", ["kuka-iiwa14"]),
                   ("--position", "bounded numbers", ["0.5", "0.1", "0.6"]),
                   ("--rotation", "rotation", ["-1", "0", "0", "0", "1", "0", "0", "0", "-1"]),
                   ("--branch", "branch", ["--+"]), ("--weights", "numbers", ["0.5", "0.5"])],
    "track": [(None, "word", ["track"]), (None, "robot", ["barrett-wam"]), ("--q0", "numbers", Q7),
              ("--twist", "bounded numbers", ["0.1", "0", "0", "0", "0", "0"]), ("--duration", "size", ["0.01"]),
              ("--dt", "size", ["0.005"]), ("--eps", "number", ["0.1"]), ("--plot", "file", ["track.png"]),
              ("--json", "flag", [])],
    "torso-arm ik": [(None, "word", ["torso-arm", "ik"]), ("--position", "bounded numbers", ["0.6", "0.4", "0.3"]),
                     ("--angles", "numbers", ["0", "90", "0"]), ("--shoulder", "number", ["10"]),
                     ("--elbow", "number", ["20"]), ("--reference", "reference", ["vector"]), ("--deg", "flag", [])],
    "torso-arm map": [(None, "word", ["torso-arm", "map"]), ("--plane", "plane", ["z=0.3"]),
                      ("--extent", "bounded numbers", ["-0.3", "1.1", "-0.6", "1.0"]),
                      ("--resolution", "count", ["5"]),
                      ("--shoulder", "number", ["0.2"]), ("--elbow", "number", ["0.3"]),
                      ("--out", "file", ["map.png"])],
    "torso-arm best map": [(None, "word", ["torso-arm", "map"]), ("--plane", "plane, default extent", ["y=0.3"]),
                           ("--resolution", "count", ["4"]), ("--samples", "counts", ["2", "3"])],
    "virtual-arms": [(None, "word", ["virtual-arms"]), (None, "robot", ["planar-5"]),
                     ("--goal", "bounded numbers", ["0.5", "0.6"]), ("--point", "point", ["joint:3=0.5,0.6"]),
                     ("--weight", "number", ["1"]), ("--weight", "number", ["2"]),
                     ("--fix", "joints", ["1"]), ("--max-steps", "count", ["3"]), ("--out", "file", ["arms.png"])],
    "virtual-arms obstacle": [(None, "word", ["virtual-arms"]), (None, "robot", ["planar-5"]),
                              ("--goal", "bounded numbers", ["0.5", "0.6"]),
                              ("--obstacle", "obstacle", ["1.2,-0.9,0.1"]),
                              ("--max-steps", "count", ["2"])],
    "workspace": [(None, "word", ["workspace"]), (None, "robot", ["pa10-7c"]), ("--out", "directory", ["map"]),
                  ("--extent", "numbers", ["-0.9", "0.9", "-0.9", "0.9", "-0.5", "1.3"]),
                  ("--resolution", "count", ["2"]), ("--orientations", "count", ["2"]), ("--chunk", "count", ["1"])],
    "reproduce": [(None, "word", ["reproduce"]), (None, "paper", ["000"]), ("--out", "report folder", ["report"]),
                  ("--quiet", "flag", [])],
    "explore": [(None, "word", ["explore"]), (None, "robot", ["pa10-7c"]),
                ("--position", "bounded numbers", ["0.65", "0", "0.5"]),
                ("--rotation", "rotation", ["-1", "0", "0", "0", "1", "0", "0", "0", "-1"]),
                ("--branch", "branch", ["+-+"]), ("--out", "page", ["page.html"])],
    "robots --show": [(None, "word", ["robots"]), ("--show", "robot", ["pa10-7c"]), ("--deg", "flag", [])],
}
# Every rendered command has exactly one broken slot; the rest of its template runs, cheaply, on its own
# (test_templates_are_valid_so_the_law_above_is_not_vacuous), so the refusal comes from that slot.

NUMBER_BAD = ["nan", "NaN", "inf", "-inf", "1e999", "-1e999", "abc", "", "0x", "1,5"]
#: Finite numbers too large for any length, speed or rotation entry: refused, not squared into an overflow.
HUGE = ["1e308", "-1e308", "1e200"]
BAD_VALUES = {
    "number": NUMBER_BAD,
    "numbers": NUMBER_BAD,
    "bounded numbers": NUMBER_BAD + HUGE + ["1e7"],  # positions, goals, extents (m) and twists: at most 1e6
    "rotation": NUMBER_BAD + HUGE + ["2"],  # "2" makes the matrix non-orthonormal
    "size": NUMBER_BAD + HUGE + ["0", "-1", "-1e-3", "1e12", "1e300"],
    "count": NUMBER_BAD + ["0", "-5", "2.5", "1000000000000", "99999999999999999999"],
    "counts": NUMBER_BAD + ["0", "-5", "2.5", "100000", "1000000000000"],
    "robot": ["no-such-robot", "PA10", "", "robots", "/no/such/file.toml", "missing.json", "bad.toml", "bad.json",
              "empty.toml", "wrong-keys.toml", "nan-joint.toml", "robot.urdf", "a-directory", "inf-joint.toml",
              "huge-joint.toml", "huge-joint.json", "huge-tool.toml", "huge.urdf", "nan.urdf", "inf-limit.urdf"],
    "branch": ["++", "++++", "+-x", "abc", "", "0", "+ +", "-", "---+"],
    "plane": ["w=1", "z=", "=0.3", "z=nan", "z=inf", "z=1e999", "z=0.3m", "z", ""],
    "plane, default extent": ["w=1", "z=nan", "z=1e999", "y=5", "x=-9", "z=2.1"],  # the last three miss the reach
    "reference": ["sideways", "1,2", "1,2,3,4", "a,b,c", "nan,0,0", "0,0,0"],
    "point": ["joint:3", "joint:9=0.5,0.6", "joint:3=a,b", "elbow=0.1,0.2", "joint:3=0.5", "joint:3=nan,0",
              "link:2@1.5=0,0", "joint:3=1e308,0", "joint:3=0,-1e308"],
    "joints": ["0", "9", "a", "1,,2", "-1", "1.5"],
    "obstacle": ["1.2,-0.9", "1.2,-0.9,0", "1.2,-0.9,-0.1", "a,b,c", "nan,-0.9,0.1", "1.2,-0.9,0.1,0.2",
                 "1e308,-0.9,0.1", "1.2,-0.9,1e308"],
    "paper": ["999", "abc", "", "000x"],
    "file": ["/proc/forbidden/run.png", "/proc/forbidden", "run.txt", "run", "a-directory", "/dev/null/x.png",
             "existing.png", "a-file/run.png"],
    "page": ["/proc/forbidden/page.html", "page.png", "a-directory", "existing.html", "a-file/page.html"],
    "directory": ["/proc/forbidden", "/proc/forbidden/report", "/dev/null/report", "a-file"],
    "report folder": ["/proc/forbidden", "/proc/forbidden/report", "/dev/null/report", "a-file", "old-report"],
    "word": [],  # the command names stay
    "flag": [],
}
KINDS_TAKING_A_COUNT_CHANGE = {"numbers", "bounded numbers", "rotation", "counts"}


def _robot_files(folder: Path) -> None:
    """Malformed robot descriptions the ``robot`` slot may name (relative paths, run inside ``folder``)."""
    (folder / "bad.toml").write_text("name = 'x'\n[[joint]\na = 0\n")  # TOML syntax error
    (folder / "bad.json").write_text('{"name": "x", "joint": [')
    (folder / "empty.toml").write_text("")
    (folder / "wrong-keys.toml").write_text("name = 'x'\nconvention = 'dh'\n[[joint]]\nlength = 1\n")
    (folder / "nan-joint.toml").write_text("name = 'x'\nconvention = 'dh'\n[[joint]]\na = nan\nalpha = 0\nd = 0\n")
    (folder / "robot.urdf").write_text("<robot name='x'><link name='a'/>")
    (folder / "a-directory").mkdir(exist_ok=True)
    (folder / "a-file").write_text("not a directory")
    # finite but absurd, and non-finite, numbers in the robot files
    (folder / "inf-joint.toml").write_text("name = 'x'\nconvention = 'dh'\n[[joint]]\na = inf\nalpha = 0\nd = 0\n")
    seven = "".join(f"[[joint]]\na = {a}\nalpha = -90\nd = 0.3\n" for a in ("1e308", "0", "-1e308", "0", "0", "0", "0"))
    (folder / "huge-joint.toml").write_text("name = 'x'\nconvention = 'dh'\nangle_unit = 'deg'\n" + seven)
    (folder / "huge-joint.json").write_text('{"name": "x", "convention": "dh", "joint": ['
                                            + ", ".join(f'{{"a": 0, "alpha": 0, "d": {d}}}' for d in
                                                        ("0.3", "1e308", "0.3", "0.3", "0.3", "0.3", "0.3")) + "]}")
    (folder / "huge-tool.toml").write_text("name = 'x'\nconvention = 'dh'\n[[joint]]\na = 0.5\nalpha = 0\nd = 0\n"
                                           "[tool]\ntranslation = [0, 0, -1e308]\n")
    (folder / "huge.urdf").write_text(_urdf(xyz="1e308 0 0"))
    (folder / "nan.urdf").write_text(_urdf(xyz="nan 0 0"))
    (folder / "inf-limit.urdf").write_text(_urdf(limit='<limit lower="-inf" upper="nan" effort="1" velocity="1"/>'))
    (folder / "existing.png").write_bytes(b"an earlier result")
    (folder / "existing.html").write_text("an earlier page")
    (folder / "old-report").mkdir(exist_ok=True)
    (folder / "old-report" / "index.html").write_text("an earlier report")


def _urdf(xyz: str = "0 0 0.3", limit: str = '<limit lower="-1" upper="1" effort="1" velocity="1"/>') -> str:
    """A seven-joint URDF chain, the second joint placed at ``xyz`` and every joint with ``limit``."""
    links = "".join(f"<link name='l{i}'/>" for i in range(8))
    joints = "".join(
        f"<joint name='j{i + 1}' type='revolute'><parent link='l{i}'/><child link='l{i + 1}'/>"
        f"<origin xyz='{xyz if i == 1 else '0 0 0.3'}' rpy='0 0 0'/><axis xyz='0 0 1'/>{limit}</joint>"
        for i in range(7))
    return f"<robot name='x'>{links}{joints}</robot>"


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cli-errors")
    _robot_files(folder)
    return folder


@st.composite
def broken_commands(draw) -> tuple[str, list[str]]:
    """A template with exactly one slot broken: a bad value, or a value too many or too few."""
    name = draw(st.sampled_from(sorted(TEMPLATES)))
    slots = TEMPLATES[name]
    breakable = [i for i, (_, kind, values) in enumerate(slots)
                 if BAD_VALUES[kind] or kind in KINDS_TAKING_A_COUNT_CHANGE]
    index = draw(st.sampled_from(breakable))
    _option, kind, values = slots[index]
    ways = ["value"] if BAD_VALUES[kind] else []
    if kind in KINDS_TAKING_A_COUNT_CHANGE:
        ways += ["fewer", "more"]
    way = draw(st.sampled_from(ways))
    if way == "value":
        position = draw(st.integers(0, len(values) - 1))
        broken = list(values)
        broken[position] = draw(st.sampled_from(BAD_VALUES[kind]))
    elif way == "fewer":
        broken = values[:-1]
    else:
        broken = values + ["0.25"]
    argv: list[str] = []
    for i, (opt, _, vals) in enumerate(slots):
        chosen = broken if i == index else vals
        if opt is None:
            argv += chosen
        elif chosen and draw(st.booleans()) and len(chosen) == 1:
            argv.append(f"{opt}={chosen[0]}")  # the same option written with '='
        else:
            argv += [opt, *chosen]
    return f"{name}: slot {index} ({kind}) {way}", argv


#: ``main`` holds back warnings (after a user mistake its one line says what went wrong): the tests take that net
#: away, so that a warning raised anywhere on the way shows up as text on stderr and breaks the law.
_NO_NET = types.SimpleNamespace(catch_warnings=lambda **kwargs: contextlib.nullcontext([]))


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """Run ``redkin argv`` in this process without ``main``'s net for warnings: exit code, stdout, and stderr with
    every warning raised on the way written into it as numpy's would be."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
            warnings.catch_warnings(record=True) as caught, _without_net():
        warnings.simplefilter("always")
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse's own exit
            code = exc.code
    text = err.getvalue() + "".join(f"{w.filename}:{w.lineno}: {w.category.__name__}: {w.message}\n"
                                    for w in caught)
    return code, out.getvalue(), text


@contextlib.contextmanager
def _without_net():
    saved = cli_main.warnings
    cli_main.warnings = _NO_NET  # type: ignore[assignment]
    try:
        yield
    finally:
        cli_main.warnings = saved


def _refused_in_one_line(code, out: str, err: str) -> bool:
    lines = err.strip("\r\n").splitlines()
    return (code == 2 and len(lines) == 1 and bool(lines[0].strip()) and "Traceback" not in err + out
            and "Warning" not in err)


@settings(max_examples=250, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(case=broken_commands())
def test_every_malformed_command_exits_2_with_one_line(workdir, monkeypatch, case):
    description, argv = case
    monkeypatch.chdir(workdir)
    code, out, err = run_cli(argv)
    lines = err.strip("\r\n").splitlines()
    assert "Traceback" not in err + out, (description, argv, err)
    assert "Warning" not in err, (description, argv, err)
    assert code == 2, (description, argv, code, out[-300:], err)
    assert len(lines) == 1 and lines[0].strip(), (description, argv, err)


@pytest.mark.parametrize("name", sorted(TEMPLATES))
def test_templates_are_valid_so_the_law_above_is_not_vacuous(tmp_path, monkeypatch, name):
    """Unbroken, every template runs (exit 0): the failures above come from the one broken slot."""
    if name == "reproduce":
        pytest.skip("the valid reproduce template runs a whole section; tests/test_reproduce_* run it")
    monkeypatch.chdir(tmp_path)  # not the shared folder: the files written here would make later refusals vacuous
    _robot_files(tmp_path)
    argv = [value for option, _, values in TEMPLATES[name] for value in ([option] if option else []) + values]
    code, _out, err = run_cli(argv)
    assert code == 0, (argv, err)


def _every_single_break() -> list[tuple[str, list[str]]]:
    """Every (template, slot, bad value) once, and every count change: the sweep hypothesis samples from."""
    cases = []
    for name, slots in TEMPLATES.items():
        for index, (_option, kind, values) in enumerate(slots):
            variants = [values[:p] + [bad] + values[p + 1:] for p in range(len(values)) for bad in BAD_VALUES[kind]]
            if kind in KINDS_TAKING_A_COUNT_CHANGE:
                variants += [values[:-1], values + ["0.25"]]
            for broken in variants:
                argv = []
                for i, (opt, _, vals) in enumerate(slots):
                    argv += ([opt] if opt else []) + (broken if i == index else vals)
                cases.append((f"{name}: slot {index} ({kind})", argv))
    return cases


def test_every_single_break_exits_2_with_one_line(workdir, monkeypatch):
    monkeypatch.chdir(workdir)
    failures = []
    for description, argv in _every_single_break():
        code, out, err = run_cli(argv)
        if not _refused_in_one_line(code, out, err):
            failures.append((description, " ".join(argv), code, err[-200:]))
    assert not failures, f"{len(failures)} commands: " + "\n".join(map(str, failures[:10]))


#: Slots whose values are numbers that may be any finite value (joint values, angles, weights, thresholds).
_ANY_FINITE = {"number", "numbers"}


def _huge_cases() -> list[tuple[str, list[str]]]:
    """Every number of every template (not the workspace map's, which is another command's law) replaced by a
    huge finite value, one at a time."""
    cases = []
    for name, slots in TEMPLATES.items():
        if name in ("workspace", "reproduce"):
            continue
        for index, (_option, kind, values) in enumerate(slots):
            if kind not in _ANY_FINITE:
                continue
            for position in range(len(values)):
                for huge in ("1e308", "-1e308", "1e160"):
                    argv = []
                    for i, (opt, _, vals) in enumerate(slots):
                        chosen = vals[:position] + [huge] + vals[position + 1:] if i == index else vals
                        argv += ([opt] if opt else []) + chosen
                    cases.append((f"{name}: slot {index} = {huge}", argv))
    return cases


def test_a_huge_finite_number_is_answered_or_refused_never_warned_about(tmp_path, monkeypatch):
    """1e308 as a joint value, an angle, a weight or a threshold: a number, if an absurd one.  The command either
    answers (exit 0, finite numbers only) or refuses in one line; no overflow warning, no inf in the output."""
    monkeypatch.chdir(tmp_path)
    failures = []
    for description, argv in _huge_cases():
        code, out, err = run_cli(argv)
        for written in tmp_path.iterdir():  # an answer's figure or page: the next case writes its own
            written.unlink()
        answered = code == 0 and "Warning" not in err and "inf" not in out.lower() and "nan" not in out.lower()
        if not (answered or _refused_in_one_line(code, out, err)):
            failures.append((description, " ".join(argv), code, err[-300:], out[-200:]))
    assert not failures, f"{len(failures)} commands: " + "\n".join(map(str, failures[:10]))


@pytest.mark.parametrize("rotation", [["1e308", "0", "0", "0", "1", "0", "0", "0", "-1"],
                                      ["-1e308", *["1e308"] * 8], ["1e154", "0", "0", "0", "1", "0", "0", "0", "1"]])
def test_a_huge_rotation_entry_is_refused_by_the_check_before_any_product(rotation):
    """The check itself, under warnings as errors: an entry larger than 1 in magnitude is refused before
    ``R R^T`` overflows."""
    import numpy as np

    from redkin._validation import check_pose, check_rotation

    matrix = np.array(rotation, dtype=float).reshape(3, 3)
    pose = np.eye(4)
    pose[:3, :3] = matrix
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="entry of magnitude"):
            check_rotation(matrix, "--rotation")
        with pytest.raises(ValueError, match="entry of magnitude"):
            check_pose(pose)


def test_the_command_itself_prints_one_line_for_a_huge_rotation(tmp_path):
    """As the user runs it (a new process, Python's default warning filters, main's net in place): numpy's
    "RuntimeWarning: overflow encountered in matmul" and its source line no longer come before the error."""
    command = [sys.executable, "-W", "default", "-m", "redkin.cli.main", "ik", "pa10-7c", "--position", "0.65", "0",
               "0.5", "--rotation", "1e308", "0", "0", "0", "1", "0", "0", "0", "-1", "--psi", "10"]
    result = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("redkin: error: --rotation must be orthonormal")


def test_main_prints_a_warning_of_a_successful_run_as_one_line(monkeypatch, capsys):
    """The net itself: a warning raised during a run that succeeds is printed once, as one line, without numpy's
    source line; one raised before a user mistake is dropped (the error's line says what went wrong)."""
    import redkin.cli.basic as basic

    def noisy(args):
        warnings.warn("overflow encountered in matmul", RuntimeWarning, stacklevel=1)
        warnings.warn("overflow encountered in matmul", RuntimeWarning, stacklevel=1)
        return 0

    def noisy_mistake(args):
        warnings.warn("overflow encountered in matmul", RuntimeWarning, stacklevel=1)
        raise ValueError("--rotation must be orthonormal")

    monkeypatch.setattr(basic, "_run_fk", noisy)
    assert main(["fk", "pa10-7c", "0"]) == 0
    assert capsys.readouterr().err == "redkin: warning: overflow encountered in matmul\n"
    monkeypatch.setattr(basic, "_run_fk", noisy_mistake)
    assert main(["fk", "pa10-7c", "0"]) == 2
    assert capsys.readouterr().err == "redkin: error: --rotation must be orthonormal\n"
