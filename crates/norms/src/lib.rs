//! # signorini-norms
//!
//! Error norms of SPEC §6 for a P1 displacement on a uniform mesh of `[0, L]`
//! against an [`ExactSolution`], accumulated while stepping — no history is
//! stored.
//!
//! Space norms are integrated exactly: each element is split at the kinks of
//! the exact solution at that time ([`ExactSolution::kinks`]); on each piece
//! the error `u_h - u` is a polynomial of degree `d = max(1, degree_x)`, so
//! it is represented exactly by its values at `d + 1` equispaced points and
//! its `L²` norm and `H¹` seminorm follow from the exact Lagrange mass and
//! stiffness matrices of that degree (`d = 1`: `ℓ(e₀² + e₀e₁ + e₁²)/3` and
//! `(e₁ - e₀)²/ℓ`). Only values of `u` are needed, never `u_x`.
//!
//! Time norms: `L∞(0,T;X) = max_n e_X(t_n)` and
//! `L²(0,T;X) = sqrt(dt Σ_n e_X(t_n)²)` over the samples fed in.
//!
//! Architecture invariant: depends only on `signorini-exact`; no IO, no
//! knowledge of schemes or matrices.

use signorini_exact::ExactSolution;

/// Which norm is the `V` norm of SPEC §6.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VNorm {
    /// `|u|_{H¹} = ‖u_x‖_{L²}` (Dirichlet end: it is a norm on V).
    H1Seminorm,
    /// `‖u‖_{H¹} = (‖u‖² + ‖u_x‖²)^{1/2}` (Neumann end).
    H1Full,
}

/// Space errors at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpaceErrors {
    /// `‖u_h - u‖_{L²(0,L)}`.
    pub l2: f64,
    /// `‖u_h - u‖_V`.
    pub v: f64,
}

/// Exact space integration of `u_h - u` for P1 nodal values on a uniform mesh.
pub struct SpaceIntegrator<'a> {
    exact: &'a dyn ExactSolution,
    length: f64,
    elements: usize,
    vnorm: VNorm,
    degree: usize,
    kinks: Vec<f64>,
    pts: Vec<f64>,
    uh: Vec<f64>,
    ex: Vec<f64>,
}

impl<'a> SpaceIntegrator<'a> {
    /// For a uniform mesh of `elements` elements on `[0, exact.length()]`.
    /// Exact solutions of degree up to 2 in `x` are supported (all of SPEC §5).
    #[track_caller]
    pub fn new(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm) -> Self {
        let degree = exact.degree_x().max(1);
        assert!(degree <= 2, "exact solutions of degree {degree} > 2 in x are not supported");
        let cap = (elements + 8) * degree + 1;
        Self {
            exact,
            length: exact.length(),
            elements,
            vnorm,
            degree,
            kinks: Vec::with_capacity(16),
            pts: Vec::with_capacity(cap),
            uh: Vec::with_capacity(cap),
            ex: Vec::with_capacity(cap),
        }
    }

    /// The errors at time `t` of the P1 function with nodal values `u`
    /// (`m + 1` values, or `m` for a clamped end whose last value is 0).
    #[track_caller]
    pub fn errors(&mut self, t: f64, u: &[f64]) -> SpaceErrors {
        let m = self.elements;
        assert!(u.len() == m || u.len() == m + 1, "need m or m+1 nodal values");
        let node_u = |i: usize| if i < u.len() { u[i] } else { 0.0 };
        let h = self.length / m as f64;
        self.exact.kinks(t, &mut self.kinks);
        self.pts.clear();
        self.uh.clear();
        let d = self.degree;
        let mut kink = self.kinks.iter().copied().peekable();
        for e in 0..m {
            let (a, b) = (e as f64 * h, if e + 1 == m { self.length } else { (e + 1) as f64 * h });
            let (ua, ub) = (node_u(e), node_u(e + 1));
            let interp = |x: f64| ua + (ub - ua) * ((x - a) / h);
            let mut p = a;
            self.pts.push(a);
            self.uh.push(ua);
            loop {
                while kink.peek().is_some_and(|&k| k <= p) {
                    kink.next();
                }
                let q = match kink.peek() {
                    Some(&k) if k < b => k,
                    _ => b,
                };
                if d == 2 {
                    let mid = 0.5 * (p + q);
                    self.pts.push(mid);
                    self.uh.push(interp(mid));
                }
                if q == b {
                    break;
                }
                self.pts.push(q);
                self.uh.push(interp(q));
                p = q;
            }
        }
        self.pts.push(self.length);
        self.uh.push(node_u(m));
        self.ex.resize(self.pts.len(), 0.0);
        self.exact.u_at(t, &self.pts, &mut self.ex);
        let (mut l2, mut semi) = (0.0, 0.0);
        let np = self.pts.len();
        let err = |i: usize| self.uh[i] - self.ex[i];
        let mut i = 0;
        while i + d < np {
            let len = self.pts[i + d] - self.pts[i];
            if len > 0.0 {
                if d == 1 {
                    let (e0, e1) = (err(i), err(i + 1));
                    l2 += len * (e0 * e0 + e0 * e1 + e1 * e1) / 3.0;
                    semi += (e1 - e0) * (e1 - e0) / len;
                } else {
                    let (e0, em, e1) = (err(i), err(i + 1), err(i + 2));
                    l2 += len / 30.0 * (4.0 * (e0 * e0 + e1 * e1) + 16.0 * em * em + 4.0 * em * (e0 + e1) - 2.0 * e0 * e1);
                    semi += (7.0 * (e0 * e0 + e1 * e1) + 16.0 * em * em - 16.0 * em * (e0 + e1) + 2.0 * e0 * e1) / (3.0 * len);
                }
            }
            i += d;
        }
        let v = match self.vnorm {
            VNorm::H1Seminorm => semi,
            VNorm::H1Full => semi + l2,
        };
        SpaceErrors { l2: l2.max(0.0).sqrt(), v: v.max(0.0).sqrt() }
    }
}

/// `L∞` and `L²` in time of a sampled error, accumulated.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeNorm {
    max: f64,
    sum_sq: f64,
    samples: usize,
}

impl TimeNorm {
    /// Adds one sample `e(t_n)` (its absolute value is used).
    #[inline]
    pub fn push(&mut self, e: f64) {
        let a = e.abs();
        // NaN propagates into max on purpose: a non-finite error must show.
        self.max = if a > self.max || a.is_nan() { a } else { self.max };
        self.sum_sq += a * a;
        self.samples += 1;
    }
    /// `max_n |e_n|`.
    pub fn linf(&self) -> f64 {
        self.max
    }
    /// `sqrt(dt Σ e_n²)`.
    pub fn l2(&self, dt: f64) -> f64 {
        (dt * self.sum_sq).sqrt()
    }
    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.samples
    }
}

/// Every error norm of SPEC §6 for one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormReport {
    /// `L∞(0,T; L²)` of `u_h - u`.
    pub linf_l2_u: f64,
    /// `L²(0,T; L²)` of `u_h - u`.
    pub l2_l2_u: f64,
    /// `L∞(0,T; V)` of `u_h - u`.
    pub linf_v_u: f64,
    /// `L²(0,T; V)` of `u_h - u`.
    pub l2_v_u: f64,
    /// `L²(0,T)` of `λ_h - λ`.
    pub l2_lambda: f64,
    /// `L∞(0,T)` of `E_h - E`.
    pub linf_energy: f64,
    /// `L²(0,T)` of `E_h - E`.
    pub l2_energy: f64,
    /// Total variation of `λ_h` over the run divided by that of the exact
    /// `λ` sampled at the same times (1 = no spurious oscillation; see
    /// [`ErrorNorms`]). NaN when the exact `λ` does not vary.
    pub lambda_tv_ratio: f64,
}

/// Accumulates all error norms of one run (an observer of the time loop).
///
/// The λ oscillation indicator is `TV(λ_h) / TV(λ)`, total variations over
/// the run of the computed and the exact contact force, sampled at the same
/// times: a scheme whose `λ_h` follows the exact square wave scores ≈ 1,
/// spurious oscillations during contact push it far above (the papers'
/// "big" oscillations are ratios of 10 and more).
pub struct ErrorNorms<'a> {
    space: SpaceIntegrator<'a>,
    exact: &'a dyn ExactSolution,
    u_l2: TimeNorm,
    u_v: TimeNorm,
    lambda: TimeNorm,
    energy: TimeNorm,
    tv_h: f64,
    tv_exact: f64,
    last_lambda: Option<(f64, f64)>,
}

impl<'a> ErrorNorms<'a> {
    /// For a uniform P1 mesh with `elements` elements.
    pub fn new(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm) -> Self {
        Self {
            space: SpaceIntegrator::new(exact, elements, vnorm),
            exact,
            u_l2: TimeNorm::default(),
            u_v: TimeNorm::default(),
            lambda: TimeNorm::default(),
            energy: TimeNorm::default(),
            tv_h: 0.0,
            tv_exact: 0.0,
            last_lambda: None,
        }
    }

    /// Displacement sample at `t` (nodal values as in [`SpaceIntegrator::errors`]).
    pub fn add_displacement(&mut self, t: f64, u: &[f64]) -> SpaceErrors {
        let e = self.space.errors(t, u);
        self.u_l2.push(e.l2);
        self.u_v.push(e.v);
        e
    }

    /// Contact force sample `λ_h` belonging to time `t`.
    pub fn add_lambda(&mut self, t: f64, lambda_h: f64) {
        let exact = self.exact.lambda(t);
        self.lambda.push(lambda_h - exact);
        if let Some((lh, le)) = self.last_lambda {
            self.tv_h += (lambda_h - lh).abs();
            self.tv_exact += (exact - le).abs();
        }
        self.last_lambda = Some((lambda_h, exact));
    }

    /// Discrete energy sample `E_h` belonging to time `t`.
    pub fn add_energy(&mut self, _t: f64, energy_h: f64) {
        self.energy.push(energy_h - self.exact.energy());
    }

    /// The norms, with `dt` the time step of the samples.
    pub fn report(&self, dt: f64) -> NormReport {
        NormReport {
            linf_l2_u: self.u_l2.linf(),
            l2_l2_u: self.u_l2.l2(dt),
            linf_v_u: self.u_v.linf(),
            l2_v_u: self.u_v.l2(dt),
            l2_lambda: self.lambda.l2(dt),
            linf_energy: self.energy.linf(),
            l2_energy: self.energy.l2(dt),
            lambda_tv_ratio: if self.tv_exact > 0.0 { self.tv_h / self.tv_exact } else { f64::NAN },
        }
    }
}
