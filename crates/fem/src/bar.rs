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
