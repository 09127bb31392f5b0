"""signorini.run's energy monitor (issue 23 §4): one EnergyGrowthWarning
through warnings, with the factor and the time, when the discrete energy
exceeds energy_warn × its budget; the largest E/budget on the result. The
expected values come from the run's own recorded energies (bar-dirichlet
has no load and no damping: the budget is E(0))."""

import math
import warnings

import numpy as np
import pytest

import signorini


def scene(mass, **output):
    s = {"bar": {"benchmark": "bar-dirichlet", "elements": 100, "mass": mass, "scheme": "newmark-cn", "ratio": 1.0, "t_end": 3.0}}
    if output:
        s["output"] = output
    return s


def ratios(r):
    return r.energy / r.energy[0]


def test_the_warning_class_is_exported():
    assert issubclass(signorini.EnergyGrowthWarning, UserWarning)
    assert "EnergyGrowthWarning" in signorini.__all__


@pytest.mark.parametrize("factor", [None, 3.0])
def test_a_growing_run_warns_once_at_the_first_level_past_the_factor(factor):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = signorini.run(scene("std"), **({} if factor is None else {"energy_warn": factor}))
    f = 2.0 if factor is None else factor
    grown = [w for w in caught if issubclass(w.category, signorini.EnergyGrowthWarning)]
    assert len(grown) == 1, [str(w.message) for w in caught]
    q = ratios(r)
    i = int(np.argmax(q > f))
    assert q[i] > f and (q[:i] <= f).all()
    x = r.energy_exceeded
    assert x["step"] == i and x["t"] == pytest.approx(r.energy_t[i], abs=1e-12)
    assert x["ratio"] == pytest.approx(q[i], rel=1e-12) and x["budget"] == pytest.approx(r.energy[0], rel=1e-12)
    assert r.energy_max_ratio == pytest.approx(q.max(), rel=1e-12)
    msg = str(grown[0].message)
    assert f"exceeds {f:g} × its budget from t = {x['t']:.12g} " in msg, msg
    assert grown[0].filename == __file__, "the warning points at the caller"


def test_a_conservative_run_does_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error", signorini.EnergyGrowthWarning)
        r = signorini.run(scene("mod"))
    assert r.energy_exceeded is None and r.energy_warning is None
    assert r.energy_max_ratio == pytest.approx(ratios(r).max(), rel=1e-12) and r.energy_max_ratio <= 1 + 1e-12


def test_the_scene_sets_the_factor_and_the_argument_overrides_it():
    # Over t <= 3 newmark-cn std reaches E/budget ≈ 4.49.
    with warnings.catch_warnings():
        warnings.simplefilter("error", signorini.EnergyGrowthWarning)
        r = signorini.run(scene("std", energy_warn=5.0))
    assert r.energy_exceeded is None and 4 < r.energy_max_ratio < 5
    with pytest.warns(signorini.EnergyGrowthWarning, match="exceeds 4 ×"):
        signorini.run(scene("std", energy_warn=5.0), energy_warn=4)


def test_the_result_pickles_with_the_monitor():
    import pickle

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", signorini.EnergyGrowthWarning)
        r = signorini.run(scene("std"))
    r2 = pickle.loads(pickle.dumps(r))
    assert r2.energy_max_ratio == r.energy_max_ratio and r2.energy_exceeded == r.energy_exceeded


@pytest.mark.parametrize("bad", [1, 1.0, 0.5, -2.0, math.nan, math.inf, -math.inf, "2", True])
def test_bad_factors_are_refused(bad):
    with pytest.raises(signorini.SceneError, match="energy_warn"):
        signorini.run(scene("mod"), energy_warn=bad)


@pytest.mark.parametrize("bad", [1.0, 0.5, math.nan, math.inf])
def test_bad_scene_factors_name_the_key(bad):
    with pytest.raises(signorini.SceneError, match=r"output\.energy_warn.*finite and > 1"):
        signorini.run(scene("mod", energy_warn=bad))
