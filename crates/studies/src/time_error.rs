//! The convergence study against the exact semi-discrete solution
//! (`cargo xtask convergence --reference event-driven`): the **time error**
//! of every scheme, apart from the space error.
//!
//! At each level `m` (and `dt = dx / ratio`) the scheme runs in lockstep
//! with `event-driven(e)` on the same problem (the same mesh, mass and
//! load): the exact solution of the semi-discrete problem with restitution
//! `e` (docs/theory.md §9) — `e` the scheme's own (`ps(e)`, `moreau-jean`),
//! 0 for the projection schemes, whose limit as dt → 0 is the plastic
//! impact law. The difference `E = U_scheme − U_exact` is measured at every
//! level in the semi-discrete norms: `linf_l2_u = max_n √(Eᵀ M E)`,
//! `linf_v_u = max_n √(Eᵀ K E)` (strain energy), `l2_lambda = (Σ_n dt
//! (λ_scheme − λ_exact)²)^{1/2}` (the exact `λ` of a level is the mean
//! force over the step, the quantity a scheme's `λ` estimates), and
//! `linf_energy = max_n |E_scheme − E_exact|` (each its own discrete
//! energy). The event-driven solution's own errors against the benchmark's
//! closed form (the exact norms of `cargo xtask convergence`) are the
//! **space error**, in the rows of scheme `event-driven(e)`.
//!
//! Outputs (`out/convergence/<benchmark>-event-driven/`): `time_error.csv`
//! with columns `scheme,mass,m,dx,dt,steps,reference,linf_l2_u,linf_v_u,l2_lambda,linf_energy`
//! then `events` (the reference's event count), and `space_error.csv`
//! (`reference,mass,m,dx,dt,linf_l2_u,l2_l2_u,linf_v_u,l2_lambda,linf_energy`);
//! on stdout the least-squares rates of each quantity against dt.

use crate::{fe, int, txt, Kind, StudyError, TableOut};
use signorini_exact::ExactSolution;
use signorini_fem::BarMass;
use signorini_reduce::Keep;
use signorini_run::study::{self, Level, StudyConfig};
use signorini_run::{Benchmark, RunConfig};
use signorini_schemes::{SchemeSpec, Stepper};
use std::path::Path;

/// The time error of one (scheme, mass, level).
#[derive(Clone, Debug)]
pub struct TimeError {
    /// The scheme.
    pub scheme: SchemeSpec,
    /// Its reference (`event-driven(e)`).
    pub reference: SchemeSpec,
    /// The mass.
    pub mass: BarMass,
    /// Elements.
    pub m: usize,
    /// Element size.
    pub dx: f64,
    /// Time step.
    pub dt: f64,
    /// Steps.
    pub steps: usize,
    /// `max_n √(Eᵀ M E)`.
    pub linf_l2_u: f64,
    /// `max_n √(Eᵀ K E)`.
    pub linf_v_u: f64,
    /// `(Σ_n dt (λ − λ_exact)²)^{1/2}` over the contacts.
    pub l2_lambda: f64,
    /// `max_n |E − E_exact|`.
    pub linf_energy: f64,
    /// The reference's events.
    pub events: usize,
    /// The scale of each quantity, in the order of the four errors above:
    /// the reference's own `max_n √(Uᵀ M U)`, `max_n √(Uᵀ K U)`,
    /// `(Σ_n dt λ²)^{1/2}` and `max_n |E|`. An error below [`ROUND_OFF`]
    /// times its scale is round-off.
    pub scales: [f64; 4],
}

/// An error at most `ROUND_OFF` times its quantity's scale
/// ([`TimeError::scales`]) is round-off, and no rate is fitted through it.
/// Measured: `event-driven(1)` conserves the energy exactly, and its
/// energy error against the closed form (pure round-off) grows with the
/// level, from 1.5e-14 of the energy at m = 10 to 5.3e-11 at m = 640
/// (19,200 steps of 640 dofs, `bar-dirichlet`, `dx/dt = 10`), while the
/// smallest error of a scheme or of the space discretisation measured there
/// (the default schemes with std, lumped and mod, m = 10 … 640) is 4.5e-5
/// (`ps-e1`, mod, m = 640, L∞(L²)), above 1e-5 of its scale. 1e-9 lies
/// between: 20 times the largest round-off measured, 1e-4 of the smallest
/// error.
pub const ROUND_OFF: f64 = 1e-9;

/// The event-driven reference of `scheme` on `mass`: its own restitution,
/// else 0; always 0 with a massless contact node (it lands without an
/// impact: no restitution acts there).
pub fn reference_of(scheme: &SchemeSpec, mass: BarMass) -> Result<SchemeSpec, StudyError> {
    let e = if mass.massless_contact_node() { 0.0 } else { scheme.param("e").unwrap_or(0.0) };
    format!("event-driven({e})").parse().map_err(|err: signorini_schemes::SchemeError| StudyError::config("schemes", format!("⟨schemes⟩ {scheme}: {err}")))
}

/// `event-driven(e)`: the reference's name in the tables.
fn label(r: &SchemeSpec) -> String {
    format!("event-driven({})", r.param("e").unwrap_or(0.0))
}

/// One (scheme, mass, level) in lockstep with its reference.
#[allow(clippy::too_many_arguments)]
pub fn run_case(benchmark: Benchmark, exact: &dyn ExactSolution, scheme: SchemeSpec, mass: BarMass, m: usize, degree: usize, ratio: f64, t_end: f64) -> Result<TimeError, StudyError> {
    let reference = reference_of(&scheme, mass)?;
    let mut rows = run_group(benchmark, exact, &[scheme], reference, mass, m, degree, ratio, t_end, None)?;
    Ok(rows.remove(0))
}

/// Every scheme of `schemes` (all with the reference `reference` on `mass`)
/// in lockstep with one run of the reference at level `m`: the same rows as
/// [`run_case`] one scheme at a time, the reference run once. With
/// `reduce`, all of them run the reduced model (docs/theory.md §2.5) and
/// the norms are the reduced model's own (`M_r`, `K_r = Tᵀ K T`): the time
/// error of the reduced semi-discrete problem.
#[allow(clippy::too_many_arguments)]
pub fn run_group(
    benchmark: Benchmark,
    exact: &dyn ExactSolution,
    schemes: &[SchemeSpec],
    reference: SchemeSpec,
    mass: BarMass,
    m: usize,
    degree: usize,
    ratio: f64,
    t_end: f64,
    reduce: Option<Keep>,
) -> Result<Vec<TimeError>, StudyError> {
    let problem = benchmark.problem_with_degree(exact, m, mass, degree).map_err(|e| StudyError::Run(e.to_string()))?;
    let dx = problem.bar.h();
    let dt = dx / ratio;
    let steps = RunConfig::new(dt, t_end).map_err(|e| StudyError::Run(e.to_string()))?.steps();
    let (dy, initial) = match reduce {
        None => (problem.dynamics(), problem.initial.clone()),
        Some(keep) => {
            let red = signorini_run::reduced::reduce(&problem.dynamics(), &problem.initial, keep).map_err(|e| StudyError::Run(format!("--reduce at m = {m}: {e}")))?;
            (red.dynamics, red.initial)
        }
    };
    let build = |s: &SchemeSpec| s.build(dy.clone(), dt, &initial).map_err(|e| StudyError::Run(format!("{s}, {mass}, m = {m}: {e}")));
    let mut b = build(&reference)?;
    // The reference's magnitudes: the scales of the four errors.
    let mut scales = [0.0f64; 4];
    let mut lam2 = 0.0;
    let mut scale = |b: &mut dyn Stepper, first: bool| {
        let u = b.displacement();
        scales[0] = scales[0].max(dy.mass.quad_form(u).max(0.0).sqrt());
        scales[1] = scales[1].max(dy.stiffness.quad_form(u).max(0.0).sqrt());
        if !first {
            lam2 += dt * b.contact_forces().iter().map(|l| l * l).sum::<f64>();
            scales[2] = lam2.sqrt();
        }
        if let Some(e) = b.energy() {
            scales[3] = scales[3].max(e.1.abs());
        }
    };
    scale(b.as_mut(), true);
    /// A scheme's lane: its stepper, its sums, whether it has started
    /// (a two-step scheme starts a level late) or blown up.
    struct Lane {
        a: Box<dyn Stepper>,
        acc: Acc,
        started: bool,
        failed: bool,
    }
    let mut lanes = schemes.iter().map(|s| Ok(Lane { a: build(s)?, acc: Acc { e: vec![0.0; dy.n()], ..Acc::default() }, started: false, failed: false })).collect::<Result<Vec<_>, StudyError>>()?;
    let start = |lanes: &mut [Lane], b: &mut dyn Stepper| {
        let level = b.level();
        for l in lanes.iter_mut().filter(|l| !l.started && l.a.level() == level) {
            l.acc.measure(&dy, dt, l.a.as_mut(), b, true);
            l.started = true;
        }
    };
    start(&mut lanes, b.as_mut());
    while b.level() < steps {
        b.step().map_err(|err| StudyError::Run(format!("{reference}, {mass}, m = {m}: {err}")))?;
        scale(b.as_mut(), false);
        for l in lanes.iter_mut().filter(|l| l.started && !l.failed) {
            if l.a.step().is_err() {
                // A blow-up: no error to report.
                l.acc = Acc { l2u: f64::NAN, lv: f64::NAN, lam2: f64::NAN, len: f64::NAN, e: Vec::new() };
                l.failed = true;
                continue;
            }
            l.acc.measure(&dy, dt, l.a.as_mut(), b.as_mut(), false);
        }
        start(&mut lanes, b.as_mut());
    }
    let events = b.events().map_or(0, <[_]>::len);
    Ok(schemes
        .iter()
        .zip(lanes)
        .map(|(&scheme, l)| {
            // A lane that never met the reference's level has no error.
            let Acc { l2u, lv, lam2, len, .. } = if l.started { l.acc } else { Acc { l2u: f64::NAN, lv: f64::NAN, lam2: f64::NAN, len: f64::NAN, e: Vec::new() } };
            TimeError { scheme, reference, mass, m, dx, dt, steps, linf_l2_u: l2u, linf_v_u: lv, l2_lambda: lam2.sqrt(), linf_energy: len, events, scales }
        })
        .collect())
}

/// The running maxima and sums of the difference.
#[derive(Default)]
struct Acc {
    e: Vec<f64>,
    l2u: f64,
    lv: f64,
    lam2: f64,
    len: f64,
}

impl Acc {
    fn measure(&mut self, dy: &signorini_schemes::Dynamics, dt: f64, a: &mut dyn Stepper, b: &mut dyn Stepper, first: bool) {
        for ((x, p), q) in self.e.iter_mut().zip(a.displacement()).zip(b.displacement()) {
            *x = p - q;
        }
        self.l2u = self.l2u.max(dy.mass.quad_form(&self.e).max(0.0).sqrt());
        self.lv = self.lv.max(dy.stiffness.quad_form(&self.e).max(0.0).sqrt());
        if !first {
            self.lam2 += dt * a.contact_forces().iter().zip(b.contact_forces()).map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
        }
        if let (Some(ea), Some(eb)) = (a.energy(), b.energy()) {
            self.len = self.len.max((ea.1 - eb.1).abs());
        }
    }
}

/// Whether `error` is round-off against `scale` ([`ROUND_OFF`]).
fn is_round_off(error: f64, scale: f64) -> bool {
    error <= ROUND_OFF * scale
}

/// The least-squares rate of `(h, error, scale)` points through the levels
/// whose error is above round-off; `round-off` when round-off leaves fewer
/// than two of them, `-` when there are fewer than two levels.
pub fn rate_cell(points: &[(f64, f64, f64)]) -> String {
    let above: Vec<(f64, f64)> = points.iter().filter(|p| !is_round_off(p.1, p.2)).map(|p| (p.0, p.1)).collect();
    if above.len() < 2 && above.len() < points.len() {
        return "round-off".into();
    }
    let r = study::rate(&above).lsq;
    if r.is_finite() {
        format!("{r:.2}")
    } else {
        "-".into()
    }
}

/// The finest level's error, marked when it is round-off.
fn finest_cell(error: f64, scale: f64) -> String {
    if is_round_off(error, scale) {
        format!("{error:.2e} (round-off)")
    } else {
        format!("{error:.2e}")
    }
}

/// The quantities, their columns and names.
const QUANTITIES: [(&str, &str); 4] = [("linf_l2_u", "L∞(L²)"), ("linf_v_u", "L∞(V)"), ("l2_lambda", "L²(λ)"), ("linf_energy", "L∞(E)")];

fn value(r: &TimeError, q: &str) -> f64 {
    match q {
        "linf_l2_u" => r.linf_l2_u,
        "linf_v_u" => r.linf_v_u,
        "l2_lambda" => r.l2_lambda,
        _ => r.linf_energy,
    }
}

/// Runs the study on `cfg`'s levels, schemes and masses (massless contact
/// nodes against `event-driven(0)`), writing
/// into `out`; returns the tables and the report.
pub fn run(cfg: &StudyConfig, reduce: Option<Keep>, out: &Path, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<(Vec<crate::Table>, String), StudyError> {
    let masses: Vec<BarMass> = cfg.masses.clone();
    let schemes: Vec<SchemeSpec> = cfg.schemes.iter().copied().filter(|s| s.family().name != "event-driven").collect();
    // One group per (mass, level, reference): the reference runs once,
    // its schemes in lockstep with it.
    let mut groups: Vec<(BarMass, usize, SchemeSpec, Vec<SchemeSpec>)> = Vec::new();
    for &mass in &masses {
        for &m in &cfg.levels {
            for &s in &schemes {
                let r = reference_of(&s, mass)?;
                match groups.iter_mut().find(|g| g.0 == mass && g.1 == m && label(&g.2) == label(&r)) {
                    Some(g) => g.3.push(s),
                    None => groups.push((mass, m, r, vec![s])),
                }
            }
        }
    }
    // The closed form (the problems' initial data and the space error's reference), built once.
    let exact = cfg.benchmark.exact(cfg.t_end).map_err(|e| StudyError::config("t_end", e.to_string()))?;
    let grouped = crate::run_cases(&groups, progress, &|(mass, m, r, ss)| run_group(cfg.benchmark, exact.as_ref(), ss, *r, *mass, *m, cfg.degree, cfg.ratio, cfg.t_end, reduce));
    let mut rows: Vec<TimeError> = Vec::new();
    for g in grouped {
        rows.extend(g?);
    }
    // In the order scheme, mass, level.
    let mut results = Vec::with_capacity(rows.len());
    for &s in &schemes {
        for &mass in &masses {
            for &m in &cfg.levels {
                if let Some(i) = rows.iter().position(|r| r.scheme == s && r.mass == mass && r.m == m) {
                    results.push(rows.swap_remove(i));
                }
            }
        }
    }
    crate::create_dir(out)?;
    let mut t = TableOut::create(
        out,
        "time_error.csv",
        &[
            ("scheme", Kind::S),
            ("mass", Kind::S),
            ("m", Kind::I),
            ("dx", Kind::F),
            ("dt", Kind::F),
            ("steps", Kind::I),
            ("reference", Kind::S),
            ("linf_l2_u", Kind::F),
            ("linf_v_u", Kind::F),
            ("l2_lambda", Kind::F),
            ("linf_energy", Kind::F),
            ("events", Kind::I),
        ],
    )?;
    for r in &results {
        t.row(vec![
            txt(r.scheme.to_string()),
            txt(r.mass.to_string()),
            int(r.m),
            fe(r.dx, 10),
            fe(r.dt, 10),
            int(r.steps),
            txt(label(&r.reference)),
            fe(r.linf_l2_u, 10),
            fe(r.linf_v_u, 10),
            fe(r.l2_lambda, 10),
            fe(r.linf_energy, 10),
            int(r.events),
        ])?;
    }
    let mut tables = vec![t.finish()?];
    // The space error: each reference against the closed form.
    let mut s = TableOut::create(
        out,
        "space_error.csv",
        &[
            ("reference", Kind::S),
            ("mass", Kind::S),
            ("m", Kind::I),
            ("dx", Kind::F),
            ("dt", Kind::F),
            ("linf_l2_u", Kind::F),
            ("l2_l2_u", Kind::F),
            ("linf_v_u", Kind::F),
            ("l2_lambda", Kind::F),
            ("linf_energy", Kind::F),
        ],
    )?;
    let mut space = Vec::new();
    // The scales of the space errors: the same reference's magnitudes.
    let scales_of = |r: &SchemeSpec, mass: BarMass, m: usize| results.iter().find(|x| label(&x.reference) == label(r) && x.mass == mass && x.m == m).map_or([f64::NAN; 4], |x| x.scales);
    // (reference, mass) pairs, each once: the references by name, each with
    // the masses (in the given order) on which a scheme uses it.
    let mut pairs: Vec<(SchemeSpec, BarMass)> = Vec::new();
    for &mass in &masses {
        for s in &schemes {
            pairs.push((reference_of(s, mass)?, mass));
        }
    }
    pairs.sort_by_key(|(r, mass)| (label(r), masses.iter().position(|m| m == mass)));
    pairs.dedup_by(|a, b| label(&a.0) == label(&b.0) && a.1 == b.1);
    for (r, mass) in &pairs {
        let (r, mass) = (r, *mass);
        for &m in &cfg.levels {
            let lv = study::run_level(&Level::new(cfg.benchmark, *r, mass, m, cfg.ratio, cfg.t_end).with_degree(cfg.degree).with_reduce(reduce), exact.as_ref())
                .map_err(|e| StudyError::Run(e.to_string()))?;
            let v = |name: &str| study::norm_value(&lv.norms, name);
            s.row(vec![
                txt(label(r)),
                txt(mass.to_string()),
                int(m),
                fe(lv.dx, 10),
                fe(lv.dt, 10),
                fe(v("linf_l2_u"), 10),
                fe(v("l2_l2_u"), 10),
                fe(v("linf_v_u"), 10),
                fe(v("l2_lambda"), 10),
                fe(v("linf_energy"), 10),
            ])?;
            space.push((label(r), mass, lv.dx, [v("linf_l2_u"), v("linf_v_u"), v("l2_lambda"), v("linf_energy")], scales_of(r, mass, m)));
        }
    }
    tables.push(s.finish()?);
    // The report: rates against dt (least squares over the levels).
    let mut report = format!(
        "# Time error against the exact semi-discrete solution: {}, dx/dt = {}, T = {}, m = {:?}, P{} elements{}\n\nEach scheme against `event-driven(e)` at the same level (its own restitution e, 0 for the projection schemes); least-squares rates against dt, then the finest level's error (CSV: {}). An error at most {ROUND_OFF:e} times the reference's own size of that quantity (max √(UᵀMU), max √(UᵀKU), (Σ dt λ²)^½, max |E|) is round-off: no rate is fitted through it, and a rate with fewer than two levels above round-off reads `round-off`.\n\n| scheme | mass | reference |",
        cfg.benchmark,
        cfg.ratio,
        cfg.t_end,
        cfg.levels,
        cfg.degree,
        match reduce {
            None => String::new(),
            Some(Keep::Modes(r)) => format!(" — reduced model (docs/theory.md §2.5), {r} modes, in its own norms"),
            Some(Keep::CutoffHz(f)) => format!(" — reduced model (docs/theory.md §2.5), modes up to {f} Hz, in its own norms"),
        },
        out.join("time_error.csv").display()
    );
    for (_, name) in QUANTITIES {
        report.push_str(&format!(" {name} rate | finest |"));
    }
    report.push_str("\n|---|---|---|");
    report.push_str(&"---|---|".repeat(QUANTITIES.len()));
    report.push('\n');
    for &sch in &schemes {
        for &mass in &masses {
            let rows: Vec<&TimeError> = results.iter().filter(|r| r.scheme == sch && r.mass == mass).collect();
            let Some(finest) = rows.iter().min_by(|a, b| a.dt.total_cmp(&b.dt)) else { continue };
            report.push_str(&format!("| {sch} | {mass} | {} |", label(&finest.reference)));
            for (k, (q, _)) in QUANTITIES.iter().enumerate() {
                let pts: Vec<(f64, f64, f64)> = rows.iter().map(|r| (r.dt, value(r, q), r.scales[k])).collect();
                report.push_str(&format!(" {} | {} |", rate_cell(&pts), finest_cell(value(finest, q), finest.scales[k])));
            }
            report.push('\n');
        }
    }
    report.push_str("\n## Space error: the exact semi-discrete solution against the closed form (rates against dx)\n\n| reference | mass |");
    for (_, name) in QUANTITIES {
        report.push_str(&format!(" {name} rate | finest |"));
    }
    report.push_str("\n|---|---|");
    report.push_str(&"---|---|".repeat(QUANTITIES.len()));
    report.push('\n');
    for (r, mass) in &pairs {
        let rows: Vec<_> = space.iter().filter(|x| x.0 == label(r) && x.1 == *mass).collect();
        let Some(finest) = rows.iter().min_by(|a, b| a.2.total_cmp(&b.2)) else { continue };
        report.push_str(&format!("| {} | {mass} |", label(r)));
        for k in 0..QUANTITIES.len() {
            let pts: Vec<(f64, f64, f64)> = rows.iter().map(|x| (x.2, x.3[k], x.4[k])).collect();
            report.push_str(&format!(" {} | {} |", rate_cell(&pts), finest_cell(finest.3[k], finest.4[k])));
        }
        report.push('\n');
    }
    Ok((tables, report))
}
