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


def test_nan_infinite_time_and_points_off_the_bar_are_nan():
    # Issue 22 item 2: u(0.5, nan) and u(0.5, inf) were 0.25, lam(nan) and
    # u_t(0.5, nan) 0.0 (the phase cast to an integer), u(5, 0.5) = -2
    # (extrapolated). As bar-neumann-gravity: NaN.
    for name in ("bar-dirichlet", "bar-mirrored", "bar-neumann-gravity"):
        s = exact.solution(name)
        for t in (np.nan, np.inf, -np.inf):
            for f in (s.u, s.u_x, s.u_t):
                assert np.isnan(f(0.5, t)), (name, f.__name__, t)
            assert np.isnan(s.lam(t)) and np.isnan(s.energy(t)), (name, t)
        for x in (-0.5, 5.0, np.nan, np.inf):
            assert np.isnan(s.u(x, 0.5)) and np.isnan(s.u_x(x, 0.5)) and np.isnan(s.u_t(x, 0.5)), (name, x)
        # Arrays: only the bad entries are NaN. u(x, 0) = (1 - x)/2 for the
        # Dirichlet-type bars; the falling bar is at rest at height 1/2.
        x = np.array([0.25, 7.0, 0.75])
        got = s.u(x, np.array([0.0, 0.0, np.nan]))
        want0 = 0.5 if name == "bar-neumann-gravity" else 0.375
        assert got[0] == want0 and np.isnan(got[1]) and np.isnan(got[2]), (name, got)
        e = s.energy(np.array([0.0, np.nan]))
        assert np.isnan(e[1]) and e[0] == {"bar-dirichlet": 0.125, "bar-mirrored": 0.25, "bar-neumann-gravity": 1 / 18}[name]
    # The falling bar's horizon: NaN beyond t_max (as before).
    s = exact.solution("bar-neumann-gravity", t_max=4.0)
    assert np.isnan(s.u(0.5, 100.0)) and np.isnan(s.energy(100.0))
