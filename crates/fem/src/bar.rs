//! The P1 bar of docs/theory.md §2.1: uniform mesh of `m` elements on `[0, L]`, node 0
//! is the contact node, node `m` is either clamped (removed from the unknowns)
//! or free.
//!
//! Element matrices: mass `ρ h/6 [2 1; 1 2]`, stiffness `c²/h [1 -1; -1 1]`.
//! The mass variants ([`BarMass`]) differ only near the contact node; every
//! variant is tridiagonal.

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
    pub const ALL: [BarMass; 8] = [
        BarMass::Std,
        BarMass::Lumped,
        BarMass::Mod,
        BarMass::Mod1,
        BarMass::Mod2,
        BarMass::Mod3,
        BarMass::Transfer,
        BarMass::Singular,
    ];

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
        BarMass::ALL
            .into_iter()
            .find(|v| v.name() == s)
            .ok_or_else(|| FemError::UnknownMass(s.to_string()))
    }
}

/// A uniform P1 bar: geometry, wave speed and boundary condition at `x = L`.
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
        Ok(Self { length, elements, wave_speed, right_end })
    }

    /// Element size `h = L/m`.
    pub fn h(&self) -> f64 {
        self.length / self.elements as f64
    }

    /// Number of unknowns: `m` (clamped) or `m + 1` (free).
    pub fn dofs(&self) -> usize {
        match self.right_end {
            RightEnd::Clamped => self.elements,
            RightEnd::Free => self.elements + 1,
        }
    }

    /// Node coordinate `x_i = i h` (`i = 0..=m`).
    pub fn node(&self, i: usize) -> f64 {
        self.length * i as f64 / self.elements as f64
    }

    /// Mass matrix on all `m + 1` nodes (before removing a clamped node).
    pub fn mass_all_nodes(&self, variant: BarMass) -> SymBand {
        let m = self.elements;
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
        let mut mm = SymBand::zeros(m + 1, 1);
        for j in 0..m {
            let w = weight(j) * h;
            if variant == BarMass::Lumped {
                mm.add(j, j, w / 2.0);
                mm.add(j + 1, j + 1, w / 2.0);
            } else {
                mm.add(j, j, w / 3.0);
                mm.add(j + 1, j + 1, w / 3.0);
                mm.add(j, j + 1, w / 6.0);
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

    /// Mass matrix on all `m + 1` nodes with a contact at each node of
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
    /// range, and any node that is not a contact node left without mass.
    pub fn mass_all_nodes_with_contacts(&self, variant: BarMass, nodes: &[usize]) -> Result<SymBand, FemError> {
        let m = self.elements;
        let refuse = |why: &'static str, node: usize| Err(FemError::MassAtContacts { mass: variant.name(), node, why });
        if let Some(&bad) = nodes.iter().find(|&&i| i > m) {
            return refuse("a contact node beyond the last node m", bad);
        }
        if nodes == [0] || !variant.massless_contact_node() {
            return Ok(self.mass_all_nodes(variant));
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
    /// [`Bar::mass_all_nodes_with_contacts`]); a clamped far end's node `m`
    /// cannot be a contact node.
    pub fn mass_with_contacts(&self, variant: BarMass, nodes: &[usize]) -> Result<SymBand, FemError> {
        if let Some(&bad) = nodes.iter().find(|&&i| i >= self.dofs()) {
            return Err(FemError::MassAtContacts { mass: variant.name(), node: bad, why: "a contact node must be an unknown (the clamped end node m is not)" });
        }
        Ok(self.restrict(self.mass_all_nodes_with_contacts(variant, nodes)?))
    }

    /// Stiffness matrix on all `m + 1` nodes.
    pub fn stiffness_all_nodes(&self) -> SymBand {
        let m = self.elements;
        let k = self.wave_speed * self.wave_speed / self.h();
        let mut kk = SymBand::zeros(m + 1, 1);
        for j in 0..m {
            kk.add(j, j, k);
            kk.add(j + 1, j + 1, k);
            kk.add(j, j + 1, -k);
        }
        kk
    }

    /// Mass matrix on the unknowns.
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
                let n = self.elements;
                let mut out = SymBand::zeros(n, 1);
                for i in 0..n {
                    for j in i.saturating_sub(1)..=i {
                        out.set(i, j, a.get(i, j));
                    }
                }
                out
            }
        }
    }

    /// Load vector `F_i = ∫ f φ_i` on the unknowns, by 3-point Gauss–Legendre
    /// quadrature per element (exact for `f` of degree <= 4).
    pub fn load(&self, f: impl Fn(f64) -> f64) -> Vec<f64> {
        const G: [(f64, f64); 3] = [
            (-0.774_596_669_241_483_4, 5.0 / 9.0),
            (0.0, 8.0 / 9.0),
            (0.774_596_669_241_483_4, 5.0 / 9.0),
        ];
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
}
