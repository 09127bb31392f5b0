//! The README's Rust quick start, compiled and run: the lines between the
//! markers are the README's ```rust block, line for line (indentation
//! aside) — `cargo xtask docs --check` (run by `cargo xtask test`) fails
//! when the two differ.

#[test]
fn readme_rust_quick_start() {
    // README quick start: begin
    use signorini::exact::{BarDirichlet, ExactSolution};

    // The exact contact force of the Signorini–Dirichlet bar at t = 1.5
    // (−1/2 on the contact phase [1, 2) of each period 3), and the exact fields at a point.
    let bar = BarDirichlet;
    println!("λ(1.5) = {}", bar.lambda(1.5));
    let f = bar.fields(0.5, 1.2);
    println!("u = {}, u_x = {}, u_t = {} at x = 0.5, t = 1.2", f.u, f.ux, f.ut);
    // README quick start: end
    assert_eq!(bar.lambda(1.5), -0.5);
    assert!(f.u.is_finite() && f.ux.is_finite() && f.ut.is_finite());
}
