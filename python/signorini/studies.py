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


# <generated by `cargo xtask docs` from each study's Config (crates/studies); do not edit>


def convergence(benchmark=None, schemes=None, masses=None, levels=None, ratio=None, t_end=None, norms=None, out=None, clean=None, reduce=None, degree=None, reference=None) -> ConvergenceResult:
    """The convergence study: for each (scheme, mass), the benchmark at each level m (m
    elements; bar-mirrored 2m on its [0, 2]) with dt = dx/``ratio`` up to ``t_end``, and
    every error norm. An output folder holding CSV or SVG files this study would not
    write (another study's or configuration's) is refused unless ``clean`` removes them.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``benchmark``: Benchmark with an exact solution (bar-dirichlet,
      bar-neumann-gravity, bar-neumann-gravity-0.11, bar-mirrored: level m is m elements
      on [0, 1], 2m on its [0, 2]). Default: ``"bar-dirichlet"``.
    * ``schemes``: Schemes, comma-separated: presets or newmark(B,G), theta(T), ps(E) or
      ps(E,B) (commas inside parentheses do not split). Default: ``["newmark-cn",
      "newmark-i", "newmark-ii", "backward-euler", "ps-e0", "ps-e0.5", "ps-e1"]``.
    * ``masses``: Mass treatments, comma-separated (std, lumped, mod, mod1, mod2, mod3,
      transfer, singular). Default: ``["std", "mod"]``.
    * ``levels``: Numbers of elements m, comma-separated. Default: ``[10, 20, 40, 80,
      160, 320, 640]``.
    * ``ratio``: dx/dt (default: the benchmark's, 10 for bar-dirichlet).
    * ``t_end``: Horizon T (default: the benchmark's, 3 for bar-dirichlet).
    * ``norms``: Error measure: exact (kink-split, docs/theory.md §6.1) or getfem
      (errors of the nodal interpolant, relative to the reference's norms, as GetFEM's
      1D dynamic-contact demo computes them). Default: ``"exact"``.
    * ``out``: Output folder (default `out/convergence/<benchmark>`, or
      `out/convergence/<benchmark>-getfem-norms` with the GetFEM norms). ``None``: a
      temporary folder, removed afterwards.
    * ``clean``: Remove the CSV and SVG files of another study or configuration from the
      output folder first (without it such a folder is refused). Default: ``False``.
    * ``reduce``: A reduced model at every level (docs/theory.md §2.5): modes=R keeps
      the R lowest fixed-interface modes, cutoff_hz=F every mode up to F Hz (needs a
      massless-contact mass and a scheme that takes one). Default: none, the full model.
    * ``degree``: Element degree k (1, 2, 3: Lagrange P1, P2, P3); level m is m elements
      of degree k (default folder `out/convergence/<benchmark>-p<k>` for k > 1); the
      files of degree 1 are those of P1, byte for byte. Default: ``1``.
    * ``reference``: What the errors are measured against: exact (the benchmark's closed
      form) or event-driven (the exact semi-discrete solution on the same mesh: the time
      error alone, with the space error beside it; every mass, massless contact nodes
      against event-driven(0); with ``reduce``, the reduced model's; default folder
      `out/convergence/<benchmark>-event-driven[-reduce-…]`). Default: ``"exact"``.
    """
    return _run("convergence", out, dict(benchmark=benchmark, schemes=schemes, masses=masses, levels=levels, ratio=ratio, t_end=t_end, norms=norms, clean=clean, reduce=reduce, degree=degree, reference=reference), ConvergenceResult)


def weighted(t_end=None, out=None) -> StudyResult:
    """The weighted-mass-redistribution study (mod1/mod2/mod3 × newmark-cn,
    backward-euler, ps-e1, hybrid): figure runs, phase errors, energy loss and
    convergence.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``t_end``: Horizon of the figure runs (the paper's figures show [0, 3]; the phase
      and energy tables use 3 and 30). Default: ``30``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    """
    return _run("weighted", out, dict(t_end=t_end), StudyResult)


def beam(scenes=None, force=None, penalty_dts=None, out=None) -> StudyResult:
    """The beam between two stops: the paper's scenes, the exact stability limit,
    self-convergence, the penalty study.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``scenes``: Scenes to run, comma-separated (fig2 … fig8, the paper's). Default:
      ``["fig2", "fig3", "fig4", "fig5", "fig6", "fig7", "fig8"]``.
    * ``force``: Run conditionally stable scenes even beyond their stability limit.
      Default: ``False``.
    * ``penalty_dts``: Time steps (s) of the penalty study (`penalty.csv`),
      comma-separated; the paper's are 5e-6, 1e-6, 5e-7 (runs the figures already made
      are reused). Default: ``[5e-6, 1e-6, 5e-7]``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    """
    return _run("beam", out, dict(scenes=scenes, force=force, penalty_dts=penalty_dts), StudyResult)


def beam_obstacles(gap=None, beta=None, t_end=None, dts=None, j=None, js=None, j_dt=None, out=None) -> StudyResult:
    """The beam between obstacles along its whole length (problem (P)): feasibility,
    self-convergence in dt (J = ``j``, time steps ``dts``) and in J (meshes ``js`` at
    ``j_dt``), energy balance.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``gap``: Obstacles at -g and +g (m) along the whole beam. Default: ``0.05``.
    * ``beta``: β of the β-scheme (>= 1/4: unconditionally stable). Default: ``0.25``.
    * ``t_end``: Horizon (s): long enough for several impacts, short enough that the
      vibro-impact motion has not become sensitive to rounding. Default: ``0.2``.
    * ``dts``: Time steps of the dt study (s), J fixed at ``j``; each must divide the
      first (coarsest), the reference is the last divided by 4. Default: ``[1e-4, 5e-5,
      2.5e-5, 1.25e-5, 6.25e-6]``.
    * ``j``: Elements of the dt study. Default: ``20``.
    * ``js``: Meshes of the J study (each a multiple of the first), dt fixed at
      ``j_dt``; the reference is the last times 2. Default: ``[5, 10, 20, 40, 80]``.
    * ``j_dt``: Time step of the J study (s). Default: ``1e-5``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    """
    return _run("beam_obstacles", out, dict(gap=gap, beta=beta, t_end=t_end, dts=dts, j=j, js=js, j_dt=j_dt), StudyResult)


def oscillator(omegas=None, dts=None, transient=None, record=None, out=None) -> StudyResult:
    """The impact oscillator against its exact period-1 orbits: impact velocity and
    phase errors and their rates in dt at each forcing frequency of ``omegas``; the
    grazing frequency.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``omegas``: Forcing frequencies (the scene's stable period-1 range). Default:
      ``[1.6, 1.7, 1.8, 1.9, 2, 2.1, 2.2]``.
    * ``dts``: Time steps (2e-3 halved eight times). Default: ``[0.002, 0.001, 5e-4,
      2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5, 1.5625e-5, 7.8125e-6]``.
    * ``transient``: Forcing periods before the record window. Default: ``60``.
    * ``record``: Forcing periods recorded. Default: ``10``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    """
    return _run("oscillator", out, dict(omegas=omegas, dts=dts, transient=transient, record=record), StudyResult)


def courant1(benchmarks=None, levels=None, t_end=None, out=None) -> StudyResult:
    """Courant number one: the lumped central difference at dx/dt = c with Taylor's and
    Newmark's starts, node by node against the exact solutions; where the first nodal
    error appears.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``benchmarks``: Benchmarks, comma-separated (default: all four). Default:
      ``["bar-dirichlet", "bar-neumann-gravity", "bar-neumann-gravity-0.11",
      "bar-mirrored"]``.
    * ``levels``: Numbers of elements m, comma-separated. Default: ``[10, 20, 40, 80]``.
    * ``t_end``: Horizon (default: 6 for the Dirichlet and mirrored bars, two periods,
      and 16 for the falling bars).
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    """
    return _run("courant1", out, dict(benchmarks=benchmarks, levels=levels, t_end=t_end), StudyResult)


def long_horizon(runs=None, levels=None, ratio=None, t_end=None, energy=None, energy_runs=None, energy_all=None, energy_ratios=None, energy_m=None, energy_t_end=None, out=None, energy_benchmark=None) -> StudyResult:
    """Long horizons: the Dirichlet bar over ``t_end`` (ten periods by default) for
    ``runs``: the largest L² error in each period, every impact time against the exact
    one, the drift per period. Then (unless ``energy`` is off) the energy-growth table:
    ``energy_runs`` (or ``energy_all``: every named scheme with every mass it accepts)
    at each dx/dt of ``energy_ratios`` on ``energy_m`` elements to ``energy_t_end``: the
    largest E/budget and when it first exceeds 2 (energy_growth.csv, energy_vs_time.csv,
    energy_growth.svg), from bar-dirichlet's initial data or ``energy_benchmark``'s. The
    default table takes minutes; a shorter ``energy_t_end`` shortens it.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``runs``: scheme:mass pairs, comma-separated (default: ps-e0 with every mass,
      moreau-jean with std and lumped). Default: ``["ps-e0:std", "ps-e0:lumped",
      "ps-e0:mod", "ps-e0:mod2", "ps-e0:mod3", "ps-e0:transfer", "ps-e0:singular",
      "moreau-jean:std", "moreau-jean:lumped"]``.
    * ``levels``: Numbers of elements m, comma-separated. Default: ``[20, 40, 80]``.
    * ``ratio``: dx/dt (the papers'). Default: ``10``.
    * ``t_end``: Horizon (three time units a period: 30 is ten periods). Default:
      ``30``.
    * ``energy``: The energy-growth table (energy_growth.csv, energy_vs_time.csv,
      energy_growth.svg; off: left out). Default: ``True``.
    * ``energy_runs``: Energy-growth table: scheme:mass pairs, comma-separated (default:
      newmark-cn and ps-e0 with std, lumped, mod, mod3; ps-e1 with std, mod3;
      moreau-jean with std, lumped; hybrid with mod, mod3).
    * ``energy_all``: Energy-growth table: every named scheme with every mass it accepts
      (instead of the default runs; not with ``energy_runs``). Default: ``False``.
    * ``energy_ratios``: Energy-growth table: dx/dt values, comma-separated. Default:
      ``[1, 2, 10]``.
    * ``energy_m``: Energy-growth table: number of elements. Default: ``100``.
    * ``energy_t_end``: Energy-growth table: horizon. Default: ``10000``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    * ``energy_benchmark``: Energy-growth table: the benchmark whose initial data, load
      and far end the runs start from (bar-dirichlet; bar-neumann-gravity:
      Doyen–Ern–Piperno's bouncing bar, two impacts every 16 time units;
      bar-neumann-gravity-0.11 to ``energy_t_end`` ≤ 225; bar-mirrored). Default:
      ``"bar-dirichlet"``.
    """
    return _run("long_horizon", out, dict(runs=runs, levels=levels, ratio=ratio, t_end=t_end, energy=energy, energy_runs=energy_runs, energy_all=energy_all, energy_ratios=energy_ratios, energy_m=energy_m, energy_t_end=energy_t_end, energy_benchmark=energy_benchmark), StudyResult)


def lyapunov(scenes=None, refine=None, dts=None, elements=None, omegas=None, perturbation=None, transient=None, window=None, per_period=None, batches=None, out=None) -> StudyResult:
    """Largest Lyapunov exponents by Benettin's twin runs: the twin perturbed by a
    relative ``perturbation`` of the state's energy norm, renormalised ``per_period``
    times a forcing period over ``window`` forcing periods after ``transient``, a 95 %
    interval from ``batches`` batch means. Cases: the beam ``scenes`` at their own dt
    and J, the ``refine`` scenes at every ``dts`` × ``elements``, the impact oscillator
    at every Ω of ``omegas``. lyapunov.csv: scene, dt, elements, lambda_max, ci_low,
    ci_high, horizon_s (the time for a 1e-16 relative round-off to grow to 1 mm; NaN for
    λ <= 0); oscillator.csv: omega, lambda_max, ci_low, ci_high, lambda_exact,
    multiplier (the exact Floquet exponent of the period-1 orbit).

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``scenes``: Beam scenes at their own dt and J, comma-separated (fig2-support, fig2
      … fig8, beam-obstacles; default every one; none: no such case). Default:
      ``["fig2-support", "fig2", "fig3", "fig4", "fig5", "fig6", "fig7", "fig8",
      "beam-obstacles"]``.
    * ``refine``: Beam scenes run again at every ``dts`` × ``elements``. Default:
      ``["fig2-support"]``.
    * ``dts``: Time steps of the refinement (s), comma-separated. Default: ``[5e-5,
      2.5e-5, 1e-5]``.
    * ``elements``: Elements J of the refinement, comma-separated. Default: ``[19,
      38]``.
    * ``omegas``: Forcing frequencies of the impact oscillator, comma-separated (default
      its sweep range 1.6 … 2.2; none or empty: no oscillator). Default: ``[1.6, 1.7,
      1.8, 1.9, 2, 2.1, 2.2]``.
    * ``perturbation``: Relative perturbation of the twin (0 < ε < 1e-3). Default:
      ``1e-10``.
    * ``transient``: Forcing periods before the twin starts. Default: ``10``.
    * ``window``: Forcing periods measured. Default: ``20``.
    * ``per_period``: Renormalisations per forcing period. Default: ``64``.
    * ``batches``: Batches of the 95 % confidence interval. Default: ``10``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    """
    return _run("lyapunov", out, dict(scenes=scenes, refine=refine, dts=dts, elements=elements, omegas=omegas, perturbation=perturbation, transient=transient, window=window, per_period=per_period, batches=batches), StudyResult)


def beam_statistics(scenes=None, dts=None, elements=None, transient=None, window=None, batches=None, episode_gap=None, out=None, schemes=None) -> StudyResult:
    """Statistics that converge: the beam ``scenes`` at every ``dts`` and ``elements``
    over ``window`` forcing periods after ``transient``, each statistic with a 95 %
    interval from ``batches`` batch means, against the finest level. statistics.csv:
    scene, dt, elements, statistic, mean, ci_low, ci_high, finest_mean, rel_diff,
    within_ci, kind (converges or step-dependent); active runs closer than
    ``episode_gap`` seconds form one contact episode.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``scenes``: Scenes, comma-separated (fig2-support, beam-obstacles). Default:
      ``["fig2-support"]``.
    * ``dts``: Time steps (s), comma-separated. Default: ``[5e-5, 2.5e-5, 1e-5]``.
    * ``elements``: Elements J, comma-separated. Default: ``[19, 38]``.
    * ``transient``: Forcing periods before the window. Default: ``10``.
    * ``window``: Forcing periods of the window (at least 10; 320 is 201 s at ω = 10).
      Default: ``320``.
    * ``batches``: Batches of the 95 % intervals (at least 10; 20 are 10-s batches).
      Default: ``20``.
    * ``episode_gap``: Active runs closer than this (s) form one contact episode.
      Default: ``0.005``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    * ``schemes``: Schemes, comma-separated (default: the scene's own, the paper's
      projection scheme `ps(0,0.5)`). Every scheme runs every level, and every level is
      compared with the finest level of the first.
    """
    return _run("beam_statistics", out, dict(scenes=scenes, dts=dts, elements=elements, transient=transient, window=window, batches=batches, episode_gap=episode_gap, schemes=schemes), StudyResult)


def work_precision(levels=None, degrees=None, modes=None, beam_dts=None, beam_ref_dt=None, beam_window=None, beam_t_end=None, beam_stat_dts=None, beam_stat_ref_dt=None, beam_stat_window=None, out=None, reference=None, repeats=None, schemes=None) -> StudyResult:
    """Work–precision: error against wall time for every scheme and mass, then the
    frontier on the same axes: Courant-one central difference, P2/P3 (``degrees``),
    reduced bar and beam models (``modes``), and the beam of figure 2 at ``beam_dts``
    against a reference at ``beam_ref_dt`` (tip error over [0, ``beam_window``] and [0,
    ``beam_t_end``], first-impact error). The beam with its support motion (fig. 2 with
    `[support]`) at ``beam_stat_dts`` gives its impact power over ``beam_stat_window``
    forcing periods with a 95 % interval, against ``beam_stat_ref_dt``. Empty
    ``degrees``, ``modes``, ``beam_dts`` or ``beam_stat_dts`` leave those rows out.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``levels``: Levels m, comma-separated. Default: ``[10, 20, 40, 80, 160, 320,
      640]``.
    * ``degrees``: Element degrees beyond P1 (2, 3), comma-separated; empty: none.
      Default: ``[2, 3]``.
    * ``modes``: Kept modes of the reduced bar and beam models, comma-separated; empty:
      none. Default: ``[2, 4, 8, 16]``.
    * ``beam_dts``: Time steps of the beam rows (s), comma-separated; empty: no beam
      rows. Default: ``[1e-5, 2.5e-5, 5e-5, 1e-4, 2.5e-4, 5e-4]``.
    * ``beam_ref_dt``: The beam reference's time step (s). Default: ``2.5e-7``.
    * ``beam_window``: The beam's error window [0, w] (s). Default: ``0.1``.
    * ``beam_t_end``: The beam's horizon (s). Default: ``1``.
    * ``beam_stat_dts``: Time steps of the beam's impact-power rows (s),
      comma-separated; empty: none. Fig. 2 with `[support]`, its impact power over a
      long window against the run at ``beam_stat_ref_dt``. Default: ``[5e-5, 2.5e-5,
      1e-5]``.
    * ``beam_stat_ref_dt``: The impact power's reference step (s). Default: ``5e-6``.
    * ``beam_stat_window``: The impact power's window (forcing periods; 320 is 201 s at
      ω = 10; 20 batches, after 10 periods). Default: ``320``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    * ``reference``: The beam rows' reference: fine-step (the projection scheme at
      ``beam_ref_dt``) or event-driven (the exact semi-discrete solution, sampled at the
      largest step dividing every ``beam_dts``). The bar rows are always measured
      against their closed forms (what the convergence study's reference exact means);
      the beam has none, hence fine-step where convergence says exact, and exact is
      refused. Default: ``"fine-step"``.
    * ``repeats``: Timed runs per configuration, in [1, 100]: the cost is their median,
      and two configurations whose ranges [min, max] overlap are a tie. Default: ``5``.
    * ``schemes``: The bar rows' schemes, comma-separated (default: every named scheme
      of `signorini list`, by name); a family without presets by its call
      (`contact-stabilized`, `nsga(0.5)`). Each runs with every mass it accepts.
    """
    return _run("work_precision", out, dict(levels=levels, degrees=degrees, modes=modes, beam_dts=beam_dts, beam_ref_dt=beam_ref_dt, beam_window=beam_window, beam_t_end=beam_t_end, beam_stat_dts=beam_stat_dts, beam_stat_ref_dt=beam_stat_ref_dt, beam_stat_window=beam_stat_window, reference=reference, repeats=repeats, schemes=schemes), StudyResult)


def stress(steps=None, elements=None, seed=None, out=None, schemes=None) -> StudyResult:
    """Stability stress: long runs at extreme dx/dt with random initial data; energy
    drift and blow-ups.

    Arguments (each ``None`` for its default; a list of numbers or names as a Python
    list):

    * ``steps``: Steps per run. Default: ``100000``.
    * ``elements``: Elements. Default: ``40``.
    * ``seed``: Random seed; run `k` of a (scheme, mass) row uses `seed · 1000 + k`
      (wrapping), written as an `I64` (wrapping too). Default: ``1``.
    * ``out``: Output folder. ``None``: a temporary folder, removed afterwards.
    * ``schemes``: Schemes, comma-separated (default: every named scheme of `signorini
      list`, by name); a family without presets by its call (`contact-stabilized`,
      `nsga(0.5)`). Each runs with every mass it accepts.
    """
    return _run("stress", out, dict(steps=steps, elements=elements, seed=seed, schemes=schemes), StudyResult)

# </generated>
