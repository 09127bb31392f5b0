"""signorini.exact against hand values and the Rust core's own output
(the CLI's series.csv exact columns)."""

import csv
import pathlib
import subprocess

import numpy as np
import pytest

import signorini
from signorini import exact

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_dirichlet_hand_values_and_broadcasting():
    s = exact.solution("bar-dirichlet")
    # u(x, 0) = (1 - x)/2 for the Signorini–Dirichlet bar; energy 1/8.
    x = np.linspace(0.0, 1.0, 11)
    assert np.allclose(s.u(x, 0.0), 0.5 * (1.0 - x), rtol=0, atol=1e-15)
    assert s.u(x, 0.0).dtype == np.float64
    grid = s.u(x[:, None], np.array([0.0, 0.5, 1.0])[None, :])
    assert grid.shape == (11, 3)
    assert np.all(s.energy(np.zeros((2, 3))) == 0.125)
    assert s.lam(np.array([[0.1, 0.2]])).shape == (1, 2)


def test_against_the_cli_exact_columns(tmp_path, exe):
    out = tmp_path / "run"
    subprocess.run([str(exe), "run", str(ROOT / "data/scenes/bar-dirichlet.toml"), "--out", str(out)], check=True, capture_output=True)
    with open(out / "series.csv") as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["t"]) for r in rows])
    want = np.array([float(r["u_contact_exact"]) for r in rows])
    s = exact.solution("bar-dirichlet")
    # The CSV prints 13 significant digits.
    assert np.allclose(s.u(0.0, t), want, rtol=1e-12, atol=1e-13)


def test_falling_bar_parameters_and_errors():
    s = exact.solution("bar-neumann-gravity", g=0.11, t_max=20.0)
    # Released from rest at height 1/2: u(x, 0) = 1/2, u_t(x, 0) = 0.
    assert np.allclose(s.u(np.linspace(0, 1, 5), 0.0), 0.5, rtol=0, atol=1e-15)
    assert np.allclose(s.u_t(np.linspace(0, 1, 5), 0.0), 0.0, rtol=0, atol=1e-15)
    assert exact.solution("bar-neumann-gravity-0.11").name == "bar-neumann-gravity-0.11"
    with pytest.raises(signorini.SceneError, match="g"):
        exact.solution("bar-neumann-gravity", g=-1.0)
    with pytest.raises(ValueError, match="name"):
        exact.solution("bar-nope")
    with pytest.raises(signorini.SceneError, match="colour"):
        exact.solution("bar-dirichlet", colour=1.0)
    with pytest.raises(signorini.SceneError, match="g"):
        exact.solution("bar-dirichlet", g=0.1)
    with pytest.raises(signorini.SceneError, match="t_max"):
        exact.solution("bar-neumann-gravity", t_max="long")


def test_a_rust_panic_is_an_exception_not_an_abort():
    with pytest.raises(signorini.InternalError, match="planted"):
        signorini._signorini._panic_for_tests()
    assert issubclass(signorini.SceneError, ValueError)
