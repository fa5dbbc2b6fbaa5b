"""Every option that writes a file: it never replaces an existing file unless ``--force`` is given, and an output
it cannot write is refused with one line and exit code 2, before any work.

The commands (not the workspace maps, which resume into their folder) and a cheap run of each:
``track --plot``, ``virtual-arms --out``, ``torso-arm map --out``, ``explore --out`` and ``reproduce --out``.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from redkin.cli.main import main

POSE = ["--position", "0.65", "0", "0.5", "--rotation", "-1", "0", "0", "0", "1", "0", "0", "0", "-1"]

#: name -> (argv before the file, the option, a file name it accepts)
WRITERS = {
    "track": (["track", "barrett-wam", "--q0", *["0.3"] * 7, "--twist", "0.1", "0", "0", "0", "0", "0",
               "--duration", "0.02", "--dt", "0.01", "--method", "pinv"], "--plot", "run.png"),
    "virtual-arms": (["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--max-steps", "3"], "--out", "run.png"),
    "torso-arm map": (["torso-arm", "map", "--plane", "z=0.3", "--extent", "0", "1", "-0.4", "0.8", "--resolution",
                       "4", "--shoulder", "0.2", "--elbow", "0"], "--out", "map.png"),
    "explore": (["explore", "pa10-7c", *POSE], "--out", "page.html"),
}


def _run(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exc:  # argparse's own refusals
        return int(exc.code)


def _one_line(capsys) -> str:
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.mark.parametrize("name", sorted(WRITERS))
def test_an_existing_output_is_kept_unless_force_is_given(tmp_path, monkeypatch, capsys, name):
    """`track --plot run.png` and then `virtual-arms --out run.png` no longer replace each other silently."""
    monkeypatch.chdir(tmp_path)
    argv, option, filename = WRITERS[name]
    target = tmp_path / filename
    target.write_bytes(b"an earlier result")
    assert _run([*argv, option, filename]) == 2
    line = _one_line(capsys)
    assert option in line and "already exists" in line and "--force" in line
    assert target.read_bytes() == b"an earlier result"
    assert _run([*argv, option, filename, "--force"]) == 0
    capsys.readouterr()
    assert target.stat().st_size > 1000 and target.read_bytes() != b"an earlier result"


def test_two_commands_on_one_file_the_second_refuses(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    track, _, _ = WRITERS["track"]
    arms, _, _ = WRITERS["virtual-arms"]
    assert _run([*track, "--plot", "run.png"]) == 0
    first = (tmp_path / "run.png").read_bytes()
    assert _run([*arms, "--out", "run.png"]) == 2
    assert "already exists" in capsys.readouterr().err
    assert (tmp_path / "run.png").read_bytes() == first


@pytest.mark.parametrize("name", sorted(WRITERS))
@pytest.mark.parametrize("where", ["/proc/forbidden/{}", "/dev/null/{}", "a-file/{}", "/proc/{}", "a" * 300 + "{}"])
def test_an_output_that_cannot_be_written_exits_2_with_one_line(tmp_path, monkeypatch, capsys, name, where):
    """A folder that does not exist and cannot be made (under /proc), a path through a file, a folder that takes no
    file (/proc itself: it said "No such file or directory"), a name longer than the file system takes (it failed
    after the run with exit 1): refused before the run, with or without --force."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a-file").write_text("not a folder")
    argv, option, filename = WRITERS[name]
    for force in ([], ["--force"]):
        assert _run([*argv, option, where.format(filename), *force]) == 2
        assert option in _one_line(capsys)
    assert not list(tmp_path.glob("*.png")) and not list(tmp_path.glob("*.html"))


def test_replacing_an_existing_file_that_cannot_be_written_is_refused_in_one_line(tmp_path, monkeypatch):
    """With --force, an existing file that cannot be opened for writing is refused up front (read-only here; root
    may write anyway, so the refusal of the open is simulated there)."""
    import os

    import redkin.cli.common as common

    target = tmp_path / "run.png"
    target.write_bytes(b"kept")
    target.chmod(0o444)
    if os.geteuid() == 0:
        def refuse(path, mode="r", *args, **kwargs):
            raise PermissionError(13, "Permission denied", str(path))

        monkeypatch.setattr(common, "open", refuse, raising=False)
    with pytest.raises(common.UsageError, match=r"cannot write to --out .*: Permission denied"):
        common.output_file(target, "--out", {".png"}, force=True)
    with pytest.raises(common.UsageError, match="already exists"):
        common.output_file(target, "--out", {".png"}, force=False)
    assert target.read_bytes() == b"kept"


def test_reproduce_refuses_a_folder_that_holds_a_report(tmp_path, monkeypatch, capsys):
    """`redkin reproduce --out report` a second time: refused unless --force (the sections are not run)."""
    import redkin.reproduce

    calls = []

    def fake_run(out, papers, progress=None):
        calls.append(out)
        (Path(out) / "index.html").write_text("new")
        (Path(out) / "summary.json").write_text("{}")
        return {}

    monkeypatch.setattr(redkin.reproduce, "run", fake_run)
    report = tmp_path / "report"
    assert _run(["reproduce", "models", "--out", str(report), "--quiet"]) == 0  # a new folder: written
    capsys.readouterr()
    (report / "index.html").write_text("the earlier report")
    assert _run(["reproduce", "models", "--out", str(report), "--quiet"]) == 2
    line = _one_line(capsys)
    assert "--out" in line and "index.html" in line and "--force" in line
    assert (report / "index.html").read_text() == "the earlier report" and len(calls) == 1
    assert _run(["reproduce", "models", "--out", str(report), "--quiet", "--force"]) == 0
    assert (report / "index.html").read_text() == "new" and len(calls) == 2
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "notes.txt").write_text("mine")
    assert _run(["reproduce", "models", "--out", str(tmp_path / "other"), "--quiet"]) == 0  # no report there yet
    assert _run(["reproduce", "models", "--out", "/proc/forbidden/report", "--quiet"]) == 2
    assert "--out" in _one_line(capsys)


def test_an_input_name_too_long_for_the_file_system_exits_2_with_one_line(capsys):
    """A robot file or a poses file whose name the file system cannot hold is the user's mistake: one line, exit 2
    (it was the machine's, exit 1, with the whole name)."""
    long = "a" * 300
    for argv in (["fk", f"{long}.urdf", *["0"] * 7], ["ik", "kuka-iiwa14", "--poses", f"{long}.npy", "--psi", "0"]):
        assert _run(argv) == 2
        line = _one_line(capsys)
        assert "too long" in line and len(line) < 200, line


class _FullDisk:
    """The ``os`` module as :mod:`redkin._files` sees it on a full disk: every write fails with ENOSPC."""

    def __getattr__(self, name: str):
        import os

        return getattr(os, name)

    @staticmethod
    def write(descriptor: int, data) -> int:
        import errno
        import os

        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.mark.parametrize("option, filename", [("--out", "page.html"), ("--plot", "path.png"),
                                              ("--trajectory", "trajectory.json")])
def test_a_full_disk_names_the_file_in_one_line_exit_2_and_leaves_nothing(tmp_path, monkeypatch, capsys, option,
                                                                          filename):
    """An output the disk has no room for is the user's to free, as a folder that takes no file: exit 2 and one
    line that names the file (it said "[Errno 28] No space left on device", exit 1, the code of "no path").  The
    write is whole or nothing (redkin._files.write_durably)."""
    import numpy as np

    import redkin._files as files
    from redkin.models import franka_panda

    monkeypatch.chdir(tmp_path)
    if option == "--out":
        argv = [*WRITERS["explore"][0], "--out", filename]
    else:
        panda = franka_panda()
        np.save("poses.npy", panda.fk(np.linspace(-0.4, 0.4, 5)[:, None] * np.ones(7) * [1, 1, 1, -1, 1, 2, 1]
                                      + [0, 0, 0, -1.5, 0, 0, 0]))
        argv = ["path", "franka-panda", "--poses", "poses.npy", "--max-step", "0.5", option, filename]
    monkeypatch.setattr(files, "os", _FullDisk())
    assert _run(argv) == 2
    line = _one_line(capsys)
    assert f"no space left on the device writing {filename!r}" in line, line
    assert sorted(path.name for path in tmp_path.iterdir()) == (["poses.npy"] if option != "--out" else [])
