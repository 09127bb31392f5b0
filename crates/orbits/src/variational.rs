//! The linearisation of the exact flow: per phase (a set of held contacts)
//! the state-transition matrix of the linear system, in closed form from
//! its modes, and at each event the saltation matrix (docs/theory.md §12).
//!
//! The state is `x = (q_s, v_s)`, `s` the dofs with mass (every dof of a
//! massive model; the massless contact dofs of mass redistribution and
//! reduced models are statically condensed and carry no state).
//!
//! **Phases.** With the contacts `H` held, the held massive dofs are fixed
//! (`δq_h = δv_h = 0`) and the free ones obey `M_ff δq'' + C_ff δq' +
//! K_eff δq = 0`, `K_eff = K_ff` (massive), or the static condensation of
//! the massless dofs not held, `K_ss − K_sZ K_ZZ⁻¹ K_Zs`. With
//! `Φᵀ M_ff Φ = I`, `Φᵀ K_eff Φ = diag(k_i)`, `Φᵀ C_ff Φ = diag(c_i)`
//! (classical damping), each modal pair `(η, η')` moves by
//!
//! ```text
//! [ e^{−ατ}(C + αS)    e^{−ατ} S        ]     α = c/2, λ = k − α²,
//! [ −k e^{−ατ} S       e^{−ατ}(C − αS)  ]     C, S = cos √λτ, sin √λτ/√λ (cosh, sinh for λ < 0; 1, τ for λ = 0)
//! ```
//!
//! the same closed form as the flow itself: exact to round-off over any
//! interval.
//!
//! **Events.** At an impact located on the contact `j` (guard
//! `h = q_{c_j} − bound`), Newton's law for the contacts `A` the impact's
//! LCP gives an impulse is the linear jump `v⁺ = D v⁻`,
//! `D = I − M⁻¹ E_A W_AA⁻¹ (I + diag e_A) E_Aᵀ` (`W = E_Aᵀ M⁻¹ E_A`). The
//! saltation matrix carries a perturbation across the event, whose time
//! moves with it:
//!
//! ```text
//! S = DJ + (f⁺ − DJ f⁻) ∇hᵀ / (∇hᵀ f⁻),   DJ = diag(I, D),   ∇hᵀ f⁻ = v⁻_{c_j},
//! ```
//!
//! `f∓` the vector fields before and after (each with its own held set: a
//! plastic impact that leaves the contact held takes the held field). A
//! release (a held force through 0) and every event of a massless contact
//! leave the vector field continuous: `S = I`, only the phase changes.
//! Where a run of impacts accumulates (chattering to rest), the run puts
//! the contact at rest at its last located impact: that instant's jump is
//! a plastic one (`e = 0` for the contact), and its saltation into the
//! phase after closes the product, whose limit is the map's Jacobian
//! (docs/theory.md §12.1.1).

use crate::OrbitError;
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::{DenseSolveCore, Solve};
use faer::{Accum, Mat, Side};
use signorini_schemes::Dynamics;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// A contact as the linearisation needs it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Site {
    pub dof: usize,
    pub restitution: f64,
}

/// The linear structure: its load-free core (shared by the models of one
/// structure: [`Core`]), its contacts, and per held set met its parts and
/// buffers (one entry per held set, in the order met: a run meets a few,
/// and each event's lookup compares the held set with theirs, without
/// hashing the set or allocating).
pub(crate) struct Linear {
    core: Arc<Core>,
    pub sites: Vec<Site>,
    held: RefCell<Vec<(Vec<usize>, Held)>>,
}

/// What the linearisation of one structure needs and no load, bound or
/// restitution enters: the dense matrices, `M⁻¹`, the state's dofs, and
/// per held set met its modes and free mass (each built lazily, when first
/// asked for, by whichever model of the structure asks: a continuation in
/// a forcing's frequency or amplitude builds each once). Shared across
/// threads (a basin's cells).
pub(crate) struct Core {
    n: usize,
    m: Mat<f64>,
    k: Mat<f64>,
    c: Option<Mat<f64>>,
    /// `M⁻¹` (massive models).
    minv: Mat<f64>,
    /// The dofs with mass, in order: the state's.
    state: Vec<usize>,
    /// The massless dofs.
    zero: Vec<usize>,
    parts: Mutex<HashMap<Vec<usize>, Arc<Parts>>>,
}

/// One held set's load-free parts.
#[derive(Default)]
struct Parts {
    /// Its free dofs' modes ([`Linear::transport`]).
    phase: OnceLock<Phase>,
    /// Its free massive dofs and the LU factors of `M_ff` (the same
    /// factors, hence the same solves, as factoring at every call:
    /// [`Linear::field`]).
    mass: OnceLock<FreeMass>,
}

/// A held set as one model meets it: its shared parts and the buffers of
/// [`Linear::transport`] (every product of its step written into one of
/// these: the variational step allocates nothing once a phase has been
/// met with a Jacobian of its width).
struct Held {
    parts: Arc<Parts>,
    work: Work,
}

/// The free massive dofs of a held set and the factors of their `M_ff`
/// (`None`: no free dof).
struct FreeMass {
    free: Vec<usize>,
    lu: Option<faer::linalg::solvers::PartialPivLu<f64>>,
}

/// The free dofs' modes of one held set.
struct Phase {
    /// Positions in the state's dof list of the free massive dofs.
    free: Vec<usize>,
    phi: Mat<f64>,
    /// `Φᵀ M_ff`.
    phit_m: Mat<f64>,
    k: Vec<f64>,
    c: Vec<f64>,
}

/// [`Linear::transport`]'s buffers: `qf`, `vf` the free rows of the
/// Jacobian, `p`, `q` their modal coordinates, `a`, `b` those moved over
/// the phase, `dq`, `dv` back on the free dofs (each `nf × cols`, the
/// shapes the products had when they were allocated per call).
#[derive(Default)]
struct Work {
    bufs: Vec<Mat<f64>>,
}

fn dense(b: &signorini_fem::SymBand) -> Mat<f64> {
    let n = b.n();
    let p = b.half_bandwidth();
    Mat::from_fn(n, n, |i, j| if i.abs_diff(j) <= p { b.get(i, j) } else { 0.0 })
}

fn sub(a: &Mat<f64>, rows: &[usize], cols: &[usize]) -> Mat<f64> {
    Mat::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
}

impl Core {
    /// The core of `dy`'s structure.
    pub fn new(dy: &Dynamics) -> Result<Self, OrbitError> {
        let n = dy.n();
        let (m, k, c) = (dense(&dy.mass), dense(&dy.stiffness), dy.damping.as_ref().map(dense));
        let mut zero: Vec<usize> = dy.contacts.iter().filter(|c| c.massless).map(|c| c.dof).collect();
        zero.sort_unstable();
        zero.dedup();
        let state: Vec<usize> = (0..n).filter(|d| zero.binary_search(d).is_err()).collect();
        let minv = if zero.is_empty() {
            let llt = m.llt(Side::Lower).map_err(|_| OrbitError::Model("the mass matrix is not positive definite".into()))?;
            llt.inverse()
        } else {
            Mat::zeros(0, 0)
        };
        Ok(Self { n, m, k, c, minv, state, zero, parts: Mutex::new(HashMap::new()) })
    }

    /// The parts of the held set `held` (made empty if new).
    fn parts(&self, held: &[usize]) -> Arc<Parts> {
        match self.parts.lock() {
            Ok(mut map) => map.entry(held.to_vec()).or_default().clone(),
            Err(_) => Arc::default(),
        }
    }
}

impl Linear {
    /// The linearisation of `dy` with restitution `e` for every contact
    /// without its own, on `core` (which the caller has found to be `dy`'s
    /// structure: [`crate::map::Model`]'s shared parts, whose flow bases
    /// were built from the same matrices, fit it), else on a new one.
    pub fn with_core(dy: &Dynamics, e: f64, core: Option<Arc<Core>>) -> Result<Self, OrbitError> {
        let core = match core {
            Some(c) => c,
            None => Arc::new(Core::new(dy)?),
        };
        let sites = dy.contacts.iter().map(|c| Site { dof: c.dof, restitution: c.restitution.unwrap_or(e) }).collect();
        Ok(Self { core, sites, held: RefCell::new(Vec::new()) })
    }

    /// The shared core.
    pub fn core(&self) -> &Arc<Core> {
        &self.core
    }

    /// The dofs with mass, in order: the state's.
    pub fn state(&self) -> &[usize] {
        &self.core.state
    }

    /// Unknowns of the state `(q_s, v_s)`.
    pub fn dim(&self) -> usize {
        2 * self.core.state.len()
    }

    pub fn massless(&self) -> bool {
        !self.core.zero.is_empty()
    }

    /// The state of the full `(q, v)`.
    pub fn pack(&self, q: &[f64], v: &[f64]) -> Vec<f64> {
        let state = &self.core.state;
        state.iter().map(|&d| q[d]).chain(state.iter().map(|&d| v[d])).collect()
    }

    /// The full `(q, v)` of a state (massless dofs 0: the run condenses them).
    pub fn unpack(&self, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let core = &*self.core;
        let (mut q, mut v) = (vec![0.0; core.n], vec![0.0; core.n]);
        let s = core.state.len();
        for (i, &d) in core.state.iter().enumerate() {
            (q[d], v[d]) = (x[i], x[s + i]);
        }
        (q, v)
    }

    /// The entry of the held set `held` (made if new: its parts from the core).
    fn held_entry<'a>(&self, sets: &'a mut Vec<(Vec<usize>, Held)>, held: &[usize]) -> &'a mut Held {
        let i = match sets.iter().position(|(set, _)| set == held) {
            Some(i) => i,
            None => {
                sets.push((held.to_vec(), Held { parts: self.core.parts(held), work: Work::default() }));
                sets.len() - 1
            }
        };
        &mut sets[i].1
    }

    /// The modes of the held set `held` into its parts (unless there).
    fn phase_of(&self, held: &[usize], parts: &Parts) -> Result<(), OrbitError> {
        if parts.phase.get().is_some() {
            return Ok(());
        }
        let core = &*self.core;
        let held_dofs: Vec<usize> = held.iter().map(|&j| self.sites[j].dof).collect();
        let (free, keff): (Vec<usize>, Mat<f64>) = if core.zero.is_empty() {
            let free: Vec<usize> = (0..core.state.len()).filter(|&i| !held_dofs.contains(&core.state[i])).collect();
            let dofs: Vec<usize> = free.iter().map(|&i| core.state[i]).collect();
            (free, sub(&core.k, &dofs, &dofs))
        } else {
            let s = &core.state;
            let cond: Vec<usize> = core.zero.iter().copied().filter(|d| !held_dofs.contains(d)).collect();
            let mut keff = sub(&core.k, s, s);
            if !cond.is_empty() {
                let kzz = sub(&core.k, &cond, &cond);
                let kzs = sub(&core.k, &cond, s);
                let lu = kzz.partial_piv_lu();
                let x = lu.solve(&kzs);
                keff -= sub(&core.k, s, &cond) * x;
            }
            ((0..s.len()).collect(), keff)
        };
        let dofs: Vec<usize> = free.iter().map(|&i| core.state[i]).collect();
        let mff = sub(&core.m, &dofs, &dofs);
        let nf = dofs.len();
        let phase = if nf == 0 {
            Phase { free, phi: Mat::zeros(0, 0), phit_m: Mat::zeros(0, 0), k: vec![], c: vec![] }
        } else {
            let llt = mff.llt(Side::Lower).map_err(|_| OrbitError::Model("the mass matrix of the free dofs is not positive definite".into()))?;
            let l = llt.L().to_owned();
            let mut linv = Mat::<f64>::identity(nf, nf);
            faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), linv.as_mut(), faer::Par::Seq);
            let a = &linv * &keff * linv.transpose();
            let a = Mat::from_fn(nf, nf, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
            let evd = a.self_adjoint_eigen(Side::Lower).map_err(|_| OrbitError::Model("the modes of a phase did not converge".into()))?;
            let kmax = (0..nf).map(|i| evd.S().column_vector()[i].abs()).fold(0.0, f64::max);
            let kv: Vec<f64> = (0..nf).map(|i| evd.S().column_vector()[i]).map(|w2| if w2.abs() <= 1e-12 * kmax { 0.0 } else { w2 }).collect();
            let phi = linv.transpose() * evd.U();
            let cv = match &core.c {
                None => vec![0.0; nf],
                Some(cm) => {
                    let modal = phi.transpose() * sub(cm, &dofs, &dofs) * &phi;
                    let diag = (0..nf).map(|i| modal[(i, i)].abs()).fold(0.0, f64::max);
                    let off = (0..nf).flat_map(|i| (0..nf).filter(move |&j| j != i).map(move |j| (i, j))).map(|(i, j)| modal[(i, j)].abs()).fold(0.0, f64::max);
                    if off > 1e-10 * diag.max(f64::MIN_POSITIVE) {
                        return Err(OrbitError::Model(
                            "damping: non-classical (the free dofs' modes do not diagonalise C); the variational flow takes classical damping (e.g. Rayleigh C = a M + b K)".into(),
                        ));
                    }
                    (0..nf).map(|i| modal[(i, i)].max(0.0)).collect()
                }
            };
            let phit_m = phi.transpose() * &mff;
            Phase { free, phi, phit_m, k: kv, c: cv }
        };
        // Another model of the structure may have set it meanwhile: the same bits.
        let _ = parts.phase.set(phase);
        Ok(())
    }

    /// The lowest mode with no contact held: `ω²` and its shape on the
    /// state's dofs, mass-normalised (`φᵀ M φ = 1`; massless dofs condensed).
    pub fn lowest_mode(&self) -> Result<(f64, Vec<f64>), OrbitError> {
        let mut map = self.held.borrow_mut();
        let parts = self.held_entry(&mut map, &[]).parts.clone();
        self.phase_of(&[], &parts)?;
        let ph = parts.phase.get().expect("just built");
        let Some(i) = (0..ph.k.len()).min_by(|&a, &b| ph.k[a].total_cmp(&ph.k[b])) else {
            return Err(OrbitError::Model("the model has no dof with mass".into()));
        };
        let mut shape = vec![0.0; self.core.state.len()];
        for (r, &pos) in ph.free.iter().enumerate() {
            shape[pos] = ph.phi[(r, i)];
        }
        Ok((ph.k[i], shape))
    }

    /// `jac ← Φ_H(τ) jac`: the state-transition matrix of the phase with
    /// the contacts `held` (sorted) over `τ`, applied to the rows of `jac`.
    pub fn transport(&self, held: &[usize], tau: f64, jac: &mut Mat<f64>) -> Result<(), OrbitError> {
        let mut map = self.held.borrow_mut();
        let entry = self.held_entry(&mut map, held);
        self.phase_of(held, &entry.parts)?;
        let ph = entry.parts.phase.get().expect("just built");
        let s = self.core.state.len();
        let cols = jac.ncols();
        let nf = ph.free.len();
        let work = &mut entry.work;
        if work.bufs.len() != 8 || work.bufs[0].ncols() != cols {
            work.bufs = (0..8).map(|_| Mat::<f64>::zeros(nf, cols)).collect();
        }
        let [qf, vf, p, q, a, b, dq, dv] = work.bufs.as_mut_slice() else { unreachable!("eight buffers") };
        for j in 0..cols {
            for (i, &r) in ph.free.iter().enumerate() {
                qf[(i, j)] = jac[(r, j)];
                vf[(i, j)] = jac[(s + r, j)];
            }
        }
        // The products as `Mat * Mat` computes them (faer's matmul, replace,
        // the global parallelism), into the buffers: the same bits.
        let par = faer::get_global_parallelism();
        matmul(p.as_mut(), Accum::Replace, ph.phit_m.as_ref(), qf.as_ref(), 1.0, par);
        matmul(q.as_mut(), Accum::Replace, ph.phit_m.as_ref(), vf.as_ref(), 1.0, par);
        for i in 0..nf {
            let [a11, a12, a21, a22] = modal_transition(ph.k[i], ph.c[i], tau);
            for j in 0..cols {
                a[(i, j)] = a11 * p[(i, j)] + a12 * q[(i, j)];
                b[(i, j)] = a21 * p[(i, j)] + a22 * q[(i, j)];
            }
        }
        matmul(dq.as_mut(), Accum::Replace, ph.phi.as_ref(), a.as_ref(), 1.0, par);
        matmul(dv.as_mut(), Accum::Replace, ph.phi.as_ref(), b.as_ref(), 1.0, par);
        // The held dofs' rows are 0.
        jac.fill(0.0);
        for (i, &r) in ph.free.iter().enumerate() {
            for j in 0..cols {
                jac[(r, j)] = dq[(i, j)];
                jac[(s + r, j)] = dv[(i, j)];
            }
        }
        Ok(())
    }

    /// The vector field `(v, a)` at `(t, q, v)` with the contacts `held`:
    /// `a_f = M_ff⁻¹ (F − K q − C v)_f`, `a_h = 0`, `f` the dofs with mass
    /// not held (a massless contact dof's row carries its reaction and no
    /// acceleration: `q` must hold it where the run put it, condensed).
    pub fn field(&self, dy: &Dynamics, held: &[usize], t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let core = &*self.core;
        let n = core.n;
        let mut r = vec![0.0; n];
        dy.load_at(t, &mut r);
        for i in 0..n {
            let mut s = 0.0;
            for j in 0..n {
                s += core.k[(i, j)] * q[j] + core.c.as_ref().map_or(0.0, |c| c[(i, j)] * v[j]);
            }
            r[i] -= s;
        }
        let mut map = self.held.borrow_mut();
        let parts = &self.held_entry(&mut map, held).parts;
        let fm = parts.mass.get_or_init(|| {
            let held_dofs: Vec<usize> = held.iter().map(|&j| self.sites[j].dof).collect();
            let free: Vec<usize> = (0..n).filter(|d| !held_dofs.contains(d) && core.zero.binary_search(d).is_err()).collect();
            let lu = (!free.is_empty()).then(|| sub(&core.m, &free, &free).partial_piv_lu());
            FreeMass { free, lu }
        });
        let mut a = vec![0.0; n];
        if let Some(lu) = &fm.lu {
            let free = &fm.free;
            let rhs = Mat::from_fn(free.len(), 1, |i, _| r[free[i]]);
            let sol = lu.solve(&rhs);
            for (i, &d) in free.iter().enumerate() {
                a[d] = sol[(i, 0)];
            }
        }
        self.pack(v, &a)
    }

    /// `M⁻¹ Σ r_i e_{c_i}` (massive models).
    pub fn minv_impulse(&self, impulses: &[(usize, f64)]) -> Vec<f64> {
        let core = &*self.core;
        let mut out = vec![0.0; core.n];
        for &(j, r) in impulses {
            let d = self.sites[j].dof;
            for i in 0..core.n {
                out[i] += core.minv[(i, d)] * r;
            }
        }
        out
    }

    /// `out −= M⁻¹ E_A W_AA⁻¹ diag(coef) E_Aᵀ v` (`W = E_Aᵀ M⁻¹ E_A`): with
    /// `coef` = `1 + e` per contact of `active` and `out` = `v`, the
    /// velocity after the impact, `D v`; with `coef` = `∂e/∂λ` and `out` =
    /// 0, the derivative of `v⁺` in the restitutions.
    pub fn impact_change(&self, active: &[usize], coef: &[f64], v: &[f64], out: &mut [f64]) {
        let n = self.core.n;
        let minv = &self.core.minv;
        let na = active.len();
        if na == 0 {
            return;
        }
        let dofs: Vec<usize> = active.iter().map(|&j| self.sites[j].dof).collect();
        let winv = Mat::from_fn(na, na, |a, b| minv[(dofs[a], dofs[b])]).partial_piv_lu().inverse();
        let ev: Vec<f64> = dofs.iter().zip(coef).map(|(&d, c)| c * v[d]).collect();
        for a in 0..na {
            let z: f64 = (0..na).map(|b| winv[(a, b)] * ev[b]).sum();
            for i in 0..n {
                out[i] -= minv[(i, dofs[a])] * z;
            }
        }
    }

    /// `(f⁺ − DJ f⁻) / v_n`, the saltation's rank-one column (module docs):
    /// `S = DJ + this ∇hᵀ`.
    fn saltation_column(&self, active: &[(usize, f64)], f_minus: &[f64], f_plus: &[f64], vn: f64) -> Vec<f64> {
        let n = self.core.n;
        let (ids, coef): (Vec<usize>, Vec<f64>) = active.iter().map(|&(j, e)| (j, 1.0 + e)).unzip();
        let mut djf = f_minus.to_vec();
        self.impact_change(&ids, &coef, &f_minus[n..], &mut djf[n..]);
        (0..2 * n).map(|i| (f_plus[i] - djf[i]) / vn).collect()
    }

    /// `jac ← S jac`, the saltation matrix of an impact located on the
    /// contact `guard` with the LCP's active contacts `active`, each with
    /// the restitution of its jump (its own; 0 where an accumulation of
    /// its impacts ends: docs/theory.md §12.1.1) (module docs); `f_minus`,
    /// `f_plus` the vector fields, `vn` the guard's velocity before.
    /// Returns the rank-one column `(f⁺ − DJ f⁻) / v_n`.
    pub fn saltation(&self, guard: usize, active: &[(usize, f64)], f_minus: &[f64], f_plus: &[f64], vn: f64, jac: &mut Mat<f64>) -> Vec<f64> {
        let n = self.core.n;
        let cols = jac.ncols();
        let (ids, coef): (Vec<usize>, Vec<f64>) = active.iter().map(|&(j, e)| (j, 1.0 + e)).unzip();
        let row = self.sites[guard].dof;
        let gq: Vec<f64> = (0..cols).map(|j| jac[(row, j)]).collect();
        for j in 0..cols {
            let col: Vec<f64> = (0..n).map(|i| jac[(n + i, j)]).collect();
            let mut dv = col.clone();
            self.impact_change(&ids, &coef, &col, &mut dv);
            for i in 0..n {
                jac[(n + i, j)] = dv[i];
            }
        }
        let s = self.saltation_column(active, f_minus, f_plus, vn);
        for (i, si) in s.iter().enumerate() {
            for j in 0..cols {
                jac[(i, j)] += si * gq[j];
            }
        }
        s
    }
}

/// The modal pair's transition over `τ` (module docs): `[a11, a12, a21, a22]`.
fn modal_transition(k: f64, c: f64, tau: f64) -> [f64; 4] {
    let alpha = 0.5 * c;
    let lambda = k - alpha * alpha;
    let (cc, s) = if lambda > 0.0 {
        let w = lambda.sqrt();
        ((w * tau).cos(), (w * tau).sin() / w)
    } else if lambda < 0.0 {
        let w = (-lambda).sqrt();
        ((w * tau).cosh(), (w * tau).sinh() / w)
    } else {
        (1.0, tau)
    };
    let d = (-alpha * tau).exp();
    [d * (cc + alpha * s), d * s, -k * d * s, d * (cc - alpha * s)]
}
