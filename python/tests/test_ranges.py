"""Every numeric keyword's error names it and gives the range the Rust side
accepts (issue 31, item 8): a value of the wrong type is refused with the
range the Rust check states (found by handing it an out-of-range stand-in,
`signorini._check.allowed` and `python/src/studies.rs`), never with a
generic "an int >= 0", and that range is then checked against what the
Rust side accepts at its boundaries."""

import inspect
import math
import re

import numpy as np
import pytest

import signorini
from signorini import _signorini, exact, fem, studies
from signorini.sweep import _probe as sweep_probe

SceneError = signorini.SceneError

BAR = {"bar": {"benchmark": "bar-dirichlet", "elements": 20, "ratio": 10.0, "t_end": 0.1}}
OSC = {"oscillator": {"mass": 1.0, "stiffness": 1.0, "damping_ratio": 0.05, "stop": 0.2, "restitution": 0.8, "dt": 1e-2, "t_end": 1.0}, "forcing": {"amplitude": 1.0, "omega": 1.8}}


def bar(**over):
    return {"bar": {**BAR["bar"], **over}}


# --- the three cases ------------------------------------------------


def test_a_str_for_the_elements_of_a_scene_states_the_scenes_minimum():
    with pytest.raises(SceneError) as e:
        signorini.run(bar(elements="80"))
    assert str(e.value) == "bar.elements: '80' (a str) is not allowed: an integer >= 2"
    # The minimum the scene accepts is 2 (check validates and builds, runs nothing).
    with pytest.raises(SceneError, match=r"^bar\.elements: 1 is not allowed: an integer >= 2$"):
        signorini.check(bar(elements=1))
    # 2 elements: dx = 1/2, dt = dx/10 = 0.05, T = 0.1: 2 steps.
    assert signorini.check(bar(elements=2)).steps == 2
    # A real key too: the scene's own words for bar.ratio.
    with pytest.raises(SceneError, match=r"^bar\.ratio: '10' \(a str\) is not allowed: finite and > 0$"):
        signorini.check(bar(ratio="10"))


def test_a_float_for_batches_states_the_studys_range():
    with pytest.raises(SceneError) as e:
        studies.beam_statistics(batches=2.5)
    assert str(e.value) == "batches: 2.5 (a float) is not allowed: an integer in [10, 1000] (fewer batches give no usable interval)"
    for ok in (10, 1000):
        _signorini.study_check("beam_statistics", {"batches": ok})
    for bad in (9, 1001):
        with pytest.raises(SceneError, match=r"^batches (9|1001): allowed an integer in \[10, 1000\]"):
            _signorini.study_check("beam_statistics", {"batches": bad})


def test_the_arguments_of_an_exact_solution_are_named():
    s = exact.solution("bar-dirichlet")
    for call, name in [
        (lambda: s.u("a", 1.0), "x"),
        (lambda: s.u(0.5, "a"), "t"),
        (lambda: s.u_x(None, 1.0), "x"),
        (lambda: s.u_t(0.5, [[1.0], [1.0, 2.0]]), "t"),
        (lambda: s.lam("a"), "t"),
        (lambda: s.energy(True), "t"),
        (lambda: s.u(np.array(["0.5"]), 1.0), "x"),
    ]:
        with pytest.raises(SceneError, match=f"^{name}: .* is not allowed: a number or an array of numbers"):
            call()
    with pytest.raises(SceneError, match=r"^x and t: shapes \(2,\) and \(3,\) do not broadcast"):
        s.u([0.1, 0.2], [1.0, 2.0, 3.0])
    # Numbers still broadcast (bar-dirichlet: u(x, 0) = 1/2 - x/2 ... its energy is 1/8).
    assert s.energy(np.array([0.5, 1.0])) == pytest.approx([0.125, 0.125])
    # The parameters: named, with the exact crate's range.
    with pytest.raises(SceneError, match=r"^g: 'a' \(a str\) is not allowed: finite and > 0$"):
        exact.solution("bar-neumann-gravity", g="a")
    with pytest.raises(SceneError, match=r"^g: -1(\.0)? is not allowed: finite and > 0$"):
        exact.solution("bar-neumann-gravity", g=-1.0)


# --- the sweep over every public function's numeric keywords ----------------

#: Every numeric keyword of the studies: "int", "float", or a list of them.
STUDY_NUMBERS = {
    "convergence": {"levels": "ints", "ratio": "float", "t_end": "float", "degree": "int"},
    "weighted": {"t_end": "float"},
    "beam": {"penalty_dts": "floats"},
    "beam_obstacles": {"gap": "float", "beta": "float", "t_end": "float", "dts": "floats", "j": "int", "js": "ints", "j_dt": "float"},
    "oscillator": {"omegas": "floats", "dts": "floats", "transient": "float", "record": "float"},
    "courant1": {"levels": "ints", "t_end": "float"},
    "long_horizon": {"levels": "ints", "ratio": "float", "t_end": "float", "energy_ratios": "floats", "energy_m": "int", "energy_t_end": "float"},
    "lyapunov": {"dts": "floats", "elements": "ints", "omegas": "floats", "perturbation": "float", "transient": "float", "window": "float", "per_period": "int", "batches": "int"},
    "beam_statistics": {"dts": "floats", "elements": "ints", "transient": "float", "window": "float", "batches": "int", "episode_gap": "float"},
    "work_precision": {
        "levels": "ints",
        "degrees": "ints",
        "modes": "ints",
        "beam_dts": "floats",
        "beam_ref_dt": "float",
        "beam_window": "float",
        "beam_t_end": "float",
        "beam_stat_dts": "floats",
        "beam_stat_ref_dt": "float",
        "beam_stat_window": "float",
        "repeats": "int",
    },
    "stress": {"steps": "int", "elements": "int", "seed": "int"},
}
#: The studies' other keywords (names, switches, the folder).
STUDY_OTHERS = {"benchmark", "schemes", "masses", "norms", "out", "clean", "scenes", "force", "benchmarks", "runs", "energy", "energy_runs", "energy_all", "energy_benchmark", "refine", "reduce", "reference"}

#: Ranges that depend on other options or couple two of them (stated in
#: words the boundary check below cannot read as one interval): only the
#: naming and the statement are checked.
COUPLED = {
    ("beam_obstacles", "dts"),  # "at least two", each dividing the first
    ("beam_obstacles", "j_dt"),  # divides t_end and the coarsest dt
    ("beam_obstacles", "j"),  # checked with js: multiples of js[0]
    ("beam_obstacles", "js"),
    ("lyapunov", "window"),  # window · per_period >= 10 · batches
    ("work_precision", "beam_dts"),
    ("work_precision", "beam_ref_dt"),
    ("work_precision", "beam_window"),
    ("work_precision", "beam_stat_ref_dt"),
    ("sweep", "shard"),
}


def test_the_table_covers_every_keyword_of_every_study():
    for name, table in STUDY_NUMBERS.items():
        params = set(inspect.signature(getattr(studies, name)).parameters)
        assert set(table) <= params, (name, set(table) - params)
        assert params <= set(table) | STUDY_OTHERS, (name, params - set(table) - STUDY_OTHERS)
    assert {n for n in studies.__all__ if callable(getattr(studies, n)) and not isinstance(getattr(studies, n), type)} == set(STUDY_NUMBERS)


def test_every_field_of_every_study_is_a_keyword_and_the_table_knows_its_kind():
    """The fields of each study's Config (each a `cargo xtask` flag, `t_end`
    for `--t-end`) are the Python function's parameters, in order, and the
    table above classifies the numeric ones as the Rust side does."""
    for name, table in STUDY_NUMBERS.items():
        fields = _signorini.study_fields(name)
        assert list(inspect.signature(getattr(studies, name)).parameters) == [f[0] for f in fields], name
        for field, kind, doc, _ in fields:
            assert doc, (name, field)
            want = {"number": "int|float", "numbers": "ints|floats"}.get(kind)
            if want is None:
                assert field in STUDY_OTHERS, (name, field, kind)
            else:
                assert table.get(field) in want.split("|"), (name, field, kind)


def _cases():
    """``(function, keyword, kind, call(v), validate(v))``: ``call`` is the
    public function with ``v`` for the keyword, ``validate`` the Rust check
    alone (nothing runs)."""
    out = []
    for name, table in STUDY_NUMBERS.items():
        f = getattr(studies, name)
        for kw, kind in table.items():
            wrap = (lambda v: [v]) if kind.endswith("s") else (lambda v: v)
            out.append((name, kw, kind.rstrip("s"), lambda v, f=f, kw=kw, wrap=wrap: f(**{kw: wrap(v)}), lambda v, name=name, kw=kw, wrap=wrap: _signorini.study_check(name, {kw: wrap(v)})))
    out.append(("run", "fields_every", "int", lambda v: signorini.run(BAR, fields_every=v), lambda v: _signorini.run_scene({}, None, v, None)))
    out.append(("run", "energy_warn", "float", lambda v: signorini.run(BAR, energy_warn=v), lambda v: _signorini.run_scene({}, None, 0, v)))
    for kw, kind in (("elements", "int"), ("length", "float"), ("wave_speed", "float"), ("degree", "int"), ("contacts", "int")):
        args = (lambda v, kw=kw: {kw: [v]}) if kw == "contacts" else (lambda v, kw=kw: {kw: v})
        base = {"elements": 4} if kw != "elements" else {}
        out.append(("fem.bar", kw, kind, lambda v, a=args, b=base: fem.bar(**{**b, **a(v)}), lambda v, a=args, b=base: fem.bar(**{**b, **a(v)})))
    for kw, kind in (("elements", "int"), ("length", "float"), ("k2", "float")):
        base = {"elements": 4} if kw != "elements" else {}
        out.append(("fem.beam", kw, kind, lambda v, kw=kw, b=base: fem.beam(**{**b, kw: v}), lambda v, kw=kw, b=base: fem.beam(**{**b, kw: v})))
    for kw in ("g", "u0", "length", "t_max"):
        out.append(("exact.solution", kw, "float", lambda v, kw=kw: exact.solution("bar-neumann-gravity", **{kw: v}), lambda v, kw=kw: exact.solution("bar-neumann-gravity", **{kw: v})))
    axis2 = dict(param2="forcing.amplitude", start2=0.5, stop2=1.0, count2=2)
    for kw, kind in (("start", "float"), ("stop", "float"), ("count", "int"), ("start2", "float"), ("stop2", "float"), ("count2", "int"), ("transient", "float"), ("record", "float"), ("phase", "float"), ("period_tol", "float"), ("threads", "int")):
        extra = dict(axis2) if kw.endswith("2") else {}
        out.append(("sweep", kw, kind, lambda v, kw=kw, e=extra: signorini.sweep(OSC, "forcing.omega", **{"start": 1.6, "stop": 2.0, "count": 2, **e, kw: v}), lambda v, kw=kw: sweep_probe(**{kw: None})(v)))
    return out


CASES = _cases()

NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?π?"


def _num(s):
    s = s.strip()
    if s.endswith("π"):
        return float(s[:-1] or 1) * math.pi
    return float(s)


def interval(text, kw):
    """``(lo, lo_closed, hi, hi_closed)`` of a range in words, or None."""
    own = re.search(rf"\b{kw} in ([\[(])\s*({NUM})\s*,\s*({NUM})\s*([\])])", text)
    m = own or re.search(rf"([\[(])\s*({NUM})\s*,\s*({NUM})\s*([\])])", text)
    if m:
        return (_num(m.group(2)), m.group(1) == "[", _num(m.group(3)), m.group(4) == "]")
    if m := re.search(rf"({NUM})\s*\.\.=\s*({NUM})", text):
        return (_num(m.group(1)), True, _num(m.group(2)), True)
    if m := re.search(rf"({NUM})\s*<\s*[a-z_]+\s*<\s*({NUM})", text):
        return (_num(m.group(1)), False, _num(m.group(2)), False)
    if m := re.search(r"\b(\d+), (\d+) or (\d+)\b", text):
        return (float(m.group(1)), True, float(m.group(3)), True)
    if m := re.search(r"^(\d+) and (\d+)\b", text):
        return (float(m.group(1)), True, float(m.group(2)), True)
    lo = hi = None
    if m := re.search(rf">=\s*({NUM})", text):
        lo = (_num(m.group(1)), True)
    elif m := re.search(rf">\s*({NUM})", text):
        lo = (_num(m.group(1)), False)
    if m := re.search(rf"<=\s*({NUM})", text):
        hi = (_num(m.group(1)), True)
    elif m := re.search(rf"at most ({NUM})", text):
        hi = (_num(m.group(1)), True)
    if lo is None and hi is None:
        return (-math.inf, False, math.inf, False) if "a finite number" in text else None
    lo, hi = lo or (-math.inf, False), hi or (math.inf, False)
    return (lo[0], lo[1], hi[0], hi[1])


def refused_by(validate, name, rng, v):
    """Whether ``validate(v)`` refuses ``v`` naming ``name`` with the range ``rng``."""
    try:
        validate(v)
    except SceneError as e:
        m = str(e)
        return m.startswith(name) and m[len(name):][:1] in (":", " ", "[") and rng in m
    return False


@pytest.mark.parametrize("function,kw,kind,call,validate", CASES, ids=[f"{c[0]}-{c[1]}" for c in CASES])
def test_a_wrong_type_is_refused_naming_the_keyword_with_the_range_rust_accepts(function, kw, kind, call, validate):
    name = kw + "[0]" if (function in STUDY_NUMBERS and STUDY_NUMBERS[function][kw].endswith("s")) or (function, kw) == ("fem.bar", "contacts") else kw
    with pytest.raises(SceneError) as e:
        call("x")
    msg = str(e.value)
    head = f"{name}: 'x' (a str) is not allowed: "
    assert msg.startswith(head), msg
    rng = msg[len(head):]
    # The range is the Rust side's, not a generic type word.
    # (the fallback words when no Rust check refuses a stand-in: only the
    # seed, any u64, has no range but its type's).
    assert rng not in ("", "an int >= 0", "a number (int or float)") or (function, kw) == ("stress", "seed"), msg
    # A bool is no number either, and gets the same range.
    with pytest.raises(SceneError, match="^" + re.escape(name) + r": True \(a bool\) is not allowed: " + re.escape(rng) + "$"):
        call(True)
    if (function, kw) in COUPLED:
        return
    if (function, kw) == ("stress", "seed"):
        # Any u64: the study takes 0 and the largest.
        validate(0)
        validate((1 << 64) - 1)
        return
    iv = interval(rng, kw)
    assert iv is not None, f"{function} {kw}: cannot read the range {rng!r}"
    lo, lo_closed, hi, hi_closed = iv
    # An out-of-range item of a list is refused naming the list (`dts …:`
    # from the study, `contacts[0]:` from fem.bar).
    check = kw
    if kind == "int":
        lo_in = int(lo) if lo_closed else int(math.floor(lo)) + 1
        assert not refused_by(validate, check, rng, lo_in), f"{function} {kw}={lo_in}: refused, but {rng!r}"
        assert refused_by(validate, check, rng, lo_in - 1), f"{function} {kw}={lo_in - 1}: not refused with {rng!r}"
        if math.isfinite(hi):
            hi_in = int(hi) if hi_closed else int(math.ceil(hi)) - 1
            if not (function.startswith("fem") and hi_in > 100_000):  # building 2^26 elements is too large for a test
                assert not refused_by(validate, check, rng, hi_in), f"{function} {kw}={hi_in}: refused, but {rng!r}"
            assert refused_by(validate, check, rng, hi_in + 1), f"{function} {kw}={hi_in + 1}: not refused with {rng!r}"
    else:
        step = lambda x: max(abs(x), 1.0) * 1e-6
        if math.isfinite(lo):
            inside, outside = (lo, lo - step(lo)) if lo_closed else (lo + step(lo), lo)
            assert not refused_by(validate, check, rng, inside), f"{function} {kw}={inside}: refused, but {rng!r}"
            assert refused_by(validate, check, rng, outside), f"{function} {kw}={outside}: not refused with {rng!r}"
        if math.isfinite(hi):
            inside, outside = (hi, hi + step(hi)) if hi_closed else (hi - step(hi), hi)
            assert not refused_by(validate, check, rng, inside), f"{function} {kw}={inside}: refused, but {rng!r}"
            assert refused_by(validate, check, rng, outside), f"{function} {kw}={outside}: not refused with {rng!r}"
        for v in (math.nan, math.inf):
            assert refused_by(validate, check, rng, v) or not ("finite" in rng or math.isfinite(hi)), f"{function} {kw}={v}: not refused"


def test_the_range_reader():
    assert interval("an integer in [10, 1000] (fewer batches give no usable interval)", "batches") == (10, True, 1000, True)
    assert interval("at least one, each finite and in (0, 1e-3]", "dts") == (0, False, 1e-3, True)
    assert interval("finite, > 0 and <= 1e4", "t_end") == (0, False, 1e4, True)
    assert interval("0 < perturbation < 1e-3 (relative)", "perturbation") == (0, False, 1e-3, False)
    assert interval("a forcing phase in [0, 2π)", "phase") == (0, True, 2 * math.pi, False)
    assert interval("multiples of the first, each in [1, 2000] (and j in [2, 2000])", "j") == (2, True, 2000, True)
    assert interval("1 ..= 1e9", "steps") == (1, True, 1e9, True)
    assert interval("finite and >= 4.5 (the second impact is at t = 4)", "t_end") == (4.5, True, math.inf, False)
    assert interval("1, 2 or 3 (Lagrange P1, P2, P3)", "degree") == (1, True, 3, True)
    assert interval("a finite number", "start") == (-math.inf, False, math.inf, False)
    assert interval("True or False", "x") is None
