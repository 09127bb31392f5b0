"""signorini.continuation: the oscillator's branch through grazing against
the closed-form grazing frequency (written here), the result's columns,
and bad input."""

import math

import pytest

import signorini

SCENE = """
[oscillator]
mass = 1.0
stiffness = 1.0
damping_ratio = 0.05
stop = 0.2
restitution = 0.8
dt = 1e-2
t_end = 10.0
scheme = "event-driven"
[forcing]
amplitude = 1.0
omega = 2.2
"""


def grazing_frequency(m, k, zeta, force, gap):
    # The linear steady state's amplitude reaches the stop: (1 - u)^2 + 4 zeta^2 u = q^2, u = (Omega/omega)^2.
    q = abs(force) / (k * gap)
    u = (1 - 2 * zeta**2) + math.sqrt(q**2 - 4 * zeta**2 * (1 - zeta**2))
    return math.sqrt(k / m) * math.sqrt(u)


def test_the_branch_grazes_at_the_closed_form_frequency(tmp_path):
    r = signorini.continuation(SCENE, "forcing.omega", 2.2, 3.0, out=tmp_path)
    kinds = r.bifurcations["kind"]
    assert "grazing" in kinds
    g = r.bifurcations["param"][kinds.index("grazing")]
    want = grazing_frequency(1.0, 1.0, 0.05, 1.0, 0.2)
    assert abs(g - want) <= 1e-8 * want
    b = r.branch
    assert b["period"].dtype.kind == "i" and b["impacts_per_period"].dtype.kind == "i"
    # One impact a period below the grazing, none above it.
    assert all(n == 1 for p, n in zip(b["param"], b["impacts_per_period"]) if p < want - 1e-6)
    assert all(n == 0 for p, n in zip(b["param"], b["impacts_per_period"]) if p > want + 1e-6)
    assert {"q0", "v0"} <= set(b)
    for f in ("branch.csv", "bifurcations.csv", "branch.svg"):
        assert (tmp_path / f).exists()
    assert r.svg.startswith("<svg")


@pytest.mark.parametrize(
    "change, words",
    [
        (dict(param="oscillator.scheme"), "not a number"),
        (dict(param="oscillator.nothing"), "not in the scene"),
        (dict(period=0), "period"),
        (dict(start=1.0, stop=1.0), "start/stop"),
    ],
)
def test_bad_input_is_a_scene_error_naming_it(change, words):
    kw = dict(param="forcing.omega", start=2.2, stop=3.0)
    kw.update(change)
    with pytest.raises(signorini.SceneError, match=words):
        signorini.continuation(SCENE, kw.pop("param"), kw.pop("start"), kw.pop("stop"), **kw)


def test_a_scheme_other_than_the_exact_one_is_refused():
    with pytest.raises(signorini.SceneError, match="event-driven"):
        signorini.continuation(SCENE.replace('scheme = "event-driven"', 'scheme = "ps(0.8, 0.25)"'), "forcing.omega", 2.2, 3.0)


BAR = """
[bar]
length = 1.0
wave_speed = 1.0
far_end = "clamped"
gap = 0.0
elements = 80
mass = "mod3"
scheme = "event-driven"
dt = 0.01
t_end = 10.0
"""


def test_modes_of_the_bar_with_gap_zero_have_the_period_3l_over_c():
    # At g = 0 the continuous bar's first family has T = 3L/c at every
    # energy (the problem scales with the energy); mod3 at m = 80 within
    # 1e-3 of it (theory §11.7).
    r = signorini.modes(BAR, 0.1, 10.0, points=4)
    b = r.backbone
    assert len(b["energy"]) == 4
    assert all(abs(t - 3.0) < 1e-3 for t in b["period"])
    assert all(abs(t - 3.0) < 1e-12 for t in b["exact_period"])
    assert b["impacts_per_period"].dtype.kind == "i"


def test_modes_bad_input_names_it():
    with pytest.raises(signorini.SceneError, match="start"):
        signorini.modes(BAR, -1.0, 10.0)


TWO_STOPS = SCENE.replace("stop = 0.2", "stops = [-0.5, 0.8]").replace("omega = 2.2", "omega = 3.0")


def test_the_oscillator_between_two_stops_grazes_the_nearer_one():
    """stops = [-0.5, 0.8]: the free orbit continued from 3 down grazes the
    lower stop, where its amplitude reaches 0.5 (closed form); with the upper
    stop alone (0.8) nothing happens down to 1.5. A run between the stops
    (the free elastic oscillator from x' = 1) meets -0.5 at the closed form's
    time and speed, 2 asin 0.8 + pi/6 and -sqrt(3)/2."""
    r = signorini.continuation(TWO_STOPS, "forcing.omega", 3.0, 1.5)
    kinds = list(r.bifurcations["kind"])
    assert "grazing" in kinds, kinds
    g = r.bifurcations["param"][kinds.index("grazing")]
    want = grazing_frequency(1.0, 1.0, 0.05, 1.0, 0.5)
    assert abs(g - want) <= 1e-9 * want
    one = signorini.continuation(TWO_STOPS.replace("stops = [-0.5, 0.8]", "stop = 0.8"), "forcing.omega", 3.0, 1.5)
    assert len(one.bifurcations["kind"]) == 0
    free = {"oscillator": {"mass": 1.0, "stiffness": 1.0, "stops": [-0.5, 0.8], "restitution": 1.0, "initial_velocity": 1.0,
                           "dt": 1e-2, "t_end": 4.0, "scheme": "event-driven"}}
    run = signorini.run(free)
    assert list(run.contact_lo) == [-0.5] and list(run.contact_hi) == [0.8]
    t1 = math.asin(0.8)
    assert abs(run.events["t"][1] - (2 * t1 + math.pi / 6)) <= 1e-12
    assert abs(run.events["velocity_before"][1] + math.sqrt(3) / 2) <= 1e-12
    with pytest.raises(signorini.SceneError, match="oscillator.stops"):
        signorini.run({"oscillator": {**free["oscillator"], "stop": 0.8}})


def test_param_scale_gives_runs_to_two_ends_the_same_steps():
    # The steps are fractions of the range by default: the runs to 3.0 and
    # to 2.6 step differently over their common range. With one
    # param_scale they take the same points there (each run's last point
    # is its own end).
    def points(stop, **kw):
        b = signorini.continuation(SCENE, "forcing.omega", 2.2, stop, **kw).branch
        return list(zip(b["param"], b["q0"], b["v0"]))

    far, near = points(3.0), points(2.6)
    assert far[: len(near) - 1] != near[:-1]
    far, near = points(3.0, param_scale=1.0), points(2.6, param_scale=1.0)
    assert len(near) > 3 and far[: len(near) - 1] == near[:-1]
    # The range's length (2.6 - 2.2 in floating point) as the scale is the default.
    assert points(2.6, param_scale=2.6 - 2.2) == points(2.6)


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf"), "1"])
def test_a_param_scale_not_finite_and_positive_is_refused_by_name(bad):
    with pytest.raises(signorini.SceneError, match="param_scale"):
        signorini.continuation(SCENE, "forcing.omega", 2.2, 3.0, param_scale=bad)
