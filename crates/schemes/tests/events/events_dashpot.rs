//! A release in a structure that a held contact splits in two, with a
//! dashpot (a non-classical damping, the first-order form of
//! docs/theory.md §9.1) in the other part: found by a sampling hunt over
//! free consistent-mass chains (2–6 dofs, dashpots, `e` in [0, 1]), where
//! 6 of 4500 runs stopped with `NoProgress` (a release of the end mass
//! followed at the same instant by its landing at zero speed, or by an
//! "impact" at 4e-33 m/s, 25 or 33 times). The end mass at rest on its
//! stop is decoupled from the moving part by the held dof, so its
//! velocity's modal terms are all round-off; the first-order basis mixes
//! the two parts at 1e-17, and that round-off was read as an approach
//! (docs/theory.md §9.2, "Zeros at the time resolution").
//!
//! Oracle: with dof 1 held at `lo₁`, dof 0 is the oscillator
//! `m x'' + x = f₀(t) + lo₁` (`m = 1/3`, the end spring tied to the held
//! dof), written here in closed form: held on its stop `x >= −0.2` while
//! the net force presses, released where it changes sign (located by
//! bisection on the closed form), then the forced oscillator from rest.

use signorini_fem::SymBand;
use signorini_schemes::events::{EventDriven, EventKind};
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Harmonic, TimeProfile};

/// Case 1344 of the hunt: the free chain of four consistent P1 masses
/// (unit springs), a dashpot `c` at dof 3, stops under dof 1 (contact 0,
/// `lo₁`) and about dof 0 (contact 1, `±0.2`), the steady load `F` and
/// `f₀(t) = F₀ + A sin(Ω t + p)` on dof 0.
struct Case {
    lo1: f64,
    c: f64,
    f: [f64; 4],
    wave: (f64, f64, f64),
}

const CASE: Case = Case {
    lo1: -0.010868231494665105,
    c: 0.2811270429044947,
    f: [0.16839628119528727, 0.0030499137368308615, -0.03218448682743573, 0.0800347296415268],
    wave: (1.309225778357078 * 0.831581195037767, 0.30670209355973493, 5.3388413795780885),
};

impl Case {
    fn dynamics(&self) -> Dynamics {
        let n = 4;
        let (mut m, mut k, mut d) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1), SymBand::zeros(n, 1));
        for i in 0..n {
            let end = i == 0 || i == n - 1;
            m.set(i, i, if end { 1.0 / 3.0 } else { 2.0 / 3.0 });
            k.set(i, i, if end { 1.0 } else { 2.0 });
            if i > 0 {
                m.set(i, i - 1, 1.0 / 6.0);
                k.set(i, i - 1, -1.0);
            }
        }
        d.set(3, 3, self.c);
        let contacts = vec![Contact::new(1, Bounds::obstacle(self.lo1), false), Contact::new(0, Bounds { lo: -0.2, hi: 0.2 }, false)];
        let (a, w, p) = self.wave;
        let time = TimeProfile::Harmonics(std::sync::Arc::from(vec![Harmonic { amplitude: a, omega: w, phase: p }]));
        Dynamics::new(m, k, self.f.to_vec(), contacts).with_forcing(vec![Forcing { shape: vec![1.0, 0.0, 0.0, 0.0], time }]).with_damping(Some(d))
    }

    /// The net force on dof 0 held at `−0.2` with dof 1 held at `lo₁`:
    /// `F(t) = f₀(t) + lo₁` (the end spring), less `−0.2`.
    fn net(&self, t: f64) -> f64 {
        let (a, w, p) = self.wave;
        self.f[0] + a * (w * t + p).sin() + self.lo1 + 0.2
    }

    /// Its zero after `t0` where it turns from pressing to pulling
    /// (bisection on the closed form).
    fn release(&self, t0: f64) -> f64 {
        let (mut a, mut b) = (t0, t0 + 1.0);
        assert!(self.net(a) < 0.0 && self.net(b) > 0.0);
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if self.net(mid) < 0.0 {
                a = mid;
            } else {
                b = mid;
            }
        }
        a
    }

    /// Dof 0 after its release at `t_r` from rest at `−0.2`:
    /// `m x'' + x = F(t)`, `m = 1/3` (`ω² = 3`), the particular solution
    /// `F₀ + lo₁ + A/(1 − m Ω²) sin(Ω t + p)`.
    fn released(&self, t: f64, t_r: f64) -> f64 {
        let (a, w, p) = self.wave;
        let om = 3f64.sqrt();
        let b = a / (1.0 - w * w / 3.0);
        let xp = |t: f64| self.f[0] + self.lo1 + b * (w * t + p).sin();
        let (c1, c2) = (-0.2 - xp(t_r), -b * w * (w * t_r + p).cos() / om);
        xp(t) + c1 * (om * (t - t_r)).cos() + c2 * (om * (t - t_r)).sin()
    }
}

/// Both contacts start held at `t = 1.9` (at rest on their stops,
/// pressed: the hunt's run held them there from 0.61), the far part moving
/// against the dashpot; the end mass is released where its net force
/// turns (1.98807, to 1e-12), once, and follows the closed form to 1e-12
/// while dof 1 stays held (at least 0.5 time units). Before: `NoProgress` at the
/// release (the release and a landing at zero speed in turn, 25 events).
/// The hunt's far-part state, and two others; `e = 0.225` as in the hunt.
#[test]
fn a_release_beside_a_dashpot_leaves_the_decoupled_end_mass_to_its_closed_form() {
    let c = &CASE;
    let t0 = 1.9;
    let t_r = c.release(t0);
    let mut runs = 0;
    for v in [[0.12310418548322452, 0.2636328425964064], [-0.3, 0.1], [0.05, -0.4]] {
        let q0 = [-0.2, c.lo1, -0.3832232248884605, -0.7005997171104265];
        let mut run = EventDriven::new(&c.dynamics(), t0, &q0, &[0.0, 0.0, v[0], v[1]], 0.225).unwrap();
        assert_eq!(run.held(), vec![(0, false), (1, false)], "start {v:?}");
        let mut t = t0;
        while t < t0 + 1.5 {
            t = (t + 0.01f64).min(t0 + 1.5);
            run.run_until(t, 1000).unwrap_or_else(|e| panic!("start {v:?}, to t = {t}: {e}"));
            if !run.held().contains(&(0, false)) {
                // Dof 1 released: the oracle's decoupling ends.
                assert!(t > t_r + 0.5, "start {v:?}: dof 1 released at {t}");
                break;
            }
            let (_, q, _) = run.state();
            let want = if t < t_r { -0.2 } else { c.released(t, t_r) };
            assert!((-0.2..=0.2).contains(&want), "the oracle's end mass stays between its stops");
            assert!((q[0] - want).abs() <= 1e-12, "start {v:?}, t = {t}: x = {}, closed form {want}", q[0]);
        }
        let ev = run.events();
        let of1: Vec<_> = ev.iter().filter(|e| e.contact == 1).collect();
        assert_eq!(of1.len(), 1, "start {v:?}: contact 1's events {of1:?}");
        assert!(of1[0].kind == EventKind::Release && (of1[0].t - t_r).abs() <= 1e-12, "start {v:?}: {:?}, closed form {t_r}", of1[0]);
        runs += 1;
    }
    assert_eq!(runs, 3);
}
