"""A 10^6-step run from Python against the same run from the command line,
whole processes timed from outside (start-up, scene reading and the copy of
the arrays included): the Signorini–Dirichlet bar, 100 elements, mod mass,
Newmark-CN, dx/dt = 10 (dt = 10^-3), T = 10^3, exact norms and the energy
every step; and the same with 1000 elements (dt = 10^-4, T = 100).

    python python/benches/run_vs_cli.py [path/to/signorini] [repeats]

Prints the median wall time of each and their ratio, per mesh. The command writes
its series every 1000 steps and no plots; Python keeps every level of every
array in memory (t, tip, contact displacement and force, energy, λ).
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

SCENE = """[bar]
benchmark = "bar-dirichlet"
elements = {m}
mass = "mod"
scheme = "newmark-cn"
ratio = 10.0
t_end = {t_end}

[output]
every = 1000
plots = false
"""

PY = "import signorini, sys; r = signorini.run(sys.argv[1]); assert r.steps == 1_000_000 and r.norms is not None"


def main():
    exe = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "../../target/release/signorini")
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    for m, t_end in ((100, 1000.0), (1000, 100.0)):
        print(f"m = {m}:")
        bench(exe, repeats, SCENE.format(m=m, t_end=t_end))


def bench(exe, repeats, text):
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "bench.toml")
        with open(scene, "w") as f:
            f.write(text)
        cmds = {"cli": [exe, "run", scene, "--out", os.path.join(tmp, "out"), "--clean"], "python": [sys.executable, "-c", PY, scene]}
        times = {k: [] for k in cmds}
        for _ in range(repeats + 1):  # the first round warms the caches
            for k, c in cmds.items():
                t = time.perf_counter()
                subprocess.run(c, check=True, capture_output=True)
                times[k].append(time.perf_counter() - t)
        med = {k: statistics.median(v[1:]) for k, v in times.items()}
    print(f"  cli    {med['cli']:.3f} s (median of {repeats})")
    print(f"  python {med['python']:.3f} s (median of {repeats})")
    print(f"  python/cli = {med['python'] / med['cli']:.3f}")


if __name__ == "__main__":
    main()
