//! Observers: exact error norms and CSV time series.

use crate::{Observer, RunError, Sample};
use signorini_exact::ExactSolution;
use signorini_norms::{ErrorNorms, NormKind, NormReport, VNorm};
use std::io::Write;

/// Accumulates the error norms of docs/theory.md §6 while stepping (no history).
pub struct NormObserver<'a> {
    norms: ErrorNorms<'a>,
    dt: f64,
}

impl<'a> NormObserver<'a> {
    /// For a mesh of `elements` elements and time step `dt`.
    pub fn new(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm, dt: f64) -> Self {
        Self::with_kind(exact, elements, vnorm, dt, NormKind::Exact)
    }

    /// With a choice of error measure.
    pub fn with_kind(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm, dt: f64, kind: NormKind) -> Self {
        Self { norms: ErrorNorms::with_kind(exact, elements, vnorm, kind), dt }
    }

    /// The norms so far.
    pub fn report(&self) -> NormReport {
        self.norms.report(self.dt)
    }
}

impl Observer for NormObserver<'_> {
    fn wants_energy(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        self.norms.add_displacement(s.t, s.u);
        if let Some((t, l)) = s.lambda {
            self.norms.add_lambda(t, l);
        }
        if let Some((t, e)) = s.energy {
            self.norms.add_energy(t, e);
        }
        Ok(())
    }
}

/// Which columns a [`SeriesWriter`] writes.
#[derive(Clone, Copy)]
pub struct SeriesColumns<'a> {
    /// Name of the time column (`t`, or `t_s` with units).
    pub t: &'static str,
    /// Name of the contact-dof column (`u_contact`, or `tip_m`).
    pub u: &'static str,
    /// Name of its velocity column (`v_contact`, or `v_tip_m_s`): the
    /// backward difference `(u_c^n - u_c^{n-1})/dt` over the last step
    /// (the velocity docs/theory.md §2.1.3 reports for a massless node; for a massive
    /// one an O(dt) estimate of the scheme's own velocity). Empty at n = 0.
    pub v: &'static str,
    /// Write `energy_t,energy` (the observer then asks for energies).
    pub energy: bool,
    /// Write `u_contact_exact,lambda_exact,energy_exact` from this solution.
    pub exact: Option<&'a dyn ExactSolution>,
}

impl Default for SeriesColumns<'_> {
    /// `n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy`.
    fn default() -> Self {
        Self { t: "t", u: "u_contact", v: "v_contact", energy: true, exact: None }
    }
}

/// Writes a CSV time series of the contact dof every `every` levels:
/// `n,<t>,<u>,<v>,lambda_t,lambda`, then `energy_t,energy` and
/// `u_contact_exact,lambda_exact,energy_exact` when asked (empty cells where a
/// value does not exist at that level). Flushed every 1024 rows and at the
/// end, also when the run stops early.
pub struct SeriesWriter<'a, W: Write> {
    out: csv::Writer<W>,
    every: usize,
    contact_dof: usize,
    rows: usize,
    cols: SeriesColumns<'a>,
    /// `(t, u_c)` of the previous level, for the velocity.
    prev: Option<(f64, f64)>,
}

impl<'a, W: Write> SeriesWriter<'a, W> {
    /// The default columns, in order.
    pub const HEADER: [&'static str; 8] = ["n", "t", "u_contact", "v_contact", "lambda_t", "lambda", "energy_t", "energy"];

    /// A writer (header written at once).
    pub fn new(w: W, every: usize, contact_dof: usize, cols: SeriesColumns<'a>) -> Result<Self, RunError> {
        let mut out = csv::Writer::from_writer(w);
        let mut header = vec!["n", cols.t, cols.u, cols.v, "lambda_t", "lambda"];
        if cols.energy {
            header.extend(["energy_t", "energy"]);
        }
        if cols.exact.is_some() {
            header.extend(["u_contact_exact", "lambda_exact", "energy_exact"]);
        }
        out.write_record(&header).map_err(|e| RunError::Output(e.to_string()))?;
        Ok(Self { out, every: every.max(1), contact_dof, rows: 0, cols, prev: None })
    }
}

impl<W: Write> Observer for SeriesWriter<'_, W> {
    fn wants_energy(&self) -> bool {
        self.cols.energy
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let u = s.u[self.contact_dof];
        let v = self.prev.map(|(t0, u0)| (u - u0) / (s.t - t0));
        self.prev = Some((s.t, u));
        if s.n % self.every != 0 {
            return Ok(());
        }
        let f = |x: f64| format!("{x:.12e}");
        let o = |x: Option<f64>| x.map_or(String::new(), f);
        let mut rec = vec![s.n.to_string(), f(s.t), f(u), o(v), o(s.lambda.map(|l| l.0)), o(s.lambda.map(|l| l.1))];
        if self.cols.energy {
            rec.push(o(s.energy.map(|e| e.0)));
            rec.push(o(s.energy.map(|e| e.1)));
        }
        if let Some(ex) = self.cols.exact {
            rec.push(f(ex.fields(0.0, s.t).u));
            rec.push(o(s.lambda.map(|l| ex.lambda(l.0))));
            rec.push(f(ex.energy()));
        }
        self.out.write_record(&rec).map_err(|e| RunError::Output(e.to_string()))?;
        self.rows += 1;
        if self.rows % 1024 == 0 {
            self.out.flush().map_err(|e| RunError::Output(e.to_string()))?;
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<(), RunError> {
        self.out.flush().map_err(|e| RunError::Output(e.to_string()))
    }
}

/// One recorded level of a [`History`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    /// Level `n`.
    pub n: usize,
    /// `t_n`.
    pub t: f64,
    /// Displacement of the contact dof at `t_n`.
    pub u_contact: f64,
    /// Contact force and its time, if the step produced one.
    pub lambda: Option<(f64, f64)>,
    /// Discrete energy and its time, if computed.
    pub energy: Option<(f64, f64)>,
    /// Whether the constraint was active in the step that reached `t_n`.
    pub active: bool,
}

/// Stores the contact-dof history of a run in memory (for studies that
/// post-process it: events, phase errors, plots). Stores nothing else.
#[derive(Clone, Debug, Default)]
pub struct History {
    /// The records, one per level.
    pub records: Vec<Record>,
    contact_dof: usize,
    with_energy: bool,
}

impl History {
    /// Records the contact dof `contact_dof`, with energies if `with_energy`.
    pub fn new(contact_dof: usize, with_energy: bool) -> Self {
        Self { records: Vec::new(), contact_dof, with_energy }
    }
}

impl Observer for History {
    fn wants_energy(&self) -> bool {
        self.with_energy
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        self.records.push(Record { n: s.n, t: s.t, u_contact: s.u[self.contact_dof], lambda: s.lambda, energy: s.energy, active: s.active });
        Ok(())
    }
}
