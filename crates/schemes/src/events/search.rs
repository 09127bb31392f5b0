//! Locating events without a miss (docs/theory.md §9.2).
//!
//! Every quantity whose sign change is an event — a contact dof's distance
//! to its bound in free flight, a held contact's force — is, along the exact
//! flow, a [`Functional`] of the modal state:
//!
//! ```text
//! g(t) = Σ_i β_i η_i(t) + α_i η_i'(t) + c₀ + c₁ (t − t_p) + Σ_j c_j sin(Ω_j t + p_j)
//! ```
//!
//! (`c₀ + c₁ (t − t_p)`: the constant and, with piecewise-linear loads, the
//! ramp of the current piece; [`Functional::set_piece`]).
//!
//! [`Search::first_zero`] advances the flow by steps that cannot cross a
//! zero of any of them. From a time where `g > 0`, split the modes at an
//! index `s`: the low ones (`i < s`) and the load terms contribute
//! `g_L(τ) >= g_L + g_L' τ − B τ²/2` (Taylor with remainder, `B` a bound of
//! `|g_L''|` over the window), the high ones at most their amplitude `A`
//! (a bound of `|Σ_{i>=s} β_i η_i + α_i η_i'|` over the window). So
//! `g(τ) >= g_L − A + g_L' τ − B τ²/2`, positive up to its first root: a
//! safe step. The step taken is the largest over the splits (far from an
//! event the high modes only cost their amplitude; near one they join the
//! curvature and the step converges quadratically to the root, like
//! Newton's from one side). An event is declared when the safe step falls
//! below a relative 1e-15 of the time.
//!
//! From a time where `g = 0` (a contact just released, or leaving its bound
//! after an impact) the first nonzero derivative `g⁽ᵐ⁾ = d` decides: `d < 0`
//! is an event now; `d > 0` gives the safe lift-off step `τ < (m + 1) d / B`
//! from `g(τ) >= d τᵐ/m! − B τᵐ⁺¹/(m + 1)!` (`B` bounding `|g⁽ᵐ⁺¹⁾|`).

use super::flow::{Event, Functional, ModalFlow, Piece, JET};
use super::record::EventsError;
use super::Bound;

/// Orders of a functional's jet.
const GJET: usize = JET - 1;

impl Functional {
    /// The gaps of a contact dof's position `q_c` (this functional) to its
    /// finite bounds, each `>= 0` inside them: `(Lower, q_c − lo)` and
    /// `(Upper, hi − q_c)`.
    pub fn gaps(&self, lo: f64, hi: f64) -> Vec<(Bound, Functional)> {
        let gap = |bound: f64| {
            let mut f = self.clone();
            f.constant -= bound;
            f.now = (f.constant, 0.0, 0.0);
            f
        };
        let mut out = Vec::with_capacity(2);
        if lo.is_finite() {
            out.push((Bound::Lower, gap(lo)));
        }
        if hi.is_finite() {
            out.push((Bound::Upper, gap(hi).negated()));
        }
        out
    }

    /// `−g`.
    pub fn negated(mut self) -> Self {
        self.beta.iter_mut().for_each(|x| *x = -*x);
        self.alpha.iter_mut().for_each(|x| *x = -*x);
        self.constant = -self.constant;
        self.waves.iter_mut().for_each(|w| w.0 = -w.0);
        self.ramps.iter_mut().for_each(|x| *x = -*x);
        self.now = (-self.now.0, -self.now.1, self.now.2);
        self
    }

    /// The series on `piece`: `c₀ = constant + Σ_l r_l s_l(t_p)`,
    /// `c₁ = Σ_l r_l s_l'` (also to be called once without series, after
    /// `constant` is set).
    pub fn set_piece(&mut self, piece: &Piece) {
        let (mut c0, mut c1) = (self.constant, 0.0);
        for (l, r) in self.ramps.iter().enumerate() {
            c0 += r * piece.values[l];
            c1 += r * piece.slopes[l];
        }
        self.now = (c0, c1, piece.t_p);
    }

    /// `|c₀ + c₁ (t − t_p)|` (a round-off scale).
    fn constant_abs(&self, t: f64) -> f64 {
        let (c0, c1, tp) = self.now;
        if c1 == 0.0 {
            c0.abs()
        } else {
            (c0 + c1 * (t - tp)).abs()
        }
    }

    fn alpha(&self, i: usize) -> f64 {
        self.alpha.get(i).copied().unwrap_or(0.0)
    }

    /// The load part's derivative of order `m` at `t`.
    fn wave(&self, t: f64, m: usize) -> f64 {
        let (c0, c1, tp) = self.now;
        let mut s = match m {
            0 if c1 == 0.0 => c0,
            0 => c0 + c1 * (t - tp),
            1 => c1,
            _ => 0.0,
        };
        for &(c, w, p) in &self.waves {
            let th = w * t + p + m as f64 * std::f64::consts::FRAC_PI_2;
            s += c * w.powi(m as i32) * th.sin();
        }
        s
    }

    /// The load part's derivatives of orders 2..=4 at `t` (one `sin_cos`
    /// per wave: [`wave`](Self::wave)'s to a few ulps of `c Ωᵐ`).
    fn wave_jet(&self, t: f64) -> [f64; 3] {
        let mut j = [0.0; 3];
        for &(c, w, p) in &self.waves {
            let (s, co) = (w * t + p).sin_cos();
            let w2 = c * w * w;
            j[0] -= w2 * s;
            j[1] -= w2 * w * co;
            j[2] += w2 * w * w * s;
        }
        j
    }

    /// A bound of the load part's derivative of order `m` (`m >= 1`; all
    /// times of the piece; `m = 0`: the waves' alone).
    fn wave_bound(&self, m: usize) -> f64 {
        let ramp = if m == 1 { self.now.1.abs() } else { 0.0 };
        ramp + self.waves.iter().map(|&(c, w, _)| c.abs() * w.abs().powi(m as i32)).sum::<f64>()
    }

    /// The value at the modal state.
    pub fn value(&self, t: f64, eta: &[f64], deta: &[f64]) -> f64 {
        let mut g = self.wave(t, 0);
        for i in 0..eta.len() {
            g += self.beta[i] * eta[i] + self.alpha(i) * deta[i];
        }
        g
    }

    /// `∫ g` over `[t0, t0 + tau]` from the modal states at both ends.
    /// (`tr`: work storage, no allocation once it has the capacity.)
    pub fn integral(&self, flow: &ModalFlow, t0: f64, start: (&[f64], &[f64]), end: (&[f64], &[f64]), tau: f64, tr: &mut [Vec<(f64, f64)>; 2]) -> f64 {
        let t1 = t0 + tau;
        flow.trig(t0, &mut tr[0]);
        flow.trig(t1, &mut tr[1]);
        let (c0, c1, tp) = self.now;
        let mut s = c0 * tau;
        if c1 != 0.0 {
            s += c1 * tau * ((t0 - tp) + 0.5 * tau);
        }
        for &(c, w, p) in &self.waves {
            s += c * ((w * t0 + p).cos() - (w * t1 + p).cos()) / w;
        }
        for i in 0..start.0.len() {
            if self.beta[i] != 0.0 {
                s += self.beta[i] * flow.integral(i, t0, start, end, tau, tr);
            }
            s += self.alpha(i) * (end.0[i] - start.0[i]);
        }
        s
    }
}

/// Steps of one search before it gives up (a grazing contact that never
/// quite touches can take many).
const MAX_STEPS: usize = 10_000_000;

/// Work storage of the search (no allocation per step).
pub(crate) struct Search {
    /// Per mode: `η⁽ᵐ⁾`, `m < JET`, at the current time.
    jet: Vec<[f64; JET]>,
    /// Per mode: bounds of `|η⁽ᵐ⁾|`, `m <= JET`, over the window.
    bnd: Vec<[f64; JET + 1]>,
    suffix: Vec<f64>,
    /// The harmonics' `sin, cos` at the current time and at the next.
    tr: [Vec<(f64, f64)>; 2],
    /// Steps taken by the last searches (for the benchmarks).
    pub steps: u64,
    /// The state's increments from the phase's base at the current step.
    inc: [Vec<f64>; 2],
    /// Per functional, its value at the base split at every mode index
    /// (`n + 1` prefix sums: the load part, then each mode's terms), the
    /// full sum 0 for one exactly at its zero there; and its load part at
    /// the base.
    prefix: Vec<f64>,
    load0: Vec<f64>,
    /// Polled every [`POLL_EVERY`] steps: `true` stops the search with
    /// [`EventsError::Interrupted`], the flow at the time reached.
    pub interrupt: Option<crate::Interrupt>,
    /// Whether a zero at a step's start exactly at the pause is found
    /// before the search pauses there ([`EventDriven::take_events_at_pause`](super::EventDriven::take_events_at_pause)).
    pub take_at_pause: bool,
}

/// Search steps between two polls of the interrupt (a step costs O(modes ×
/// functionals); every event takes at least one step, or stalls: so an
/// interrupt is seen within 256 steps' work, whatever the events' density).
pub(crate) const POLL_EVERY: u64 = 256;

impl Search {
    pub fn new(n: usize) -> Self {
        Self {
            jet: vec![[0.0; JET]; n],
            bnd: vec![[0.0; JET + 1]; n],
            suffix: vec![0.0; n + 1],
            tr: [Vec::new(), Vec::new()],
            steps: 0,
            inc: [vec![0.0; n], vec![0.0; n]],
            prefix: Vec::new(),
            load0: Vec::new(),
            interrupt: None,
            take_at_pause: false,
        }
    }

    /// Whether `t` lies beyond the pause `pause`: after it, or at it unless
    /// events at the pause are taken. The one rule for a zero at the pause,
    /// read by the search's steps and by the run's located events.
    pub(crate) fn beyond_pause(&self, t: f64, pause: f64) -> bool {
        t > pause || (t == pause && !self.take_at_pause)
    }

    /// The first time in `(t0, end]` at which one of `fns` reaches 0 from
    /// above, with its index; the modal state is advanced there (or to
    /// `end`, then `None`). `quiet[f]`: a functional that stays at 0 with
    /// every derivative 0 is no event (a held contact's force at rest); for
    /// the others (a distance) it is one.
    #[allow(clippy::too_many_arguments)]
    pub fn first_zero(&mut self, flow: &ModalFlow, t0: f64, eta: &mut [f64], deta: &mut [f64], fns: &[Functional], quiet: &[bool], end: f64) -> Result<Option<(f64, usize)>, EventsError> {
        let base = (eta.to_vec(), deta.to_vec());
        let mut cursor = Cursor { tau: 0.0, window: end - t0 };
        let zero = vec![AtBase::Open; fns.len()];
        match self.resume(flow, (t0, &base.0, &base.1), &mut cursor, (eta, deta), (fns, quiet, &zero), end, f64::INFINITY)? {
            Found::Event(t, f) => Ok(Some((t, f))),
            Found::End | Found::Paused => Ok(None),
        }
    }

    /// Goes on from `cursor` to the first zero of one of `fns` in
    /// `(cursor.t, end]` (docs/theory.md §9.2), the state at every step
    /// evaluated from the phase's `base` `(t_b, η, η')` — never re-based —
    /// so the steps and the event found do not depend on where a caller
    /// paused: it stops once the cursor reaches `pause` (no step is cut
    /// there; with `take_at_pause`, once it passes it: a zero at `pause`
    /// itself is found first), at the event ([`Found::Event`], the state there in `state`)
    /// or at `end` ([`Found::End`], the state there in `state`). Each
    /// functional is read as its value at the base plus the terms of the
    /// state's increments; `zero` marks those exactly 0 at the base (a
    /// contact that the event starting the phase put on its bound, or
    /// released: [`AtBase`]).
    #[allow(clippy::too_many_arguments)]
    pub fn resume(
        &mut self,
        flow: &ModalFlow,
        base: (f64, &[f64], &[f64]),
        cursor: &mut Cursor,
        state: (&mut [f64], &mut [f64]),
        (fns, quiet, zero): (&[Functional], &[bool], &[AtBase]),
        end: f64,
        pause: f64,
    ) -> Result<Found, EventsError> {
        let n = flow.n();
        if self.jet.len() != n {
            // Another phase's size (a held phase has fewer free modes): the
            // storage of `new(n)`, in the buffers already there (no
            // allocation once they have had the largest size).
            let zeros = |x: &mut Vec<f64>, len: usize| {
                x.clear();
                x.resize(len, 0.0);
            };
            self.jet.clear();
            self.jet.resize(n, [0.0; JET]);
            self.bnd.clear();
            self.bnd.resize(n, [0.0; JET + 1]);
            zeros(&mut self.suffix, n + 1);
            self.inc.iter_mut().for_each(|x| zeros(x, n));
            self.tr.iter_mut().for_each(Vec::clear);
            self.prefix.clear();
            self.load0.clear();
        }
        let (eta, deta) = state;
        // Each functional at the base, split at every mode index: a value
        // along the phase is that plus the increments' terms, precise
        // where it is small (a slow approach: docs/theory.md §9.2).
        self.prefix.clear();
        self.load0.clear();
        for (f, func) in fns.iter().enumerate() {
            let l0 = func.wave(base.0, 0);
            self.load0.push(l0);
            let mut g = l0;
            self.prefix.push(g);
            for i in 0..n {
                g += func.beta[i] * base.1[i] + func.alpha(i) * base.2[i];
                self.prefix.push(g);
            }
            if zero[f] == AtBase::Leaving {
                *self.prefix.last_mut().expect("n + 1 sums") = 0.0;
            }
        }
        // Without time-dependent loads the flow is the same at every
        // absolute time: events are located relative to the phase (its
        // elapsed time τ), not to t (docs/theory.md §9.2).
        let autonomous = !flow.time_dependent();
        for _ in 0..MAX_STEPS {
            let tau = cursor.tau;
            let t = base.0 + tau;
            let h = cursor.window.min(end - t);
            // At the pause itself a step start on a zero is taken first
            // only when asked (a sampler: the state after the events at its
            // instant, as a root step there gives); the orbits' section
            // leaves it to the next period (docs/orbits.md).
            if h > 0.0 && self.beyond_pause(t, pause) {
                return Ok(Found::Paused);
            }
            // The state τ after the base (the same state whatever the pauses).
            if tau != 0.0 {
                let [d, dd] = &mut self.inc;
                flow.advance_modal_from(base.0, (base.1, base.2), tau, (&mut *eta, &mut *deta), (d, dd), &mut self.tr);
            } else {
                eta.copy_from_slice(base.1);
                deta.copy_from_slice(base.2);
                self.inc.iter_mut().for_each(|x| x.iter_mut().for_each(|y| *y = 0.0));
            }
            let res = time_resolution(if autonomous { tau } else { t });
            if h <= 0.0 {
                return Ok(Found::End);
            }
            if self.steps % POLL_EVERY == 0 && self.interrupt.as_ref().is_some_and(|poll| poll()) {
                return Err(EventsError::Interrupted { t });
            }
            self.steps += 1;
            flow.trig(t, &mut self.tr[0]);
            for i in 0..n {
                (self.jet[i], self.bnd[i]) = flow.jet_and_bounds(i, t, eta, deta, h, &self.tr[0]);
            }
            // The shortest root step and whose, and the shortest step of all.
            let (mut step, mut root) = (h, f64::INFINITY);
            let mut who = None;
            for (f, func) in fns.iter().enumerate() {
                // Within the resolution of its release (docs/theory.md §9.3, "Touches").
                let released = zero[f] == AtBase::Released && tau <= 4.0 * time_resolution(t);
                match self.safe_step(flow, (f, func), (quiet[f], released), (t, res), eta, deta, h) {
                    Reach::Now => return Ok(Found::Event(t, f)),
                    Reach::Free(s) => step = step.min(s),
                    Reach::Root(s) => {
                        if s < root {
                            root = s;
                            who = Some(f);
                        }
                        step = step.min(s);
                    }
                }
            }
            // A root is reached only by a step that goes all the way to it
            // (a shorter lift-off step of another functional is no event).
            if step < root {
                who = None;
            }
            let last = step >= end - t;
            let step = if last { end - t } else { step };
            cursor.tau = if last { end - base.0 } else { tau + step };
            cursor.window = 2.0 * step.max(f64::MIN_POSITIVE);
            let event = who.filter(|_| step <= res);
            if event.is_some() || last {
                eta.copy_from_slice(base.1);
                deta.copy_from_slice(base.2);
                flow.advance_modal(base.0, eta, deta, cursor.tau, &mut self.tr);
                // At the end: `end` itself (base + τ may round below it).
                return Ok(event.map_or(Found::End, |f| Found::Event(base.0 + cursor.tau, f)));
            }
        }
        Err(EventsError::NoConvergence { t: base.0 + cursor.tau, steps: MAX_STEPS })
    }

    /// The safe step for one functional over the window `h` (module docs).
    #[allow(clippy::too_many_arguments)]
    fn safe_step(&mut self, flow: &ModalFlow, (fi, f): (usize, &Functional), (quiet, released): (bool, bool), (t, res): (f64, f64), eta: &[f64], deta: &[f64], h: f64) -> Reach {
        let n = eta.len();
        let (lv, ld, lc) = (f.wave(t, 0), f.wave(t, 1), f.wave_bound(2));
        // The functional split at mode `s`: its value at the base plus the
        // increments of its load part and of the modes below `s`.
        let prefix = &self.prefix[fi * (n + 1)..(fi + 1) * (n + 1)];
        let (inc, dinc) = (&self.inc[0], &self.inc[1]);
        // Suffix sums of the amplitudes.
        self.suffix[n] = 0.0;
        // The size of the terms of g: its round-off is 1e-16 of it.
        let mut scale = f.constant_abs(t) + f.wave_bound(0);
        // `g'(t)` and a bound of its terms over the window.
        let (mut rate, mut rate_terms) = (ld, f.wave_bound(1));
        for i in (0..n).rev() {
            let (b, a) = (f.beta[i], f.alpha(i));
            let (jet, bnd) = (&self.jet[i], &self.bnd[i]);
            let amp = b.abs() * bnd[0] + a.abs() * bnd[1];
            self.suffix[i] = self.suffix[i + 1] + amp;
            scale += (b * jet[0]).abs() + (a * jet[1]).abs();
            rate += b * jet[1] + a * jet[2];
            rate_terms += b.abs() * bnd[1] + a.abs() * bnd[2];
        }
        let g = prefix[n] + (0..n).fold(lv - self.load0[fi], |d, i| d + f.beta[i] * inc[i] + f.alpha(i) * dinc[i]);
        // Taylor's bound of `|g''|` is for a functional whose terms cancel
        // as a whole, its value and rate too (the dip's flight), not for
        // an ordinary one at an inflection or a slow impact, whose steps
        // (so its events' bits) stay those of the terms' bounds
        // ([`TAYLOR_GAIN`]).
        let value_terms = f.constant_abs(t) + f.now.1.abs() * h + f.wave_bound(0) + self.suffix[0];
        let cancelled = TAYLOR_GAIN * g.abs() < value_terms && TAYLOR_GAIN * rate.abs() < rate_terms;
        // Read only there: an ordinary step pays none of it.
        let taylor = cancelled.then(|| self.taylor_jet(f, t, n));
        // A gap at its release is at its zero whatever its size against
        // its own terms: the gap of a contact with no load term (its scale
        // is its value alone) released a few ulps before the phase's base
        // sat at 1e-48 there, and the root steps located it 2e-24 s later,
        // landed it at zero speed and released it again (an extra row:
        // docs/theory.md §9.3, "Touches").
        if g <= 1e-13 * scale || released {
            match self.lift_off(flow, f, (quiet, released), (t, res), eta, deta, h) {
                // Approaching from just above: the root steps below.
                Reach::Now if g > 0.0 => {}
                r => return r,
            }
        }
        let mut best = 0.0f64;
        let (mut dl, mut bl) = (ld, if n == 0 { taylor.map_or(lc, |j| taylor_curvature(lc, j, h)) } else { lc });
        // The increments' part of the split value, accumulated with `s`.
        let mut dsum = lv - self.load0[fi];
        for s in 0..=n {
            let gl = prefix[s] + dsum;
            let margin = gl - self.suffix[s];
            if margin > 0.0 {
                let reach = if bl > 0.0 {
                    // The positive root of `margin + dl s − bl s²/2`; for an
                    // approach (`dl < 0`) in the form without cancellation.
                    let root = (dl * dl + 2.0 * bl * margin).sqrt();
                    if dl >= 0.0 {
                        (dl + root) / bl
                    } else {
                        2.0 * margin / (root - dl)
                    }
                } else if dl < 0.0 {
                    margin / -dl
                } else {
                    f64::INFINITY
                };
                best = best.max(reach);
            }
            if s < n {
                let (b, a) = (f.beta[s], f.alpha(s));
                dsum += b * inc[s] + a * dinc[s];
                dl += b * self.jet[s][1] + a * self.jet[s][2];
                bl += b.abs() * self.bnd[s][2] + a.abs() * self.bnd[s][3];
                if let Some(j) = taylor.filter(|_| s + 1 == n) {
                    bl = taylor_curvature(bl, j, h);
                }
            }
        }
        // The root less 1e-12 of it (its own round-off is a few ulps): a
        // margin, not the guard against passing an event — the bounds'
        // 1e-12 inflation covers the root's round-off wherever the
        // curvature counts, and on a nearly linear approach an overshoot
        // leaves g within its own round-off of 0, where the lift-off rule
        // declares the event (docs/theory.md §9.2, "The root's margin").
        Reach::Root(best * (1.0 - 1e-12))
    }

    /// The whole functional's jet of orders 2..=4 at `t`, the sizes of
    /// their terms, and a bound of `|g⁽⁵⁾|` over the window: the inputs of
    /// Taylor's bound of `|g''|` ([`taylor_curvature`]).
    fn taylor_jet(&self, f: &Functional, t: f64, n: usize) -> TaylorJet {
        let (mut tj, mut ts) = (f.wave_jet(t), [2, 3, 4].map(|m| f.wave_bound(m)));
        let mut b5 = f.wave_bound(5);
        for i in (0..n).rev() {
            let (b, a) = (f.beta[i], f.alpha(i));
            let (jet, bnd) = (&self.jet[i], &self.bnd[i]);
            for m in 0..3 {
                tj[m] += b * jet[m + 2] + a * jet[m + 3];
                ts[m] += b.abs() * bnd[m + 2] + a.abs() * bnd[m + 3];
            }
            b5 += b.abs() * bnd[5] + a.abs() * bnd[6];
        }
        (tj, ts, b5)
    }

    /// At `g = 0`: the first nonzero derivative decides (module docs).
    #[allow(clippy::too_many_arguments)]
    fn lift_off(&self, flow: &ModalFlow, f: &Functional, (quiet, released): (bool, bool), (t, res): (f64, f64), eta: &[f64], deta: &[f64], h: f64) -> Reach {
        let mut gj = [0.0; GJET];
        // The size of the terms of each derivative (its round-off scale).
        let mut gs = [0.0; GJET];
        let mut gb = [0.0; GJET + 1];
        // A wave's derivative is read from its phase `Ω t + p + m π/2`,
        // whose round-off leaves an error of ε times its amplitude `c Ωᵐ`,
        // not of the value: at a zero of the load's rate (a held force
        // touching 0 at its minimum) the value itself is that round-off
        // (`cos t − 1` at t = 0 had a rate of 6e-17 and was released).
        for (m, x) in gj.iter_mut().enumerate() {
            *x = f.wave(t, m);
            gs[m] = x.abs() + f.wave_bound(m) + if m == 0 { f.constant_abs(t) } else { 0.0 };
        }
        for (m, x) in gb.iter_mut().enumerate() {
            *x = if m == 0 { f.constant_abs(t) + f.now.1.abs() * h + f.wave_bound(0) } else { f.wave_bound(m) };
        }
        // In the first-order form (a non-classical damping) the basis `T⁻¹`
        // mixes every dof: a modal state's round-off is relative to the
        // whole state, not to its own term. A contact at rest whose modes
        // a held dof decouples from the moving ones has terms of round-off
        // size only (the general eigensolver mixes the blocks at 1e-17,
        // where the classical one returns exact zeros), so each
        // derivative's scale also counts `Σ|β| + |α|` times the largest
        // jet (docs/theory.md §9.2, "Zeros at the time resolution").
        let (mut coef, mut jmax) = (0.0f64, [0.0f64; GJET]);
        for i in 0..eta.len() {
            let (b, a) = (f.beta[i], f.alpha(i));
            if b == 0.0 && a == 0.0 {
                continue;
            }
            let (j, bd) = flow.jet_and_bounds(i, t, eta, deta, h, &self.tr[0]);
            coef += b.abs() + a.abs();
            for m in 0..GJET {
                gj[m] += b * j[m] + a * j[m + 1];
                gs[m] += (b * j[m]).abs() + (a * j[m + 1]).abs();
                jmax[m] = jmax[m].max(j[m].abs()).max(j[m + 1].abs());
            }
            for m in 0..=GJET {
                gb[m] += b.abs() * bd[m] + a.abs() * bd[m + 1];
            }
        }
        // The jets of orders 1..=4 beyond their round-off (0 otherwise),
        // and the bounds of |g⁽⁴⁾| and |g⁽⁵⁾| over the window (order 4: a gap leaving at
        // a double zero of the load, `1 − cos t` pulling from rest on the
        // stop, is `t⁴/24`; read up to order 3 it was an approach, landed
        // and released at t = 0 until the run stopped). A derivative of
        // order 2 to 4 is also zero if the next one moves it by more than itself
        // within the time resolution (an event is located to
        // `time_resolution(t)`: at a release the held force is `r' δt`, not
        // 0, and the free phase's g'' ∝ r inherits it; the velocity is
        // decided exactly by the impact law: docs/theory.md §9.2, "Zeros at
        // the time resolution").
        if !flow.classical() {
            for m in 0..GJET {
                gs[m] = gs[m].max(coef * jmax[m]);
            }
        }
        let dt_res = 4.0 * res;
        let mut d = [0.0; GJET];
        for m in 1..GJET {
            // The last order's next derivative: its bound over the window.
            let next = if m + 1 < GJET { gj[m + 1].abs() } else { gb[GJET] };
            let resolution = if m >= 2 { next * dt_res } else { 0.0 };
            if gj[m].abs() > 1e-12 * gs[m] + resolution {
                d[m] = gj[m];
            }
        }
        // A contact at its release: at rest, its acceleration its force's
        // share, 0 at the force's zero; what is left is the release
        // time's round-off, `g''' Δt` for a release
        // located `Δt` off (7e-11 s at a force's zero of rate 1.4e-6,
        // far beyond `4 δ(t)`), read as an approach it landed the
        // contact at once, at zero speed, and released it again
        // (docs/theory.md §9.3, "Touches").
        if released {
            d[1] = 0.0;
            d[2] = 0.0;
        }
        d[0] = gj[0].max(0.0);
        // The orders read: 1..=3 with B bounding |g⁽⁴⁾| wherever one of
        // them is nonzero (every impact's departure: the windows, and so
        // every run's bits, as before order 4 was read), 1..=4 with B
        // bounding |g⁽⁵⁾| where all three are zero.
        let top = if d[1..4].iter().any(|&x| x != 0.0) { 4 } else { GJET };
        let Some(first) = (1..top).find(|&m| d[m] != 0.0) else {
            return if quiet { Reach::Free(h) } else { Reach::Now };
        };
        if d[first] < 0.0 {
            // A held force at the bottom of a touch: falling (`d₁ < 0`) but
            // curving up (`d₂ > 0`), its parabola's minimum `g − d₁²/(2d₂)`
            // within the band where `g` counts as 0, less `|g'''|`'s share
            // up to the mirror point `2|d₁|/d₂`. The contact does not leave
            // (a release there logged a row at each tangent zero of
            // `1 + cos t`, two at the first): step past the minimum
            // (docs/theory.md §9.3, "Touches").
            if quiet && first == 1 && d[2] > 0.0 {
                let step = (-2.0 * d[1] / d[2]).min(h);
                let dip = gj[0] - d[1] * d[1] / (2.0 * d[2]) - gb[3] * step.powi(3) / 6.0;
                if dip >= -1e-13 * gs[0] {
                    return Reach::Free(step);
                }
            }
            return Reach::Now;
        }
        // For each order j whose lower jets are all >= 0 and d_j > 0:
        // g(s) >= d_j s^j/j! − Σ_{k>j, d_k<0} |d_k| s^k/k! − B s^top/top!,
        // whose bracket after s^j is decreasing: its root (bisection) is
        // safe.
        let b = gb[top];
        let fact = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0];
        let mut best = 0.0f64;
        for j in 0..top {
            if d[..j].iter().any(|&x| x < 0.0) {
                break;
            }
            if d[j] <= 0.0 {
                continue;
            }
            let phi = |s: f64| -> f64 {
                let mut v = d[j] / fact[j];
                for k in j + 1..top {
                    if d[k] < 0.0 {
                        v += d[k] * s.powi((k - j) as i32) / fact[k];
                    }
                }
                v - b * s.powi((top - j) as i32) / fact[top]
            };
            let root = if phi(h) > 0.0 {
                h
            } else {
                let (mut lo, mut hi) = (0.0, h);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    if phi(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            };
            best = best.max(root);
        }
        Reach::Free(best.min(h))
    }
}

/// The jet `g⁽ᵐ⁾(t)` (m = 2..=4), the sizes of its terms, and a bound of
/// `|g⁽⁵⁾|` over the window ([`Search::taylor_jet`]).
type TaylorJet = ([f64; 3], [f64; 3], f64);

/// Where the terms of `g''` cancel (a resonant mode's static part, its
/// particular solution `t sin t` and its homogeneous part, each O(1),
/// summing to a flight 1e-20 high: docs/theory.md §9.2, "Cancelled
/// curvature"), the sum of their bounds, `bl`, is far above `|g''|`:
/// Taylor's bound over the window `[t, t + h]`,
/// `Σ_{m=2..4} (|g⁽ᵐ⁾(t)| + e_m) h^{m−2}/(m−2)! + B₅ h³/6` (`tj`: the jet
/// `g⁽ᵐ⁾(t)`, `ts`: the sizes of its terms, `e_m = 1e-14` of them its
/// round-off; `b5 >= |g⁽⁵⁾|` over the window), in its place where it is
/// [`TAYLOR_GAIN`] times tighter.
fn taylor_curvature(bl: f64, (tj, ts, b5): TaylorJet, h: f64) -> f64 {
    let at = |m: usize| tj[m].abs() + 1e-14 * ts[m];
    let taylor = (at(0) + h * (at(1) + 0.5 * h * (at(2) + b5 * h / 3.0))) * (1.0 + 1e-12);
    if taylor * TAYLOR_GAIN < bl {
        taylor
    } else {
        bl
    }
}

/// Taylor's bound of `|g''|` ([`taylor_curvature`]) is taken where it and
/// the functional's value and rate are each this many times below the
/// bounds of their terms. Both bounds are bounds, either step is safe (no
/// gain can lose an event); the gain only decides which runs change their
/// last bits: at 16 an ordinary slow impact (the two-stop oscillator's
/// continuation near its grazing at 1.0383) took Taylor's and moved its
/// branch point by 4e-12; from 100 up nothing ordinary does (docs/theory.md
/// §9.2, "Cancelled curvature"), while the dip's curvature is `~1/δ`
/// below its terms'.
const TAYLOR_GAIN: f64 = 1e3;

/// The time to which an event at `t` (or `τ` into its phase, for a flow
/// without time-dependent loads) is located: a relative 1e-15, at least
/// one rounding (`ε max(|t|, 1)`).
pub(crate) fn time_resolution(t: f64) -> f64 {
    (1e-15 * t.abs()).max(f64::EPSILON * t.abs().max(1.0))
}

/// A functional at its phase's base ([`Search::resume`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AtBase {
    /// Read from the modal state.
    Open,
    /// A gap exactly 0, leaving its bound with a speed (a rebound).
    Leaving,
    /// The gap of a contact released at the base: on its bound, at rest,
    /// its acceleration exactly 0 (its force's zero).
    Released,
}

/// Where a search stands in its phase: the time it reached, `τ` after the
/// phase's base, and the window of its next step (twice its last step).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cursor {
    pub tau: f64,
    pub window: f64,
}

impl Cursor {
    /// A phase's first step: the window is the flow's shortest period
    /// `2π/ω_max` (1 without stiffness), whatever the sampling.
    pub fn start(flow: &ModalFlow) -> Self {
        let w2 = flow.omega2().iter().fold(0.0f64, |a, &k| a.max(k));
        Self { tau: 0.0, window: if w2 > 0.0 { std::f64::consts::TAU / w2.sqrt() } else { 1.0 } }
    }
}

/// How [`Search::resume`] stopped.
pub(crate) enum Found {
    /// A zero of the functional at the time.
    Event(f64, usize),
    /// The cursor passed the pause, no zero up to it.
    Paused,
    /// The cursor reached the end, no zero before it.
    End,
}

/// What one functional allows over a window.
enum Reach {
    /// Its zero is now.
    Now,
    /// A safe step that does not approach a zero (a lift-off).
    Free(f64),
    /// A safe step toward its zero.
    Root(f64),
}

// ---- The search applied to one free flight: `ModalFlow::first_crossing`.

impl ModalFlow {
    /// The first time in `(t0, t0 + horizon]` at which the contact dof `dof`
    /// of the trajectory from `(q0, v0)` reaches `lo` (from above) or `hi`
    /// (from below), with the state there; `None` if it stays strictly
    /// inside. The state must start inside (`lo < q_c < hi`, or on a bound
    /// and leaving it). The search is the module `search`'s (docs/theory.md
    /// §9.2): no event is missed, each is located to a relative 1e-15.
    #[allow(clippy::too_many_arguments)]
    pub fn first_crossing(&self, t0: f64, q0: &[f64], v0: &[f64], dof: usize, lo: f64, hi: f64, horizon: f64) -> Result<Option<Event>, EventsError> {
        let n = self.n();
        let (mut eta, mut deta) = (vec![0.0; n], vec![0.0; n]);
        self.to_modal(t0, q0, v0, &mut eta, &mut deta);
        let mut unit = vec![0.0; n];
        unit[dof] = 1.0;
        let (sides, fns): (Vec<Bound>, Vec<_>) = self.linear(&unit, &vec![0.0; n]).gaps(lo, hi).into_iter().unzip();
        let mut search = Search::new(n);
        let Some((t, which)) = search.first_zero(self, t0, &mut eta, &mut deta, &fns, &[false; 2][..fns.len()], t0 + horizon)? else {
            return Ok(None);
        };
        let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
        self.to_physical(t, &eta, &deta, &mut q, &mut v);
        Ok(Some(Event { t, bound: sides[which], q, v }))
    }
}
