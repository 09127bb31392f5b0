//! Periodic orbits by shooting on the exact map: Newton on `P(x) − x = 0`
//! (forced: the stroboscopic map over `p` forcing periods) or on
//! `(P_T(x) − x, phase, energy) = 0` with the period `T` unknown
//! (autonomous), and the Floquet multipliers from the map's Jacobian.

use crate::map::{Image, Model};
use crate::OrbitError;
use faer::linalg::solvers::{Solve, SolveLstsq};
use faer::{c64, Mat};
use signorini_schemes::events::{EventKind, EventRecord};

/// Newton's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Newton {
    /// Converged when `‖P(x) − x‖∞ <= tol · max(‖x‖∞, scale)`, or (in
    /// [`periodic_orbit`]) when the residual has stopped falling at the
    /// map's round-off, `64 ε ‖P'‖∞ max(‖x‖∞, scale)` (an ill-conditioned
    /// map, as past a grazing): the orbit's `residual` says what was
    /// reached.
    pub tol: f64,
    /// The state's scale (a length or speed below which the relative test
    /// would ask for more than round-off).
    pub scale: f64,
    /// Most iterations.
    pub max_iter: usize,
    /// Give up when the residual has not halved in this many iterations
    /// while still above `1e4 · tol` of the state (relative, as `tol`):
    /// Newton converging, however slowly from afar (a square-root side of
    /// a grazing), halves it every few; one wandering on a map that has
    /// no fixed point near does not (the paper's beam past its grazing).
    /// 0: never (every iteration up to `max_iter` is taken). Only
    /// [`periodic_orbit`] (and the continuation's searches at a grazing)
    /// read it; [`autonomous_orbit`] takes every iteration.
    pub stall: usize,
}

impl Default for Newton {
    fn default() -> Self {
        Self { tol: 1e-12, scale: 1e-300, max_iter: 40, stall: 0 }
    }
}

/// The stall test of [`Newton::stall`]: the residual at the last halving
/// and the iterations since.
struct Stall {
    reference: f64,
    since: usize,
}

impl Stall {
    fn new(res: f64) -> Self {
        Self { reference: res, since: 0 }
    }

    /// After an iteration to the residual `res`: whether Newton has stalled
    /// far from an orbit (`far`: the residual's level above which it counts).
    fn stalled(&mut self, newton: &Newton, res: f64, far: f64) -> bool {
        if res < 0.5 * self.reference {
            (self.reference, self.since) = (res, 0);
            return false;
        }
        self.since += 1;
        newton.stall > 0 && self.since >= newton.stall && self.reference.min(res) > far
    }
}

/// A periodic orbit: its state on the section, its period, the events of
/// one period, the monodromy matrix and the Floquet multipliers.
#[derive(Clone, Debug)]
pub struct Orbit {
    /// The state `(q_s, v_s)` on the section (at the section's time `t0`).
    pub x: Vec<f64>,
    /// The section's time.
    pub t0: f64,
    /// The period (s).
    pub period: f64,
    /// The events of one period.
    pub events: Vec<EventRecord>,
    /// The monodromy matrix `∂P/∂x`.
    pub monodromy: Mat<f64>,
    /// Its eigenvalues, by decreasing modulus.
    pub multipliers: Vec<c64>,
    /// `‖P(x) − x‖∞` at the solution.
    pub residual: f64,
    /// Newton's iterations.
    pub iterations: usize,
}

impl Orbit {
    /// The largest multiplier's modulus (of an autonomous orbit, the
    /// trivial multipliers at +1 of the flow's direction and, conservative,
    /// the energy's are left out).
    pub fn mu_max(&self) -> f64 {
        self.multipliers.first().map_or(0.0, |m| m.norm())
    }

    /// Impacts in one period.
    pub fn impacts(&self) -> usize {
        self.events.iter().filter(|e| e.kind == EventKind::Impact && e.velocity_before != 0.0).count()
    }

    /// Held phases that start in one period (impacts that leave a contact
    /// held, accumulations): the orbit sticks.
    pub fn releases(&self) -> usize {
        self.events.iter().filter(|e| e.kind == EventKind::Release).count()
    }

    /// The fastest impact of the period: its speed `|v⁻|` and its time
    /// from the section in periods (`[0, 1)`); `None` without an impact.
    pub fn fastest_impact(&self) -> Option<(f64, f64)> {
        self.events.iter().filter(|e| e.kind == EventKind::Impact).map(|e| (e.velocity_before.abs(), ((e.t - self.t0) / self.period).rem_euclid(1.0))).max_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// The slowest impact's speed (grazing: it goes to 0).
    pub fn slowest_impact(&self) -> Option<f64> {
        self.events.iter().filter(|e| e.kind == EventKind::Impact && e.velocity_before != 0.0).map(|e| e.velocity_before.abs()).min_by(f64::total_cmp)
    }
}

fn inf_norm(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, v| a.max(v.abs()))
}

/// The eigenvalues of `m` by decreasing modulus.
pub fn eigenvalues(m: &Mat<f64>) -> Result<Vec<c64>, OrbitError> {
    if m.nrows() == 0 {
        return Ok(Vec::new());
    }
    let mut ev = m.eigenvalues().map_err(|_| OrbitError::Model("the monodromy matrix's eigenvalues did not converge".into()))?;
    ev.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    Ok(ev)
}

/// A fixed point of the map over `period` from `t0` (a forced scene's
/// stroboscopic map: `period` = p forcing periods), by Newton from `guess`.
pub fn periodic_orbit(model: &Model, t0: f64, period: f64, guess: &[f64], newton: &Newton) -> Result<Orbit, OrbitError> {
    let mut least = f64::INFINITY;
    newton_orbit(model, t0, period, guess, newton, None, true, &mut least)
}

/// [`periodic_orbit`] converged only at the tolerance, never at the map's
/// round-off: the continuation's own searches (a period-doubled orbit, a
/// rejoin, the orbit beside a grazing), whose branches were traced with
/// that rule. With the round-off rule the period-3 loop of the oscillator
/// between −1 and 0.5 (`tests/it/isola.rs`) stopped at its grazing at Ω =
/// 3.4277, the corrector failing, where it closed before.
pub(crate) fn periodic_orbit_strict(model: &Model, t0: f64, period: f64, guess: &[f64], newton: &Newton) -> Result<Orbit, OrbitError> {
    let mut least = f64::INFINITY;
    newton_orbit(model, t0, period, guess, newton, None, false, &mut least)
}

/// [`periodic_orbit`] for an orbit with `impacts` impacts per period, from
/// a guess that has them: each Newton step is halved (down to 2⁻³⁰ of it)
/// until the trial keeps that many impacts. Just past a grazing the map
/// has a square-root singularity (a new impact's speed grows as the square
/// root of how far the flight reaches past the stop, and the orbit reaches
/// past it by the square of its distance to the grazing): a full step from
/// a guess that reaches too far lands on the side without the impact, from
/// where plain Newton steps back — it cycles. A halved step takes about
/// the geometric mean of the guess's reach and the orbit's, so that a few
/// steps bring the iterate within reach of full ones. `least` as
/// [`periodic_orbit_least`] says.
pub(crate) fn periodic_orbit_keeping(model: &Model, t0: f64, period: f64, guess: &[f64], newton: &Newton, impacts: usize, least: &mut f64) -> Result<Orbit, OrbitError> {
    *least = f64::INFINITY;
    newton_orbit(model, t0, period, guess, newton, Some(impacts), false, least)
}

/// [`periodic_orbit`] that also says how near an orbit Newton came when
/// it fails: `least` takes the smallest residual over its iterates, each
/// relative to its own state as [`Newton::tol`] is (`‖P(x) − x‖∞ /
/// max(‖x‖∞, scale)`; infinite when the start could not be mapped).
pub(crate) fn periodic_orbit_least(model: &Model, t0: f64, period: f64, guess: &[f64], newton: &Newton, least: &mut f64) -> Result<Orbit, OrbitError> {
    *least = f64::INFINITY;
    newton_orbit(model, t0, period, guess, newton, None, false, least)
}

/// Impacts at a nonzero speed among `events` (as [`Orbit::impacts`] counts them).
pub(crate) fn count_impacts(events: &[EventRecord]) -> usize {
    events.iter().filter(|e| e.kind == EventKind::Impact && e.velocity_before != 0.0).count()
}

/// The map's round-off, in units of `‖P'‖∞ ‖x‖∞`: an orbit whose map is
/// ill-conditioned (a slow impact: a multiplier near the inverse of its
/// speed) cannot be computed to a residual below about `‖P'‖ ε ‖x‖` (the
/// state's own rounding, carried through the map), whatever the
/// tolerance. Newton stops there, converged, when its last step did not
/// halve the residual and the residual is within `ROUNDOFF ‖P'‖∞ ‖x‖∞`:
/// 64 ε, a few dozen roundings over a period's events. On the oscillator
/// between symmetric stops past the grazing at Ω = 1.0383 (the mirror
/// 3-impact orbit, `tests/it/mirror.rs`) Newton from the orbit itself
/// stalled at 2.4e-10, 1.5e-11 and 7.6e-13 at 1e-5, 1e-4 and 1e-3 of the
/// range past it, above the tolerance 1e-12 of the state (0.43) and
/// within this level, and failed. Where `‖P'‖∞ ε 64 < tol` (`‖P'‖∞` below
/// about 70 at the default 1e-12) the rule is never looser than the
/// tolerance; where the residual still halves it is not used.
pub(crate) const ROUNDOFF: f64 = 64.0 * f64::EPSILON;

/// Newton keeping a number of impacts halves a step until the trial keeps
/// them, down to this fraction of the step. The current point keeps them,
/// so a trial that far along the step that still does not sits at a
/// grazing boundary of the current point: halving further (each a run of
/// the map) is the cost of a search that fails, not a way to succeed.
const KEEP_STEP_FLOOR: f64 = 1.0 / (1u64 << 30) as f64;

/// Newton on `P(x) − x` (`keep`: keeping that many impacts); `roundoff`:
/// also converged at the map's round-off ([`ROUNDOFF`]).
#[allow(clippy::too_many_arguments)]
fn newton_orbit(model: &Model, t0: f64, period: f64, guess: &[f64], newton: &Newton, keep: Option<usize>, roundoff: bool, least: &mut f64) -> Result<Orbit, OrbitError> {
    let mut x = guess.to_vec();
    let n = x.len();
    let tol = |x: &[f64]| newton.tol * inf_norm(x).max(newton.scale);
    let relative = |res: f64, x: &[f64]| res / inf_norm(x).max(newton.scale);
    let mut img: Image = model.flow(t0, &x, period, true)?;
    let mut g: Vec<f64> = img.x.iter().zip(&x).map(|(a, b)| a - b).collect();
    let mut res = inf_norm(&g);
    *least = least.min(relative(res, &x));
    if let Some(k) = keep {
        if count_impacts(&img.events) != k {
            return Err(OrbitError::NoConvergence { residual: res, iterations: 0, why: format!("the start has {} impacts per period, not {k}", count_impacts(&img.events)) });
        }
    }
    let mut stall = Stall::new(res);
    // The residual before the last step (a step that did not halve it, at
    // the map's round-off, ends Newton: [`ROUNDOFF`]).
    let mut before = f64::INFINITY;
    for it in 0..=newton.max_iter {
        // `ROUNDOFF ‖P'‖∞ max(‖x‖∞, scale)`, asked only when the residual
        // did not halve.
        let at_roundoff = || {
            let jn = img.jacobian.as_ref().map_or(0.0, |j| (0..n).map(|r| (0..n).map(|c| j[(r, c)].abs()).sum::<f64>()).fold(0.0, f64::max));
            res <= ROUNDOFF * jn * inf_norm(&x).max(newton.scale)
        };
        if res <= tol(&x) || (roundoff && res > 0.5 * before && at_roundoff()) {
            let monodromy = img.jacobian.take().expect("asked for");
            let multipliers = eigenvalues(&monodromy)?;
            return Ok(Orbit { x, t0, period, events: img.events, monodromy, multipliers, residual: res, iterations: it });
        }
        if it > 0 && stall.stalled(newton, res, 1e4 * tol(&x)) {
            return Err(OrbitError::NoConvergence { residual: res, iterations: it, why: format!("stalled: the residual did not halve in {} iterations", newton.stall) });
        }
        if it == newton.max_iter {
            break;
        }
        before = res;
        let j = img.jacobian.as_ref().expect("asked for");
        let a = Mat::from_fn(n, n, |r, c| j[(r, c)] - if r == c { 1.0 } else { 0.0 });
        let rhs = Mat::from_fn(n, 1, |r, _| -g[r]);
        let step = a.partial_piv_lu().solve(&rhs);
        if (0..n).any(|r| !step[(r, 0)].is_finite()) {
            return Err(OrbitError::NoConvergence { residual: res, iterations: it, why: "the Newton matrix P' − I is singular (a multiplier at +1: a fold or a family of orbits)".into() });
        }
        // Backtracking: a step that does not lower the residual is halved
        // (the map is only piecewise smooth).
        let mut lambda = 1.0;
        loop {
            let trial: Vec<f64> = (0..n).map(|r| x[r] + lambda * step[(r, 0)]).collect();
            if let Some(k) = keep {
                // Halved until the trial keeps its impacts (the residual
                // may grow: the square-root side is reached from afar); a
                // trial's run stops at its (k + 1)-th impact.
                match model.flow_within(t0, &trial, period, true, k) {
                    Ok(Some(ti)) if count_impacts(&ti.events) == k => {
                        let tg: Vec<f64> = ti.x.iter().zip(&trial).map(|(a, b)| a - b).collect();
                        (res, g, img, x) = (inf_norm(&tg), tg, ti, trial);
                        *least = least.min(relative(res, &x));
                        break;
                    }
                    _ if lambda < KEEP_STEP_FLOOR => {
                        return Err(OrbitError::NoConvergence { residual: res, iterations: it, why: format!("no step keeps the {k} impacts per period") });
                    }
                    _ => {}
                }
                lambda *= 0.5;
                continue;
            }
            let attempt = model.flow(t0, &trial, period, true);
            if let Ok(ti) = attempt {
                let tg: Vec<f64> = ti.x.iter().zip(&trial).map(|(a, b)| a - b).collect();
                let tr = inf_norm(&tg);
                if tr < res || lambda < 1.0 / 64.0 {
                    (x, img, g, res) = (trial, ti, tg, tr);
                    *least = least.min(relative(res, &x));
                    break;
                }
            } else if lambda < 1.0 / 64.0 {
                attempt?;
            }
            lambda *= 0.5;
        }
    }
    Err(OrbitError::NoConvergence { residual: res, iterations: newton.max_iter, why: "no periodic orbit near the start (Newton's residual did not fall below the tolerance)".into() })
}

/// The longest trial period of [`autonomous_orbit`], in multiples of the
/// guess: a Newton step that goes beyond is halved (a lumped bar above its
/// contact threshold stepped from the guess 2.09 to 1.9e11, whose flow,
/// an event every ~80 time units, did not end).
const PERIOD_REACH: f64 = 4.0;

/// A periodic orbit of an autonomous model at the energy `energy`, its
/// period unknown: Gauss–Newton on `P_T(x) − x = 0`, the phase condition
/// `f(x_ref)ᵀ (x − x_ref) = 0` (`x_ref` = `guess`) and `E(x) = energy`
/// (`2n + 2` equations in `2n + 1` unknowns, consistent at a solution: the
/// conserved energy makes `P' − I` singular along the family).
pub fn autonomous_orbit(model: &Model, guess: &[f64], period: f64, energy: f64, newton: &Newton) -> Result<Orbit, OrbitError> {
    let n = guess.len();
    if n != model.dim() {
        return Err(OrbitError::Size { given: n, expected: model.dim() });
    }
    if !(energy.is_finite() && energy > 0.0) {
        return Err(OrbitError::Option { option: "energy", message: format!("{energy} is not allowed: finite and > 0") });
    }
    if !(period.is_finite() && period > 0.0) {
        return Err(OrbitError::Option { option: "period", message: format!("{period} is not allowed: a guess of the period, finite and > 0") });
    }
    let x_ref = guess.to_vec();
    // The phase condition's normal, of unit length; the energy's row
    // weighed so that a relative error of the energy counts as half that
    // of the state (E is quadratic in it).
    let f0 = {
        let f = field_at_start(model, &x_ref, period)?;
        let norm = f.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !norm.is_finite() {
            return Err(OrbitError::Model("the vector field at the start is not finite".into()));
        }
        if norm == 0.0 {
            return Err(OrbitError::NoConvergence { residual: f64::NAN, iterations: 0, why: "the start is an equilibrium (no flow to fix a phase on)".into() });
        }
        f.into_iter().map(|v| v / norm).collect::<Vec<f64>>()
    };
    let w_e = inf_norm(&x_ref).max(newton.scale) / (2.0 * energy);
    // The residuals at (x, t): the image, the energy's gradient, the rows.
    let eval = |x: &[f64], t: f64| -> Result<(Image, Vec<f64>, Vec<f64>), OrbitError> {
        let img = model.flow(0.0, x, t, true)?;
        let (e, ge) = model.energy(0.0, x)?;
        let mut rows: Vec<f64> = img.x.iter().zip(x).map(|(a, b)| a - b).collect();
        rows.push((0..n).map(|i| f0[i] * (x[i] - x_ref[i])).sum());
        rows.push(w_e * (e - energy));
        Ok((img, ge, rows))
    };
    let merit = |rows: &[f64]| rows.iter().map(|r| r * r).sum::<f64>();
    let (mut x, mut t) = (guess.to_vec(), period);
    let (mut img, mut ge, mut rows) = eval(&x, t)?;
    for it in 0..=newton.max_iter {
        let res = inf_norm(&rows[..n]);
        let tol = newton.tol * inf_norm(&x).max(newton.scale);
        if res <= tol && rows[n + 1].abs() <= tol {
            let monodromy = img.jacobian.take().expect("asked for");
            let mut multipliers = eigenvalues(&monodromy)?;
            // The two trivial multipliers (flow direction, energy) at +1.
            for _ in 0..2 {
                if let Some(i) = multipliers.iter().enumerate().min_by(|a, b| (a.1 - c64::new(1.0, 0.0)).norm().total_cmp(&(b.1 - c64::new(1.0, 0.0)).norm())).map(|p| p.0) {
                    multipliers.remove(i);
                }
            }
            return Ok(Orbit { x, t0: 0.0, period: t, events: img.events, monodromy, multipliers, residual: res, iterations: it });
        }
        if it == newton.max_iter {
            break;
        }
        let j = img.jacobian.as_ref().expect("asked for");
        let a = Mat::from_fn(n + 2, n + 1, |r, c| match (r, c) {
            (r, c) if r < n && c < n => j[(r, c)] - if r == c { 1.0 } else { 0.0 },
            (r, _) if r < n => img.field[r],
            (r, c) if r == n && c < n => f0[c],
            (r, c) if r == n + 1 && c < n => w_e * ge[c],
            _ => 0.0,
        });
        let mut step = Mat::from_fn(n + 2, 1, |r, _| -rows[r]);
        a.qr().solve_lstsq_in_place(step.as_mut());
        if (0..=n).any(|r| !step[(r, 0)].is_finite()) {
            return Err(OrbitError::NoConvergence { residual: res, iterations: it, why: "the shooting matrix is singular".into() });
        }
        // Backtracking on the residuals' squares (the map is only piecewise
        // smooth): a step that does not lower them is halved.
        let m0 = merit(&rows);
        let mut lambda = 1.0;
        loop {
            let tx: Vec<f64> = (0..n).map(|i| x[i] + lambda * step[(i, 0)]).collect();
            let tt = t + lambda * step[(n, 0)];
            // A trial period beyond `PERIOD_REACH` times the guess is not
            // run: the flow's cost grows with it (docs/orbits.md).
            let attempt = if tt > 0.0 && tt <= PERIOD_REACH * period { eval(&tx, tt).ok() } else { None };
            match attempt {
                Some((ti, tg, tr)) if merit(&tr) < m0 || lambda < 1.0 / 256.0 => {
                    (x, t, img, ge, rows) = (tx, tt, ti, tg, tr);
                    break;
                }
                None if lambda < 1.0 / 256.0 => {
                    return Err(OrbitError::NoConvergence {
                        residual: res,
                        iterations: it,
                        why: format!("no admissible step (the period went to {tt}, allowed: > 0 and at most {PERIOD_REACH} times the guess {period}; or the flow has no derivative there)"),
                    });
                }
                _ => lambda *= 0.5,
            }
        }
    }
    Err(OrbitError::NoConvergence { residual: inf_norm(&rows[..n]), iterations: newton.max_iter, why: "no periodic orbit at this energy near the start".into() })
}

/// The vector field at the start state (the flow over a vanishing time).
fn field_at_start(model: &Model, x: &[f64], period: f64) -> Result<Vec<f64>, OrbitError> {
    let img = model.flow(0.0, x, period * 1e-12, false)?;
    Ok(img.field)
}
