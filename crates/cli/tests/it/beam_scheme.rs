//! Beam scenes take `scheme = "…"` through the scheme registry (issue 24
//! §2). The paper's contacts stay the defaults; a registry scheme that
//! writes the same integrator must give the same file byte for byte, which
//! checks the scene layer's spelling against the registry's.

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
}

/// Runs a scene text; `Ok(series.csv)` or `Err(stderr)` with the exit code 2.
fn run(dir: &Path, name: &str, text: &str) -> Result<Vec<u8>, String> {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join(name);
    let o = bin().args(["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]).output().unwrap();
    if o.status.success() {
        Ok(std::fs::read(out.join("series.csv")).unwrap())
    } else {
        assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

/// The paper's projection (the β-scheme, e = 0) and its penalty law, each
/// against the registry scheme that is the same integrator: `ps(0,β)` and
/// `penalty-cn` with the stop's own stiffness in N/m.
#[test]
fn registry_schemes_on_the_beam_equal_the_papers_contacts() {
    let dir = tempfile::tempdir().unwrap();
    for beta in ["0.5", "0.25"] {
        let paper = run(dir.path(), &format!("paper-{beta}"), &format!("[beam]\nscene = \"fig2\"\nt_end = 0.2\nbeta = {beta}\n")).unwrap();
        let registry = run(dir.path(), &format!("registry-{beta}"), &format!("[beam]\nscene = \"fig2\"\nt_end = 0.2\nscheme = \"ps(0,{beta})\"\n")).unwrap();
        assert!(paper.len() > 4000 * 20, "a series of 4000 steps");
        assert!(paper == registry, "β = {beta}: the registry's ps(0,β) differs from the paper's β-scheme");
    }
    let stop = "[[stop]]\nx = 1.501\nlo = -0.1\nhi = 0.1\nstiffness = 1e8\n";
    let paper = run(dir.path(), "penalty", &format!("[beam]\nscene = \"fig5\"\nt_end = 0.3\ncontact = \"penalty\"\n{stop}")).unwrap();
    let registry = run(dir.path(), "penalty-cn", &format!("[beam]\nscene = \"fig5\"\nt_end = 0.3\nscheme = \"penalty-cn\"\n{stop}")).unwrap();
    // Contacts do happen in this window (the test would be empty otherwise).
    let active = String::from_utf8_lossy(&paper).lines().skip(1).filter(|l| !l.ends_with(",0")).count();
    assert!(active > 100, "{active} rows in contact");
    assert!(paper == registry, "the registry's penalty-cn differs from the paper's penalty contact");
}

/// The paper's spellings now parse into registry schemes (`contact =
/// "projection"` is `ps(0,β)`, `"penalty"` is `penalty-cn` with a spring):
/// each paper scene writes the `series.csv` the hand-built integrators wrote
/// before (the β-scheme built by `PaoliSchatzman::new`, Newmark-CN with
/// `ContactLaw::Penalty`), pinned here by the length and FNV-1a hash of
/// the files that code wrote (commit 8b17752), with the projection, the
/// penalty spring (tip and [[stop]]s), β < 1/4 and a reduced model.
#[test]
fn paper_spellings_write_what_the_hand_built_integrators_wrote() {
    fn fnv1a(b: &[u8]) -> u64 {
        b.iter().fold(0xcbf2_9ce4_8422_2325, |h, &x| (h ^ u64::from(x)).wrapping_mul(0x0000_0100_0000_01b3))
    }
    let dir = tempfile::tempdir().unwrap();
    let stops = "[[stop]]\nx = 0.7505\nlo = -0.03\nhi = 0.03\nstiffness = 1e7\n[[stop]]\nx = 1.501\nlo = -0.1\nhi = 0.1\n";
    for (name, text, len, hash) in [
        ("fig2", "[beam]\nscene = \"fig2\"\nt_end = 0.2\n".to_string(), 378_499, 0x5079_a47e_af16_1887_u64),
        // Past the first impacts (0.0878 s): the contact law acts.
        ("fig3", "[beam]\nscene = \"fig3\"\nt_end = 0.15\n[output]\nevery = 10\n".into(), 287_288, 0x9647_5917_1d33_ddad),
        ("fig5", "[beam]\nscene = \"fig5\"\nt_end = 0.15\n[output]\nevery = 10\n".into(), 287_261, 0x5024_ae33_8749_46fb),
        ("fig8", "[beam]\nscene = \"fig8\"\nt_end = 0.1\n[output]\nevery = 50\n".into(), 192_251, 0x5336_9ef8_b70c_0e4b),
        ("beta01", "[beam]\nscene = \"fig2\"\nbeta = 0.1\ndt = 1e-5\nt_end = 0.1\n".into(), 950_864, 0x7302_9e96_da5f_bc12),
        ("penalty-stops", format!("[beam]\nscene = \"fig5\"\nelements = 20\nt_end = 0.05\npenalty_stiffness = 2e8\n{stops}"), 1_703_271, 0x68c3_a21d_a707_fb22),
        ("reduced", "[beam]\nscene = \"fig2\"\nt_end = 0.2\nreduce = { modes = 4 }\n".into(), 377_188, 0x2ea2_bc27_55ac_f486),
    ] {
        let series = run(dir.path(), name, &text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((series.len(), fnv1a(&series)), (len, hash), "{name}: series.csv differs from the hand-built integrator's");
    }
}

/// A scheme that is not the paper's runs on the beam, keeps the tip within
/// its stops (the projection of Newmark's contact at t_{n+1}: to round-off),
/// and differs from the default.
#[test]
fn another_registry_scheme_runs_on_the_beam() {
    let dir = tempfile::tempdir().unwrap();
    let default = run(dir.path(), "default", "[beam]\nscene = \"fig2\"\nt_end = 0.2\n").unwrap();
    let newmark = run(dir.path(), "newmark", "[beam]\nscene = \"fig2\"\nt_end = 0.2\nscheme = \"backward-euler\"\n").unwrap();
    assert!(default != newmark);
    let text = String::from_utf8(newmark).unwrap();
    let tip = text.lines().next().unwrap().split(',').position(|h| h == "tip_m").unwrap();
    let max = text.lines().skip(1).map(|l| l.split(',').nth(tip).unwrap().parse::<f64>().unwrap().abs()).fold(0.0, f64::max);
    assert!(max > 0.0999 && max <= 0.1 + 1e-12, "max |tip| = {max}");
}

/// Every key acts or is refused: schemes that do not take the beam, the
/// paper's keys beside `scheme`, restitution with a scheme without an
/// impact law.
#[test]
fn beam_scheme_refusals_name_the_field() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, field) in [
        ("cd-taylor", "[beam]\nscene = \"fig2\"\nscheme = \"cd-taylor\"\n", "beam.scheme"),
        ("hybrid", "[beam]\nscene = \"fig2\"\nscheme = \"hybrid\"\n", "beam.scheme"),
        ("with-beta", "[beam]\nscene = \"fig2\"\nscheme = \"newmark-cn\"\nbeta = 0.3\n", "beam.beta"),
        ("with-contact", "[beam]\nscene = \"fig2\"\nscheme = \"newmark-cn\"\ncontact = \"penalty\"\n", "beam.contact"),
        ("unknown", "[beam]\nscene = \"fig2\"\nscheme = \"leapfrog\"\n", "beam.scheme"),
        ("unstable", "[beam]\nscene = \"fig2\"\nscheme = \"taylor-flanagan\"\n", "beam.dt"),
        ("restitution", "[beam]\nscene = \"fig2\"\nscheme = \"newmark-cn\"\n[[stop]]\nx = 1.501\nlo = -0.1\nhi = 0.1\nrestitution = 0.5\n", "stop.0.restitution"),
    ] {
        let e = run(dir.path(), name, text).expect_err(name);
        assert!(e.contains(field), "{name}: {e}");
    }
}
