"""The studies of ``cargo xtask``, from Python.

Each function runs the same library code as ``cargo xtask <study>`` (the
numbers are identical to the CSV files it writes: the tables hold the very
floats that were formatted into them) and returns a :class:`StudyResult`:
``tables`` maps each CSV file name (relative to the output folder) to a
dict of its columns as numpy arrays (float64, int64, or str), ``report`` is
the Markdown text the command prints, ``wall_s`` its wall time, ``notes``
what it printed on stderr. With ``out=None`` the files go to a temporary
folder that is removed afterwards; give ``out`` to keep the CSVs and plots.

The stepping releases the GIL. A study cannot be interrupted half-way: its
runs go in parallel on every core, and Ctrl-C is seen when it returns.
"""

import os as _os
import tempfile as _tempfile

import numpy as _np

from . import _signorini

__all__ = ["StudyResult", "ConvergenceResult", "convergence", "weighted", "beam", "beam_obstacles", "oscillator", "courant1", "long_horizon", "lyapunov", "beam_statistics", "work_precision", "stress", "LEVEL_COLUMNS", "NORMS"]

#: The columns of a convergence study's per-configuration CSV.
LEVEL_COLUMNS = ("m", "dx", "dt", "steps", "linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy", "wall_s", "setup_s", "step_s")
#: The error norms, in column order.
NORMS = ("linf_l2_u", "l2_l2_u", "linf_v_u", "l2_v_u", "l2_lambda", "linf_energy", "l2_energy")


def _table(cols):
    return {k: (_np.asarray(v, dtype=str) if isinstance(v, list) else v) for k, v in cols.items()}


class StudyResult:
    """What a study wrote and printed; see the module's documentation."""

    def __init__(self, d):
        self.tables = {f: _table(c) for f, c in d["tables"].items()}
        self.report = d["report"]
        self.wall_s = d["wall_s"]
        self.notes = list(d["notes"])
        self.out = d["out"]

    def __getitem__(self, file):
        return self.tables[file]

    def __repr__(self) -> str:
        return f"<signorini.studies.{type(self).__name__}: {len(self.tables)} tables ({', '.join(list(self.tables)[:4])}{', ...' if len(self.tables) > 4 else ''}), {self.wall_s:.2f} s>"


class ConvergenceResult(StudyResult):
    """The error table of a convergence study.

    ``res["linf_l2_u"]`` (any name of :data:`LEVEL_COLUMNS`) is a numpy array
    in level order when one scheme and one mass were asked; with several,
    its shape is ``(len(res.schemes), len(res.masses), len(res.levels))``,
    schemes and masses in the order asked (a scheme that cannot take the
    benchmark — the reduced ones on the two stops of bar-mirrored — is left
    out with a note). ``res.rates`` is ``rates.csv`` (columns ``scheme, mass,
    norm, lsq_rate, last_rate``), ``res.rate(norm, scheme, mass)`` one
    least-squares rate, ``res.oscillation`` is ``oscillation.csv``; any CSV
    by its file name: ``res["newmark-cn_std.csv"]``.
    """

    def __init__(self, d):
        super().__init__(d)
        self.configs = [tuple(c) for c in d["configs"]]
        self.schemes = list(dict.fromkeys(s for s, _, _ in self.configs))
        self.masses = list(dict.fromkeys(m for _, m, _ in self.configs))
        self.ratio = d["ratio"]
        self.t_end = d["t_end"]
        first = self.tables[self.configs[0][2]] if self.configs else {"m": _np.zeros(0, dtype=_np.int64)}
        self.levels = [int(m) for m in first["m"]]
        self._file = {(s, m): f for s, m, f in self.configs}

    def __getitem__(self, key):
        if key in self.tables:
            return self.tables[key]
        if key not in LEVEL_COLUMNS:
            raise KeyError(f"{key!r}: a column of {', '.join(LEVEL_COLUMNS)}, or a file of {', '.join(self.tables)}")
        grid = _np.array([[self.tables[self._file[(s, m)]][key] for m in self.masses] for s in self.schemes])
        return grid[0, 0] if len(self.schemes) == 1 and len(self.masses) == 1 else grid

    @property
    def rates(self):
        return self.tables["rates.csv"]

    @property
    def oscillation(self):
        return self.tables["oscillation.csv"]

    def rate(self, norm, scheme=None, mass=None, kind="lsq"):
        """The rate of ``norm`` for (scheme, mass) — each may be omitted when
        there is one — least squares (``kind='lsq'``) or of the last two levels
        (``'last'``)."""
        scheme = scheme if scheme is not None else _only("scheme", self.schemes)
        mass = mass if mass is not None else _only("mass", self.masses)
        r = self.rates
        sel = (r["scheme"] == scheme) & (r["mass"] == mass) & (r["norm"] == norm)
        if not sel.any():
            raise KeyError(f"no rate of {norm} for ({scheme}, {mass})")
        return float(r[f"{kind}_rate"][sel][0])


def _only(what, values):
    if len(values) != 1:
        raise ValueError(f"{what}: give one of {', '.join(values)}")
    return values[0]


def _run(name, out, kwargs, cls=StudyResult):
    kwargs = {k: v for k, v in kwargs.items() if v is not None}
    if out is not None:
        _os.makedirs(_os.fspath(out), exist_ok=True)
        return cls(_signorini.study(name, kwargs, _os.fspath(out)))
    with _tempfile.TemporaryDirectory(prefix=f"signorini-{name}-") as tmp:
        return cls(_signorini.study(name, kwargs, tmp))


def convergence(benchmark="bar-dirichlet", schemes=None, masses=None, levels=None, ratio=None, t_end=None, norms="exact", out=None, clean=False) -> ConvergenceResult:
    """The convergence study (``cargo xtask convergence``): for each (scheme,
    mass), the benchmark at each level m (m elements; bar-mirrored 2m on its
    [0, 2]) with dt = dx/ratio up to t_end, and every error norm.

    ``benchmark``: bar-dirichlet, bar-neumann-gravity, bar-neumann-gravity-0.11,
    bar-mirrored; ``schemes``: names or parametrised forms (``"newmark-cn"``,
    ``"ps(0.5)"``, ``"newmark(0.3,0.6)"``), default the papers' seven;
    ``masses``: default ``["std", "mod"]``; ``levels``: default 10 … 640;
    ``ratio``, ``t_end``: default the benchmark's (10 and 3 for bar-dirichlet);
    ``norms``: ``"exact"`` (kink-split exact integrals) or ``"getfem"`` (the
    nodal interpolant's errors, relative, as GetFEM's demo). An ``out``
    folder holding CSV or SVG files this study would not write (another
    study's or configuration's) is refused unless ``clean=True`` removes them."""
    kw = dict(benchmark=benchmark, schemes=schemes, masses=masses, levels=levels, ratio=ratio, t_end=t_end, norms=norms, clean=clean)
    return _run("convergence", out, kw, ConvergenceResult)


def weighted(t_end=None, out=None) -> StudyResult:
    """The weighted-mass-redistribution study (``cargo xtask weighted``)."""
    return _run("weighted", out, dict(t_end=t_end))


def beam(scenes=None, force=None, penalty_dts=None, out=None) -> StudyResult:
    """The beam between two stops (``cargo xtask beam``): the paper's scenes
    (default fig2 … fig8), the exact stability limit, self-convergence."""
    return _run("beam", out, dict(scenes=scenes, force=force, penalty_dts=penalty_dts))


def beam_obstacles(gap=None, beta=None, t_end=None, dts=None, j=None, js=None, j_dt=None, out=None) -> StudyResult:
    """The beam between obstacles along its whole length (``cargo xtask
    beam-obstacles``): feasibility, self-convergence in dt (J = ``j``, time
    steps ``dts``) and in J (meshes ``js`` at ``j_dt``), energy balance."""
    return _run("beam_obstacles", out, dict(gap=gap, beta=beta, t_end=t_end, dts=dts, j=j, js=js, j_dt=j_dt))


def oscillator(omegas=None, dts=None, transient=None, record=None, out=None) -> StudyResult:
    """The impact oscillator against its exact period-1 orbits (``cargo xtask
    oscillator``): impact velocity and phase errors and their rates in dt at
    each forcing frequency of ``omegas``; the grazing frequency."""
    return _run("oscillator", out, dict(omegas=omegas, dts=dts, transient=transient, record=record))


def courant1(benchmarks=None, levels=None, t_end=None, out=None) -> StudyResult:
    """Courant number one (``cargo xtask courant1``): the lumped central
    difference at dx/dt = c with Taylor's and Newmark's starts, node by node
    against the exact solutions; where the first nodal error appears."""
    return _run("courant1", out, dict(benchmarks=benchmarks, levels=levels, t_end=t_end))


def long_horizon(runs=None, levels=None, ratio=None, t_end=None, energy=None, energy_runs=None, energy_all=None, energy_ratios=None, energy_m=None, energy_t_end=None, out=None) -> StudyResult:
    """Long horizons (``cargo xtask long-horizon``): the Dirichlet bar over
    ``t_end`` (default 30, ten periods) for ``runs`` (``"scheme:mass"`` pairs;
    default ps-e0 with every mass, moreau-jean with std and lumped): the
    largest L² error in each period, every impact time against the exact one,
    the drift per period. Then (``energy=False`` leaves it out) the energy
    growth table: ``energy_runs`` (``"scheme:mass"`` pairs, or
    ``energy_all=True``: every named scheme with every mass it accepts) at
    each dx/dt of ``energy_ratios`` (default 1, 2, 10) on ``energy_m``
    (default 100) elements to ``energy_t_end`` (default 10⁴): the largest
    E/budget and when it first exceeds 2 (``energy_growth.csv``,
    ``energy_vs_time.csv``, ``energy_growth.svg``). The default table takes
    minutes; ``energy_t_end=`` shortens it."""
    return _run("long_horizon", out, dict(runs=runs, levels=levels, ratio=ratio, t_end=t_end, energy=energy, energy_runs=energy_runs, energy_all=energy_all, energy_ratios=energy_ratios, energy_m=energy_m, energy_t_end=energy_t_end))


def lyapunov(scenes=None, refine=None, dts=None, elements=None, omegas=None, perturbation=None, transient=None, window=None, per_period=None, batches=None, out=None) -> StudyResult:
    """Largest Lyapunov exponents (``cargo xtask lyapunov``) by Benettin's twin
    runs: the twin perturbed by a relative ``perturbation`` (default 1e-10,
    allowed 0 < ε < 1e-3) of the state's energy norm, renormalised
    ``per_period`` times a forcing period (64) over ``window`` forcing periods
    (20) after ``transient`` (10), a 95 % interval from ``batches`` (10) batch
    means. Cases: the beam ``scenes`` (default fig2-support, fig2 … fig8,
    beam-obstacles) at their own dt and J, the ``refine`` scenes (default
    fig2-support) at every ``dts`` × ``elements``, the impact oscillator at
    every Ω of ``omegas`` (default 1.6 … 2.2; ``[]``: none).
    ``res["lyapunov.csv"]``: ``scene, dt, elements, lambda_max, ci_low,
    ci_high, horizon_s`` (the time for a 1e-16 relative round-off to grow to
    1 mm; NaN for λ <= 0); ``res["oscillator.csv"]``: ``omega, lambda_max,
    ci_low, ci_high, lambda_exact, multiplier`` (the exact Floquet exponent of
    the period-1 orbit)."""
    return _run("lyapunov", out, dict(scenes=scenes, refine=refine, dts=dts, elements=elements, omegas=omegas, perturbation=perturbation, transient=transient, window=window, per_period=per_period, batches=batches))


def beam_statistics(scenes=None, dts=None, elements=None, transient=None, window=None, batches=None, episode_gap=None, out=None) -> StudyResult:
    """Statistics that converge (``cargo xtask beam-statistics``): the beam
    ``scenes`` (default ``["fig2-support"]``; also ``"beam-obstacles"``) at
    every ``dts`` (5e-5, 2.5e-5, 1e-5) and ``elements`` (19, 38) over
    ``window`` forcing periods (320; at least 10) after ``transient`` (10),
    each statistic with a 95 % interval from ``batches`` (20; at least 10)
    batch means, against the finest level. ``res["statistics.csv"]``:
    ``scene, dt, elements, statistic, mean, ci_low, ci_high, finest_mean,
    rel_diff, within_ci, kind`` (``kind``: ``"converges"`` or
    ``"step-dependent"``); active runs closer than ``episode_gap`` seconds
    (5e-3) form one contact episode."""
    return _run("beam_statistics", out, dict(scenes=scenes, dts=dts, elements=elements, transient=transient, window=window, batches=batches, episode_gap=episode_gap))


def work_precision(levels=None, degrees=None, modes=None, beam_dts=None, beam_ref_dt=None, beam_window=None, beam_t_end=None, beam_stat_dts=None, beam_stat_ref_dt=None, beam_stat_window=None, out=None) -> StudyResult:
    """Work–precision (``cargo xtask work-precision``): error against wall
    time for every scheme and mass, then the frontier on the same axes:
    Courant-one central difference, P2/P3 (``degrees``), reduced bar and beam
    models (``modes``), and the beam of figure 2 at ``beam_dts`` against a
    full-model reference at ``beam_ref_dt`` (tip error over
    ``[0, beam_window]`` and ``[0, beam_t_end]``, first-impact error).
    The beam with its support motion (fig. 2 with ``[support]``) at
    ``beam_stat_dts`` gives its impact power over ``beam_stat_window``
    forcing periods with a 95 % interval, against ``beam_stat_ref_dt``.
    Empty ``degrees``, ``modes``, ``beam_dts`` or ``beam_stat_dts`` leave
    those rows out."""
    return _run("work_precision", out, dict(levels=levels, degrees=degrees, modes=modes, beam_dts=beam_dts, beam_ref_dt=beam_ref_dt, beam_window=beam_window, beam_t_end=beam_t_end, beam_stat_dts=beam_stat_dts, beam_stat_ref_dt=beam_stat_ref_dt, beam_stat_window=beam_stat_window))


def stress(steps=None, elements=None, seed=None, out=None) -> StudyResult:
    """Stability stress (``cargo xtask stress``): long runs at extreme dx/dt."""
    return _run("stress", out, dict(steps=steps, elements=elements, seed=seed))
