//! # signorini-norms
//!
//! The errors of nodal values against the Dirichlet bar's exact solution,
//! with values found by hand:
//!
//! ```
//! use signorini_exact::{BarDirichlet, ExactSolution};
//! use signorini_norms::{SpaceIntegrator, VNorm};
//!
//! let exact = BarDirichlet;
//! // 4 P1 elements on [0, 1]; with the clamped end, V is the H¹ seminorm.
//! let mut space = SpaceIntegrator::new(&exact, 4, VNorm::H1Seminorm);
//! let nodal = |t: f64| -> Vec<f64> { (0..=4).map(|i| exact.fields(i as f64 / 4.0, t).u).collect() };
//! let close = |a: f64, b: f64| (a - b).abs() <= 1e-12;
//!
//! // At t = 1/4 the kinks x = t and x = 1 - t are nodes: the exact field is
//! // the P1 function of its nodal values, so the error is zero.
//! let u = nodal(0.25);
//! let e = space.errors(0.25, &u);
//! assert!(close(e.l2, 0.0) && close(e.v, 0.0));
//!
//! // Shifted by s: the error is the constant s, of L² norm s·sqrt(L) = s and
//! // zero gradient.
//! let s = 1e-3;
//! let shifted: Vec<f64> = u.iter().map(|v| v + s).collect();
//! let e = space.errors(0.25, &shifted);
//! assert!(close(e.l2, s) && close(e.v, 0.0));
//!
//! // At t = 0.3 the kink x = 0.3 cuts the element [0.25, 0.5]: the P1 function
//! // misses the corner of u there by 0.02, a hat of height 0.02 on that element
//! // with slopes 0.4 and 0.1, so ‖e‖² = 0.02² · 0.25/3 and
//! // |e|²_{H¹} = 0.4² · 0.05 + 0.1² · 0.2 = 0.01. The integrator splits the
//! // element at the kink and finds both.
//! let e = space.errors(0.3, &nodal(0.3));
//! assert!(close(e.l2, (0.02_f64 * 0.02 * 0.25 / 3.0).sqrt()), "{}", e.l2);
//! assert!(close(e.v, 0.1), "{}", e.v);
//! ```
//!
//! Error norms of docs/theory.md §6 for a P1 displacement on a uniform mesh of `[0, L]`
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
//! Degree `k = 2, 3` ([`SpaceIntegrator::with_degree`]): `u_h` is the Lagrange
//! interpolant of its `k m + 1` nodal values; on each piece (an element, or
//! the part of one between kinks) the error is a polynomial of degree
//! `q = max(k, degree_x)`, represented by its values at `q + 1` equispaced
//! points and integrated by `(q + 1)`-point Gauss–Legendre, exact for the
//! degree `2q` of `(u_h - u)²` (and `2q - 2` of its derivative's square).
//! Degree 1 keeps the P1 path above unchanged, bit for bit.
//!
//! Time norms: `L∞(0,T;X) = max_n e_X(t_n)` and
//! `L²(0,T;X) = sqrt(dt Σ_n e_X(t_n)²)` over the samples fed in.
//!
//! Architecture invariant: depends only on `signorini-exact`; no IO, no
//! knowledge of schemes or matrices.

use signorini_exact::ExactSolution;

/// Which norm is the `V` norm of docs/theory.md §6.1.
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
///
/// Per call: one batch evaluation of the exact solution at the nodes and at
/// the points of the few elements a kink crosses (and at the element
/// midpoints for degree 2), a branch-free pass over the elements, and, for
/// the elements a kink crosses, the unsplit contribution is replaced by the
/// sum over the pieces.
pub struct SpaceIntegrator<'a> {
    exact: &'a dyn ExactSolution,
    length: f64,
    h: f64,
    vnorm: VNorm,
    degree: usize,
    nodes: Vec<f64>,
    mids: Vec<f64>,
    ex_mids: Vec<f64>,
    kinks: Vec<f64>,
    ends: Vec<f64>,
    /// Degree 1: the nodes, then a level's split elements' points (`ex`:
    /// the exact solution there, `uh`: `u_h` at the split points). Degree
    /// `k >= 2`: the split points alone.
    pts: Vec<f64>,
    uh: Vec<f64>,
    ex: Vec<f64>,
    /// The degree-1 path's split elements: `(j, index of its first point in pts)`.
    split: Vec<(usize, usize)>,
    /// Element degree `k` of `u_h`.
    k: usize,
    /// Degree `k >= 2`: the Lagrange nodes `L i/(k m)`, their exact values,
    /// and the Gauss tables of the degree `q` interpolant on `[0, 1]`:
    /// weights `gw[g]`, values `gv[r][g] = ℓ_r(s_g)`, derivatives `gd[r][g] = ℓ_r'(s_g)`.
    lnodes: Vec<f64>,
    ex_lnodes: Vec<f64>,
    q: usize,
    gw: Vec<f64>,
    gv: Vec<Vec<f64>>,
    gd: Vec<Vec<f64>>,
    /// The CPU has AVX2: the P1 element sums are compiled with it too
    /// (chosen at run time; [`SpaceIntegrator::without_avx2`]).
    avx2: bool,
    /// [`p1_sums_body`]'s element terms, a chunk at a time.
    p1_buf: Box<([f64; P1_CHUNK], [f64; P1_CHUNK])>,
}

/// Gauss–Legendre nodes and weights on `[0, 1]` with `n` points (`1..=4`).
fn gauss01(n: usize) -> Vec<(f64, f64)> {
    let sym: &[(f64, f64)] = match n {
        1 => &[(0.0, 2.0)],
        2 => &[(-0.577_350_269_189_625_8, 1.0), (0.577_350_269_189_625_8, 1.0)],
        3 => &[(-0.774_596_669_241_483_4, 5.0 / 9.0), (0.0, 8.0 / 9.0), (0.774_596_669_241_483_4, 5.0 / 9.0)],
        4 => &[
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        ],
        _ => unreachable!("Gauss rules of 1 to 4 points only"),
    };
    sym.iter().map(|&(x, w)| (0.5 * (x + 1.0), 0.5 * w)).collect()
}

/// The Lagrange basis `ℓ_i` of degree `k` on the nodes `r/k` of `[0, 1]` at `s`.
fn lagrange(k: usize, i: usize, s: f64) -> f64 {
    let kf = k as f64;
    (0..=k).filter(|&r| r != i).map(|r| (kf * s - r as f64) / (i as f64 - r as f64)).product()
}

/// `ℓ_i'(s)` (product rule).
fn lagrange_d(k: usize, i: usize, s: f64) -> f64 {
    let kf = k as f64;
    (0..=k).filter(|&r| r != i).map(|r| kf / (i as f64 - r as f64) * (0..=k).filter(|&p| p != i && p != r).map(|p| (kf * s - p as f64) / (i as f64 - p as f64)).product::<f64>()).sum()
}

/// `(∫e², ∫e'²)` of the polynomial of degree `d` (1 or 2) with values `e` at
/// `d + 1` equispaced points of an interval of length `len`.
#[inline(always)]
fn piece(d: usize, len: f64, e: &[f64]) -> (f64, f64) {
    if d == 1 {
        let (e0, e1) = (e[0], e[1]);
        (len * (e0 * e0 + e0 * e1 + e1 * e1) / 3.0, (e1 - e0) * (e1 - e0) / len)
    } else {
        let (e0, em, e1) = (e[0], e[1], e[2]);
        // e'(s) = (a + b (2s − 1))/len on s in [0, 1], with the first and
        // second differences a = e1 − e0, b = 2(e0 − 2 em + e1): the
        // seminorm from the differences themselves. (Expanded as a quadratic
        // form in e0, em, e1 it cancels to round-off of e² before the
        // division by len, which on the sliver a kink at round-off distance
        // from a node cuts off an element made 0.003 of |e|²: 2 % of the
        // falling bar's V error at such levels.)
        let (a, b) = (e1 - e0, 2.0 * (e0 - 2.0 * em + e1));
        (len / 30.0 * (4.0 * (e0 * e0 + e1 * e1) + 16.0 * em * em + 4.0 * em * (e0 + e1) - 2.0 * e0 * e1), (a * a + b * b / 3.0) / len)
    }
}

/// Elements per chunk of [`p1_sums_body`] (its two buffers, 512 B, held by
/// the integrator: no allocation per call).
const P1_CHUNK: usize = 32;

/// The unsplit P1 element sums `(Σ_j (e_j² + e_j e_{j+1} + e_{j+1}²),
/// Σ_j (e_{j+1} − e_j)²)` over the `m = ex.len() − 1 >= 2` elements, with
/// `e_i = u_i − ex_i` (`u` holds nodes `0..m`, `u_last` node `m`): each
/// element's term `(e₀e₀ + e₀e₁) + e₁e₁`, `(e₁ − e₀)(e₁ − e₀)`, and each sum
/// from `0.0` in element order — the plain per-element formula, bit for
/// bit. In chunks of [`P1_CHUNK`] elements: the terms first, branch-free
/// over equal-length slices (vectorised across elements), then the two
/// ordered sums, one addition per element each, so the sums' dependency
/// chains are all that stays serial. (Chunks of 32 measured fastest of
/// 16 to 512 at m = 100, 1000 and 10 000: behind longer ones the sums wait
/// for the terms' loads from L2 instead of overlapping them.)
#[inline(always)]
fn p1_sums_body(u: &[f64], ex: &[f64], u_last: f64, ta: &mut [f64; P1_CHUNK], td: &mut [f64; P1_CHUNK]) -> (f64, f64) {
    let m = ex.len() - 1;
    let (u, ex) = (&u[..m], &ex[..=m]);
    let (mut l2, mut semi) = (0.0, 0.0);
    // Elements 0..m-1 (both nodes in `u`), chunk by chunk.
    let mut j = 0;
    while j + 1 < m {
        let c = P1_CHUNK.min(m - 1 - j);
        let (u0, u1, x0, x1) = (&u[j..j + c], &u[j + 1..j + c + 1], &ex[j..j + c], &ex[j + 1..j + c + 1]);
        for ((((a, d), (ua, ub)), xa), xb) in ta[..c].iter_mut().zip(td[..c].iter_mut()).zip(u0.iter().zip(u1)).zip(x0).zip(x1) {
            let (e0, e1) = (ua - xa, ub - xb);
            *a = e0 * e0 + e0 * e1 + e1 * e1;
            *d = (e1 - e0) * (e1 - e0);
        }
        for (a, d) in ta[..c].iter().zip(&td[..c]) {
            l2 += a;
            semi += d;
        }
        j += c;
    }
    // The last element, node m from `u_last`.
    let (e0, e1) = (u[m - 1] - ex[m - 1], u_last - ex[m]);
    l2 += e0 * e0 + e0 * e1 + e1 * e1;
    semi += (e1 - e0) * (e1 - e0);
    (l2, semi)
}

/// [`p1_sums_body`] compiled with AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn p1_sums_avx2(u: &[f64], ex: &[f64], u_last: f64, ta: &mut [f64; P1_CHUNK], td: &mut [f64; P1_CHUNK]) -> (f64, f64) {
    p1_sums_body(u, ex, u_last, ta, td)
}

/// [`p1_sums_body`], with AVX2 when `avx2` (no FMA: the same bits either way).
#[inline]
fn p1_sums(avx2: bool, u: &[f64], ex: &[f64], u_last: f64, buf: &mut ([f64; P1_CHUNK], [f64; P1_CHUNK])) -> (f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is set only when the CPU reports AVX2.
        return unsafe { p1_sums_avx2(u, ex, u_last, &mut buf.0, &mut buf.1) };
    }
    let _ = avx2;
    p1_sums_body(u, ex, u_last, &mut buf.0, &mut buf.1)
}

impl<'a> SpaceIntegrator<'a> {
    /// For a uniform mesh of `elements` elements on `[0, exact.length()]`.
    /// Exact solutions of degree up to 2 in `x` are supported (all of docs/theory.md §5).
    #[track_caller]
    pub fn new(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm) -> Self {
        Self::with_degree(exact, elements, 1, vnorm)
    }

    /// For Lagrange elements of degree `k` (1, 2 or 3; equispaced nodes) on a
    /// uniform mesh of `elements` elements: [`SpaceIntegrator::errors`] then
    /// takes the `k m + 1` nodal values (or `k m`, clamped end), numbered by
    /// position. Panics for another `k` (callers validate it).
    #[track_caller]
    pub fn with_degree(exact: &'a dyn ExactSolution, elements: usize, k: usize, vnorm: VNorm) -> Self {
        assert!((1..=3).contains(&k), "element degree {k} not in 1..=3");
        let degree = exact.degree_x().max(1);
        assert!(degree <= 2, "exact solutions of degree {degree} > 2 in x are not supported");
        assert!(elements >= 1, "need at least one element");
        let length = exact.length();
        let m = elements;
        let h = length / m as f64;
        let nodes: Vec<f64> = (0..=m).map(|i| if i == m { length } else { i as f64 * h }).collect();
        let mids: Vec<f64> = if degree == 2 && k == 1 { nodes.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect() } else { Vec::new() };
        let q = k.max(degree);
        let (lnodes, gw, gv, gd) = if k == 1 {
            (Vec::new(), Vec::new(), Vec::new(), Vec::new())
        } else {
            let g = gauss01(q + 1);
            (
                (0..=k * m).map(|i| length * i as f64 / (k * m) as f64).collect(),
                g.iter().map(|p| p.1).collect(),
                (0..=q).map(|r| g.iter().map(|p| lagrange(q, r, p.0)).collect()).collect(),
                (0..=q).map(|r| g.iter().map(|p| lagrange_d(q, r, p.0)).collect()).collect(),
            )
        };
        // Degree 1: the nodes, then each level's split elements' points
        // (`errors`); degree >= 2: the split elements' points alone.
        let mut pts = Vec::with_capacity(nodes.len() + 64);
        if k == 1 {
            pts.extend_from_slice(&nodes);
        }
        let pts_len = pts.len();
        Self {
            k,
            ex_lnodes: vec![0.0; lnodes.len()],
            lnodes,
            q,
            gw,
            gv,
            gd,
            exact,
            length,
            h,
            vnorm,
            degree,
            ex_mids: vec![0.0; mids.len()],
            nodes,
            mids,
            kinks: Vec::with_capacity(16),
            ends: Vec::with_capacity(16),
            pts,
            uh: Vec::with_capacity(64),
            ex: Vec::with_capacity(pts_len + 64),
            split: Vec::with_capacity(16),
            #[cfg(target_arch = "x86_64")]
            avx2: std::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            avx2: false,
            p1_buf: Box::new(([0.0; P1_CHUNK], [0.0; P1_CHUNK])),
        }
    }

    /// The same integrator with the P1 element sums on the baseline
    /// target's code even where the CPU has AVX2 (the same bits: for tests
    /// and benchmarks).
    pub fn without_avx2(mut self) -> Self {
        self.avx2 = false;
        self
    }

    /// The next element a kink splits, from kink `*k` on: fills `ends` with
    /// its piece ends (`a`, the kinks strictly inside `(a, b)`, `b`) and
    /// returns its index, advancing `*k` past those kinks; `None` (with `*k`
    /// advanced) for a kink at or beyond L or on a node, which splits nothing.
    fn split_element(&mut self, k: &mut usize, h: f64, m: usize) -> Option<usize> {
        // The element containing the kink: nodes[j] <= x < nodes[j+1]
        // (the division can round across a node, so settle it exactly).
        let x0 = self.kinks[*k];
        let mut j = ((x0 / h) as usize).min(m - 1);
        while j + 1 < m && self.nodes[j + 1] <= x0 {
            j += 1;
        }
        while j > 0 && self.nodes[j] > x0 {
            j -= 1;
        }
        let (a, b) = (self.nodes[j], self.nodes[j + 1]);
        if !(x0 < b) {
            *k += 1; // at or beyond L: not inside any element
            return None;
        }
        self.ends.clear();
        self.ends.push(a);
        while *k < self.kinks.len() && self.kinks[*k] < b {
            let x = self.kinks[*k];
            if x > *self.ends.last().unwrap_or(&a) {
                self.ends.push(x);
            }
            *k += 1;
        }
        if self.ends.len() == 1 {
            return None; // kink on a node: no split needed
        }
        self.ends.push(b);
        Some(j)
    }

    /// The errors at time `t` of the P1 function with nodal values `u`
    /// (`m + 1` values, or `m` for a clamped end whose last value is 0).
    #[track_caller]
    pub fn errors(&mut self, t: f64, u: &[f64]) -> SpaceErrors {
        if self.k > 1 {
            return self.errors_pk(t, u);
        }
        let m = self.nodes.len() - 1;
        assert!(u.len() == m || u.len() == m + 1, "need m or m+1 nodal values");
        let u_last = if u.len() == m + 1 { u[m] } else { 0.0 };
        let node_u = |i: usize| if i < m { u[i] } else { u_last };
        let (h, d) = (self.h, self.degree);
        // The elements crossed by kinks first: their sample points (with
        // midpoints for degree 2) go after the nodes in `pts`, and `u_h`
        // there into `uh`, so that the exact solution at the nodes and at
        // all of them is one call (pointwise: the values of one call each).
        self.exact.kinks(t, &mut self.kinks);
        self.pts.truncate(m + 1);
        self.uh.clear();
        self.split.clear();
        let mut k = 0;
        while k < self.kinks.len() {
            let Some(j) = self.split_element(&mut k, h, m) else { continue };
            let a = self.nodes[j];
            let (ua, ub) = (node_u(j), node_u(j + 1));
            let first = self.pts.len();
            self.pts.push(a);
            for w in self.ends.windows(2) {
                if d == 2 {
                    self.pts.push(0.5 * (w[0] + w[1]));
                }
                self.pts.push(w[1]);
            }
            self.uh.extend(self.pts[first..].iter().map(|x| ua + (ub - ua) * ((x - a) / h)));
            self.split.push((j, first));
        }
        self.ex.resize(self.pts.len(), 0.0);
        self.exact.u_at(t, &self.pts, &mut self.ex);
        if d == 2 {
            self.exact.u_at(t, &self.mids, &mut self.ex_mids);
        }
        // Unsplit element sums.
        let (mut l2, mut semi) = (0.0, 0.0);
        let ex = &self.ex[..=m];
        let err = |i: usize| node_u(i) - ex[i];
        if m == 1 {
            let e = [err(0), 0.5 * (node_u(0) + node_u(1)) - self.ex_mids.first().copied().unwrap_or(0.0), err(1)];
            let e = if d == 1 { [e[0], e[2], 0.0] } else { e };
            (l2, semi) = piece(d, h, &e[..=d]);
        } else if d == 1 {
            (l2, semi) = p1_sums(self.avx2, &u[..m], ex, u_last, &mut self.p1_buf);
            l2 *= h / 3.0;
            semi /= h;
        } else {
            for j in 0..m {
                let (ua, ub) = (node_u(j), node_u(j + 1));
                let e = [ua - ex[j], 0.5 * (ua + ub) - self.ex_mids[j], ub - ex[j + 1]];
                let (a, b) = piece(2, h, &e);
                l2 += a;
                semi += b;
            }
        }
        // The split elements, in order: the unsplit contribution removed,
        // the pieces' added.
        for (s, &(j, first)) in self.split.iter().enumerate() {
            let last = self.split.get(s + 1).map_or(self.pts.len(), |n| n.1);
            let (ua, ub) = (node_u(j), node_u(j + 1));
            let (xa, xb) = (self.ex[j], self.ex[j + 1]);
            let e_whole = if d == 1 { [ua - xa, ub - xb, 0.0] } else { [ua - xa, 0.5 * (ua + ub) - self.ex_mids[j], ub - xb] };
            let (wa, wb) = piece(d, h, &e_whole[..=d]);
            l2 -= wa;
            semi -= wb;
            let (pts, uh, ex) = (&self.pts[first..last], &self.uh[first - m - 1..last - m - 1], &self.ex[first..last]);
            let mut i = 0;
            while i + d < pts.len() {
                let len = pts[i + d] - pts[i];
                if len > 0.0 {
                    let e: [f64; 3] = std::array::from_fn(|q| if q <= d { uh[i + q] - ex[i + q] } else { 0.0 });
                    let (pa, pb) = piece(d, len, &e[..=d]);
                    l2 += pa;
                    semi += pb;
                }
                i += d;
            }
        }
        self.errors_from_integrals(l2, semi)
    }

    /// Length of the domain.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The errors from the integrals `∫ e²` and `∫ e_x²` (the P1 and Pk paths).
    fn errors_from_integrals(&self, l2: f64, semi: f64) -> SpaceErrors {
        let v = match self.vnorm {
            VNorm::H1Seminorm => semi,
            VNorm::H1Full => semi + l2,
        };
        SpaceErrors { l2: l2.max(0.0).sqrt(), v: v.max(0.0).sqrt() }
    }

    /// `(∫e², ∫e'²)` over a piece of length `len` of the degree-`q` polynomial
    /// with values `e[r]` at its `q + 1` equispaced points (Gauss, exact).
    #[inline]
    fn piece_pk(&self, len: f64, e: &[f64]) -> (f64, f64) {
        let (mut a, mut b) = (0.0, 0.0);
        for (g, w) in self.gw.iter().enumerate() {
            let (mut v, mut d) = (0.0, 0.0);
            for (r, er) in e.iter().enumerate() {
                v += er * self.gv[r][g];
                d += er * self.gd[r][g];
            }
            a += w * v * v;
            b += w * d * d;
        }
        (len * a, b / len)
    }

    /// [`SpaceIntegrator::errors`] for degree `k >= 2`.
    #[track_caller]
    fn errors_pk(&mut self, t: f64, u: &[f64]) -> SpaceErrors {
        let (k, q) = (self.k, self.q);
        let m = self.nodes.len() - 1;
        let n = k * m;
        assert!(u.len() == n || u.len() == n + 1, "need k m or k m + 1 nodal values");
        let node_u = |i: usize| if i < u.len() { u[i] } else { 0.0 };
        let h = self.h;
        self.exact.u_at(t, &self.lnodes, &mut self.ex_lnodes);
        // q == k (exact solutions have degree <= 2 <= k): the Lagrange nodes
        // of an element are its sample points.
        debug_assert_eq!(q, k);
        let mut e = [0.0; 4];
        let (mut l2, mut semi) = (0.0, 0.0);
        for j in 0..m {
            for (r, er) in e[..=k].iter_mut().enumerate() {
                *er = node_u(k * j + r) - self.ex_lnodes[k * j + r];
            }
            let (a, b) = self.piece_pk(h, &e[..=k]);
            l2 += a;
            semi += b;
        }
        // Elements crossed by kinks: replace their contribution.
        self.exact.kinks(t, &mut self.kinks);
        let mut kk = 0;
        while kk < self.kinks.len() {
            let Some(j) = self.split_element(&mut kk, h, m) else { continue };
            let a = self.nodes[j];
            for (r, er) in e[..=k].iter_mut().enumerate() {
                *er = node_u(k * j + r) - self.ex_lnodes[k * j + r];
            }
            let (wa, wb) = self.piece_pk(h, &e[..=k]);
            l2 -= wa;
            semi -= wb;
            // q + 1 equispaced points per piece.
            self.pts.clear();
            for w in self.ends.windows(2) {
                for r in 0..=q {
                    self.pts.push(if r == q { w[1] } else { w[0] + (w[1] - w[0]) * r as f64 / q as f64 });
                }
            }
            self.uh.clear();
            for p in 0..self.pts.len() {
                let s = (self.pts[p] - a) / h;
                self.uh.push((0..=k).map(|i| node_u(k * j + i) * lagrange(k, i, s)).sum());
            }
            self.ex.resize(self.pts.len(), 0.0);
            self.exact.u_at(t, &self.pts, &mut self.ex);
            for (p, w) in self.ends.windows(2).enumerate() {
                let len = w[1] - w[0];
                if len > 0.0 {
                    for (r, er) in e[..=q].iter_mut().enumerate() {
                        *er = self.uh[p * (q + 1) + r] - self.ex[p * (q + 1) + r];
                    }
                    let (pa, pb) = self.piece_pk(len, &e[..=q]);
                    l2 += pa;
                    semi += pb;
                }
            }
        }
        self.errors_from_integrals(l2, semi)
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

/// Every error norm of docs/theory.md §6 for one run.
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
    kind: NormKind,
    nodes: Vec<f64>,
    ref_vals: Vec<f64>,
    ref_l2: TimeNorm,
    ref_v: TimeNorm,
    ref_lambda: TimeNorm,
    ref_energy: TimeNorm,
    vnorm: VNorm,
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

/// Which error measure an [`ErrorNorms`] accumulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum NormKind {
    /// The exact norms of docs/theory.md §6.1 (elements split at the kinks).
    #[default]
    Exact,
    /// What GetFEM's 1D dynamic-contact demo computes: the error against the
    /// nodal interpolant `I_h u` (a P1 function, so `u_h - I_h u` is
    /// integrated exactly on the mesh, with no kink splitting), and every
    /// time norm divided by the same time norm of the reference (`I_h u`,
    /// `λ`, `E`). A weaker, relative measure, labelled as such.
    GetfemInterpolated,
}

impl<'a> ErrorNorms<'a> {
    /// For a uniform P1 mesh with `elements` elements.
    pub fn new(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm) -> Self {
        Self::with_kind(exact, elements, vnorm, NormKind::Exact)
    }

    /// With a choice of error measure.
    pub fn with_kind(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm, kind: NormKind) -> Self {
        Self::with_degree(exact, elements, 1, vnorm, kind)
    }

    /// For Lagrange elements of degree `k` (1, 2, 3; see
    /// [`SpaceIntegrator::with_degree`]). [`NormKind::GetfemInterpolated`]
    /// is a P1 measure: it panics for `k > 1` (callers refuse it).
    #[track_caller]
    pub fn with_degree(exact: &'a dyn ExactSolution, elements: usize, k: usize, vnorm: VNorm, kind: NormKind) -> Self {
        assert!(k == 1 || kind == NormKind::Exact, "the GetFEM-demo norms are defined for P1 only");
        Self {
            kind,
            // The nodes and the reference's values: the GetFEM-demo measure's
            // (the exact norms have their own in `space`).
            nodes: if kind == NormKind::GetfemInterpolated { (0..=elements).map(|i| exact.length() * i as f64 / elements as f64).collect() } else { Vec::new() },
            ref_vals: vec![0.0; if kind == NormKind::GetfemInterpolated { elements + 1 } else { 0 }],
            ref_l2: TimeNorm::default(),
            ref_v: TimeNorm::default(),
            ref_lambda: TimeNorm::default(),
            ref_energy: TimeNorm::default(),
            vnorm,
            space: SpaceIntegrator::with_degree(exact, elements, k, vnorm),
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
        let e = match self.kind {
            NormKind::Exact => self.space.errors(t, u),
            NormKind::GetfemInterpolated => self.interpolated(t, u),
        };
        self.u_l2.push(e.l2);
        self.u_v.push(e.v);
        e
    }

    /// `‖u_h - I_h u‖` (P1, exact on the mesh), and `‖I_h u‖` into the reference norms.
    fn interpolated(&mut self, t: f64, u: &[f64]) -> SpaceErrors {
        let m = self.nodes.len() - 1;
        self.exact.u_at(t, &self.nodes, &mut self.ref_vals);
        let h = self.nodes[1] - self.nodes[0];
        let node = |i: usize| if i < u.len() { u[i] } else { 0.0 };
        let (mut el2, mut esemi, mut rl2, mut rsemi) = (0.0, 0.0, 0.0, 0.0);
        for j in 0..m {
            let (e0, e1) = (node(j) - self.ref_vals[j], node(j + 1) - self.ref_vals[j + 1]);
            let (r0, r1) = (self.ref_vals[j], self.ref_vals[j + 1]);
            el2 += e0 * e0 + e0 * e1 + e1 * e1;
            esemi += (e1 - e0) * (e1 - e0);
            rl2 += r0 * r0 + r0 * r1 + r1 * r1;
            rsemi += (r1 - r0) * (r1 - r0);
        }
        let (el2, esemi, rl2, rsemi) = (el2 * h / 3.0, esemi / h, rl2 * h / 3.0, rsemi / h);
        let (ev, rv) = match self.vnorm {
            VNorm::H1Seminorm => (esemi, rsemi),
            VNorm::H1Full => (esemi + el2, rsemi + rl2),
        };
        self.ref_l2.push(rl2.sqrt());
        self.ref_v.push(rv.sqrt());
        SpaceErrors { l2: el2.max(0.0).sqrt(), v: ev.max(0.0).sqrt() }
    }

    /// Contact force sample `λ_h` belonging to time `t`.
    pub fn add_lambda(&mut self, t: f64, lambda_h: f64) {
        let exact = self.exact.lambda(t);
        self.lambda.push(lambda_h - exact);
        self.ref_lambda.push(exact);
        if let Some((lh, le)) = self.last_lambda {
            self.tv_h += (lambda_h - lh).abs();
            self.tv_exact += (exact - le).abs();
        }
        self.last_lambda = Some((lambda_h, exact));
    }

    /// Discrete energy sample `E_h` belonging to time `t`.
    pub fn add_energy(&mut self, _t: f64, energy_h: f64) {
        self.energy.push(energy_h - self.exact.energy());
        self.ref_energy.push(self.exact.energy());
    }

    /// The norms, with `dt` the time step of the samples (relative to the
    /// reference's norms for [`NormKind::GetfemInterpolated`]).
    pub fn report(&self, dt: f64) -> NormReport {
        let rel = |e: f64, r: f64| match self.kind {
            NormKind::Exact => e,
            NormKind::GetfemInterpolated => e / r,
        };
        NormReport {
            linf_l2_u: rel(self.u_l2.linf(), self.ref_l2.linf()),
            l2_l2_u: rel(self.u_l2.l2(dt), self.ref_l2.l2(dt)),
            linf_v_u: rel(self.u_v.linf(), self.ref_v.linf()),
            l2_v_u: rel(self.u_v.l2(dt), self.ref_v.l2(dt)),
            l2_lambda: rel(self.lambda.l2(dt), self.ref_lambda.l2(dt)),
            linf_energy: rel(self.energy.linf(), self.ref_energy.linf()),
            l2_energy: rel(self.energy.l2(dt), self.ref_energy.l2(dt)),
            lambda_tv_ratio: if self.tv_exact > 0.0 { self.tv_h / self.tv_exact } else { f64::NAN },
        }
    }
}
