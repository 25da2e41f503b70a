#!/usr/bin/env python3
"""Gmsh's Bézier-based Jacobian bounds on the same cells geocert checks.

Input (argv[1]): JSON {"cells": [[[x,y,z] * 64], ...]} — tricubic Bézier control nets on
[0,1]^3, u fastest. Each net is evaluated at the 64 reference nodes of Gmsh's cubic
hexahedron (element type 92, nodes on [-1,1]^3), giving the same tricubic map as a
64-node Lagrange element. Gmsh then computes "minDetJac" (its Bézier-bound minimum of the
Jacobian determinant, in [-1,1]^3 coordinates; times 8 for [0,1]^3), single-threaded.

Output (stdout): JSON {"gmsh": version, "cells": N, "runs": R, "seconds": [per run],
"min_det": [per cell, [0,1]^3 scale]}.
"""
import json
import sys
import time
from math import comb

import gmsh
import numpy as np


def bernstein(n, i, t):
    return comb(n, i) * t**i * (1.0 - t) ** (n - i)


def main():
    data = json.load(open(sys.argv[1]))
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    nets = np.array(data["cells"], dtype=float)  # N x 64 x 3
    n = len(nets)
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    _, _, _, nn, ref, _ = gmsh.model.mesh.getElementProperties(92)
    ref = np.array(ref).reshape(nn, 3)
    t = (ref + 1.0) / 2.0  # to [0,1]^3
    # Basis matrix: node k, control point (i,j,l) with i fastest.
    basis = np.zeros((nn, 64))
    for k in range(nn):
        for l in range(4):
            for j in range(4):
                for i in range(4):
                    basis[k, i + 4 * j + 16 * l] = (
                        bernstein(3, i, t[k, 0]) * bernstein(3, j, t[k, 1]) * bernstein(3, l, t[k, 2])
                    )
    nodes = np.einsum("kc,ncd->nkd", basis, nets)  # N x 64 x 3
    gmsh.model.add("cells")
    tag = gmsh.model.addDiscreteEntity(3)
    node_tags = np.arange(1, n * nn + 1)
    gmsh.model.mesh.addNodes(3, tag, node_tags.tolist(), nodes.reshape(-1).tolist())
    elem_tags = np.arange(1, n + 1)
    gmsh.model.mesh.addElementsByType(tag, 92, elem_tags.tolist(), node_tags.tolist())
    seconds = []
    q = None
    for _ in range(runs):
        start = time.perf_counter()
        q = gmsh.model.mesh.getElementQualities(elem_tags.tolist(), "minDetJac")
        seconds.append(time.perf_counter() - start)
    version = gmsh.__version__
    gmsh.finalize()
    json.dump(
        {
            "gmsh": version,
            "cells": n,
            "runs": runs,
            "seconds": seconds,
            "min_det": [8.0 * v for v in q],
        },
        sys.stdout,
    )


if __name__ == "__main__":
    main()
