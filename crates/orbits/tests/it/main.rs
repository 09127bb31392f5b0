//! signorini-orbits' integration tests (one binary, one module per concern).
mod autonomous;
mod basins;
mod basins_stop;
mod beam;
mod between;
mod cascade;
mod chain;
mod chatter;
mod conservative;
mod corrector;
mod free_grazing;
mod further_impact;
mod isola;
mod mirror;
mod nonsmooth_fold;
mod oscillator;
mod period_two;
mod reach;
mod rebuilt;
mod reuse;
mod scale;
mod section;
mod shared;
mod slow_impact;
mod start;
mod store;
mod switch;
mod symmetric;
mod turn;
mod two_stops;

/// The impact oscillator most modules trace: `x'' + 2ζx' + x = sin Ωt`
/// against one stop at `stop` (mass, stiffness and forcing amplitude 1),
/// run event-driven with restitution `e`, as a scene's TOML table.
pub fn oscillator(zeta: f64, stop: f64, e: f64, omega: f64) -> toml::Table {
    let text = format!(
        "[oscillator]\nmass = 1.0\nstiffness = 1.0\ndamping_ratio = {zeta:?}\nstop = {stop:?}\nrestitution = {e:?}\n\
         dt = 1e-2\nt_end = 10.0\nscheme = \"event-driven\"\n[forcing]\namplitude = 1.0\nomega = {omega:?}\n"
    );
    text.parse().expect("the oscillator's scene text")
}
