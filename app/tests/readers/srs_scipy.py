"""An independent shock response spectrum: each single-degree-of-freedom oscillator of the band,
H(s) = (2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2) from base acceleration to absolute
acceleration, marched by SciPy's lsim (a state-space solution with the input linear between its
samples) over the history and one natural period of zeros after it; its maximax read at the
samples. Prints one JSON object {"frequencies": [...], "srs": [...]}.

Usage: srs_scipy.py PROBE.csv SRS.csv COLUMN Q   (COLUMN: 1, 2, 3 for x, y, z)
"""

import json
import sys

import numpy as np
from scipy import signal


def main():
    probe, srs, column, q = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
    history = np.loadtxt(probe, delimiter=",", skiprows=1)
    t, a = history[:, 0], history[:, column]
    dt = t[1] - t[0]
    freqs = np.loadtxt(srs, delimiter=",", skiprows=1)[:, 0]
    zeta = 0.5 / q
    out = []
    for f in freqs:
        w = 2.0 * np.pi * f
        tail = int(np.ceil(1.0 / (f * dt))) + 2
        u = np.concatenate([a, np.zeros(tail)])
        times = dt * np.arange(len(u))
        system = signal.lti([2.0 * zeta * w, w * w], [1.0, 2.0 * zeta * w, w * w])
        _, y, _ = signal.lsim(system, u, times)
        out.append(float(np.max(np.abs(y))))
    print(json.dumps({"frequencies": freqs.tolist(), "srs": out}))


if __name__ == "__main__":
    main()
