"""signorini.run: the same numbers as the CLI, from a path, TOML text or a
dict; typed errors; Ctrl-C keeps the partial result."""

import _thread
import csv
import pathlib
import subprocess
import threading

import numpy as np
import pytest

import signorini

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "data/scenes/bar-dirichlet.toml"


def test_path_text_and_dict_give_the_cli_numbers(tmp_path):
    a = signorini.run(SCENE)
    b = signorini.run(SCENE.read_text())
    c = signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "mass": "mod", "scheme": "newmark-cn", "ratio": 10.0, "t_end": 3.0}})
    for r in (b, c):
        assert np.array_equal(a.t, r.t) and np.array_equal(a.tip, r.tip) and np.array_equal(a.lam, r.lam)
    assert a.t.dtype == np.float64 and a.t.shape == (2401,) and a.status == "ok" and a.steps == 2400
    exe = ROOT / "target" / "release" / "signorini"
    if not exe.exists():
        pytest.skip("the signorini binary is not built")
    out = tmp_path / "run"
    subprocess.run([str(exe), "run", str(SCENE), "--out", str(out)], check=True, capture_output=True)
    with open(out / "series.csv") as f:
        rows = list(csv.DictReader(f))
    # The CSV prints 13 significant digits of the same floats.
    assert np.allclose(a.tip, [float(r["u_contact"]) for r in rows], rtol=1e-12, atol=1e-14)


def test_bad_input_names_the_field():
    with pytest.raises(signorini.SceneError, match="bar.elements"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": [80], "ratio": 10.0}})
    with pytest.raises(ValueError, match="bar.dt"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "dt": float("nan")}})
    with pytest.raises(signorini.SceneError, match="bar.scheme"):
        signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": 80, "ratio": 10.0, "scheme": "nope"}})
    with pytest.raises(signorini.SceneError, match="object"):
        signorini.run({"bar": object()})


def test_ctrl_c_keeps_the_partial_result():
    # About a second of stepping; interrupted after 0.3 s.
    long = {"bar": {"benchmark": "bar-dirichlet", "elements": 400, "mass": "mod", "scheme": "newmark-cn", "ratio": 1.0, "t_end": 3000.0}}
    threading.Timer(0.3, _thread.interrupt_main).start()
    with pytest.raises(KeyboardInterrupt) as e:
        signorini.run(long)
    part = e.value.partial
    assert 0 < part.t.size < 1_200_001 and "interrupted" in part.status
