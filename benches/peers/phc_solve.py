"""PHCpack's blackbox solver (Debian python3-phcpy) on the systems given as JSON on stdin.

Input: [{"polys": ["3*x1^2 - x2 + 1;", ...]}, ...] (integer coefficients: PHCpack's parser
takes no fractions). Output on stdout: one JSON list, per system {"seconds": wall time of
phcpy.solver.solve in this process, "real": [[x1, x2, ...], ...]} with the solutions whose
imaginary parts are all below 1e-8 (PHCpack's solutions are approximate and uncertified).
solve() needs verbose=True to return its solutions (it returns nothing otherwise), so its own
printing is sent to /dev/null at the file-descriptor level.
"""
import json
import os
import sys
import time

from phcpy.solver import solve
from phcpy.solutions import strsol2dict


def quiet_solve(polys):
    sys.stdout.flush()
    saved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    try:
        start = time.perf_counter()
        sols = solve(polys, verbose=True)
        seconds = time.perf_counter() - start
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(null)
        os.close(saved)
    return sols or [], seconds


def main():
    systems = json.load(sys.stdin)
    out = []
    for system in systems:
        polys = system["polys"]
        n = len(polys)
        sols, seconds = quiet_solve(polys)
        real = []
        for s in sols:
            d = strsol2dict(s)
            xs = [d.get("x%d" % (i + 1)) for i in range(n)]
            if any(x is None for x in xs):
                continue
            if all(abs(complex(x).imag) < 1e-8 for x in xs):
                real.append([complex(x).real for x in xs])
        out.append({"seconds": seconds, "real": real})
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
