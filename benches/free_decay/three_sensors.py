"""Writes a three-accelerometer hammer test for benches/free_decay/run.sh (the speed
target: a 65,536-sample, 3-channel ringdown in under 0.2 s end to end) into DIR:
sensors.npz and sensors.toml.

The shipped hammer test (models/data/ringdown/hammer.npz: mode 1 at 80 Hz under
viscous + 5|v|^1.5, mode 2 at 296 Hz, half-sine hammer) is read by three sensors with
the shape of a fixed-free 3-DOF chain's first mode, plus a third mode at 420 Hz with a
shape orthogonal to it, and 0.5 % noise per channel. Only the timing is of interest
here; tests/free_decay_sensors.rs checks the accuracy.

    python3 benches/free_decay/three_sensors.py DIR
"""

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1])
hammer = np.load(ROOT / "models/data/ringdown/hammer.npz")
a1, force = hammer["acceleration"], hammer["force"]
k = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
values, shapes = np.linalg.eigh(k)
phi1, phi3 = shapes[:, 0] * np.sign(shapes[0, 0]), shapes[:, 2]
step = 1.0 / 12_800.0
t = np.arange(a1.size) * step
w3 = 2 * np.pi * 420.0
start = t >= 0.0205
a3 = np.where(start, -(w3**2) * 5e-4 * np.exp(-0.003 * w3 * (t - 0.0205)) * np.sin(w3 * (t - 0.0205)), 0.0)
rng = np.random.default_rng(3)
channels = {}
for j in range(3):
    y = phi1[j] * a1 + phi3[j] * a3
    channels[f"a{j + 1}"] = y + rng.normal(0.0, 0.005 * np.sqrt(np.mean(y**2)), y.size)
np.savez(out / "sensors.npz", force=force, **channels)
model = (ROOT / "models/ringdown.toml").read_text()
model = model.replace('"data/ringdown/hammer.npz"', '"sensors.npz"')
model = model.replace('accelerations = ["acceleration"]', 'accelerations = ["a1", "a2", "a3"]')
model += "mode_shape = [{:.12g}, {:.12g}, {:.12g}]\n".format(*phi1)
(out / "sensors.toml").write_text(model)
(out / "sensors_pod.toml").write_text(model.replace(
    "mode_shape = [{:.12g}, {:.12g}, {:.12g}]\n".format(*phi1), 'modal_filter = "pod"\n'))
