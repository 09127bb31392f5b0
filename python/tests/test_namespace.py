"""The package's surface (issue 22, item 10): a clean namespace, real types
in signatures, floats from scalar calls, integer counts, a structured
check(), fem.bar(far_end=)."""

import csv
import inspect
import math
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest

import signorini
from signorini import exact, fem, studies
from conftest import ROOT

# signorini.sweep is the function; its module is signorini.sweep in sys.modules.
MODULES = [signorini, exact, fem, studies, sys.modules["signorini.sweep"]]


@pytest.mark.parametrize("mod", MODULES, ids=lambda m: m.__name__)
def test_the_namespace_holds_no_helper_imports(mod):
    public = {k for k in vars(mod) if not k.startswith("_")}
    assert not public & {"np", "os", "Optional", "Union", "annotations", "pathlib", "tempfile", "numbers", "math", "warnings"}, public
    for name in mod.__all__:
        assert hasattr(mod, name), name


@pytest.mark.parametrize("mod", MODULES, ids=lambda m: m.__name__)
def test_signatures_show_types_not_strings(mod):
    for name in mod.__all__:
        f = getattr(mod, name)
        if not inspect.isfunction(f):
            continue
        sig = inspect.signature(f)
        for p in list(sig.parameters.values()) + [sig]:
            ann = p.annotation if isinstance(p, inspect.Parameter) else p.return_annotation
            assert not isinstance(ann, str), f"{mod.__name__}.{name}: {ann!r}"
    assert inspect.signature(signorini.run).return_annotation is signorini.RunResult


def test_scalar_calls_return_floats():
    s = exact.solution("bar-dirichlet")
    # u(x, 0) = (1 - x)/2, u_x = -1/2, u_t = 0, λ(1.5) = -1/2, E = 1/8.
    for got, want in ((s.u(0.5, 0.0), 0.25), (s.u_x(0.5, 0.0), -0.5), (s.u_t(0.5, 0.0), 0.0), (s.lam(1.5), -0.5), (s.energy(0.0), 0.125)):
        assert type(got) is float and got == want
    assert isinstance(s.u(np.array([0.5]), 0.0), np.ndarray) and s.u(np.array([0.5]), 0.0).shape == (1,)
    assert isinstance(s.u(np.array(0.5), 0.0), float)


def test_sweep_counts_are_integers(tmp_path):
    r = signorini.sweep(ROOT / "data/scenes/oscillator.toml", "forcing.omega", 1.6, 2.2, 4, transient=20, record=5, out=tmp_path)
    with open(tmp_path / "summary.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    for k in ("run", "impacts", "period", "poincare_points", "steps"):
        assert r.summary[k].dtype == np.int64, k
        assert r.summary[k].tolist() == [int(row[k]) for row in rows], k
    assert r.summary["param"].dtype == np.float64
    assert r.impacts["stop"].dtype == np.int64 and r.sweep["run"].dtype == np.int64


def test_check_is_the_text_with_its_numbers(exe):
    scene = ROOT / "data/scenes/bar-dirichlet.toml"
    c = signorini.check(scene)
    assert isinstance(c, str) and isinstance(c, signorini.CheckResult) and str(c) == c.text
    assert c.startswith("valid bar scene") and "stability: unconditionally stable" in c
    # 80 elements, ratio 10: dt = 1/800, T = 3.
    assert c.steps == 2400 and c.stability_limit is None
    cli = subprocess.run([str(exe), "check", str(scene)], check=True, capture_output=True, text=True).stdout
    mb = float(re.search(r"memory estimate: ([0-9.]+) MB", cli).group(1))
    assert round(c.memory_bytes / 1e6, 1) == mb and c.output_bytes > 0
    # The lumped central difference: dt < 2/sqrt(κ_h), κ_h = 4 m² sin²((2m-1)π/(4m)).
    m = 12
    c = signorini.check({"bar": {"benchmark": "bar-dirichlet", "elements": m, "mass": "lumped", "scheme": "cd-taylor", "dt": 0.05, "t_end": 1.0}})
    kappa = 4 * m * m * math.sin((2 * m - 1) * math.pi / (4 * m)) ** 2
    assert c.steps == 20 and c.stability_limit == pytest.approx(2 / math.sqrt(kappa), rel=1e-9)
    printed = float(re.search(r"exact limit dt < ([0-9.e+-]+)", c).group(1))
    assert printed == pytest.approx(c.stability_limit, rel=1e-6)


def test_fem_bar_far_end_as_the_scene_key():
    # A free far end adds node m: m + 1 unknowns; clamped: m.
    assert fem.bar(10, far_end="free").n == 11 and fem.bar(10, far_end="clamped").n == 10 and fem.bar(10).n == 10
    with pytest.warns(DeprecationWarning, match="far_end"):
        old = fem.bar(10, right_end="free")
    assert old.n == 11 and np.array_equal(old.mass_band, fem.bar(10, far_end="free").mass_band)
    with pytest.raises(signorini.SceneError, match="^far_end: "):
        fem.bar(10, far_end="hinged")
    with pytest.raises(signorini.SceneError, match="^right_end: "):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fem.bar(10, right_end="free", far_end="free")
