//! The flow map of the exact event-driven run and its Jacobian.

use crate::variational::{Core, Linear};
use crate::OrbitError;
use faer::Mat;
use signorini_schemes::events::{Condensation, EventDriven, EventKind, EventRecord, FlowBases, ModalFlow, Reached, MAX_EVENTS};
use signorini_schemes::Dynamics;
use std::cell::RefCell;
use std::sync::Arc;

/// A linear structure with unilateral contacts, as the shooting sees it:
/// its exact event-driven flow ([`EventDriven`]) and that flow's
/// linearisation (the variational equations with the saltation matrices:
/// docs/theory.md §12).
pub struct Model {
    dy: Dynamics,
    e: f64,
    lin: Linear,
    max_events: usize,
    interrupt: Option<signorini_schemes::Interrupt>,
    /// Runs of the flow done with, started again for the next one
    /// ([`EventDriven::restart`]: the flows of the active sets met are
    /// kept, the same run bit for bit as a new one).
    runs: RefCell<Vec<EventDriven>>,
    /// The flows' load-free bases, shared with the other models of the
    /// structure ([`Shared`]).
    bases: Arc<FlowBases>,
    /// The flows of the held sets met by [`Model::phase_advance`].
    phases: RefCell<Vec<PhaseFlow>>,
}

/// One held set's flow without events: the free dofs' exact flow
/// ([`ModalFlow`]) with the held dofs on their bounds.
struct PhaseFlow {
    /// The held contacts, each with its side (`true`: the upper bound).
    held: Vec<(usize, bool)>,
    free: Vec<usize>,
    /// The held dofs and their bounds.
    fixed: Vec<(usize, f64)>,
    /// `None`: no free dof.
    flow: Option<ModalFlow>,
}

/// A parameter's stencil: the models at `λ_k` with weights `w_k`, so that
/// `Σ w_k g(λ_k)` is the derivative in `λ` of any quantity `g` of a
/// model's data (a central or one-sided difference: no event crosses it,
/// the data are smooth in `λ`), and `horizon` = `Σ w_k T(λ_k)`, the map's
/// horizon's derivative ([`Model::param_sensitivity`]).
pub(crate) struct Stencil<'a> {
    pub models: Vec<(&'a Model, f64)>,
    pub horizon: f64,
}

impl Stencil<'_> {
    /// The derivative of a quantity of the models.
    fn diff(&self, g: impl Fn(&Model) -> f64) -> f64 {
        self.models.iter().map(|&(m, w)| w * g(m)).sum()
    }
}

/// What the models of one structure (the same matrices and contact dofs;
/// loads, bounds and restitutions free) share: the linearisation's core
/// (its matrices, `M⁻¹`, each held set's modes) and the flows' bases (each
/// active set's modes). A family of scenes in a forcing's parameter keeps
/// it across the parameter's values ([`crate::SceneFamily`]): each
/// eigen-decomposition is computed once, and every model's flow and
/// Jacobian are the same bits as a model built alone.
#[derive(Clone)]
pub(crate) struct Shared {
    core: Arc<Core>,
    bases: Arc<FlowBases>,
}

impl Shared {
    /// The flows' bases.
    pub fn bases(&self) -> Arc<FlowBases> {
        self.bases.clone()
    }
}

/// The most runs a model keeps ([`Model::run_from`]): a flow and the
/// searches nested in it (a margin's golden-section trials).
const KEPT_RUNS: usize = 4;

/// An interior extremum of a free flight ([`Model::flight_extremum`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Extremum {
    /// Its distance to the bound it nears.
    pub distance: f64,
    /// When.
    pub t: f64,
    /// The contact.
    pub contact: usize,
    /// A maximum below the upper bound (`false`: a minimum above the lower).
    pub upper: bool,
}

/// Where the flow took a state: the state after `τ`, its Jacobian, and the
/// events on the way.
#[derive(Clone, Debug)]
pub struct Image {
    /// The state `(q_s, v_s)` at `t0 + τ`.
    pub x: Vec<f64>,
    /// `∂x(t0 + τ)/∂x(t0)` (when asked for).
    pub jacobian: Option<Mat<f64>>,
    /// The events in `(t0, t0 + τ]` (and at `t0`, if the start is on a bound).
    pub events: Vec<EventRecord>,
    /// The contacts held at the end (sorted).
    pub held: Vec<usize>,
    /// The vector field `(v, a)` of the state at the end (the derivative of
    /// the end state in `τ`).
    pub field: Vec<f64>,
}

impl Model {
    /// The model of `dy` with restitution `e` for every contact without
    /// its own (as the `event-driven(e)` scheme takes it).
    pub fn new(dy: Dynamics, e: f64) -> Result<Self, OrbitError> {
        Self::new_shared(dy, e, None, None, None)
    }

    /// [`Model::new`] on `shared`, which the caller has found to be `dy`'s
    /// structure (its bases' [`FlowBases::fits`]: the core was built from
    /// the same matrices and contact dofs, [`Model::shared`]; `None`: on
    /// parts of its own, the flows' bases in `bases` where it is `dy`'s
    /// structure), with `first` (a run of `dy` with restitution `e`, as
    /// [`EventDriven::new`] makes it: a scene's validated integrator) kept
    /// for its first flow: the same model, bit for bit.
    pub(crate) fn new_shared(dy: Dynamics, e: f64, shared: Option<&Shared>, bases: Option<Arc<FlowBases>>, first: Option<EventDriven>) -> Result<Self, OrbitError> {
        if !(0.0..=1.0).contains(&e) {
            return Err(OrbitError::Model(format!("restitution {e} is not allowed: [0, 1]")));
        }
        let lin = Linear::with_core(&dy, e, shared.map(|s| s.core.clone()))?;
        let bases = match shared {
            Some(s) => s.bases.clone(),
            None => bases.filter(|b| b.fits(&dy)).unwrap_or_else(|| Arc::new(FlowBases::new(&dy))),
        };
        let runs = first
            .map(|mut run| {
                run.set_max_events(MAX_EVENTS);
                run.share_bases(bases.clone());
                run
            })
            .into_iter()
            .collect();
        Ok(Self { dy, e, lin, max_events: crate::MAX_EVENTS_PER_MAP, interrupt: None, runs: RefCell::new(runs), bases, phases: RefCell::new(Vec::new()) })
    }

    /// What this model shares with the others of its structure.
    pub(crate) fn shared(&self) -> Shared {
        Shared { core: self.lin.core().clone(), bases: self.bases.clone() }
    }

    /// With at most `n` events in one evaluation of the map (beyond:
    /// [`OrbitError::TooManyEvents`]; [`crate::MAX_EVENTS_PER_MAP`] by
    /// default).
    pub fn with_max_events(mut self, n: usize) -> Self {
        self.max_events = n;
        self
    }

    /// A run of the flow from `(q0, v0)` at `t0`, without the interrupt
    /// (as [`EventDriven::new`] makes it): one kept from an earlier flow,
    /// started again, or a new one. Given back with [`Model::done`].
    fn run_from(&self, t0: f64, q0: &[f64], v0: &[f64]) -> Result<EventDriven, OrbitError> {
        let kept = self.runs.borrow_mut().pop();
        match kept {
            Some(mut run) => {
                run.set_interrupt(None);
                match run.restart(t0, q0, v0) {
                    Ok(()) => Ok(run),
                    Err(e) => {
                        self.done(run);
                        Err(e.into())
                    }
                }
            }
            None => Ok(EventDriven::new_with(&self.dy, t0, q0, v0, self.e, Some(self.bases.clone()))?),
        }
    }

    /// Keeps `run` for the next flow.
    fn done(&self, run: EventDriven) {
        let mut runs = self.runs.borrow_mut();
        if runs.len() < KEPT_RUNS {
            runs.push(run);
        }
    }

    /// With a poll every run of the flow calls (every 256 steps of its
    /// event search): `true` stops it with [`OrbitError::Interrupted`].
    pub fn with_interrupt(mut self, poll: Option<signorini_schemes::Interrupt>) -> Self {
        self.interrupt = poll;
        self
    }

    /// The restitution of every contact without its own.
    pub(crate) fn restitution(&self) -> f64 {
        self.e
    }

    /// The structure.
    pub fn dynamics(&self) -> &Dynamics {
        &self.dy
    }

    /// Unknowns of the state `(q_s, v_s)`: twice the dofs with mass (a
    /// massless contact dof is condensed: it carries no state).
    pub fn dim(&self) -> usize {
        self.lin.dim()
    }

    /// The dofs with mass, whose displacements and velocities make the state.
    pub fn state_dofs(&self) -> &[usize] {
        self.lin.state()
    }

    /// The lowest linear mode with no contact held: its circular
    /// frequency `ω` and its shape on the state dofs (`q_s`, mass-normalised;
    /// massless contact dofs condensed).
    pub fn lowest_mode(&self) -> Result<(f64, Vec<f64>), OrbitError> {
        let (k, shape) = self.lin.lowest_mode()?;
        Ok((k.max(0.0).sqrt(), shape))
    }

    /// The state of a full `(q, v)`.
    pub fn pack(&self, q: &[f64], v: &[f64]) -> Vec<f64> {
        self.lin.pack(q, v)
    }

    /// The full `(q, v)` of a state as the exact run takes it at `t`
    /// (massless dofs condensed, a contact on its bound held if pressed).
    pub fn settle(&self, t: f64, x: &[f64]) -> Result<(Vec<f64>, Vec<f64>), OrbitError> {
        let (q, v) = self.lin.unpack(x);
        let run = self.run_from(t, &q, &v)?;
        let (_, q, v) = run.state();
        self.done(run);
        Ok((q, v))
    }

    /// The mechanical energy of a state at `t` and its gradient in the state.
    pub fn energy(&self, t: f64, x: &[f64]) -> Result<(f64, Vec<f64>), OrbitError> {
        let (q, v) = self.settle(t, x)?;
        let n = q.len();
        let mut f = vec![0.0; n];
        self.dy.load_at(t, &mut f);
        let (mut kq, mut mv) = (vec![0.0; n], vec![0.0; n]);
        self.dy.stiffness.mul_vec(&q, &mut kq);
        self.dy.mass.mul_vec(&v, &mut mv);
        let e = 0.5 * (0..n).map(|i| v[i] * mv[i] + q[i] * kq[i]).sum::<f64>() - (0..n).map(|i| f[i] * q[i]).sum::<f64>();
        let gq: Vec<f64> = (0..n).map(|i| kq[i] - f[i]).collect();
        Ok((e, self.lin.pack(&gq, &mv)))
    }

    /// The exact flow from `x0` at `t0` over `τ`, with its Jacobian if
    /// `jacobian` (a contact dof beyond its bound in `x0`, as a Newton
    /// iterate may put it, starts on the bound). Errors: the run's ([`OrbitError::Events`]); for the
    /// Jacobian, an event where the flow has no derivative (two contacts
    /// reached at one instant, an impact at zero speed: grazing). Through
    /// an accumulation of impacts the Jacobian is the limit of the
    /// saltations (docs/theory.md §12.1.1).
    pub fn flow(&self, t0: f64, x0: &[f64], tau: f64, jacobian: bool) -> Result<Image, OrbitError> {
        Ok(self.flow_within(t0, x0, tau, jacobian, usize::MAX)?.expect("no bound on the impacts"))
    }

    /// [`Model::flow`] that stops as soon as the run has had more than
    /// `impacts` impacts (at a nonzero speed, as [`crate::Orbit::impacts`]
    /// counts them): `None` then. Newton keeping a number of impacts
    /// rejects such a trial whatever the rest of its run (on a map that
    /// chatters, the most of it).
    pub(crate) fn flow_within(&self, t0: f64, x0: &[f64], tau: f64, jacobian: bool, impacts: usize) -> Result<Option<Image>, OrbitError> {
        self.flow_from(t0, x0, tau, jacobian, impacts, &[], &mut Vec::new(), None)
    }

    /// [`Model::flow_within`] with [`Model::flow_reading`]'s readings: the
    /// checks of `x0` and `τ`, the start on the bounds, the run.
    /// With `sens`, the map's derivative in the stencil's parameter into
    /// its vector ([`Model::param_sensitivity`]).
    #[allow(clippy::too_many_arguments)]
    fn flow_from(
        &self,
        t0: f64,
        x0: &[f64],
        tau: f64,
        jacobian: bool,
        impacts: usize,
        reads: &[f64],
        states: &mut Vec<Vec<f64>>,
        sens: Option<(&Stencil, &mut Vec<f64>)>,
    ) -> Result<Option<Image>, OrbitError> {
        if x0.len() != self.dim() {
            return Err(OrbitError::Size { given: x0.len(), expected: self.dim() });
        }
        if !(tau.is_finite() && tau > 0.0) {
            return Err(OrbitError::Model(format!("the flow's horizon {tau} is not allowed: > 0 and finite")));
        }
        let (mut q0, v0) = self.lin.unpack(x0);
        // A start beyond a bound (a Newton iterate) is taken on it: there
        // its derivative in a parameter is the bound's.
        let mut s0 = vec![0.0; self.dim()];
        for (j, c) in self.dy.contacts.iter().enumerate().filter(|(_, c)| !c.massless) {
            let side = if q0[c.dof] < c.bounds.lo { Some(false) } else { (q0[c.dof] > c.bounds.hi).then_some(true) };
            if let (Some(upper), Some((st, _)), Some(row)) = (side, sens.as_ref(), self.lin.state().iter().position(|&d| d == c.dof)) {
                s0[row] = st.diff(|m| m.bound(j, upper));
            }
            q0[c.dof] = q0[c.dof].clamp(c.bounds.lo, c.bounds.hi);
        }
        let mut run = self.run_from(t0, &q0, &v0)?;
        run.set_interrupt(self.interrupt.clone());
        let sens = sens.map(|(st, out)| {
            *out = s0;
            (st, out)
        });
        let out = self.flow_run(&mut run, t0, tau, jacobian, impacts, reads, states, sens);
        self.done(run);
        out
    }

    /// [`Model::flow`] that also reads the state at `t0 + r` for each `r`
    /// of `reads` (increasing, each below `τ`) on the way: the same run,
    /// which a reading neither starts again nor re-bases (its event search
    /// goes on from where it stands), and the Jacobian carried from event
    /// to event as without them. So the image is `flow(t0, x0, τ,
    /// jacobian)`'s and each state read `flow(t0, x0, r, false).x`, bit for
    /// bit (`tests/it/readings.rs`): a continuation's return check takes
    /// the states of its orbits at the intermediate periods from the
    /// corrector's last flow, instead of flowing again to each.
    pub fn flow_reading(&self, t0: f64, x0: &[f64], tau: f64, jacobian: bool, reads: &[f64]) -> Result<(Image, Vec<Vec<f64>>), OrbitError> {
        let mut states = Vec::with_capacity(reads.len());
        let image = self.flow_from(t0, x0, tau, jacobian, usize::MAX, reads, &mut states, None)?.expect("no bound on the impacts");
        Ok((image, states))
    }

    /// The exact flow from `x0` at `t0` read at `t0 + k·step`, `k = 1, …,
    /// n`: `visit(k, x_k)` after each reading, which stops the flow there
    /// by returning `false` (the last reading ends it whatever `visit` says). The run is [`Model::flow`]'s over `n·step`,
    /// read on the way (a reading does not start the run again: the same
    /// trajectory, the same bound on its events), so the last state, `k =
    /// n`, is `flow(t0, x0, n·step)`'s bit for bit. Returns the last `k`
    /// and its state.
    pub fn flow_read(&self, t0: f64, x0: &[f64], step: f64, n: usize, mut visit: impl FnMut(usize, &[f64]) -> bool) -> Result<(usize, Vec<f64>), OrbitError> {
        if x0.len() != self.dim() {
            return Err(OrbitError::Size { given: x0.len(), expected: self.dim() });
        }
        if !(step.is_finite() && step > 0.0 && n > 0) {
            return Err(OrbitError::Model(format!("the flow's readings every {step} ({n} of them) are not allowed: a step > 0 and finite, at least one")));
        }
        let (mut q0, v0) = self.lin.unpack(x0);
        for c in self.dy.contacts.iter().filter(|c| !c.massless) {
            q0[c.dof] = q0[c.dof].clamp(c.bounds.lo, c.bounds.hi);
        }
        let mut run = self.run_from(t0, &q0, &v0)?;
        run.set_interrupt(self.interrupt.clone());
        let out = self.read_run(&mut run, t0, step, n, &mut visit);
        self.done(run);
        out
    }

    /// [`Model::flow_read`] on `run`, started at `t0`.
    fn read_run(&self, run: &mut EventDriven, t0: f64, step: f64, n: usize, visit: &mut dyn FnMut(usize, &[f64]) -> bool) -> Result<(usize, Vec<f64>), OrbitError> {
        let size = self.dy.mass.n();
        let (mut q, mut v) = (vec![0.0; size], vec![0.0; size]);
        let mut x = Vec::new();
        for k in 1..=n {
            // As `flow` ends: `t0 + τ` with `τ = k·step`.
            let t_end = t0 + k as f64 * step;
            while run.next_change(t_end)? != Reached::End {
                if run.events().len() > self.max_events {
                    return Err(signorini_schemes::events::EventsError::TooManyEvents { t: run.time(), events: run.events().len() }.into());
                }
            }
            run.state_into(&mut q, &mut v);
            // `Linear::pack` into the same vector.
            x.clear();
            x.extend(self.lin.state().iter().map(|&d| q[d]));
            x.extend(self.lin.state().iter().map(|&d| v[d]));
            if !visit(k, &x) || k == n {
                return Ok((k, x));
            }
        }
        Ok((n, x))
    }

    /// [`Model::flow_within`] on `run`, started at `t0`, its states at
    /// `t0 + r` (`r` in `reads`, increasing, below `τ`) into `states`
    /// ([`Model::flow_reading`]).
    /// With `sens` (its vector holding the start's derivative), the map's
    /// derivative in the stencil's parameter carried as one more column
    /// of the Jacobian (the same transports and saltations), plus each
    /// phase's own term ([`Model::phase_term`]), each impact's
    /// ([`Model::linearise_event`]) and the horizon's, into the vector.
    #[allow(clippy::too_many_arguments)]
    fn flow_run(
        &self,
        run: &mut EventDriven,
        t0: f64,
        tau: f64,
        jacobian: bool,
        impacts: usize,
        reads: &[f64],
        states: &mut Vec<Vec<f64>>,
        sens: Option<(&Stencil, &mut Vec<f64>)>,
    ) -> Result<Option<Image>, OrbitError> {
        let dim = self.dim();
        let (st, sens_out) = match sens {
            Some((st, out)) => (Some(st), Some(out)),
            None => (None, None),
        };
        let mut jac = match (st, sens_out.as_ref()) {
            (Some(_), Some(s0)) => Some(Mat::<f64>::from_fn(dim, dim + 1, |i, j| {
                if j == dim {
                    s0[i]
                } else if i == j {
                    1.0
                } else {
                    0.0
                }
            })),
            _ => jacobian.then(|| Mat::<f64>::identity(dim, dim)),
        };
        let mut seen = run.events().len();
        // The events of the start (a contact on its bound, approaching).
        if seen > 0 {
            if let Some(j) = jac.as_mut() {
                self.linearise_event(run, run.events(), &[], &sorted_held(run), j, st)?;
            }
        }
        // The state the phase under way started from (with `sens`).
        let mut start = st.map(|_| run.state());
        let mut held = sorted_held(run);
        let mut t_prev = t0;
        let t_end = t0 + tau;
        // Impacts so far, over the events counted so far.
        let (mut hits, mut counted) = (0, 0);
        let mut read = 0;
        loop {
            // The next reading's time, as `flow` ends: `t0 + r`.
            let stop = match reads.get(read) {
                Some(&r) if t0 + r < t_end => t0 + r,
                _ => t_end,
            };
            // Every applied event, those that log nothing included (a
            // landing at zero speed may start a held phase without a record).
            let event = run.next_change(stop)?;
            if stop < t_end && event == Reached::End {
                // A reading: the run stands at `stop` (read from its phase's
                // base, which stays); no event, nothing carried.
                let (_, q, v) = run.state();
                states.push(self.lin.pack(&q, &v));
                read += 1;
                continue;
            }
            if run.events().len() > self.max_events {
                return Err(signorini_schemes::events::EventsError::TooManyEvents { t: run.time(), events: run.events().len() }.into());
            }
            hits += run.events()[counted..].iter().filter(|e| e.kind == EventKind::Impact && e.velocity_before != 0.0).count();
            counted = run.events().len();
            if hits > impacts {
                return Ok(None);
            }
            let t_now = run.time();
            if let Some(j) = jac.as_mut() {
                if t_now > t_prev {
                    self.lin.transport(&held, t_now - t_prev, j)?;
                    if let (Some(st), Some((ta, qa, va))) = (st, start.as_ref()) {
                        self.phase_term(st, &held, *ta, qa, va, t_now - t_prev, j)?;
                    }
                }
            }
            t_prev = t_now;
            if event == Reached::End {
                break;
            }
            let new_held = sorted_held(run);
            if let Some(j) = jac.as_mut() {
                if event == Reached::Event(None) && new_held != held {
                    // A contact that lands at zero speed and is held from
                    // there: a grazing, where the map has no derivative
                    // (nearby starts land with a speed, or fly on).
                    return Err(OrbitError::NoDerivative { t: t_now, why: "a contact landed on its bound at zero speed and is held there (grazing)".into() });
                }
                self.linearise_event(run, &run.events()[seen..], &held, &new_held, j, st)?;
            }
            if st.is_some() {
                start = Some(run.state());
            }
            seen = run.events().len();
            held = new_held;
        }
        let (t, q, v) = run.state();
        let field = if self.lin.massless() { self.lin.field(&self.dy, &[], t, &q, &v) } else { self.lin.field(&self.dy, &held, t, &q, &v) };
        if let (Some(st), Some(out), Some(j)) = (st, sens_out, jac.as_mut()) {
            // The horizon moves with the parameter: `f(x(T), T) dT/dλ`.
            *out = (0..dim).map(|i| j[(i, dim)] + field[i] * st.horizon).collect();
            jac = jacobian.then(|| j.subcols(0, dim).to_owned());
        }
        Ok(Some(Image { x: self.lin.pack(&q, &v), jacobian: jac, events: run.events().to_vec(), held, field }))
    }

    /// The state `x` with the impulse `r` of the contact `contact` added
    /// (`sign` = 1) or taken back (`sign` = −1): `v ± M⁻¹ e_c r`. The
    /// section state on the other side of an impact that crosses the
    /// section's time.
    pub fn with_impulse(&self, x: &[f64], contact: usize, r: f64, sign: f64) -> Vec<f64> {
        if self.lin.massless() {
            return x.to_vec();
        }
        let dv = self.lin.minv_impulse(&[(contact, sign * r)]);
        let s = self.lin.state().len();
        let mut out = x.to_vec();
        for (i, &d) in self.lin.state().iter().enumerate() {
            out[s + i] += dv[d];
        }
        out
    }

    /// The smallest distance of a contact dof to its bounds over
    /// `[t0, t0 + τ]` from `x0` (0 for a contact on its bound, held or at
    /// an impact; the exact run is never beyond): sampled at 256 instants,
    /// the closest refined by golden-section search.
    pub fn margin(&self, t0: f64, x0: &[f64], tau: f64) -> Result<f64, OrbitError> {
        let dist = |q: &[f64]| -> f64 { self.dy.contacts.iter().map(|c| (q[c.dof] - c.bounds.lo).min(c.bounds.hi - q[c.dof])).fold(f64::INFINITY, f64::min) };
        let (q0, v0) = self.lin.unpack(x0);
        let mut run = self.run_from(t0, &q0, &v0)?;
        let samples = 256;
        let mut best = (f64::INFINITY, 0usize);
        let (mut q, mut v) = (vec![0.0; q0.len()], vec![0.0; q0.len()]);
        for i in 0..=samples {
            run.run_until(t0 + tau * i as f64 / samples as f64, self.max_events)?;
            run.state_into(&mut q, &mut v);
            let d = dist(&q);
            if d < best.0 {
                best = (d, i);
            }
        }
        self.done(run);
        // Golden section on [t_{i−1}, t_{i+1}].
        let h = tau / samples as f64;
        let at = |t: f64| -> Result<f64, OrbitError> {
            let mut r = self.run_from(t0, &q0, &v0)?;
            let d = r.run_until(t, self.max_events).map(|()| dist(&r.state().1));
            self.done(r);
            Ok(d?)
        };
        let (a, b) = (t0 + h * (best.1 as f64 - 1.0).max(0.0), t0 + h * (best.1 as f64 + 1.0).min(samples as f64));
        let (d, _) = golden_min(a, b, 1e-14 * tau, at)?;
        Ok(best.0.min(d))
    }

    /// The smallest distance to a bound at an interior extremum of a free
    /// flight over `[t0, t0 + τ]` from `x0`: at each local maximum of a
    /// contact dof's displacement between two events, its distance to the
    /// upper bound; at each local minimum, to the lower one. It reaches 0
    /// where a flight grazes a stop — a further impact appearing on an
    /// orbit that already impacts (its impacts, where the distance is 0,
    /// are ends of flights, not extrema), or the first one on an orbit
    /// without. `f64::INFINITY` when no flight has such an extremum.
    /// Sampled at 512 instants (and two beyond `t0 + τ`, so that an
    /// extremum at the section of a periodic orbit is seen); each extremum
    /// with no event within a sample of it is refined by golden-section
    /// search, each trial a run from the sample before it. A pair of
    /// extrema closer than a sample apart is not seen.
    pub fn flight_margin(&self, t0: f64, x0: &[f64], tau: f64) -> Result<f64, OrbitError> {
        Ok(self.flight_extremum(t0, x0, tau)?.map_or(f64::INFINITY, |e| e.distance))
    }

    /// The extremum of [`Model::flight_margin`]: where it is and which
    /// bound it nears (`None` when no flight has one).
    pub(crate) fn flight_extremum(&self, t0: f64, x0: &[f64], tau: f64) -> Result<Option<Extremum>, OrbitError> {
        if x0.len() != self.dim() {
            return Err(OrbitError::Size { given: x0.len(), expected: self.dim() });
        }
        if !(tau.is_finite() && tau > 0.0) {
            return Err(OrbitError::Model(format!("the flight margin's horizon {tau} is not allowed: > 0 and finite")));
        }
        let (q0, v0) = self.lin.unpack(x0);
        let mut run = self.run_from(t0, &q0, &v0)?;
        let samples = 512;
        let h = tau / samples as f64;
        // (t, q, v, events so far) at each sample.
        let mut at = Vec::with_capacity(samples + 3);
        for i in 0..=samples + 2 {
            let t = t0 + h * i as f64;
            run.run_until(t, self.max_events)?;
            let (_, q, v) = run.state();
            at.push((t, q, v, run.events().len()));
        }
        self.done(run);
        let mut best: Option<Extremum> = None;
        let mut keep = |distance: f64, t: f64, contact: usize, upper: bool| {
            if best.is_none_or(|b| distance < b.distance) {
                best = Some(Extremum { distance, t, contact, upper });
            }
        };
        for i in 1..at.len() - 1 {
            let (prev, mid, next) = (&at[i - 1], &at[i], &at[i + 1]);
            if prev.3 != next.3 {
                continue;
            }
            for (j, c) in self.dy.contacts.iter().enumerate() {
                let d = c.dof;
                let (a, b, z) = (prev.1[d], mid.1[d], next.1[d]);
                let upper = b > a;
                // A local maximum below the upper bound, a minimum above the lower.
                // The distance to the bound: `sign · (bound − q)`.
                let (bound, sign) = if b > a && b >= z && c.bounds.hi.is_finite() {
                    (c.bounds.hi, 1.0)
                } else if b < a && b <= z && c.bounds.lo.is_finite() {
                    (c.bounds.lo, -1.0)
                } else {
                    continue;
                };
                let dist = |q: &[f64]| sign * (bound - q[d]);
                keep(dist(&mid.1), mid.0, j, upper);
                let trial = |t: f64| -> Result<f64, OrbitError> {
                    let mut r = self.run_from(prev.0, &prev.1, &prev.2)?;
                    let d = r.run_until(t, self.max_events).map(|()| dist(&r.state().1));
                    self.done(r);
                    Ok(d?)
                };
                let (m, t) = golden_min(prev.0, next.0, 1e-14 * tau, trial)?;
                keep(m, t, j, upper);
            }
        }
        Ok(best)
    }

    /// The gradient in the start state `x0` (at `t0`) of the displacement
    /// of the contact `contact`'s dof at `t` (the row of the flow's
    /// Jacobian to `t`); `None` for a massless contact dof (not in the
    /// state).
    pub(crate) fn displacement_gradient(&self, t0: f64, x0: &[f64], t: f64, contact: usize) -> Result<Option<Vec<f64>>, OrbitError> {
        let Some(row) = self.dy.contacts.get(contact).and_then(|c| self.lin.state().iter().position(|&d| d == c.dof)) else { return Ok(None) };
        let img = self.flow(t0, x0, t - t0, true)?;
        let j = img.jacobian.expect("asked for");
        Ok(Some((0..self.dim()).map(|c| j[(row, c)]).collect()))
    }

    /// The derivative of the map `x0 → x(t0 + τ)` in the parameter of
    /// `st` at fixed `x0`, `s(t0 + τ)` with `s = ∂x/∂λ`, from this model's
    /// exact run (`self` is the model at `λ`): within each phase
    /// `s' = A s + ∂F/∂λ`, carried by the phase's transition and its own term
    /// ([`Model::phase_term`]); at each impact the saltation and the
    /// impact's own term; the horizon's `f(x(T)) dT/dλ` (docs/theory.md
    /// §12.2). Exact to the stencil's differences of smooth data (no
    /// event crosses them). With massless contact dofs each phase's flow
    /// is the condensed one ([`Model::phase_flow`]) and no event adds a
    /// term (the vector field is continuous at a landing and a lift-off).
    pub(crate) fn param_sensitivity(&self, t0: f64, x0: &[f64], tau: f64, st: &Stencil) -> Result<Vec<f64>, OrbitError> {
        let mut s = Vec::new();
        self.flow_from(t0, x0, tau, false, usize::MAX, &[], &mut Vec::new(), Some((st, &mut s)))?;
        Ok(s)
    }

    /// The bound of the contact `j` (`upper`: its upper one).
    fn bound(&self, j: usize, upper: bool) -> f64 {
        let b = self.dy.contacts[j].bounds;
        if upper {
            b.hi
        } else {
            b.lo
        }
    }

    /// Whether the contact `j`, on a bound in `q`, is on its upper one.
    fn upper(&self, j: usize, q: &[f64]) -> bool {
        let c = &self.dy.contacts[j];
        (c.bounds.hi - q[c.dof]).abs() < (q[c.dof] - c.bounds.lo).abs()
    }

    /// A phase's own term of the parameter's derivative, added to the
    /// Jacobian's last column: `∫ Φ(t_a + τ, r) ∂F/∂λ(x(r), r) dr` over
    /// the phase, which is the stencil's difference of the phase's flows
    /// without events from its start `(q_a, v_a)` at `t_a` over `τ` (each
    /// model's, its held dofs on its own bounds: a bound that moves with
    /// `λ` holds them there).
    #[allow(clippy::too_many_arguments)]
    fn phase_term(&self, st: &Stencil, held: &[usize], ta: f64, qa: &[f64], va: &[f64], tau: f64, jac: &mut Mat<f64>) -> Result<(), OrbitError> {
        let sides: Vec<(usize, bool)> = held.iter().map(|&j| (j, self.upper(j, qa))).collect();
        let last = jac.ncols() - 1;
        for &(m, w) in &st.models {
            let x = m.phase_advance(&sides, ta, qa, va, tau)?;
            for (i, xi) in x.iter().enumerate() {
                jac[(i, last)] += w * xi;
            }
        }
        Ok(())
    }

    /// The state after `τ` from `(q, v)` at `t` with the contacts `held`
    /// (each with its side) on this model's bounds and no event.
    fn phase_advance(&self, held: &[(usize, bool)], t: f64, q: &[f64], v: &[f64], tau: f64) -> Result<Vec<f64>, OrbitError> {
        let mut phases = self.phases.borrow_mut();
        let i = match phases.iter().position(|p| p.held == held) {
            Some(i) => i,
            None => {
                phases.push(self.phase_flow(held)?);
                phases.len() - 1
            }
        };
        let p = &phases[i];
        let (mut qo, mut vo) = (q.to_vec(), v.to_vec());
        for &(d, b) in &p.fixed {
            (qo[d], vo[d]) = (b, 0.0);
        }
        if let Some(flow) = &p.flow {
            let nf = p.free.len();
            let qf: Vec<f64> = p.free.iter().map(|&d| q[d]).collect();
            let vf: Vec<f64> = p.free.iter().map(|&d| v[d]).collect();
            let (mut qn, mut vn) = (vec![0.0; nf], vec![0.0; nf]);
            flow.advance(t, &qf, &vf, tau, &mut qn, &mut vn);
            for (k, &d) in p.free.iter().enumerate() {
                (qo[d], vo[d]) = (qn[k], vn[k]);
            }
        }
        Ok(self.lin.pack(&qo, &vo))
    }

    /// The flow of the free dofs with the contacts `held` on their bounds:
    /// `M_ff q_f'' + C_ff q_f' + K_eff q_f = F_eff`, a held dof at rest,
    /// the massless dofs not held statically condensed ([`Condensation`],
    /// the run's own phase: docs/theory.md §9.3).
    fn phase_flow(&self, held: &[(usize, bool)]) -> Result<PhaseFlow, OrbitError> {
        let dy = &self.dy;
        let fixed: Vec<(usize, f64)> = held.iter().map(|&(j, upper)| (dy.contacts[j].dof, self.bound(j, upper))).collect();
        let mut cond: Vec<usize> = dy.contacts.iter().filter(|c| c.massless && !fixed.iter().any(|f| f.0 == c.dof)).map(|c| c.dof).collect();
        cond.sort_unstable();
        cond.dedup();
        let cd = Condensation::new(dy, &fixed, &cond)?;
        let flow = if cd.free().is_empty() { None } else { Some(cd.flow(dy)?) };
        Ok(PhaseFlow { held: held.to_vec(), free: cd.free().to_vec(), fixed, flow })
    }

    /// With `st`, the impact's own term of the derivative in the
    /// stencil's parameter into the Jacobian's last column: the guard's
    /// bound `b` moves the impact's time, `(f⁺ − DJ f⁻)(−∂b/∂λ)/v_n`, and
    /// the restitutions the jump, `∂v⁺/∂e ∂e/∂λ` (docs/theory.md §12.2).
    fn linearise_event(&self, run: &EventDriven, recs: &[EventRecord], before: &[usize], after: &[usize], jac: &mut Mat<f64>, st: Option<&Stencil>) -> Result<(), OrbitError> {
        // Chattering to rest: the run ends an accumulation of impacts at
        // its last located impact, the contact put at rest there (then
        // held if pressed); the contacts that accumulate jump plastically.
        let accumulated: Vec<usize> = recs.iter().filter(|r| r.kind == EventKind::Accumulation).map(|r| r.contact).collect();
        if !accumulated.is_empty() {
            // When the held phase holds every dof with mass (the
            // oscillator), the state is on the bound at rest until the held
            // force's zero, a time the start does not move: every start
            // near this one leaves the phase in the same state, so the
            // map's Jacobian is exactly 0 from here on (central differences
            // of the map: 0 to round-off).
            let all_held = !self.lin.massless() && self.lin.state().iter().all(|d| after.iter().any(|&j| self.lin.sites[j].dof == *d));
            if all_held {
                *jac = Mat::zeros(jac.nrows(), jac.ncols());
                return Ok(());
            }
            // A run ended at rest on the bound but not held: an impact
            // slower than the run resolves (§9, micro-impacts), as at a
            // grazing, not a chatter pressed onto its bound.
            if let Some(r) = recs.iter().find(|r| r.kind == EventKind::Accumulation && !after.contains(&r.contact)) {
                return Err(OrbitError::NoDerivative {
                    t: r.t,
                    why: format!("contact {}'s impacts ended at rest on its bound without being held there (an impact too slow for the run to resolve, as at a grazing)", r.contact),
                });
            }
            // With dofs left free, the product of the chattering run's
            // saltations converges (the time shift carried, the rest
            // shrinking by e an impact), and the run's last located impact,
            // where it puts the contact at rest, closes it as a plastic
            // impact into the phase after (docs/theory.md §12.1.1).
        }
        // Massless contacts: the vector field is continuous at every event.
        if self.lin.massless() {
            return Ok(());
        }
        let impacts: Vec<&EventRecord> = recs.iter().filter(|r| r.kind == EventKind::Impact).collect();
        let Some(guard) = impacts.first() else { return Ok(()) };
        if let Some(other) = impacts.iter().skip(1).find(|r| r.velocity_before != 0.0 && !before.contains(&r.contact)) {
            return Err(OrbitError::NoDerivative { t: guard.t, why: format!("contacts {} and {} reached their bounds at one instant", guard.contact, other.contact) });
        }
        let (t, q, vplus) = run.state();
        // The impulses of the instant: the impacts' and the accumulations'
        // (that bring their contacts to rest).
        let jumps: Vec<&EventRecord> = recs.iter().filter(|r| r.kind == EventKind::Impact || r.kind == EventKind::Accumulation).collect();
        let impulses: Vec<(usize, f64)> = jumps.iter().map(|r| (r.contact, r.impulse)).collect();
        let dv = self.lin.minv_impulse(&impulses);
        let vminus: Vec<f64> = vplus.iter().zip(&dv).map(|(a, b)| a - b).collect();
        let vn = vminus[self.lin.sites[guard.contact].dof];
        if vn == 0.0 {
            return Err(OrbitError::NoDerivative { t, why: format!("contact {} reached its bound at zero speed (grazing)", guard.contact) });
        }
        let mut active: Vec<usize> = jumps.iter().filter(|r| r.impulse != 0.0).map(|r| r.contact).collect();
        active.sort_unstable();
        active.dedup();
        let f_minus = self.lin.field(&self.dy, before, t, &q, &vminus);
        let f_plus = self.lin.field(&self.dy, after, t, &q, &vplus);
        let active: Vec<(usize, f64)> = active.into_iter().map(|j| (j, if accumulated.contains(&j) { 0.0 } else { self.lin.sites[j].restitution })).collect();
        let column = self.lin.saltation(guard.contact, &active, &f_minus, &f_plus, vn, jac);
        if let Some(st) = st {
            let n = q.len();
            let last = jac.ncols() - 1;
            let db = st.diff(|m| m.bound(guard.contact, self.upper(guard.contact, &q)));
            let (ids, de): (Vec<usize>, Vec<f64>) = active.iter().map(|&(j, _)| (j, if accumulated.contains(&j) { 0.0 } else { st.diff(|m| m.lin.sites[j].restitution) })).unzip();
            let mut dv = vec![0.0; n];
            self.lin.impact_change(&ids, &de, &vminus, &mut dv);
            for (i, c) in column.iter().enumerate() {
                jac[(i, last)] -= c * db;
            }
            for i in 0..n {
                jac[(n + i, last)] += dv[i];
            }
        }
        Ok(())
    }
}

fn sorted_held(run: &EventDriven) -> Vec<usize> {
    let mut h: Vec<usize> = run.held_iter().map(|(c, _)| c).collect();
    h.sort_unstable();
    h
}

/// The minimum of `f` on `[a, b]` by golden-section search, to an
/// interval of `tol`: `(f there, where)`.
pub(crate) fn golden_min(mut a: f64, mut b: f64, tol: f64, f: impl Fn(f64) -> Result<f64, OrbitError>) -> Result<(f64, f64), OrbitError> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    for _ in 0..80 {
        if b - a <= tol {
            break;
        }
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - g * (b - a);
            fc = f(c)?;
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + g * (b - a);
            fd = f(d)?;
        }
    }
    Ok(if fc < fd { (fc, c) } else { (fd, d) })
}
