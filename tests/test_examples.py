"""The shipped example robot files (:mod:`redkin.examples`) and the rule by which a path finds them.

Laws: every example loads from an empty folder by ``examples/NAME`` and by ``NAME``, in Python and on the command
line; a file that exists (the user's own, of the same name) wins; an absolute path or another folder is never
looked up; the xacro example is ``fr3.urdf`` with and without the hand; every example is package data (the wheel
carries it); a missing extra's message gives the command for an installed redkin and for a checkout.
"""

from __future__ import annotations

import fnmatch
import sys
from pathlib import Path

import numpy as np
import pytest

from redkin import examples
from redkin.cli.main import main
from redkin.errors import RedkinError, RobotDescriptionError
from redkin.models import get_robot

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
#: A two-joint robot file: a user's own ``pa10.toml``, unlike the shipped seven-joint one.
OWN_ARM = 'name = "mine"\n[[joint]]\na = 0.1\nalpha = 0\nd = 0\n[[joint]]\na = 0.1\nalpha = 0\nd = 0\n'


def _needs(name: str) -> None:
    if name.endswith(".xml"):
        pytest.importorskip("mujoco", reason="the mjcf extra (mujoco) is not installed")


@pytest.mark.parametrize("name", examples.names())
def test_every_example_loads_from_an_empty_folder_by_either_name(name, tmp_path, monkeypatch):
    _needs(name)
    monkeypatch.chdir(tmp_path)
    written, bare = get_robot(f"examples/{name}"), get_robot(name)
    shipped = get_robot(examples.path(name))
    q = np.random.default_rng(0).uniform(-1.0, 1.0, (5, shipped.n))
    assert written.n == bare.n == shipped.n >= 7
    np.testing.assert_array_equal(written.fk(q), shipped.fk(q))
    np.testing.assert_array_equal(bare.fk(q), shipped.fk(q))


def test_the_command_line_finds_an_example_from_an_empty_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["fk", "examples/iiwa14.urdf", "0", "0.5", "0", "-1.2", "0", "0.8", "0", "--json"]) == 0
    assert main(["robots", "--show", "pa10.toml"]) == 0
    assert "pa10" in capsys.readouterr().out


def test_a_file_of_the_user_wins_over_the_example_of_the_same_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "pa10.toml").write_text(OWN_ARM)
    assert get_robot("pa10.toml").n == 2
    assert get_robot("examples/pa10.toml").n == 7  # no examples/ folder here: the shipped file
    (tmp_path / "examples").mkdir()
    (tmp_path / "examples" / "pa10.toml").write_text(OWN_ARM)
    assert get_robot("examples/pa10.toml").n == 2


def test_other_folders_and_absolute_paths_are_never_looked_up(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    for path in ("robots/iiwa14.urdf", str(tmp_path / "iiwa14.urdf"), "examples/nothing.urdf", "./x/pa10.toml"):
        with pytest.raises(RobotDescriptionError):
            get_robot(path)
    assert examples.resolve(tmp_path / "iiwa14.urdf") == tmp_path / "iiwa14.urdf"
    assert main(["fk", "robots/iiwa14.urdf", *["0"] * 7]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "robots/iiwa14.urdf" in err


def test_an_unknown_example_name_lists_the_examples():
    with pytest.raises(ValueError, match=r"no example named 'iiwa.urdf': redkin ships fr3\.urdf, .*yumi_right\.urdf"):
        examples.path("iiwa.urdf")


def test_the_xacro_example_is_the_fr3_urdf_with_and_without_the_hand():
    q = np.random.default_rng(1).uniform(-1.0, 1.0, (20, 7))
    for hand, tip in ((True, None), (False, "fr3_link8")):
        expanded = get_robot("examples/fr3.urdf.xacro", xacro_args={"hand": hand})
        written = get_robot("examples/fr3.urdf", tip=tip)
        np.testing.assert_allclose(expanded.fk(q), written.fk(q), rtol=0, atol=1e-15)
        np.testing.assert_array_equal(expanded.limits, written.limits)
        np.testing.assert_array_equal(expanded.velocity, written.velocity)
        assert expanded.joint_names == written.joint_names
    np.testing.assert_allclose(get_robot("fr3.urdf.xacro", xacro_args={"hand": False}).fk(q),
                               get_robot("franka-fr3").fk(q), rtol=0, atol=1e-12)
    assert get_robot("fr3.urdf.xacro", xacro_args={"arm_id": "left"}).joint_names[0] == "left_joint1"


def test_every_example_is_package_data():
    """pyproject's package-data patterns name every example file, so that an installed redkin (a wheel) has them."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    patterns = config["tool"]["setuptools"]["package-data"]["redkin"]
    for name in examples.names():
        assert any(fnmatch.fnmatch(f"examples/{name}", pattern) for pattern in patterns), name


def test_a_missing_mjcf_extra_gives_the_command_for_either_install(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # importing it now raises ImportError
    monkeypatch.chdir(tmp_path)
    with pytest.raises(RedkinError) as caught:
        get_robot("examples/iiwa14.xml")
    assert 'pip install "redkin[mjcf]"' in str(caught.value) and 'pip install -e ".[mjcf]"' in str(caught.value)
    assert main(["fk", "examples/iiwa14.xml", *["0"] * 7]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "in a checkout of redkin" in err


def test_a_missing_examples_path_names_the_shipped_ones(tmp_path, monkeypatch, capsys):
    """``examples/NAME`` that neither exists nor is shipped: one line listing what is shipped, exit 2."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(RobotDescriptionError, match=r"redkin ships no example 'iiwa15\.urdf' \(it ships fr3\.urdf"):
        get_robot("examples/iiwa15.urdf")
    assert main(["fk", "examples/iiwa15.urdf", *["0"] * 7]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and all(name in err for name in examples.names())
