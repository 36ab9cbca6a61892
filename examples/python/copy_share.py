"""The copy of a 100-DOF x 1e5-sample NumPy record into dampid's layout against the
identification of it (the Python-side share of the overhead): python examples/python/copy_share.py"""
import time, numpy as np, dampid
n, N, h, w = 100, 100_000, 0.05, 0.618
t = np.arange(N) * h; j = np.arange(n)
x = (1.0 + j / n) * np.sin(w * t[:, None] + 0.01 * j); f = np.cos(w * t)
model = dampid.Model.from_toml(f"""
dofs = {n}
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[[terms]]
kind = "law"
law = "quadratic"
elements = "each_dof"
coefficient = "d"
""")
for _ in range(2):
    s = time.perf_counter(); r = dampid.Record(x=x, step=h, forces=[(f, 1)], period=2*np.pi/w); a = time.perf_counter() - s
    s = time.perf_counter(); rep = dampid.identify(model, [r]); b = time.perf_counter() - s
    print(f"record from numpy {a:.3f} s, identify {b:.3f} s, copy share {100*a/b:.1f} %", flush=True)
