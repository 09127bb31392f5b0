//! The Pk bar of docs/theory.md §2.1 (P2/P3: §2.1.4): uniform mesh of `m` elements on
//! `[0, L]`, Lagrange elements of degree `k ∈ {1, 2, 3}` with equispaced nodes,
//! the `k m + 1` nodes `x_i = i h / k` numbered by position; node 0 is the
//! contact node, node `k m` is either clamped (removed from the unknowns) or
//! free. Every matrix is banded with half-bandwidth `k`.
//!
//! Element matrices (`ρ = 1`, local nodes left to right):
//!
//! * P1: mass `h/6 [2 1; 1 2]`, stiffness `c²/h [1 -1; -1 1]`;
//! * P2: mass `h/30 [4 2 -1; 2 16 2; -1 2 4]`, stiffness
//!   `c²/(3h) [7 -8 1; -8 16 -8; 1 -8 7]`;
//! * P3: mass `h/1680 [128 99 -36 19; 99 648 -81 -36; -36 -81 648 99; 19 -36 99 128]`,
//!   stiffness `c²/(40h) [148 -189 54 -13; -189 432 -297 54; 54 -297 432 -189; -13 54 -189 148]`.
//!
//! The mass variants ([`BarMass`]) differ only near the contact node; for
//! `k = 1` every variant is tridiagonal, for `k = 2, 3` std, lumped and
//! mod/mod1 are defined ([`Bar::check_mass`]).

use crate::{FemError, SymBand};
use std::fmt;
use std::str::FromStr;

/// The condition at the far end `x = L` of the bar.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RightEnd {
    /// `u(L, t) = 0`: node `m` is not an unknown.
    Clamped,
    /// `u_x(L, t) = 0`: node `m` is an unknown.
    Free,
}

/// The mass treatments of docs/theory.md §2.1.2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BarMass {
    /// Consistent mass.
    Std,
    /// Row-sum lumped mass (GetFEM demo).
    Lumped,
    /// Mass redistribution of the papers: element `[0, h]` carries no mass
    /// (identical to [`BarMass::Mod1`], printed as `mod`).
    Mod,
    /// Weighted redistribution, `w_j = 1` for `j >= 1` (no redistribution).
    Mod1,
    /// Weighted redistribution, `w_j = m/(m-1)` (uniform, total mass kept).
    Mod2,
    /// Weighted redistribution, `w_1 = 2`, `w_j = 1` for `j >= 2` (nearest neighbour).
    Mod3,
    /// Consistent mass, then `M11 += M00 + M01`, row/column 0 zeroed (GetFEM type 1).
    Transfer,
    /// Consistent mass, row/column 0 zeroed and `M11 = 7h/12` (GetFEM type 2).
    Singular,
}

impl BarMass {
    /// Every variant, in documentation order.
    pub const ALL: [BarMass; 8] = [BarMass::Std, BarMass::Lumped, BarMass::Mod, BarMass::Mod1, BarMass::Mod2, BarMass::Mod3, BarMass::Transfer, BarMass::Singular];

    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            BarMass::Std => "std",
            BarMass::Lumped => "lumped",
            BarMass::Mod => "mod",
            BarMass::Mod1 => "mod1",
            BarMass::Mod2 => "mod2",
            BarMass::Mod3 => "mod3",
            BarMass::Transfer => "transfer",
            BarMass::Singular => "singular",
        }
    }

    /// Whether the contact node carries no mass (row/column 0 of M is zero).
    pub fn massless_contact_node(self) -> bool {
        !matches!(self, BarMass::Std | BarMass::Lumped)
    }

    /// Whether M is diagonal.
    pub fn is_diagonal(self) -> bool {
        matches!(self, BarMass::Lumped)
    }
}

impl fmt::Display for BarMass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for BarMass {
    type Err = FemError;
    fn from_str(s: &str) -> Result<Self, FemError> {
        BarMass::ALL.into_iter().find(|v| v.name() == s).ok_or_else(|| FemError::UnknownMass(s.to_string()))
    }
}

/// One degree's element matrices as exact fractions `num/den` (see the module docs).
struct Element {
    /// Mass `h · num/den`, row-major `(k+1)²`.
    mass: &'static [(f64, f64)],
    /// Row sums of the mass (lumped), `h · num/den`.
    lumped: &'static [(f64, f64)],
    /// Stiffness `c²/h · num/den`, row-major `(k+1)²`.
    stiffness: &'static [(f64, f64)],
}

/// P1: the fractions the P1 code always used (`h/3`, `h/6`, `h/2`, `c²/h`).
const P1: Element = Element { mass: &[(1.0, 3.0), (1.0, 6.0), (1.0, 6.0), (1.0, 3.0)], lumped: &[(1.0, 2.0), (1.0, 2.0)], stiffness: &[(1.0, 1.0), (-1.0, 1.0), (-1.0, 1.0), (1.0, 1.0)] };

const P2: Element = Element {
    mass: &[(4.0, 30.0), (2.0, 30.0), (-1.0, 30.0), (2.0, 30.0), (16.0, 30.0), (2.0, 30.0), (-1.0, 30.0), (2.0, 30.0), (4.0, 30.0)],
    lumped: &[(1.0, 6.0), (2.0, 3.0), (1.0, 6.0)],
    stiffness: &[(7.0, 3.0), (-8.0, 3.0), (1.0, 3.0), (-8.0, 3.0), (16.0, 3.0), (-8.0, 3.0), (1.0, 3.0), (-8.0, 3.0), (7.0, 3.0)],
};

const P3: Element = Element {
    mass: &[
        (128.0, 1680.0),
        (99.0, 1680.0),
        (-36.0, 1680.0),
        (19.0, 1680.0),
        (99.0, 1680.0),
        (648.0, 1680.0),
        (-81.0, 1680.0),
        (-36.0, 1680.0),
        (-36.0, 1680.0),
        (-81.0, 1680.0),
        (648.0, 1680.0),
        (99.0, 1680.0),
        (19.0, 1680.0),
        (-36.0, 1680.0),
        (99.0, 1680.0),
        (128.0, 1680.0),
    ],
    lumped: &[(1.0, 8.0), (3.0, 8.0), (3.0, 8.0), (1.0, 8.0)],
    stiffness: &[
        (148.0, 40.0),
        (-189.0, 40.0),
        (54.0, 40.0),
        (-13.0, 40.0),
        (-189.0, 40.0),
        (432.0, 40.0),
        (-297.0, 40.0),
        (54.0, 40.0),
        (54.0, 40.0),
        (-297.0, 40.0),
        (432.0, 40.0),
        (-189.0, 40.0),
        (-13.0, 40.0),
        (54.0, 40.0),
        (-189.0, 40.0),
        (148.0, 40.0),
    ],
};

/// A uniform Pk bar (`k = 1` unless [`Bar::with_degree`]): geometry, wave
/// speed, boundary condition at `x = L`, element degree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bar {
    /// Length `L` (> 0).
    pub length: f64,
    /// Number of elements `m` (>= 2).
    pub elements: usize,
    /// Wave speed `c` (> 0); the density is 1 (nondimensional).
    pub wave_speed: f64,
    /// Condition at `x = L`.
    pub right_end: RightEnd,
    /// Element degree `k` (1, 2 or 3; 1 from [`Bar::new`]).
    pub degree: usize,
}

impl Bar {
    /// A validated bar.
    pub fn new(length: f64, elements: usize, wave_speed: f64, right_end: RightEnd) -> Result<Self, FemError> {
        if !(2..=crate::MAX_ELEMENTS).contains(&elements) {
            return Err(FemError::Invalid { field: "m", value: elements as f64, allowed: "an integer in [2, 2^40] (sizes beyond are not addressable; memory runs out long before)" });
        }
        if !(length > 0.0 && length.is_finite()) {
            return Err(FemError::Invalid { field: "length", value: length, allowed: "finite and > 0" });
        }
        if !(wave_speed > 0.0 && wave_speed.is_finite()) {
            return Err(FemError::Invalid { field: "wave_speed", value: wave_speed, allowed: "finite and > 0" });
        }
        Ok(Self { length, elements, wave_speed, right_end, degree: 1 })
    }

    /// The same bar with Lagrange elements of degree `k` (equispaced nodes).
    /// Refused, naming `degree`: `k` other than 1, 2, 3, or a mesh whose
    /// `k m + 1` nodes are not addressable.
    pub fn with_degree(mut self, k: usize) -> Result<Self, FemError> {
        if !(1..=3).contains(&k) {
            return Err(FemError::Invalid { field: "degree", value: k as f64, allowed: "1, 2 or 3 (Lagrange P1, P2, P3)" });
        }
        if self.elements.checked_mul(k).is_none_or(|n| n > 3 * crate::MAX_ELEMENTS) {
            return Err(FemError::Invalid { field: "degree", value: k as f64, allowed: "k m <= 3 · 2^40 nodes" });
        }
        self.degree = k;
        Ok(self)
    }

    fn element(&self) -> &'static Element {
        match self.degree {
            1 => &P1,
            2 => &P2,
            3 => &P3,
            k => unreachable!("degree {k} is refused by with_degree"),
        }
    }

    /// The index of the last node, `k m` (nodes are `0..=k m`).
    pub fn last_node(&self) -> usize {
        self.degree * self.elements
    }

    /// Whether the mass treatment is defined at this degree: every one at
    /// `k = 1`; std, lumped, mod and mod1 at `k = 2, 3`. Refused, naming
    /// `mass`, otherwise (mod2, mod3, transfer and singular are P1 recipes:
    /// weights and values of P1 element matrices).
    pub fn check_mass(&self, variant: BarMass) -> Result<(), FemError> {
        if self.degree == 1 || matches!(variant, BarMass::Std | BarMass::Lumped | BarMass::Mod | BarMass::Mod1) {
            Ok(())
        } else {
            Err(FemError::MassForDegree { mass: variant.name(), degree: self.degree })
        }
    }

    /// The closed-form largest generalized eigenvalue `κ_h` of `(K, M)` for
    /// P1 with the `std` or `lumped` mass (docs/theory.md §2.4; `None`
    /// otherwise): with `C = cos(π/(2m))` for a clamped far end and `C = 1`
    /// for a free one, lumped `κ_h = (2c²/h²)(1 + C)` (`= (4c²/h²) sin²(θ/2)`
    /// at the top mode `θ = π − π/(2m)`, resp. `π`), consistent
    /// `κ_h = (6c²/h²)(1 + C)/(2 − C)`.
    pub fn max_eigenvalue_closed_form(&self, variant: BarMass) -> Option<f64> {
        if self.degree != 1 || !matches!(variant, BarMass::Std | BarMass::Lumped) {
            return None;
        }
        // In the pencil's entries: a = c²/h, e = M_00 = h/2 (lumped) or h/3 (std).
        let c2h2 = self.wave_speed * self.wave_speed / (self.h() * self.h());
        let lumped = variant == BarMass::Lumped;
        let a_over_e = if lumped { 2.0 * c2h2 } else { 3.0 * c2h2 };
        Some(crate::eigen::p1_closed_form(a_over_e, self.elements, self.right_end == RightEnd::Free, lumped))
    }

    /// Element size `h = L/m`.
    pub fn h(&self) -> f64 {
        self.length / self.elements as f64
    }

    /// Number of unknowns: `k m` (clamped) or `k m + 1` (free).
    pub fn dofs(&self) -> usize {
        match self.right_end {
            RightEnd::Clamped => self.last_node(),
            RightEnd::Free => self.last_node() + 1,
        }
    }

    /// Node coordinate `x_i = i h / k` (`i = 0..=k m`), computed as `L i / (k m)`.
    pub fn node(&self, i: usize) -> f64 {
        self.length * i as f64 / self.last_node() as f64
    }

    /// Mass matrix on all `k m + 1` nodes (before removing a clamped node).
    ///
    /// Element `j` contributes `w_j` times its element mass (or its row
    /// sums, lumped) with the variant's weights `w_j`. At `k = 2, 3` the
    /// massless contact node (mod, mod1) keeps of element 0 only its block on
    /// the interior nodes `1..k-1` (the mass of the functions vanishing at
    /// both ends of the element, positive definite), so node 0 alone is
    /// massless; at `k = 1` there is no such block and this is the P1 mod.
    ///
    /// Panics (`#[track_caller]`) for a variant [`Bar::check_mass`] refuses.
    #[track_caller]
    pub fn mass_all_nodes(&self, variant: BarMass) -> SymBand {
        if let Err(e) = self.check_mass(variant) {
            panic!("{e} (check with Bar::check_mass first)");
        }
        let m = self.elements;
        let (k, el) = (self.degree, self.element());
        let h = self.h();
        let weight = |j: usize| -> f64 {
            match variant {
                BarMass::Mod | BarMass::Mod1 if j == 0 => 0.0,
                BarMass::Mod2 if j == 0 => 0.0,
                BarMass::Mod2 => m as f64 / (m as f64 - 1.0),
                BarMass::Mod3 if j == 0 => 0.0,
                BarMass::Mod3 if j == 1 => 2.0,
                _ => 1.0,
            }
        };
        let mut mm = SymBand::zeros(k * m + 1, k);
        for j in 0..m {
            let w = weight(j) * h;
            let o = k * j;
            if variant == BarMass::Lumped {
                for (a, &(num, den)) in el.lumped.iter().enumerate() {
                    mm.add(o + a, o + a, w * num / den);
                }
            } else {
                for a in 0..=k {
                    for b in a..=k {
                        let (num, den) = el.mass[a * (k + 1) + b];
                        mm.add(o + a, o + b, w * num / den);
                    }
                }
            }
        }
        if k > 1 && matches!(variant, BarMass::Mod | BarMass::Mod1) {
            // Element 0's bubble block: interior nodes 1..k-1 only.
            for a in 1..k {
                for b in a..k {
                    let (num, den) = el.mass[a * (k + 1) + b];
                    mm.add(a, b, h * num / den);
                }
            }
        }
        match variant {
            BarMass::Transfer => {
                let moved = mm.get(0, 0) + mm.get(0, 1);
                mm.add(1, 1, moved);
                mm.zero_row_col(0);
            }
            BarMass::Singular => {
                mm.zero_row_col(0);
                mm.set(1, 1, 7.0 * h / 12.0);
            }
            _ => {}
        }
        mm
    }

    /// Mass matrix on all `k m + 1` nodes with a contact at each node of
    /// `nodes` (sorted or not, distinct): the mass treatment generalised
    /// from the one contact node 0 of [`Bar::mass_all_nodes`] (identical
    /// for `nodes = [0]`). For the massless family every contact node
    /// carries no mass:
    ///
    /// * `mod`/`mod1`: every element next to a contact node carries no mass;
    /// * `mod2`: the same, the other elements weighted `m/(m - z)` (`z`
    ///   elements emptied), so the total mass is kept;
    /// * `mod3`: each emptied element's mass goes to the next element away
    ///   from its contact node (refused if that element is missing or
    ///   emptied too);
    /// * `transfer`: consistent mass, then each contact node's row sum moves
    ///   to its neighbours' diagonals (all of it at an end node, half to
    ///   each side inside; refused for two adjacent contact nodes);
    /// * `singular` (GetFEM's type 2): end nodes only (0 and, with a free
    ///   end, `m`): the neighbour's diagonal becomes `7h/12`;
    ///
    /// and `std`/`lumped` are unchanged. Refused too: a contact node out of
    /// range, any node that is not a contact node left without mass, a
    /// variant [`Bar::check_mass`] refuses, and at `k = 2, 3` a massless
    /// treatment with contacts other than the one at node 0.
    pub fn mass_all_nodes_with_contacts(&self, variant: BarMass, nodes: &[usize]) -> Result<SymBand, FemError> {
        let m = self.elements;
        let refuse = |why: &'static str, node: usize| Err(FemError::MassAtContacts { mass: variant.name(), node, why });
        if let Some(&bad) = nodes.iter().find(|&&i| i > self.last_node()) {
            return refuse("a contact node beyond the last node k m", bad);
        }
        self.check_mass(variant)?;
        if nodes == [0] || !variant.massless_contact_node() {
            return Ok(self.mass_all_nodes(variant));
        }
        if self.degree > 1 {
            return refuse("at degree 2 and 3 the massless contact node (mod, mod1) is defined for the one contact node 0 only", nodes.iter().copied().find(|&i| i != 0).unwrap_or(0));
        }
        let is_contact = |i: usize| nodes.contains(&i);
        let h = self.h();
        let mut mm = match variant {
            BarMass::Transfer | BarMass::Singular => self.mass_all_nodes(BarMass::Std),
            _ => {
                // Element weights: 0 next to a contact node.
                let mut w = vec![1.0; m];
                let emptied: Vec<(usize, usize)> = nodes.iter().flat_map(|&i| [(i.wrapping_sub(1), i), (i, i)]).filter(|&(j, _)| j < m).collect();
                for &(j, _) in &emptied {
                    w[j] = 0.0;
                }
                let z = w.iter().filter(|x| **x == 0.0).count();
                if z >= m {
                    return refuse("every element would be emptied", nodes[0]);
                }
                match variant {
                    BarMass::Mod2 => {
                        let s = m as f64 / (m - z) as f64;
                        w.iter_mut().filter(|x| **x != 0.0).for_each(|x| *x = s);
                    }
                    BarMass::Mod3 => {
                        for &(j, i) in &emptied {
                            // The next element away from node i.
                            let next = if j == i { j + 1 } else { j.wrapping_sub(1) };
                            if next >= m || w[next] == 0.0 {
                                return refuse("mod3 moves an emptied element's mass to the next element away from the contact node, which is missing or emptied too (contact nodes at least 3 elements apart, 2 from an end)", i);
                            }
                            w[next] += 1.0;
                        }
                    }
                    _ => {}
                }
                let mut mm = SymBand::zeros(m + 1, 1);
                for (j, wj) in w.iter().enumerate() {
                    let wh = wj * h;
                    mm.add(j, j, wh / 3.0);
                    mm.add(j + 1, j + 1, wh / 3.0);
                    mm.add(j, j + 1, wh / 6.0);
                }
                mm
            }
        };
        match variant {
            BarMass::Transfer => {
                if let Some(&i) = nodes.iter().find(|&&i| (i > 0 && is_contact(i - 1)) || is_contact(i + 1)) {
                    return refuse("transfer moves a contact node's mass to its neighbours, which must not be contact nodes", i);
                }
                let moves: Vec<(usize, f64)> = nodes
                    .iter()
                    .flat_map(|&i| {
                        let row = mm.get(i, i) + if i > 0 { mm.get(i, i - 1) } else { 0.0 } + if i < m { mm.get(i, i + 1) } else { 0.0 };
                        let sides: Vec<usize> = [i.wrapping_sub(1), i + 1].into_iter().filter(|&j| j <= m).collect();
                        let share = row / sides.len() as f64;
                        sides.into_iter().map(move |j| (j, share))
                    })
                    .collect();
                for (j, v) in moves {
                    mm.add(j, j, v);
                }
                for &i in nodes {
                    mm.zero_row_col(i);
                }
            }
            BarMass::Singular => {
                if let Some(&i) = nodes.iter().find(|&&i| i != 0 && i != m) {
                    return refuse("singular (GetFEM's type 2) is defined at an end node only", i);
                }
                for &i in nodes {
                    mm.zero_row_col(i);
                    mm.set(if i == 0 { 1 } else { m - 1 }, if i == 0 { 1 } else { m - 1 }, 7.0 * h / 12.0);
                }
            }
            _ => {}
        }
        if let Some(i) = (0..=m).find(|&i| !is_contact(i) && !(mm.get(i, i) > 0.0)) {
            return refuse("it would leave a node that is not a contact node without mass", i);
        }
        Ok(mm)
    }

    /// Mass matrix on the unknowns with contacts at `nodes` (see
    /// [`Bar::mass_all_nodes_with_contacts`]); a clamped far end's node `k m`
    /// cannot be a contact node.
    pub fn mass_with_contacts(&self, variant: BarMass, nodes: &[usize]) -> Result<SymBand, FemError> {
        if let Some(&bad) = nodes.iter().find(|&&i| i >= self.dofs()) {
            return Err(FemError::MassAtContacts { mass: variant.name(), node: bad, why: "a contact node must be an unknown (the clamped end node m is not)" });
        }
        Ok(self.restrict(self.mass_all_nodes_with_contacts(variant, nodes)?))
    }

    /// Stiffness matrix on all `k m + 1` nodes.
    pub fn stiffness_all_nodes(&self) -> SymBand {
        let m = self.elements;
        let (deg, el) = (self.degree, self.element());
        let k = self.wave_speed * self.wave_speed / self.h();
        let mut kk = SymBand::zeros(deg * m + 1, deg);
        for j in 0..m {
            let o = deg * j;
            for a in 0..=deg {
                for b in a..=deg {
                    let (num, den) = el.stiffness[a * (deg + 1) + b];
                    kk.add(o + a, o + b, k * num / den);
                }
            }
        }
        kk
    }

    /// Mass matrix on the unknowns (panics for a variant [`Bar::check_mass`] refuses).
    #[track_caller]
    pub fn mass(&self, variant: BarMass) -> SymBand {
        self.restrict(self.mass_all_nodes(variant))
    }

    /// Stiffness matrix on the unknowns.
    pub fn stiffness(&self) -> SymBand {
        self.restrict(self.stiffness_all_nodes())
    }

    fn restrict(&self, a: SymBand) -> SymBand {
        match self.right_end {
            RightEnd::Free => a,
            // Drop the last node: the leading principal submatrix.
            RightEnd::Clamped => {
                let (n, p) = (self.last_node(), self.degree);
                let mut out = SymBand::zeros(n, p);
                for i in 0..n {
                    for j in i.saturating_sub(p)..=i {
                        out.set(i, j, a.get(i, j));
                    }
                }
                out
            }
        }
    }

    /// Load vector `F_i = ∫ f φ_i` on the unknowns, by Gauss–Legendre
    /// quadrature per element: 3 points for P1 (exact for `f` of degree
    /// <= 4), 5 points for P2 and P3 (exact for `f` of degree <= 9 - k).
    pub fn load(&self, f: impl Fn(f64) -> f64) -> Vec<f64> {
        if self.degree > 1 {
            return self.load_pk(f);
        }
        const G: [(f64, f64); 3] = [(-0.774_596_669_241_483_4, 5.0 / 9.0), (0.0, 8.0 / 9.0), (0.774_596_669_241_483_4, 5.0 / 9.0)];
        let h = self.h();
        let mut out = vec![0.0; self.elements + 1];
        for j in 0..self.elements {
            let a = self.node(j);
            for (xi, w) in G {
                let s = 0.5 * (xi + 1.0); // local coordinate in [0, 1]
                let fx = f(a + s * h) * w * 0.5 * h;
                out[j] += fx * (1.0 - s);
                out[j + 1] += fx * s;
            }
        }
        out.truncate(self.dofs());
        out
    }

    fn load_pk(&self, f: impl Fn(f64) -> f64) -> Vec<f64> {
        let (k, h) = (self.degree, self.h());
        let mut out = vec![0.0; self.last_node() + 1];
        for j in 0..self.elements {
            let a = self.node(k * j);
            for (xi, w) in GAUSS5 {
                let s = 0.5 * (xi + 1.0);
                let fx = f(a + s * h) * w * 0.5 * h;
                for (i, o) in out[k * j..=k * j + k].iter_mut().enumerate() {
                    *o += fx * lagrange(k, i, s);
                }
            }
        }
        out.truncate(self.dofs());
        out
    }
}

/// 5-point Gauss–Legendre on `[-1, 1]` (exact for degree <= 9).
const GAUSS5: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// The Lagrange basis function `i` of degree `k` on the equispaced nodes
/// `r/k` (`r = 0..=k`) of `[0, 1]`, at `s`.
pub fn lagrange(k: usize, i: usize, s: f64) -> f64 {
    let kf = k as f64;
    (0..=k).filter(|&r| r != i).map(|r| (kf * s - r as f64) / (i as f64 - r as f64)).product()
}
