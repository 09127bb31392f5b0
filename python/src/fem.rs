//! `signorini.fem`: the bar's and the beam's matrices in LAPACK's symmetric
//! band storage (what `scipy.linalg.eig_banded` and `solveh_banded` take),
//! and the largest generalized eigenvalue `κ_h` of the pencil.

use crate::{guarded, SceneError};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use signorini_fem::{Bar, BarMass, Beam, RightEnd, SymBand};

/// `a` in upper band storage: `ab[p + i - j, j] = a[i, j]` for `i <= j`.
fn upper_band(py: Python<'_>, a: &SymBand) -> Py<PyArray2<f64>> {
    let (n, p) = (a.n(), a.half_bandwidth());
    let mut ab = Array2::<f64>::zeros((p + 1, n));
    for j in 0..n {
        for i in j.saturating_sub(p)..=j {
            ab[[p + i - j, j]] = a.get(i, j);
        }
    }
    ab.into_pyarray(py).unbind()
}

/// `a` without the rows and columns `drop` (sorted): the pencil with those
/// dofs held fixed.
fn without(a: &SymBand, drop: &[usize]) -> SymBand {
    let keep: Vec<usize> = (0..a.n()).filter(|i| drop.binary_search(i).is_err()).collect();
    let p = a.half_bandwidth();
    let mut out = SymBand::zeros(keep.len(), p);
    for (r, &i) in keep.iter().enumerate() {
        // keep[r] - keep[c] >= r - c: every entry within the band of `a` stays within p.
        for c in r.saturating_sub(p)..=r {
            out.set(r, c, a.get(i, keep[c]));
        }
    }
    out
}

/// A discretisation's matrices (see `signorini.fem`).
#[pyclass(module = "signorini._signorini", frozen)]
pub struct Matrices {
    mass: SymBand,
    stiffness: SymBand,
    massless: Vec<usize>,
    beam: Option<Beam>,
    #[pyo3(get)]
    kind: String,
    #[pyo3(get)]
    h: f64,
    #[pyo3(get)]
    x: Vec<f64>,
}

#[pymethods]
impl Matrices {
    /// The mass matrix in upper band storage, shape `(p + 1, n)`.
    #[getter]
    fn mass_band(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        upper_band(py, &self.mass)
    }
    /// The stiffness matrix in upper band storage, shape `(p + 1, n)`.
    #[getter]
    fn stiffness_band(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        upper_band(py, &self.stiffness)
    }
    /// The half-bandwidth `p`.
    #[getter]
    fn half_bandwidth(&self) -> usize {
        self.mass.half_bandwidth().max(self.stiffness.half_bandwidth())
    }
    /// The number of unknowns `n`.
    #[getter]
    fn n(&self) -> usize {
        self.mass.n()
    }
    /// The unknowns that carry no mass (zero row of M), in order.
    #[getter]
    fn massless(&self) -> Vec<usize> {
        self.massless.clone()
    }
    /// `κ_h`: the largest generalized eigenvalue of `(K, M)` — with the
    /// massless unknowns held fixed (their rows and columns removed), the
    /// pencil whose `2/sqrt(κ_h)` is the central-difference limit.
    fn kappa_h(&self, py: Python<'_>) -> PyResult<f64> {
        let (k, m) = (without(&self.stiffness, &self.massless), without(&self.mass, &self.massless));
        let beam = self.beam;
        py.detach(|| {
            guarded(|| {
                let r = match beam {
                    // The element bound is strictly above κ_h of the assembled beam.
                    Some(b) => signorini_fem::max_generalized_eigenvalue(&k, &m, b.element_kappa_bound() * (1.0 + 1e-3), 1_000_000).map(|r| r.0),
                    None => signorini_fem::max_generalized_eigenvalue_auto(&k, &m),
                };
                r.map_err(|e| SceneError::new_err(format!("kappa_h: {e}")))
            })
        })
    }
}

fn count(name: &str, v: i64, lo: i64) -> PyResult<usize> {
    // 2^26 elements: the band storage of M, K and a factor is < 4 GB.
    const MAX: i64 = 1 << 26;
    if v < lo || v > MAX {
        return Err(SceneError::new_err(format!("{name}: {v} is out of range: an integer in [{lo}, {MAX}]")));
    }
    Ok(v as usize)
}

fn positive(name: &str, v: f64) -> PyResult<f64> {
    if !(v > 0.0 && v.is_finite()) {
        return Err(SceneError::new_err(format!("{name}: {v} is out of range: finite and > 0")));
    }
    Ok(v)
}

fn massless_of(m: &SymBand) -> Vec<usize> {
    (0..m.n()).filter(|&i| m.get(i, i) == 0.0).collect()
}

/// The P1 bar's matrices (see `signorini.fem.bar`).
#[pyfunction]
#[pyo3(signature = (elements, mass="std", length=1.0, wave_speed=1.0, right_end="clamped", contacts=None, degree=1))]
#[allow(clippy::too_many_arguments)]
pub fn bar_matrices(elements: i64, mass: &str, length: f64, wave_speed: f64, right_end: &str, contacts: Option<Vec<i64>>, degree: i64) -> PyResult<Matrices> {
    let m = count("elements", elements, 2)?;
    let variant: BarMass = mass.parse().map_err(|e| SceneError::new_err(format!("mass: {e}")))?;
    let end = match right_end {
        "clamped" => RightEnd::Clamped,
        "free" => RightEnd::Free,
        other => return Err(SceneError::new_err(format!("right_end: {other:?} is not one of clamped, free"))),
    };
    if !(1..=3).contains(&degree) {
        return Err(SceneError::new_err(format!("degree: {degree} is out of range: 1, 2 or 3 (Lagrange P1, P2, P3)")));
    }
    let bar = Bar::new(positive("length", length)?, m, positive("wave_speed", wave_speed)?, end).and_then(|b| b.with_degree(degree as usize)).map_err(|e| SceneError::new_err(e.to_string()))?;
    bar.check_mass(variant).map_err(|e| SceneError::new_err(format!("mass: {e}")))?;
    let nodes = contacts.unwrap_or_else(|| vec![0]);
    let mut ns = Vec::with_capacity(nodes.len());
    for (k, &c) in nodes.iter().enumerate() {
        if c < 0 || c as usize >= bar.dofs() {
            return Err(SceneError::new_err(format!("contacts[{k}]: node {c} is out of range: a node in [0, {}] (an unknown)", bar.dofs() - 1)));
        }
        ns.push(c as usize);
    }
    let mass_m = guarded(|| bar.mass_with_contacts(variant, &ns).map_err(|e| SceneError::new_err(format!("mass: {e}"))))?;
    Ok(Matrices {
        massless: massless_of(&mass_m),
        mass: mass_m,
        stiffness: bar.stiffness(),
        beam: None,
        kind: format!("bar, {m} P{degree} elements, mass {variant}"),
        h: bar.h(),
        x: (0..bar.dofs()).map(|i| bar.node(i)).collect(),
    })
}

/// The clamped Hermite beam's matrices (see `signorini.fem.beam`).
#[pyfunction]
#[pyo3(signature = (elements, length=1.0, k2=1.0))]
pub fn beam_matrices(elements: i64, length: f64, k2: f64) -> PyResult<Matrices> {
    let j = count("elements", elements, 1)?;
    let beam = Beam::new(positive("length", length)?, j, positive("k2", k2)?).map_err(|e| SceneError::new_err(e.to_string()))?;
    let mass = beam.mass();
    Ok(Matrices {
        massless: massless_of(&mass),
        mass,
        stiffness: beam.stiffness(),
        beam: Some(beam),
        kind: format!("beam, {j} Hermite elements"),
        h: beam.h(),
        // Unknown 2(j-1) is node j's value, 2(j-1)+1 its slope: both at x_j.
        x: (0..2 * j).map(|k| (k / 2 + 1) as f64 * beam.h()).collect(),
    })
}
