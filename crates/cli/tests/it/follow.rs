//! A beam run started from an absolute state: the lifting `u = ũ − h φ(t)`
//! is undone and redone, so the beam at rest and undeformed (ũ = ũ_t = 0)
//! is exactly the scene's own start `u = 0`, `u_t = −h φ'(0) = −A ω h`.

use signorini_cli::scene::{Limits, Scene, SceneFile};

#[test]
fn a_beam_started_at_rest_is_the_scenes_own_start() {
    let text = "[beam]\nscene = \"fig2\"\nt_end = 0.01\n\n[support]\namplitude = 0.2\nomega = 10.0\n";
    let scene = SceneFile::parse(text).unwrap().validate_with(&Limits { max_memory: 1e9 }).unwrap();
    let Scene::Beam { pipe, scene: bs, .. } = &scene else { panic!("a beam scene") };
    let n = 2 * bs.elements;
    let own = scene.instantiate(None).unwrap();
    let rest = (vec![0.0; n], vec![0.0; n]);
    let from_rest = scene.instantiate(Some(&rest)).unwrap();
    assert_eq!(own.u0, from_rest.u0);
    // Both steppers take the same first step: the same initial velocity.
    let (mut a, mut b) = (own.stepper, from_rest.stepper);
    for _ in 0..50 {
        a.step().unwrap();
        b.step().unwrap();
    }
    assert_eq!(a.displacement(), b.displacement());
    // The absolute velocity of a lifted state at rest is +A ω h(x)
    // (ũ_t = u_t + h φ'(0)), h written out here.
    let built = scene.instantiate(None).unwrap();
    let (ua, va) = built.absolute(&vec![0.0; n], &vec![0.0; n], 0.0);
    let (a_s, w) = pipe.support;
    assert!(ua.iter().all(|x| *x == 0.0));
    let mid = 2 * (bs.elements / 2 - 1);
    let x_mid = pipe.length * (bs.elements / 2) as f64 / bs.elements as f64;
    let y = x_mid / pipe.length;
    let h = 1.0 - 2.0 * y * y + 4.0 / 3.0 * y.powi(3) - y.powi(4) / 3.0;
    assert!((va[mid] - a_s * w * h).abs() < 1e-12, "absolute velocity of a lifted 0 is +A ω h: {} vs {}", va[mid], a_s * w * h);
}

/// Validation's build is the run's (`Ready`): the first instantiation from
/// the scene's own state takes it, later ones build anew; both must be the
/// same integrator, so every shipped scene (bar, beam with supports, loads,
/// several contacts and reductions, oscillator; schemes of every kind) steps
/// bit for bit alike from either, with the same start, tip, contacts and
/// lifting.
#[test]
fn the_validated_simulation_is_the_one_a_fresh_build_gives() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes");
    let mut names = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let mut file = SceneFile::parse(&std::fs::read_to_string(&p).unwrap()).unwrap();
        file.base = p.parent().map(|b| b.to_path_buf());
        let scene = file.validate_with(&Limits { max_memory: 1e9 }).unwrap();
        let (kept, fresh) = (scene.instantiate(None).unwrap(), scene.instantiate(None).unwrap());
        assert_eq!((&kept.u0, &kept.v0, kept.tip, kept.contacts()), (&fresh.u0, &fresh.v0, fresh.tip, fresh.contacts()), "{}", p.display());
        let n = kept.unknowns();
        assert_eq!(kept.absolute(&vec![0.0; n], &vec![0.0; n], 0.3), fresh.absolute(&vec![0.0; n], &vec![0.0; n], 0.3), "{}", p.display());
        let (mut a, mut b) = (kept.stepper, fresh.stepper);
        for _ in 0..200 {
            let (ra, rb) = (a.step(), b.step());
            assert_eq!(ra.is_ok(), rb.is_ok(), "{}", p.display());
            assert_eq!(a.displacement(), b.displacement(), "{}", p.display());
        }
        names.push(p.file_stem().unwrap().to_string_lossy().into_owned());
    }
    assert!(names.len() >= 20 && names.iter().any(|n| n.starts_with("beam")) && names.iter().any(|n| n == "oscillator"), "{names:?}");
}
