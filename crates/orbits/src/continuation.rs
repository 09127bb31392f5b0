//! Pseudo-arclength continuation of periodic orbits in a parameter, with
//! the bifurcations located on the way (docs/theory.md §12.3).
//!
//! Unknowns `y = (x, λ)`, scaled (`x/X`, `λ/Λ`) so that the arclength
//! weighs state and parameter alike. `G(x, λ) = P_λ(x) − x` with
//! `G_x = P' − I` (the variational Jacobian) and `G_λ` by central
//! differences of the map. Predictor along the tangent `t` (the null vector
//! of `[G_x G_λ]`, oriented by the previous one), Newton corrector on the
//! hyperplane `tᵀ (y − y_pred) = 0`; a step that fails is halved (a trial
//! predicted past a grazing, with more impacts than the orbit it starts
//! from, is given up before its first Newton step). A trial of a short
//! step (at most 1e-3) whose orbit has another number of impacts or held
//! phases is a corner, the change located on the arclength, only when the
//! bisection's last two points meet (no further apart than the step);
//! otherwise it fell onto another arc: the other arc of a grazing where
//! the branch turns back (`turned_back`), or the step is halved. Between
//! two points:
//!
//! - **fold**: the tangent's `λ` component changes sign and so does
//!   `det(P' − I)` (a multiplier passes through +1 at the turning point);
//! - **branch point**: a multiplier reaches +1 without a fold — `det(P' −
//!   I)` changes sign where the branch goes on in `λ` (the symmetric orbit
//!   of a symmetric structure at its symmetry-breaking pitchfork), or the
//!   branch turns in `λ` where it does not (the asymmetric orbit meeting
//!   the symmetric one there, the branch going on onto its mirror image,
//!   where it ends: [`Returns`]), named only where a multiplier is at +1
//!   there (a turn at a corner is no branch point); or, on a symmetric
//!   structure, the branch passes from asymmetric orbits onto symmetric
//!   ones with no test changing sign, named where the asymmetry reaches 0
//!   ([`pitchfork`]); [`crossing_branch`] follows the other branch;
//! - **period doubling**: a real multiplier passes through −1;
//! - **Neimark–Sacker**: a complex pair leaves or enters the unit circle;
//! - **grazing**: the number of impacts per period changes (an impact at
//!   zero speed separates the two) — an impact vanishing, a free orbit's
//!   first, or a further one where a flight between two impacts reaches a
//!   stop (its interior extremum: [`Model::flight_margin`]), after which
//!   the branch goes on past the grazing or turns back from it with the
//!   further impact, wherever that orbit is;
//! - **sticking**: the number of held phases per period changes.
//!
//! Each is located by bisection on the arclength (the test function's sign,
//! or the event count), every trial point corrected onto the branch.

use crate::map::{Extremum, Model, Stencil};
use crate::shoot::{count_impacts, eigenvalues, periodic_orbit, periodic_orbit_keeping, periodic_orbit_least, periodic_orbit_strict, Newton, Orbit};
use crate::OrbitError;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use signorini_schemes::events::EventKind;

/// A family of models in one parameter, with the period of its map.
pub trait Family {
    /// The model at the parameter value `param`.
    fn model(&self, param: f64) -> Result<Model, OrbitError>;
    /// The map's horizon at `param` (p forcing periods).
    fn period(&self, param: f64) -> Result<f64, OrbitError>;
    /// Both at once (a family that builds its model once per value
    /// overrides it).
    fn model_and_period(&self, param: f64) -> Result<(Model, f64), OrbitError> {
        Ok((self.model(param)?, self.period(param)?))
    }
    /// The model and horizon at `param`, and what marks an orbit there for
    /// the front ends ([`Mark`], from the model and the orbit's state): a
    /// family of scenes marks each point with the scene it built for the
    /// point's model, so that no one builds it again to label the point.
    /// The default marks nothing.
    fn model_period_marker(&self, param: f64) -> Result<(Model, f64, Option<Marker>), OrbitError> {
        let (model, period) = self.model_and_period(param)?;
        Ok((model, period, None))
    }
    /// The forcing periods `p` the map's horizon spans: an orbit's state
    /// after `k` forcing periods (`k < p`) is the section state of the same
    /// orbit, shifted in phase, a fixed point of the map too. The default
    /// is 1 (no shifted copies).
    fn periods(&self) -> usize {
        1
    }
}

/// What a branch point (or a bifurcation located at one) of a family of
/// scenes carries for the front ends: the scene's forcing frequency Ω and
/// its tip's displacement on the section (the quantities `branch.csv`'s
/// `impact_phase` and `displacement` are made of).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mark {
    /// The forcing frequency Ω.
    pub omega: f64,
    /// The tip's displacement on the section.
    pub tip: f64,
}

/// Marks the orbit through a state of the model it is given
/// ([`Family::model_period_marker`]); `None` when it cannot.
pub type Marker = Box<dyn Fn(&Model, &[f64]) -> Option<Mark>>;

/// What a continuation is asked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContinuationOptions {
    /// The start of the parameter range.
    pub from: f64,
    /// Its end.
    pub to: f64,
    /// Most points.
    pub max_points: usize,
    /// The first step (scaled arclength: the state over the first orbit's
    /// size, the parameter over [`ContinuationOptions::param_scale`]).
    pub step: f64,
    /// The smallest step before the branch is given up.
    pub min_step: f64,
    /// The largest step.
    pub max_step: f64,
    /// Newton's settings.
    pub newton: Newton,
    /// The parameter's scale Λ: the scaled arclength divides the parameter
    /// by it, and the steps, the bisections locating a bifurcation and the
    /// searches' offsets at a grazing are fractions of it. `None`: the
    /// range `|to − from|`. Given, runs from one start to different ends
    /// take the same steps and list the same bifurcations where their
    /// ranges overlap (the range then only says where to stop, as the
    /// interval does for AUTO's and COCO's step bounds).
    pub scale: Option<f64>,
}

impl ContinuationOptions {
    /// From `from` to `to` with the defaults: at most 400 points, steps
    /// (scaled arclength) from 1e-7 to 0.25, the first 0.02, a step
    /// accepted when the tangent turns by less than 25°, Newton to 1e-11.
    pub fn new(from: f64, to: f64) -> Self {
        Self { from, to, max_points: 400, step: 0.02, min_step: 1e-7, max_step: 0.25, newton: Newton { tol: 1e-11, ..Newton::default() }, scale: None }
    }

    /// The parameter's scale Λ ([`ContinuationOptions::scale`]): the one
    /// given, else the range `|to − from|`.
    pub fn param_scale(&self) -> f64 {
        self.scale.unwrap_or((self.to - self.from).abs())
    }

    /// What the searches' offsets are said to be fractions of.
    fn scale_name(&self) -> &'static str {
        if self.scale.is_some() {
            "the parameter's scale"
        } else {
            "the range"
        }
    }

    fn validate(&self) -> Result<(), OrbitError> {
        let opt = |option, message: String| Err(OrbitError::Option { option, message });
        if !(self.from.is_finite() && self.to.is_finite()) || self.from == self.to {
            return opt("from/to", format!("{} to {} is not allowed: two finite, different values", self.from, self.to));
        }
        if let Some(s) = self.scale {
            if !(s.is_finite() && s > 0.0) {
                return opt("param-scale", format!("{s} is not allowed: finite, > 0"));
            }
        }
        if self.max_points < 2 {
            return opt("max-points", format!("{} is not allowed: >= 2", self.max_points));
        }
        if !(self.min_step > 0.0 && self.min_step <= self.step && self.step <= self.max_step && self.max_step.is_finite()) {
            return opt("step", format!("min {} <= step {} <= max {} is not allowed: 0 < min <= step <= max, finite", self.min_step, self.step, self.max_step));
        }
        Ok(())
    }
}

/// One point of a branch.
#[derive(Clone, Debug)]
pub struct BranchPoint {
    /// The parameter.
    pub param: f64,
    /// The orbit.
    pub orbit: Orbit,
    /// Its [`Mark`] (a family of scenes).
    pub mark: Option<Mark>,
}

impl BranchPoint {
    /// Linearly stable: every multiplier inside the unit circle (with a
    /// margin of 1e-9 for round-off).
    pub fn stable(&self) -> bool {
        self.orbit.mu_max() < 1.0 - 1e-9
    }
}

/// A bifurcation's kind (`bifurcations.csv`'s `kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BifurcationKind {
    /// A turning point (a multiplier through +1).
    Fold,
    /// A multiplier at +1 that is no turning point: a branch point where
    /// another branch of orbits crosses this one (the symmetry-breaking
    /// pitchfork of a symmetric orbit, where its asymmetric mirror pair
    /// is born; seen from the pair, the point where the branch turns in
    /// the parameter onto the mirror image, its multiplier touching +1
    /// without passing it).
    BranchPoint,
    /// A real multiplier through −1.
    PeriodDoubling,
    /// A complex pair through the unit circle.
    NeimarkSacker,
    /// The number of impacts per period changes.
    Grazing,
    /// The number of held phases per period changes.
    Sticking,
}

impl BifurcationKind {
    /// The name in `bifurcations.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Fold => "fold",
            Self::BranchPoint => "branch-point",
            Self::PeriodDoubling => "period-doubling",
            Self::NeimarkSacker => "neimark-sacker",
            Self::Grazing => "grazing",
            Self::Sticking => "sticking",
        }
    }
}

/// A located bifurcation.
#[derive(Clone, Debug)]
pub struct Bifurcation {
    /// Where.
    pub param: f64,
    /// What.
    pub kind: BifurcationKind,
    /// The critical multiplier there (fold and branch point: nearest +1;
    /// period doubling: nearest −1; Neimark–Sacker: the pair's, upper half
    /// plane; grazing and sticking: the largest).
    pub mu: c64,
    /// Impacts per period on the two sides (the branch's direction).
    pub impacts: (usize, usize),
    /// Held phases per period on the two sides.
    pub releases: (usize, usize),
    /// The branch points it lies between (indices).
    pub between: (usize, usize),
    /// The orbit's state there.
    pub x: Vec<f64>,
    /// The [`Mark`] of that orbit when it is a point of the branch's
    /// family at `param` (a bifurcation located on the arclength); `None`
    /// for a grazing located by its distance to the stop.
    pub mark: Option<Mark>,
}

/// A branch: its points in order, its bifurcations, and why it ended.
#[derive(Clone, Debug)]
pub struct Branch {
    /// The points.
    pub points: Vec<BranchPoint>,
    /// The bifurcations located between them.
    pub bifurcations: Vec<Bifurcation>,
    /// Why the branch ended (`"reached to"`, or what stopped it).
    pub end: String,
    /// A period-doubled branch ([`doubled_branch`]) that ends where it
    /// rejoins the branch of half its period: the parameter there (a
    /// period doubling of that branch, the other end of the loop); a
    /// crossing branch ([`crossing_branch`]) that ends where it meets the
    /// branch it crossed again: the parameter of that branch point.
    pub rejoins: Option<f64>,
}

/// The map linearised at a point: `G = P(x) − x`, `G_x + I` (the map's
/// Jacobian), `G_λ`, and the period's events and horizon.
struct Linearised {
    g: Vec<f64>,
    jac: Mat<f64>,
    gl: Vec<f64>,
    /// `P(x)`.
    image: Vec<f64>,
    events: Vec<signorini_schemes::events::EventRecord>,
    period: f64,
    /// The model at the point and its marker.
    model: Model,
    marker: Option<Marker>,
    /// The orbit's states the flow passed through ([`Readings`]).
    readings: Readings,
}

/// The states of the orbit through a point at the intermediate times
/// [`Returns`] watches, read on the way by the map's flow at the point
/// ([`Model::flow_reading`]: the same bits as a flow to each): a closing
/// check costs no flow of its own. `None` where not read (then flowed to).
#[derive(Clone, Default)]
struct Readings {
    /// Its state after `k` forcing periods, `k = 1 … p − 1`, as
    /// [`Returns::all_shifted`] flows to them (read on maps of `p > 1`
    /// forcing periods).
    shifted: Option<Vec<Option<Vec<f64>>>>,
    /// Its mirror images, as [`mirror_images`] makes them (read on maps of
    /// a structure symmetric at the point's parameter; each `None` where
    /// not).
    mirrors: Option<Vec<Option<Vec<f64>>>>,
}

struct Ctx<'a, F: Family> {
    family: &'a F,
    opts: &'a ContinuationOptions,
    /// Scales of the state and the parameter.
    xs: f64,
    ls: f64,
    n: usize,
}

/// Why a trial step of the branch was given up: its prediction lies past a
/// grazing — the map there has more impacts per period than the orbit the
/// step starts from, a new impact whose speed grows as the square root of
/// how far past the stop it reaches, where Newton has no quadratic
/// convergence to rely on. The step is given up before any Newton step and
/// halved, down to the grazing, which the branch then crosses or turns back
/// from by its own searches ([`graze`], [`further_impact`]) instead of a
/// corrector run past it. Giving up only at the first Newton step that did
/// not lower the residual (the rule before) let one trial on the
/// oscillator's period-2 loop (`tests/it/switch.rs`) converge past the
/// grazing where the 2-impact orbit turns back as an unstable 3-impact
/// one, onto the stable 3-impact orbit beyond the fold: the branch skipped
/// the fold and the unstable orbits, and listed the grazing twice, 9.3e-7
/// and 4.6e-6 off (docs/orbits.md). Every other test of the crate passes
/// unchanged, and the beam's frequency and amplitude runs write the same
/// files byte for byte.
const PAST_A_GRAZING: &str = "the trial step's prediction lies past a grazing (more impacts per period than the orbit it starts from)";

/// A converged point with its tangent.
#[derive(Clone)]
struct Point {
    x: Vec<f64>,
    param: f64,
    orbit: Orbit,
    /// The unit tangent (scaled coordinates; last entry: the parameter's).
    tangent: Vec<f64>,
    mark: Option<Mark>,
    /// The orbit's states at the intermediate times [`Returns`] watches.
    readings: Readings,
}

impl<F: Family> Ctx<'_, F> {
    fn residual_and_jacobian(&self, x: &[f64], param: f64) -> Result<Linearised, OrbitError> {
        let mut lin = self.image(x, param)?;
        self.param_derivative(&mut lin, x, param, false)?;
        Ok(lin)
    }

    /// The map at `(x, λ)` with its Jacobian: [`Linearised`] without `G_λ`
    /// (empty until [`Ctx::param_derivative`]).
    ///
    /// On a map of `p > 1` forcing periods, or of a structure symmetric
    /// under `x → −x` ([`mirror_symmetric`]), the flow also reads the
    /// orbit's states at the times [`Returns`] watches ([`Readings`]),
    /// at the times [`Returns::shifted`] and [`mirror_images`] flow to.
    fn image(&self, x: &[f64], param: f64) -> Result<Linearised, OrbitError> {
        let (model, period, marker) = self.family.model_period_marker(param)?;
        let p = self.family.periods().max(1);
        let half = 0.5 * period / p as f64;
        let symmetric = mirror_symmetric(&model, half);
        // (time, k, mirror): the shifted states' `period · k / p`, the
        // mirror images' `(2k + 1) · half`, in order of time.
        let mut reads: Vec<(f64, usize, bool)> = (1..p).map(|k| (period * k as f64 / p as f64, k, false)).collect();
        if symmetric {
            reads.extend((0..p).map(|k| ((2 * k + 1) as f64 * half, k, true)));
        }
        let (img, readings) = if reads.is_empty() {
            (model.flow(0.0, x, period, true)?, Readings::default())
        } else {
            reads.sort_by(|a, b| a.0.total_cmp(&b.0));
            let times: Vec<f64> = reads.iter().map(|r| r.0).collect();
            let (img, states) = model.flow_reading(0.0, x, period, true, &times)?;
            // A time not below the period (round-off): not read, flowed to.
            let readings = if states.len() < reads.len() {
                Readings::default()
            } else {
                let mut shifted = vec![None; p - 1];
                let mut mirrors = vec![None; p];
                for (&(_, k, mirror), state) in reads.iter().zip(states) {
                    if mirror {
                        mirrors[k] = Some(state.iter().map(|v| -v).collect());
                    } else {
                        shifted[k - 1] = Some(state);
                    }
                }
                Readings { shifted: (p > 1).then_some(shifted), mirrors: Some(mirrors) }
            };
            (img, readings)
        };
        let g: Vec<f64> = img.x.iter().zip(x).map(|(a, b)| a - b).collect();
        Ok(Linearised { g, jac: img.jacobian.expect("asked for"), gl: Vec::new(), image: img.x, events: img.events, period, model, marker, readings })
    }

    /// `G_λ` at the point `lin` linearises. `exact` (the corrector's
    /// Newton converging only linearly: [`Ctx::correct`]): the map's
    /// sensitivity to the parameter from the variational flow
    /// ([`Model::param_sensitivity`]), its data's derivatives by the
    /// central difference of step 1e-5 Λ (one-sided of second order,
    /// `(−3g(λ) + 4g(λ ± h) − g(λ ± 2h))/(±2h)`, where `λ ∓ h` is no valid
    /// scene: a restitution of 1); otherwise [`Ctx::param_difference`].
    /// It steers Newton and the tangent only; the points themselves solve
    /// G = 0 to the tolerance.
    fn param_derivative(&self, lin: &mut Linearised, x: &[f64], param: f64, exact: bool) -> Result<(), OrbitError> {
        if !exact {
            return self.param_difference(lin, x, param);
        }
        let h = 1e-5 * self.ls;
        let outside = |e: &OrbitError| matches!(e, OrbitError::Option { .. } | OrbitError::Scene(_) | OrbitError::Model(_));
        let at = |p: f64| self.family.model_and_period(p);
        let (plus, minus) = (at(param + h), at(param - h));
        let (models, weights, periods): (Vec<Model>, Vec<f64>, Vec<f64>) = match (plus, minus) {
            (Ok(a), Ok(b)) => (vec![a.0, b.0], vec![0.5 / h, -0.5 / h], vec![a.1, b.1]),
            (plus, minus) => {
                let d = match (&plus, &minus) {
                    (Err(e), Ok(_)) if outside(e) => -h,
                    (Ok(_), Err(e)) if outside(e) => h,
                    _ => return Err(plus.err().or(minus.err()).expect("one failed")),
                };
                let (one, two) = (if d > 0.0 { plus? } else { minus? }, at(param + 2.0 * d)?);
                (vec![one.0, two.0], vec![2.0 / d, -0.5 / d], vec![one.1, two.1])
            }
        };
        let one_sided = (weights[1] + weights[0]) != 0.0;
        let mut stencil: Vec<(&Model, f64)> = models.iter().zip(&weights).map(|(m, &w)| (m, w)).collect();
        let mut horizon: f64 = periods.iter().zip(&weights).map(|(t, w)| w * t).sum();
        if one_sided {
            let w0 = -(weights[0] + weights[1]);
            stencil.push((&lin.model, w0));
            horizon += w0 * lin.period;
        }
        lin.gl = lin.model.param_sensitivity(0.0, x, lin.period, &Stencil { models: stencil, horizon })?;
        Ok(())
    }

    /// `G_λ` by a forward difference of the map (a second run)
    /// ([`Ctx::param_derivative`]).
    fn param_difference(&self, lin: &mut Linearised, x: &[f64], param: f64) -> Result<(), OrbitError> {
        // Backward where the forward value is no valid scene (a range that
        // starts at the end of the parameter's domain: a restitution of 1).
        let mut h = 1e-7 * self.ls * slow_impact_scale(&lin.events);
        let (m, t) = match self.family.model_and_period(param + h) {
            Err(e @ (OrbitError::Option { .. } | OrbitError::Scene(_) | OrbitError::Model(_))) => {
                h = -h;
                self.family.model_and_period(param + h).map_err(|_| e)?
            }
            other => other?,
        };
        let mut plus = m.flow(0.0, x, t, false)?;
        // Backward where the point has an impact within 1e-4 of a period of
        // the section's time and the forward run has another number of
        // impacts, the backward one the point's: the difference moved that
        // impact across the end of the period, and the image jumped by its
        // impulse. On the oscillator between symmetric stops the forward
        // difference 1e-7 of the range on put an impact at 3e-9 of a
        // period after the section into the period's end: G_λ was 1.8e8
        // (the backward difference's −1.56) and the corrector stalled
        // (docs/orbits.md, `tests/it/section.rs`). Elsewhere (a grazing
        // ahead) the forward difference stands, as before.
        let k = count_impacts(&lin.events);
        let on_section = lin.events.iter().any(|e| {
            e.kind == EventKind::Impact && {
                let phase = (e.t / lin.period).rem_euclid(1.0);
                !(1e-4..=1.0 - 1e-4).contains(&phase)
            }
        });
        if h > 0.0 && on_section && count_impacts(&plus.events) != k {
            if let Ok((m, t)) = self.family.model_and_period(param - h) {
                let minus = m.flow(0.0, x, t, false)?;
                if count_impacts(&minus.events) == k {
                    (plus, h) = (minus, -h);
                }
            }
        }
        lin.gl = (0..self.n).map(|i| (plus.x[i] - lin.image[i]) / h).collect();
        Ok(())
    }

    /// The tangent at `(x, λ)` oriented along `prev` (scaled; unit).
    fn tangent(&self, jac: &Mat<f64>, gl: &[f64], prev: &[f64]) -> Vec<f64> {
        let n = self.n;
        // [G_x·X  G_λ·Λ; prevᵀ] t = [0; 1]
        let a = Mat::from_fn(n + 1, n + 1, |r, c| {
            if r < n {
                if c < n {
                    (jac[(r, c)] - if r == c { 1.0 } else { 0.0 }) * self.xs
                } else {
                    gl[r] * self.ls
                }
            } else {
                prev[c]
            }
        });
        let rhs = Mat::from_fn(n + 1, 1, |r, _| if r == n { 1.0 } else { 0.0 });
        let t = a.partial_piv_lu().solve(&rhs);
        let norm = (0..=n).map(|i| t[(i, 0)] * t[(i, 0)]).sum::<f64>().sqrt();
        (0..=n).map(|i| t[(i, 0)] / norm).collect()
    }

    /// Newton on the branch from the prediction `(x, λ)`, on the hyperplane
    /// through it normal to `t`. Returns the point and the map linearised
    /// there.
    ///
    /// `trial`: for a trial step of the branch ([`Ctx::trial`]), the
    /// impacts per period of the orbit it starts from. When the map at the
    /// prediction has more (the step crossed a grazing where an impact
    /// appears), the step is given up before any Newton step
    /// ([`PAST_A_GRAZING`]).
    fn correct(&self, mut x: Vec<f64>, mut param: f64, t: &[f64], trial: Option<usize>) -> Result<(Vec<f64>, f64, Linearised), OrbitError> {
        let n = self.n;
        let (x0, p0) = (x.clone(), param);
        let nt = self.opts.newton;
        let mut last = f64::NAN;
        // The forward difference's `G_λ` errs where the map's `G_λλ` is
        // large (near a slow impact: 0.6 % at Ω = 0.7087 on the two-stop
        // scene, where Newton fell by only 0.15 … 0.24 an iteration and the
        // branch crept); from the third iteration on, a residual that fell
        // by less than 10× switches it to the variational flow's — except
        // where an impact is slower than 1e-2 of the fastest, where the
        // difference's step is shrunk instead ([`slow_impact_scale`]: with
        // the switch there too, `tests/it/slow_impact.rs`'s 50 points ended
        // 5.7e-6 short of the fold they reach).
        let mut exact = false;
        // The last Newton step (scaled, ∞-norm): a step that does not
        // halve it says Newton can do no better ([`at_floor`]).
        let mut last_step = f64::INFINITY;
        for k in 0..nt.max_iter.min(12) {
            let mut lin = self.image(&x, param)?;
            let res = lin.g.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let plane: f64 = (0..n).map(|i| t[i] * (x[i] - x0[i]) / self.xs).sum::<f64>() + t[n] * (param - p0) / self.ls;
            let xn = x.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(nt.scale);
            if res <= nt.tol * xn && plane.abs() <= 1e-12 {
                self.param_derivative(&mut lin, &x, param, exact)?;
                return Ok((x, param, lin));
            }
            if k == 0 && trial.is_some_and(|from| count_impacts(&lin.events) > from) {
                return Err(OrbitError::NoConvergence { residual: res, iterations: k, why: PAST_A_GRAZING.into() });
            }
            exact |= k >= 2 && res > 0.1 * last && slow_impact_scale(&lin.events) == 1.0;
            last = res;
            self.param_derivative(&mut lin, &x, param, exact)?;
            let (g, jac, gl) = (&lin.g, &lin.jac, &lin.gl);
            let a = Mat::from_fn(n + 1, n + 1, |r, c| {
                if r < n {
                    if c < n {
                        jac[(r, c)] - if r == c { 1.0 } else { 0.0 }
                    } else {
                        gl[r]
                    }
                } else if c < n {
                    t[c] / self.xs
                } else {
                    t[n] / self.ls
                }
            });
            let rhs = Mat::from_fn(n + 1, 1, |r, _| if r < n { -g[r] } else { -plane });
            let d = a.partial_piv_lu().solve(&rhs);
            if (0..=n).any(|i| !d[(i, 0)].is_finite()) {
                break;
            }
            let step = (0..n).map(|i| d[(i, 0)].abs() / self.xs).fold(d[(n, 0)].abs() / self.ls, f64::max);
            if at_floor(res, step * self.xs, last_step * self.xs, nt.tol * xn, plane, &x, &lin) {
                return Ok((x, param, lin));
            }
            last_step = step;
            for i in 0..n {
                x[i] += d[(i, 0)];
            }
            param += d[(n, 0)];
        }
        Err(OrbitError::NoConvergence { residual: last, iterations: nt.max_iter.min(12), why: "the corrector did not converge".into() })
    }

    fn point(&self, x: Vec<f64>, param: f64, prev_tangent: &[f64]) -> Result<Point, OrbitError> {
        let lin = self.residual_and_jacobian(&x, param)?;
        self.point_from(x, param, lin, prev_tangent)
    }

    /// The branch point at `(x, λ)` from the map linearised there (the
    /// corrector's last linearisation: not computed again).
    fn point_from(&self, x: Vec<f64>, param: f64, lin: Linearised, prev_tangent: &[f64]) -> Result<Point, OrbitError> {
        let tangent = self.tangent(&lin.jac, &lin.gl, prev_tangent);
        let residual = lin.g.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let multipliers = eigenvalues(&lin.jac)?;
        let mark = lin.marker.as_ref().and_then(|m| m(&lin.model, &x));
        let orbit = Orbit { x: x.clone(), t0: 0.0, period: lin.period, events: lin.events, monodromy: lin.jac, multipliers, residual, iterations: 0 };
        Ok(Point { x, param, orbit, tangent, mark, readings: lin.readings })
    }

    /// The point at arclength `s` from `a` along its tangent.
    fn at(&self, a: &Point, s: f64) -> Result<Point, OrbitError> {
        self.along(a, s, None)
    }

    /// [`Ctx::at`] for a trial step of the branch, which the corrector
    /// gives up early past a grazing ([`Ctx::correct`]): a step that fails
    /// is halved and tried again, so giving up costs nothing but the
    /// iterations left. (A bisection's steps are not: a bisection ends at
    /// its first step that fails.)
    fn trial(&self, a: &Point, s: f64) -> Result<Point, OrbitError> {
        self.along(a, s, Some(a.orbit.impacts()))
    }

    fn along(&self, a: &Point, s: f64, trial: Option<usize>) -> Result<Point, OrbitError> {
        let n = self.n;
        let x: Vec<f64> = (0..n).map(|i| a.x[i] + s * a.tangent[i] * self.xs).collect();
        let param = a.param + s * a.tangent[n] * self.ls;
        let (x, param, lin) = self.correct(x, param, &a.tangent, trial)?;
        self.point_from(x, param, lin, &a.tangent)
    }
}

/// The factor on `G_λ`'s difference step at an orbit whose slowest impact
/// (speed `v`) is below 1e-2 of its fastest (`V`): `(100 v / V)²`, at
/// least 1e-6; 1 otherwise. Near a slow impact the map's second
/// derivative in the parameter grows as `1/v³` (the impact's time moves
/// as `1/v`), so a forward difference errs by about `h/v²` of `G_λ`: on
/// the oscillator between stops (`x'' + 0.1x' + x = 2 sin Ωt`, `|x| <= 1`,
/// e = 0.8, period 3, a range of 3) at Ω = 3.8264736, the 3-impact orbit's
/// slow impact at 8.75e-4, the step 3e-7 gave `G_λ` 2642 where it is 1490
/// (its differences at 3e-9 and 3e-10: 1494, 1490.8), and the corrector
/// failed at every step from there (`tests/it/slow_impact.rs`; the
/// period-2 branch of `tests/it/period_two.rs` the same way, up its
/// 4-impact arc). With the factor from a tenth of `V` the switched
/// period-4 branch of `tests/it/cascade.rs` fell onto period-2 orbits.
fn slow_impact_scale(events: &[signorini_schemes::events::EventRecord]) -> f64 {
    let speeds = events.iter().filter(|e| e.kind == EventKind::Impact && e.velocity_before != 0.0).map(|e| e.velocity_before.abs());
    let (v, vmax) = speeds.fold((f64::INFINITY, 0.0f64), |(a, b), s| (a.min(s), b.max(s)));
    if v < 1e-2 * vmax {
        (100.0 * v / vmax).powi(2).max(1e-6)
    } else {
        1.0
    }
}

/// The map's round-off at `x`, `ε (‖x‖∞ + ‖P(x)‖∞)(1 + ‖P'‖∞)`: the
/// rounding of the state and of its image, the state's carried through
/// the map. `|P(x) − x|` cannot be computed much below it, whatever the
/// tolerance: on the two-stop scene near its 4 → 2 grazing at Ω = 0.7010
/// (`tests/it/floor.rs`, ‖P'‖∞ 6e4 … 5e7) Newton's residual stops at 0.1 …
/// 2.7 times this, above the tolerance (1.7e-11) from Ω = 0.7026 down.
fn floor(x: &[f64], lin: &Linearised) -> f64 {
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, u| a.max(u.abs()));
    let n = x.len();
    let jn = (0..n).map(|r| (0..n).map(|c| lin.jac[(r, c)].abs()).sum::<f64>()).fold(0.0, f64::max);
    f64::EPSILON * (inf(x) + inf(&lin.image)) * (1.0 + jn)
}

/// The corrector has converged at the map's round-off ([`floor`]): its
/// Newton step `step` (in the state's units) did not halve the last one
/// (`last`: Newton makes no more progress), is itself within the
/// tolerance `tol` (the distance it would still move the point), the
/// point is on the hyperplane, and the residual is within 4 times the
/// floor (measured 0.1 … 2.7 where this fires; where Newton wandered
/// near a grazing without converging, steps 1e-9 that did not halve,
/// 4.8 … 640). A point 1e-8 off the branch moves by 1e-8 on its first
/// step and is not taken (`tests/it/floor.rs`).
fn at_floor(res: f64, step: f64, last: f64, tol: f64, plane: f64, x: &[f64], lin: &Linearised) -> bool {
    step > 0.5 * last && step <= tol && plane.abs() <= 1e-12 && res <= 4.0 * floor(x, lin)
}

/// How far the multipliers near the unit circle (modulus below 2) moved
/// from `a` to `b` (each list by decreasing modulus, compared in order): a
/// step over which they move more than 0.25 is halved, so that a step
/// cannot straddle two crossings of the unit circle (a window between two
/// period doublings) and see none. Multipliers on the circle at both ends
/// (to 1e-4: an undamped structure's free orbit, whose multipliers
/// `e^{±iω_k T}` turn by `ω_k ΔT` along the circle, the highest modes'
/// fastest: on the beam (J = 3) the steps fell to 2.4e-6 rad/s) are left
/// out: they turn without crossing it.
fn mu_change(a: &Point, b: &Point) -> f64 {
    let on_circle = |m: &c64| (m.norm() - 1.0).abs() <= 1e-4;
    a.orbit.multipliers.iter().zip(&b.orbit.multipliers).filter(|(x, y)| x.norm().min(y.norm()) < 2.0 && !(on_circle(x) && on_circle(y))).map(|(x, y)| (x - y).norm()).fold(0.0, f64::max)
}

/// Test functions whose sign change marks a bifurcation.
fn fold_test(p: &Point) -> f64 {
    p.tangent[p.tangent.len() - 1]
}

/// The sign of `det(P' − I)` = `∏ (μ − 1)` (a complex pair contributes
/// `|μ − 1|² >= 0`): it changes where a real multiplier passes through +1.
fn det_test(p: &Point) -> f64 {
    p.orbit.multipliers.iter().fold(c64::new(1.0, 0.0), |a, m| a * (m - c64::new(1.0, 0.0))).re
}

/// The multipliers' product has modulus 1 (to 1e-6): the map preserves
/// volume (a conservative structure: no damping, elastic impacts).
fn on_circle(p: &Point) -> bool {
    (p.orbit.multipliers.iter().map(|m| m.norm()).product::<f64>() - 1.0).abs() <= 1e-6
}

fn is_real(m: &c64) -> bool {
    m.im.abs() <= 1e-9 * m.norm().max(1e-300)
}

fn pd_test(p: &Point) -> f64 {
    // The real multiplier nearest −1: its distance beyond −1 (positive
    // outside the circle).
    p.orbit.multipliers.iter().filter(|m| is_real(m) && m.re < 0.0).map(|m| -m.re - 1.0).min_by(|a, b| a.abs().total_cmp(&b.abs())).unwrap_or(-1.0)
}

/// The sign of `det(P' + I)` = `∏ (μ + 1)`: a complex pair contributes
/// `|μ + 1|² >= 0`, a real pair `(μ, 1/μ)` of a volume-preserving map
/// `(μ + 1)²/μ`, negative when the pair is. It changes where such a pair
/// meets at −1 and leaves the unit circle along the negative real axis —
/// a period doubling of the conservative map, where no single multiplier
/// passes through −1 ([`pd_test`] keeps its sign: of the pair `−1 − ε`
/// and `−1 + ε/(1 + ε)` the nearer to −1 is inside the circle).
fn pair_pd_test(p: &Point) -> f64 {
    p.orbit.multipliers.iter().fold(c64::new(1.0, 0.0), |a, m| a * (m + c64::new(1.0, 0.0))).re
}

/// A real negative multiplier off the unit circle by more than 1e-6: a
/// pair that has left it (not a pair on it near −1 that round-off split
/// onto the real axis).
fn negative_pair_off_circle(p: &Point) -> bool {
    p.orbit.multipliers.iter().any(|m| is_real(m) && m.re < 0.0 && (m.norm() - 1.0).abs() > 1e-6)
}

fn ns_test(p: &Point) -> f64 {
    p.orbit.multipliers.iter().filter(|m| !is_real(m)).map(|m| m.norm() - 1.0).max_by(f64::total_cmp).unwrap_or(-1.0)
}

/// `G_λ` of `family`'s map at `(x, param)` as the continuation takes it,
/// the parameter's scale Λ = `scale`, `exact`: the variational flow's
/// (else the forward difference) (for `tests/it/param_derivative.rs`).
#[doc(hidden)]
pub fn param_derivative<F: Family>(family: &F, x: &[f64], param: f64, scale: f64, exact: bool) -> Result<Vec<f64>, OrbitError> {
    let opts = ContinuationOptions { scale: Some(scale), ..ContinuationOptions::new(param, param + scale) };
    let ctx = Ctx { family, opts: &opts, xs: 1.0, ls: scale, n: x.len() };
    let mut lin = ctx.image(x, param)?;
    ctx.param_derivative(&mut lin, x, param, exact)?;
    Ok(lin.gl)
}

/// The corrector's point from `(x, param)` on the plane of `param`
/// (the parameter's scale 1; for `tests/it/floor.rs`): the fixed point
/// it accepts, or why none.
#[doc(hidden)]
pub fn corrected<F: Family>(family: &F, x: &[f64], param: f64) -> Result<Vec<f64>, OrbitError> {
    let opts = ContinuationOptions::new(param, param + 1.0);
    let ctx = Ctx { family, opts: &opts, xs: 1.0, ls: 1.0, n: x.len() };
    let plane: Vec<f64> = (0..=x.len()).map(|i| if i == x.len() { 1.0 } else { 0.0 }).collect();
    ctx.correct(x.to_vec(), param, &plane, None).map(|p| p.0)
}

/// Continues the branch of the family's periodic orbits from `guess` (a
/// state near an orbit at `opts.from`) toward `opts.to`.
pub fn continuation<F: Family>(family: &F, guess: &[f64], opts: &ContinuationOptions) -> Result<Branch, OrbitError> {
    continuation_watched(family, guess, opts, &mut |_| true)
}

/// [`continuation`] with `watch` called after each new point (a progress
/// display, an interrupt): when it returns `false` the branch ends there,
/// its points so far kept, `end` saying so.
pub fn continuation_watched<F: Family>(family: &F, guess: &[f64], opts: &ContinuationOptions, watch: &mut dyn FnMut(&BranchPoint) -> bool) -> Result<Branch, OrbitError> {
    continuation_until(family, guess, opts, watch, &mut |_| None)
}

/// [`continuation_watched`] that also ends the branch when `stop`, shown
/// the branch so far after each step, returns why (the branch's `end`).
/// The branch ends where it returns onto itself, or onto the mirror image
/// of its orbits on a symmetric structure ([`Returns`]: on a period-doubled
/// branch the states of its 2p-period orbits after each of the 2p − 1
/// forcing periods, and their mirror images); `stop` is asked first why
/// (a period-doubled branch rejoining the branch of half its period:
/// [`doubled_branch`]).
fn continuation_until<F: Family>(
    family: &F,
    guess: &[f64],
    opts: &ContinuationOptions,
    watch: &mut dyn FnMut(&BranchPoint) -> bool,
    stop: &mut dyn FnMut(&Branch) -> Option<String>,
) -> Result<Branch, OrbitError> {
    opts.validate()?;
    let model = family.model(opts.from)?;
    let start = periodic_orbit(&model, 0.0, family.period(opts.from)?, guess, &opts.newton)?;
    let n = start.x.len();
    let ls = opts.param_scale();
    let xs = match start.x.iter().fold(0.0f64, |a, v| a.max(v.abs())) {
        // A start at rest (no forcing at `from`: an amplitude from 0) has
        // no size to scale the state by: the change of the orbit over the
        // parameter's scale, `|dx/dλ| Λ`, from `(P' − I) dx/dλ = −G_λ`.
        0.0 => {
            let ctx = Ctx { family, opts, xs: 1.0, ls, n };
            let lin = ctx.residual_and_jacobian(&start.x, opts.from)?;
            let a = Mat::from_fn(n, n, |r, c| lin.jac[(r, c)] - if r == c { 1.0 } else { 0.0 });
            let d = a.partial_piv_lu().solve(Mat::from_fn(n, 1, |r, _| -lin.gl[r]));
            let size = (0..n).fold(0.0f64, |m, i| m.max(d[(i, 0)].abs())) * ls;
            if size.is_finite() && size > 0.0 {
                size
            } else {
                1.0
            }
        }
        norm => norm.max(opts.newton.scale).max(1e-300),
    };
    let ctx = Ctx { family, opts, xs, ls, n };
    let dir = (opts.to - opts.from).signum();
    let mut seed = vec![0.0; n + 1];
    seed[n] = dir;
    let mut cur = ctx.point(start.x.clone(), opts.from, &seed)?;
    let mut branch = Branch { points: vec![BranchPoint { param: opts.from, orbit: cur.orbit.clone(), mark: cur.mark }], bifurcations: Vec::new(), end: String::new(), rejoins: None };
    let mut ds = opts.step;
    // The impact speeds' scale, for the grazing test.
    let mut vref = cur.orbit.fastest_impact().map_or(0.0, |f| f.0);
    let (lo, hi) = (opts.from.min(opts.to), opts.from.max(opts.to));
    let beyond = |p: f64| (p - opts.to) * dir > 0.0;
    let periods = family.periods().max(1);
    let symmetric = family.model_and_period(opts.from).is_ok_and(|(m, t)| mirror_symmetric(&m, 0.5 * t / periods as f64));
    let mut returns = Returns::new(periods, &cur, symmetric);
    // The last point's asymmetry (its parameter and state, and the value).
    let mut asym: Option<(f64, Vec<f64>, f64)> = None;
    while branch.points.len() < opts.max_points {
        if let Some(last) = branch.points.last() {
            if !watch(last) {
                branch.end = format!("interrupted at param = {}", last.param);
                return Ok(branch);
            }
        }
        if let Some(why) = stop(&branch) {
            branch.end = why;
            return Ok(branch);
        }
        let trial = ctx.trial(&cur, ds);
        if matches!(trial, Err(OrbitError::Interrupted)) {
            branch.end = format!("interrupted at param = {}", cur.param);
            return Ok(branch);
        }
        // The trial taken as a corner (its bracket's ends meet).
        let mut cornered = false;
        let next = match trial {
            // Not a trial whose corrector ran far along the hyperplane
            // (more than 3 steps from `cur`: a jump onto another arc; on
            // a conservative map the multipliers on the circle do not
            // say so, [`mu_change`] leaves them out).
            Ok(p)
                if p.tangent.iter().zip(&cur.tangent).map(|(a, b)| a * b).sum::<f64>() > 0.9
                    && (ds <= 16.0 * opts.min_step || mu_change(&cur, &p) <= 0.25)
                    && arclength(&ctx, &cur, &p) <= 3.0 * ds
                    && along_tangent(&ctx, &cur, &p) =>
            {
                p
            }
            // A corner where the number of impacts or held phases changes
            // (a grazing, where a branch may also turn back): taken, the
            // change located on the arclength.
            Ok(p) if ds <= 1e-3 && (p.orbit.impacts() != cur.orbit.impacts() || p.orbit.releases() != cur.orbit.releases()) => {
                let i = branch.points.len() - 1;
                let kind = if p.orbit.impacts() != cur.orbit.impacts() { BifurcationKind::Grazing } else { BifurcationKind::Sticking };
                let (at, meets) = corner_bracket(&ctx, &cur, &p, ds);
                // The bracket's ends apart (the rule of [`corner_bracket`];
                // before, further apart than the step, and a step whose
                // ends lay within it, taken here, was then halved by that
                // rule with its grazing left listed: the period-2
                // oscillator with `--param-scale 0.01` listed its 4 → 3
                // grazing near 2.38354 three times): no corner (where the
                // orbits on either side meet) but a trial fallen onto
                // another arc of the branch: the two arcs of a grazing
                // where the branch turns back ([`turned_back`]), or the
                // step halved.
                if !meets {
                    if let Some((bif, across)) = turned_back(&ctx, &branch.points, &cur, &p, vref) {
                        branch.bifurcations.push(bif);
                        branch.points.push(BranchPoint { param: across.param, orbit: across.orbit.clone(), mark: across.mark });
                        cur = across;
                        ds = opts.step;
                        continue;
                    }
                    ds *= 0.5;
                    // Below the least step the trials still fall onto the
                    // other arc: the branch ends there, named (as the
                    // other failures below it end), not halving on until
                    // the step underflows or some later trial is taken
                    // from the other arc (which went back along it).
                    if ds < opts.min_step {
                        branch.end = format!(
                            "stopped at param = {}: trial steps down to the least step ({:e}) fall onto another arc of orbits (one with {} impacts per period at param = {}, where this one has {}), not a corner of this one: the branch is not continued onto it",
                            cur.param,
                            opts.min_step,
                            p.orbit.impacts(),
                            p.param,
                            cur.orbit.impacts()
                        );
                        return Ok(branch);
                    }
                    continue;
                }
                branch.bifurcations.push(Bifurcation {
                    param: at.param,
                    kind,
                    mu: critical(kind, &at),
                    impacts: (cur.orbit.impacts(), p.orbit.impacts()),
                    releases: (cur.orbit.releases(), p.orbit.releases()),
                    between: (i, i + 1),
                    x: at.x.clone(),
                    mark: at.mark,
                });
                cornered = true;
                p
            }
            other => {
                ds *= 0.5;
                if ds < opts.min_step {
                    // An impact crossing the section's time: the section
                    // state jumps by its impulse; the branch goes on from
                    // the state on the other side.
                    if let Some(p) = across_section(&ctx, &cur, &branch.points, dir) {
                        branch.points.push(BranchPoint { param: p.param, orbit: p.orbit.clone(), mark: p.mark });
                        cur = p;
                        ds = opts.step;
                        continue;
                    }
                    // An orbit without impacts grazing a stop: the grazing
                    // located on its smooth side, the impacting orbit beyond.
                    // An orbit with impacts whose flight between them grazes
                    // a stop: the same, with the further impact beyond.
                    let grazed = appearing_impact(&ctx, &cur, &branch.points, dir).or_else(|| further_impact(&ctx, &cur, &branch.points, dir));
                    if let Some((bif, away, retraced, least)) = grazed {
                        let at = bif.param;
                        // Retraced: the grazing is the one the branch just
                        // crossed, listed then.
                        if !retraced {
                            branch.bifurcations.push(bif);
                        }
                        // No impacting orbit beyond: the branch ends at
                        // the grazing, which is named.
                        let Some(last) = away.last().cloned() else {
                            let unit = opts.scale_name();
                            branch.end = if retraced {
                                format!("ended at the grazing at param = {at}: the orbit with the further impact there is the one the branch came along (it would retrace itself)")
                            } else if cur.orbit.impacts() == 0 {
                                format!(
                                    "ended at the grazing at param = {at}: no periodic orbit with the new impact found past it or turning back from it (Newton from the grazing orbit, and from it pushed past the stop, at 1e-9 … 1e-3 of {unit} past it; from the free orbit pushed past the stop at 1e-6 … 1e-2 before it){}",
                                    residuals(least, unit)
                                )
                            } else {
                                format!(
                                    "ended at the grazing at param = {at}, where a flight between the {} impacts per period reaches a stop: no periodic orbit with the further impact found past it or turning back from it (Newton at 1e-9 … 1e-3 of {unit} on either side)",
                                    cur.orbit.impacts()
                                )
                            };
                            return Ok(branch);
                        };
                        branch.points.extend(away.iter().map(|p| BranchPoint { param: p.param, orbit: p.orbit.clone(), mark: p.mark }));
                        cur = last;
                        ds = opts.min_step.max(1e-4);
                        continue;
                    }
                    // A corner where impacts appear or held phases start
                    // (a free flight grazing a stop): the orbit just beyond.
                    if let Some((bif, p)) = corner(&ctx, &cur, &branch.points, dir) {
                        // An orbit with fewer impacts beside one whose slow
                        // impact is vanishing: the two arcs of a nonsmooth
                        // fold, which meet at the grazing of `p`'s arc
                        // ([`turned_back`]), not a corner between them.
                        let (bif, p) = match (p.orbit.impacts() < cur.orbit.impacts()).then(|| turned_back(&ctx, &branch.points, &cur, &p, vref)).flatten() {
                            Some(turned) => turned,
                            None => (bif, p),
                        };
                        branch.bifurcations.push(bif);
                        branch.points.push(BranchPoint { param: p.param, orbit: p.orbit.clone(), mark: p.mark });
                        cur = p;
                        ds = opts.step;
                        continue;
                    }
                    let why = match other {
                        Err(e) => e.to_string(),
                        Ok(_) => "a corner of the branch that the corrector cannot turn (a free flight grazing a stop, where a new impact appears with a vanishing speed, or a nonsmooth fold): the branch is not continued through it".into(),
                    };
                    let near = cur.orbit.slowest_impact().map_or(String::new(), |v| format!("; the slowest impact there at speed {v:e}"));
                    branch.end = format!("stopped at param = {}: {why}{near}", cur.param);
                    return Ok(branch);
                }
                continue;
            }
        };
        // A trial with other impacts than `cur` where the two arcs meet at
        // no corner (the bracket's ends stay apart): the corrector fell
        // onto another arc, not onto this one's continuation. The step is
        // halved, as for any trial fallen onto another arc. The period-2
        // oscillator of `tests/it/period_two.rs` with `--param-scale 0.05`
        // went down its 4-impact arc to Ω = 2.38496 and the trial fell onto
        // the 2-impact orbits it began with, 0.02 away, a grazing 4 → 2
        // listed at 2.3847259 where there is none (that arc goes on down to
        // 2.3806476); further down, from the 3-impact orbit at 2.3728416, a
        // trial of 1.6e-2 landed on the 2-impact arc that begins at
        // 2.3678525 (1.3e-2 away, scaled, an arc not traced yet), a 3 → 2
        // grazing listed at 2.372073 where there is none.
        if next.orbit.impacts() != cur.orbit.impacts() && !cornered && !corner_bracket(&ctx, &cur, &next, ds).1 {
            ds *= 0.5;
            if ds < opts.min_step {
                branch.end = format!(
                    "stopped at param = {}: trial steps down to the least step ({:e}) fall onto orbits the branch has traced (with {} impacts per period at param = {}, where this one has {})",
                    cur.param,
                    opts.min_step,
                    next.orbit.impacts(),
                    next.param,
                    cur.orbit.impacts()
                );
                return Ok(branch);
            }
            continue;
        }
        let next = if beyond(next.param) {
            // Land on `to` exactly: the corrector on the plane λ = to.
            let mut t = vec![0.0; n + 1];
            t[n] = 1.0;
            let frac = (opts.to - cur.param) / (next.param - cur.param);
            let x: Vec<f64> = (0..n).map(|i| cur.x[i] + frac * (next.x[i] - cur.x[i])).collect();
            let (x, p, lin) = ctx.correct(x, opts.to, &t, None)?;
            ctx.point_from(x, p, lin, &cur.tangent)?
        } else {
            next
        };
        let i = branch.points.len() - 1;
        // Back at the first orbit (a closed branch: an isola, or a loop of
        // copies shifted in phase), or onto orbits already traced: the
        // step's bifurcations are located as on any step (a fold, a period
        // doubling, the branch point of a turn onto a copy or a mirror
        // image), the point where it returned kept, and the branch ends
        // there; a caller's stop (a crossing branch meeting the branch it
        // crossed, a doubled one rejoining the branch of half its period)
        // says why first.
        let returned = returns.check(&ctx, &branch.points, &cur, &next).map(|r| {
            let periods = |k: usize| format!("{k} forcing period{}", if k == 1 { "" } else { "s" });
            let segment = |on: usize| format!("between param = {} and {}", branch.points[on].param, branch.points[on + 1].param);
            match r {
                Returned::Closed { at, shift } => {
                    let shifted = if shift == 0 { String::new() } else { format!(" shifted by {}", periods(shift)) };
                    let why = format!(
                        "closed: an isola/loop of {} points (the branch returned to its first orbit{shifted}, at param = {}; the last point repeats it): each bifurcation listed once",
                        branch.points.len(),
                        at.param
                    );
                    (*at, why)
                }
                // Onto a traced segment, or a copy of one shifted in phase.
                Returned::Copy { shift, on } => {
                    let shifted = if shift == 0 { String::new() } else { format!(", shifted by {},", periods(shift)) };
                    let why = format!("returned onto itself at param = {}: the orbit there{shifted} is one the branch has traced ({}): not traced again", next.param, segment(on));
                    (next.clone(), why)
                }
                // Onto the mirror image of the branch's own orbits (a turn
                // where it meets a symmetric orbit): the rest of it the
                // traced one mirrored.
                Returned::Mirror { shift, on } => {
                    let half = if shift == 0 { "half a forcing period".to_string() } else { format!("{shift}½ forcing periods") };
                    let why = format!(
                        "returned onto its mirror image at param = {}: the orbit there, mirrored (−x(t + τ), τ {half}), is one the branch has traced ({}): the branch beyond is the traced one mirrored, not traced again",
                        next.param,
                        segment(on)
                    );
                    (next.clone(), why)
                }
            }
        });
        if let Some((last, why)) = returned {
            locate(&ctx, &cur, &last, i, &mut branch.bifurcations);
            branch.points.push(BranchPoint { param: last.param, orbit: last.orbit, mark: last.mark });
            branch.end = stop(&branch).unwrap_or(why);
            return Ok(branch);
        }
        let found = branch.bifurcations.len();
        locate(&ctx, &cur, &next, i, &mut branch.bifurcations);
        // A pitchfork passed from asymmetric orbits onto symmetric ones
        // (or back) where no test changed sign: named where the asymmetry
        // reaches 0 ([`pitchfork`]), unless the step's own branch point
        // or fold is there.
        if symmetric {
            let ac = match &asym {
                Some((l, x, v)) if *l == cur.param && *x == cur.x => Some(*v),
                _ => asymmetry(&ctx, &cur, periods),
            };
            let an = asymmetry(&ctx, &next, periods);
            let turned = branch.bifurcations[found..].iter().any(|b| matches!(b.kind, BifurcationKind::Fold | BifurcationKind::BranchPoint));
            if let (false, Some(ac), Some(an)) = (turned, ac, an) {
                if let Some(b) = pitchfork(&ctx, &cur, &next, i, periods, ac, an) {
                    branch.bifurcations.push(b);
                }
            }
            asym = an.map(|v| (next.param, next.x.clone(), v));
        }
        // Across a change of the impacts onto an orbit the branch has
        // passed through (a corrector falling onto the orbit it came along,
        // near a grazing where the two meet): it would retrace itself.
        if next.orbit.impacts() != cur.orbit.impacts() && retraces(&branch.points, &next, &cur) {
            branch.end = format!("returned onto itself at param = {}: the orbit with {} impacts per period there is one the branch has passed through", next.param, next.orbit.impacts());
            return Ok(branch);
        }
        branch.points.push(BranchPoint { param: next.param, orbit: next.orbit.clone(), mark: next.mark });
        if beyond(next.param) || next.param == opts.to {
            branch.end = "reached to".into();
            return Ok(branch);
        }
        if next.param < lo - 0.5 * (hi - lo) || next.param > hi + 0.5 * (hi - lo) {
            branch.end = format!("left the range at param = {}", next.param);
            return Ok(branch);
        }
        let turn: f64 = next.tangent.iter().zip(&cur.tangent).map(|(a, b)| a * b).sum();
        let prev = std::mem::replace(&mut cur, next);
        vref = vref.max(cur.orbit.fastest_impact().map_or(0.0, |f| f.0));
        // Grazing ahead: jump across it (module docs).
        if let Some((bif, across)) = graze(&ctx, &prev, &cur, dir, branch.points.len() - 1, vref) {
            branch.bifurcations.push(bif);
            if retraces(&branch.points, &across, &cur) {
                branch.end =
                    format!("returned onto itself at param = {}: the orbit with {} impacts per period across the grazing is one the branch has passed through", across.param, across.orbit.impacts());
                return Ok(branch);
            }
            let beyond_to = beyond(across.param);
            if !beyond_to {
                branch.points.push(BranchPoint { param: across.param, orbit: across.orbit.clone(), mark: across.mark });
                cur = across;
                ds = opts.step;
                continue;
            }
        }
        if turn > 0.99 {
            ds = (ds * 1.5).min(opts.max_step);
        }
    }
    branch.end = format!("max points ({}) reached at param = {}", opts.max_points, cur.param);
    Ok(branch)
}

/// The period-doubled branch born at the period doubling `bif` of the
/// branch of `single` (orbits of p forcing periods): the eigenvector `w`
/// of the multiplier −1 there gives the guesses `x ± ε w` for an orbit of
/// `double` (2p periods) just beside the bifurcation, on each side in turn;
/// the first that converges to an orbit that is not the p-periodic one is
/// continued away from the bifurcation to the end of `range` on its side.
pub fn doubled_branch<F: Family>(single: &F, double: &F, bif: &Bifurcation, range: (f64, f64), opts: &ContinuationOptions) -> Result<Branch, OrbitError> {
    if bif.kind != BifurcationKind::PeriodDoubling {
        return Err(OrbitError::Option { option: "switch", message: format!("a branch switch at a {}: only at a period doubling", bif.kind.name()) });
    }
    let model = single.model(bif.param)?;
    let img = model.flow(0.0, &bif.x, single.period(bif.param)?, true)?;
    let jac = img.jacobian.expect("asked for");
    let eig = jac.eigen().map_err(|_| OrbitError::Model("the monodromy's eigenvectors did not converge".into()))?;
    let n = bif.x.len();
    let k = (0..n).min_by(|&a, &b| (eig.S()[a] + c64::new(1.0, 0.0)).norm().total_cmp(&(eig.S()[b] + c64::new(1.0, 0.0)).norm())).unwrap_or(0);
    let w: Vec<f64> = (0..n).map(|i| eig.U()[(i, k)].re).collect();
    let wn = w.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-300);
    let xs = bif.x.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-300);
    let span = (range.1 - range.0).abs();
    // The offsets from the bifurcation: fractions of the parameter's scale
    // (by default the range).
    let scale = opts.scale.unwrap_or(span);
    let mut last = None;
    let mut guesses = Guesses::default();
    for delta in [1e-4, 1e-3, 1e-2] {
        for side in [1.0, -1.0] {
            let param = bif.param + side * delta * scale;
            let end = if side > 0.0 { range.0.max(range.1) } else { range.0.min(range.1) };
            if (end - param) * side <= 0.0 {
                continue;
            }
            for (eps, sign) in [0.3, 1.0, 3.0].iter().flat_map(|f| [(f * delta.sqrt() * xs, 1.0), (f * delta.sqrt() * xs, -1.0)]) {
                let guess: Vec<f64> = (0..n).map(|i| bif.x[i] + sign * eps * w[i] / wn).collect();
                guesses.tried += 1;
                let orbit = match double.model(param).and_then(|model| periodic_orbit_strict(&model, 0.0, double.period(param)?, &guess, &opts.newton)) {
                    Ok(orbit) => orbit,
                    Err(e) => {
                        guesses.failed(e);
                        continue;
                    }
                };
                // Not the p-periodic orbit: its image after p periods differs.
                let half = single.model(param)?.flow(0.0, &orbit.x, single.period(param)?, false)?;
                let gap = half.x.iter().zip(&orbit.x).fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
                if gap <= 1e-6 * xs {
                    guesses.back += 1;
                    continue;
                }
                let mut o = *opts;
                (o.from, o.to) = (param, end);
                let mut copies = Copies { single, xs, ls: scale, images: Vec::new(), cut: None, copy: None };
                match continuation_until(double, &orbit.x, &o, &mut |_| true, &mut |b| copies.check(&b.points)) {
                    Ok(mut b) => {
                        // The points the last step added (a branch that
                        // ended otherwise) are checked too.
                        if let Some(why) = copies.check(&b.points) {
                            b.end = why;
                        }
                        if let Some((keep, rejoin)) = copies.cut {
                            // The crossing located between the two points
                            // of the step where it was seen.
                            let rejoin = rejoin.map(|at| rejoin_parameter(single, &b.points[keep - 1], &b.points[keep], &o.newton).unwrap_or(at));
                            if let (Some(at), Some((copy, on))) = (rejoin, copies.copy) {
                                b.end = format!(
                                    "rejoined the branch of half its period at its period doubling at param = {at} (between param = {} and {}); past it the orbits are the phase-shifted copies of the branch's own (the image after half the period of the orbit at param = {copy} is the branch's at {on}): not traced again",
                                    b.points[keep - 1].param, b.points[keep].param
                                );
                            }
                            b.points.truncate(keep);
                            b.bifurcations.retain(|f| f.between.1 < keep);
                            b.rejoins = rejoin;
                        }
                        // Cut where the branch rejoins the p-periodic one
                        // (its orbits are then fixed points of the p map).
                        let rejoin = b.points.iter().skip(1).position(|p| {
                            single
                                .model(p.param)
                                .and_then(|m| Ok(m.flow(0.0, &p.orbit.x, single.period(p.param)?, false)?.x))
                                .is_ok_and(|y| y.iter().zip(&p.orbit.x).fold(0.0f64, |a, (u, v)| a.max((u - v).abs())) <= 1e-7 * xs)
                        });
                        if let Some(k) = rejoin {
                            let at = b.points[k + 1].param;
                            b.points.truncate(k + 2);
                            b.bifurcations.retain(|f| f.between.1 <= k + 1);
                            b.end = format!("rejoined the branch of half its period at param = {at}");
                            b.rejoins = Some(at);
                        }
                        return Ok(b);
                    }
                    Err(e) => last = Some(e),
                }
            }
        }
    }
    Err(last.unwrap_or_else(|| {
        guesses.error(format!("no period-doubled orbit found beside the period doubling at {}", bif.param), &format!("onto the branch's own orbit of {} period(s)", single.periods()))
    }))
}

/// What the guesses for the first orbit of a branch beside a bifurcation
/// came to, for the error when none of them starts a branch: how many fell
/// back onto orbits that are not the branch's (the parent's own, another
/// arc's) and the failed Newton search that came closest.
#[derive(Default)]
struct Guesses {
    tried: usize,
    back: usize,
    closest: Option<OrbitError>,
}

impl Guesses {
    fn failed(&mut self, e: OrbitError) {
        let residual = |e: &OrbitError| match e {
            OrbitError::NoConvergence { residual, .. } if residual.is_finite() => *residual,
            _ => f64::INFINITY,
        };
        if self.closest.as_ref().is_none_or(|c| residual(&e) < residual(c)) {
            self.closest = Some(e);
        }
    }

    fn error(self, none: String, back: &str) -> OrbitError {
        let mut why = format!("{none}: of {} guesses, {} converged {back}", self.tried, self.back);
        if let Some(e) = self.closest {
            why += &format!(", {} did not converge (the closest: {e})", self.tried - self.back);
        }
        OrbitError::NoBranch(why)
    }
}

/// The branch that crosses `parent` at its branch point `bif` (a multiplier
/// at +1 where two branches of orbits of the family cross): the asymmetric
/// orbits born at a symmetric orbit's symmetry-breaking pitchfork, or, seen
/// from one of those, the symmetric branch. At the crossing the kernel of
/// `[G_x G_λ]` is two-dimensional: it holds the parent's tangent (the
/// chord of the parent's step across `bif`, `c`) and the crossing branch's
/// direction `w`, the null vector of `[G_x G_λ; cᵀ]` (scaled coordinates;
/// inverse iteration). The first point is Newton from `bif ± s w` on the
/// hyperplane through it normal to `w` (`s` = 1e-3, 1e-2, 3e-2 in turn: the
/// corrector is singular at `bif` itself), one that lands more than `3 s`
/// from the prediction being taken for another arc; the branch is
/// continued from it away from `bif` to the end of `range` on its side.
/// It ends where it meets the parent again (a branch point within 1e-4 of
/// the range and 1e-2 of the state's size of one of the parent's, or of
/// `bif`: located from either branch, near the crossing where the
/// corrector is singular, their states differ by up to 3e-3 of it on the
/// oscillator between its stops): there the asymmetric orbit turns onto its mirror image, the
/// other half of the pair, which is not traced (`rejoins` says where).
/// Of the two halves `±w` the first that converges is followed: at a
/// pitchfork they are the mirror pair.
pub fn crossing_branch<F: Family>(family: &F, parent: &Branch, bif: &Bifurcation, range: (f64, f64), opts: &ContinuationOptions) -> Result<Branch, OrbitError> {
    if bif.kind != BifurcationKind::BranchPoint {
        return Err(OrbitError::Option { option: "switch", message: format!("a crossing branch at a {}: only at a branch point", bif.kind.name()) });
    }
    let (Some(a), Some(b)) = (parent.points.get(bif.between.0), parent.points.get(bif.between.1)) else {
        return Err(OrbitError::Option { option: "switch", message: format!("the branch point at {} lies between no two points of its branch", bif.param) });
    };
    let n = bif.x.len();
    let span = (range.1 - range.0).abs();
    // The arclength's parameter scale (by default the range).
    let scale = opts.scale.unwrap_or(span);
    let xs = bif.x.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(opts.newton.scale).max(1e-300);
    let ctx = Ctx { family, opts, xs, ls: scale, n };
    let lin = ctx.residual_and_jacobian(&bif.x, bif.param)?;
    let unit = |v: Vec<f64>| -> Vec<f64> {
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.into_iter().map(|x| x / norm).collect()
    };
    let c = unit((0..n).map(|i| (b.orbit.x[i] - a.orbit.x[i]) / xs).chain(std::iter::once((b.param - a.param) / scale)).collect());
    let m = Mat::from_fn(n + 1, n + 1, |r, col| {
        if r < n {
            if col < n {
                (lin.jac[(r, col)] - if r == col { 1.0 } else { 0.0 }) * xs
            } else {
                lin.gl[r] * scale
            }
        } else {
            c[col]
        }
    });
    let lu = m.partial_piv_lu();
    let mut w: Vec<f64> = (0..=n).map(|i| 1.0 / (1.0 + i as f64)).collect();
    for _ in 0..4 {
        let z = lu.solve(Mat::from_fn(n + 1, 1, |r, _| w[r]));
        let z: Vec<f64> = (0..=n).map(|i| z[(i, 0)]).collect();
        if !z.iter().all(|v| v.is_finite()) || z.iter().all(|v| *v == 0.0) {
            break;
        }
        w = unit(z);
    }
    // Exactly orthogonal to the parent's chord.
    let wc: f64 = w.iter().zip(&c).map(|(u, v)| u * v).sum();
    let w = unit(w.iter().zip(&c).map(|(u, v)| u - wc * v).collect());
    if !w.iter().all(|v| v.is_finite()) {
        return Err(OrbitError::Model(format!("no crossing direction at the branch point at {}", bif.param)));
    }
    let mut last = None;
    let mut guesses = Guesses::default();
    for s in [1e-3, 1e-2, 3e-2] {
        for sign in [1.0, -1.0] {
            let x: Vec<f64> = (0..n).map(|i| bif.x[i] + sign * s * w[i] * xs).collect();
            let param = bif.param + sign * s * w[n] * scale;
            guesses.tried += 1;
            let (x, param) = match ctx.correct(x.clone(), param, &w, None) {
                Ok((y, l, _)) if ((0..n).map(|i| ((y[i] - x[i]) / xs).powi(2)).sum::<f64>() + ((l - param) / scale).powi(2)).sqrt() <= 3.0 * s => (y, l),
                Ok(_) => {
                    guesses.back += 1;
                    continue;
                }
                Err(e) => {
                    guesses.failed(e);
                    continue;
                }
            };
            let side = if param != bif.param { (param - bif.param).signum() } else { sign * w[n].signum() };
            let end = if side > 0.0 { range.0.max(range.1) } else { range.0.min(range.1) };
            if (end - param) * side <= 0.0 {
                continue;
            }
            let mut o = *opts;
            (o.from, o.to) = (param, end);
            // Where the branch meets the parent again: at one of its branch
            // points, or at `bif`.
            let meets = |f: &Bifurcation| {
                f.kind == BifurcationKind::BranchPoint
                    && parent
                        .bifurcations
                        .iter()
                        .chain(std::iter::once(bif))
                        .any(|g| g.kind == BifurcationKind::BranchPoint && (g.param - f.param).abs() <= 1e-4 * scale && g.x.iter().zip(&f.x).all(|(u, v)| (u - v).abs() <= 1e-2 * xs))
            };
            let mut met = None;
            let stop = &mut |br: &Branch| {
                let f = br.bifurcations.iter().find(|f| meets(f))?;
                met = Some(f.param);
                Some(format!(
                    "met the branch it crossed again at its branch point at param = {}: past it the orbits are the other half of the pair born there (on a symmetric structure, the mirror images of this branch's): not traced",
                    f.param
                ))
            };
            match continuation_until(family, &x, &o, &mut |_| true, stop) {
                Ok(mut br) => {
                    br.rejoins = met;
                    return Ok(br);
                }
                Err(e) => last = Some(e),
            }
        }
    }
    Err(last.unwrap_or_else(|| guesses.error(format!("no crossing branch found beside the branch point at {}", bif.param), "onto another arc (more than 3 offsets from their prediction)")))
}

/// Recognises, on a period-doubled branch, the phase-shifted copy of an
/// orbit it has already traced: the orbits of 2p periods come in pairs
/// `x`, `S(x)` (`S` the map over p periods, which commutes with the map
/// over 2p), and a branch that passes through the period doubling at its
/// other end (the pitchfork of the 2p map) goes on along the copies of its
/// own orbits, listing every bifurcation of the loop a second time.
struct Copies<'a, F: Family> {
    /// The family of p periods.
    single: &'a F,
    /// Scales of the state and the parameter.
    xs: f64,
    ls: f64,
    /// `S(x) − x` of each point checked so far (empty when `S` failed).
    images: Vec<Vec<f64>>,
    /// Where the branch is cut (points kept) and the parameter where it
    /// rejoins the branch of p periods, once a copy is seen (interpolated
    /// between the two points of the crossing; [`rejoin_parameter`]
    /// locates it).
    cut: Option<(usize, Option<f64>)>,
    /// The parameters of the copy seen and of the branch's orbit it copies.
    copy: Option<(f64, f64)>,
}

impl<F: Family> Copies<'_, F> {
    /// Checks the points not yet checked: a point `k` whose image `S(x_k)`
    /// lies on the branch traced before it (within a quarter of a
    /// segment's length of the segment, in the continuation's scaled
    /// coordinates: a chord of a step the tangent turns by less than 25°
    /// over stays within 6 % of its length of the curve; another orbit of
    /// the same parameter is a fixed point of its own, isolated) is a copy.
    /// The branch is cut where it crossed the period doubling — the last
    /// step of the four before `k` over which `S(x) − x` turns back on
    /// itself, the orbit passing through the one of p periods — or before
    /// `k`.
    fn check(&mut self, points: &[BranchPoint]) -> Option<String> {
        if self.cut.is_some() {
            return None;
        }
        while self.images.len() < points.len() {
            let k = self.images.len();
            let p = &points[k];
            let image = self
                .single
                .model(p.param)
                .and_then(|m| Ok(m.flow(0.0, &p.orbit.x, self.single.period(p.param)?, false)?.x))
                .map(|y| y.iter().zip(&p.orbit.x).map(|(a, b)| a - b).collect())
                .unwrap_or_default();
            self.images.push(image);
            if k < 2 || self.images[k].is_empty() {
                continue;
            }
            let y: Vec<f64> = p.orbit.x.iter().zip(&self.images[k]).map(|(x, d)| x + d).collect();
            // A step across the section (an impact moved from one side of
            // the section's time to the other) is a jump of the section
            // state by the impulse, not a piece of the curve: neither a
            // segment to lie near nor a turn of `S(x) − x`.
            let jump = |j: usize| section_jump(&points[j].orbit, &points[j + 1].orbit);
            let Some(on) = (0..k - 1).find(|&j| !jump(j) && self.near_segment(&points[j], &points[j + 1], &y, p.param)) else { continue };
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(u, v)| u * v).sum::<f64>();
            // Within the last four steps: the copy is seen within a step or
            // two of the crossing (the traced copy is there).
            let flip = (k.saturating_sub(4)..k).rev().find(|&j| !self.images[j].is_empty() && !jump(j) && dot(&self.images[j], &self.images[j + 1]) < 0.0);
            let (keep, rejoin) = match flip {
                Some(j) => {
                    let (a, b) = (dot(&self.images[j], &self.images[j]).sqrt(), dot(&self.images[j + 1], &self.images[j + 1]).sqrt());
                    (j + 1, Some(points[j].param + a / (a + b) * (points[j + 1].param - points[j].param)))
                }
                None => (k, None),
            };
            self.cut = Some((keep, rejoin));
            self.copy = Some((p.param, points[on].param));
            let at = points[keep - 1].param;
            return Some(match rejoin {
                Some(_) => format!(
                    "rejoined the branch of half its period (at its period doubling) between param = {at} and {}; past it the orbits are the phase-shifted copies of the branch's own (the image after half the period of the orbit at param = {} is the branch's at {}): not traced again",
                    points[keep].param, p.param, points[on].param
                ),
                None => format!(
                    "ended at param = {at}: the next orbit is the phase-shifted copy of one the branch has passed through (the image after half the period of the orbit at param = {} is the branch's at {}): not traced again",
                    p.param, points[on].param
                ),
            });
        }
        None
    }

    /// Whether `(y, λ)` lies within a quarter of the segment's length of
    /// the segment from `a` to `b` (scaled coordinates).
    fn near_segment(&self, a: &BranchPoint, b: &BranchPoint, y: &[f64], param: f64) -> bool {
        let scaled = |x: &[f64], l: f64| -> Vec<f64> { x.iter().map(|v| v / self.xs).chain(std::iter::once(l / self.ls)).collect() };
        let (pa, pb, py) = (scaled(&a.orbit.x, a.param), scaled(&b.orbit.x, b.param), scaled(y, param));
        let ab: Vec<f64> = pa.iter().zip(&pb).map(|(u, v)| v - u).collect();
        let len2: f64 = ab.iter().map(|v| v * v).sum();
        if !(len2 > 0.0) {
            return false;
        }
        let w = (pa.iter().zip(&py).zip(&ab).map(|((u, v), d)| (v - u) * d).sum::<f64>() / len2).clamp(0.0, 1.0);
        let d2: f64 = pa.iter().zip(&ab).zip(&py).map(|((u, d), v)| (u + w * d - v).powi(2)).sum();
        d2 <= 0.0625 * len2
    }
}

/// Whether the step from `a` to `b` crossed the section with an impact
/// ([`across_section`]): one contact has fewer impacts within 1e-2 of a
/// period after the section and more within 1e-2 before its end in one
/// orbit than in the other (the impact moved across the section's time).
fn section_jump(a: &Orbit, b: &Orbit) -> bool {
    // A contact's impacts near the period's start and near its end.
    let near = |o: &Orbit, c: usize| -> (usize, usize) {
        o.events.iter().filter(|e| e.kind == EventKind::Impact && e.contact == c).fold((0, 0), |(s, f), e| {
            let ph = (e.t - o.t0) / o.period;
            (s + usize::from(ph < 1e-2), f + usize::from(ph > 1.0 - 1e-2))
        })
    };
    a.events.iter().chain(&b.events).filter(|e| e.kind == EventKind::Impact).any(|e| {
        let ((sa, fa), (sb, fb)) = (near(a, e.contact), near(b, e.contact));
        (sa > sb && fa < fb) || (sa < sb && fa > fb)
    })
}

/// Where a period-doubled branch rejoins the branch of half its period,
/// seen between its points `a` and `b` (the phase-shift distance
/// `S(x) − x`, `S` the map over p periods, turns back on itself between
/// them: the orbit passes through the one of p periods). That point is a
/// period doubling of the p-periodic branch, and is located as one: the
/// parameter where a real multiplier of the p-periodic orbit (Newton on
/// `S` from `a`'s and `b`'s states) is −1, by secant steps in the
/// parameter, each a Newton solve from the last orbit, to 1e-14 of the
/// parameter. (The phase-shift distance itself vanishes on the whole
/// p-periodic branch, which crosses the doubled one there: a corrector on
/// the doubled branch near the crossing falls onto it, and a bisection on
/// that distance lands beyond the crossing.) `None` when an orbit cannot be
/// computed or the steps do not converge.
fn rejoin_parameter<F: Family>(single: &F, a: &BranchPoint, b: &BranchPoint, newton: &Newton) -> Option<f64> {
    // The p-periodic orbit at `param` from `guess` and its multiplier
    // nearest −1 (real), plus 1.
    let at = |param: f64, guess: &[f64]| -> Option<(Vec<f64>, f64)> {
        let orbit = periodic_orbit_strict(&single.model(param).ok()?, 0.0, single.period(param).ok()?, guess, newton).ok()?;
        let mu = orbit.multipliers.iter().filter(|m| is_real(m) && m.re < 0.0).map(|m| m.re + 1.0).min_by(|u, v| u.abs().total_cmp(&v.abs()))?;
        Some((orbit.x, mu))
    };
    let (mut l0, (_, mut f0)) = (a.param, at(a.param, &a.orbit.x)?);
    let (mut l1, (mut x1, mut f1)) = (b.param, at(b.param, &b.orbit.x)?);
    for _ in 0..40 {
        if f1 == 0.0 {
            return Some(l1);
        }
        if f0 == f1 {
            return None;
        }
        let next = l1 - f1 * (l1 - l0) / (f1 - f0);
        if !next.is_finite() {
            return None;
        }
        let (x, f) = at(next, &x1)?;
        (l0, f0, l1, x1, f1) = (l1, f1, next, x, f);
        if (l1 - l0).abs() <= 1e-14 * l1.abs().max(1.0) {
            return Some(l1);
        }
    }
    None
}

/// A grazing ahead of a branch ([`impact_beyond_grazing`]): the grazing,
/// the orbits with the new impact away from it (none: the branch ends
/// there), whether that orbit is one the branch passed through, and
/// the searches past the grazing and before it ([`Searches`]: Newton's
/// least residual when none was found).
type Grazed = (Bifurcation, Vec<Point>, bool, [Searches; 2]);

/// The Newton searches for the orbit born at a grazing on one side of it
/// ([`impact_beyond_grazing`]): the smallest residual of those that failed
/// (`‖P(x) − x‖∞` at Newton's last iterate) with the offset where it was
/// reached (a fraction of the parameter's scale, by default the range), and how many failed far from any
/// orbit ([`Searches::failed`]). Once [`FAR_STALLS`] have, the side's
/// remaining searches are skipped.
#[derive(Clone, Copy, Debug)]
struct Searches {
    least: (f64, f64),
    /// Plain Newton's smallest residual (said when the side was given up
    /// before any other search failed).
    plain: (f64, f64),
    far: usize,
}

impl Searches {
    fn new() -> Self {
        Self { least: (f64::INFINITY, 0.0), plain: (f64::INFINITY, 0.0), far: 0 }
    }

    /// Whether the side's searches go on.
    fn open(&self) -> bool {
        self.far < FAR_STALLS
    }

    /// A search at the offset `f` that failed with Newton's last residual
    /// `residual` and its least relative residual `relative`
    /// ([`periodic_orbit_least`]) (`plain`: plain Newton's).
    fn failed(&mut self, f: f64, residual: f64, relative: f64, plain: bool) {
        let slot = if plain { &mut self.plain } else { &mut self.least };
        if residual < slot.0 {
            *slot = (residual, f);
        }
        if relative.is_finite() && relative > far_level(f) {
            self.far += 1;
        }
    }

    /// The residual to say: plain Newton's when the side was given up
    /// before any other search failed.
    fn said(&self) -> (f64, f64) {
        if self.least.0.is_infinite() && !self.open() {
            self.plain
        } else {
            self.least
        }
    }
}

/// Searches (on one side of a grazing) that fail far from any orbit
/// ([`far_level`]) after which the side's remaining searches are skipped.
const FAR_STALLS: usize = 2;

/// The least relative residual above which a search at the offset `f` (a
/// fraction of the parameter's scale from the grazing) that fails counts as far from
/// any orbit: `max(1e-4, 100 f)`. Where an orbit is found at some offset
/// (the oscillator, the chain, `tests/it`), the searches that fail at the
/// others come within `4.9 f` (`1.6e-6` below `f = 1e-6`) of their state
/// (20 times below this); on the paper's beam every search stays above
/// 7.5e-4 (the amplitude run's plain Newton; 7.5 times above this) at
/// every offset (docs/orbits.md, the table).
fn far_level(f: f64) -> f64 {
    (1e2 * f).max(1e-4)
}

/// An orbit without impacts whose branch stops (the corrector fails at
/// every step) because its motion reaches a stop: the grazing parameter as
/// the zero of the orbit's distance to the stops ([`margin`]), and the
/// impacting orbit beyond ([`impact_beyond_grazing`]; `impacts` and
/// `releases` read 0 on both sides when there is none).
fn appearing_impact<F: Family>(ctx: &Ctx<'_, F>, cur: &Point, points: &[BranchPoint], dir: f64) -> Option<Grazed> {
    if cur.orbit.impacts() != 0 || cur.orbit.releases() != 0 || points.len() < 2 {
        return None;
    }
    impact_beyond_grazing(ctx, cur, points, dir, &margin)
}

/// An orbit with impacts whose branch stops because a free flight between
/// them reaches a stop (a further impact appears: the oscillator's flight
/// touching the other stop, or a second, slow impact at the same stop):
/// the grazing parameter as the zero of the orbit's smallest distance to a
/// bound at an interior extremum of a flight ([`flight_margin`]), and the
/// orbit with the further impact beyond ([`impact_beyond_grazing`]; with
/// none, `impacts` and `releases` read the orbit's on both sides).
fn further_impact<F: Family>(ctx: &Ctx<'_, F>, cur: &Point, points: &[BranchPoint], dir: f64) -> Option<Grazed> {
    if cur.orbit.impacts() == 0 || points.len() < 2 {
        return None;
    }
    impact_beyond_grazing(ctx, cur, points, dir, &flight_margin)
}

/// The grazing ahead of `cur` where `measure` (the distance to grazing)
/// reaches 0: its parameter by secant steps on the smooth side (each a
/// Newton solve), then the orbit just beyond it with more impacts (Newton
/// from the grazing orbit's state at parameters `1e-9` … `1e-3` of the
/// parameter's scale (by default the range) past it; its Jacobian grows as the inverse of the new impact's
/// speed, so the nearest that converges is taken, within 1e-2 of the
/// state's scale of the grazing orbit), and from it
/// natural-parameter steps away from the grazing. When none converges the
/// grazing is returned with no orbit beyond (the branch ends there, the
/// event named).
fn impact_beyond_grazing<F: Family>(ctx: &Ctx<'_, F>, cur: &Point, points: &[BranchPoint], dir: f64, measure: Measure<'_, F>) -> Option<Grazed> {
    let smooth = cur.orbit.impacts();
    let prev = &points[points.len() - 2];
    let p0 = ctx.point(prev.orbit.x.clone(), prev.param, &cur.tangent).ok()?;
    let (m0, m1) = (measure(ctx, &p0)?, measure(ctx, cur)?);
    if !(m1 < m0 && m1 >= 0.0) {
        return None;
    }
    // How fast the distance to grazing closes in the parameter: how far
    // past the stop the smooth orbit's flight would reach past the grazing.
    let slope = ((m1 - m0) / (cur.param - p0.param)).abs();
    let step = (cur.param - p0.param).abs();
    let (estimate, p1) = grazing_parameter(ctx, Some((p0, m0)), (cur.clone(), m1), (smooth, measure), None, OnFailure::Stop, dir)?;
    // A grazing no orbit of the smooth side came near (the secant's
    // extrapolation from the last two points, its first Newton solve
    // failed): not located, not named. From an orbit whose impact sits on
    // the section (the corrector stalls there, its steps shrinking to
    // 1e-6 of the range) the distance to grazing, barely changing, was
    // extrapolated 0.53 beyond the branch's last point and named a
    // grazing where the branch ended (at 0.8687, the orbit's grazing
    // between 0.880 and 0.885).
    if (estimate - p1.param).abs() > 2.0 * step {
        return None;
    }
    let lerp = |p: &Point, q: &Point, w: f64| -> Vec<f64> { p.x.iter().zip(&q.x).map(|(x, y)| x + w * (y - x)).collect() };
    let side = (estimate - cur.param).signum();
    // The searches past the grazing and before it: their smallest
    // residual, said when the branch ends there, and how many failed far
    // from any orbit (after [`FAR_STALLS`] the side's others are skipped).
    let (mut past, mut before) = (Searches::new(), Searches::new());
    // Plain Newton from the grazing orbit's state, then Newton keeping the
    // guess's new impacts (the square-root side: [`periodic_orbit_keeping`])
    // at each offset in turn. From an orbit without impacts, plain Newton at
    // every offset first (the nearest orbit it finds is the one it found
    // before the keeping search was added), then Newton keeping from that
    // state and from it pushed past the stop: the impacting orbit born at
    // the grazing, one slow impact a period near the grazing phase.
    let offsets = [1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3];
    // The searches from seeds give up when Newton stalls far from an orbit
    // ([`Newton::stall`]; converging ones halve the residual every few
    // iterations): on a map that has no orbit near (the paper's beam, each
    // iteration a run of a map with many impacts) the rest of the
    // iterations are the cost of a search that fails. And once two
    // searches on a side have failed far from any orbit ([`far_level`]:
    // the beam's, at every offset), the side's others are not run.
    let stalling = ContinuationOptions { newton: Newton { stall: SEARCH_STALL, ..ctx.opts.newton }, ..*ctx.opts };
    let search = Ctx { opts: &stalling, ..*ctx };
    // The grazing orbit's push past the stop, the same at every offset:
    // computed once, when first needed.
    let push = std::cell::OnceCell::new();
    let param_at = |f: f64| estimate + side * f * ctx.ls;
    // An orbit past the grazing is the one born there only near the
    // grazing orbit: within 1e-2 of the state's scale. The period-3
    // oscillator (cosine forcing, stops −1 and 0.5, e = 0.3) from Ω = 4 to
    // 1 found, 1e-3 of the range (3e-3 in Ω) past its grazing at 3.4277,
    // a 2-impact orbit of another arc 0.022 away (3e-2 of the scale) and
    // went on along it, where the runs to 3 and to 2 turned back onto the
    // orbits born at the grazing and listed their fold and period doubling
    // (`tests/it/scale.rs`).
    let near = |p: &Point| p.x.iter().zip(&p1.x).fold(0.0f64, |a, (u, v)| a.max((u - v).abs())) <= 1e-2 * ctx.xs;
    let plain = |f: f64, past: &mut Searches| match solve_at_or(&search, &p1.x, param_at(f), side) {
        Ok(p) => (p.orbit.impacts() > smooth && near(&p)).then_some(p),
        Err(miss) => {
            past.failed(f, miss.residual, miss.relative, true);
            None
        }
    };
    let keeping = |f: f64, past: &mut Searches| {
        let param = param_at(f);
        let miss = match solve_keeping_or(&search, &p1.x, param, side, smooth) {
            Ok(p) if near(&p) => return Some(p),
            Ok(_) => Miss::NONE,
            Err(miss) => miss,
        };
        past.failed(f, miss.residual, miss.relative, false);
        let push = (smooth == 0 && past.open()).then(|| push.get_or_init(|| push_of(&search, &p1)).as_ref()).flatten()?;
        past_the_stop_along(&search, &p1, push, param, slope * (param - estimate).abs(), side, past, f).filter(near)
    };
    let mut beyond = None;
    if smooth > 0 {
        for &f in &offsets {
            if !past.open() {
                break;
            }
            beyond = plain(f, &mut past).or_else(|| past.open().then(|| keeping(f, &mut past)).flatten());
            if beyond.is_some() {
                break;
            }
        }
    } else {
        for &f in &offsets {
            if !past.open() {
                break;
            }
            beyond = plain(f, &mut past);
            if beyond.is_some() {
                break;
            }
        }
        for &f in &offsets {
            if beyond.is_some() || !past.open() {
                break;
            }
            beyond = keeping(f, &mut past);
        }
    }
    // None past it: the impacting orbit on the near side (the branch turns
    // back at the grazing, where the two orbits meet: a nonsmooth fold),
    // from the smooth orbit there pushed past the stop. A free orbit's
    // grazing has it there when the square-root map's fixed point lies on
    // that side (theory §12.3: the oscillator between Ω = ω and 2ω).
    // Nearer than 1e-6 of the range, the new impact is too slow for Newton
    // to converge: the map's round-off grows as the inverse of its speed.
    if beyond.is_none() {
        for f in [1e-6, 1e-5, 1e-4, 1e-3, 1e-2] {
            if !before.open() {
                break;
            }
            let param = estimate - side * f * ctx.ls;
            let Some(near) = solve_at(ctx, &p1.x, param, -side).filter(|p| p.orbit.impacts() == smooth) else { continue };
            let found = past_the_stop(&search, &near, param, 0.0, -side, &mut before, f);
            if found.is_some() {
                beyond = found;
                break;
            }
        }
    }
    let least = [past, before];
    let bif = Bifurcation {
        param: estimate,
        kind: BifurcationKind::Grazing,
        mu: critical(BifurcationKind::Grazing, &p1),
        impacts: (smooth, beyond.as_ref().map_or(smooth, |b| b.orbit.impacts())),
        releases: (cur.orbit.releases(), beyond.as_ref().map_or(cur.orbit.releases(), |b| b.orbit.releases())),
        between: (points.len() - 1, points.len()),
        x: p1.x.clone(),
        mark: None,
    };
    let Some(b) = beyond else { return Some((bif, Vec::new(), false, least)) };
    // An orbit the branch has already passed through (it came to this
    // grazing along the orbit with the further impact, and crossed to the
    // smooth one at it): going on from it would retrace the branch.
    if retraces(points, &b, &p1) {
        return Some((bif, Vec::new(), true, least));
    }
    let side = (b.param - estimate).signum();
    // Turned back: the smooth orbit is as near as the orbit is to the
    // grazing, and the corrector (plain Newton) would fall onto it.
    let turned = side * (estimate - cur.param).signum() < 0.0;
    // Away from the grazing by natural-parameter steps doubling
    // (each from the last two orbits' extrapolation) until the new impact's
    // speed has grown a hundredfold (turned back: and the orbit is 1 % of
    // the range from the grazing): the arclength steps take over there.
    let v0 = b.orbit.slowest_impact().unwrap_or(0.0);
    let mut away = vec![b];
    let (mut dist, mut misses) = ((away[0].param - estimate).abs(), 0);
    let mut ignored = Searches::new();
    for _ in 0..30 {
        let last = &away[away.len() - 1];
        if last.orbit.slowest_impact().unwrap_or(0.0) >= 100.0 * v0 && (!turned || (last.param - estimate).abs() >= 1e-2 * ctx.ls) {
            break;
        }
        dist *= 2.0;
        let param = estimate + side * dist;
        // Linear in the distance to the grazing: from the grazing orbit
        // and the last one, then from the last two.
        let before = if away.len() == 1 { &p1 } else { &away[away.len() - 2] };
        let guess = lerp(before, last, (param - before.param) / (last.param - before.param));
        let k = away[0].orbit.impacts();
        let found = solve_at(ctx, &guess, param, side).filter(|p| p.orbit.impacts() == k).or_else(|| solve_keeping(ctx, &guess, param, side, k - 1).filter(|p| p.orbit.impacts() == k));
        // Turned back: the smooth orbit there, pushed past the stop.
        let found = found.or_else(|| {
            turned
                .then(|| solve_at(ctx, &guess, param, side).filter(|p| p.orbit.impacts() == smooth))
                .flatten()
                .and_then(|near| past_the_stop(ctx, &near, param, 0.0, side, &mut ignored, f64::INFINITY))
                .filter(|p| p.orbit.impacts() == k)
        });
        match found {
            Some(p) => away.push(p),
            // Turned back, a miss near the grazing (Newton at the map's
            // round-off there) is skipped, at most 4 times.
            None if turned && misses < 4 => misses += 1,
            None => break,
        }
    }
    Some((bif, away, false, least))
}

/// Iterations without the residual halving after which a search for the
/// orbit born at a grazing gives up ([`Newton::stall`]): the searches that
/// converge on the oscillator and the chain (`tests/it`) go at most 6.
const SEARCH_STALL: usize = 10;

/// The least residuals of the Newton searches past a grazing and before
/// it, as the end of a branch says them.
fn residuals(least: [Searches; 2], unit: &str) -> String {
    let say = |s: &Searches| {
        let (r, f) = s.said();
        let given_up = if s.open() { String::new() } else { format!(", the rest given up after {FAR_STALLS} searches failed far from any orbit") };
        if r.is_finite() {
            format!("{r:.1e} (at {f:e} of {unit}{given_up})")
        } else {
            "none (no start with the impact)".into()
        }
    };
    format!("; Newton's least residual past it {}, before it {}", say(&least[0]), say(&least[1]))
}

/// Whether `b` lies on the branch so far: between two of its points with
/// `b`'s impacts that bracket its parameter, their linear interpolation
/// there is within 1 % of `b`'s distance from `p1` (the grazing orbit, or
/// the point it jumped from: an orbit that differs from the branch's does
/// by as much as it differs from `p1`; the interpolation's error is of the
/// square of the spacing).
fn retraces(points: &[BranchPoint], b: &Point, p1: &Point) -> bool {
    let scale = b.x.iter().zip(&p1.x).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
    points.windows(2).any(|w| {
        let (q, r) = (&w[0], &w[1]);
        if q.orbit.impacts() != b.orbit.impacts() || r.orbit.impacts() != b.orbit.impacts() || (q.param - b.param) * (r.param - b.param) > 0.0 || q.param == r.param {
            return false;
        }
        let s = (b.param - q.param) / (r.param - q.param);
        let gap = q.orbit.x.iter().zip(&r.orbit.x).zip(&b.x).fold(0.0f64, |a, ((u, v), x)| a.max((u + s * (v - u) - x).abs()));
        gap <= 1e-2 * scale
    })
}

/// The change of the impacts or held phases between `cur` and the trial
/// `p` (a step `ds` along `cur`'s tangent), located by bisection on the
/// arclength (the bracket's end on `cur`'s side), and whether it is a
/// corner of `cur`'s arc: the bracket's ends meet (within 1e-2 of the
/// step), where an orbit fallen onto another arc leaves them as far apart
/// as the two arcs are.
fn corner_bracket<F: Family>(ctx: &Ctx<'_, F>, cur: &Point, p: &Point, ds: f64) -> (Point, bool) {
    let count = |q: &Point| (q.orbit.impacts(), q.orbit.releases());
    let (at, far) = bracket(ctx, cur, ds, p, |q| (count(q).0 * 1000 + count(q).1) as f64, |a, b| count(a) != count(b));
    let meets = arclength(ctx, &at, &far) <= 1e-2 * ds;
    (at, meets)
}

/// At a corner of the branch (the corrector fails at every step): an orbit
/// just beyond `cur` in the parameter with another number of impacts or
/// held phases (natural-parameter Newton from `cur`'s state), the change
/// located between by bisection in the parameter (a trial that does not
/// converge counts as beyond).
fn corner<F: Family>(ctx: &Ctx<'_, F>, cur: &Point, points: &[BranchPoint], dir: f64) -> Option<(Bifurcation, Point)> {
    let trend = points.len().checked_sub(2).map_or(dir, |i| (cur.param - points[i].param).signum());
    let same = |p: &Point| p.orbit.impacts() == cur.orbit.impacts() && p.orbit.releases() == cur.orbit.releases();
    let mut beyond = None;
    for f in [1e-7, 1e-6, 1e-5, 1e-4, 1e-3] {
        let param = cur.param + trend * f * ctx.ls;
        if let Some(p) = solve_at(ctx, &cur.x, param, trend) {
            if !same(&p) {
                beyond = Some(p);
                break;
            }
        }
    }
    let b = beyond?;
    let (mut lo, mut hi) = (cur.param, b.param);
    let mut hi_x = b.x.clone();
    for _ in 0..60 {
        if (hi - lo).abs() <= 1e-14 * ctx.ls.max(hi.abs()) {
            break;
        }
        let mid = 0.5 * (lo + hi);
        match solve_at(ctx, &cur.x, mid, trend) {
            Some(p) if same(&p) => lo = mid,
            Some(p) => (hi, hi_x) = (mid, p.x),
            None => hi = mid,
        }
    }
    let _ = hi_x;
    let kind = if b.orbit.impacts() != cur.orbit.impacts() { BifurcationKind::Grazing } else { BifurcationKind::Sticking };
    let bif = Bifurcation {
        param: 0.5 * (lo + hi),
        kind,
        mu: critical(kind, cur),
        impacts: (cur.orbit.impacts(), b.orbit.impacts()),
        releases: (cur.orbit.releases(), b.orbit.releases()),
        between: (points.len() - 1, points.len()),
        x: cur.x.clone(),
        mark: None,
    };
    Some((bif, b))
}

/// When an impact of `cur`'s orbit falls within 1e-4 of a period of the
/// section's time, the orbit with that impact on the other side of the
/// section: its section state is `cur`'s with the impulse added (the
/// impact moves before the section) or taken back (after it), sought a
/// little further along the branch's direction in the parameter (at 0.1,
/// 1 and 4 times the last step, then 1e-7, 1e-6 and 1e-5 of the
/// parameter's scale, by default the range).
///
/// Only the same orbit with that impact moved is taken: as many impacts
/// and held phases per period as `cur`, an impact of that contact within
/// 1e-2 of a period of the section on the other side, and the state within
/// a tenth of the impulse's jump (plus 1e-3 of the state's scale) of the
/// guess. Newton from the guess at a parameter where the impact lies
/// within round-off of the section may land on another orbit of the same
/// parameter: on the oscillator between symmetric stops (the asymmetric
/// orbit from Ω = 1.5 down) the stable 3-impact orbit's impact at −1
/// reached the section at Ω = 1.32838440; Newton 2.3e-9 further on landed
/// on the stable 2-impact orbit 0.3 away, which was taken (its impacts at
/// both stops, one "on the other side"), and the branch went back along
/// the 2-impact arc it had traced, listing nothing at the jump
/// (`tests/it/section.rs`). 1e-7 of the range on, Newton from the same
/// guess finds the 3-impact orbit, its impact at 6e-8 of a period before
/// the section.
fn across_section<F: Family>(ctx: &Ctx<'_, F>, cur: &Point, points: &[BranchPoint], dir: f64) -> Option<Point> {
    let period = cur.orbit.period;
    let model = ctx.family.model(cur.param).ok()?;
    let trend = points.len().checked_sub(2).map_or(dir * 1e-6 * ctx.ls, |i| cur.param - points[i].param);
    for e in cur.orbit.events.iter().filter(|e| e.kind == EventKind::Impact) {
        let phase = (e.t - cur.orbit.t0) / period;
        let sign = if phase < 1e-4 {
            1.0
        } else if phase > 1.0 - 1e-4 {
            -1.0
        } else {
            continue;
        };
        let guess = model.with_impulse(&cur.x, e.contact, e.impulse, sign);
        let jump = guess.iter().zip(&cur.x).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
        let step = trend.abs().max(1e-9 * ctx.ls);
        let further = [1e-7, 1e-6, 1e-5].map(|f| f * ctx.ls).into_iter().filter(|d| *d > 4.0 * step);
        for d in [0.1 * step, step, 4.0 * step].into_iter().chain(further) {
            let param = cur.param + d * trend.signum();
            if let Some(p) = solve_at(ctx, &guess, param, cur.tangent[ctx.n].signum()) {
                let moved = p.orbit.events.iter().any(|q| {
                    q.kind == EventKind::Impact && q.contact == e.contact && {
                        let ph = (q.t - p.orbit.t0) / period;
                        if sign > 0.0 {
                            ph > 1.0 - 1e-2
                        } else {
                            ph < 1e-2
                        }
                    }
                });
                let same = p.orbit.impacts() == cur.orbit.impacts() && p.orbit.releases() == cur.orbit.releases();
                let near = p.x.iter().zip(&guess).fold(0.0f64, |a, (u, v)| a.max((u - v).abs())) <= 0.1 * jump + 1e-3 * ctx.xs;
                if moved && same && near {
                    return Some(p);
                }
            }
        }
    }
    None
}

/// A fixed point of the map at the parameter `param` from `guess`
/// (natural-parameter Newton), as a branch point oriented along `dir`.
fn solve_at<F: Family>(ctx: &Ctx<'_, F>, guess: &[f64], param: f64, dir: f64) -> Option<Point> {
    solve_at_or(ctx, guess, param, dir).ok()
}

/// A Newton search that failed: its last residual `‖P(x) − x‖∞` (infinite
/// when the map or the model failed, or the start lacked the impacts to
/// keep) and its least relative one ([`periodic_orbit_least`]).
#[derive(Clone, Copy, Debug)]
struct Miss {
    residual: f64,
    relative: f64,
}

impl Miss {
    const NONE: Self = Self { residual: f64::INFINITY, relative: f64::INFINITY };
}

/// [`solve_at`], or how near Newton came when it fails.
fn solve_at_or<F: Family>(ctx: &Ctx<'_, F>, guess: &[f64], param: f64, dir: f64) -> Result<Point, Miss> {
    let (model, period) = ctx.family.model_and_period(param).map_err(|_| Miss::NONE)?;
    let mut relative = f64::INFINITY;
    let orbit = periodic_orbit_least(&model, 0.0, period, guess, &ctx.opts.newton, &mut relative).map_err(|e| miss(e, relative))?;
    let mut seed = vec![0.0; ctx.n + 1];
    seed[ctx.n] = dir;
    ctx.point(orbit.x, param, &seed).map_err(|_| Miss::NONE)
}

/// The [`Miss`] of a Newton that failed with `e`, its least relative
/// residual `relative`.
fn miss(e: OrbitError, relative: f64) -> Miss {
    match e {
        OrbitError::NoConvergence { residual, .. } if residual.is_finite() => Miss { residual, relative },
        _ => Miss { relative, ..Miss::NONE },
    }
}

/// [`solve_at`] for an orbit with the impacts of `guess`'s own period at
/// `param` when it has more than `fewer` of them: Newton keeping them
/// ([`periodic_orbit_keeping`]).
fn solve_keeping<F: Family>(ctx: &Ctx<'_, F>, guess: &[f64], param: f64, dir: f64, fewer: usize) -> Option<Point> {
    solve_keeping_or(ctx, guess, param, dir, fewer).ok()
}

/// [`solve_keeping`], or how near Newton came when it fails ([`Miss`]:
/// infinite when the guess has no more than `fewer` impacts or the map
/// fails).
fn solve_keeping_or<F: Family>(ctx: &Ctx<'_, F>, guess: &[f64], param: f64, dir: f64, fewer: usize) -> Result<Point, Miss> {
    let (model, period) = ctx.family.model_and_period(param).map_err(|_| Miss::NONE)?;
    let k = model.flow(0.0, guess, period, false).map_err(|_| Miss::NONE)?.events.iter().filter(|e| e.kind == EventKind::Impact && e.velocity_before != 0.0).count();
    if k <= fewer {
        return Err(Miss::NONE);
    }
    let mut relative = f64::INFINITY;
    let orbit = periodic_orbit_keeping(&model, 0.0, period, guess, &ctx.opts.newton, k, &mut relative).map_err(|e| miss(e, relative))?;
    let mut seed = vec![0.0; ctx.n + 1];
    seed[ctx.n] = dir;
    ctx.point(orbit.x, param, &seed).map_err(|_| Miss::NONE)
}

/// The orbit with a further impact beside the smooth orbit `near` (at
/// `param`, `near`'s parameter or one just past a grazing): Newton keeping
/// the impacts ([`periodic_orbit_keeping`]) from `near`'s state moved along
/// the gradient of its flight's extremum ([`Model::flight_extremum`]; an
/// orbit without impacts: its extremum over the period) until the flight
/// reaches past the stop by 1, 4 or 1/4 times its distance to it, or to
/// `reach` when that is larger (the grazing orbit, its distance 0, moved
/// as far as the flight would reach past the stop at `param`). `None` for
/// an extremum of a massless contact dof (not in the state). Each Newton
/// that fails counts in `searches`, as a search at the offset `f` (the
/// remaining ones skipped once it gives up; `f` infinite: never).
fn past_the_stop<F: Family>(ctx: &Ctx<'_, F>, near: &Point, param: f64, reach: f64, dir: f64, searches: &mut Searches, f: f64) -> Option<Point> {
    past_the_stop_along(ctx, near, &push_of(ctx, near)?, param, reach, dir, searches, f)
}

/// The extremum of `near`'s flight nearest a bound and the gradient of its
/// displacement in `near`'s state, with the squared norm of that gradient:
/// how [`past_the_stop`] pushes `near` past the stop (computed once for a
/// seed tried at several parameters).
struct Push {
    extremum: Extremum,
    grad: Vec<f64>,
    norm2: f64,
}

/// [`Push`] for `near`: `None` as [`past_the_stop`] says.
fn push_of<F: Family>(ctx: &Ctx<'_, F>, near: &Point) -> Option<Push> {
    let model = ctx.family.model(near.param).ok()?;
    let extremum = model.flight_extremum(0.0, &near.x, near.orbit.period).ok()??;
    let grad = model.displacement_gradient(0.0, &near.x, extremum.t, extremum.contact).ok()??;
    let norm2: f64 = grad.iter().map(|g| g * g).sum();
    (norm2 > 0.0 && norm2.is_finite()).then_some(Push { extremum, grad, norm2 })
}

/// [`past_the_stop`] with `near`'s [`Push`] given.
#[allow(clippy::too_many_arguments)]
fn past_the_stop_along<F: Family>(ctx: &Ctx<'_, F>, near: &Point, push: &Push, param: f64, reach: f64, dir: f64, searches: &mut Searches, f: f64) -> Option<Point> {
    let Push { extremum: e, ref grad, norm2 } = *push;
    let toward = if e.upper { 1.0 } else { -1.0 };
    let smooth = near.orbit.impacts();
    let distance = e.distance.max(reach);
    for beyond in [1.0, 4.0, 0.25] {
        if !searches.open() {
            break;
        }
        let dq = toward * distance * (1.0 + beyond);
        let guess: Vec<f64> = near.x.iter().zip(grad.iter()).map(|(x, g)| x + dq * g / norm2).collect();
        match solve_keeping_or(ctx, &guess, param, dir, smooth) {
            Ok(p) => return Some(p),
            Err(miss) => searches.failed(f, miss.residual, miss.relative, false),
        }
    }
    None
}

/// The smallest distance of `p`'s orbit to a bound over its period.
fn margin<F: Family>(ctx: &Ctx<'_, F>, p: &Point) -> Option<f64> {
    ctx.family.model(p.param).ok().and_then(|m| m.margin(0.0, &p.x, p.orbit.period).ok())
}

/// The smallest distance of `p`'s orbit to a bound at an interior extremum
/// of a free flight over its period ([`Model::flight_margin`]): 0 where a
/// flight between two impacts grazes a stop.
fn flight_margin<F: Family>(ctx: &Ctx<'_, F>, p: &Point) -> Option<f64> {
    ctx.family.model(p.param).ok().and_then(|m| m.flight_margin(0.0, &p.x, p.orbit.period).ok())
}

/// The distance to grazing a bound of a point's orbit ([`margin`] or
/// [`flight_margin`]).
type Measure<'a, F> = &'a dyn Fn(&Ctx<'_, F>, &Point) -> Option<f64>;

/// What [`grazing_parameter`] does when a trial is not an orbit of the
/// smooth side (Newton fails, or the orbit has the grazing impact; for
/// [`OnFailure::Shorten`], also an orbit whose margin is not finite).
#[derive(Clone, Copy, PartialEq, Eq)]
enum OnFailure {
    /// The search ends: its steps stop 0.9 of the way to each secant
    /// estimate, so as to stay on the smooth side.
    Stop,
    /// The step is shortened (the trial becomes the nearest parameter known
    /// to be beyond) and tried again, at most 30 times in a row: full secant
    /// steps, never past that parameter.
    Shorten,
}

/// The grazing parameter from the smooth side of a grazing — the orbits
/// with `smooth` impacts, which do not have the grazing impact and are
/// smooth in the parameter — as the zero of `measure` (the orbit's
/// smallest distance to a bound, [`margin`], or that of its flights
/// between impacts, [`flight_margin`]): secant steps, each a Newton solve from the
/// state extrapolated from the last two orbits. Starts from `p1` (and `p0`
/// with their margins); `beyond` is `(first estimate, a parameter known to
/// be past the grazing)`, with which the first step goes halfway there
/// (for [`OnFailure::Shorten`]; [`OnFailure::Stop`] starts from the secant
/// of `p0`, `p1`). Returns the estimate and the last orbit of the smooth
/// side; `None` if a margin cannot be computed.
fn grazing_parameter<F: Family>(
    ctx: &Ctx<'_, F>,
    p0: Option<(Point, f64)>,
    p1: (Point, f64),
    (smooth, measure): (usize, Measure<'_, F>),
    beyond: Option<(f64, f64)>,
    fail: OnFailure,
    dir: f64,
) -> Option<(f64, Point)> {
    let lerp = |p: &Point, q: &Point, w: f64| -> Vec<f64> { p.x.iter().zip(&q.x).map(|(x, y)| x + w * (y - x)).collect() };
    let (mut p1, mut m1) = p1;
    let (mut p0, mut m0) = p0.unwrap_or_else(|| (p1.clone(), f64::NAN));
    let secant = |p0: &Point, m0: f64, p1: &Point, m1: f64| p1.param - m1 * (p1.param - p0.param) / (m1 - m0);
    let (mut estimate, mut limit) = match beyond {
        Some((first, limit)) => (first, limit),
        None => (secant(&p0, m0, &p1, m1), f64::NAN),
    };
    let first = estimate;
    let (iterations, tiny) = if fail == OnFailure::Stop { (40, 1e-14) } else { (60, 1e-15) };
    let mut tries = 0;
    for k in 0..iterations {
        let next = match fail {
            OnFailure::Stop => {
                if m1 == 0.0 || m0 == m1 {
                    break;
                }
                estimate = secant(&p0, m0, &p1, m1);
                if (estimate - p1.param).abs() <= tiny * ctx.ls.max(estimate.abs()) {
                    break;
                }
                // Short of the estimate, on the smooth side.
                p1.param + 0.9 * (estimate - p1.param)
            }
            OnFailure::Shorten => {
                let mut next = if k == 0 || m0 == m1 || !m0.is_finite() {
                    // First step: halfway toward the nearest orbit beyond.
                    p1.param + 0.5 * (limit - p1.param)
                } else {
                    secant(&p0, m0, &p1, m1)
                };
                // Never past the nearest orbit beyond.
                if (next - limit) * (p1.param - limit) <= 0.0 {
                    next = p1.param + 0.5 * (limit - p1.param);
                }
                if (next - p1.param).abs() <= tiny * ctx.ls.max(next.abs()) || m1 == 0.0 {
                    estimate = next;
                    break;
                }
                next
            }
        };
        let guess = if m0.is_finite() { lerp(&p0, &p1, (next - p0.param) / (p1.param - p0.param)) } else { p1.x.clone() };
        let found = match solve_at(ctx, &guess, next, dir) {
            Some(p) if p.orbit.impacts() == smooth => Some((measure(ctx, &p)?, p)),
            _ => None,
        };
        match found {
            // Shortening, a margin without a finite value (a flight
            // without an interior extremum: Newton landed on an orbit of
            // another arc, past the grazing) is a failed trial: its secant
            // would be NaN, and every later one with it.
            Some((m, p)) if m.is_finite() || fail == OnFailure::Stop => {
                (p0, m0, p1, m1) = (p1, m1, p, m);
                if fail == OnFailure::Shorten {
                    estimate = if m0.is_finite() && m0 != m1 { secant(&p0, m0, &p1, m1) } else { p1.param };
                    tries = 0;
                }
            }
            _ if fail == OnFailure::Stop => break,
            _ => {
                tries += 1;
                if tries > 30 {
                    break;
                }
                limit = next;
            }
        }
    }
    // A margin without a finite value (a flight left without an interior
    // extremum) makes the secant NaN: the first estimate stands (the
    // extrapolation that brought the search here), never a NaN parameter.
    if !estimate.is_finite() && first.is_finite() {
        estimate = first;
    }
    Some((estimate, p1))
}

/// The last two orbits `a`, `b` before a grazing ahead of them (the
/// slowest impact's speed extrapolated linearly to 0 at `graze`, `step`
/// from `b`), brought nearer it along their own arc until that
/// extrapolation holds: halfway toward `graze` (the corrector at that
/// parameter from `b`'s tangent), the speed there extrapolated again with
/// `b`; while the new estimate moves by more than 1e-2 of the step (the
/// offset of [`graze`]'s first search beyond), the two orbits nearer it
/// are kept and the next halfway step taken (at most 30 times). Stops
/// where the corrector fails, or finds an orbit with other impacts or not
/// slowing down.
/// Returns the two orbits, the grazing extrapolated from them and its
/// distance from the last.
///
/// The linear extrapolation from far off lands the jump past a narrow arc:
/// the oscillator between stops ±1 (`data/scenes/oscillator-two-stops.
/// toml`) loses the slow impact of its asymmetric 3-impact orbits at Ω =
/// 1.0383070501555, whose 2-impact orbits beyond meet the symmetric ones
/// at a branch point 6.6e-4 below it; from Ω = 1.0574 (speed 0.041) the
/// extrapolation said 1.036678 and the jump landed on a symmetric orbit
/// past the branch point (`tests/it/graze_approach.rs`).
fn approach<F: Family>(ctx: &Ctx<'_, F>, a: &Point, b: &Point, graze: f64) -> (Point, Point, f64, f64) {
    let (mut a, mut b, mut graze) = (a.clone(), b.clone(), graze);
    for _ in 0..30 {
        let (Some(vb), step) = (b.orbit.slowest_impact(), (graze - b.param).abs()) else { break };
        let m = b.param + 0.5 * (graze - b.param);
        let Some(p) = on_tangent(ctx, &b, m) else { break };
        let Some(vp) = p.orbit.slowest_impact().filter(|v| *v < vb && p.orbit.impacts() == b.orbit.impacts()) else { break };
        let next = m + (m - b.param) / (vb - vp) * vp;
        if !next.is_finite() || (next - graze).abs() <= 1e-2 * step {
            break;
        }
        (a, b, graze) = (b, p, next);
    }
    let step = (graze - b.param).abs();
    (a, b, graze, step)
}

/// The orbit of `b`'s arc at `param`: `b`'s tangent predicts it, the
/// corrector solves on the plane of that parameter. `None` where the
/// tangent has no component along the parameter or the corrector fails.
fn on_tangent<F: Family>(ctx: &Ctx<'_, F>, b: &Point, param: f64) -> Option<Point> {
    let n = ctx.n;
    let tl = b.tangent[n] * ctx.ls;
    if tl.abs() < 1e-12 * ctx.ls {
        return None;
    }
    let s = (param - b.param) / tl;
    let x: Vec<f64> = (0..n).map(|i| b.x[i] + s * b.tangent[i] * ctx.xs).collect();
    let mut t = vec![0.0; n + 1];
    t[n] = 1.0;
    let (x, p, lin) = ctx.correct(x, param, &t, None).ok()?;
    ctx.point_from(x, p, lin, &b.tangent).ok()
}

/// When the slowest impact of `b` is slowing down toward 0 (the orbit is
/// near grazing: its Jacobian grows as 1/speed and the steps shrink),
/// the grazing parameter extrapolated from `a`, `b`: an orbit is sought
/// just beyond it, and if one is found with another number of impacts,
/// the grazing is located between by bisection in the parameter (each
/// trial a Newton solve from the interpolated state) and the branch
/// goes on from the orbit beyond.
fn graze<F: Family>(ctx: &Ctx<'_, F>, a: &Point, b: &Point, dir: f64, i: usize, vref: f64) -> Option<(Bifurcation, Point)> {
    let (va, vb) = (a.orbit.slowest_impact()?, b.orbit.slowest_impact()?);
    if !(vb < va && vb < 0.02 * vref) || a.orbit.impacts() != b.orbit.impacts() {
        return None;
    }
    let slope = (b.param - a.param) / (va - vb);
    let graze = b.param + slope * vb;
    let step = (graze - b.param).abs();
    // Only a grazing within a few of the last steps.
    if step > 2.0 * (b.param - a.param).abs() || step == 0.0 {
        return None;
    }
    let lerp = |p: &Point, q: &Point, w: f64| -> Vec<f64> { p.x.iter().zip(&q.x).map(|(x, y)| x + w * (y - x)).collect() };
    let (a, b, graze, step) = approach(ctx, a, b, graze);
    let (a, b) = (&a, &b);
    let sign = (graze - b.param).signum();
    // An orbit just beyond, with another number of impacts.
    let mut across = None;
    for f in [0.01, 0.1, 1.0] {
        let at = graze + sign * f * step.max(1e-6 * ctx.ls);
        let guess = lerp(a, b, (at - a.param) / (b.param - a.param));
        if let Some(p) = solve_at(ctx, &guess, at, dir) {
            if p.orbit.impacts() != b.orbit.impacts() {
                across = Some(p);
                break;
            }
        }
    }
    let c = across?;
    // The grazing parameter, from the side without the grazing impact,
    // where the orbit is smooth in the parameter: the zero of the orbit's
    // smallest distance to a bound (secant steps, each a Newton solve from
    // the extrapolated state). The impacting side's Jacobian grows as the
    // inverse of the impact speed: it is used only for the first estimate.
    // Without impacts left, the distance over the whole period; with
    // impacts left, at the interior extrema of the flights between them.
    let measure: Measure<'_, F> = if c.orbit.impacts() == 0 { &margin } else { &flight_margin };
    let m1 = measure(ctx, &c)?;
    let (estimate, _) = grazing_parameter(ctx, None, (c.clone(), m1), (c.orbit.impacts(), measure), Some((graze, b.param)), OnFailure::Shorten, dir)?;
    // `c` on `b`'s side of the grazing: both orbits exist there, the two
    // arcs of a nonsmooth fold that meet at the grazing (`c`'s flight
    // reaches the stop there, `b`'s slow impact vanishes): the branch
    // turns back along `c`'s arc, away from the grazing. Oriented along
    // `dir` it went on down `c`'s arc to the grazing, turned back there
    // onto `b`'s and traced it again (the oscillator's 2-impact orbit from
    // Ω = 0.905 down, its extrapolated grazing 1.5e-5 short: `c` the
    // 1-impact orbit 3e-6 above the grazing; `tests/it/nonsmooth_fold.rs`).
    let c = if (c.param - estimate) * (b.param - estimate) > 0.0 {
        let mut away = vec![0.0; ctx.n + 1];
        away[ctx.n] = (c.param - estimate).signum();
        ctx.point(c.x.clone(), c.param, &away).ok()?
    } else {
        c
    };
    let lo = b.clone();
    let bif = Bifurcation {
        param: estimate,
        kind: BifurcationKind::Grazing,
        mu: critical(BifurcationKind::Grazing, &lo),
        impacts: (b.orbit.impacts(), c.orbit.impacts()),
        releases: (b.orbit.releases(), c.orbit.releases()),
        between: (i, i + 1),
        x: lo.x.clone(),
        mark: None,
    };
    Some((bif, c))
}

/// A trial from `cur` on an orbit whose slowest impact is slowing down
/// toward 0 (as [`graze`] asks) that converged onto `p`, an orbit of
/// another arc with fewer impacts: `cur`'s arc (its slow impact vanishing)
/// ends at a grazing, where it meets and turns back into an arc whose
/// flight reaches the stop there (a nonsmooth fold), neither continuing
/// past it. When `p` lies on that arc ([`turn_onto`]: on `cur`'s side of
/// the grazing, the two arcs meeting where it is located) the branch goes
/// on from `p`; otherwise from the orbit of that arc found beside the
/// grazing ([`beside_the_grazing`]). `None` when neither is found (the
/// trial is then taken for a jump and the step halved).
///
/// The trial need not land on the arc that turns back: on the period-2
/// orbits of the oscillator (ζ = 0.05, e = 0.3, stop 0.2; `tests/it/
/// period_two.rs`) the 4-impact orbits' third impact vanishes at Ω =
/// 2.3806475600, where they turn back into unstable 3-impact orbits; the
/// trial from 2.381266 landed on a 2-impact orbit at 2.382314, 0.23 away
/// in the state, and was taken: its grazing search found no orbit of its
/// arc near the extrapolated grazing, so the extrapolation itself
/// (2.3806534, 5.9e-6 off) stood as the grazing and "agreed" with itself.
/// The branch ran that arc and skipped the 3-impact orbits and their fold.
/// Now the arcs must meet, and Newton from `cur`'s arc extrapolated to
/// 1e-3 of its distance to the grazing finds the 3-impact orbit there
/// (|μ| 752, 3e-6 from the extrapolation): the grazing is located on its
/// arc at 2.3806475600435 (the transcription's, to 1e-13), the fold at
/// 2.3927018 follows, and at 2.3678525 the same turn back onto the
/// 2-impact orbits (the trial there landed 0.23 away too).
fn turned_back<F: Family>(ctx: &Ctx<'_, F>, points: &[BranchPoint], cur: &Point, p: &Point, vref: f64) -> Option<(Bifurcation, Point)> {
    let prev = &points[points.len().checked_sub(2)?];
    let (va, vb) = (prev.orbit.slowest_impact()?, cur.orbit.slowest_impact()?);
    if !(vb < va && vb < 0.02 * vref) || prev.orbit.impacts() != cur.orbit.impacts() || p.orbit.impacts() >= cur.orbit.impacts() {
        return None;
    }
    // The slowest impact's speed extrapolated linearly to 0.
    let graze = cur.param + (cur.param - prev.param) / (va - vb) * vb;
    if (p.param - graze) * (cur.param - graze) > 0.0 {
        if let Some(turned) = turn_onto(ctx, points, cur, p, graze, cur.param) {
            return Some(turned);
        }
    }
    let q = beside_the_grazing(ctx, points, cur, graze)?;
    // Its grazing search never past `cur`'s grazing mirrored (where the
    // turning arc has no orbit).
    turn_onto(ctx, points, cur, &q, graze, graze - (cur.param - graze))
}

/// The grazing where `cur`'s arc (its slowest impact vanishing, `graze`
/// that speed's linear extrapolation to 0) turns back into `p`'s (fewer
/// impacts, on the same side), located on `p`'s arc as the zero of its
/// distance to grazing ([`margin`], [`flight_margin`]: secant steps, never
/// past `limit`, as [`graze`] does), and the branch's point at `p`,
/// oriented away from it. Only where the two arcs meet there: the grazing
/// within `cur`'s distance from `graze`, `p` on `cur`'s side of it, and
/// the orbit of `p`'s arc nearest the grazing within 1e-2 of the state's
/// scale of `cur`'s arc extrapolated linearly to its parameter (3e-5 and
/// 6e-6 at the period-2 oscillator's two turns, 5e-6 at `switch.rs`'s;
/// the 2-impact orbits the trials fell onto there, 1.0).
fn turn_onto<F: Family>(ctx: &Ctx<'_, F>, points: &[BranchPoint], cur: &Point, p: &Point, graze: f64, limit: f64) -> Option<(Bifurcation, Point)> {
    let prev = &points[points.len().checked_sub(2)?];
    let measure: Measure<'_, F> = if p.orbit.impacts() == 0 { &margin } else { &flight_margin };
    let m1 = measure(ctx, p)?;
    let dir = (p.param - graze).signum();
    let (estimate, p1) = grazing_parameter(ctx, None, (p.clone(), m1), (p.orbit.impacts(), measure), Some((graze, limit)), OnFailure::Shorten, dir)?;
    if (estimate - graze).abs() > (cur.param - graze).abs() || (p.param - estimate) * (cur.param - estimate) <= 0.0 {
        return None;
    }
    let w = (p1.param - cur.param) / (cur.param - prev.param);
    let meet = p1.x.iter().zip(&cur.x).zip(&prev.orbit.x).fold(0.0f64, |a, ((y, c), b)| a.max((y - (c + w * (c - b))).abs()));
    // The arcs meet: `cur`'s extrapolated reaches `p1`, or, where that
    // extrapolation spans more than 100 of `cur`'s last steps, the orbit
    // beside the grazing on `p`'s side has `cur`'s impact slowing as
    // `cur`'s does ([`meets_by_speed`]).
    let meets = meet <= 1e-2 * ctx.xs || (w.abs() > 100.0 && meets_by_speed(ctx, cur, p, &p1, estimate));
    if !meets {
        return None;
    }
    let mut seed = vec![0.0; ctx.n + 1];
    seed[ctx.n] = (p.param - estimate).signum();
    let across = ctx.point(p.x.clone(), p.param, &seed).ok()?;
    let i = points.len() - 1;
    let bif = Bifurcation {
        param: estimate,
        kind: BifurcationKind::Grazing,
        mu: critical(BifurcationKind::Grazing, cur),
        impacts: (cur.orbit.impacts(), p.orbit.impacts()),
        releases: (cur.orbit.releases(), p.orbit.releases()),
        between: (i, i + 1),
        x: cur.x.clone(),
        mark: None,
    };
    Some((bif, across))
}

/// Whether the arc of `cur` (its slowest impact vanishing) meets `p`'s
/// arc (one impact fewer) at the grazing `estimate` located on `p`'s arc
/// (`p1` its orbit there), seen from `p`'s side where `cur`'s two last
/// points are too near each other for their extrapolation (by more than
/// 100 times their distance): the orbit of `p`'s arc at 1e-2 of the way
/// from the grazing to `cur`, pushed past the stop ([`past_the_stop`]),
/// gives an orbit with `cur`'s impacts whose slowest impact's speed is
/// `cur`'s scaled linearly to that distance, within a factor 2.
///
/// On the sine-forced period-3 loop of `tests/it/isola.rs` with the
/// parameter's scale 4 the branch crawled (the corrector at its residual
/// floor) and met the 1-impact orbits from two 2-impact points 2.2e-7
/// apart at Ω = 3.1387640, 1.5e-2 above the grazing at 3.1238288: their
/// extrapolation missed the 1-impact orbit there by 0.83 (the state's
/// scale 0.78), the turn was refused, a grazing was listed at 3.1387178
/// where there is none and the loop did not close. The orbit found at
/// 1e-2 of the way has its new impact at 8.020e-5 where `cur`'s speed
/// scaled gives 8.041e-5 (`tests/it/turned_back.rs`).
fn meets_by_speed<F: Family>(ctx: &Ctx<'_, F>, cur: &Point, p: &Point, p1: &Point, estimate: f64) -> bool {
    let (Some(vb), k) = (cur.orbit.slowest_impact(), cur.orbit.impacts()) else { return false };
    let at = estimate + 1e-2 * (cur.param - estimate);
    let w = (at - p1.param) / (p.param - p1.param);
    let guess: Vec<f64> = p1.x.iter().zip(&p.x).map(|(a, b)| a + w * (b - a)).collect();
    let dir = (cur.param - estimate).signum();
    let Some(r) = solve_at(ctx, &guess, at, dir).filter(|r| r.orbit.impacts() + 1 == k) else { return false };
    let Some(q) = past_the_stop(ctx, &r, at, 0.0, dir, &mut Searches::new(), f64::INFINITY) else { return false };
    let want = vb * (at - estimate) / (cur.param - estimate);
    q.orbit.impacts() == k && q.orbit.slowest_impact().is_some_and(|v| v > 0.5 * want && v < 2.0 * want)
}

/// The orbit with one impact fewer than `cur` beside the grazing where
/// `cur`'s slowest impact vanishes (`graze`, extrapolated), on `cur`'s
/// side: plain Newton (giving up where it stalls) from `cur`'s arc
/// extrapolated linearly to 1e-3, 1e-2 and 1e-1 of the way from `graze`
/// to `cur`. Near the grazing the two arcs are near each other, the slow
/// impact's speed near 0, and the extrapolated state lies on the side
/// without it; farther, the orbit of fewer impacts is strongly unstable
/// (|μ| about 750 on the period-2 oscillator) and Newton from `cur`'s own
/// state stalls at a residual of 1.5e-3. Taken only with one impact fewer
/// and within 1e-2 of the state's scale of its guess.
fn beside_the_grazing<F: Family>(ctx: &Ctx<'_, F>, points: &[BranchPoint], cur: &Point, graze: f64) -> Option<Point> {
    let prev = &points[points.len().checked_sub(2)?];
    let k = cur.orbit.impacts();
    let newton = Newton { stall: SEARCH_STALL, ..ctx.opts.newton };
    for f in [1e-3, 1e-2, 0.1] {
        let param = graze + f * (cur.param - graze);
        let w = (param - cur.param) / (cur.param - prev.param);
        let guess: Vec<f64> = cur.x.iter().zip(&prev.orbit.x).map(|(c, b)| c + w * (c - b)).collect();
        let (model, period) = ctx.family.model_and_period(param).ok()?;
        let Ok(o) = periodic_orbit_strict(&model, 0.0, period, &guess, &newton) else { continue };
        let d = o.x.iter().zip(&guess).fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
        if o.impacts() + 1 == k && d <= 1e-2 * ctx.xs {
            let mut seed = vec![0.0; ctx.n + 1];
            seed[ctx.n] = (cur.param - graze).signum();
            return ctx.point(o.x, param, &seed).ok();
        }
    }
    None
}

/// How a branch came back onto itself ([`Returns::check`]).
enum Returned {
    /// The step passes the first orbit (shifted by `shift` forcing
    /// periods): the branch is closed, `at` that orbit as a point of it.
    Closed { at: Box<Point>, shift: usize },
    /// The step's end, shifted by `shift` forcing periods, lies on the
    /// branch's segment `on` (its points `on`, `on + 1`).
    Copy { shift: usize, on: usize },
    /// The step's end mirrored (`−x(t + (shift + ½) T)`, `T` the forcing
    /// period: [`mirror_images`]) lies on the branch's segment `on`: the
    /// branch has turned onto the mirror image of its own orbits.
    Mirror { shift: usize, on: usize },
}

/// Watches a branch for its return onto itself. A closed branch (an isola,
/// or any loop of orbits) was traced round and round until the point
/// budget, each bifurcation listed once a lap: the two-stop oscillator's
/// isola of period 5 (`x'' + 0.1x' + x = 2 sin Ωt`, stops −1 and 0.5,
/// e = 0.3, Ω from 5.6) listed its folds at 5.5419 and 6.0079 ten times
/// each (`tests/it/isola.rs`). An orbit of `p` forcing periods has `p`
/// section states (its state after `k` forcing periods, `k < p`), each a
/// fixed point of the map: a loop of such orbits may close only on a
/// shifted copy of its first state, and a branch may come back onto a
/// shifted copy of an arc it has traced (the period-3 orbits of that
/// oscillator, e = 0.3, from Ω = 4 down, listed a fold and a period
/// doubling twice, at two section states of the same orbits). On a
/// structure symmetric under `x → −x` ([`mirror_symmetric`]) the mirror
/// images of the branch's orbits are orbits too: a branch that turns onto
/// them where it meets a symmetric orbit (a branch point) traced itself
/// again, mirrored — the two-stop oscillator from Ω = 1.5 down listed its
/// grazings, fold and period doubling twice and closed on its first orbit
/// after 254 points (`tests/it/mirror.rs`).
struct Returns {
    /// The forcing periods of the map.
    p: usize,
    /// The first point, and its state after `k` forcing periods (`k = 1 …
    /// p − 1`).
    first: Point,
    first_shifted: Vec<Option<Vec<f64>>>,
    /// The shifted states of the branch's points so far (`[k − 1]`).
    images: Vec<Vec<Option<Vec<f64>>>>,
    /// Whether the structure at the range's start is symmetric under
    /// `x → −x` with the forcing's half-period shift ([`mirror_symmetric`]):
    /// then the branch's points' mirror images (`mirrors`, `[k]` for
    /// `(k + ½)` forcing periods) are watched too.
    symmetric: bool,
    mirrors: Vec<Vec<Option<Vec<f64>>>>,
}

impl Returns {
    fn new(p: usize, first: &Point, symmetric: bool) -> Self {
        Self { p, first: first.clone(), first_shifted: Vec::new(), images: Vec::new(), symmetric, mirrors: Vec::new() }
    }

    /// `x`'s state after `k` forcing periods at `param` (`None` when the
    /// map fails).
    fn shifted<F: Family>(ctx: &Ctx<'_, F>, x: &[f64], param: f64, k: usize, p: usize) -> Option<Vec<f64>> {
        let (model, period) = ctx.family.model_and_period(param).ok()?;
        Some(model.flow(0.0, x, period * k as f64 / p as f64, false).ok()?.x)
    }

    fn all_shifted<F: Family>(&self, ctx: &Ctx<'_, F>, x: &[f64], param: f64) -> Vec<Option<Vec<f64>>> {
        (1..self.p).map(|k| Self::shifted(ctx, x, param, k, self.p)).collect()
    }

    /// [`Returns::all_shifted`] of the point `q`: read by its map's flow
    /// ([`Readings`]), else flowed to.
    fn shifted_of<F: Family>(&self, ctx: &Ctx<'_, F>, q: &Point) -> Vec<Option<Vec<f64>>> {
        match &q.readings.shifted {
            Some(s) if s.len() + 1 == self.p => s.clone(),
            _ => self.all_shifted(ctx, &q.x, q.param),
        }
    }

    /// Whether the step from `cur` to `next` closes the branch (it passes
    /// within a quarter of its length of the first orbit or one of its
    /// shifted states, and the corrector from there lands on it:
    /// [`Returned::Closed`]), or ends on orbits the branch has traced
    /// (`next`, or its state shifted by `k` forcing periods, within a
    /// quarter of a segment's length of a traced segment with as many
    /// impacts, the two steps parallel: [`Returned::Copy`]).
    fn check<F: Family>(&mut self, ctx: &Ctx<'_, F>, points: &[BranchPoint], cur: &Point, next: &Point) -> Option<Returned> {
        let i = points.len() - 1;
        if i == 0 {
            return None;
        }
        if self.first_shifted.len() + 1 < self.p {
            self.first_shifted = self.shifted_of(ctx, &self.first);
        }
        let scaled = |x: &[f64], l: f64| -> Vec<f64> { x.iter().map(|v| v / ctx.xs).chain(std::iter::once(l / ctx.ls)).collect() };
        let (a, b) = (scaled(&cur.x, cur.param), scaled(&next.x, next.param));
        // The first orbit on the step.
        for shift in 0..self.p {
            let c = if shift == 0 { Some(&self.first.x) } else { self.first_shifted[shift - 1].as_ref() };
            let Some(c) = c else { continue };
            if cur.orbit.impacts() != self.first.orbit.impacts() && next.orbit.impacts() != self.first.orbit.impacts() {
                continue;
            }
            if !near_segment(&a, &b, &scaled(c, self.first.param)) {
                continue;
            }
            // The branch through it, oriented along the step: the same
            // orbit, where the corrector from the step's chord lands.
            let Ok(at) = ctx.point(c.clone(), self.first.param, &cur.tangent) else { continue };
            if shift == 0 && at.tangent.iter().zip(&self.first.tangent).map(|(u, v)| u * v).sum::<f64>() <= 0.0 {
                continue;
            }
            if !self.lands(ctx, cur, next, &at) {
                continue;
            }
            return Some(Returned::Closed { at: Box::new(at), shift });
        }
        // Onto a traced segment.
        // The branch's last point is `cur` (its states read by its flow).
        let is_cur = |j: usize, q: &BranchPoint| j == i && q.param == cur.param && q.orbit.x == cur.x;
        while self.images.len() < points.len() {
            let j = self.images.len();
            let q = &points[j];
            let im = if is_cur(j, q) { self.shifted_of(ctx, cur) } else { self.all_shifted(ctx, &q.orbit.x, q.param) };
            self.images.push(im);
        }
        let next_images = self.shifted_of(ctx, next);
        for shift in 0..self.p {
            let (y, y0) = if shift == 0 { (Some(&next.x), Some(&cur.x)) } else { (next_images[shift - 1].as_ref(), self.images[i][shift - 1].as_ref()) };
            let (Some(y), Some(y0)) = (y, y0) else { continue };
            let (sy, sy0) = (scaled(y, next.param), scaled(y0, cur.param));
            // Not the step's own segment, nor the one before (unshifted).
            let last = if shift == 0 { i.saturating_sub(1) } else { i };
            if let Some(on) = beside_a_segment(&points[..=last], next.orbit.impacts(), &sy, &sy0, &scaled) {
                if traced_through(ctx, &points[on], &points[on + 1], y, next.param, &sy, &sy0) {
                    return Some(Returned::Copy { shift, on });
                }
            }
        }
        // Onto the mirror image of a traced segment (a symmetric
        // structure): the step mirrored, from `cur`'s image to `next`'s,
        // lies on it. Every segment traced counts, the step's last one too
        // (a turn onto the mirror image: the step's end mirrored lies
        // beside the segment before it). A symmetric orbit is its own
        // mirror image: a branch of them mirrors each step onto itself,
        // ahead of its traced segments, never inside one.
        if !self.symmetric {
            return None;
        }
        while self.mirrors.len() < points.len() {
            let j = self.mirrors.len();
            let q = &points[j];
            let im = if is_cur(j, q) { mirrors_of(ctx, cur, self.p) } else { mirror_images(ctx, &q.orbit.x, q.param, self.p) };
            self.mirrors.push(im);
        }
        let next_mirrors = mirrors_of(ctx, next, self.p);
        for shift in 0..self.p {
            let (Some(y), Some(y0)) = (next_mirrors[shift].as_ref(), self.mirrors[i][shift].as_ref()) else { continue };
            let (sy, sy0) = (scaled(y, next.param), scaled(y0, cur.param));
            if let Some(on) = beside_a_segment(&points[..=i], next.orbit.impacts(), &sy, &sy0, &scaled) {
                return Some(Returned::Mirror { shift, on });
            }
        }
        None
    }

    /// Whether the corrector from the step's chord, on the hyperplane
    /// through `at` normal to its tangent, lands on `at` (to 1e-6 of the
    /// scaled state: the same orbit, not another one nearby).
    fn lands<F: Family>(&self, ctx: &Ctx<'_, F>, cur: &Point, next: &Point, at: &Point) -> bool {
        let n = ctx.n;
        let t = &at.tangent;
        let side = |x: &[f64], l: f64| (0..n).map(|k| t[k] * (x[k] - at.x[k]) / ctx.xs).sum::<f64>() + t[n] * (l - at.param) / ctx.ls;
        let (sa, sb) = (side(&cur.x, cur.param), side(&next.x, next.param));
        if !(sa * sb <= 0.0 && sa != sb) {
            return false;
        }
        let w = sa / (sa - sb);
        let x: Vec<f64> = (0..n).map(|k| cur.x[k] + w * (next.x[k] - cur.x[k])).collect();
        let l = cur.param + w * (next.param - cur.param);
        match ctx.correct(x, l, t, None) {
            Ok((y, lam, _)) => (0..n).map(|k| ((y[k] - at.x[k]) / ctx.xs).abs()).fold(((lam - at.param) / ctx.ls).abs(), f64::max) <= 1e-6,
            Err(_) => false,
        }
    }
}

/// Whether the arc traced from `a` to `b` passes through `(y, param)`
/// (`sy` scaled; `sy0` the step's start, scaled): the corrector from
/// `(y, param)`'s projection onto the chord, on the hyperplane through it
/// normal to the chord, lands within 1e-2 of the shorter of the chord and
/// the step of it. Near a fold, in the scaled coordinates of a small
/// parameter's scale, the two arcs run side by side, nearer each other
/// than a quarter of a step: with `--param-scale 0.01` the period-2
/// oscillator of `tests/it/period_two.rs` ended past its 3-impact fold at
/// 2.4010173, its orbit at 2.4004090 taken for one of the arc traced before
/// the fold (3.6e-3 from it, scaled; the steps 2.3e-2), where the
/// corrector lands on that arc's own orbit, 3.6e-3 away.
fn traced_through<F: Family>(ctx: &Ctx<'_, F>, a: &BranchPoint, b: &BranchPoint, y: &[f64], param: f64, sy: &[f64], sy0: &[f64]) -> bool {
    let n = ctx.n;
    let scaled = |x: &[f64], l: f64| -> Vec<f64> { x.iter().map(|v| v / ctx.xs).chain(std::iter::once(l / ctx.ls)).collect() };
    let (sa, sb) = (scaled(&a.orbit.x, a.param), scaled(&b.orbit.x, b.param));
    let ab: Vec<f64> = sa.iter().zip(&sb).map(|(u, v)| v - u).collect();
    let len = ab.iter().map(|v| v * v).sum::<f64>().sqrt();
    let step = sy.iter().zip(sy0).map(|(u, v)| (u - v).powi(2)).sum::<f64>().sqrt();
    if !(len > 0.0) {
        return false;
    }
    let t: Vec<f64> = ab.iter().map(|v| v / len).collect();
    let w = sa.iter().zip(sy).zip(&t).map(|((u, v), d)| (v - u) * d).sum::<f64>();
    let x: Vec<f64> = (0..n).map(|k| (sa[k] + w * t[k]) * ctx.xs).collect();
    let l = (sa[n] + w * t[n]) * ctx.ls;
    match ctx.correct(x, l, &t, None) {
        Ok((z, lam, _)) => {
            let d = (0..n).map(|k| ((z[k] - y[k]) / ctx.xs).powi(2)).sum::<f64>() + ((lam - param) / ctx.ls).powi(2);
            d.sqrt() <= 1e-2 * len.min(step)
        }
        Err(_) => false,
    }
}

/// Whether `model` is symmetric under `x → −x` with the time shifted by
/// `half` (half a forcing period): no steady load, every contact between
/// stops at `−g` and `g` (a contact's restitution serves both), and every
/// forcing term odd under the shift (a sine, or harmonics, each of whose
/// frequencies `ω` puts `ω · half` at an odd multiple of π, to 1e-9; a
/// series is not looked at). Then `x(t)` an orbit, so is `−x(t + half)`:
/// its mirror image, with the same multipliers. Unforced structures are
/// left out (the shift is then no forcing's).
fn mirror_symmetric(model: &Model, half: f64) -> bool {
    use signorini_schemes::TimeProfile;
    let dy = model.dynamics();
    let odd = |w: f64| {
        let k = w * half / std::f64::consts::PI;
        let r = k.round();
        r.rem_euclid(2.0) == 1.0 && (k - r).abs() <= 1e-9 * r.abs()
    };
    !dy.forcing.is_empty()
        && dy.load.iter().all(|&f| f == 0.0)
        && dy.contacts.iter().all(|c| c.bounds.hi.is_finite() && c.bounds.lo == -c.bounds.hi)
        && dy.forcing.iter().all(|f| match &f.time {
            TimeProfile::Sine { omega, .. } => odd(*omega),
            TimeProfile::Harmonics(h) => h.iter().all(|t| t.amplitude == 0.0 || odd(t.omega)),
            _ => false,
        })
}

/// The mirror images of the orbit through `x` at `param` on a map of `p`
/// forcing periods: `−x((k + ½) T)` (`T` the forcing period, `k = 0 …
/// p − 1`), each `None` where the structure there is not symmetric
/// ([`mirror_symmetric`]) or the flow fails.
fn mirror_images<F: Family>(ctx: &Ctx<'_, F>, x: &[f64], param: f64, p: usize) -> Vec<Option<Vec<f64>>> {
    let Ok((model, period)) = ctx.family.model_and_period(param) else { return vec![None; p] };
    let half = 0.5 * period / p as f64;
    if !mirror_symmetric(&model, half) {
        return vec![None; p];
    }
    (0..p).map(|k| model.flow(0.0, x, (2 * k + 1) as f64 * half, false).ok().map(|img| img.x.iter().map(|v| -v).collect())).collect()
}

/// [`mirror_images`] of the point `q`: read by its map's flow
/// ([`Readings`]), else flowed to.
fn mirrors_of<F: Family>(ctx: &Ctx<'_, F>, q: &Point, p: usize) -> Vec<Option<Vec<f64>>> {
    match &q.readings.mirrors {
        Some(m) if m.len() == p => m.clone(),
        _ => mirror_images(ctx, &q.x, q.param, p),
    }
}

/// The asymmetry of the orbit through the point `q` on a map of `p`
/// forcing periods: the least distance (max norm, over the state's scale)
/// of its mirror images ([`mirrors_of`]) from its state, 0 on a
/// symmetric orbit; `None` where the structure is not symmetric.
fn asymmetry<F: Family>(ctx: &Ctx<'_, F>, q: &Point, p: usize) -> Option<f64> {
    let x = &q.x;
    mirrors_of(ctx, q, p).iter().flatten().map(|y| y.iter().zip(x).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / ctx.xs).reduce(f64::min)
}

/// At most this asymmetry ([`asymmetry`]) an orbit is symmetric.
const SYMMETRIC: f64 = 1e-7;

/// The pitchfork between `a` and `b` (points `i`, `i + 1`) where the
/// branch passes from asymmetric orbits onto symmetric ones (or back): the
/// asymmetric pair born at a symmetric orbit's pitchfork meets it there,
/// and a branch coming along one of the pair may go on along the
/// symmetric orbits, its multiplier touching +1 with no test changing
/// sign (the period-3 orbits of the oscillator between symmetric stops
/// from Ω = 5 to 5.5: `tests/it/turn.rs`). Located by bisection on the
/// arclength on whether the orbit is symmetric, named a branch point.
fn pitchfork<F: Family>(ctx: &Ctx<'_, F>, a: &Point, b: &Point, i: usize, p: usize, aa: f64, ab: f64) -> Option<Bifurcation> {
    let sym = |v: f64| v <= SYMMETRIC;
    if sym(aa) == sym(ab) {
        return None;
    }
    let test = |q: &Point| asymmetry(ctx, q, p).map_or(f64::NAN, |v| if sym(v) { 0.0 } else { 1.0 });
    let at = bisect(ctx, a, arclength(ctx, a, b), b, test, |u, v| test(u) != test(v));
    let kind = BifurcationKind::BranchPoint;
    Some(Bifurcation {
        param: at.param,
        kind,
        mu: critical(kind, &at),
        impacts: (a.orbit.impacts(), b.orbit.impacts()),
        releases: (a.orbit.releases(), b.orbit.releases()),
        between: (i, i + 1),
        x: at.x.clone(),
        mark: at.mark,
    })
}

/// The first segment of `points` (`on` to `on + 1`, both with `impacts`)
/// that the step from `y0` to `y` (scaled as `scaled` does) lies inside of
/// and runs parallel to: where a step ends on orbits already traced.
fn beside_a_segment(points: &[BranchPoint], impacts: usize, y: &[f64], y0: &[f64], scaled: &impl Fn(&[f64], f64) -> Vec<f64>) -> Option<usize> {
    points.windows(2).position(|w| {
        let (q, r) = (&w[0], &w[1]);
        if q.orbit.impacts() != impacts || r.orbit.impacts() != impacts {
            return false;
        }
        let (sq, sr) = (scaled(&q.orbit.x, q.param), scaled(&r.orbit.x, r.param));
        inside_segment(&sq, &sr, y, y0) && parallel(&sq, &sr, y0, y)
    })
}

/// Whether `y` lies within a quarter of the segment's length of the
/// segment from `a` to `b` (scaled coordinates).
fn near_segment(a: &[f64], b: &[f64], y: &[f64]) -> bool {
    let ab: Vec<f64> = a.iter().zip(b).map(|(u, v)| v - u).collect();
    let len2: f64 = ab.iter().map(|v| v * v).sum();
    if !(len2 > 0.0) {
        return false;
    }
    let w = (a.iter().zip(y).zip(&ab).map(|((u, v), d)| (v - u) * d).sum::<f64>() / len2).clamp(0.0, 1.0);
    let d2: f64 = a.iter().zip(&ab).zip(y).map(|((u, d), v)| (u + w * d - v).powi(2)).sum();
    d2 <= 0.0625 * len2
}

/// Whether `y` lies beside the inside of the segment from `a` to `b` (its
/// projection not at an end), within a quarter of the shorter of that
/// segment and the step from `y0` to `y`: a step shorter than a traced
/// segment, ahead of its end, is not on it.
fn inside_segment(a: &[f64], b: &[f64], y: &[f64], y0: &[f64]) -> bool {
    let ab: Vec<f64> = a.iter().zip(b).map(|(u, v)| v - u).collect();
    let len2: f64 = ab.iter().map(|v| v * v).sum();
    let step2: f64 = y.iter().zip(y0).map(|(u, v)| (u - v).powi(2)).sum();
    if !(len2 > 0.0 && step2 > 0.0) {
        return false;
    }
    let w = a.iter().zip(y).zip(&ab).map(|((u, v), d)| (v - u) * d).sum::<f64>() / len2;
    if !(w > 0.0 && w < 1.0) {
        return false;
    }
    let d2: f64 = a.iter().zip(&ab).zip(y).map(|((u, d), v)| (u + w * d - v).powi(2)).sum();
    d2 <= 0.0625 * len2.min(step2)
}

/// Whether the step from `c` to `d` is parallel (either way, within about
/// 25°) to the segment from `a` to `b`.
fn parallel(a: &[f64], b: &[f64], c: &[f64], d: &[f64]) -> bool {
    let u: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let v: Vec<f64> = c.iter().zip(d).map(|(x, y)| y - x).collect();
    let dot: f64 = u.iter().zip(&v).map(|(x, y)| x * y).sum();
    let (nu, nv) = (u.iter().map(|x| x * x).sum::<f64>().sqrt(), v.iter().map(|x| x * x).sum::<f64>().sqrt());
    nu > 0.0 && nv > 0.0 && dot.abs() >= 0.9 * nu * nv
}

/// The scaled distance between two points, as the arclength measures it.
fn arclength<F: Family>(ctx: &Ctx<'_, F>, a: &Point, b: &Point) -> f64 {
    let d: f64 = (0..ctx.n).map(|k| (b.x[k] - a.x[k]) / ctx.xs).map(|v| v * v).sum::<f64>() + ((b.param - a.param) / ctx.ls).powi(2);
    d.sqrt()
}

/// Whether the chord from `a` to the trial `b` keeps within 25° of `a`'s
/// tangent (cosine above 0.9, as the tangents must): the corrector moves
/// on the plane normal to the tangent, so on `a`'s own arc the chord turns
/// by about half the tangents' turn, while a corrector that ran across to
/// another arc lying beside it turns the chord by the gap between the arcs.
/// The period-2 oscillator of `tests/it/period_two.rs` with
/// `--param-scale 0.01`, going up its 4-impact arc, took a trial from Ω =
/// 2.3855371 (|μ| 122) landing 3.4e-3 off the arc at 2.3858515 (|μ| 5.1),
/// its chord's cosine against the previous chord 0.83 (every other step
/// of the run: 0.93 and more); the tangents' test passed, a grazing was
/// listed there where there is none and the branch ended.
fn along_tangent<F: Family>(ctx: &Ctx<'_, F>, a: &Point, b: &Point) -> bool {
    let s = arclength(ctx, a, b);
    let d: f64 = (0..ctx.n).map(|k| (b.x[k] - a.x[k]) / ctx.xs * a.tangent[k]).sum::<f64>() + (b.param - a.param) / ctx.ls * a.tangent[ctx.n];
    s == 0.0 || d > 0.9 * s
}

/// The bifurcations between `a` and `b` (points `i`, `i + 1`), each
/// located by bisection on the arclength from `a`.
fn locate<F: Family>(ctx: &Ctx<'_, F>, a: &Point, b: &Point, i: usize, out: &mut Vec<Bifurcation>) {
    let s_b = arclength(ctx, a, b);
    type Test = fn(&Point) -> f64;
    let tests: [(BifurcationKind, Test); 3] = [(BifurcationKind::Fold, fold_test), (BifurcationKind::PeriodDoubling, pd_test), (BifurcationKind::NeimarkSacker, ns_test)];
    let mut found = Vec::new();
    // Across a change of the event sequence the multipliers jump: their
    // sign changes there belong to the grazing (or sticking), not to a
    // smooth bifurcation.
    let smooth = a.orbit.impacts() == b.orbit.impacts() && a.orbit.releases() == b.orbit.releases();
    // A multiplier through +1: a fold where the branch turns in λ, a
    // branch point where it does not; a turn in λ without one, a branch
    // point too (the multiplier touches +1: a pitchfork seen from the
    // asymmetric branch, which goes on onto its mirror image).
    let det_sign = det_test(a) * det_test(b) < 0.0;
    let turns = fold_test(a) * fold_test(b) < 0.0;
    if smooth && det_sign && !turns {
        let mut p = bisect(ctx, a, s_b, b, det_test, |p, q| det_test(p) * det_test(q) < 0.0);
        // The corrector is singular at a branch point (two branches cross
        // there), so the bisection ends at a bracket whose multiplier is
        // within about 1e-2 of +1 (0.0035 on the symmetric oscillator,
        // its parameter 4.4e-9 and 1.3e-8 off at its two branch points):
        // farther, the sign change is no crossing. On symmetric orbits the
        // crossing is located on them alone, where nothing is singular
        // (to 5e-12 there, `tests/it/symmetric.rs`).
        if let Some((param, x, multipliers)) = symmetric_pitchfork(ctx, a, b) {
            (p.param, p.x, p.orbit.multipliers, p.mark) = (param, x, multipliers, None);
        }
        if (critical(BifurcationKind::BranchPoint, &p) - c64::new(1.0, 0.0)).norm() <= 1e-2 {
            found.push((BifurcationKind::BranchPoint, p));
        }
    }
    // A volume-preserving map (no damping, elastic impacts) whose pair of
    // multipliers meets at −1 and leaves the circle along the real axis:
    // its period doubling, seen by `∏ (μ + 1)` alone. The bisection ends
    // within about 1e-6 of the double multiplier −1 (the pair's distance
    // from it grows as the square root of the parameter's). On a
    // dissipative map, a multiplier through −1 that [`pd_test`] does not
    // follow, beyond −1 farther from it than a small negative one: the
    // period-2 oscillator of `tests/it/period_two.rs` at scale 1 stepped
    // through its 3-impact fold from 2.3925294 (μ 8.18 and 5.3e-5) to
    // 2.3926706 (−2.05 and −2.1e-4), `pd_test` −1 and −0.9998, and its
    // period doubling at 2.3926883 was not listed; `∏ (μ + 1)` went from
    // 9.18 to −1.05.
    let conservative = on_circle(a) && on_circle(b);
    if smooth && pd_test(a) * pd_test(b) >= 0.0 && pair_pd_test(a) * pair_pd_test(b) < 0.0 && (!conservative || negative_pair_off_circle(a) || negative_pair_off_circle(b)) {
        let p = bisect(ctx, a, s_b, b, pair_pd_test, |p, q| pair_pd_test(p) * pair_pd_test(q) < 0.0);
        if (critical(BifurcationKind::PeriodDoubling, &p) + c64::new(1.0, 0.0)).norm() <= 1e-2 {
            found.push((BifurcationKind::PeriodDoubling, p));
        }
    }
    for (kind, f) in tests {
        // A volume-preserving map (`∏ |μ| = 1`: no damping, elastic
        // impacts) whose complex multipliers are on the unit circle at
        // both ends: `|μ| − 1` is round-off, its sign changes are no
        // Neimark–Sacker point (a pair leaves the circle only where it
        // meets another or the real axis: there a pair is off it, or
        // real, at one end).
        if kind == BifurcationKind::NeimarkSacker && conservative && [a, b].iter().all(|p| p.orbit.multipliers.iter().filter(|m| !is_real(m)).all(|m| (m.norm() - 1.0).abs() <= 1e-4)) {
            continue;
        }
        if smooth && f(a) * f(b) < 0.0 {
            let p = bisect(ctx, a, s_b, b, f, |p, q| f(p) * f(q) < 0.0);
            let kind = if kind == BifurcationKind::Fold && !det_sign { BifurcationKind::BranchPoint } else { kind };
            // A turn in λ is a branch point only where a multiplier is at
            // +1 there: elsewhere the branch turns at a corner (a flight
            // grazing a stop, named a grazing) and the multipliers say
            // nothing crosses. On the elastic oscillator between its stops
            // two such turns were named, their multipliers 0.73 ± 0.68i
            // (at a grazing) and a real pair near −0.1.
            if kind == BifurcationKind::BranchPoint && !at_plus_one(&p) {
                continue;
            }
            // The period-doubling and Neimark–Sacker tests jump where
            // they change the multiplier they follow (the real multiplier
            // nearest −1 passes from one of two negative ones to the other,
            // equally far from −1 on either side of it; a complex pair
            // meets on the real axis): a sign change whose located point is
            // not at the crossing (test value beyond 1e-4, where a
            // crossing's bracket ends within 1e-12 of it) is such a jump,
            // not a bifurcation.
            if matches!(kind, BifurcationKind::PeriodDoubling | BifurcationKind::NeimarkSacker) && f(&p).abs() > 1e-4 {
                continue;
            }
            found.push((kind, p));
        }
    }
    for (kind, count) in [(BifurcationKind::Grazing, Orbit::impacts as fn(&Orbit) -> usize), (BifurcationKind::Sticking, Orbit::releases)] {
        // Not again when the step was taken as a corner, located there.
        if count(&a.orbit) != count(&b.orbit) && !out.iter().any(|o| o.kind == kind && o.between == (i, i + 1)) {
            let p = bisect(ctx, a, s_b, b, |p| count(&p.orbit) as f64, |p, q| count(&p.orbit) != count(&q.orbit));
            found.push((kind, p));
        }
    }
    for (kind, p) in found {
        let mu = critical(kind, &p);
        out.push(Bifurcation {
            param: p.param,
            kind,
            mu,
            impacts: (a.orbit.impacts(), b.orbit.impacts()),
            releases: (a.orbit.releases(), b.orbit.releases()),
            between: (i, i + 1),
            x: p.x.clone(),
            mark: p.mark,
        });
    }
    out.sort_by_key(|p| p.between);
}

/// The pitchfork between `a` and `b`, two symmetric orbits of a
/// mirror-symmetric structure (`x(t + τ) = −x(t)`, `τ` half the map's
/// period of an odd number `p` of forcing periods): the fixed points of
/// the half map mirrored, `R(x) = −φ(x, τ)`, whose square is the map
/// (`P' = R'²`). A multiplier of `P` passes +1 where one of `R'` passes
/// −1, while `R' − I` stays regular: Newton on `R` at fixed `λ` converges
/// through the pitchfork, and `det(R' + I)` changes sign there, its zero
/// found by regula falsi (Illinois) in `λ` to 1e-13 of the parameter's
/// scale. `None` where the structure is not symmetric, `a` or `b` is not a
/// fixed point of `R` (within 1e-7 of the state's scale), or the test
/// keeps its sign. Returns the parameter, the orbit's state and the
/// multipliers of `P` there (by decreasing modulus).
fn symmetric_pitchfork<F: Family>(ctx: &Ctx<'_, F>, a: &Point, b: &Point) -> Option<(f64, Vec<f64>, Vec<c64>)> {
    let p = ctx.family.periods().max(1);
    if p % 2 == 0 {
        return None;
    }
    let n = ctx.n;
    // The fixed point of `R` at `param` from `guess`, `det(R' + I)` there
    // and the half map's Jacobian `J` (`R' = −J`).
    let solve = |param: f64, guess: &[f64]| -> Option<(Vec<f64>, f64, Mat<f64>)> {
        let (model, period) = ctx.family.model_and_period(param).ok()?;
        let half = 0.5 * period;
        if !mirror_symmetric(&model, half / p as f64) {
            return None;
        }
        let mut x = guess.to_vec();
        for _ in 0..30 {
            let img = model.flow(0.0, &x, half, true).ok()?;
            let j = img.jacobian?;
            let step = Mat::from_fn(n, n, |r, c| j[(r, c)] + if r == c { 1.0 } else { 0.0 }).partial_piv_lu().solve(Mat::from_fn(n, 1, |r, _| x[r] + img.x[r]));
            let size = (0..n).fold(0.0f64, |m, i| m.max(step[(i, 0)].abs()));
            if !size.is_finite() {
                return None;
            }
            if size <= 1e-14 * ctx.xs {
                let test = eigenvalues(&j).ok()?.iter().fold(c64::new(1.0, 0.0), |acc, m| acc * (c64::new(1.0, 0.0) - m)).re;
                return Some((x, test, j));
            }
            (0..n).for_each(|i| x[i] -= step[(i, 0)]);
        }
        None
    };
    let near = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(u, v)| (u - v).abs() <= 1e-7 * ctx.xs);
    let (mut xa, mut ga, _) = solve(a.param, &a.x).filter(|s| near(&s.0, &a.x))?;
    let (mut xb, mut gb, mut jb) = solve(b.param, &b.x).filter(|s| near(&s.0, &b.x))?;
    let (mut la, mut lb) = (a.param, b.param);
    if ga * gb >= 0.0 {
        return None;
    }
    // Illinois: the end kept twice in a row has its value halved.
    let mut kept = 0i8;
    for _ in 0..100 {
        if (lb - la).abs() <= 1e-13 * ctx.ls {
            break;
        }
        let w = ga / (ga - gb);
        let l = la + w * (lb - la);
        let guess: Vec<f64> = xa.iter().zip(&xb).map(|(u, v)| u + w * (v - u)).collect();
        let (x, g, j) = solve(l, &guess)?;
        if g * gb < 0.0 {
            (la, xa, ga) = (lb, xb, gb);
            kept = 0;
        } else {
            ga *= if kept < 0 { 0.5 } else { 1.0 };
            kept = -1;
        }
        (lb, xb, gb, jb) = (l, x, g, j);
        if g == 0.0 {
            break;
        }
    }
    let mut mu: Vec<c64> = eigenvalues(&jb).ok()?.iter().map(|m| m * m).collect();
    mu.sort_by(|u, v| v.norm().total_cmp(&u.norm()));
    Some((lb, xb, mu))
}

/// A multiplier at +1 at a located turn: within 1e-2 of it (as a branch
/// point located by `det(P' − I)` is), or, on a volume-preserving map
/// ([`on_circle`]), a pair whose `|μ − 1|²` is within 1e-2 — there the
/// pair meets at +1 on the circle and its distance from +1 grows as the
/// square root of the distance from the turn (the elastic oscillator's
/// asymmetric orbit meeting the symmetric one: `0.9967 ± 0.0815i` at the
/// bisection's end, 2.7e-7 in Ω from the symmetric branch's branch point).
fn at_plus_one(p: &Point) -> bool {
    let d = (critical(BifurcationKind::BranchPoint, p) - c64::new(1.0, 0.0)).norm();
    d <= 1e-2 || (on_circle(p) && d * d <= 1e-2)
}

fn critical(kind: BifurcationKind, p: &Point) -> c64 {
    let near = |z: c64| p.orbit.multipliers.iter().copied().min_by(|a, b| (a - z).norm().total_cmp(&(b - z).norm())).unwrap_or(c64::new(f64::NAN, 0.0));
    match kind {
        BifurcationKind::Fold | BifurcationKind::BranchPoint => near(c64::new(1.0, 0.0)),
        BifurcationKind::PeriodDoubling => near(c64::new(-1.0, 0.0)),
        BifurcationKind::NeimarkSacker => {
            p.orbit.multipliers.iter().copied().filter(|m| m.im > 0.0).min_by(|a, b| (a.norm() - 1.0).abs().total_cmp(&(b.norm() - 1.0).abs())).unwrap_or(c64::new(f64::NAN, 0.0))
        }
        _ => p.orbit.multipliers.first().copied().unwrap_or(c64::new(f64::NAN, 0.0)),
    }
}

/// Bisection on the arclength `s ∈ (0, s_b)` from `a` for where `differs`
/// (a sign change, a count change) happens, to 1e-12 of the parameter's
/// scale (by default the range): the
/// point on `a`'s side of the change nearest to it (its limit from `a`).
/// A trial that fails to converge ends the bisection at the bracket so far.
fn bisect<F: Family>(ctx: &Ctx<'_, F>, a: &Point, s_b: f64, b: &Point, value: impl Fn(&Point) -> f64, differs: impl Fn(&Point, &Point) -> bool) -> Point {
    bracket(ctx, a, s_b, b, value, differs).0
}

/// [`bisect`], with the bracket's end on `b`'s side (the point beyond the
/// change nearest to it).
fn bracket<F: Family>(ctx: &Ctx<'_, F>, a: &Point, s_b: f64, b: &Point, value: impl Fn(&Point) -> f64, differs: impl Fn(&Point, &Point) -> bool) -> (Point, Point) {
    let (mut lo, mut hi) = (0.0, s_b);
    let (mut pa, mut pb) = (a.clone(), b.clone());
    for _ in 0..60 {
        if hi - lo <= 1e-13 {
            break;
        }
        // Regula falsi on a continuous test function, halving otherwise.
        let (va, vb) = (value(&pa), value(&pb));
        let mut s = if va.is_finite() && vb.is_finite() && va != vb { lo + (hi - lo) * va / (va - vb) } else { 0.5 * (lo + hi) };
        if !(s > lo + 0.01 * (hi - lo) && s < hi - 0.01 * (hi - lo)) {
            s = 0.5 * (lo + hi);
        }
        let Ok(p) = ctx.at(a, s) else { break };
        if differs(&pa, &p) {
            (hi, pb) = (s, p);
        } else {
            (lo, pa) = (s, p);
        }
    }
    // The continuous tests' zero: interpolate the bracket; a count's: the
    // point just on `a`'s side.
    let (va, vb) = (value(&pa), value(&pb));
    if va.is_finite() && vb.is_finite() && va != vb && (va * vb < 0.0) {
        let w = va / (va - vb);
        let mut p = pa.clone();
        p.param = pa.param + w * (pb.param - pa.param);
        p.x = pa.x.iter().zip(&pb.x).map(|(x, y)| x + w * (y - x)).collect();
        // Not an orbit computed there: no mark (the front end builds it).
        p.mark = None;
        (p, pb)
    } else {
        (pa, pb)
    }
}
