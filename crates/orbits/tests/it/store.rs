//! A branch builds each flow basis (the modes of one active set's phase)
//! once: every scene of the family — the model's runs and the scene's own
//! validated run alike, at each parameter value and at each shifted value
//! of the parameter's difference — takes it from the family's store. The
//! count of bases the runs of the test's thread built
//! (`signorini_schemes::events::bases_built`) against the number of
//! distinct active sets the branch visits, counted from its own listing of
//! events: the free phase, and one held set per contact that is released
//! or chatters to rest in a period (one stop: at most one contact held at
//! a time). A run outside the store, or a store not kept from one value to
//! the next, builds the free phase's basis once per scene: hundreds.

use crate::continuation;
use signorini_orbits::{periodic_orbit, ContinuationOptions, Family, Newton, SceneFamily};
use signorini_schemes::events::{bases_built, EventKind};
use std::collections::BTreeSet;

/// The oscillator `x'' + 0.1 x' + x = cos Ωt`, `x <= 0.2`, restitution `e`.
fn scene(e: f64, omega: f64) -> toml::Table {
    format!(
        "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = 0.05\nstop = 0.2\nrestitution = {e}\ndt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = {omega}\n"
    )
    .parse()
    .unwrap()
}

/// The branch of the family in Ω from `from` to `to` (its start after 200
/// periods from rest): the bases built on the way, and the active sets
/// its points' periods visit (`Some(c)`: contact c held, `None`: free).
fn branch(e: f64, from: f64, to: f64) -> (u64, BTreeSet<Option<usize>>, usize) {
    let before = bases_built();
    let fam = SceneFamily::new(scene(e, from), "forcing.omega", 1).unwrap().0;
    let model = fam.model(from).unwrap();
    let t = fam.period(from).unwrap();
    let x = model.flow(0.0, &[0.0, 0.0], 200.0 * t, false).unwrap().x;
    let x = periodic_orbit(&model, 0.0, t, &x, &Newton::default()).unwrap().x;
    drop(model);
    let b = continuation(&fam, &x, &ContinuationOptions::new(from, to)).unwrap();
    let built = bases_built() - before;
    let mut sets = BTreeSet::from([None]);
    for p in &b.points {
        for ev in &p.orbit.events {
            if matches!(ev.kind, EventKind::Release | EventKind::Accumulation) {
                sets.insert(Some(ev.contact));
            }
        }
    }
    (built, sets, b.points.len())
}

#[test]
fn a_branch_builds_each_active_sets_flow_basis_once() {
    // e = 0.8 past the period doubling and the grazing: free flights and
    // impacts only; e = 0.5 at low frequency: each period chatters to
    // rest on the stop and is held until the force lets go.
    for (e, from, to, held) in [(0.8, 2.2, 3.0, false), (0.5, 0.3, 0.5, true)] {
        let (built, sets, points) = branch(e, from, to);
        assert!(points > 20, "e = {e}: {points} points");
        assert_eq!(sets.len() == 2, held, "e = {e}: active sets {sets:?}");
        assert_eq!(built, sets.len() as u64, "e = {e}: {built} flow bases built over {points} points for the active sets {sets:?}");
    }
}
