#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Import time and the cost of a binding call against the C++ work it wraps (BENCHMARKS.md).

    PYTHONPATH=build/release/python /usr/bin/python3 python/bench_overhead.py
"""
import subprocess
import sys
import time

import numpy as np


def best(f, repeat=7, number=1):
    """Best time of `number` calls over `repeat` runs, per call [s]."""
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(number):
            f()
        out.append((time.perf_counter() - t) / number)
    return min(out)


def main():
    code = "import time; t = time.perf_counter(); import {}; print(time.perf_counter() - t)"
    imports = [float(subprocess.check_output([sys.executable, "-c", code.format(m)]))
               for m in ["translucent"] * 5]
    numpy_import = [float(subprocess.check_output([sys.executable, "-c", code.format("numpy")]))
                    for _ in range(5)]
    print(f"import translucent: {1e3 * min(imports):.1f} ms (best of 5; numpy alone "
          f"{1e3 * min(numpy_import):.1f} ms, which translucent imports)")
    import translucent as t

    p = t.model("dipole").profiles(t.preset("Marble").medium())
    one = np.array([1.0])
    big = np.linspace(0.01, 10, 1_000_000)
    per_elem = best(lambda: p.R(big), repeat=5) / big.size / 3  # per R(r) evaluation
    small = best(lambda: p.R(one), number=20000)
    print(f"Profiles.R, 1e6 radii: {1e9 * per_elem:.1f} ns per R(r) evaluation (3 per radius)")
    print(f"Profiles.R, 1 radius: {1e6 * small:.2f} us per call; C++ work 3 x "
          f"{1e9 * per_elem:.1f} ns: binding overhead {1e6 * (small - 3 * per_elem):.2f} us")
    prof = best(lambda: t.profile("dipole", one, material="Marble"), number=5000)
    print(f"profile('dipole', [1.0], preset='Marble'): {1e6 * prof:.2f} us per call "
          "(makes the medium and the three profiles each call, as the CLI's profile does)")
    med = best(lambda: t.Medium(), number=20000)
    print(f"Medium(): {1e6 * med:.2f} us per call")
    for photons in (1e4, 1e6):
        wall, cpp = [], []
        for _ in range(5):
            s = time.perf_counter()
            r = t.pathtrace_slab(material="Marble", channel="r", photons=photons, threads=2)
            wall.append(time.perf_counter() - s)
            cpp.append(r["seconds"])
        i = int(np.argmin(wall))
        print(f"pathtrace_slab {photons:.0e} photons: {1e3 * wall[i]:.2f} ms wall, traceSlab "
              f"{1e3 * cpp[i]:.2f} ms: binding {1e3 * (wall[i] - cpp[i]):.3f} ms")
    img = t.pathtrace_sphere(photons=1e4, width=512, height=512)
    s = time.perf_counter()
    img = t.pathtrace_sphere(photons=1e4, width=512, height=512)
    wall = time.perf_counter() - s
    print(f"pathtrace_sphere 512x512, 1e4 photons: {1e3 * wall:.1f} ms wall, tracing "
          f"{1e3 * img['seconds']:.1f} ms (six 512x512x3 float32 arrays handed over)")


if __name__ == "__main__":
    main()
