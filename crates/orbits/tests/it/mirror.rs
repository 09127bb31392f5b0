//! The mirror 3-impact orbit past the grazing at 1.038307 of the
//! oscillator between symmetric stops (`x'' + 0.1 x' + x = 2 sin Ωt`,
//! `|x| <= 1`, e = 0.8; `section.rs`'s branch), where the branch ends.
//! A transcription sharing no code with the crate (a scratch program: the
//! closed-form flow between impacts, impacts by bisection on it, the orbit
//! solved as impact times and signed speeds by Newton on central
//! differences) puts the grazing at 1.0383070501555 (the 3-impact orbit
//! with its slow impact at −1 of speed 0, solved for Ω) and its mirror
//! image (times + T/2, sides and speeds negated) there too; Newton on the
//! mirror 3-impact equations from that grazing orbit converges on both
//! sides (to 1e-14), admissible past it (Ω above: the slow impact at +1
//! arrives at +2.23 (Ω − Ω_g), 1.34e-3 at 6e-4 past) and not before it
//! (the speed of the other sign). So the orbit exists past the grazing:
//! the mirror image of every 3-impact orbit the branch traced above it.
//! The states below are the transcription's, to 16 digits.

use crate::between::model;
use signorini_orbits::{periodic_orbit, Newton};
use std::f64::consts::TAU;

/// The transcription's grazing.
pub const GRAZING: f64 = 1.0383070501555;
/// The branch's grazing orbit on the mirror side (its last point, 1.2e-12
/// below the grazing): the state the searches start from.
const GRAZING_ORBIT: [f64; 2] = [0.4272603007551, 0.2509852574797];
/// The transcription's mirror 3-impact orbit at `GRAZING + 0.6 f`, for
/// f = 1e-5, 1e-4, 1e-3 of the branch's range.
const PAST: [(f64, [f64; 2]); 3] = [(1e-5, [0.427257791098679, 0.25099501747308395]), (1e-4, [0.42723504104373866, 0.2510828311828792]), (1e-3, [0.4270077404336803, 0.25196147442841266])];

fn impacts(img: &signorini_orbits::Image) -> usize {
    img.events.iter().filter(|e| e.kind == signorini_schemes::events::EventKind::Impact && e.velocity_before != 0.0).count()
}

/// The orbit is in the crate's own model: each transcribed state is a
/// fixed point of the crate's map with three impacts. Newton's residual
/// from the orbit itself stalls at 2.4e-10, 1.5e-11 and 7.6e-13 at 1e-5,
/// 1e-4 and 1e-3 of the range (the slow impact's multiplier, near the
/// inverse of its speed, lifts the map's round-off above the tolerance
/// 1e-12), where it now stops, converged at that round-off (below); with
/// the tolerance 1e-8 it converges. From the grazing orbit, the seed of
/// the branch's searches, it reaches it at neither tolerance.
#[test]
fn the_mirror_three_impact_orbit_exists_past_the_grazing() {
    let mut seen = Vec::new();
    for (f, x) in PAST {
        let w = GRAZING + 0.6 * f;
        let m = model(w).unwrap();
        let img = m.flow(0.0, &x, TAU / w, false).unwrap();
        let d = (img.x[0] - x[0]).abs().max((img.x[1] - x[1]).abs());
        // The slow impact's speed, 2.23·0.6 f, amplifies the states'
        // round-off (|μ| ≈ 1/speed): within 1e-12 of it, over that speed.
        let tol = 1e-12 / (2.23 * 0.6 * f);
        let reached = |seed: &[f64], tol_newton: f64| match periodic_orbit(&m, 0.0, TAU / w, seed, &Newton { tol: tol_newton, ..Newton::default() }) {
            Ok(o) => format!(
                "{} ({} impacts, {:.1e} from it)",
                if (o.x[0] - x[0]).abs().max((o.x[1] - x[1]).abs()) <= tol && o.impacts() == 3 { "reached" } else { "elsewhere" },
                o.impacts(),
                (o.x[0] - x[0]).abs().max((o.x[1] - x[1]).abs())
            ),
            Err(e) => format!("failed: {e}"),
        };
        let default = Newton::default().tol;
        let (own, own_loose) = (reached(&x, default), reached(&x, 1e-8));
        let (graze, graze_loose) = (reached(&GRAZING_ORBIT, default), reached(&GRAZING_ORBIT, 1e-8));
        eprintln!("f = {f:e}: |P(x) − x| = {d:e}, {} impacts\n  Newton (tol {default:e}) from it: {own}\n  (tol 1e-8) from it: {own_loose}\n  (tol {default:e}) from the grazing orbit: {graze}\n  (tol 1e-8) from the grazing orbit: {graze_loose}", impacts(&img));
        seen.push((f, d, tol, impacts(&img), own_loose, graze));
    }
    for (f, d, tol, k, own, graze) in &seen {
        assert!(d <= tol && *k == 3, "f = {f:e}: |P(x) − x| = {d:e} > {tol:e}, {k} impacts");
        assert!(!graze.starts_with("reached"), "f = {f:e}: Newton from the grazing orbit {graze}");
        assert!(own.starts_with("reached"), "f = {f:e}: Newton (tol 1e-8) from the orbit {own}");
    }
}

/// The mirror image of an orbit the branch traced above the grazing (its
/// 3-impact point at Ω = 1.039819015677, `branch.csv` of `signorini
/// continue`) is a fixed point of the crate's map with three impacts:
/// `−x(T/2)`, as the symmetry `x → −x, t → t + T/2` of the forcing says.
#[test]
fn the_mirror_image_of_a_traced_orbit_is_an_orbit() {
    let (w, x) = (1.039819015677, [-0.9960664685493, -0.09150763112566]);
    let m = model(w).unwrap();
    let o = periodic_orbit(&m, 0.0, TAU / w, &x, &Newton::default()).unwrap();
    let half = m.flow(0.0, &o.x, 0.5 * TAU / w, false).unwrap();
    let y = [-half.x[0], -half.x[1]];
    let img = m.flow(0.0, &y, TAU / w, false).unwrap();
    let d = (img.x[0] - y[0]).abs().max((img.x[1] - y[1]).abs());
    assert!(d <= 1e-9 && impacts(&img) == 3, "the mirror image {y:?}: |P(y) − y| = {d:e}, {} impacts", impacts(&img));
    // And it is the transcription's mirror family: nearer the grazing
    // orbit than the offset's own 3e-3 times the state's pace (the
    // transcription's orbit at 1e-3 of the range is 1e-3 from it).
    assert!((y[0] - GRAZING_ORBIT[0]).abs().max((y[1] - GRAZING_ORBIT[1]).abs()) <= 5e-3, "{y:?}");
}

/// Newton's stopping rule at the map's round-off: 1e-4 of the range past
/// the grazing the slow impact (1.3e-4) makes the map ill-conditioned, and
/// Newton with its default tolerance (1e-12 of the state) stalled at
/// 1.5e-11 and failed, even from the orbit itself. It now stops where its
/// residual no longer falls within `64 ε ‖P'‖∞ ‖x‖∞` and reports what it
/// reached. From 1e-8 beside the transcription's orbit (each way), the
/// orbit found is the transcription's to the tolerance its conditioning
/// sets (1e-12 over the slow impact's speed), with its three impacts, and
/// a fixed point of the transcription's own map (`between.rs`, no code of
/// the crate) to that tolerance with three impacts.
#[test]
fn newton_finds_the_mirror_orbit_at_the_maps_round_off() {
    let f = 1e-4;
    let x = PAST[1].1;
    let w = GRAZING + 0.6 * f;
    let m = model(w).unwrap();
    let tol = 1e-12 / (2.23 * 0.6 * f);
    for (dx, dv) in [(0.0, 0.0), (1e-8, -1e-8), (-1e-8, 1e-8)] {
        let seed = [x[0] + dx, x[1] + dv];
        let o = match periodic_orbit(&m, 0.0, TAU / w, &seed, &Newton::default()) {
            Ok(o) => o,
            Err(e) => panic!("from {seed:?}: {e}"),
        };
        let d = (o.x[0] - x[0]).abs().max((o.x[1] - x[1]).abs());
        let (y, k, _) = crate::between::map_between(w, [o.x[0], o.x[1]], 1, (-1.0, 1.0), crate::between::E, 4000.0);
        let e = (y[0] - o.x[0]).abs().max((y[1] - o.x[1]).abs());
        eprintln!(
            "from {seed:?}: {} impacts, {d:e} from the transcription's, its map's residual {e:e} ({k} impacts), Newton's {:e} after {} iterations, |μ| {:e}",
            o.impacts(),
            o.residual,
            o.iterations,
            o.mu_max()
        );
        assert!(d <= tol && o.impacts() == 3, "from {seed:?}: {d:e} from the transcription's orbit (tolerance {tol:e}), {} impacts", o.impacts());
        assert!(e <= tol && k == 3, "from {seed:?}: the transcription's map moves the orbit by {e:e} ({k} impacts)");
    }
}

/// The branch from Ω = 1.5 down (`section.rs`'s) turns at its branch point
/// at 1.0376 onto the mirror images of its own orbits, and went on along
/// them, back up to the mirror grazing at 1.0383, listing that grazing a
/// second time (and, where the searches found the orbit beyond, every
/// bifurcation of the branch again). It now ends at the first point past
/// the turn, each bifurcation listed once. Checked against the
/// transcription (`between.rs`, no code of the crate): the last point's
/// mirror image `−x(T/2)` by the transcription's own half-period flow is
/// a fixed point of its map with as many impacts, and an orbit the branch
/// traced before the turn (Newton on that map at the last point's Ω, from
/// the chord of a traced step across that Ω, lands on it), while the last
/// point itself is another orbit (its asymmetry `x(0) + x(T/2)` of the
/// other sign).
#[test]
fn a_branch_turned_onto_its_mirror_image_ends_there() {
    use crate::between::{fixed_point, flow_between, map_between, E};
    use crate::continuation;
    use signorini_orbits::{ContinuationOptions, Family, OrbitError};
    struct Between;
    impl Family for Between {
        fn model(&self, w: f64) -> Result<signorini_orbits::Model, OrbitError> {
            model(w)
        }
        fn period(&self, w: f64) -> Result<f64, OrbitError> {
            Ok(TAU / w)
        }
    }
    let w0 = 1.5;
    let m = model(w0).unwrap();
    let x0 = m.flow(0.0, &[0.0, 0.0], 400.0 * TAU / w0, false).unwrap().x;
    let start = periodic_orbit(&m, 0.0, TAU / w0, &x0, &Newton::default()).unwrap();
    let branch = continuation(&Between, &start.x, &ContinuationOptions::new(w0, 0.9)).unwrap();
    let listed: Vec<(&str, f64)> = branch.bifurcations.iter().map(|b| (b.kind.name(), b.param)).collect();
    eprintln!("{} points: {}\n{listed:?}", branch.points.len(), branch.end);
    assert!(branch.end.starts_with("returned onto its mirror image"), "{}", branch.end);
    // Each bifurcation once: no two of a kind within 1e-6 of each other;
    // the branch point of the turn the last.
    for (k, a) in listed.iter().enumerate() {
        assert!(!listed[k + 1..].iter().any(|b| b.0 == a.0 && (b.1 - a.1).abs() <= 1e-6), "{} at {} listed twice: {listed:?}", a.0, a.1);
    }
    assert!(listed.last().is_some_and(|&(kind, w)| kind == "branch-point" && (w - 1.0376426).abs() < 1e-6), "{listed:?}");
    // The transcription's mirror image of the last point.
    let last = &branch.points[branch.points.len() - 1];
    let w = last.param;
    let map = |x: [f64; 2]| map_between(w, x, 1, (-1.0, 1.0), E, 4000.0);
    let half = |x: [f64; 2]| flow_between(w, 0.0, 0.5 * TAU / w, x, (-1.0, 1.0), E, 4000.0).0;
    let x = [last.orbit.x[0], last.orbit.x[1]];
    let h = half(x);
    let y = [-h[0], -h[1]];
    let (py, k, _) = map(y);
    let off = (py[0] - y[0]).abs().max((py[1] - y[1]).abs());
    assert!(off <= 1e-9 && k == last.orbit.impacts(), "the mirror image {y:?} at Ω = {w}: |P(y) − y| = {off:e}, {k} impacts");
    let (ax, ay) = (x[0] + h[0], y[0] + half(y)[0]);
    let n = branch.points.len() - 1;
    let mut nearest = f64::INFINITY;
    for s in branch.points[..n].windows(2) {
        let (a, b) = (&s[0], &s[1]);
        if (a.param - w) * (b.param - w) > 0.0 || a.param == b.param || a.orbit.impacts() != last.orbit.impacts() || b.orbit.impacts() != last.orbit.impacts() {
            continue;
        }
        let f = (w - a.param) / (b.param - a.param);
        let seed = [a.orbit.x[0] + f * (b.orbit.x[0] - a.orbit.x[0]), a.orbit.x[1] + f * (b.orbit.x[1] - a.orbit.x[1])];
        if let Some(z) = fixed_point(seed, 60, |x| map(x).0) {
            nearest = nearest.min((z[0] - y[0]).abs().max((z[1] - y[1]).abs()));
        }
    }
    eprintln!("Ω = {w}: mirror image {y:?}, {nearest:e} from the nearest orbit found from the traced steps; asymmetry {ax:e} and {ay:e}");
    assert!(nearest <= 1e-8, "no traced step across Ω = {w} leads to the mirror image {y:?} (nearest {nearest:e})");
    assert!(ax * ay < 0.0 && ax.abs() > 1e-3, "the last point is no other orbit than its mirror image: asymmetry {ax:e}, {ay:e}");
}
