//! scratch
use faer::linalg::solvers::Solve;
use signorini_orbits::*;
use std::time::Instant;

fn doc(omega: f64, amp: f64, extra: &str) -> toml::Table {
    format!("[beam]\nscene = \"fig2\"\nscheme = \"event-driven\"\n{extra}\n[support]\namplitude = {amp}\nomega = {omega}\n").parse().unwrap()
}

fn linear_orbit(model: &Model, period: f64) -> Vec<f64> {
    let mut dy = model.dynamics().clone();
    for c in dy.contacts.iter_mut() {
        c.bounds.lo = -1e6;
        c.bounds.hi = 1e6;
    }
    let free = Model::new(dy, 0.0).unwrap();
    let n = free.dim();
    let x0 = vec![0.0; n];
    let img = free.flow(0.0, &x0, period, true).unwrap();
    let j = img.jacobian.unwrap();
    let a = faer::Mat::from_fn(n, n, |r, c| if r == c { 1.0 } else { 0.0 } - j[(r, c)]);
    let rhs = faer::Mat::from_fn(n, 1, |r, _| img.x[r]);
    let s = a.partial_piv_lu().solve(&rhs);
    (0..n).map(|i| s[(i, 0)]).collect()
}

fn scan(extra: &str, lo: f64, hi: f64, n: usize) {
    for k in 0..=n {
        let omega = lo + (hi - lo) * k as f64 / n as f64;
        let (fam, _) = SceneFamily::new(doc(omega, 0.2, extra), "support.omega", 1).unwrap();
        let b = fam.build(omega).unwrap();
        let x = linear_orbit(&b.model, b.horizon);
        let mut dy = b.model.dynamics().clone();
        let tipdof = dy.contacts[0].dof;
        for c in dy.contacts.iter_mut() {
            c.bounds.lo = -1e6;
            c.bounds.hi = 1e6;
        }
        let free = Model::new(dy, 0.0).unwrap();
        let mut amp: f64 = 0.0;
        for i in 1..=512 {
            let img = free.flow(0.0, &x, b.horizon * i as f64 / 512.0, false).unwrap();
            let (q, _) = free.settle(0.0, &img.x).unwrap();
            amp = amp.max(q[tipdof].abs());
        }
        println!("{omega:8.3} amp {amp:10.6}");
    }
}

fn newton_amp(extra: &str, omega: f64, amps: &[f64]) {
    for &a in amps {
        let (fam, _) = SceneFamily::new(doc(omega, a, extra), "support.amplitude", 1).unwrap();
        let b = fam.build(a).unwrap();
        let x = linear_orbit(&b.model, b.horizon);
        let t0 = Instant::now();
        let r = periodic_orbit(&b.model, 0.0, b.horizon, &x, &Newton { tol: 1e-11, ..Newton::default() });
        match r {
            Ok(o) => {
                println!("A {a} ok: impacts {} releases {} mu_max {:.6} it {} mus {:?} ({:.2}s)", o.impacts(), o.releases(), o.mu_max(), o.iterations, &o.multipliers[..4], t0.elapsed().as_secs_f64())
            }
            Err(e) => println!("A {a} err {e} ({:.2}s)", t0.elapsed().as_secs_f64()),
        }
    }
}

fn newton_dbg(extra: &str, omega: f64, a: f64) {
    let (fam, _) = SceneFamily::new(doc(omega, a, extra), "support.amplitude", 1).unwrap();
    let b = fam.build(a).unwrap();
    let mut x = linear_orbit(&b.model, b.horizon);
    let n = x.len();
    for it in 0..15 {
        let img = b.model.flow(0.0, &x, b.horizon, true).unwrap();
        let g: Vec<f64> = img.x.iter().zip(&x).map(|(p, q)| p - q).collect();
        let res = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let ni = img.events.len();
        let j = img.jacobian.unwrap();
        let mus = eigenvalues(&j).unwrap();
        println!(
            "it {it} res {res:e} events {ni} {:?} mu_max {:.6} margin {:e}",
            img.events.iter().map(|e| (e.kind.name(), e.t, e.velocity_before)).collect::<Vec<_>>(),
            mus[0].norm(),
            b.model.margin(0.0, &x, b.horizon).unwrap()
        );
        let am = faer::Mat::from_fn(n, n, |r, c| j[(r, c)] - if r == c { 1.0 } else { 0.0 });
        let rhs = faer::Mat::from_fn(n, 1, |r, _| -g[r]);
        let st = am.partial_piv_lu().solve(&rhs);
        for i in 0..n {
            x[i] += st[(i, 0)];
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args[1] == "dbg" {
        let extra = args[2].replace("\\n", "\n");
        newton_dbg(&extra, args[3].parse().unwrap(), args[4].parse().unwrap());
        return;
    }
    if args[1] == "amp" {
        let extra = args[2].replace("\\n", "\n");
        let v: Vec<f64> = args[4..].iter().map(|s| s.parse().unwrap()).collect();
        newton_amp(&extra, args[3].parse().unwrap(), &v);
        return;
    }
    if args[1] == "scan" {
        let extra = args[2].replace("\\n", "\n");
        scan(&extra, args[3].parse().unwrap(), args[4].parse().unwrap(), args[5].parse().unwrap());
        return;
    }
    let extra = args[1].replace("\\n", "\n");
    let from: f64 = args[2].parse().unwrap();
    let to: f64 = args[3].parse().unwrap();
    let (fam, _) = SceneFamily::new(doc(from, 0.2, &extra), "support.omega", 1).unwrap();
    let b = fam.build(from).unwrap();
    let x = linear_orbit(&b.model, b.horizon);
    let t0 = Instant::now();
    let mut opts = ContinuationOptions::new(from, to);
    opts.max_points = 400;
    let br = continuation_watched(&fam, &x, &opts, &mut |p| {
        eprintln!("{:.6} imp {} rel {} mu {:.6} t {:.1}", p.param, p.orbit.impacts(), p.orbit.releases(), p.orbit.mu_max(), t0.elapsed().as_secs_f64());
        true
    });
    match br {
        Ok(br) => {
            println!("{} points, end: {}", br.points.len(), br.end);
            for f in &br.bifurcations {
                println!("  {} at {:.10} mu {} impacts {:?} releases {:?}", f.kind.name(), f.param, f.mu, f.impacts, f.releases);
            }
        }
        Err(e) => println!("error {e}"),
    }
    println!("wall {:.2}", t0.elapsed().as_secs_f64());
}
