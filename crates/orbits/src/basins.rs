//! Basins of attraction on the exact flow: each initial state of a grid
//! in two numeric scene keys (an initial displacement and velocity) run
//! for a transient of forcing periods, then its attractor read off the
//! stroboscopic map `P` (the flow over one forcing period `2π/Ω`, section
//! at forcing phase 0):
//!
//! * **period k** — the smallest `k ≤ max_period` with
//!   `‖P^k(x) − x‖∞ ≤ tol · max(1, ‖x‖∞)`, `x` the state after the
//!   transient (the state is the displacements and velocities of the dofs
//!   with mass);
//! * **impacts per period** — the impacts of the flow over those `k`
//!   forcing periods (one period of the orbit);
//! * **sticking** — a held phase on the way (a release or an
//!   accumulation of impacts over those `k` periods, or a contact held at
//!   the section);
//! * **non-periodic** — no such `k` (chaos, a longer period, or a
//!   transient not yet over: the tolerance is stated, the transient a
//!   choice).
//!
//! A slow transient is refined before it is read: where `P^j(x)` is within
//! `match_tol · max(1, ‖x‖∞)` of `x` for a `j` that divides the `k` found
//! (or for any `j ≤ max_period` when none is found), Newton on `P^j` from
//! `x` is tried, and a stable orbit it converges to within that distance
//! is the cell's attractor, its period and impacts read from the orbit's
//! point. A lightly damped free vibration left over after the transient
//! returns nearly whole after as many forcing periods as make one natural
//! period, and was called a longer period (the oscillator forced at
//! Ω = 5: "period 5" where the attractor is the free period-1 orbit).
//!
//! **A transient stopped on a known attractor.** A grid first classifies
//! its seed cells ([`BasinScene::seeds`], 8 × 8 spread over the grid) in
//! full; each distinct stable periodic attractor they reach becomes a
//! [`Target`]: Newton on `P^p` from its point converges to a fixed point
//! `x*` whose multipliers are all inside the unit circle, and its radius
//! `r` is the largest of `0.05 · max(1, ‖x*‖∞) · 2^−m` (`m ≤ 14`) at which
//! `P^p` maps `x* ± r·d` to within `r/10` of its linearisation
//! `x* ± r·J d` for every coordinate direction `d` and the two diagonals
//! (no impact appears, vanishes or moves beyond what the Jacobian says
//! within that distance). Every other cell's transient is read at each
//! forcing period ([`Model::flow_read`]: the same run as one flow), and
//! stops at the first `n` where `d_n = ‖P^n(x0) − x*‖∞ <= r` and
//! `d_{n+2p} < d_{n+p} < d_n` (`p` periods apart: the same phase of the
//! cycle; two contractions in a row where the map is its contracting
//! linearisation): the cell is then the target's attractor, written as the
//! target's period, impacts, held phase and canonical point. A cell that
//! never stops so runs its whole transient and is classified as above,
//! bit for bit. The targets come from the seeds alone (not from the cells
//! classified so far), so every shard and thread count makes the same
//! decisions, and a merge is the unsharded grid byte for byte; a key that
//! changes the map (not only the start) makes each cell's map its own, and
//! no target fits it ([`Target::fits`]). Known orbits (below) add their
//! stable points at the scene's map as targets beside the seeds'
//! ([`BasinScene::known_targets`]: the same [`Target::new`], so the same
//! Newton, stability test and radius); an unstable one never is.
//!
//! Cells on one attractor are grouped ([`Grouper`]): two periodic cells
//! share an attractor when their periods agree and a point of one's cycle
//! is within `match_tol · max(1, ‖x‖∞)` of the other's canonical point
//! (the cycle point with the smallest first coordinate, ties broken by the
//! next ones). Ids are given in cell order, each new attractor the next
//! id, so a prefix of the grid has the ids the whole grid gives it.
//! Known orbits (a continuation's `branch.csv` rows, [`parse_branch`])
//! label the attractors they match within the same tolerance.
//!
//! A whole grid as the front ends run it — options, known orbits, cells in
//! parallel, attractor ids, shards and their merge, and the text of
//! `basins.csv`, `basins.svg` and `basins.toml` — is [`Grid`] ([`basins_csv`]
//! gives the columns). Nothing here does IO; the front ends write the
//! files.

mod grid;

pub use grid::{basins_csv, basins_svg, basins_toml, block, merge, AttractorEntry, Basins, Grid, GridOptions, Manifest, Merged, BASIN_COLUMNS, FAILED, NON_PERIODIC};

use crate::map::Model;
use crate::scene::{lookup_as, Built, SceneFamily};
use crate::shoot::{periodic_orbit, Newton};
use crate::OrbitError;
use signorini_scene::Limits;
use signorini_schemes::events::EventKind;
use signorini_schemes::Dynamics;
use std::f64::consts::TAU;

/// One axis of the grid: a numeric scene key and its values
/// `from + (to − from)·i/(count − 1)`, `i = 0, …, count − 1` (`from`
/// alone when `count = 1`).
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The dotted path in the scene (`oscillator.initial_displacement`).
    pub path: String,
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Values (>= 1).
    pub count: usize,
}

impl Axis {
    /// The `i`-th value, spaced as a sweep's axis ([`signorini_sweep::grid`]):
    /// the ends exact, so a range that ends on the stop starts a cell on it.
    pub fn value(&self, i: usize) -> f64 {
        signorini_sweep::grid(self.from, self.to, self.count, false, i)
    }
}

/// What is asked of the classification.
#[derive(Clone, Debug, PartialEq)]
pub struct BasinOptions {
    /// Forcing periods run before the attractor is read (default 200).
    pub transient: usize,
    /// The longest period looked for, in forcing periods (default 16).
    pub max_period: usize,
    /// The periodicity tolerance, relative to `max(1, ‖x‖∞)` (default 1e-6).
    pub tol: f64,
    /// The tolerance of grouping cells into attractors and matching known
    /// orbits, relative to `max(1, ‖x‖∞)` (default 1e-3).
    pub match_tol: f64,
}

impl Default for BasinOptions {
    fn default() -> Self {
        Self { transient: 200, max_period: 16, tol: 1e-6, match_tol: 1e-3 }
    }
}

impl BasinOptions {
    /// Checks every value: a typed error naming the option otherwise.
    pub fn validate(&self) -> Result<(), OrbitError> {
        let bad = |option: &'static str, message: String| Err(OrbitError::Option { option, message });
        if self.max_period == 0 || self.max_period > 1000 {
            return bad("max-period", format!("{} is not allowed: forcing periods, an integer in [1, 1000]", self.max_period));
        }
        if !(self.tol.is_finite() && self.tol > 0.0 && self.tol < 1.0) {
            return bad("tol", format!("{} is not allowed: a relative tolerance in (0, 1)", self.tol));
        }
        if !(self.match_tol.is_finite() && self.match_tol > 0.0 && self.match_tol < 1.0) {
            return bad("match-tol", format!("{} is not allowed: a relative tolerance in (0, 1)", self.match_tol));
        }
        Ok(())
    }
}

/// The attractor a cell went to.
#[derive(Clone, Debug, PartialEq)]
pub struct Attractor {
    /// Its period in forcing periods (0: non-periodic).
    pub period: usize,
    /// Impacts over one period of the orbit (`period` forcing periods; over
    /// `max_period` forcing periods for a non-periodic cell).
    pub impacts: usize,
    /// A held phase on the orbit.
    pub sticking: bool,
    /// The canonical point of its cycle on the section (the state after the
    /// transient for a non-periodic cell).
    pub state: Vec<f64>,
    /// Every point of its cycle on the section, in the map's order
    /// (empty for a non-periodic cell).
    pub cycle: Vec<Vec<f64>>,
}

impl Attractor {
    /// Periodic.
    pub fn periodic(&self) -> bool {
        self.period > 0
    }
}

/// What became of a cell.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// It reached (or did not reach) an attractor.
    Attractor(Attractor),
    /// The scene at this cell's values is not valid, or the exact run
    /// failed (the reason, in words).
    Failed(String),
}

/// The infinity norm.
fn norm(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// The index of the canonical point of a cycle: the smallest first
/// coordinate, ties by the next ones.
fn canonical(cycle: &[Vec<f64>]) -> usize {
    (0..cycle.len()).min_by(|&a, &b| cycle[a].iter().zip(&cycle[b]).map(|(x, y)| x.total_cmp(y)).find(|o| o.is_ne()).unwrap_or(std::cmp::Ordering::Equal)).unwrap_or(0)
}

/// Classifies the state `x0` at `t = 0` of `model` forced at `omega`:
/// `opts.transient` forcing periods of the exact flow, then the period test
/// on the stroboscopic map, with a slow transient's refinement (module
/// docs). Errors are the exact run's.
pub fn classify(model: &Model, omega: f64, x0: &[f64], opts: &BasinOptions) -> Result<Attractor, OrbitError> {
    let period = TAU / omega;
    let mut x = x0.to_vec();
    if opts.transient > 0 {
        x = model.flow(0.0, &x, opts.transient as f64 * period, false)?.x;
    }
    after_transient(model, period, x, opts)
}

/// [`classify`] with `targets`, the stable attractors a transient may stop
/// on (module docs, "A transient stopped on a known attractor"): the
/// transient's flow is read at each forcing period, and where its iterates
/// come within a target's radius of its point and their distances to it
/// shrink twice, `p` periods apart (the same phase), the cell is the
/// target's attractor: the target's own classification is returned with
/// the forcing period the transient stopped at. A target of another map
/// (another structure, loads, restitution or forcing frequency) is not
/// used. Without a target stopped on, the transient runs whole and the
/// result is [`classify`]'s, bit for bit (the same run read on the way).
pub fn classify_near(model: &Model, omega: f64, x0: &[f64], opts: &BasinOptions, targets: &[Target]) -> Result<(Attractor, Option<usize>), OrbitError> {
    let near: Vec<&Target> = targets.iter().filter(|t| t.fits(model, omega)).collect();
    if near.is_empty() || opts.transient == 0 {
        return Ok((classify(model, omega, x0, opts)?, None));
    }
    let period = TAU / omega;
    // The last 2p + 1 distances to each target's point, by period.
    let mut seen: Vec<Vec<f64>> = near.iter().map(|t| vec![f64::INFINITY; 2 * t.attractor.period + 1]).collect();
    let mut stop = None;
    let (_, x) = model.flow_read(0.0, x0, period, opts.transient, |k, x| {
        for (n, t) in near.iter().enumerate() {
            let (p, ring) = (t.attractor.period, &mut seen[n]);
            let len = ring.len();
            ring[k % len] = dist(x, &t.point);
            if k > 2 * p {
                let (a, b, c) = (ring[(k - 2 * p) % len], ring[(k - p) % len], ring[k % len]);
                if a <= t.radius && b < a && c < b {
                    stop = Some((n, k));
                    return false;
                }
            }
        }
        true
    })?;
    if let Some((n, k)) = stop {
        return Ok((near[n].attractor.clone(), Some(k)));
    }
    Ok((after_transient(model, period, x, opts)?, None))
}

/// The period test and a slow transient's refinement from `x`, the state
/// after the transient (at `t = transient · period`).
fn after_transient(model: &Model, period: f64, x: Vec<f64>, opts: &BasinOptions) -> Result<Attractor, OrbitError> {
    let t0 = opts.transient as f64 * period;
    let scale = norm(&x).max(1.0);
    let it = iterate(model, t0, period, &x, opts.max_period, opts.tol * scale)?;
    // A slow transient: the smallest j whose iterate is within `match_tol`
    // of `x`, a divisor of the period found, or any j without one.
    let near = |j: &usize| dist(&it.cycle[*j], &x) <= opts.match_tol * scale;
    let slow = match it.period {
        0 => (1..=opts.max_period).find(near),
        k => (1..k).filter(|j| k % j == 0).find(near),
    };
    if let Some(j) = slow {
        if let Some(a) = refined(model, t0, period, j, &x, opts)? {
            return Ok(a);
        }
    }
    if it.period == 0 {
        return Ok(Attractor { period: 0, impacts: it.impacts, sticking: it.sticking, state: x, cycle: Vec::new() });
    }
    let c = canonical(&it.cycle);
    Ok(Attractor { period: it.period, impacts: it.impacts, sticking: it.sticking, state: it.cycle[c].clone(), cycle: it.cycle })
}

/// A stable periodic attractor a transient may stop on ([`classify_near`]).
#[derive(Clone, Debug)]
pub struct Target {
    /// What a cell stopped on it is: the period, impacts and held phase
    /// of the orbit Newton converged to, its canonical point and cycle.
    pub attractor: Attractor,
    /// A fixed point of `P^p` on the orbit (Newton's), which the
    /// distances are taken to.
    pub point: Vec<f64>,
    /// The radius (∞-norm) within which `P^p` is its linearisation at
    /// `point` to a tenth of the distance ([`Target::new`]).
    pub radius: f64,
    dy: Dynamics,
    e: f64,
    omega: f64,
}

/// A target's radius tried first, relative to `max(1, ‖x‖∞)`.
const RADIUS_START: f64 = 0.05;

/// The most halvings of a target's radius from [`RADIUS_START`].
const RADIUS_HALVINGS: usize = 14;

impl Target {
    /// The target of the attractor `a` a cell of `model` (forced at
    /// `omega`) reached: Newton on `P^p` from its point (`p` its period,
    /// [`periodic_orbit`]) must converge within `match_tol · max(1,
    /// ‖x‖∞)` of it to an orbit whose multipliers are all inside the unit
    /// circle and whose period test gives `p` again. Its radius `r` is the
    /// largest of `0.05 · max(1, ‖x*‖∞) · 2^−m`, `m = 0, …, 14`, at which
    /// each start `x* ± r d` (`d` each coordinate direction and the two
    /// diagonals `(1, 1, …)`, `(1, −1, 1, …)`) is mapped by `P^p` to within
    /// `r/10` of its linearisation `x* ± r J d` (`J` the monodromy matrix):
    /// no impact appears, vanishes or moves its phase more than the
    /// Jacobian says within that distance, in those directions. `None`
    /// when Newton fails, the orbit is not stable or no radius passes (the
    /// attractor is not a target: its cells run their whole transient).
    /// Errors: only an interrupt.
    pub fn new(model: &Model, omega: f64, a: &Attractor, opts: &BasinOptions) -> Result<Option<Self>, OrbitError> {
        if !a.periodic() {
            return Ok(None);
        }
        let (period, p) = (TAU / omega, a.period);
        let horizon = p as f64 * period;
        let orbit = match periodic_orbit(model, 0.0, horizon, &a.state, &Newton::default()) {
            Ok(o) => o,
            Err(OrbitError::Interrupted) => return Err(OrbitError::Interrupted),
            Err(_) => return Ok(None),
        };
        let scale = norm(&orbit.x).max(1.0);
        if !(orbit.mu_max() < 1.0) || dist(&orbit.x, &a.state) > opts.match_tol * scale {
            return Ok(None);
        }
        let it = match iterate(model, 0.0, period, &orbit.x, p, opts.tol * scale) {
            Ok(it) if it.period == p => it,
            Err(OrbitError::Interrupted) => return Err(OrbitError::Interrupted),
            _ => return Ok(None),
        };
        let j = &orbit.monodromy;
        let dim = orbit.x.len();
        // The directions tried: each coordinate and the two diagonals
        // (1, 1, …, 1) and (1, −1, 1, …), both signs.
        let mut dirs: Vec<Vec<f64>> = (0..dim).map(|i| (0..dim).map(|k| f64::from(u8::from(k == i))).collect()).collect();
        dirs.push(vec![1.0; dim]);
        dirs.push((0..dim).map(|k| if k % 2 == 0 { 1.0 } else { -1.0 }).collect());
        let mut r = RADIUS_START * scale;
        let mut radius = None;
        'radius: for _ in 0..=RADIUS_HALVINGS {
            for d in &dirs {
                for s in [r, -r] {
                    let y: Vec<f64> = orbit.x.iter().zip(d).map(|(x, d)| x + s * d).collect();
                    let img = match model.flow(0.0, &y, horizon, false) {
                        Ok(img) => img.x,
                        Err(OrbitError::Interrupted) => return Err(OrbitError::Interrupted),
                        Err(_) => {
                            r *= 0.5;
                            continue 'radius;
                        }
                    };
                    let off = (0..dim).fold(0.0f64, |w, k| {
                        let jd: f64 = (0..dim).map(|i| j[(k, i)] * d[i]).sum();
                        w.max((img[k] - orbit.x[k] - s * jd).abs())
                    });
                    if !(off <= 0.1 * r) {
                        r *= 0.5;
                        continue 'radius;
                    }
                }
            }
            radius = Some(r);
            break;
        }
        let Some(radius) = radius else { return Ok(None) };
        let c = canonical(&it.cycle);
        let attractor = Attractor { period: p, impacts: it.impacts, sticking: it.sticking, state: it.cycle[c].clone(), cycle: it.cycle };
        Ok(Some(Self { attractor, point: orbit.x, radius, dy: model.dynamics().clone(), e: model.restitution(), omega }))
    }

    /// Whether `model` forced at `omega` is this target's map: the same
    /// matrices, loads, contacts, restitution and frequency, bit for bit
    /// (a grid whose keys move only the start; another key makes each
    /// cell's map its own).
    pub fn fits(&self, model: &Model, omega: f64) -> bool {
        let dy = model.dynamics();
        omega.to_bits() == self.omega.to_bits()
            && model.restitution().to_bits() == self.e.to_bits()
            && dy.mass == self.dy.mass
            && dy.stiffness == self.dy.stiffness
            && dy.damping == self.dy.damping
            && dy.load == self.dy.load
            && dy.contacts == self.dy.contacts
            && dy.forcing == self.dy.forcing
    }
}

/// A slow transient's attractor: Newton on `P^j` from `x` (the state after
/// the transient, at `t0`), taken when it converges within `match_tol` of
/// `x` to a stable orbit; the period test from that orbit's point then
/// gives the period (a divisor of `j`) and the impacts. `None` otherwise
/// (the plain period test stands).
fn refined(model: &Model, t0: f64, period: f64, j: usize, x: &[f64], opts: &BasinOptions) -> Result<Option<Attractor>, OrbitError> {
    let orbit = match periodic_orbit(model, t0, j as f64 * period, x, &Newton::default()) {
        Ok(o) => o,
        Err(OrbitError::Interrupted) => return Err(OrbitError::Interrupted),
        Err(_) => return Ok(None),
    };
    if !(orbit.mu_max() < 1.0) || dist(&orbit.x, x) > opts.match_tol * norm(x).max(1.0) {
        return Ok(None);
    }
    let it = iterate(model, t0, period, &orbit.x, j, opts.tol * norm(&orbit.x).max(1.0))?;
    if it.period == 0 {
        return Ok(None);
    }
    let c = canonical(&it.cycle);
    Ok(Some(Attractor { period: it.period, impacts: it.impacts, sticking: it.sticking, state: it.cycle[c].clone(), cycle: it.cycle }))
}

/// The map's iterates from `x` at `t0`, up to the first return within
/// `tol` (at most `max` forcing periods).
struct Iterates {
    /// `P^j(x)`, `j = 0, 1, …`: up to the one before the return (`period`
    /// of them), or all `max + 1` without one.
    cycle: Vec<Vec<f64>>,
    /// The smallest `k` with `P^k(x)` within `tol` of `x` (0: none).
    period: usize,
    /// Impacts over the periods flowed.
    impacts: usize,
    /// A held phase on the way.
    sticking: bool,
}

fn iterate(model: &Model, t0: f64, period: f64, x: &[f64], max: usize, tol: f64) -> Result<Iterates, OrbitError> {
    let mut it = Iterates { cycle: vec![x.to_vec()], period: 0, impacts: 0, sticking: false };
    let mut t = t0;
    for k in 1..=max {
        // From t = t0 + (k − 1)·T, whole forcing periods: the load's phase
        // is the section's.
        let img = model.flow(t, it.cycle.last().expect("the cycle starts with x"), period, false)?;
        t += period;
        it.impacts += img.events.iter().filter(|e| e.kind == EventKind::Impact && e.t > t - period).count();
        it.sticking |= img.events.iter().any(|e| matches!(e.kind, EventKind::Release | EventKind::Accumulation)) || !img.held.is_empty();
        if dist(&img.x, x) <= tol {
            it.period = k;
            return Ok(it);
        }
        it.cycle.push(img.x);
    }
    Ok(it)
}

/// Groups attractors, in the order they are given (module docs).
#[derive(Clone, Debug, Default)]
pub struct Grouper {
    reps: Vec<(usize, Vec<f64>)>,
    tol: f64,
}

impl Grouper {
    /// A grouper with the relative tolerance `match_tol`.
    pub fn new(match_tol: f64) -> Self {
        Self { reps: Vec::new(), tol: match_tol }
    }

    /// The id of the attractor of period `period` through the section
    /// point `state` (a new id if it matches none so far); `None` for a
    /// non-periodic one (`period` 0).
    pub fn id(&mut self, period: usize, state: &[f64]) -> Option<usize> {
        if period == 0 {
            return None;
        }
        let tol = self.tol * norm(state).max(1.0);
        if let Some(i) = self.reps.iter().position(|(p, s)| *p == period && dist(s, state) <= tol) {
            return Some(i);
        }
        self.reps.push((period, state.to_vec()));
        Some(self.reps.len() - 1)
    }

    /// Attractors seen so far.
    pub fn len(&self) -> usize {
        self.reps.len()
    }

    /// None seen yet.
    pub fn is_empty(&self) -> bool {
        self.reps.is_empty()
    }
}

/// A known periodic orbit: a row of a continuation's `branch.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct KnownOrbit {
    /// Its name in `basins.csv`: `branch<B>:<N>`, the `N`-th point (from 0)
    /// of branch `B`.
    pub label: String,
    /// Forcing periods per orbit.
    pub period: usize,
    /// Stable.
    pub stable: bool,
    /// The continuation parameter's value.
    pub param: f64,
    /// The state on the section (`q…` then `v…` of the state dofs).
    pub state: Vec<f64>,
}

/// The known orbits of a `branch.csv` text (`signorini continue`'s):
/// columns `param`, `period`, `stable`, `branch` and the state's `q<dof>`,
/// `v<dof>`. Errors name the option `orbits` and the line.
pub fn parse_branch(text: &str) -> Result<Vec<KnownOrbit>, OrbitError> {
    let bad = |m: String| OrbitError::Option { option: "orbits", message: m };
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).ok_or_else(|| bad(format!("no {name} column: a branch.csv of signorini continue is expected")));
    let (cp, cper, cst, cbr) = (col("param")?, col("period")?, col("stable")?, col("branch")?);
    let first_q = header.iter().position(|h| h.starts_with('q') && h[1..].parse::<usize>().is_ok()).ok_or_else(|| bad("no state columns (q<dof>, v<dof>)".into()))?;
    let mut out = Vec::new();
    let mut index: Vec<usize> = Vec::new();
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let c: Vec<&str> = line.split(',').collect();
        let num = |i: usize| -> Result<f64, OrbitError> {
            c.get(i).and_then(|s| s.parse::<f64>().ok()).ok_or_else(|| bad(format!("line {}: column {} is not a number", n + 2, header.get(i).unwrap_or(&"?"))))
        };
        let branch = num(cbr)? as usize;
        if index.len() <= branch {
            index.resize(branch + 1, 0);
        }
        let state = (first_q..header.len()).map(num).collect::<Result<Vec<_>, _>>()?;
        out.push(KnownOrbit { label: format!("branch{branch}:{}", index[branch]), period: num(cper)? as usize, stable: num(cst)? != 0.0, param: num(cp)?, state });
        index[branch] += 1;
    }
    if out.is_empty() {
        return Err(bad("no orbit in the file".into()));
    }
    Ok(out)
}

/// The known orbit an attractor is, if any: the same period (a known
/// orbit of period p also matches a cycle whose period divides p) and a
/// point of its cycle within `match_tol · max(1, ‖x‖∞)` of the orbit's
/// state; the nearest if several.
pub fn match_known<'a>(a: &Attractor, known: &'a [KnownOrbit], match_tol: f64) -> Option<&'a KnownOrbit> {
    if !a.periodic() {
        return None;
    }
    let mut best: Option<(f64, &KnownOrbit)> = None;
    for o in known.iter().filter(|o| o.period > 0 && o.period % a.period == 0 && o.state.len() == a.state.len()) {
        let d = a.cycle.iter().map(|p| dist(p, &o.state)).fold(f64::INFINITY, f64::min);
        if d <= match_tol * norm(&o.state).max(1.0) && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, o));
        }
    }
    best.map(|(_, o)| o)
}

/// The label of an attractor without a known orbit: `p<k>-i<n>` (period
/// and impacts per period), `-sticking` appended for a held phase;
/// `non-periodic`.
pub fn describe(a: &Attractor) -> String {
    if !a.periodic() {
        return "non-periodic".into();
    }
    format!("p{}-i{}{}", a.period, a.impacts, if a.sticking { "-sticking" } else { "" })
}

/// Seed cells a side of a grid ([`BasinScene::seeds`]): classified in full
/// first, their stable attractors the targets the other cells' transients
/// may stop on.
pub const SEEDS: usize = 8;

/// The most cells of one grid (5000 × 5000).
pub const MAX_CELLS: usize = 25_000_000;

/// A scene over a grid of initial states: the two keys' axes, the scene's
/// forcing frequency and the model (built once per cell: a key may be any
/// numeric one).
#[derive(Clone, Debug)]
pub struct BasinScene {
    family: SceneFamily,
    /// The displacement axis (`i`).
    pub x: Axis,
    /// The velocity axis (`j`).
    pub v: Axis,
}

impl BasinScene {
    /// The grid of `x` and `v` over the scene `doc` (scheme
    /// `event-driven(e)`, a periodic forcing). Checks both paths name
    /// numbers written in the scene, the counts and ranges, and the scene
    /// at the four corners of the grid.
    pub fn new(doc: toml::Table, x: Axis, v: Axis, limits: Limits) -> Result<Self, OrbitError> {
        for (option, a) in [("x", &x), ("v", &v)] {
            lookup_as(&doc, &a.path, option)?;
        }
        for (option, a) in [("grid", &x), ("grid", &v)] {
            if a.count == 0 || a.count > 100_000 {
                return Err(OrbitError::Option { option, message: format!("{} is not allowed: cells per axis, an integer in [1, 100000]", a.count) });
            }
        }
        for (option, a) in [("x-range", &x), ("v-range", &v)] {
            if !(a.from.is_finite() && a.to.is_finite()) {
                return Err(OrbitError::Option { option, message: format!("{} {} is not allowed: two finite numbers", a.from, a.to) });
            }
            // Equal ends would give `count` copies of one cell.
            if a.from == a.to && a.count > 1 {
                return Err(OrbitError::Option { option, message: format!("{} {} is not allowed: two different numbers (or a count of 1 on this axis in --grid)", a.from, a.to) });
            }
        }
        if x.count * v.count > MAX_CELLS {
            return Err(OrbitError::Option { option: "grid", message: format!("{} x {} is not allowed: at most {MAX_CELLS} cells (split a larger map into several grids)", x.count, v.count) });
        }
        if x.path == v.path {
            return Err(OrbitError::Option { option: "v", message: format!("{} is also --x: two different keys", v.path) });
        }
        let (family, _) = SceneFamily::with_limits(doc, &x.path, 1, limits)?;
        let s = Self { family, x, v };
        for (i, j) in [(0, 0), (s.x.count - 1, 0), (0, s.v.count - 1), (s.x.count - 1, s.v.count - 1)] {
            s.build(i, j).map_err(|e| match e {
                OrbitError::Scene(m) => {
                    // The axis to blame: `x` alone at this corner (`v` as the
                    // scene writes it) builds, or it does not.
                    let x_alone = s.family.build_with(&[("x", &s.x.path, s.x.value(i))]);
                    let option = if x_alone.is_ok() { "v-range" } else { "x-range" };
                    OrbitError::Option { option, message: format!("a corner of the grid is not a valid scene ({m}); allowed: --x-range and --v-range within the scene's ranges") }
                }
                other => other,
            })?;
        }
        Ok(s)
    }

    /// Cells: `nx · ny`, numbered `c = j·nx + i`.
    pub fn cells(&self) -> usize {
        self.x.count * self.v.count
    }

    /// `(i, j)` of cell `c`.
    pub fn ij(&self, c: usize) -> (usize, usize) {
        (c % self.x.count, c / self.x.count)
    }

    /// The scene at cell `(i, j)`, built.
    pub fn build(&self, i: usize, j: usize) -> Result<Built, OrbitError> {
        self.family.build_with(&[("x", &self.x.path, self.x.value(i)), ("v", &self.v.path, self.v.value(j))])
    }

    /// Cell `c`: its scene built and its start classified.
    pub fn classify(&self, c: usize, opts: &BasinOptions) -> Outcome {
        let (i, j) = self.ij(c);
        let built = match self.build(i, j) {
            Ok(b) => b,
            Err(e) => return Outcome::Failed(e.to_string()),
        };
        match classify(&built.model, built.omega, &built.start, opts) {
            Ok(a) => Outcome::Attractor(a),
            Err(e) => Outcome::Failed(e.to_string()),
        }
    }

    /// Cell `c` classified with `targets` ([`classify_near`]): its
    /// outcome and the forcing period its transient stopped at, if it did.
    pub fn classify_near(&self, c: usize, opts: &BasinOptions, targets: &[Target]) -> (Outcome, Option<usize>) {
        let (i, j) = self.ij(c);
        let built = match self.build(i, j) {
            Ok(b) => b,
            Err(e) => return (Outcome::Failed(e.to_string()), None),
        };
        match classify_near(&built.model, built.omega, &built.start, opts, targets) {
            Ok((a, k)) => (Outcome::Attractor(a), k),
            Err(e) => (Outcome::Failed(e.to_string()), None),
        }
    }

    /// The seed cells of the grid ([`SEEDS`] a side, fewer on a shorter
    /// axis): `i = ⌊(2a + 1)·nx / 2s⌋`, `a = 0, …, s − 1`, and the same in
    /// `j`, in cell order. Every shard of a grid has the same seeds.
    pub fn seeds(&self) -> Vec<usize> {
        let along = |n: usize| -> Vec<usize> {
            let s = SEEDS.min(n);
            let mut v: Vec<usize> = (0..s).map(|a| (2 * a + 1) * n / (2 * s)).collect();
            v.dedup();
            v
        };
        let (xs, vs) = (along(self.x.count), along(self.v.count));
        vs.iter().flat_map(|&j| xs.iter().map(move |&i| j * self.x.count + i)).collect()
    }

    /// The targets of the attractors the cells `cells` reached
    /// (`outcomes`, classified in full): one per distinct stable periodic
    /// attractor (grouped as [`Grouper`] does, in the cells' order), each
    /// made on its first cell's model ([`Target::new`]). Errors: only an
    /// interrupt.
    pub fn targets(&self, cells: &[usize], outcomes: &[Outcome], opts: &BasinOptions) -> Result<Vec<Target>, OrbitError> {
        let mut grouper = Grouper::new(opts.match_tol);
        let mut out = Vec::new();
        for (&c, o) in cells.iter().zip(outcomes) {
            let Outcome::Attractor(a) = o else { continue };
            let seen = grouper.len();
            if grouper.id(a.period, &a.state).is_none_or(|k| k < seen) {
                continue;
            }
            let (i, j) = self.ij(c);
            let Ok(built) = self.build(i, j) else { continue };
            if let Some(t) = Target::new(&built.model, built.omega, a, opts)? {
                out.push(t);
            }
        }
        Ok(out)
    }

    /// The targets of the known orbits (a continuation's `branch.csv`,
    /// [`parse_branch`]) at this grid's map, beside `have` (the seeds'):
    /// each orbit marked stable, of a period `p <= max_period` and with a
    /// state of the model's size, whose residual `‖P^p(x) − x‖∞` at the map
    /// of cell 0 is within `match_tol · max(1, ‖x‖∞)` (a point at the
    /// scene's value of the continued parameter; a point of another value
    /// is another map's orbit), taken in the order of that residual (the
    /// file's order among equals), and not within `match_tol · max(1,
    /// ‖x‖∞)` of a point of the cycle of a target of its period already
    /// made, becomes a [`Target`] as a seed's attractor does
    /// ([`Target::new`]: Newton at this map within `match_tol` of it, its
    /// multipliers inside the unit circle, the same radius). An unstable
    /// orbit is never a target (the file's `stable` column, and Newton's
    /// multipliers at this map). Errors: only an interrupt.
    pub fn known_targets(&self, known: &[KnownOrbit], have: &[Target], opts: &BasinOptions) -> Result<Vec<Target>, OrbitError> {
        let Ok(built) = self.build(0, 0) else { return Ok(Vec::new()) };
        let (model, omega) = (&built.model, built.omega);
        let dim = 2 * model.state_dofs().len();
        let period = TAU / omega;
        let mut near: Vec<(f64, &KnownOrbit)> = Vec::new();
        for o in known.iter().filter(|o| o.stable && o.period > 0 && o.period <= opts.max_period && o.state.len() == dim) {
            let residual = match model.flow(0.0, &o.state, o.period as f64 * period, false) {
                Ok(img) => dist(&img.x, &o.state),
                Err(OrbitError::Interrupted) => return Err(OrbitError::Interrupted),
                Err(_) => continue,
            };
            if residual <= opts.match_tol * norm(&o.state).max(1.0) {
                near.push((residual, o));
            }
        }
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out: Vec<Target> = Vec::new();
        for (_, o) in near {
            let tol = opts.match_tol * norm(&o.state).max(1.0);
            if have.iter().chain(&out).any(|t| t.attractor.period == o.period && t.attractor.cycle.iter().any(|c| dist(c, &o.state) <= tol)) {
                continue;
            }
            let a = Attractor { period: o.period, impacts: 0, sticking: false, state: o.state.clone(), cycle: Vec::new() };
            if let Some(t) = Target::new(model, omega, &a, opts)? {
                out.push(t);
            }
        }
        Ok(out)
    }

    /// The state dofs of the model (the columns of a state).
    pub fn state_dofs(&self) -> Result<Vec<usize>, OrbitError> {
        Ok(self.build(0, 0)?.model.state_dofs().to_vec())
    }
}
