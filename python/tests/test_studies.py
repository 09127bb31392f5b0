"""The studies from Python: the same files as `cargo xtask <study>` (a
separate front end over the same library), tables holding exactly the
numbers written into the CSVs, rates recomputed here, norms equal to an
independent signorini.run of the same level, and typed bad input."""

import csv
import subprocess
from decimal import Decimal

import numpy as np
import pytest

import signorini
from signorini import studies

WALL = {"wall_s", "wall", "wall_time_s", "time_s", "seconds", "ns_per_step", "run_s", "paper_s", "speedup", "setup_s", "step_s"}


def read(path):
    with open(path, newline="") as f:
        r = list(csv.reader(f))
    return r[0], r[1:]


def half_ulp(cell):
    """Half a unit in the last printed digit of a CSV number ("1.0362",
    "5.832182e-2", "12"): a correctly rounded value is within it."""
    mant, _, exp = cell.lower().partition("e")
    decimals = len(mant.partition(".")[2])
    return Decimal(5).scaleb(int(exp or 0) - decimals - 1)


def same_numbers(table, path):
    """Every cell of the CSV is the table's value as it was formatted
    (a float is within half a unit of the cell's last printed digit: it
    rounds to the cell; integers and text equal), wall-clock columns aside."""
    header, rows = read(path)
    assert list(table) == header, path
    for j, name in enumerate(header):
        col = table[name]
        assert len(col) == len(rows), (path, name)
        if any(w in name for w in WALL):
            continue
        for i, row in enumerate(rows):
            cell, v = row[j], col[i]
            if col.dtype.kind == "f":
                if cell in ("", "NaN", "nan"):
                    assert np.isnan(v), (path, name, i)
                else:
                    assert float(cell) == float(v) or abs(Decimal(cell) - Decimal(float(v))) <= half_ulp(cell), (path, name, i, cell, v)
            elif col.dtype.kind == "i":
                assert int(cell) == int(v), (path, name, i)
            else:
                assert cell == str(v), (path, name, i)


def xtask_files(xtask, tmp_path, args):
    out = tmp_path / "xtask"
    subprocess.run([str(xtask), *args, "--out", str(out)], check=True, capture_output=True)
    return out


def test_convergence_is_the_xtask_study(tmp_path, xtask):
    res = signorini.convergence(schemes=["newmark-cn"], masses=["mod"], levels=[10, 20, 40])
    out = xtask_files(xtask, tmp_path, ["convergence", "--schemes", "newmark-cn", "--masses", "mod", "--levels", "10,20,40"])
    assert set(res.tables) == {"newmark-cn_mod.csv", "rates.csv", "oscillation.csv"}
    for f, t in res.tables.items():
        same_numbers(t, out / f)
    # Level order, float64, the names of the CSV.
    e = res["linf_l2_u"]
    assert e.dtype == np.float64 and e.shape == (3,) and res.levels == [10, 20, 40] and list(res["m"]) == [10, 20, 40]
    # Rates recomputed here: least-squares slope of log(error) against log(dx).
    for norm in studies.NORMS:
        slope = np.polyfit(np.log(res["dx"]), np.log(res[norm]), 1)[0]
        assert res.rate(norm) == pytest.approx(slope, rel=1e-9, abs=1e-12), norm
    # Each level's norms are those of an independent run of that level.
    for k, m in enumerate(res.levels):
        r = signorini.run({"bar": {"benchmark": "bar-dirichlet", "elements": m, "mass": "mod", "scheme": "newmark-cn", "ratio": 10.0, "t_end": 3.0}})
        for norm in studies.NORMS:
            assert res[norm][k] == pytest.approx(r.norms[norm], rel=1e-12, abs=1e-300), (m, norm)


def test_several_schemes_and_masses_are_a_grid():
    res = signorini.convergence(schemes=["newmark-cn", "ps-e1"], masses=["std", "mod"], levels=[10, 20])
    assert res.schemes == ["newmark-cn", "ps-e1"] and res.masses == ["std", "mod"]
    grid = res["l2_l2_u"]
    assert grid.shape == (2, 2, 2)
    one = signorini.convergence(schemes=["ps-e1"], masses=["std"], levels=[10, 20])
    assert np.array_equal(grid[1, 0], one["l2_l2_u"])
    with pytest.raises(ValueError, match="scheme"):
        res.rate("l2_l2_u")
    assert res.rate("l2_l2_u", "ps-e1", "std") == one.rate("l2_l2_u")


def test_bar_mirrored_leaves_out_the_schemes_that_cannot_take_two_stops():
    res = signorini.convergence(benchmark="bar-mirrored", schemes=["newmark-cn", "hybrid"], masses=["mod"], levels=[10, 20])
    assert res.schemes == ["newmark-cn"] and res["linf_l2_u"].shape == (2,)
    assert any("hybrid" in n for n in res.notes)


@pytest.mark.parametrize(
    "name,kwargs,args",
    [
        ("stress", dict(steps=2000, elements=10), ["stress", "--steps", "2000", "--elements", "10"]),
        (
            "work_precision",
            dict(levels=[10, 20], degrees=[2], modes=[2, 16], beam_dts=[1e-4], beam_ref_dt=1e-5, beam_window=0.05, beam_t_end=0.1, beam_stat_dts=[1e-4], beam_stat_ref_dt=5e-5, beam_stat_window=12),
            ["work-precision", "--levels", "10,20", "--degrees", "2", "--modes", "2,16", "--beam-dts", "1e-4", "--beam-ref-dt", "1e-5", "--beam-window", "0.05", "--beam-t-end", "0.1", "--beam-stat-dts", "1e-4", "--beam-stat-ref-dt", "5e-5", "--beam-stat-window", "12"],
        ),
        # The keywords issue 33 added (the flags' fields): repeats, reference, degree, reduce.
        ("work_precision", dict(levels=[10, 20], degrees=[], modes=[], beam_dts=[], beam_stat_dts=[], repeats=1), ["work-precision", "--levels", "10,20", "--degrees", "", "--modes", "", "--beam-dts", "", "--beam-stat-dts", "", "--repeats", "1"]),
        ("convergence", dict(schemes=["newmark-cn"], masses=["mod"], levels=[10, 20], degree=2), ["convergence", "--schemes", "newmark-cn", "--masses", "mod", "--levels", "10,20", "--degree", "2"]),
        ("convergence", dict(schemes=["newmark-cn"], masses=["mod"], levels=[10, 20], reference="event-driven", reduce="modes=4"), ["convergence", "--schemes", "newmark-cn", "--masses", "mod", "--levels", "10,20", "--reference", "event-driven", "--reduce", "modes=4"]),
        ("weighted", dict(t_end=5.0), ["weighted", "--t-end", "5"]),
        ("beam", dict(scenes=["fig2"], penalty_dts=[5e-5]), ["beam", "--scenes", "fig2", "--penalty-dts", "5e-5"]),
        ("beam_obstacles", dict(dts=[1e-4, 5e-5, 2.5e-5], js=[5, 10, 20], t_end=0.05), ["beam-obstacles", "--dts", "1e-4,5e-5,2.5e-5", "--js", "5,10,20", "--t-end", "0.05"]),
        ("courant1", dict(levels=[10, 20]), ["courant1", "--levels", "10,20"]),
        ("long_horizon", dict(levels=[20], t_end=9.0, energy_runs=["newmark-cn:std", "ps-e0:mod"], energy_ratios=[1, 2], energy_m=20, energy_t_end=30.0), ["long-horizon", "--levels", "20", "--t-end", "9", "--energy-runs", "newmark-cn:std,ps-e0:mod", "--energy-ratios", "1,2", "--energy-m", "20", "--energy-t-end", "30"]),
        (
            "lyapunov",
            dict(scenes=["fig2-support"], refine=[], omegas=[2.0], transient=4.0, window=5.0, batches=4),
            ["lyapunov", "--scenes", "fig2-support", "--refine", "none", "--omegas", "2.0", "--transient", "4", "--window", "5", "--batches", "4"],
        ),
        (
            "beam_statistics",
            dict(dts=[5e-5, 2.5e-5], elements=[19], transient=2.0, window=12.0, batches=10),
            ["beam-statistics", "--dts", "5e-5,2.5e-5", "--elements", "19", "--transient", "2", "--window", "12", "--batches", "10"],
        ),
        ("oscillator", dict(omegas=[1.8, 2.0], dts=[2e-3, 1e-3, 5e-4], transient=20.0, record=5.0), ["oscillator", "--omegas", "1.8,2.0", "--dts", "2e-3,1e-3,5e-4", "--transient", "20", "--record", "5"]),
    ],
)
def test_the_other_studies_are_the_xtask_studies(tmp_path, xtask, name, kwargs, args):
    res = getattr(studies, name)(**kwargs)
    out = xtask_files(xtask, tmp_path, args)
    written = {str(p.relative_to(out)) for p in out.rglob("*.csv")}
    assert set(res.tables) == written
    for f, t in res.tables.items():
        same_numbers(t, out / f)
    assert res.report.startswith("#") or res.notes


def test_out_keeps_the_files(tmp_path):
    res = signorini.convergence(schemes=["newmark-cn"], masses=["std"], levels=[10, 20], out=tmp_path / "c")
    assert (tmp_path / "c" / "rates.csv").exists() and (tmp_path / "c" / "plot_linf_l2_u.svg").exists()
    same_numbers(res["newmark-cn_std.csv"], tmp_path / "c" / "newmark-cn_std.csv")


def test_bad_input_names_the_argument():
    for call, field in [
        (lambda: signorini.convergence(levels=[-10]), "levels"),
        (lambda: signorini.convergence(levels=[10, "20"]), r"levels\[1\]"),
        (lambda: signorini.convergence(levels=[]), "levels"),
        (lambda: signorini.convergence(schemes=["nope"]), "schemes"),
        (lambda: signorini.convergence(masses=[3]), r"masses\[0\]"),
        (lambda: signorini.convergence(masses=["heavy"]), "masses"),
        (lambda: signorini.convergence(ratio=float("nan")), "ratio"),
        (lambda: signorini.convergence(ratio=-1.0), "ratio"),
        (lambda: signorini.convergence(t_end="3"), "t_end"),
        (lambda: signorini.convergence(benchmark="bar-nothing"), "benchmark"),
        (lambda: signorini.convergence(norms="l3"), "norms"),
        (lambda: studies.stress(steps=0), "steps"),
        (lambda: studies.stress(steps=2.5), "steps"),
        (lambda: studies.stress(elements=True), "elements"),
        (lambda: studies.beam(scenes=["fig9"]), "scenes"),
        (lambda: studies.beam(force="yes"), "force"),
        (lambda: studies.weighted(t_end=float("inf")), "t_end"),
        (lambda: studies.beam_obstacles(dts=[1e-4, 3e-5]), "dts"),
        (lambda: studies.beam_obstacles(j=0), "j"),
        (lambda: studies.oscillator(omegas=[]), "omegas"),
        (lambda: studies.courant1(levels=[1]), "levels"),
        (lambda: studies.long_horizon(runs=["moreau-jean:mod"]), "runs"),
        (lambda: studies.long_horizon(t_end=1.0), "t_end"),
        (lambda: studies.long_horizon(energy_ratios=[0.0]), "energy_ratios"),
        (lambda: studies.long_horizon(energy_runs=["moreau-jean:mod"]), "energy_runs"),
        (lambda: studies.long_horizon(energy=False, energy_m=50), "energy"),
        (lambda: studies.lyapunov(perturbation=0.0), "perturbation"),
        (lambda: studies.lyapunov(perturbation=1e-3), "perturbation"),
        (lambda: studies.lyapunov(window=0.5), "window"),
        (lambda: studies.beam_statistics(window=9.0), "window"),
        (lambda: studies.beam_statistics(batches=9), "batches"),
        (lambda: studies.oscillator(dts=[-1e-3]), "dts"),
    ]:
        with pytest.raises(signorini.SceneError, match="^" + field):
            call()


def csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_work_precision_frontier_rows_are_independent_runs(tmp_path, exe):
    """The frontier rows of work_precision.csv against runs made here through
    the scene path: a P2 row's norm is signorini.run's with bar.degree = 2; a
    reduced bar row's is `signorini run` with bar.reduce; a beam row's tip
    errors and first-impact error are recomputed in numpy from two
    signorini.run beam scenes (the row's step and the reference step), a
    reduced beam row's from the command's series.csv."""
    res = studies.work_precision(levels=[10, 20], degrees=[2], modes=[2], beam_dts=[1e-4], beam_ref_dt=1e-5, beam_window=0.05, beam_t_end=0.1, beam_stat_dts=[])
    t = res.tables["work_precision.csv"]

    def row(**kw):
        (i,) = np.flatnonzero(np.all([t[k] == v for k, v in kw.items()], axis=0))
        return i

    bar = {"benchmark": "bar-dirichlet", "elements": 20, "mass": "mod", "scheme": "newmark-cn", "ratio": 10.0, "t_end": 3.0}
    i = row(benchmark="bar-dirichlet", scheme="newmark-cn", mass="mod", degree=2, modes=0, m=20)
    assert t["l2_l2_u"][i] == pytest.approx(signorini.run({"bar": {**bar, "degree": 2}}).norms["l2_l2_u"], rel=1e-12)
    assert np.isnan(t["tip_err"][i]) and np.isnan(t["impact_err"][i])

    scene = tmp_path / "reduced.toml"
    scene.write_text('[bar]\nbenchmark = "bar-dirichlet"\nelements = 20\nmass = "mod"\nscheme = "newmark-cn"\nratio = 10.0\nt_end = 3.0\nreduce = { modes = 2 }\n')
    subprocess.run([str(exe), "run", str(scene), "--out", str(tmp_path / "reduced")], check=True, capture_output=True)
    (want,) = csv_rows(tmp_path / "reduced" / "norms.csv")
    i = row(benchmark="bar-dirichlet", scheme="newmark-cn", mass="mod", degree=1, modes=2, m=20)
    assert t["l2_l2_u"][i] == pytest.approx(float(want["l2_l2_u"]), rel=1e-9)
    assert t["steps"][i] == 600

    ref = signorini.run({"beam": {"scene": "fig2", "dt": 1e-5, "t_end": 0.1}})
    run = signorini.run({"beam": {"scene": "fig2", "dt": 1e-4, "t_end": 0.1}})
    gap = np.abs(run.tip - np.interp(run.t, ref.t, ref.tip))
    i = row(benchmark="beam-fig2", mass="consistent", modes=0)
    assert t["tip_err"][i] == pytest.approx(gap[run.t <= 0.05 + 1e-12].max(), rel=1e-9)
    assert t["tip_err_end"][i] == pytest.approx(gap.max(), rel=1e-9)
    first = lambda r: r.t[np.argmax(r.active)]
    assert t["impact_err"][i] == pytest.approx(abs(first(run) - first(ref)), rel=1e-9, abs=1e-12)
    assert np.isnan(t["l2_l2_u"][i]) and t["m"][i] == 19 and t["steps"][i] == 1000

    scene = tmp_path / "beam.toml"
    scene.write_text('[beam]\nscene = "fig2"\ndt = 1e-4\nt_end = 0.1\nreduce = { modes = 2 }\n')
    subprocess.run([str(exe), "run", str(scene), "--out", str(tmp_path / "beam")], check=True, capture_output=True)
    rs = csv_rows(tmp_path / "beam" / "series.csv")
    tt, tip = (np.array([float(r[k]) for r in rs]) for k in ("t_s", "tip_m"))
    gap = np.abs(tip - np.interp(tt, ref.t, ref.tip))
    i = row(benchmark="beam-fig2", mass="massless-tip", modes=2)
    assert t["tip_err"][i] == pytest.approx(gap[tt <= 0.05 + 1e-12].max(), rel=1e-9)
    assert t["tip_err_end"][i] == pytest.approx(gap.max(), rel=1e-9)


def test_convergence_refuses_a_folder_of_another_configuration(tmp_path):
    """Issue 22 §5 from Python: a second study with fewer schemes into the same
    folder is refused (naming clean), clean=True removes the stale files."""
    kw = dict(masses=["std"], levels=[10, 20], out=tmp_path)
    signorini.studies.convergence(schemes=["newmark-cn", "ps-e1"], **kw)
    with pytest.raises(signorini.SceneError, match="clean"):
        signorini.studies.convergence(schemes=["newmark-cn"], **kw)
    assert (tmp_path / "ps-e1_std.csv").exists()
    res = signorini.studies.convergence(schemes=["newmark-cn"], clean=True, **kw)
    assert not (tmp_path / "ps-e1_std.csv").exists() and (tmp_path / "newmark-cn_std.csv").exists()
    assert res.schemes == ["newmark-cn"]


def test_work_precision_impact_power_rows_are_the_commands_impacts(tmp_path, exe):
    """Issue 23 §5: the beam's impact-power rows against `signorini run` of the
    same scene: Σ |impulse| |velocity| over impacts.csv's impacts in the
    window, per second, and its error against the reference step's."""
    res = studies.work_precision(levels=[10, 20], degrees=[], modes=[], beam_dts=[], beam_stat_dts=[1e-4], beam_stat_ref_dt=5e-5, beam_stat_window=12)
    t = res.tables["work_precision.csv"]
    period = 2 * np.pi / 10.0
    power = {}
    for dt in (1e-4, 5e-5):
        t0, t_end = round(10 * period / dt) * dt, round(22 * period / dt) * dt
        scene = tmp_path / f"beam-{dt}.toml"
        scene.write_text(f'[beam]\nscene = "fig2"\ndt = {dt}\nt_end = {t_end!r}\n\n[support]\namplitude = 0.2\nomega = 10.0\n\n[output]\nevery = 1000\nimpacts = true\n')
        out = tmp_path / f"out-{dt}"
        subprocess.run([str(exe), "run", str(scene), "--out", str(out)], check=True, capture_output=True)
        rows = [r for r in csv_rows(out / "impacts.csv") if float(r["t"]) >= t0]
        power[dt] = sum(abs(float(r["impulse"])) * abs(float(r["velocity"])) for r in rows) / (t_end - t0)
    for dt in (1e-4, 5e-5):
        (i,) = np.flatnonzero((t["benchmark"] == "beam-fig2-support") & (t["dt"] == dt))
        assert t["impact_power"][i] == pytest.approx(power[dt], rel=1e-6)
        assert t["impact_power_low"][i] < t["impact_power"][i] < t["impact_power_high"][i]
        assert t["impact_power_rel_err"][i] == pytest.approx(power[dt] / power[5e-5] - 1.0, rel=1e-6, abs=1e-9)


def test_the_convergence_plot_tells_coinciding_schemes_apart(tmp_path):
    """The five second-order schemes with the mod mass have the same errors
    to two or three digits, so their curves lie on one another (issue 31,
    item 11): each must differ from the others by more than its colour —
    its markers (circles, filled or hollow polygons, strokes) and dash
    pattern (one polyline, or one per dash) — or the last one drawn hides
    the rest."""
    import re

    schemes = ["newmark-cn", "newmark-ii", "ps-e0", "ps-e0.5", "ps-e1"]
    res = signorini.convergence(schemes=schemes, masses=["mod"], levels=[10, 20, 40], out=tmp_path / "c")
    # The curves do coincide: every L∞(L²) error within 5 % of newmark-cn's.
    err = res["linf_l2_u"][:, 0, :]
    assert np.all(np.abs(err / err[0] - 1) < 0.05), err
    svg = (tmp_path / "c" / "plot_linf_l2_u.svg").read_text()
    colours = set(re.findall(r'<circle [^>]*fill="(#[0-9A-F]{6})"', svg)) | set(re.findall(r'<polyline [^>]*stroke="(#[0-9A-F]{6})"', svg))
    colours -= {"#000000", "#FFFFFF"}
    looks = {}
    for c in colours:
        looks[c] = (
            len(re.findall(rf'<polyline [^>]*stroke="{c}"', svg)),
            len(re.findall(rf'<circle [^>]*fill="{c}"', svg)),
            len(re.findall(rf'<polygon [^>]*fill="{c}"', svg)),
        )
    assert len(looks) == len(schemes), looks
    assert len(set(looks.values())) == len(schemes), f"two schemes drawn alike but for their colour: {looks}"
