//! Observers: exact error norms and CSV time series.

use crate::{Observer, RunError, Sample};
use signorini_exact::ExactSolution;
use signorini_norms::{ErrorNorms, NormKind, NormReport, VNorm};
use std::io::Write;

/// Accumulates the error norms of docs/theory.md §6 while stepping (no history).
pub struct NormObserver<'a> {
    norms: ErrorNorms<'a>,
    dt: f64,
    /// The contact was active at the last sample.
    active: bool,
    /// The first level at which the contact is inactive after being active.
    first_release: Option<f64>,
}

impl<'a> NormObserver<'a> {
    /// For a mesh of `elements` elements and time step `dt`.
    pub fn new(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm, dt: f64) -> Self {
        Self::with_kind(exact, elements, vnorm, dt, NormKind::Exact)
    }

    /// With a choice of error measure.
    pub fn with_kind(exact: &'a dyn ExactSolution, elements: usize, vnorm: VNorm, dt: f64, kind: NormKind) -> Self {
        Self { norms: ErrorNorms::with_kind(exact, elements, vnorm, kind), dt, active: false, first_release: None }
    }

    /// For Lagrange elements of degree `k` ([`ErrorNorms::with_degree`]: the
    /// GetFEM-demo norms are P1 only, so `kind` must be exact for `k > 1`).
    #[track_caller]
    pub fn with_degree(exact: &'a dyn ExactSolution, elements: usize, k: usize, vnorm: VNorm, dt: f64, kind: NormKind) -> Self {
        Self { norms: ErrorNorms::with_degree(exact, elements, k, vnorm, kind), dt, active: false, first_release: None }
    }

    /// The norms so far.
    pub fn report(&self) -> NormReport {
        self.norms.report(self.dt)
    }

    /// The time of the first level at which the contact is inactive after
    /// having been active (the discrete release), if there was one.
    pub fn first_release(&self) -> Option<f64> {
        self.first_release
    }
}

impl Observer for NormObserver<'_> {
    fn wants_energy(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        if self.active && !s.active && self.first_release.is_none() {
            self.first_release = Some(s.t);
        }
        self.active = s.active;
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
    /// Append, for the contacts at these dofs (in contact order, the
    /// order of [`Sample::forces`]), `u_c<i>,lambda_<i>,active_<i>`: the
    /// dof's displacement, the contact's force (at `lambda_t`) and which
    /// bound holds it (`-1` lower, `1` upper, `0` none; see [`active_code`]). `lambda_<i>` and
    /// `active_<i>` are empty where `lambda` is (the start levels).
    pub contacts: Option<&'a [usize]>,
}

impl Default for SeriesColumns<'_> {
    /// `n,t,u_contact,v_contact,lambda_t,lambda,energy_t,energy`.
    fn default() -> Self {
        Self { t: "t", u: "u_contact", v: "v_contact", energy: true, exact: None, contacts: None }
    }
}

/// A CSV sink that hands its writer **whole rows only**: rows are formatted
/// into a reused buffer (no allocation once it has grown) and passed on with
/// one `write_all` when it holds 64 KiB or 1024 rows, and at
/// [`flush`](Self::flush). On a file opened without buffering each hand-over
/// is one `write` call ending at a row boundary, so a run stopped by a
/// signal it handles (SIGINT/SIGTERM: the CLI flushes) leaves only complete
/// rows. A SIGKILL (or a full disk) can still cut the `write` in flight:
/// then every newline-terminated line is a complete row and only the last
/// line can be partial — a reader drops a last line without `\n`.
pub struct RowSink<W: Write> {
    out: W,
    buf: Vec<u8>,
    pending: usize,
}

impl<W: Write> RowSink<W> {
    const BYTES: usize = 64 * 1024;
    const ROWS: usize = 1024;

    /// A sink writing to `out`.
    pub fn new(out: W) -> Self {
        Self { out, buf: Vec::with_capacity(Self::BYTES + 1024), pending: 0 }
    }

    /// Appends one row: `fill` writes its fields (comma-separated, without
    /// the final newline) into the buffer.
    pub fn row(&mut self, fill: impl FnOnce(&mut Vec<u8>) -> std::io::Result<()>) -> Result<(), RunError> {
        let mark = self.buf.len();
        if let Err(e) = fill(&mut self.buf) {
            self.buf.truncate(mark);
            return Err(RunError::Output(e));
        }
        self.buf.push(b'\n');
        self.pending += 1;
        if self.buf.len() >= Self::BYTES || self.pending >= Self::ROWS {
            self.hand_over()?;
        }
        Ok(())
    }

    fn hand_over(&mut self) -> Result<(), RunError> {
        if !self.buf.is_empty() {
            self.out.write_all(&self.buf).map_err(RunError::Output)?;
            self.buf.clear();
        }
        self.pending = 0;
        Ok(())
    }

    /// Hands over the rows held and flushes the writer.
    pub fn flush(&mut self) -> Result<(), RunError> {
        self.hand_over()?;
        self.out.flush().map_err(RunError::Output)
    }
}

/// Writes `x` as `{:.12e}`, or nothing for `None` (an empty cell).
fn cell(buf: &mut Vec<u8>, x: Option<f64>) -> std::io::Result<()> {
    buf.push(b',');
    match x {
        Some(x) => write!(buf, "{x:.12e}"),
        None => Ok(()),
    }
}

/// The `active_<i>` code of a contact status: `-1` at the lower bound,
/// `1` at the upper bound, `0` free. The contact force `λ` (the stress,
/// entering the equations as `−λ e_c`) is `<= 0` at a lower bound and
/// `>= 0` at an upper one: a nonzero `λ_i` has the sign of `active_i`.
pub fn active_code(a: signorini_contact::Active) -> i8 {
    match a {
        signorini_contact::Active::Lower => -1,
        signorini_contact::Active::Upper => 1,
        signorini_contact::Active::None => 0,
    }
}

/// Writes a CSV time series of the contact dof every `every` levels:
/// `n,<t>,<u>,<v>,lambda_t,lambda`, then `energy_t,energy` and
/// `u_contact_exact,lambda_exact,energy_exact` when asked, then
/// `u_c<i>,lambda_<i>,active_<i>` for every contact when asked (see
/// [`SeriesColumns::contacts`]; empty cells where a value does not exist
/// at that level). Rows go out whole through a
/// [`RowSink`] (every 64 KiB or 1024 rows, and at the end, also when the run
/// stops early); no allocation per row.
pub struct SeriesWriter<'a, W: Write> {
    out: RowSink<W>,
    every: usize,
    contact_dof: usize,
    cols: SeriesColumns<'a>,
    /// `(t, u_c)` of the previous level, for the velocity.
    prev: Option<(f64, f64)>,
}

impl<'a, W: Write> SeriesWriter<'a, W> {
    /// The default columns, in order.
    pub const HEADER: [&'static str; 8] = ["n", "t", "u_contact", "v_contact", "lambda_t", "lambda", "energy_t", "energy"];

    /// A writer (header written at once).
    pub fn new(w: W, every: usize, contact_dof: usize, cols: SeriesColumns<'a>) -> Result<Self, RunError> {
        let mut header: Vec<String> = ["n", cols.t, cols.u, cols.v, "lambda_t", "lambda"].map(String::from).to_vec();
        if cols.energy {
            header.extend(["energy_t", "energy"].map(String::from));
        }
        if cols.exact.is_some() {
            header.extend(["u_contact_exact", "lambda_exact", "energy_exact"].map(String::from));
        }
        for i in 0..cols.contacts.map_or(0, <[usize]>::len) {
            header.extend([format!("u_c{i}"), format!("lambda_{i}"), format!("active_{i}")]);
        }
        let mut out = RowSink::new(w);
        out.row(|b| b.write_all(header.join(",").as_bytes()))?;
        out.flush()?;
        Ok(Self { out, every: every.max(1), contact_dof, cols, prev: None })
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
        let cols = self.cols;
        self.out.row(|b| {
            write!(b, "{}", s.n)?;
            cell(b, Some(s.t))?;
            cell(b, Some(u))?;
            cell(b, v)?;
            cell(b, s.lambda.map(|l| l.0))?;
            cell(b, s.lambda.map(|l| l.1))?;
            if cols.energy {
                cell(b, s.energy.map(|e| e.0))?;
                cell(b, s.energy.map(|e| e.1))?;
            }
            if let Some(ex) = cols.exact {
                cell(b, Some(ex.fields(0.0, s.t).u))?;
                cell(b, s.lambda.map(|l| ex.lambda(l.0)))?;
                cell(b, Some(ex.energy()))?;
            }
            if let Some(dofs) = cols.contacts {
                for (i, &d) in dofs.iter().enumerate() {
                    cell(b, s.u.get(d).copied())?;
                    let stepped = s.lambda.is_some();
                    cell(b, s.forces.get(i).copied().filter(|_| stepped))?;
                    match s.status.get(i).filter(|_| stepped) {
                        Some(a) => write!(b, ",{}", active_code(*a))?,
                        None => b.push(b','),
                    }
                }
            }
            Ok(())
        })
    }
    fn finish(&mut self) -> Result<(), RunError> {
        self.out.flush()
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

/// `events.csv` of an event-driven run: `t,kind,contact,velocity_before,velocity_after,impulse`,
/// one row per event in the order taken (`kind`: `impact`, `release`,
/// `accumulation`; `contact`: the index of the stop; the velocities are the
/// contact dof's; the impulse is the contact force's, positive at a lower
/// bound), numbers with 17 significant digits (they round-trip).
pub fn write_events<W: Write>(mut w: W, events: &[signorini_schemes::events::EventRecord]) -> std::io::Result<()> {
    writeln!(w, "t,kind,contact,velocity_before,velocity_after,impulse")?;
    for e in events {
        writeln!(w, "{:.16e},{},{},{:.16e},{:.16e},{:.16e}", e.t, e.kind.name(), e.contact, e.velocity_before, e.velocity_after, e.impulse)?;
    }
    w.flush()
}
