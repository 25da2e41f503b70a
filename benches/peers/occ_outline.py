"""OpenCASCADE's outline of a capsule (a sphere swept along a segment) from a perspective eye,
against geocert's silhouette of the same sweep.

Usage: occ_outline.py IN.json, where IN.json is
  {"a": [x, y, z], "b": [x, y, z], "radius": r, "eye": [x, y, z],
   "envelope": [[[x, y, z], ...], ...], "caps": [[[x, y, z], ...], ...]}
(geocert's envelope components and end-position contours as 3-D polylines).

The capsule is built as a cylinder fused with two spheres (BRepAlgoAPI_Fuse); HLRBRep_Algo with
a perspective HLRAlgo_Projector (viewing system at the capsule's midpoint, its Z axis towards
the eye, focus = the eye's distance, so that the eye sits at Focus·Z) gives the outline edges,
visible and hidden (OutLineVCompound, OutLineHCompound). geocert's points are projected by the
same projector (HLRAlgo_Projector.Project), and the two are compared in its view plane:
  occ_to_geocert: the largest distance from an OCC outline sample to geocert's polylines
                  (envelope and caps: the outline is made of both);
  envelope_to_occ: the largest distance from a geocert envelope vertex to OCC's outline
                  (geocert's caps are whole contours of the end spheres, partly inside the
                  capsule, which OCC does not draw).
and both against the closed form (the capsule's true outline from the eye: the two cylinder
lines where the sight line is tangent, (a − e)·ρ(θ) = −r for the radial direction ρ, and the
end spheres' contour circles, centre c + k(e − c), radius r√(1 − k), k = r²/|e − c|², sampled
densely): occ_to_closed_form, geocert_to_closed_form (every geocert vertex, caps included).
Distances in the view plane's units; diagonal is the outline's bounding-box diagonal there.
Prints one JSON object. Times: median of 5 runs of build + HLR.
"""
import json
import math
import sys
import time

from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakeSphere
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Pnt2d
from OCP.HLRAlgo import HLRAlgo_Projector
from OCP.HLRBRep import HLRBRep_Algo, HLRBRep_HLRToShape
from OCP.TopAbs import TopAbs_EDGE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS

SAMPLES_PER_EDGE = 200


def capsule(a, b, r):
    d = [b[i] - a[i] for i in range(3)]
    length = math.sqrt(sum(x * x for x in d))
    shape = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(*a), gp_Dir(*d)), r, length).Shape()
    for c in (a, b):
        fuse = BRepAlgoAPI_Fuse(shape, BRepPrimAPI_MakeSphere(gp_Pnt(*c), r).Shape())
        fuse.Build()
        shape = fuse.Shape()
    return shape


def projector(a, b, eye):
    mid = [(a[i] + b[i]) / 2 for i in range(3)]
    z = [eye[i] - mid[i] for i in range(3)]
    focus = math.sqrt(sum(x * x for x in z))
    return HLRAlgo_Projector(gp_Ax2(gp_Pnt(*mid), gp_Dir(*z)), focus)


def outline(shape, proj):
    algo = HLRBRep_Algo()
    algo.Add(shape)
    algo.Projector(proj)
    algo.Update()
    algo.Hide()
    return HLRBRep_HLRToShape(algo)


def edges_2d(hlr):
    polylines = []
    for compound in (hlr.OutLineVCompound(), hlr.OutLineHCompound()):
        if compound is None or compound.IsNull():
            continue
        ex = TopExp_Explorer(compound, TopAbs_EDGE)
        while ex.More():
            curve = BRepAdaptor_Curve(TopoDS.Edge(ex.Current()))
            u0, u1 = curve.FirstParameter(), curve.LastParameter()
            poly = []
            for k in range(SAMPLES_PER_EDGE + 1):
                p = curve.Value(u0 + (u1 - u0) * k / SAMPLES_PER_EDGE)
                poly.append((p.X(), p.Y()))
            polylines.append(poly)
            ex.Next()
    return polylines


def to_segments(polylines):
    return [(p[k], p[k + 1]) for p in polylines for k in range(len(p) - 1)]


def point_segment(q, s):
    (ax, ay), (bx, by) = s
    dx, dy = bx - ax, by - ay
    dd = dx * dx + dy * dy
    t = 0.0 if dd == 0 else max(0.0, min(1.0, ((q[0] - ax) * dx + (q[1] - ay) * dy) / dd))
    return math.hypot(q[0] - ax - t * dx, q[1] - ay - t * dy)


def farthest(points, segments):
    return max((min(point_segment(q, s) for s in segments) for q in points), default=float("nan"))


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def frame(w):
    """Two unit vectors perpendicular to the unit vector w and to each other."""
    helper = [1.0, 0.0, 0.0] if abs(w[0]) < 0.9 else [0.0, 1.0, 0.0]
    v1 = unit(cross(helper, w))
    return v1, cross(w, v1)


def closed_form(a, b, r, eye, n=4000):
    """The capsule's true outline from the eye, as 3-D polylines (a superset: whole circles)."""
    curves = []
    for c in (a, b):
        d = [eye[i] - c[i] for i in range(3)]
        k = r * r / sum(x * x for x in d)
        centre = [c[i] + k * d[i] for i in range(3)]
        radius = r * math.sqrt(1 - k)
        v1, v2 = frame(unit(d))
        curves.append([[centre[i] + radius * (math.cos(2 * math.pi * j / n) * v1[i]
                                              + math.sin(2 * math.pi * j / n) * v2[i])
                        for i in range(3)] for j in range(n + 1)])
    w = unit([b[i] - a[i] for i in range(3)])
    v1, v2 = frame(w)
    ae = [a[i] - eye[i] for i in range(3)]
    p, q = sum(ae[i] * v1[i] for i in range(3)), sum(ae[i] * v2[i] for i in range(3))
    # p cos θ + q sin θ = −r: θ = φ ± acos(−r / √(p² + q²)), φ = atan2(q, p).
    phi, h = math.atan2(q, p), math.acos(-r / math.hypot(p, q))
    for theta in (phi + h, phi - h):
        rho = [math.cos(theta) * v1[i] + math.sin(theta) * v2[i] for i in range(3)]
        curves.append([[a[i] + r * rho[i] for i in range(3)], [b[i] + r * rho[i] for i in range(3)]])
    return curves


def main():
    spec = json.load(open(sys.argv[1]))
    a, b, r, eye = spec["a"], spec["b"], spec["radius"], spec["eye"]
    times = []
    for _ in range(5):
        t = time.perf_counter()
        shape = capsule(a, b, r)
        proj = projector(a, b, eye)
        hlr = outline(shape, proj)
        occ = edges_2d(hlr)
        times.append(time.perf_counter() - t)
    times.sort()

    def project(p):
        q = gp_Pnt2d()
        proj.Project(gp_Pnt(*p), q)
        return (q.X(), q.Y())

    envelope = [[project(p) for p in c] for c in spec["envelope"]]
    caps = [[project(p) for p in c] for c in spec["caps"]]
    occ_points = [q for poly in occ for q in poly]
    xs = [q[0] for q in occ_points]
    ys = [q[1] for q in occ_points]
    diagonal = math.hypot(max(xs) - min(xs), max(ys) - min(ys)) if occ_points else float("nan")
    occ_to_geocert = farthest(occ_points, to_segments(envelope + caps))
    envelope_to_occ = farthest([q for c in envelope for q in c], to_segments(occ))
    truth = to_segments([[project(p) for p in c] for c in closed_form(a, b, r, eye)])
    occ_to_closed_form = farthest(occ_points, truth)
    geocert_to_closed_form = farthest([q for c in envelope + caps for q in c], truth)
    import OCP

    print(json.dumps({
        "version": getattr(OCP, "__version__", "unknown"),
        "median_s": times[len(times) // 2],
        "edges": len(occ),
        "diagonal": diagonal,
        "occ_to_geocert": occ_to_geocert,
        "envelope_to_occ": envelope_to_occ,
        "occ_to_closed_form": occ_to_closed_form,
        "geocert_to_closed_form": geocert_to_closed_form,
    }))


if __name__ == "__main__":
    main()
