//! The explicit schemes on a diagonal (lumped) mass, against stored
//! outputs of the code before `BandLdlt`'s diagonal path (commit 1679ea4,
//! where every solve with a lumped `M` ran the tridiagonal sweeps over its
//! zero sub-diagonal): random chains of 2–100 dofs, random lumped masses
//! and springs, a steady load and a sine forcing, one and two contacts,
//! random initial states and a random state set halfway (where the scheme
//! offers it). Every bit of every step's report (`n`, `t`, `λ` and its
//! time, the status), of `U`, of the state, of each contact's force and
//! status, of the energy, the works and the dissipation is folded into
//! one FNV-1a hash per scheme, compared with the hash the old code gave
//! (printed with `SIGNORINI_PRINT_HASHES=1`).

use signorini_contact::Active;
use signorini_fem::SymBand;
use signorini_schemes::{Bounds, Contact, Dynamics, Forcing, Initial, SchemeSpec, SplitMix64, TimeProfile};

/// FNV-1a over 64-bit words.
struct Fnv(u64);

impl Fnv {
    fn word(&mut self, w: u64) {
        for b in w.to_le_bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x100_0000_01b3);
        }
    }
    fn f(&mut self, x: f64) {
        self.word(x.to_bits());
    }
    fn all(&mut self, xs: &[f64]) {
        xs.iter().for_each(|x| self.f(*x));
    }
    fn active(&mut self, a: Active) {
        self.word(match a {
            Active::None => 0,
            Active::Lower => 1,
            Active::Upper => 2,
        });
    }
}

/// A chain of `n` dofs: lumped masses, springs to the neighbours (the
/// first and last also to the wall), contact 0 at dof 0 (a lower stop, an
/// upper one too if `two_sided`), a second at the last dof if `two`.
fn chain(rng: &mut SplitMix64, n: usize, two: bool, two_sided: bool) -> (Dynamics, Initial) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        m.set(i, i, 0.5 + rng.next_f64());
        let ki = 1.0 + 3.0 * rng.next_f64();
        k.set(i, i, 2.0 * ki);
        if i > 0 {
            k.set(i, i - 1, -ki);
        }
    }
    let load: Vec<f64> = (0..n).map(|_| 0.3 * (rng.next_f64() - 0.7)).collect();
    let hi = if two_sided { 0.05 + 0.05 * rng.next_f64() } else { f64::INFINITY };
    let mut contacts = vec![Contact::new(0, Bounds { lo: -0.03 * rng.next_f64(), hi }, false)];
    if two && n > 1 {
        contacts.push(Contact::new(n - 1, Bounds { lo: f64::NEG_INFINITY, hi: 0.02 * rng.next_f64() }, false));
    }
    let shape: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.5).collect();
    let dy = Dynamics::new(m, k, load, contacts).with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 0.8, omega: 3.0 } }]);
    let u = (0..n).map(|_| 0.02 * (rng.next_f64() - 0.5)).collect();
    let v = (0..n).map(|_| 2.0 * rng.next_f64() - 1.0).collect();
    (dy, Initial { u, v })
}

/// One run of `spec` on `(dy, init)`, 80 steps (a random state set at
/// step 40 where offered), folded into `h`; `fuse`: the energy asked for
/// after every step ([`signorini_schemes::Stepper::fuse_energy`], as
/// `signorini run` does).
fn fold(h: &mut Fnv, rng: &mut SplitMix64, spec: &SchemeSpec, dy: Dynamics, init: &Initial, dt: f64, fuse: bool) {
    let mut s = spec.build(dy, dt, init).unwrap_or_else(|e| panic!("{spec}: {e}"));
    s.fuse_energy(fuse);
    for step in 0..80 {
        if step == 40 {
            if let Some(st) = s.state() {
                let st: Vec<f64> = st.iter().map(|x| x + 0.01 * (rng.next_f64() - 0.5)).collect();
                s.set_state(&st).unwrap();
                h.all(&st);
            }
        }
        let r = s.step().unwrap_or_else(|e| panic!("{spec}: {e}"));
        h.word(r.n as u64);
        h.f(r.t);
        if let Some((t, l)) = r.lambda {
            h.f(t);
            h.f(l);
        }
        h.active(r.active);
        h.all(s.displacement());
        if let Some(st) = s.state() {
            h.all(&st);
        }
        h.all(s.contact_forces());
        for a in s.contact_status() {
            h.active(*a);
        }
        if let Some((t, e)) = s.energy() {
            h.f(t);
            h.f(e);
        }
        if let Some((wf, wc)) = s.work() {
            h.f(wf);
            h.f(wc);
        }
        if let Some(d) = s.dissipation() {
            h.f(d);
        }
    }
}

/// Each scheme of `expected` stepped on the chains `make` builds (for
/// each variant, each size, with one contact and, but for the one-contact
/// schemes, two; two-sided stops on the odd cases but for Verlet–Nitsche's
/// one-sided one), its steps folded into one hash ([`fold`]) compared with
/// the old code's (`SIGNORINI_PRINT_HASHES` prints them); `fuse` as
/// [`fold`]'s.
fn against_old_hashes<V: Copy>(expected: &[(&str, u64)], seed: u64, fuse: bool, variants: &[V], sizes: &[usize], make: impl Fn(&mut SplitMix64, usize, bool, bool, V) -> (Dynamics, Initial)) {
    let print = std::env::var_os("SIGNORINI_PRINT_HASHES").is_some();
    let mut wrong = Vec::new();
    for &(name, expected) in expected {
        let spec: SchemeSpec = name.parse().unwrap();
        let one_contact = name.starts_with("verlet-nitsche") || name.starts_with("penalty-cd");
        let mut h = Fnv(0xcbf2_9ce4_8422_2325);
        let mut rng = SplitMix64::new(seed);
        for &variant in variants {
            for (case, &n) in sizes.iter().enumerate() {
                for two in [false, true] {
                    if two && one_contact {
                        continue;
                    }
                    // Verlet–Nitsche takes a one-sided stop.
                    let two_sided = case % 2 == 1 && !name.starts_with("verlet-nitsche");
                    let (dy, init) = make(&mut rng, n, two, two_sided, variant);
                    fold(&mut h, &mut rng, &spec, dy, &init, 0.05, fuse);
                }
            }
        }
        if print {
            println!("    (\"{name}\", {:#x}),", h.0);
        }
        if h.0 != expected {
            wrong.push(format!("{name}: {:#x}, the old code's {expected:#x}", h.0));
        }
    }
    assert!(wrong.is_empty(), "{wrong:?}");
}

/// The old code's hashes (commit 1679ea4).
const EXPECTED: [(&str, u64); 6] = [
    ("cd-lagrange(0)", 0x2aeb211a36b8eb4a),
    ("cd-lagrange(0.7)", 0x2ad9716f7dd817ac),
    ("d1-minus-linear(0)", 0xa4eac765593c6d3b),
    ("d1-minus-linear-velocity(0.5)", 0x9fc59da90c222728),
    ("verlet-nitsche(10,1)", 0xe2a8fd5cccaa88ba),
    ("penalty-cd", 0x2c84f0b60e904a77),
];

#[test]
fn explicit_schemes_on_a_lumped_mass_are_the_old_code_bit_for_bit() {
    against_old_hashes(&EXPECTED, 35, false, &[()], &[2, 3, 5, 17, 64, 100], |rng, n, two, two_sided, ()| chain(rng, n, two, two_sided));
}

/// A chain as [`chain`]'s without forcing (the explicit schemes' fused
/// passes on a lumped mass take this case without the forcing's term);
/// `rest`: `U⁰ = V⁰ = −0` and a load with `−0` entries, so that some
/// `M⁻¹(F − K U)` is `−0` — where the fused passes give the step back to
/// the plain one — and the sweeps' zeros' signs (`+0` after a negative
/// row) reach `V` and `U`.
fn chain_unforced(rng: &mut SplitMix64, n: usize, two: bool, two_sided: bool, rest: bool) -> (Dynamics, Initial) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    for i in 0..n {
        m.set(i, i, 0.5 + rng.next_f64());
        let ki = 1.0 + 3.0 * rng.next_f64();
        k.set(i, i, 2.0 * ki);
        if i > 0 {
            k.set(i, i - 1, -ki);
        }
    }
    let load: Vec<f64> = (0..n).map(|i| if rest && i % 3 != 1 { -0.0 } else { 0.3 * (rng.next_f64() - 0.7) }).collect();
    let hi = if two_sided { 0.05 + 0.05 * rng.next_f64() } else { f64::INFINITY };
    let mut contacts = vec![Contact::new(0, Bounds { lo: -0.03 * rng.next_f64(), hi }, false)];
    if two && n > 1 {
        contacts.push(Contact::new(n - 1, Bounds { lo: f64::NEG_INFINITY, hi: 0.02 * rng.next_f64() }, false));
    }
    let dy = Dynamics::new(m, k, load, contacts);
    let (u, v) = if rest { (vec![-0.0; n], vec![-0.0; n]) } else { ((0..n).map(|_| 0.02 * (rng.next_f64() - 0.5)).collect(), (0..n).map(|_| 2.0 * rng.next_f64() - 1.0).collect()) };
    (dy, Initial { u, v })
}

/// The old code's hashes (commit 9ca2869, before the fused passes) of
/// the runs of [`explicit_schemes_unforced_and_from_rest_are_the_old_code_bit_for_bit`].
const EXPECTED_UNFORCED: [(&str, u64); 7] = [
    ("cd-lagrange(0)", 0xefee4ab956d238a3),
    ("cd-lagrange(0.7)", 0x5b83bfab80b3dfd1),
    ("d1-minus-linear(0)", 0x1576d78c856db85b),
    ("d1-minus-linear-velocity(0)", 0xd4bc107bd7348311),
    ("d1-minus-linear-velocity(0.5)", 0xd4cad8c992985a00),
    ("verlet-nitsche(10,1)", 0x9eef954a1e5e528d),
    ("penalty-cd", 0xde0a3f8a5f21a557),
];

/// [`explicit_schemes_on_a_lumped_mass_are_the_old_code_bit_for_bit`]
/// without forcing (the fused passes' unforced builds), and from rest
/// with `−0` loads (their fall-back to the plain step), against the hashes
/// of the code before them.
#[test]
fn explicit_schemes_unforced_and_from_rest_are_the_old_code_bit_for_bit() {
    against_old_hashes(&EXPECTED_UNFORCED, 36, false, &[false, true], &[2, 3, 4, 5, 17, 64, 100], chain_unforced);
}

/// A chain as [`chain`]'s whose interior is uniform: one mass on every
/// node but the two ends (their own random masses), one spring everywhere,
/// so that `K`'s diagonals and `M`'s inverse pivots are, bit for bit, one
/// value on the interior rows — the explicit steps' passes then take them
/// as scalars (`Same` columns) instead of arrays. `forced`: the sine
/// forcing of [`chain`]; `rest`: `U⁰ = V⁰ = −0` and `−0` loads, as
/// [`chain_unforced`]'s.
fn chain_uniform(rng: &mut SplitMix64, n: usize, two: bool, two_sided: bool, forced: bool, rest: bool) -> (Dynamics, Initial) {
    let (mut m, mut k) = (SymBand::zeros(n, 1), SymBand::zeros(n, 1));
    let (mass, spring) = (0.5 + rng.next_f64(), 1.0 + 3.0 * rng.next_f64());
    for i in 0..n {
        m.set(i, i, if i == 0 || i == n - 1 { 0.5 + rng.next_f64() } else { mass });
        k.set(i, i, 2.0 * spring);
        if i > 0 {
            k.set(i, i - 1, -spring);
        }
    }
    let load: Vec<f64> = (0..n).map(|i| if rest && i % 3 != 1 { -0.0 } else { 0.3 * (rng.next_f64() - 0.7) }).collect();
    let hi = if two_sided { 0.05 + 0.05 * rng.next_f64() } else { f64::INFINITY };
    let mut contacts = vec![Contact::new(0, Bounds { lo: -0.03 * rng.next_f64(), hi }, false)];
    if two && n > 1 {
        contacts.push(Contact::new(n - 1, Bounds { lo: f64::NEG_INFINITY, hi: 0.02 * rng.next_f64() }, false));
    }
    let mut dy = Dynamics::new(m, k, load, contacts);
    if forced {
        let shape: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.5).collect();
        dy = dy.with_forcing(vec![Forcing { shape, time: TimeProfile::Sine { amplitude: 0.8, omega: 3.0 } }]);
    }
    let (u, v) = if rest { (vec![-0.0; n], vec![-0.0; n]) } else { ((0..n).map(|_| 0.02 * (rng.next_f64() - 0.5)).collect(), (0..n).map(|_| 2.0 * rng.next_f64() - 1.0).collect()) };
    (dy, Initial { u, v })
}

/// The old code's hashes of the runs of
/// [`explicit_schemes_on_a_uniform_chain_are_the_old_code_bit_for_bit`]:
/// commit 904d0a4 (before the uniform columns) for the first seven; the
/// central difference's three (`paoli.rs`' explicit step, a uniform
/// chain with one contact and no forcing) printed by this test at commit
/// 3877503, before its uniform columns.
const EXPECTED_UNIFORM: [(&str, u64); 10] = [
    ("cd-lagrange(0)", 0xd9cc59afc43252cf),
    ("cd-lagrange(0.7)", 0x7997608b3a69b0ff),
    ("d1-minus-linear(0)", 0x537bab40d8a41bda),
    ("d1-minus-linear-velocity(0)", 0x9ef18ff41bb61f6b),
    ("d1-minus-linear-velocity(0.5)", 0x87b36022100e7744),
    ("verlet-nitsche(10,1)", 0xe2879cb064b47835),
    ("penalty-cd", 0x87cf654fed963720),
    ("taylor-flanagan", 0x2358cf6eb09c416e),
    ("cd-taylor", 0x7a08ebc8efbfd6b4),
    ("ps(0.5,0)", 0x8a1e7412d850114d),
];

/// The explicit schemes on uniform chains ([`chain_uniform`]: the passes'
/// scalar coefficients), forced, unforced and from rest, against the
/// hashes of the code before the scalar coefficients (which streamed the
/// same values from arrays).
#[test]
fn explicit_schemes_on_a_uniform_chain_are_the_old_code_bit_for_bit() {
    let variants = [(true, false), (false, false), (false, true)];
    against_old_hashes(&EXPECTED_UNIFORM, 37, false, &variants, &[2, 3, 4, 5, 17, 64, 100], |rng, n, two, two_sided, (forced, rest)| chain_uniform(rng, n, two, two_sided, forced, rest));
}

/// The old code's hashes (commit 3877503, before the uniform energy
/// passes; printed by this test there) of the runs of
/// [`explicit_schemes_with_the_energy_fused_are_the_old_code_bit_for_bit`]:
/// the same as without the fusion ([`EXPECTED_UNIFORM`]'s, commit 904d0a4).
const EXPECTED_UNIFORM_FUSED: [(&str, u64); 1] = [("penalty-cd", 0x87cf654fed963720)];

/// [`explicit_schemes_on_a_uniform_chain_are_the_old_code_bit_for_bit`]
/// with the energy asked for after every step (`fuse_energy`, as
/// `signorini run` asks): `penalty-cd`'s fused end of a step (the next
/// step's right-hand side, its forward sweep and the energy's sums).
#[test]
fn explicit_schemes_with_the_energy_fused_are_the_old_code_bit_for_bit() {
    let variants = [(true, false), (false, false), (false, true)];
    against_old_hashes(&EXPECTED_UNIFORM_FUSED, 37, true, &variants, &[2, 3, 4, 5, 17, 64, 100], |rng, n, two, two_sided, (forced, rest)| chain_uniform(rng, n, two, two_sided, forced, rest));
}
