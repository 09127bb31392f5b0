//! `run_lockstep` keeps `run`'s sample contract lane by lane: `L` beam runs
//! stepped in lockstep and the same runs one at a time with `run` (the
//! reference, with the single `PaoliSchatzman` stepper) feed their
//! observers the same samples — every field of every sample at every
//! level, bit for bit — and end alike (summary, error, level reached),
//! for lanes with different forcing and horizons, a lane that blows up, a
//! lane whose observer cancels its token, a lane whose observer fails, and
//! a partial batch — with the Paoli–Schatzman engine (level 1 after its
//! start step), the Moreau–Jean one (a one-step scheme: level 0), the
//! contact-stabilized one, the CD-Lagrange one, Schindler and Acary's
//! (both levels) and Moreau–Jean with the combined projection; for the
//! last two also the rows a `SeriesWriter` writes every 7 levels. The
//! one documented difference: the engine does not track the works, so a
//! lockstep sample's `work` is `None`.

use signorini_run::beam::Pipe;
use signorini_run::reduced::Need;
use signorini_run::{run, run_lockstep, Cancel, LockstepRun, Observer, RunConfig, RunError, RunSummary, Sample, SeriesColumns, SeriesWriter};
use signorini_schemes::{CdLagrange, ContactStabilized, D1Level, D1MinusLinear, LockstepBatch, LockstepLane, LockstepScheme, MoreauJean, MoreauJeanCombined, PaoliSchatzman, Stepper};

const DT: f64 = 5e-6;

/// Every field of a sample, as bits.
#[derive(Debug, PartialEq)]
struct Rec {
    n: usize,
    t: u64,
    u: Vec<u64>,
    lambda: Option<(u64, u64)>,
    energy: Option<(u64, u64)>,
    active: bool,
    forces: Vec<u64>,
    status: Vec<signorini_contact::Active>,
}

/// What a lane does besides recording.
#[derive(Clone, Copy, Debug)]
enum Twist {
    None,
    /// Cancels the run's token when it sees this level.
    CancelAt(usize),
    /// Fails when it sees this level.
    FailAt(usize),
}

struct Recorder {
    recs: Vec<Rec>,
    works: Vec<Option<(f64, f64)>>,
    finished: usize,
    twist: Twist,
    cancel: Cancel,
}

impl Observer for Recorder {
    fn observe(&mut self, s: &Sample<'_>) -> Result<(), RunError> {
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let pair = |p: Option<(f64, f64)>| p.map(|(a, b)| (a.to_bits(), b.to_bits()));
        self.recs.push(Rec { n: s.n, t: s.t.to_bits(), u: bits(s.u), lambda: pair(s.lambda), energy: pair(s.energy), active: s.active, forces: bits(s.forces), status: s.status.to_vec() });
        self.works.push(s.work);
        match self.twist {
            Twist::CancelAt(n) if s.n == n => self.cancel.cancel(),
            Twist::FailAt(n) if s.n == n => return Err(RunError::NotAllowed { field: "test", allowed: "a planted observer failure" }),
            _ => {}
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<(), RunError> {
        self.finished += 1;
        Ok(())
    }
}

/// Lane `k`: the paper's beam (J = 19) with its support motion scaled.
fn lane(amplitude: f64, omega: f64) -> LockstepLane {
    let p = Pipe::paper();
    let (_, dynamics, initial) = Pipe { support: (amplitude, omega), ..p }.dynamics(19).unwrap();
    LockstepLane { dynamics, initial, restitution: 0.0 }
}

/// What a run gave: its samples, works, finish count, and its end
/// (summary without the wall time, or the error's text) and level.
type Outcome = (Vec<Rec>, Vec<Option<(f64, f64)>>, usize, Result<(usize, u64, usize, bool), String>, usize);

fn summary(r: Result<RunSummary, RunError>) -> Result<(usize, u64, usize, bool), String> {
    r.map(|s| (s.steps, s.t_end.to_bits(), s.contact_steps, s.energy.is_some())).map_err(|e| e.to_string())
}

/// The scheme of a test: `ps(e, 1/2)` or `moreau-jean(1/2, e, 1/2)`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scheme {
    Ps,
    Mj,
    /// `contact-stabilized` (no restitution).
    Cs,
    /// `cd-lagrange(e)` (explicit: DT is below its limit on J = 19).
    Cd,
    /// `d1-minus-linear(e)` on a level (explicit: DT is below its limit).
    D1(D1Level),
    /// `moreau-jean-combined(1, e)`.
    Mjc,
}

impl Scheme {
    /// The batch's scheme (the restitution is each lane's).
    fn lockstep(self) -> LockstepScheme {
        match self {
            Scheme::Ps => LockstepScheme::PaoliSchatzman { beta: 0.5, restitution: 0.0 },
            Scheme::Mj => LockstepScheme::MoreauJean { theta: 0.5, restitution: 0.0, gamma: 0.5 },
            Scheme::Cs => LockstepScheme::ContactStabilized,
            Scheme::Cd => LockstepScheme::CdLagrange { restitution: 0.0 },
            Scheme::D1(level) => LockstepScheme::D1MinusLinear { level, restitution: 0.0 },
            Scheme::Mjc => LockstepScheme::MoreauJeanCombined { theta: 1.0, restitution: 0.0 },
        }
    }

    /// The batch of `width` lanes on `lanes` (the one non-generic entry:
    /// this crate compiles no engine).
    fn batch(self, width: usize, lanes: &[LockstepLane]) -> LockstepBatch {
        LockstepBatch::with_width(self.lockstep(), width, DT, lanes.to_vec()).unwrap()
    }
}

fn single(l: &LockstepLane, steps: usize, twist: Twist) -> Outcome {
    single_of(Scheme::Ps, l, steps, twist)
}

fn single_of(scheme: Scheme, l: &LockstepLane, steps: usize, twist: Twist) -> Outcome {
    let mut s: Box<dyn Stepper> = match scheme {
        Scheme::Ps => Box::new(PaoliSchatzman::new("single".into(), l.dynamics.clone(), 0.5, l.restitution, DT, &l.initial).unwrap()),
        Scheme::Mj => Box::new(MoreauJean::new("single".into(), l.dynamics.clone(), 0.5, l.restitution, 0.5, DT, &l.initial).unwrap()),
        Scheme::Cs => Box::new(ContactStabilized::new("single".into(), l.dynamics.clone(), DT, &l.initial).unwrap()),
        Scheme::Cd => Box::new(CdLagrange::new("single".into(), l.dynamics.clone(), l.restitution, DT, &l.initial).unwrap()),
        Scheme::D1(level) => Box::new(D1MinusLinear::at_level(level, "single".into(), l.dynamics.clone(), l.restitution, DT, &l.initial).unwrap()),
        Scheme::Mjc => Box::new(MoreauJeanCombined::new("single".into(), l.dynamics.clone(), 1.0, l.restitution, DT, &l.initial).unwrap()),
    };
    let cancel = Cancel::new();
    let cfg = RunConfig::new(DT, steps as f64 * DT).unwrap().with_interrupt(cancel.clone());
    let mut rec = Recorder { recs: Vec::new(), works: Vec::new(), finished: 0, twist, cancel };
    let r = run(s.as_mut(), &l.initial.u, &cfg, &mut [&mut rec]);
    (rec.recs, rec.works, rec.finished, summary(r), s.level())
}

fn lockstep(width: usize, lanes: &[LockstepLane], steps: &[usize], twists: &[Twist], need: &Need) -> Vec<Outcome> {
    lockstep_of(Scheme::Ps, width, lanes, steps, twists, need)
}

fn lockstep_of(scheme: Scheme, width: usize, lanes: &[LockstepLane], steps: &[usize], twists: &[Twist], need: &Need) -> Vec<Outcome> {
    let mut eng = scheme.batch(width, lanes);
    let cancels: Vec<Cancel> = lanes.iter().map(|_| Cancel::new()).collect();
    let cfgs: Vec<RunConfig> = steps.iter().zip(&cancels).map(|(&n, c)| RunConfig::new(DT, n as f64 * DT).unwrap().with_interrupt(c.clone())).collect();
    let mut recs: Vec<Recorder> = twists.iter().zip(&cancels).map(|(&twist, c)| Recorder { recs: Vec::new(), works: Vec::new(), finished: 0, twist, cancel: c.clone() }).collect();
    let ends = {
        let mut runs: Vec<LockstepRun<'_>> = recs.iter_mut().zip(&cfgs).zip(lanes).map(|((r, c), l)| LockstepRun::new(&l.initial.u, c, vec![r as &mut dyn Observer])).collect();
        run_lockstep(&mut eng, &mut runs, need).unwrap()
    };
    recs.into_iter().zip(ends).map(|(r, e)| (r.recs, r.works, r.finished, summary(e.result), e.level)).collect()
}

fn check(lanes: &[LockstepLane], steps: &[usize], twists: &[Twist], got: Vec<Outcome>) {
    check_of(Scheme::Ps, lanes, steps, twists, got)
}

fn check_of(scheme: Scheme, lanes: &[LockstepLane], steps: &[usize], twists: &[Twist], got: Vec<Outcome>) {
    assert_eq!(got.len(), lanes.len());
    for (k, (l, g)) in lanes.iter().zip(got).enumerate() {
        let want = single_of(scheme, l, steps[k], twists[k]);
        assert!(want.0.len() >= 2, "lane {k}: the reference recorded levels 0 and 1 at least");
        assert_eq!(g.0.len(), want.0.len(), "lane {k}: number of samples");
        for (a, b) in g.0.iter().zip(&want.0) {
            assert_eq!(a, b, "lane {k}: sample at level {}", b.n);
        }
        // The documented difference: no works from the engine; the single
        // run has them from level 1 on.
        assert!(g.1.iter().all(Option::is_none), "lane {k}: lockstep works");
        if scheme == Scheme::Ps {
            assert!(want.1[1..].iter().all(Option::is_some), "lane {k}: the single run's works");
        }
        assert_eq!((g.2, &g.3, g.4), (want.2, &want.3, want.4), "lane {k}: finish count, end, level");
    }
}

#[test]
fn lockstep_lanes_feed_their_observers_the_single_runs_samples() {
    // Different frequencies and amplitudes, horizons on and off the
    // 64-step checks; one lane cancelled by its observer, one that fails.
    let lanes: Vec<LockstepLane> = (0..4).map(|k| lane(0.2 + 0.05 * k as f64, 10.0 + 3.0 * k as f64)).collect();
    let steps = [700, 640, 1000, 333];
    let twists = [Twist::None, Twist::CancelAt(129), Twist::None, Twist::FailAt(200)];
    let got = lockstep(4, &lanes, &steps, &twists, &Need::Full);
    assert!(got[1].3.as_ref().is_err_and(|e| e.contains("interrupted at step 129")), "{:?}", got[1].3);
    assert!(got[3].3.as_ref().is_err_and(|e| e.contains("planted")), "{:?}", got[3].3);
    assert_eq!(got[2].3.as_ref().map(|s| s.0), Ok(1000));
    check(&lanes, &steps, &twists, got);
}

#[test]
fn a_lane_that_blows_up_stops_where_its_single_run_does_in_a_partial_batch() {
    // Five lanes on an engine of eight; lanes 1 and 3 blow up.
    let lanes: Vec<LockstepLane> = [0.2, 1e303, 0.3, 4e303, 0.25].iter().map(|&a| lane(a, 12.0)).collect();
    let steps = [500; 5];
    let twists = [Twist::None; 5];
    let got = lockstep(8, &lanes, &steps, &twists, &Need::Full);
    for k in [1, 3] {
        assert!(got[k].3.as_ref().is_err_and(|e| e.contains("blew up")), "lane {k}: {:?}", got[k].3);
        assert!(got[k].4 < 500, "lane {k} stopped early");
    }
    check(&lanes, &steps, &twists, got);
}

#[test]
fn with_a_few_dofs_needed_those_dofs_are_the_single_runs() {
    let lanes: Vec<LockstepLane> = (0..2).map(|k| lane(0.2, 10.0 + k as f64)).collect();
    let steps = [300, 300];
    let twists = [Twist::None; 2];
    let tip = lanes[0].dynamics.contacts[0].dof;
    let got = lockstep(2, &lanes, &steps, &twists, &Need::Dofs(vec![tip]));
    for (l, g) in lanes.iter().zip(got) {
        let want = single(l, 300, Twist::None);
        assert_eq!(g.0.len(), want.0.len());
        for (a, b) in g.0.iter().zip(&want.0) {
            assert_eq!((a.n, a.t, a.u[tip], a.lambda, a.active), (b.n, b.t, b.u[tip], b.lambda, b.active));
        }
        assert_eq!(g.3, want.3);
    }
}

#[test]
fn observers_that_want_the_energy_are_refused() {
    struct Wants;
    impl Observer for Wants {
        fn wants_energy(&self) -> bool {
            true
        }
        fn observe(&mut self, _: &Sample<'_>) -> Result<(), RunError> {
            Ok(())
        }
    }
    let l = lane(0.2, 10.0);
    let mut eng = Scheme::Ps.batch(2, std::slice::from_ref(&l));
    let cfg = RunConfig::new(DT, 100.0 * DT).unwrap();
    let mut w = Wants;
    let mut runs = vec![LockstepRun::new(&l.initial.u, &cfg, vec![&mut w as &mut dyn Observer])];
    assert!(matches!(run_lockstep(&mut eng, &mut runs, &Need::Full), Err(RunError::NotAllowed { field: "energy", .. })));
}

#[test]
fn lanes_with_different_numbers_of_observers_each_feed_their_own_and_get_them_back() {
    // Lane 0 has two observers, lane 1 none, lane 2 one, lane 3 two: each
    // observer sees its own lane's single run, and every lane's list is
    // given back, in order, when the batch ends.
    let lanes: Vec<LockstepLane> = (0..4).map(|k| lane(0.2 + 0.05 * k as f64, 10.0 + 3.0 * k as f64)).collect();
    let steps = [300, 200, 257, 130];
    let counts = [2, 0, 1, 2];
    let mut eng = Scheme::Ps.batch(4, &lanes);
    let cfgs: Vec<RunConfig> = steps.iter().map(|&n| RunConfig::new(DT, n as f64 * DT).unwrap()).collect();
    let mut recs: Vec<Vec<Recorder>> =
        counts.iter().map(|&c| (0..c).map(|_| Recorder { recs: Vec::new(), works: Vec::new(), finished: 0, twist: Twist::None, cancel: Cancel::new() }).collect()).collect();
    {
        let mut runs: Vec<LockstepRun<'_>> =
            recs.iter_mut().zip(&cfgs).zip(&lanes).map(|((r, c), l)| LockstepRun::new(&l.initial.u, c, r.iter_mut().map(|r| r as &mut dyn Observer).collect())).collect();
        let ends = run_lockstep(&mut eng, &mut runs, &Need::Full).unwrap();
        for (k, (run, end)) in runs.iter().zip(&ends).enumerate() {
            assert_eq!(run.observers.len(), counts[k], "lane {k}: observers given back");
            assert_eq!(end.level, steps[k], "lane {k}: level");
        }
    }
    for (k, rs) in recs.iter().enumerate() {
        let want = single(&lanes[k], steps[k], Twist::None);
        for (j, r) in rs.iter().enumerate() {
            assert_eq!(r.recs, want.0, "lane {k}, observer {j}: samples");
            assert_eq!(r.finished, 1, "lane {k}, observer {j}: finished once");
        }
    }
}

/// The Moreau–Jean engine (level 0 after construction: no start step) in
/// `run_lockstep`: lanes with different forcing and horizons, one cancelled
/// by its observer, one whose observer fails, two that blow up in a
/// partial batch — each lane's samples and end are its single run's.
#[test]
fn moreau_jean_lanes_feed_their_observers_the_single_runs_samples() {
    let lanes: Vec<LockstepLane> = (0..4).map(|k| lane(0.2 + 0.05 * k as f64, 10.0 + 3.0 * k as f64)).collect();
    let steps = [700, 640, 1000, 333];
    let twists = [Twist::None, Twist::CancelAt(129), Twist::None, Twist::FailAt(200)];
    let got = lockstep_of(Scheme::Mj, 4, &lanes, &steps, &twists, &Need::Full);
    assert!(got[1].3.as_ref().is_err_and(|e| e.contains("interrupted at step 129")), "{:?}", got[1].3);
    assert!(got[3].3.as_ref().is_err_and(|e| e.contains("planted")), "{:?}", got[3].3);
    assert_eq!(got[2].3.as_ref().map(|s| s.0), Ok(1000));
    assert!(got.iter().all(|g| g.0[0].n == 0 && g.0[1].n == 1 && g.0[1].lambda.is_some()), "level 1 is a step's sample");
    check_of(Scheme::Mj, &lanes, &steps, &twists, got);
    let lanes: Vec<LockstepLane> = [0.2, 1e303, 0.3, 4e303, 0.25].iter().map(|&a| lane(a, 12.0)).collect();
    let got = lockstep_of(Scheme::Mj, 8, &lanes, &[500; 5], &[Twist::None; 5], &Need::Full);
    for k in [1, 3] {
        assert!(got[k].3.as_ref().is_err_and(|e| e.contains("blew up")), "lane {k}: {:?}", got[k].3);
        assert!(got[k].4 < 500, "lane {k} stopped early");
    }
    check_of(Scheme::Mj, &lanes, &[500; 5], &[Twist::None; 5], got);
}

/// The contact-stabilized engine (level 0 after construction) in
/// `run_lockstep`: as the Moreau–Jean one above — lanes with different
/// forcing and horizons, one cancelled by its observer, one whose observer
/// fails, two that blow up in a partial batch.
#[test]
fn contact_stabilized_lanes_feed_their_observers_the_single_runs_samples() {
    let lanes: Vec<LockstepLane> = (0..4).map(|k| lane(0.2 + 0.05 * k as f64, 10.0 + 3.0 * k as f64)).collect();
    let steps = [700, 640, 1000, 333];
    let twists = [Twist::None, Twist::CancelAt(129), Twist::None, Twist::FailAt(200)];
    let got = lockstep_of(Scheme::Cs, 4, &lanes, &steps, &twists, &Need::Full);
    assert!(got[1].3.as_ref().is_err_and(|e| e.contains("interrupted at step 129")), "{:?}", got[1].3);
    assert!(got[3].3.as_ref().is_err_and(|e| e.contains("planted")), "{:?}", got[3].3);
    assert_eq!(got[2].3.as_ref().map(|s| s.0), Ok(1000));
    assert!(got.iter().all(|g| g.0[0].n == 0 && g.0[1].n == 1 && g.0[1].lambda.is_some()), "level 1 is a step's sample");
    check_of(Scheme::Cs, &lanes, &steps, &twists, got);
    let lanes: Vec<LockstepLane> = [0.2, 1e303, 0.3, 4e303, 0.25].iter().map(|&a| lane(a, 12.0)).collect();
    let got = lockstep_of(Scheme::Cs, 8, &lanes, &[500; 5], &[Twist::None; 5], &Need::Full);
    for k in [1, 3] {
        assert!(got[k].3.as_ref().is_err_and(|e| e.contains("blew up")), "lane {k}: {:?}", got[k].3);
        assert!(got[k].4 < 500, "lane {k} stopped early");
    }
    check_of(Scheme::Cs, &lanes, &[500; 5], &[Twist::None; 5], got);
}

/// The CD-Lagrange engine (level 0 after construction; its first step the
/// start's half step) in `run_lockstep`: as the Moreau–Jean one above —
/// lanes with different forcing, restitutions and horizons, one cancelled
/// by its observer, one whose observer fails, two that blow up in a
/// partial batch.
#[test]
fn cd_lagrange_lanes_feed_their_observers_the_single_runs_samples() {
    let lanes: Vec<LockstepLane> = (0..4).map(|k| LockstepLane { restitution: 0.25 * k as f64, ..lane(0.2 + 0.05 * k as f64, 10.0 + 3.0 * k as f64) }).collect();
    let steps = [700, 640, 1000, 333];
    let twists = [Twist::None, Twist::CancelAt(129), Twist::None, Twist::FailAt(200)];
    let got = lockstep_of(Scheme::Cd, 4, &lanes, &steps, &twists, &Need::Full);
    assert!(got[1].3.as_ref().is_err_and(|e| e.contains("interrupted at step 129")), "{:?}", got[1].3);
    assert!(got[3].3.as_ref().is_err_and(|e| e.contains("planted")), "{:?}", got[3].3);
    assert_eq!(got[2].3.as_ref().map(|s| s.0), Ok(1000));
    assert!(got.iter().all(|g| g.0[0].n == 0 && g.0[1].n == 1 && g.0[1].lambda.is_some()), "level 1 is a step's sample");
    check_of(Scheme::Cd, &lanes, &steps, &twists, got);
    let lanes: Vec<LockstepLane> = [0.2, 1e303, 0.3, 4e303, 0.25].iter().map(|&a| lane(a, 12.0)).collect();
    let got = lockstep_of(Scheme::Cd, 8, &lanes, &[500; 5], &[Twist::None; 5], &Need::Full);
    for k in [1, 3] {
        assert!(got[k].3.as_ref().is_err_and(|e| e.contains("blew up")), "lane {k}: {:?}", got[k].3);
        assert!(got[k].4 < 500, "lane {k} stopped early");
    }
    check_of(Scheme::Cd, &lanes, &[500; 5], &[Twist::None; 5], got);
}

/// The lanes of the engines below: the paper's beam at four forcings and
/// restitutions, on stops at ±2e-4, which the tip reaches within the
/// first 200 steps (so contacts and their forces appear in the samples).
fn rattling_lanes() -> Vec<LockstepLane> {
    (0..4)
        .map(|k| {
            let mut l = lane(0.2 + 0.05 * k as f64, 10.0 + 3.0 * k as f64);
            l.dynamics.contacts[0].bounds = signorini_schemes::Bounds { lo: -2e-4, hi: 2e-4 };
            LockstepLane { restitution: 0.25 * k as f64, ..l }
        })
        .collect()
}

/// What the CSV series of a lane says: each lane's `SeriesWriter` (every
/// `every` levels, with the contact's columns, no energy) in lockstep,
/// against the same writer fed by the single run; returns the number of
/// rows with the contact active.
fn series_rows(scheme: Scheme, width: usize, lanes: &[LockstepLane], steps: &[usize], every: usize) -> usize {
    let dof = lanes[0].dynamics.contacts[0].dof;
    let dofs = [dof];
    let cols = SeriesColumns { energy: false, contacts: Some(&dofs), ..SeriesColumns::default() };
    let cfgs: Vec<RunConfig> = steps.iter().map(|&n| RunConfig::new(DT, n as f64 * DT).unwrap()).collect();
    let mut bufs: Vec<Vec<u8>> = vec![Vec::new(); lanes.len()];
    {
        let mut ws: Vec<SeriesWriter<'_, &mut Vec<u8>>> = bufs.iter_mut().map(|b| SeriesWriter::new(b, every, dof, cols).unwrap()).collect();
        let mut runs: Vec<LockstepRun<'_>> = ws.iter_mut().zip(&cfgs).zip(lanes).map(|((w, c), l)| LockstepRun::new(&l.initial.u, c, vec![w as &mut dyn Observer])).collect();
        assert!(matches!(scheme, Scheme::D1(_) | Scheme::Mjc), "the series test's engines");
        let ends = run_lockstep(&mut scheme.batch(width, lanes), &mut runs, &Need::Full).unwrap();
        assert!(ends.iter().all(|e| e.result.is_ok()), "every lane reaches its horizon");
    }
    let mut active = 0;
    for (k, (l, got)) in lanes.iter().zip(&bufs).enumerate() {
        let mut s: Box<dyn Stepper> = match scheme {
            Scheme::D1(level) => Box::new(D1MinusLinear::at_level(level, "single".into(), l.dynamics.clone(), l.restitution, DT, &l.initial).unwrap()),
            _ => Box::new(MoreauJeanCombined::new("single".into(), l.dynamics.clone(), 1.0, l.restitution, DT, &l.initial).unwrap()),
        };
        let mut want = Vec::new();
        {
            let mut w = SeriesWriter::new(&mut want, every, dof, cols).unwrap();
            run(s.as_mut(), &l.initial.u, &cfgs[k], &mut [&mut w]).unwrap();
        }
        let text = String::from_utf8(want.clone()).unwrap();
        let rows: Vec<&str> = text.lines().collect();
        // Level 0, then every `every`-th level up to the horizon: the last
        // row is the last multiple of `every`, not the horizon itself.
        assert_eq!(rows.len(), 1 + 1 + steps[k] / every, "{scheme:?} lane {k}: the single run's rows");
        active += rows.iter().skip(2).filter(|r| !r.ends_with(",0")).count();
        assert!(got == &want, "{scheme:?} lane {k}: the series differs from its single run's (first differing row {:?})", String::from_utf8_lossy(got).lines().zip(text.lines()).find(|(a, b)| a != b));
    }
    active
}

/// Schindler and Acary's engine (level 0 after construction: no start
/// step), both levels, in `run_lockstep`: lanes with different forcing,
/// restitutions and horizons, one cancelled by its observer, one whose
/// observer fails, two that blow up in a partial batch — each lane's
/// samples and end are its single run's; and the CSV series every 7 levels
/// (horizons off the multiples of 7 and of the 64-step checks).
#[test]
fn d1_minus_linear_lanes_feed_their_observers_the_single_runs_samples() {
    for level in [D1Level::Acceleration, D1Level::Velocity] {
        lanes_feed_the_single_runs_samples(Scheme::D1(level));
    }
}

/// Moreau–Jean with the combined projection (θ = 1; level 0 after
/// construction) in `run_lockstep`: as Schindler and Acary's above.
#[test]
fn moreau_jean_combined_lanes_feed_their_observers_the_single_runs_samples() {
    lanes_feed_the_single_runs_samples(Scheme::Mjc);
}

fn lanes_feed_the_single_runs_samples(scheme: Scheme) {
    let lanes = rattling_lanes();
    let steps = [700, 640, 1000, 333];
    let twists = [Twist::None, Twist::CancelAt(129), Twist::None, Twist::FailAt(200)];
    let got = lockstep_of(scheme, 4, &lanes, &steps, &twists, &Need::Full);
    assert!(got[1].3.as_ref().is_err_and(|e| e.contains("interrupted at step 129")), "{scheme:?}: {:?}", got[1].3);
    assert!(got[3].3.as_ref().is_err_and(|e| e.contains("planted")), "{scheme:?}: {:?}", got[3].3);
    assert_eq!(got[2].3.as_ref().map(|s| s.0), Ok(1000));
    assert!(got.iter().all(|g| g.0[0].n == 0 && g.0[1].n == 1 && g.0[1].lambda.is_some()), "{scheme:?}: level 1 is a step's sample");
    // Not vacuous: the contact acts in the samples.
    let held = got.iter().flat_map(|g| g.0.iter()).filter(|r| r.status[0] != signorini_contact::Active::None).count();
    eprintln!("{scheme:?}: {held} samples with the contact active");
    assert!(held > 100, "{scheme:?}: only {held} samples with the contact active");
    check_of(scheme, &lanes, &steps, &twists, got);
    let blow: Vec<LockstepLane> = [0.2, 1e303, 0.3, 4e303, 0.25].iter().map(|&a| lane(a, 12.0)).collect();
    let got = lockstep_of(scheme, 8, &blow, &[500; 5], &[Twist::None; 5], &Need::Full);
    for k in [1, 3] {
        assert!(got[k].3.as_ref().is_err_and(|e| e.contains("blew up")), "{scheme:?} lane {k}: {:?}", got[k].3);
        assert!(got[k].4 < 500, "{scheme:?}: lane {k} stopped early");
    }
    check_of(scheme, &blow, &[500; 5], &[Twist::None; 5], got);
    let active = series_rows(scheme, 4, &lanes, &[703, 640, 1000, 333], 7);
    assert!(active > 10, "{scheme:?}: only {active} series rows with the contact active");
}
