//! Hermite-cubic Euler–Bernoulli beam (docs/theory.md §1.2, §2.2): `u_tt + k² u_xxxx = f`
//! on `(0, L)`, clamped at `x = 0` (both dofs of node 0 removed), `J`
//! elements, two dofs per node (value, slope): `2J` unknowns, banded with
//! half-bandwidth 3. Unknown `2(j-1)` is the value at node `j`, `2(j-1)+1`
//! its slope; the tip value is unknown `2J - 2`. Unit `ρS` (scaled).
//!
//! Element matrices:
//! `M_e = h/420 [156, 22h, 54, -13h; 22h, 4h², 13h, -3h²; 54, 13h, 156, -22h; -13h, -3h², -22h, 4h²]`,
//! `K_e = k²/h³ [12, 6h, -12, 6h; 6h, 4h², -6h, 2h²; -12, -6h, 12, -6h; 6h, 2h², -6h, 4h²]`.

use crate::{FemError, SymBand};

/// A uniform Hermite-cubic beam clamped at `x = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beam {
    /// Length `L` (> 0).
    pub length: f64,
    /// Number of elements `J` (>= 1).
    pub elements: usize,
    /// `k² = EI/(ρS)` (> 0).
    pub k2: f64,
}

/// Element mass matrix (unit `ρS`) on an element of size `h`.
pub fn element_mass(h: f64) -> [[f64; 4]; 4] {
    let c = h / 420.0;
    let h2 = h * h;
    [
        [156.0 * c, 22.0 * h * c, 54.0 * c, -13.0 * h * c],
        [22.0 * h * c, 4.0 * h2 * c, 13.0 * h * c, -3.0 * h2 * c],
        [54.0 * c, 13.0 * h * c, 156.0 * c, -22.0 * h * c],
        [-13.0 * h * c, -3.0 * h2 * c, -22.0 * h * c, 4.0 * h2 * c],
    ]
}

/// Element stiffness matrix on an element of size `h`.
pub fn element_stiffness(h: f64, k2: f64) -> [[f64; 4]; 4] {
    let c = k2 / (h * h * h);
    let h2 = h * h;
    [
        [12.0 * c, 6.0 * h * c, -12.0 * c, 6.0 * h * c],
        [6.0 * h * c, 4.0 * h2 * c, -6.0 * h * c, 2.0 * h2 * c],
        [-12.0 * c, -6.0 * h * c, 12.0 * c, -6.0 * h * c],
        [6.0 * h * c, 2.0 * h2 * c, -6.0 * h * c, 4.0 * h2 * c],
    ]
}

/// Hermite shape functions on `[0, h]` at local coordinate `s ∈ [0, 1]`.
pub fn hermite(s: f64, h: f64) -> [f64; 4] {
    let (s2, s3) = (s * s, s * s * s);
    [1.0 - 3.0 * s2 + 2.0 * s3, h * (s - 2.0 * s2 + s3), 3.0 * s2 - 2.0 * s3, h * (s3 - s2)]
}

impl Beam {
    /// A validated beam.
    pub fn new(length: f64, elements: usize, k2: f64) -> Result<Self, FemError> {
        if !(1..=crate::MAX_ELEMENTS).contains(&elements) {
            return Err(FemError::Invalid { field: "J", value: elements as f64, allowed: "an integer in [1, 2^40] (sizes beyond are not addressable; memory runs out long before)" });
        }
        if !(length > 0.0 && length.is_finite()) {
            return Err(FemError::Invalid { field: "length", value: length, allowed: "finite and > 0" });
        }
        if !(k2 > 0.0 && k2.is_finite()) {
            return Err(FemError::Invalid { field: "k2", value: k2, allowed: "finite and > 0" });
        }
        Ok(Self { length, elements, k2 })
    }

    /// Element size `h = L/J`.
    pub fn h(&self) -> f64 {
        self.length / self.elements as f64
    }

    /// Number of unknowns `2J`.
    pub fn dofs(&self) -> usize {
        2 * self.elements
    }

    /// The tip-value unknown `2J - 2`.
    pub fn tip_dof(&self) -> usize {
        2 * self.elements - 2
    }

    /// Global unknown of local dof `a` (0..4) of element `e`, `None` for the clamped node.
    fn global(e: usize, a: usize) -> Option<usize> {
        let node = e + a / 2;
        (node > 0).then(|| 2 * (node - 1) + a % 2)
    }

    fn assemble(&self, elem: [[f64; 4]; 4]) -> SymBand {
        let mut m = SymBand::zeros(self.dofs(), 3);
        for e in 0..self.elements {
            for a in 0..4 {
                for b in 0..=a {
                    if let (Some(i), Some(j)) = (Self::global(e, a), Self::global(e, b)) {
                        m.add(i, j, elem[a][b]);
                    }
                }
            }
        }
        m
    }

    /// Consistent mass matrix (unit `ρS`).
    pub fn mass(&self) -> SymBand {
        self.assemble(element_mass(self.h()))
    }

    /// Stiffness matrix.
    pub fn stiffness(&self) -> SymBand {
        self.assemble(element_stiffness(self.h(), self.k2))
    }

    /// Load vector `F_i = ∫ f φ_i` by 4-point Gauss–Legendre quadrature per
    /// element (exact for `f` of degree <= 4: the quartic lifting `h(x)`).
    pub fn load(&self, f: impl Fn(f64) -> f64) -> Vec<f64> {
        const G: [(f64, f64); 4] = [
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        ];
        let h = self.h();
        let mut out = vec![0.0; self.dofs()];
        for e in 0..self.elements {
            let a = e as f64 * h;
            for (xi, w) in G {
                let s = 0.5 * (xi + 1.0);
                let fx = f(a + s * h) * w * 0.5 * h;
                let phi = hermite(s, h);
                for (k, p) in phi.iter().enumerate() {
                    if let Some(i) = Self::global(e, k) {
                        out[i] += fx * p;
                    }
                }
            }
        }
        out
    }

    /// Nodal interpolation (values and slopes) of a function and its derivative.
    pub fn interpolate(&self, f: impl Fn(f64) -> f64, df: impl Fn(f64) -> f64) -> Vec<f64> {
        let h = self.h();
        (0..self.dofs())
            .map(|i| {
                let x = (i / 2 + 1) as f64 * h;
                if i % 2 == 0 {
                    f(x)
                } else {
                    df(x)
                }
            })
            .collect()
    }

    /// The classical element-by-element upper bound of `κ_h` (largest
    /// generalized eigenvalue of the element pair `(K_e, M_e)`, which bounds
    /// that of the assembled pair), computed by the same shift-free power
    /// iteration on the 4×4 pencil. Used as the shift for [`crate::max_generalized_eigenvalue`].
    pub fn element_kappa_bound(&self) -> f64 {
        let h = self.h();
        let (ke, me) = (element_stiffness(h, self.k2), element_mass(h));
        let mut a = SymBand::zeros(4, 3);
        let mut b = SymBand::zeros(4, 3);
        for i in 0..4 {
            for j in 0..=i {
                a.set(i, j, ke[i][j]);
                b.set(i, j, me[i][j]);
            }
        }
        crate::eigen::power_max(&a, &b, 2000)
    }
}
