"""Arguments from Python (issue 22, items 7-9): numpy scalars and 0-d
arrays wherever their value fits, missing files as FileNotFoundError,
messages that speak Python and name the argument."""

import os
import pathlib

import numpy as np
import pytest

import signorini
from signorini import exact, fem

BAR = {"bar": {"benchmark": "bar-dirichlet", "elements": 20, "ratio": 10.0, "t_end": 0.1}}


def bar(**over):
    d = {k: dict(v) for k, v in BAR.items()}
    for k, v in over.items():
        sec, key = k.split("__")
        d.setdefault(sec, {})[key] = v
    return d


# --- item 7: numpy scalars --------------------------------------------------


def test_numpy_integers_and_zero_d_arrays_where_an_integer_is_expected():
    # h = length / elements: 1/10.
    for m in (np.int64(10), np.int32(10), np.uint16(10), np.array(10), np.float64(10.0), 10.0):
        a = fem.bar(m)
        assert a.n == 10 and a.h == 0.1, repr(m)
    for m in np.arange(2, 5):
        assert fem.bar(m).n == int(m) and fem.beam(m).n == 2 * int(m)
    assert fem.bar(4, degree=np.int8(2)).half_bandwidth == 2
    # A scene dict: 20 elements, dt = 1/200, t_end 0.1: 20 steps.
    for v in (np.int64(20), np.array(20), np.uint8(20)):
        r = signorini.run(bar(bar__elements=v), fields_every=np.int64(4))
        assert r.steps == 20 and r.fields.shape == (6, 20), repr(v)
        assert r.dt == 0.005
    r = signorini.run(bar(output__every=np.int64(2), bar__ratio=np.float32(10.0), bar__t_end=np.array(0.1)))
    assert r.steps == 20


def test_non_integral_values_and_bools_are_refused_naming_the_field():
    for bad in (np.float64(10.5), 10.5, np.True_, True, np.array([10]), np.array(10.5), np.nan):
        with pytest.raises(signorini.SceneError, match="^elements: "):
            fem.bar(bad)
    with pytest.raises(signorini.SceneError, match="^fields_every: "):
        signorini.run(BAR, fields_every=np.float64(2.5))
    with pytest.raises(signorini.SceneError, match="^fields_every: "):
        signorini.run(BAR, fields_every=np.True_)
    # A numpy bool is a bool, not an integer, in a scene too.
    with pytest.raises(signorini.SceneError, match="bar.elements"):
        signorini.run(bar(bar__elements=np.True_))


def test_numpy_bools_where_a_bool_is_expected():
    # A beam computes no energy unless asked (as the CLI).
    beam = {"beam": {"scene": "fig2", "t_end": 0.002}}
    a = signorini.run(beam, energy=np.True_)
    b = signorini.run(beam, energy=np.False_)
    assert a.energy.size >= a.t.size - 1 > 0 and b.energy.size == 0


def test_numpy_floats_in_the_exact_solutions():
    # u(x, 0) = u0 = 1/2, energy g u0 L with the float32's value.
    for g in (np.float32(0.11), np.array(0.11), np.float64(0.11)):
        s = exact.solution("bar-neumann-gravity", g=g, u0=np.float32(0.5), length=np.int64(1), t_max=np.array(4))
        assert s.u(0.3, 0.0) == 0.5
        assert s.energy(0.0) == pytest.approx(float(g) * 0.5, rel=1e-15), repr(g)
    for bad in (np.True_, "0.1", np.array([0.1, 0.2]), None):
        with pytest.raises(signorini.SceneError, match="^g: "):
            exact.solution("bar-neumann-gravity", g=bad)


def test_numpy_values_in_the_studies_and_sweeps():
    r = signorini.studies.convergence(schemes=["newmark-cn"], masses=["std"], levels=[np.int64(10), np.float64(20.0), np.array(40)], ratio=np.float32(10), t_end=np.array(0.5))
    assert r.levels == [10, 20, 40] and list(r["m"]) == [10, 20, 40]
    with pytest.raises(signorini.SceneError, match=r"^levels\[0\]: "):
        signorini.studies.convergence(levels=[np.float64(10.5)])
    with pytest.raises(signorini.SceneError, match=r"^levels\[0\]: "):
        signorini.studies.convergence(levels=[np.True_])
    with pytest.raises(signorini.SceneError, match="^force: "):
        signorini.studies.beam(force=np.int64(1))
    osc = {"oscillator": {"mass": 1.0, "stiffness": 1.0, "damping_ratio": np.float32(0.05), "stop": 0.2, "restitution": 0.8, "dt": 1e-2, "t_end": 10.0}, "forcing": {"amplitude": 1.0, "omega": np.float64(2.0)}}
    s = signorini.sweep(osc, "forcing.omega", np.float32(1.5), np.array(2.0), np.int64(3), transient=np.int64(2), record=np.float32(2), impacts=np.False_)
    assert s.summary["param"].tolist() == [1.5, 1.75, 2.0] and s.impacts is None


# --- item 8: missing files --------------------------------------------------


def test_a_missing_file_is_file_not_found(tmp_path):
    missing = pathlib.Path("/nonexistent/x.toml")
    for call in (lambda s: signorini.run(s), lambda s: signorini.check(s), lambda s: signorini.sweep(s, "forcing.omega", 1.0, 2.0, 2)):
        for s in (missing, str(missing), "/nonexistent.toml", "x-missing.toml", tmp_path / "nothing.toml"):
            with pytest.raises(FileNotFoundError) as e:
                call(s)
            assert e.value.filename == os.fspath(s) and "scene" in str(e.value), s
        with pytest.raises(FileNotFoundError):
            call(tmp_path)  # a folder is not a scene file


class Where(os.PathLike):
    def __init__(self, p):
        self.p = p

    def __fspath__(self):
        return self.p


def test_any_path_like_is_a_path(tmp_path, exe):
    import subprocess

    src = pathlib.Path(__file__).resolve().parents[2] / "data/scenes/bar-dirichlet.toml"
    r = signorini.run(Where(str(src)))
    b = signorini.run(Where(os.fsencode(str(src))))
    out = tmp_path / "cli"
    subprocess.run([str(exe), "run", str(src), "--out", str(out)], check=True, capture_output=True)
    import csv

    with open(out / "series.csv") as f:
        want = [float(row["u_contact"]) for row in csv.DictReader(f)]
    np.testing.assert_allclose(r.tip, want, rtol=1e-12, atol=1e-14)
    assert np.array_equal(r.tip, b.tip)


# --- item 9: messages in Python's words ---------------------------------------


@pytest.mark.parametrize(
    "scene, want",
    [
        (bar(bar__elements=80.0), r"^bar\.elements: 80\.0 \(a float\) is not allowed: an integer >= 2$"),
        (bar(bar__elements=[80]), r"^bar\.elements: a list is not allowed: an integer >= 2$"),
        (bar(bar__elements=-80), r"^bar\.elements: -80 \(an int\) is not allowed: an integer >= 2$"),
        (bar(bar__benchmark=3), r"^bar\.benchmark: 3 \(an int\) is not allowed: a str$"),
        (bar(bar__ratio=True), r"^bar\.ratio: True \(a bool\) is not allowed: finite and > 0$"),
        ({"bar": 3}, r"^bar: 3 \(an int\) is not allowed: a dict$"),
        ({"stop": {"x": 1.0}}, r"^stop: a dict is not allowed: a list$"),
        (bar(bar__nope=1), r"^bar\.nope: not a key of bar \(allowed: benchmark, "),
        ({"a": 1}, r"^a: not a key of the scene \(allowed: bar, beam, "),
        ({"oscillator": {"dt": 1.0}}, r"^oscillator\.mass: missing: a required key$"),
        ({"bar": None}, r"^bar: None \(a NoneType\) is not allowed: "),
    ],
)
def test_scene_messages_speak_python(scene, want):
    with pytest.raises(signorini.SceneError, match=want) as e:
        signorini.check(scene)
    msg = str(e.value)
    for rust in ("usize", "f64", "sequence", "map", "scene file", "struct ", "`"):
        assert rust not in msg, msg


@pytest.mark.parametrize("bad", [None, 42, 1.5, [1], object()])
def test_a_scene_of_the_wrong_type_names_the_scene_argument(bad):
    for call in (signorini.run, signorini.check):
        with pytest.raises(signorini.SceneError, match=r"^scene: .* is not allowed: a dict, a path \(str or os.PathLike\) or TOML text \(str\)$"):
            call(bad)


def test_the_partial_status_does_not_speak_of_files():
    bad = {"bar": {"elements": 10, "dt": 0.01, "initial_displacement": 0.0, "initial_velocity": 1e300, "body_force": 1e300}}
    with pytest.raises(signorini.BlowUp) as e:
        signorini.run(bad)
    for text in (str(e.value), e.value.partial.status):
        assert "blew up" in text and "written" not in text and "partial" in text, text


def test_argument_messages_speak_python():
    with pytest.raises(signorini.SceneError) as e:
        fem.bar(10.5)
    assert str(e.value) == "elements: 10.5 (a float) is not a whole number: an integer in [2, 67108864]"
    with pytest.raises(signorini.SceneError) as e:
        signorini.studies.stress(elements=True)
    assert str(e.value) == "elements: True (a bool) is not allowed: an integer >= 2"
