//! Nitsche's method for the Signorini condition at the contact node
//! (Chouly–Hild–Renard), with Newmark(β, γ) in time (docs/theory.md §4.6.2).
//!
//! With `σ(v) = c² v_x(0) = k (v_1 - v_0)` (`k = c²/h = -K_01`), `γ = γ_0 k`
//! (`γ_0 c²/h`) and `θ ∈ [-1, 1]`, the semi-discrete problem is
//!
//! ```text
//! M U'' + (K - (θ/γ) d dᵀ) U + (1/γ) min(0, qᵀU - γ g) (θ d + γ e_0) = F,
//! d = k (e_1 - e_0)  (σ(v) = dᵀv),   q = d + γ e_0  (P_γ(u) = σ(u) + γ (u_0 - g)),
//! ```
//!
//! consistent because `min(0, P_γ(u)) = σ(u) = λ` for the exact solution.
//! Each Newmark step is one solve with `A = M + β dt² K_N` and the exact
//! solution of a scalar piecewise-linear equation in `s = qᵀU^{n+1}`:
//! `s = s_y - W min(0, s - γ g)`, `W = β dt² qᵀA⁻¹r`, `r = (θ d + γ e_0)/γ`.
//! The reported contact force is `λ = min(0, P_γ(u^{n+1}))` at `t_{n+1}`.
//!
//! Energy: with `E = ½VᵀMV + ½UᵀK_N U - FᵀU` and `N^n` the Nitsche force
//! vector, the Newmark identity holds with `λ e_0` replaced by `N`; for
//! Crank–Nicolson, `ΔE = -ΔUᵀ(N^n + N^{n+1})/2` (tested). For θ = 1 the
//! force derives from the potential `(1/2γ) min(0, qᵀU - γg)²`.

use crate::fused::{fused_switches, FusedSwitch};
use crate::stabilized::{neighbours, tridiagonal_forward_dispatch, TriMatrix, TriRows};
use crate::{Dynamics, Initial, SchemeError, StepReport, Stepper};
use signorini_contact::Active;
use signorini_fem::{BandLdlt, SymBand};

/// The structure Nitsche's method is written for here (theory §4.6.2): the
/// P1 bar's node 0 as the contact node, a one-sided obstacle.
pub(crate) fn bar_end(dy: &Dynamics) -> Result<(), SchemeError> {
    if dy.contact().dof != 0 || dy.n() < 2 || dy.stiffness.half_bandwidth() != 1 {
        return Err(SchemeError::Structure("Nitsche needs the P1 bar's contact node 0"));
    }
    if dy.contact().bounds.hi.is_finite() {
        return Err(SchemeError::Structure("Nitsche here handles a one-sided obstacle"));
    }
    Ok(())
}

/// Nitsche's terms at the bar's end (theory §4.6.2), for `nitsche` and
/// `verlet-nitsche`: with `k = −K_01` and `γ = γ_0 k`, `K_N = K − (θ/γ) d dᵀ`
/// (`d = k (e_1 − e_0)`), `q = d + γ e_0` and `r = (θ d + γ e_0)/γ` on dofs
/// (0, 1).
pub(crate) struct NitscheTerms {
    pub(crate) gamma_n: f64,
    pub(crate) k_n: SymBand,
    pub(crate) q: [f64; 2],
    pub(crate) r: [f64; 2],
}

impl NitscheTerms {
    /// The terms of `dy` (its structure checked by [`bar_end`]).
    pub(crate) fn new(dy: &Dynamics, gamma0: f64, theta: f64) -> Self {
        let k = -dy.stiffness.get(0, 1);
        let gamma_n = gamma0 * k;
        let mut k_n = dy.stiffness.clone();
        let c = theta / gamma_n * k * k;
        k_n.add(0, 0, -c);
        k_n.add(1, 1, -c);
        k_n.add(0, 1, c);
        Self { gamma_n, k_n, q: [-k + gamma_n, k], r: [(-theta * k + gamma_n) / gamma_n, theta * k / gamma_n] }
    }
}

/// Nitsche + Newmark integrator on the P1 bar.
pub struct Nitsche {
    label: String,
    beta: f64,
    gamma_t: f64,
    dt: f64,
    n: usize,
    dy: Dynamics,
    k_n: SymBand,
    a: BandLdlt,
    m_massive: BandLdlt,
    q: [f64; 2],
    r: [f64; 2],
    gamma_n: f64,
    /// `A⁻¹ r` and `W`.
    ar: Vec<f64>,
    w: f64,
    u: Vec<f64>,
    mom: Vec<f64>,
    acc_r: Vec<f64>,
    rhs: Vec<f64>,
    ku: Vec<f64>,
    force: f64,
    lams: [f64; 1],
    acts: [Active; 1],
    /// The step fused on the P1 bar ([`Tridiagonal`]), if it applies, and its switches.
    fused: FusedSwitch<Tridiagonal>,
}

/// The step fused on the P1 bar (`M` and the factor of `A` tridiagonal,
/// `L` not the identity): the right-hand side
/// `M U + dt P + (½ − β) dt² R + β dt² F` made row by row inside the
/// forward sweep of the solve (the shared
/// [`tridiagonal_forward`](crate::stabilized::tridiagonal_forward), as
/// `contact-stabilized`'s), the factor's backward sweep, and after the
/// contact, `R^{n+1} = F − K_N U^{n+1} − N` and `P^{n+1}` in one pass
/// ([`Nitsche::fused_update`]) where the general path copies `R^n`, makes
/// `K_N U^{n+1}` and runs two passes. Every value is the general path's
/// operations in the same order (`SymBand::mul_vec`'s tridiagonal rows,
/// the sums, `BandLdlt::solve_in_place`'s sweeps, `update_r`'s rows), so
/// the same bits (cost: `crates/run/benches/step.rs`, `implicit_scheme_step`).
type Tridiagonal = crate::stabilized::TriPair;

/// [`Tridiagonal`]'s rows for one step: `M u + ((dt p + ao r) + an f)`.
struct NitscheRows<'a> {
    m: &'a TriMatrix,
    dt: f64,
    ao: f64,
    an: f64,
    u: &'a [f64],
    p: &'a [f64],
    r: &'a [f64],
    f: &'a [f64],
}

impl TriRows for NitscheRows<'_> {
    #[inline(always)]
    fn interior(&self, a: usize, o: &mut [f64]) {
        let len = o.len();
        let (u, dt, ao, an) = (self.u, self.dt, self.ao, self.an);
        let (ul, uc, ur) = neighbours(u, a, len);
        let (msl, mdc, msr) = self.m.window(a, len);
        let (p, r, f) = (&self.p[a..a + len], &self.r[a..a + len], &self.f[a..a + len]);
        for j in 0..len {
            let mu = msl[j] * ul[j] + mdc[j] * uc[j] + msr[j] * ur[j];
            o[j] = mu + (dt * p[j] + ao * r[j] + an * f[j]);
        }
    }

    #[inline(always)]
    fn edge(&self, i: usize) -> f64 {
        let mu = self.m.row(self.u.len(), i, |j| self.u[j]);
        mu + (self.dt * self.p[i] + self.ao * self.r[i] + self.an * self.f[i])
    }
}

impl Nitsche {
    /// Sets up the scheme: Newmark(β, γ) (β ∈ (0, 1/2], γ ∈ [1/2, 2β]),
    /// Nitsche parameters γ_0 > 0 and θ ∈ [-1, 1]. The contact node must be
    /// dof 0, the end of one P1 element, with a one-sided obstacle.
    #[allow(clippy::too_many_arguments)] // the scheme's four named parameters beside the common ones
    pub fn new(label: String, dy: Dynamics, beta: f64, gamma_t: f64, gamma0: f64, theta: f64, dt: f64, init: &Initial) -> Result<Self, SchemeError> {
        dy.validate()?;
        if dy.damping.is_some() {
            return Err(crate::onestep::no_damping(&label));
        }
        let n = dy.n();
        if dy.k() > 1 {
            return Err(crate::family::not_taken(
                label,
                crate::family::Refused::SeveralContacts,
                " (Nitsche's method is formulated here at the bar's end node 0: its flux σ = c² u_x(0) is one element's)",
            ));
        }
        bar_end(&dy)?;
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SchemeError::Invalid { field: "dt", value: dt, allowed: "finite and > 0" });
        }
        let NitscheTerms { gamma_n, k_n, q, r } = NitscheTerms::new(&dy, gamma0, theta);
        let a = dy.mass.lin_comb(1.0, &k_n, beta * dt * dt).factor().map_err(|_| SchemeError::Invalid {
            field: "gamma0",
            value: gamma0,
            allowed: "large enough that K - (θ/γ) d dᵀ keeps the step matrix positive definite (γ_0 > θ c² suffices)",
        })?;
        let m_massive = dy.mass.trailing(dy.massive_start()).factor()?;
        let mut ar = vec![0.0; n];
        ar[0] = r[0];
        ar[1] = r[1];
        a.solve_in_place(&mut ar);
        let w = beta * dt * dt * (q[0] * ar[0] + q[1] * ar[1]);
        if !(1.0 + w > 0.0) {
            return Err(SchemeError::Invalid { field: "theta", value: theta, allowed: "a value for which the Nitsche step is solvable (θ = 1 always is)" });
        }
        let mut mom = vec![0.0; n];
        dy.mass.mul_vec(&init.v, &mut mom);
        let fused = FusedSwitch::new(Tridiagonal::beside(&dy.mass, &k_n, &a));
        let mut s = Self {
            label,
            beta,
            gamma_t,
            dt,
            n: 0,
            k_n,
            a,
            m_massive,
            q,
            r,
            gamma_n,
            ar,
            w,
            u: init.u.clone(),
            mom,
            acc_r: vec![0.0; n],
            rhs: vec![0.0; n],
            ku: vec![0.0; n],
            force: 0.0,
            lams: [0.0],
            acts: [Active::None],
            fused,
            dy,
        };
        if s.dy.massless_contact() {
            s.mom[0] = 0.0;
        }
        s.update_r();
        Ok(s)
    }

    fn p_gamma(&self) -> f64 {
        self.q[0] * self.u[0] + self.q[1] * self.u[1] - self.gamma_n * self.dy.contact().bounds.lo
    }

    /// `R = F - K_N U - N(U)`, `N = min(0, P_γ) r`; R_0 = 0 for a massless node.
    fn update_r(&mut self) {
        self.k_n.mul_vec(&self.u, &mut self.ku);
        for ((r, f), k) in self.acc_r.iter_mut().zip(&self.dy.load).zip(&self.ku) {
            *r = f - k;
        }
        self.force = self.p_gamma().min(0.0);
        self.acc_r[0] -= self.force * self.r[0];
        self.acc_r[1] -= self.force * self.r[1];
        if self.dy.massless_contact() {
            self.acc_r[0] = 0.0;
        }
    }

    fused_switches!(fused);

    /// [`update_r`](Self::update_r) and the momentum's update
    /// `P += dt ((1−γ) R^n + γ R^{n+1})` in one pass, `R^n` read from
    /// `acc_r` before it is overwritten ([`Tridiagonal`]): each row the
    /// general path's operations in its order.
    fn fused_update(&mut self) {
        let (dt, g) = (self.dt, self.gamma_t);
        let tri = self.fused.active().expect("the fused step applies");
        self.force = self.p_gamma().min(0.0);
        let n = self.u.len();
        let massless = self.dy.massless_contact();
        let (u, f, k) = (&self.u[..n], &self.dy.load[..n], &tri.k);
        let (acc, mom) = (&mut self.acc_r[..n], &mut self.mom[..n]);
        // Rows 0, 1 (the Nitsche force) and the last, as `update_r` and the step.
        let mut edge = |i: usize| {
            let mut rn = f[i] - k.row(n, i, |j| u[j]);
            if i < 2 {
                rn -= self.force * self.r[i];
            }
            if i == 0 && massless {
                rn = 0.0;
            }
            mom[i] += dt * ((1.0 - g) * acc[i] + g * rn);
            acc[i] = rn;
        };
        edge(0);
        edge(1);
        if n > 2 {
            edge(n - 1);
        }
        if n > 3 {
            let (a, len) = (2, n - 3);
            let (ul, uc, ur) = neighbours(u, a, len);
            let (ksl, kdc, ksr) = k.window(a, len);
            let (fr, acc, mom) = (&f[a..a + len], &mut acc[a..a + len], &mut mom[a..a + len]);
            for j in 0..len {
                let rn = fr[j] - (ksl[j] * ul[j] + kdc[j] * uc[j] + ksr[j] * ur[j]);
                mom[j] += dt * ((1.0 - g) * acc[j] + g * rn);
                acc[j] = rn;
            }
        }
        if massless {
            self.mom[0] = 0.0;
        }
    }

    /// The Nitsche force vector `N(U^n)` (entries 0 and 1; zero elsewhere).
    pub fn force_vector(&self) -> [f64; 2] {
        [self.force * self.r[0], self.force * self.r[1]]
    }

    /// `K_N = K - (θ/γ) d dᵀ`.
    pub fn nitsche_stiffness(&self) -> &SymBand {
        &self.k_n
    }

    /// Velocity `V^n` (massive dofs; a massless node reports 0).
    pub fn velocity(&self, out: &mut [f64]) {
        let s = self.dy.massive_start();
        out[s..].copy_from_slice(&self.mom[s..]);
        self.m_massive.solve_in_place(&mut out[s..]);
        if s == 1 {
            out[0] = 0.0;
        }
    }
}

impl Stepper for Nitsche {
    stepper_accessors!();

    fn step(&mut self) -> Result<StepReport, SchemeError> {
        let dt = self.dt;
        let (an, ao, g) = (self.beta * dt * dt, (0.5 - self.beta) * dt * dt, self.gamma_t);
        // b = M U + dt P + (1/2 - β) dt² R + β dt² F;  A U = b - β dt² N(U).
        if let Some(tri) = self.fused.active() {
            // The same right-hand side and solve, fused ([`Tridiagonal`]).
            let rows = NitscheRows { m: &tri.m, dt, ao, an, u: &self.u, p: &self.mom, r: &self.acc_r, f: &self.dy.load };
            let (l, _) = self.a.tridiagonal_factors().expect("tridiagonal");
            tridiagonal_forward_dispatch(tri.avx2, &rows, &[], &[], &[], l, &mut self.rhs);
            self.a.backward_in_place(&mut self.rhs);
        } else {
            self.dy.mass.mul_vec(&self.u, &mut self.rhs);
            for (((b, p), r), f) in self.rhs.iter_mut().zip(&self.mom).zip(&self.acc_r).zip(&self.dy.load) {
                *b += dt * p + ao * r + an * f;
            }
            self.a.solve_in_place(&mut self.rhs);
        }
        let gg = self.gamma_n * self.dy.contact().bounds.lo;
        let s_y = self.q[0] * self.rhs[0] + self.q[1] * self.rhs[1];
        // s = s_y - W min(0, s - γg): free branch if s_y >= γg.
        let s = if s_y >= gg { s_y } else { (s_y + self.w * gg) / (1.0 + self.w) };
        let nf = (s - gg).min(0.0);
        if nf != 0.0 {
            for (y, ar) in self.rhs.iter_mut().zip(&self.ar) {
                *y -= an * nf * ar;
            }
        }
        std::mem::swap(&mut self.u, &mut self.rhs);
        if self.fused.active().is_some() {
            // R^{n+1} and P^{n+1} in one pass ([`Nitsche::fused_update`]).
            self.fused_update();
        } else {
            // P^{n+1} = P^n + dt ((1-γ) R^n + γ R^{n+1}).
            // The old R into the (now free) rhs buffer: no allocation.
            let mut r_old = std::mem::take(&mut self.rhs);
            r_old.copy_from_slice(&self.acc_r);
            self.update_r();
            for ((p, ro), rn) in self.mom.iter_mut().zip(&r_old).zip(&self.acc_r) {
                *p += dt * ((1.0 - g) * ro + g * rn);
            }
            self.rhs = r_old;
            if self.dy.massless_contact() {
                self.mom[0] = 0.0;
            }
        }
        self.n += 1;
        let t = self.time();
        if !(self.u[0].is_finite() && self.force.is_finite()) {
            return Err(SchemeError::NonFinite { step: self.n, time: t });
        }
        let active = if self.force < 0.0 { Active::Lower } else { Active::None };
        (self.lams[0], self.acts[0]) = (self.force, active);
        Ok(StepReport { n: self.n, t, lambda: Some((t, self.force)), active })
    }

    fn energy(&mut self) -> Option<(f64, f64)> {
        let s = self.dy.massive_start();
        let kin = self.m_massive.inverse_quad_form(&self.mom[s..]);
        let pot = self.k_n.quad_form(&self.u);
        let load: f64 = self.dy.load.iter().zip(&self.u).map(|(f, u)| f * u).sum();
        Some((self.time(), 0.5 * kin + 0.5 * pot - load))
    }
}

// ---- The registry's row of this file: nitsche.

use crate::family::{check, Capabilities, Family, Group, Node, Param, Preset, SchemeSpec};

/// Nitsche's method with Newmark-CN: γ = γ_0 c²/h (γ_0 > 0), θ ∈ [-1, 1].
pub(crate) static NITSCHE: Family = Family {
    name: "nitsche",
    about: "Nitsche's method with Newmark-CN at the bar's end node (docs/theory.md §4.6)",
    params: &[Param { name: "gamma0", symbol: "γ_0", syntax: "GAMMA0", allowed: "> 0", default: None }, Param { name: "theta", symbol: "θ", syntax: "THETA", allowed: "∈ [-1, 1]", default: None }],
    presets: &[Preset { name: "nitsche-cn", args: &[10.0, 1.0], group: Group::Peer, rank: 5 }],
    validate: |a| {
        check("gamma0", a[0], a[0] > 0.0, "finite and > 0")?;
        check("theta", a[1], (-1.0..=1.0).contains(&a[1]), "[-1, 1]")
    },
    capabilities: |_| Capabilities {
        explicit: false,
        node: Node::Any,
        diagonal_mass: false,
        damping: false,
        forcing: false,
        restitution: false,
        stiffness: false,
        several_contacts: false,
        beam: false,
        lockstep: false,
    },
    cfl_limit: |_, _| Ok(None),
    stability_rule: |_| None,
    build: |s, dy, dt, init| Ok(Box::new(Nitsche::new(s.to_string(), dy, 0.25, 0.5, s.args()[0], s.args()[1], dt, init)?)),
};

impl SchemeSpec {
    /// Nitsche's method with γ_0 and θ (not validated until built).
    pub fn nitsche(gamma0: f64, theta: f64) -> Self {
        NITSCHE.with(&[gamma0, theta])
    }
}
