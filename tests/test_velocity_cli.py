"""``redkin track`` end to end."""

import json

import numpy as np

from redkin.cli.main import main

SCENARIO = ["track", "barrett-wam", "--q0", "30", "20", "50", "70", "40", "100", "0", "--deg",
            "--twist", "0.15", "0", "0", "0", "5.729577951", "0", "--duration", "4", "--dt", "0.01"]


def test_velocity_cli_track_json_crosses_once(capsys, tmp_path):
    png = tmp_path / "run.png"
    assert main(SCENARIO + ["--method", "sc", "--json", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["crossings"] == 1 and png.stat().st_size > 1000
    realised = np.array(out["realised_twist"])
    assert np.allclose(realised[0], [0.15, 0, 0, 0, 0.1, 0], atol=1e-9)
    assert np.allclose(realised[-1], [-0.15, 0, 0, 0, 0.1, 0], atol=1e-9)


def test_velocity_cli_track_dls_text(capsys):
    assert main(SCENARIO + ["--method", "dls", "--damping", "0.05"]) == 0
    assert "sign changes: 0" in capsys.readouterr().out


def test_velocity_cli_bad_input(capsys):
    assert main(["track", "barrett-wam", "--q0", "0", "0", "--twist", "0", "0", "0", "0", "0", "0", "--duration", "1"]) == 2
    assert "7 joints" in capsys.readouterr().err
    assert main(["track", "pa10-7c", "--q0", *["0.3"] * 7, "--twist", "0.1", "0", "0", "0", "0", "0",
                 "--duration", "0.1", "--method", "sc"]) == 2
    assert "singularity index" in capsys.readouterr().err
    assert main(SCENARIO + ["--method", "dls", "--damping", "-1"]) == 2
    assert main(SCENARIO[:-4] + ["--duration", "-1"]) == 2
    assert main(SCENARIO + ["--eps", "0"]) == 2
