"""``redkin workspace``: the map, its slices and its summary; one-line errors with exit code 2."""

import io
import json
import subprocess
import sys

import pytest

pytest.importorskip("dask")
pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")

from redkin.cli import common, map_run  # noqa: E402
from redkin.cli.main import main  # noqa: E402

EXTENT = ["-0.9", "0.9", "-0.9", "0.9", "-0.5", "1.3"]


def _command(out, *extra):
    return ["workspace", "pa10-7c", "--out", str(out), "--extent", *EXTENT, "--resolution", "5", "--orientations", "6",
            *extra]


@pytest.mark.slow
def test_workspace_writes_map_slices_and_json_summary(tmp_path, capsys):
    out = tmp_path / "pa10"
    assert main(_command(out, "--chunk", "3", "--json")) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert summary["positions"] == 125 and summary["orientations"] == 6 and summary["pose_branch_evaluations"] == 6000
    assert (summary["chunks"], summary["chunks_computed"], summary["chunks_resumed"]) == (8, 8, 0)
    assert summary["units"]["seconds"] == "s" and summary["scheduler"] == "local"
    # stderr is not a terminal here: plain progress lines, no bar redrawn with \r
    assert "\r" not in captured.err and captured.err.splitlines()[-1] == "progress: 8/8 chunks (100.0%)"
    with xr.open_zarr(out / "map.zarr", chunks=None) as dataset:
        reach = dataset["reachability"].values
        assert summary["reachable_positions"] == pytest.approx((reach > 0).mean())
        assert summary["reachable_poses"] == pytest.approx(reach.mean())
    for name in ("reachability", "redundancy"):
        assert (out / f"{name}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(_command(out, "--chunk", "3", "--quiet")) == 0  # the same map again: resumed, nothing computed
    captured = capsys.readouterr()
    assert "(0 computed, 8 resumed)" in captured.out and "reachable:" in captured.out and captured.err == ""


def test_progress_is_a_bar_on_a_terminal_and_plain_lines_elsewhere(monkeypatch):
    class Stream(io.StringIO):
        def __init__(self, terminal):
            super().__init__()
            self.terminal = terminal

        def isatty(self):
            return self.terminal

    terminal = Stream(True)
    monkeypatch.setattr(sys, "stderr", terminal)  # the bar draws on sys.stderr
    bar = map_run._ChunkProgress(terminal)
    for done in range(1, 101):
        bar(done, 100)
    bar.close()
    assert terminal.getvalue().count("\r") == 100 and terminal.getvalue().endswith("100.0%\n")

    redirected = Stream(False)
    lines = map_run._ChunkProgress(redirected)
    for done in range(1, 1001):
        lines(done, 1000)
    lines.close()
    text = redirected.getvalue()
    assert "\r" not in text and text.splitlines() == [f"progress: {100 * k}/1000 chunks ({10 * k:.1f}%)"
                                                     for k in range(1, 11)]
    monkeypatch.setattr(common, "_PROGRESS_LINE_EVERY", 0.0)  # a slow run also says it is alive between tenths
    lines = map_run._ChunkProgress(redirected)
    lines(1, 1000)
    assert redirected.getvalue().endswith("progress: 1/1000 chunks (0.1%)\n")


def test_a_store_in_use_is_refused_in_one_line(tmp_path, capsys):
    from redkin.workspace.store import hold_store

    with hold_store(tmp_path / "map.zarr"):
        assert main(_command(tmp_path)) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{str(tmp_path / 'map.zarr')!r} is in use by another run (pid " in err
    assert not (tmp_path / "map.zarr").exists()


@pytest.mark.parametrize("change, message", [
    (["--resolution", "1"], "--resolution must be an integer in 2..1000"),
    (["--orientations", "0"], "--orientations must be an integer in 1..20000"),
    (["--orientations", "50000"], "--orientations must be an integer in 1..20000"),
    (["--chunk", "9"], "--chunk must be an integer in 1..5"),
    (["--extent", "1", "0", "0", "1", "0", "1"], "xmin must be below xmax"),
    (["--extent", "0", "1", "0", "nan", "0", "1"], "extent must be finite"),
])
def test_workspace_bad_sizes_exit_2_with_one_line(tmp_path, capsys, change, message):
    command = _command(tmp_path / "out", *change)
    assert main(command) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_workspace_refuses_a_general_chain_and_unwritable_out(tmp_path, capsys):
    command = _command(tmp_path / "out")
    command[1] = "sawyer.urdf"
    assert main(command) == 2
    err = capsys.readouterr().err
    assert "not S-R-S" in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert main(_command(blocker)) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "not a directory" in err and err.count("\n") == 1


def test_workspace_unreachable_scheduler_exits_2(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(map_run, "_CONNECT_TIMEOUT", "0.5s")
    assert main(_command(tmp_path / "out", "--scheduler", "tcp://127.0.0.1:9")) == 2
    err = capsys.readouterr().err
    assert "cannot connect to --scheduler 'tcp://127.0.0.1:9'" in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("missing", ["xarray", "dask", "zarr"])
def test_workspace_without_the_extra_says_how_to_install(tmp_path, capsys, monkeypatch, missing):
    monkeypatch.setitem(sys.modules, missing, None)  # importing it now raises ImportError
    assert main(_command(tmp_path / "out")) == 2
    err = capsys.readouterr().err
    assert 'pip install "redkin[workspace]"' in err and 'pip install -e ".[workspace]"' in err
    assert err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_plain_commands_do_not_import_dask():
    code = ("import sys; from redkin.cli.main import _build_parser; import redkin.workspace; _build_parser(); "
            "print(sorted(m for m in ('dask', 'distributed', 'zarr', 'xarray') if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "[]"


def test_an_absurd_extent_is_refused_in_one_line_before_any_work(tmp_path, capsys):
    """--extent of 1e308 m (finite, so no NaN check catches it) once computed a whole map and failed in the plot;
    the humanoid map's grid is checked by the same workspace_grid."""
    from redkin.workspace.humanoid import humanoid_grid

    code = main(["workspace", "pa10-7c", "--extent", "-1e308", "1e308", "-1", "1", "-1", "1", "--resolution", "4",
                 "--orientations", "8", "--out", str(tmp_path / "m")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "at most 1e+06 m" in err
    assert not (tmp_path / "m").exists() or not any((tmp_path / "m").iterdir())
    with pytest.raises(ValueError, match="at most 1e\\+06 m"):
        humanoid_grid([-1e308, 1e308, -1, 1, -1, 1], 4)


def test_a_missing_orientations_option_is_named_as_missing(tmp_path, capsys):
    code = main(["workspace", "pa10-7c", "--extent", "-1", "1", "-1", "1", "-1", "1", "--resolution", "4",
                 "--out", str(tmp_path / "m")])
    err = capsys.readouterr().err
    assert code == 2 and "needs --orientations N" in err and "None" not in err
