//! Approximation quality of a decimated height field or planar FEM mesh: at every node of
//! the original, the difference between its height (z) or scalar and the decimated mesh's
//! linear interpolant at the same xy position (the node located by a uniform grid over the
//! decimated triangles' xy bounding boxes).

use crate::mesh::Mesh;

/// Max and RMS errors over the original's nodes.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Errors {
    /// Largest height (or distance) error.
    pub max_height: f64,
    /// Root mean square of the height (or distance) errors.
    pub rms_height: f64,
    /// `None` without a scalar field.
    pub max_scalar: Option<f64>,
    /// Root mean square of the scalar errors (`None` without a scalar field).
    pub rms_scalar: Option<f64>,
    /// Nodes outside every decimated triangle in xy (0 for a decimation that keeps the
    /// border; then the node is measured against the nearest triangle found).
    pub unlocated: usize,
}

/// Running max and sum of squares of the height (or distance) and scalar errors.
#[derive(Default)]
struct Tally {
    max_height: f64,
    sum_height: f64,
    max_scalar: f64,
    sum_scalar: f64,
}

impl Tally {
    fn height(&mut self, d: f64) {
        self.max_height = self.max_height.max(d);
        self.sum_height += d * d;
    }

    fn scalar(&mut self, d: f64) {
        self.max_scalar = self.max_scalar.max(d);
        self.sum_scalar += d * d;
    }

    /// The errors over `nodes` nodes (scalar ones when `scalars`).
    fn finish(self, nodes: usize, scalars: bool, unlocated: usize) -> Errors {
        let n = nodes.max(1) as f64;
        Errors {
            max_height: self.max_height,
            rms_height: (self.sum_height / n).sqrt(),
            max_scalar: scalars.then_some(self.max_scalar),
            rms_scalar: scalars.then(|| (self.sum_scalar / n).sqrt()),
            unlocated,
        }
    }
}

/// Interpolation errors of `decimated` against `original`, both in the xy plane. The
/// decimated mesh's scalar field is read when the original has one.
pub fn xy_errors(original: &Mesh, decimated: &Mesh) -> Errors {
    let tris = &decimated.triangles;
    let pv = &decimated.vertices;
    if tris.is_empty() {
        return Errors::default();
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in pv {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let cells = ((tris.len() as f64).sqrt().ceil() as usize).clamp(1, 2048);
    let size = [
        ((hi[0] - lo[0]) / cells as f64).max(f64::MIN_POSITIVE),
        ((hi[1] - lo[1]) / cells as f64).max(f64::MIN_POSITIVE),
    ];
    let cell =
        |x: f64, k: usize| (((x - lo[k]) / size[k]).floor().max(0.0) as usize).min(cells - 1);
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); cells * cells];
    for (t, tri) in tris.iter().enumerate() {
        let ps = tri.map(|i| pv[i as usize]);
        let (x0, x1) = (
            ps.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
            ps.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
        );
        let (y0, y1) = (
            ps.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
            ps.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
        );
        for j in cell(y0, 1)..=cell(y1, 1) {
            for i in cell(x0, 0)..=cell(x1, 0) {
                grid[j * cells + i].push(t as u32);
            }
        }
    }
    let scalars = original.scalars.as_ref().zip(decimated.scalars.as_ref());
    let mut tally = Tally::default();
    let mut unlocated = 0;
    for (v, p) in original.vertices.iter().enumerate() {
        let bucket = &grid[cell(p[1], 1) * cells + cell(p[0], 0)];
        let mut best: Option<(f64, u32, [f64; 3])> = None;
        for &t in bucket {
            let [a, b, c] = tris[t as usize].map(|i| pv[i as usize]);
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if area <= 0.0 {
                continue;
            }
            let l0 = ((b[0] - p[0]) * (c[1] - p[1]) - (b[1] - p[1]) * (c[0] - p[0])) / area;
            let l1 = ((c[0] - p[0]) * (a[1] - p[1]) - (c[1] - p[1]) * (a[0] - p[0])) / area;
            let l2 = 1.0 - l0 - l1;
            let min = l0.min(l1).min(l2);
            if best.is_none_or(|b| min > b.0) {
                best = Some((min, t, [l0, l1, l2]));
            }
        }
        let Some((min, t, l)) = best else {
            unlocated += 1;
            continue;
        };
        if min < -1e-9 {
            unlocated += 1;
        }
        let tri = tris[t as usize];
        let z: f64 = (0..3).map(|k| l[k] * pv[tri[k] as usize][2]).sum();
        tally.height((p[2] - z).abs());
        if let Some((so, sd)) = scalars {
            let f: f64 = (0..3).map(|k| l[k] * sd.values[tri[k] as usize]).sum();
            tally.scalar((so.values[v] - f).abs());
        }
    }
    tally.finish(original.vertices.len(), scalars.is_some(), unlocated)
}

/// The closest point of triangle `abc` to `p` (Ericson, *Real-Time Collision Detection*,
/// 5.1.5: Voronoi regions of the vertices, edges and face).
pub fn closest_point_on_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let at = |o: [f64; 3], d: [f64; 3], t: f64| [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return at(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return at(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return at(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom == 0.0 || !denom.is_finite() {
        // Degenerate (zero-area) triangle: the nearest of its three edges' closest points.
        let seg = |u: [f64; 3], v: [f64; 3]| {
            let d = sub(v, u);
            let l = dot(d, d);
            let t = if l > 0.0 {
                (dot(sub(p, u), d) / l).clamp(0.0, 1.0)
            } else {
                0.0
            };
            at(u, d, t)
        };
        let cands = [seg(a, b), seg(b, c), seg(c, a)];
        return cands
            .into_iter()
            .min_by(|x, y| dot(sub(p, *x), sub(p, *x)).total_cmp(&dot(sub(p, *y), sub(p, *y))))
            .expect("three candidates");
    }
    let (v, w) = (vb / denom, vc / denom);
    [
        a[0] + ab[0] * v + ac[0] * w,
        a[1] + ab[1] * v + ac[1] * w,
        a[2] + ab[2] * v + ac[2] * w,
    ]
}

/// Closest-point queries on a triangle surface: a bounding-volume hierarchy over its
/// triangles in flat arrays (median splits along the longest axis, at most four
/// triangles per leaf, the leaves' corners stored in leaf order), searched nearest box
/// first with pruning by the best distance found; every box also holds the cone of its
/// triangles' normals, so that searches for triangles facing one way skip boxes facing the
/// other ([`faces_against`](Self::faces_against)); with
/// [`with_clearances`](Self::with_clearances), most facing tests from a seed vertex end at
/// its leaf.
pub struct ClosestPoints {
    nodes: Vec<BvhNode>,
    /// Every node's cone of unit triangle normals ([`Cone`]).
    cones: Vec<Cone>,
    /// Per mesh vertex, the leaf holding one of its triangles (`u32::MAX` for none).
    vertex_leaf: Vec<u32>,
    /// The triangles' corners in leaf order.
    corners: Vec<[[f64; 3]; 3]>,
    /// The mesh's triangle index of each entry of `corners`.
    ids: Vec<u32>,
    /// Per node, its clearance ([`ClosestPoints::with_clearances`]; empty until computed).
    clearance: Vec<f64>,
    /// An absolute bound on the rounding of the distances the clearances are compared with.
    slack: f64,
}

/// The cosine of the half-angle of a leaf's *aligned* cone: the triangles whose unit normal
/// lies within 50° of the axis of the leaf's own cone of normals.
const ALIGNED_COS: f64 = 0.642_787_609_686_539_3;

/// [`ALIGNED_COS`] squared, rounded up (the test it makes is then, if anything, stricter).
const ALIGNED_COS2: f64 = 0.413_175_911_166_535_1;

/// The cosine of the largest angle (35°) between a tested triangle's normal and a leaf's axis
/// for which the leaf's clearance settles the facing test: with the aligned cone's 50°, every
/// aligned triangle's normal lies within 85° of the tested one, so their dot product is
/// positive far beyond rounding (`cos 85° ≈ 0.087`).
const QUERY_COS: f64 = 0.819_152_044_288_991_8;

/// The clearance searched up to, as a share of the root box's diagonal: the clearance of a
/// leaf with no other triangle that near is this (no search goes farther).
const CLEARANCE_REACH: f64 = 0.05;

/// The clearance searched up to, in diagonals of the leaf's own box.
const LEAF_REACH: f64 = 3.0;

/// Triangles per leaf at most.
const LEAF: usize = 4;

/// Triangles from which [`ClosestPoints::new`] builds the root's two subtrees side by side.
const PARALLEL_BUILD: usize = 65_536;

/// A box of the hierarchy: a leaf holds `corners[start..start + count]`; an inner node
/// (`count == 0`) has its first child right after it and its second at `start`.
#[derive(Clone, Copy)]
struct BvhNode {
    lo: [f64; 3],
    hi: [f64; 3],
    start: u32,
    count: u32,
}

impl BvhNode {
    /// The inner node over two children (`start`: the second child's index).
    fn union(l: &BvhNode, r: &BvhNode, start: u32) -> BvhNode {
        BvhNode {
            lo: std::array::from_fn(|k| l.lo[k].min(r.lo[k])),
            hi: std::array::from_fn(|k| l.hi[k].max(r.hi[k])),
            start,
            count: 0,
        }
    }

    /// The box's centre.
    fn centre(&self) -> [f64; 3] {
        std::array::from_fn(|k| 0.5 * (self.lo[k] + self.hi[k]))
    }

    /// The length of the box's diagonal.
    fn diagonal(&self) -> f64 {
        (0..3)
            .map(|k| (self.hi[k] - self.lo[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// The squared distance from `p` to the box (0 inside).
    #[inline]
    fn distance2(&self, p: [f64; 3]) -> f64 {
        let mut d2 = 0.0;
        for ((lo, hi), x) in self.lo.iter().zip(&self.hi).zip(p) {
            let d = (lo - x).max(x - hi).max(0.0);
            d2 += d * d;
        }
        d2
    }
}

/// The answer of [`ClosestPoints::query`].
#[derive(Clone, Copy, Debug)]
pub struct Closest {
    /// Distance from the point to the surface.
    pub distance: f64,
    /// The closest triangle.
    pub triangle: u32,
    /// The closest point on it.
    pub point: [f64; 3],
}

impl ClosestPoints {
    /// The hierarchy over `mesh`'s triangles; `None` when `mesh` has no triangles.
    pub fn new(mesh: &Mesh) -> Option<ClosestPoints> {
        let (pv, tris) = (&mesh.vertices, &mesh.triangles);
        if tris.is_empty() {
            return None;
        }
        let mut items: Vec<(u32, [f64; 3])> = tris
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let c = tri.map(|i| pv[i as usize]);
                (
                    t as u32,
                    std::array::from_fn(|k| c[0][k] + c[1][k] + c[2][k]),
                )
            })
            .collect();
        let empty = |n: usize| ClosestPoints {
            nodes: Vec::with_capacity(2 * n / LEAF + 1),
            cones: Vec::with_capacity(2 * n / LEAF + 1),
            vertex_leaf: Vec::new(),
            corners: Vec::with_capacity(n),
            ids: Vec::with_capacity(n),
            clearance: Vec::new(),
            slack: 0.0,
        };
        let mut cp = empty(tris.len());
        if items.len() <= PARALLEL_BUILD {
            cp.build(mesh, &mut items);
        } else {
            // The root here, its two subtrees built side by side and appended (the same
            // hierarchy as one depth-first build).
            let mid = split(&mut items);
            let (first, second) = items.split_at_mut(mid);
            let (left, right) = crate::par::join(
                || {
                    let mut sub = empty(first.len());
                    sub.build(mesh, first);
                    sub
                },
                || {
                    let mut sub = empty(second.len());
                    sub.build(mesh, second);
                    sub
                },
            );
            cp.nodes.push(BvhNode::union(
                &left.nodes[0],
                &right.nodes[0],
                1 + left.nodes.len() as u32,
            ));
            cp.cones.push(left.cones[0].merge(&right.cones[0]));
            cp.append(left);
            cp.append(right);
        }
        cp.vertex_leaf = vec![u32::MAX; pv.len()];
        for (at, node) in cp.nodes.iter().enumerate() {
            let s = node.start as usize;
            if node.count > 0 {
                for &t in &cp.ids[s..s + node.count as usize] {
                    for &i in &tris[t as usize] {
                        cp.vertex_leaf[i as usize] = at as u32;
                    }
                }
            }
        }
        Some(cp)
    }

    /// Computes every leaf's *clearance*, which lets [`faces_against_from`] settle most
    /// tests at the seed leaf without a search from the root. A leaf's clearance `R` is the
    /// distance from its box's centre `p` to the nearest triangle that is not *aligned* with
    /// it (unit normal more than 50° from the axis of the leaf's cone of normals, or none that
    /// can be normalised), searched up to three diagonals of the leaf's box (and at most 5 % of
    /// the root box's diagonal); a leaf with none that near gets that reach. Every
    /// triangle nearer than `R` to `p` is aligned, so a triangle whose normal lies within 35°
    /// of the axis faces along every one of them (85° apart at most). The answers of every
    /// search are unchanged; the leaves' searches run on all cores.
    ///
    /// [`faces_against_from`]: Self::faces_against_from
    pub fn with_clearances(mut self) -> ClosestPoints {
        use crate::par::prelude::*;
        let root = self.nodes[0];
        let diagonal = root.diagonal();
        let magnitude = root
            .lo
            .iter()
            .chain(&root.hi)
            .fold(diagonal, |m, x| m.max(x.abs()));
        // Far above the rounding of closest points and distances (about 1e-15 of the
        // coordinates' magnitude), far below any distance that matters.
        self.slack = 1e-10 * magnitude;
        let reach = CLEARANCE_REACH * diagonal;
        // Only the leaves searches start from (a vertex's leaf) need one.
        let mut seed = vec![false; self.nodes.len()];
        for &l in &self.vertex_leaf {
            if let Some(s) = seed.get_mut(l as usize) {
                *s = true;
            }
        }
        let clearance: Vec<f64> = (0..self.nodes.len())
            .into_par_iter()
            .map(|n| {
                let node = self.nodes[n];
                let cone = self.cones[n];
                if !seed[n] || node.count == 0 || !(reach.is_finite() && cone.cos <= 1.0) {
                    return 0.0;
                }
                let reach = reach.min(LEAF_REACH * node.diagonal());
                let axis = cone.axis;
                let centre = node.centre();
                // Aligned: `m·axis ≥ cos·|m|`, squared (no root); a triangle without area
                // faces no way, and no test counts it; one whose squares overflow or
                // underflow counts as not aligned.
                let unaligned = |j: usize| {
                    let [a, b, c] = self.corners[j];
                    let m = crate::mesh::area_vector(a, b, c);
                    if m == [0.0; 3] {
                        return false;
                    }
                    let (d, l2) = (dot3(m, axis), dot3(m, m));
                    !(d > 0.0 && l2 > 1e-300 && l2 < 1e300 && d * d >= ALIGNED_COS2 * l2)
                };
                // Boxes whose whole cone is certainly inside the aligned one are skipped.
                let may_hold = |m: u32| !self.cones[m as usize].within(axis, ALIGNED_COS);
                let mut best = Best::new(centre);
                best.best2 = reach * reach;
                self.descend_from(centre, 0, &mut best, &unaligned, &may_hold);
                best.best2.min(reach * reach).sqrt()
            })
            .collect();
        self.clearance = clearance;
        self
    }

    /// Whether the seed leaf's clearance proves that no triangle facing against the unit
    /// normal `unit` lies nearer to `centroid` than `reach`
    /// ([`with_clearances`](Self::with_clearances)).
    fn clear_within(&self, leaf: u32, centroid: [f64; 3], unit: [f64; 3], reach: f64) -> bool {
        let Some(&r) = self.clearance.get(leaf as usize) else {
            return false;
        };
        let node = self.nodes[leaf as usize];
        let cone = self.cones[leaf as usize];
        if !(r > 0.0 && dot3(unit, cone.axis) >= QUERY_COS) {
            return false;
        }
        // The same centre the clearance was measured from.
        let centre = node.centre();
        let off: f64 = (0..3)
            .map(|k| (centroid[k] - centre[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        off + reach + 2.0 * self.slack < r * (1.0 - 1e-9)
    }

    /// Appends the hierarchy `sub` (built on its own) as the next subtree, its node and
    /// corner indices shifted.
    fn append(&mut self, sub: ClosestPoints) {
        let (nodes, corners) = (self.nodes.len() as u32, self.corners.len() as u32);
        self.nodes.extend(sub.nodes.into_iter().map(|n| BvhNode {
            start: n.start + if n.count > 0 { corners } else { nodes },
            ..n
        }));
        self.cones.extend(sub.cones);
        self.corners.extend(sub.corners);
        self.ids.extend(sub.ids);
    }

    /// Appends the subtree over `items` (triangle of `mesh`, centroid × 3) in depth-first
    /// order. A leaf's box and cone come from its own triangles (their corners, their unit
    /// normals, [`unit_normal`]), an inner node's from its children's: the same boxes as
    /// from all its triangles, and a cone that holds all their normals ([`Cone::merge`]).
    fn build(&mut self, mesh: &Mesh, items: &mut [(u32, [f64; 3])]) {
        let at = self.nodes.len();
        let mid = split(items);
        if mid == items.len() {
            let start = self.corners.len();
            for &(t, _) in items.iter() {
                self.corners
                    .push(mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]));
                self.ids.push(t);
            }
            let corners = &self.corners[start..];
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for p in corners.iter().flatten() {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            self.nodes.push(BvhNode {
                lo,
                hi,
                start: start as u32,
                count: items.len() as u32,
            });
            self.cones
                .push(Cone::of(corners.iter().filter_map(|&c| unit_normal(c))));
            return;
        }
        self.nodes.push(BvhNode {
            lo: [0.0; 3],
            hi: [0.0; 3],
            start: 0,
            count: 0,
        });
        self.cones.push(Cone::EMPTY);
        let (first, second) = items.split_at_mut(mid);
        self.build(mesh, first);
        let right = self.nodes.len();
        self.build(mesh, second);
        self.nodes[at] = BvhNode::union(&self.nodes[at + 1], &self.nodes[right], right as u32);
        self.cones[at] = self.cones[at + 1].merge(&self.cones[right]);
    }

    /// The closest point of the surface to `p` (the first triangle found on ties).
    pub fn query(&self, p: [f64; 3]) -> Closest {
        self.query_where(p, |_| true)
    }

    /// The closest point to `p` on the triangles `accept` admits (by index in the mesh; the
    /// first found on ties); distance infinite when it admits none.
    pub fn query_where(&self, p: [f64; 3], accept: impl Fn(u32) -> bool) -> Closest {
        self.search(p, |j| accept(self.ids[j]))
    }

    /// Whether a triangle with area vector `normal` and centroid `centroid` faces against this
    /// surface: the nearest of its triangles facing against it (negative dot product of the
    /// area vectors) lies nearer than the nearest facing along it (positive) by more than
    /// `tie`, or none faces along. Triangles at right angles or without area take no side. A
    /// tie at an edge or vertex shared by triangles facing both ways, as at a scan's folds,
    /// goes to agreement. Both distances are minima, so the answer does not depend on the
    /// order of any search. [`deviation`] counts flipped triangles by it.
    pub fn faces_against(&self, centroid: [f64; 3], normal: [f64; 3], tie: f64) -> bool {
        self.faces_against_near(centroid, normal, tie, &[])
    }

    /// [`faces_against`](Self::faces_against), with the triangles of the leaves holding one
    /// of each `seeds` vertex's triangles (any vertices of the mesh) tried first: when one of
    /// them faces along at distance `d`, a seed leaf's clearance or a search for a triangle
    /// facing against within `d − tie`, which skips every box whose normals all face along
    /// (their cones), usually settles it. The leaves are scanned one at a time, and the
    /// clearances of those scanned are tried after each (a nearer triangle facing along
    /// found later only shrinks `d`, so what they settle stays settled). The same answer
    /// for any seeds.
    pub fn faces_against_from(
        &self,
        centroid: [f64; 3],
        normal: [f64; 3],
        tie: f64,
        seeds: &[u32],
    ) -> bool {
        let mut leaves = [u32::MAX; 4];
        let mut count = 0;
        for &s in seeds {
            let Some(&l) = self.vertex_leaf.get(s as usize) else {
                continue;
            };
            if l != u32::MAX && count < leaves.len() && !leaves[..count].contains(&l) {
                leaves[count] = l;
                count += 1;
            }
        }
        self.faces_against_near(centroid, normal, tie, &leaves[..count])
    }

    /// Starts loading vertex `v`'s seed leaf index (a hint; the first of two steps ahead of
    /// a facing test seeded there, [`prefetch_seed`](Self::prefetch_seed) the second).
    pub(crate) fn prefetch_seed_index(&self, v: u32) {
        if let Some(l) = self.vertex_leaf.get(v as usize) {
            crate::memory::prefetch(l);
        }
    }

    /// Starts loading what a facing test seeded at vertex `v` reads first: its leaf's box,
    /// cone, clearance and triangles (a hint: it changes nothing but timing).
    pub(crate) fn prefetch_seed(&self, v: u32) {
        let Some(&leaf) = self.vertex_leaf.get(v as usize) else {
            return;
        };
        let Some(node) = self.nodes.get(leaf as usize) else {
            return;
        };
        if let Some(c) = self.cones.get(leaf as usize) {
            crate::memory::prefetch(c);
        }
        if let Some(r) = self.clearance.get(leaf as usize) {
            crate::memory::prefetch(r);
        }
        let s = node.start as usize;
        if let Some(corners) = self.corners.get(s..s + node.count as usize) {
            for c in corners {
                crate::memory::prefetch(&c[0]);
                crate::memory::prefetch(&c[2]);
            }
        }
    }

    /// [`faces_against`](Self::faces_against) with the seed leaf `leaf` when given.
    fn faces_against_near(
        &self,
        centroid: [f64; 3],
        normal: [f64; 3],
        tie: f64,
        leaves: &[u32],
    ) -> bool {
        let length = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
        if !(length > 0.0 && length.is_finite()) {
            return false;
        }
        let unit = normal.map(|x| x / length);
        let facing = |j: usize| {
            let [a, b, c] = self.corners[j];
            let m = crate::mesh::area_vector(a, b, c);
            dot3(normal, m)
        };
        let along = |j: usize| facing(j) > 0.0;
        let against = |j: usize| facing(j) < 0.0;
        // Boxes that may hold a triangle facing along (against): not all of their normals
        // certainly face the other way.
        let may_along = |n: u32| !self.cones[n as usize].all_against(unit);
        let may_against = |n: u32| !self.cones[n as usize].all_against(unit.map(|x| -x));
        let mut nearest_along = Best::new(centroid);
        // The nearest triangle facing against, when the seeded search found it.
        let mut opposed_known = None;
        let mut seeded = Best::new(centroid);
        for (k, &leaf) in leaves.iter().enumerate() {
            self.scan_leaf(centroid, leaf, &mut seeded, &along);
            // The leaves scanned so far may already settle it (as below, with a nearest
            // facing along that the later leaves can only bring nearer).
            if k + 1 < leaves.len() && seeded.found() {
                let reach = seeded.best2.sqrt() - tie;
                if reach <= 0.0
                    || leaves[..=k]
                        .iter()
                        .any(|&l| self.clear_within(l, centroid, unit, reach))
                {
                    return false;
                }
            }
        }
        if seeded.found() {
            let reach = seeded.best2.sqrt() - tie;
            if reach <= 0.0 {
                return false;
            }
            // A seed leaf's clearance may settle it without a search.
            if leaves
                .iter()
                .any(|&leaf| self.clear_within(leaf, centroid, unit, reach))
            {
                return false;
            }
            // Flipped needs a triangle facing against nearer than `reach`.
            let mut opposed = Best::new(centroid);
            opposed.best2 = reach * reach;
            self.descend_where(centroid, &mut opposed, &against, &may_against);
            if !opposed.found_below(reach * reach) {
                return false;
            }
            // Found within `reach`, it is the nearest facing against of all; the nearest
            // facing along is at most as far as the seeds'.
            opposed_known = Some(opposed);
            nearest_along = seeded;
        }
        self.descend_where(centroid, &mut nearest_along, &along, &may_along);
        let d_along = nearest_along.best2.sqrt();
        let reach = d_along - tie;
        if reach <= 0.0 {
            return false;
        }
        let opposed = match opposed_known {
            // What a search bounded by `reach` would have found.
            Some(o) if o.found_below(reach * reach) => o,
            Some(_) => return false,
            None => {
                let mut opposed = Best::new(centroid);
                if reach.is_finite() {
                    opposed.best2 = reach * reach;
                }
                self.descend_where(centroid, &mut opposed, &against, &may_against);
                opposed
            }
        };
        opposed.entry != usize::MAX && opposed.best2.sqrt() + tie < d_along
    }

    /// [`query_where`](Self::query_where) with `accept` on entries of `corners`.
    fn search(&self, p: [f64; 3], accept: impl Fn(usize) -> bool) -> Closest {
        let mut best = Best::new(p);
        self.descend(p, 0, &mut best, &accept);
        Closest {
            distance: best.best2.sqrt(),
            triangle: if best.found() {
                self.ids[best.entry]
            } else {
                0
            },
            point: best.point,
        }
    }

    /// Tests the triangles of leaf `n` that `accept` admits against `best`.
    #[inline]
    fn scan_leaf(&self, p: [f64; 3], n: u32, best: &mut Best, accept: &impl Fn(usize) -> bool) {
        let node = self.nodes[n as usize];
        let s = node.start as usize;
        for j in s..s + node.count as usize {
            if !accept(j) {
                continue;
            }
            let [a, b, c] = self.corners[j];
            let q = closest_point_on_triangle(p, a, b, c);
            let e2 = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2);
            if e2 < best.best2 {
                best.best2 = e2;
                best.entry = j;
                best.point = q;
            }
        }
    }

    /// Searches the subtree at `root` for triangles `accept` admits nearer than `best`,
    /// nearest box first with pruning by the best distance found.
    fn descend(&self, p: [f64; 3], root: u32, best: &mut Best, accept: &impl Fn(usize) -> bool) {
        self.descend_from(p, root, best, accept, &|_| true);
    }

    /// [`descend`](Self::descend) from the root, skipping the boxes `keep` rejects.
    fn descend_where(
        &self,
        p: [f64; 3],
        best: &mut Best,
        accept: &impl Fn(usize) -> bool,
        keep: &impl Fn(u32) -> bool,
    ) {
        self.descend_from(p, 0, best, accept, keep);
    }

    /// [`descend`](Self::descend), skipping the boxes `keep` rejects (no triangle `accept`
    /// admits lies in them).
    fn descend_from(
        &self,
        p: [f64; 3],
        root: u32,
        best: &mut Best,
        accept: &impl Fn(usize) -> bool,
        keep: &impl Fn(u32) -> bool,
    ) {
        if !keep(root) {
            return;
        }
        // Pending subtrees with their boxes' squared distances.
        let mut stack: [(u32, f64); 128] = [(0, 0.0); 128];
        stack[0] = (root, 0.0);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (mut n, d2) = stack[top];
            if d2 >= best.best2 {
                continue;
            }
            loop {
                let node = self.nodes[n as usize];
                if node.count > 0 {
                    self.scan_leaf(p, n, best, accept);
                    break;
                }
                let (l, r) = (n + 1, node.start);
                // The box's distance first: a box beyond the best found is not asked about.
                let box2 = |c: u32| {
                    let d2 = self.nodes[c as usize].distance2(p);
                    if d2 < best.best2 && keep(c) {
                        d2
                    } else {
                        f64::INFINITY
                    }
                };
                let (dl, dr) = (box2(l), box2(r));
                let (near, dn, far, df) = if dl <= dr {
                    (l, dl, r, dr)
                } else {
                    (r, dr, l, dl)
                };
                if df < best.best2 && top < stack.len() {
                    stack[top] = (far, df);
                    top += 1;
                } else if df < best.best2 {
                    // A hierarchy deeper than the stack (not built by `new`): search the far
                    // side now, which is correct, only slower.
                    self.descend_from(p, far, best, accept, keep);
                }
                if dn >= best.best2 {
                    break;
                }
                n = near;
            }
        }
    }
}

/// Where the median split of `items` (triangle, centroid × 3) falls along the longest axis
/// of their centroids' box (`items` partially sorted along it), or `items.len()` when they
/// fit in a leaf.
fn split(items: &mut [(u32, [f64; 3])]) -> usize {
    if items.len() <= LEAF {
        return items.len();
    }
    let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for (_, c) in items.iter() {
        for k in 0..3 {
            clo[k] = clo[k].min(c[k]);
            chi[k] = chi[k].max(c[k]);
        }
    }
    let mut axis = 0;
    for k in [1, 2] {
        if chi[k] - clo[k] > chi[axis] - clo[axis] {
            axis = k;
        }
    }
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.1[axis].total_cmp(&b.1[axis]));
    mid
}

/// The best answer of a search so far.
struct Best {
    /// Squared distance (infinite before the first triangle).
    best2: f64,
    /// The entry of `corners` it was found at (`usize::MAX` before).
    entry: usize,
    point: [f64; 3],
}

impl Best {
    /// Nothing found yet, for the point `p`.
    fn new(p: [f64; 3]) -> Best {
        Best {
            best2: f64::INFINITY,
            entry: usize::MAX,
            point: p,
        }
    }

    fn found(&self) -> bool {
        self.entry != usize::MAX
    }

    /// Whether a triangle was found nearer than `bound2` (squared).
    fn found_below(&self, bound2: f64) -> bool {
        self.found() && self.best2 < bound2
    }
}

/// A cone holding the unit normals of a box's triangles: every one lies within the angle
/// `acos(cos)` of `axis` (a unit vector). Triangles whose area vector is zero face no way
/// and are left out (a box with only such has an empty cone, `cos` > 1); one whose normal
/// cannot be normalised makes the cone the whole sphere.
#[derive(Clone, Copy)]
struct Cone {
    axis: [f64; 3],
    cos: f64,
}

/// `m / |m|` when `|m|` is positive and finite (and not so small that its square underflows).
fn unit_vector(m: [f64; 3]) -> Option<[f64; 3]> {
    let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    (l > 1e-150 && l.is_finite()).then(|| m.map(|x| x / l))
}

/// The unit normal of the triangle `t` ([`unit_vector`] of its area vector): `None` when
/// its area vector is exactly zero (it faces no way), NaNs when it cannot be normalised.
fn unit_normal([a, b, c]: [[f64; 3]; 3]) -> Option<[f64; 3]> {
    let m = crate::mesh::area_vector(a, b, c);
    if m == [0.0; 3] {
        return None;
    }
    Some(unit_vector(m).unwrap_or([f64::NAN; 3]))
}

/// The angle between two unit vectors, accurate near 0 and π too (`atan2` of the cross
/// product's length and the dot product).
fn angle_between(a: [f64; 3], b: [f64; 3]) -> f64 {
    let x = crate::mesh::cross(a, b);
    dot3(x, x).sqrt().atan2(dot3(a, b))
}

/// `a · b`, summed in coordinate order.
fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The margin by which [`Cone::all_against`] and [`Cone::within`] must hold. A cosine `c`
/// near 1 carries a rounding error `δ` of about 1e-15 (unit vectors, dot products), and its
/// sine `√(1 − c²)` then one of up to `√(2δ)`, about 5e-8: the margin is far above that.
const CONE_MARGIN: f64 = 1e-6;

impl Cone {
    /// The cone of no normal.
    const EMPTY: Cone = Cone {
        axis: [0.0; 3],
        cos: 2.0,
    };

    /// The whole sphere.
    const WHOLE: Cone = Cone {
        axis: [1.0, 0.0, 0.0],
        cos: -1.0,
    };

    /// A cone holding both cones' normals: around the sum of their axes, wide enough for
    /// each (the angle to its axis plus its own half-angle, rounded outwards).
    fn merge(&self, other: &Cone) -> Cone {
        if self.cos > 1.0 {
            return *other;
        }
        if other.cos > 1.0 {
            return *self;
        }
        let sum = std::array::from_fn(|k| self.axis[k] + other.axis[k]);
        let Some(axis) = unit_vector(sum) else {
            return Cone::WHOLE;
        };
        let angle = [self, other]
            .iter()
            .map(|c| angle_between(axis, c.axis) + c.cos.clamp(-1.0, 1.0).acos())
            .fold(0.0f64, f64::max);
        if angle.is_nan() || angle >= std::f64::consts::PI {
            return Cone::WHOLE;
        }
        // `acos` and `cos` are faithful to a few ulps: widen by far more.
        Cone {
            axis,
            cos: (angle.cos() - 1e-12).max(-1.0),
        }
    }

    /// The cone of the unit normals `units`; the whole sphere when one is NaN.
    fn of(units: impl Iterator<Item = [f64; 3]> + Clone) -> Cone {
        let whole = Cone {
            axis: [1.0, 0.0, 0.0],
            cos: -1.0,
        };
        let mut sum = [0.0; 3];
        let mut any = false;
        for u in units.clone() {
            if u.iter().any(|x| x.is_nan()) {
                return whole;
            }
            any = true;
            for k in 0..3 {
                sum[k] += u[k];
            }
        }
        if !any {
            return Cone {
                axis: [0.0; 3],
                cos: 2.0,
            };
        }
        let Some(axis) = unit_vector(sum) else {
            return whole;
        };
        // Lowered by far more than the dot products' rounding, so that the cone holds every
        // normal whatever the last bits ([`Cone::merge`] builds on it).
        let cos = units
            .map(|u| dot3(u, axis))
            .fold(1.0f64, f64::min)
            .clamp(-1.0, 1.0);
        Cone {
            axis,
            cos: (cos - 1e-14).max(-1.0),
        }
    }

    /// Whether every normal in the cone certainly lies within the cone of unit axis `axis`
    /// and half-angle cosine `cos` (by [`CONE_MARGIN`]). False for an empty cone (no normal
    /// to bound; the caller searches it).
    fn within(&self, axis: [f64; 3], cos: f64) -> bool {
        if self.cos > 1.0 || self.cos <= 0.0 {
            return false;
        }
        let c_phi = dot3(self.axis, axis);
        if c_phi <= 0.0 {
            return false;
        }
        let c_phi = c_phi.min(1.0);
        let sin = |c: f64| (1.0 - c * c).max(0.0).sqrt();
        // cos(θ + φ) ≥ cos + margin, both angles below 90°.
        self.cos * c_phi - sin(self.cos) * sin(c_phi) > cos + CONE_MARGIN
    }

    /// Whether every normal in the cone certainly faces against the unit vector `n`
    /// (negative dot product): the cone lies within 90° of `−n`, by [`CONE_MARGIN`]. True
    /// for an empty cone.
    fn all_against(&self, n: [f64; 3]) -> bool {
        if self.cos > 1.0 {
            return true;
        }
        // cos of the angle between the axis and −n, and the cone's half-angle.
        let c_phi = -dot3(self.axis, n);
        if self.cos <= 0.0 || c_phi <= 0.0 {
            return false;
        }
        let c_phi = c_phi.min(1.0);
        let sin = |c: f64| (1.0 - c * c).max(0.0).sqrt();
        // cos(θ + φ) > margin, both angles below 90°.
        self.cos * c_phi - sin(self.cos) * sin(c_phi) > CONE_MARGIN
    }
}

/// The largest distance from a vertex of `from` to the surface `to` (exact closest points
/// per triangle, found through [`ClosestPoints`]); NaN when either is empty.
pub fn vertex_distance_to_surface(from: &Mesh, to: &Mesh) -> f64 {
    if from.vertices.is_empty() {
        return f64::NAN;
    }
    let Some(cp) = ClosestPoints::new(to) else {
        return f64::NAN;
    };
    use crate::par::prelude::*;
    let d: Vec<f64> = from
        .vertices
        .par_iter()
        .map(|&p| cp.query(p).distance)
        .collect();
    d.into_iter().fold(0.0, f64::max)
}

/// The barycentric coordinates of `q` (a point of triangle `abc`) by least squares in 3-D.
fn barycentric(q: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let (v0, v1, v2) = (sub(b, a), sub(c, a), sub(q, a));
    let (d00, d01, d11, d20, d21) = (
        dot(v0, v0),
        dot(v0, v1),
        dot(v1, v1),
        dot(v2, v0),
        dot(v2, v1),
    );
    let denom = d00 * d11 - d01 * d01;
    if denom == 0.0 || !denom.is_finite() {
        return [1.0, 0.0, 0.0];
    }
    let v = (d11 * d20 - d01 * d21) / denom;
    let w = (d00 * d21 - d01 * d20) / denom;
    [1.0 - v - w, v, w]
}

/// Errors of a decimated surface that is not a height field: at every original node of the
/// surface (vertices no triangle uses are skipped), its distance to the decimated surface
/// (in `max_height`/`rms_height`) and the difference between its scalar and the decimated
/// field interpolated at its closest point.
pub fn surface_errors(original: &Mesh, decimated: &Mesh) -> Errors {
    use crate::par::prelude::*;
    let Some(cp) = ClosestPoints::new(decimated) else {
        return Errors::default();
    };
    let fields = original.scalars.as_ref().zip(decimated.scalars.as_ref());
    let used = original.used_vertices();
    // On all cores; the tally runs in vertex order (the same sums either way).
    let per_vertex: Vec<(f64, f64)> = original
        .vertices
        .par_iter()
        .enumerate()
        .filter(|&(i, _)| used[i])
        .map(|(i, &p)| {
            let c = cp.query(p);
            let scalar = fields.map_or(0.0, |(f, g)| {
                let tri = decimated.triangles[c.triangle as usize];
                let [a, b, cc] = tri.map(|k| decimated.vertices[k as usize]);
                let w = barycentric(c.point, a, b, cc);
                let at: f64 = (0..3).map(|k| w[k] * g.values[tri[k] as usize]).sum();
                (f.values[i] - at).abs()
            });
            (c.distance, scalar)
        })
        .collect();
    let mut tally = Tally::default();
    let nodes = per_vertex.len();
    for (d, e) in per_vertex {
        tally.height(d);
        if fields.is_some() {
            tally.scalar(e);
        }
    }
    tally.finish(nodes, fields.is_some(), 0)
}

/// How far a simplified surface lies from its original, both ways, and how many of its
/// triangles face against it ([`deviation`]).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Deviation {
    /// The original's bounding-box diagonal (the unit of the `_percent` figures).
    pub diagonal: f64,
    /// Largest distance from a vertex of the original surface (one some triangle uses) to
    /// the simplified surface.
    pub forward_max: f64,
    /// Root mean square of those distances.
    pub forward_rms: f64,
    /// Largest distance from a sample of the simplified surface (every triangle at the
    /// barycentric points `(i, j, k)/SAMPLE_STEPS`) to the original surface.
    pub backward_max: f64,
    /// Root mean square of those distances.
    pub backward_rms: f64,
    /// `max(forward_max, backward_max)`: the symmetric Hausdorff distance at the samples.
    pub hausdorff: f64,
    /// Simplified triangles whose normal points against the original surface nearest their
    /// centroid ([`ClosestPoints::faces_against`]): the nearest original triangle facing
    /// against it (negative dot product) lies nearer than the nearest facing along it
    /// (positive), by more than [`FLIP_TIE`] of the diagonal. The closest point is often an
    /// edge or vertex shared by triangles facing both ways (folds of a scan, thin parts); such
    /// a tie goes to agreement. Original triangles at right angles or without area take no
    /// side; degenerate simplified triangles are not counted.
    pub flipped: usize,
    /// Points measured: original vertices and simplified-surface samples.
    pub samples: usize,
}

impl Deviation {
    /// `x` in percent of the diagonal.
    pub fn percent(&self, x: f64) -> f64 {
        100.0 * x / self.diagonal
    }
}

/// How much farther (in units of the diagonal) the nearest original triangle facing along a
/// simplified triangle must lie than the nearest one facing against it for the triangle to
/// count as flipped ([`Deviation::flipped`]).
pub const FLIP_TIE: f64 = 1e-9;

/// An original surface as the facing test sees it: its closest-point structure (with its
/// leaves' clearances) and the tie distance ([`FLIP_TIE`] of its bounding-box diagonal), as
/// [`deviation`] counts flipped triangles.
pub struct OriginalSurface {
    /// The closest-point structure over its triangles.
    pub closest: ClosestPoints,
    /// The tie distance of [`ClosestPoints::faces_against`].
    pub tie: f64,
}

impl OriginalSurface {
    /// The surface of `mesh`; `None` when it has no triangles.
    pub fn new(mesh: &Mesh) -> Option<OriginalSurface> {
        let closest = ClosestPoints::new(mesh)?.with_clearances();
        Some(OriginalSurface {
            closest,
            tie: FLIP_TIE * bounding_diagonal(mesh),
        })
    }

    /// Whether the triangle `(a, b, c)` faces against this surface
    /// ([`ClosestPoints::faces_against`] at its centroid), the search started at the mesh
    /// vertices `seeds` ([`ClosestPoints::faces_against_from`]; the answer does not depend
    /// on them, only its cost).
    pub fn faces_against(&self, [a, b, c]: [[f64; 3]; 3], seeds: &[u32]) -> bool {
        let centroid = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
        let normal = crate::mesh::area_vector(a, b, c);
        self.closest
            .faces_against_from(centroid, normal, self.tie, seeds)
    }
}

/// The length of the bounding-box diagonal of `mesh`'s surface: the vertices some triangle
/// uses (0 without any).
pub fn bounding_diagonal(mesh: &Mesh) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let mut any = false;
    for p in mesh
        .triangles
        .iter()
        .flatten()
        .filter_map(|&i| mesh.vertices.get(i as usize))
    {
        any = true;
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !any {
        return 0.0;
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// Barycentric steps per edge of the simplified triangles' samples in [`deviation`].
pub const SAMPLE_STEPS: usize = 3;

/// The deviation of `simplified` from `original` both ways ([`Deviation`]): closest points on
/// triangles through a bounding-volume hierarchy ([`ClosestPoints`]), in `f64`, on all cores.
/// Meshes without triangles give NaN distances.
pub fn deviation(original: &Mesh, simplified: &Mesh) -> Deviation {
    use crate::par::prelude::*;
    let diagonal = bounding_diagonal(original);
    let (Some(to_simplified), Some(to_original)) =
        (ClosestPoints::new(simplified), ClosestPoints::new(original))
    else {
        return Deviation {
            diagonal,
            forward_max: f64::NAN,
            forward_rms: f64::NAN,
            backward_max: f64::NAN,
            backward_rms: f64::NAN,
            hausdorff: f64::NAN,
            ..Deviation::default()
        };
    };
    let used = original.used_vertices();
    let forward: Vec<f64> = original
        .vertices
        .par_iter()
        .enumerate()
        .filter(|&(i, _)| used[i])
        .map(|(_, &p)| to_simplified.query(p).distance)
        .collect();
    let normal = |m: &Mesh, t: u32| {
        let [a, b, c] = m.triangles[t as usize].map(|i| m.vertices[i as usize]);
        crate::mesh::area_vector(a, b, c)
    };
    let n = SAMPLE_STEPS;
    // Per simplified triangle: its samples' largest and summed squared distances, and
    // whether it is flipped.
    let backward: Vec<(f64, f64, usize, bool)> = (0..simplified.triangles.len() as u32)
        .into_par_iter()
        .map(|t| {
            let [a, b, c] =
                simplified.triangles[t as usize].map(|i| simplified.vertices[i as usize]);
            let (mut max, mut sum, mut count) = (0.0f64, 0.0, 0);
            for i in 0..=n {
                for j in 0..=n - i {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    let w = 1.0 - u - v;
                    let p = std::array::from_fn(|k| w * a[k] + u * b[k] + v * c[k]);
                    let d = to_original.query(p).distance;
                    max = max.max(d);
                    sum += d * d;
                    count += 1;
                }
            }
            let centroid = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
            let flipped =
                to_original.faces_against(centroid, normal(simplified, t), FLIP_TIE * diagonal);
            (max, sum, count, flipped)
        })
        .collect();
    let rms = |sum: f64, count: usize| (sum / count.max(1) as f64).sqrt();
    let forward_max = forward.iter().copied().fold(0.0, f64::max);
    let forward_rms = rms(forward.iter().map(|d| d * d).sum(), forward.len());
    let backward_max = backward.iter().map(|b| b.0).fold(0.0, f64::max);
    let count: usize = backward.iter().map(|b| b.2).sum();
    let backward_rms = rms(backward.iter().map(|b| b.1).sum(), count);
    Deviation {
        diagonal,
        forward_max,
        forward_rms,
        backward_max,
        backward_rms,
        hausdorff: forward_max.max(backward_max),
        flipped: backward.iter().filter(|b| b.3).count(),
        samples: forward.len() + count,
    }
}

/// The symmetric Hausdorff distance between two meshes sampled at their vertices:
/// `max(max_{v ∈ A} d(v, B), max_{w ∈ B} d(w, A))`. A lower bound of the true Hausdorff
/// distance, equal to it where the farthest points are vertices (a decimation's are: every
/// decimated vertex lies on the original surface and the deviation peaks at original nodes
/// over a decimated triangle's interior).
pub fn hausdorff_at_vertices(a: &Mesh, b: &Mesh) -> f64 {
    vertex_distance_to_surface(a, b).max(vertex_distance_to_surface(b, a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_to_a_triangle_and_a_surface() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let q = closest_point_on_triangle([0.2, 0.2, 5.0], a, b, c);
        assert!((q[0] - 0.2).abs() < 1e-15 && (q[1] - 0.2).abs() < 1e-15 && q[2] == 0.0);
        assert_eq!(closest_point_on_triangle([-1.0, -1.0, 0.0], a, b, c), a);
        assert_eq!(closest_point_on_triangle([2.0, -1.0, 0.0], a, b, c), b);
        let q = closest_point_on_triangle([1.0, 1.0, 0.0], a, b, c);
        assert!((q[0] - 0.5).abs() < 1e-15 && (q[1] - 0.5).abs() < 1e-15);
        // A unit square and the same square lifted by 0.25: distance 0.25 both ways.
        let square = |z: f64| Mesh {
            vertices: vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            ..Default::default()
        };
        assert!((hausdorff_at_vertices(&square(0.0), &square(0.25)) - 0.25).abs() < 1e-15);
    }

    /// The flipped count: a reversed triangle counts; where the original folds onto itself
    /// (two coincident triangles facing both ways, as in scans), a triangle facing along one
    /// of them does not, whichever of the two the search meets first.
    #[test]
    fn flipped_triangles_and_ties_at_folds() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let one = |t: [u32; 3]| Mesh {
            vertices: vec![a, b, c],
            triangles: vec![t],
            ..Default::default()
        };
        assert_eq!(deviation(&one([0, 1, 2]), &one([0, 2, 1])).flipped, 1);
        assert_eq!(deviation(&one([0, 1, 2]), &one([0, 1, 2])).flipped, 0);
        let folded = Mesh {
            vertices: vec![a, b, c, a, b, c],
            triangles: vec![[0, 1, 2], [3, 5, 4]],
            ..Default::default()
        };
        for t in [[0, 1, 2], [0, 2, 1]] {
            assert_eq!(deviation(&folded, &one(t)).flipped, 0, "{t:?}");
        }
        assert_eq!(deviation(&folded, &folded).flipped, 0);
    }

    /// A xorshift generator from `state` (not zero): the tests' pseudo-random points.
    fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        }
    }

    /// The height field `z = h(x, y)` on `n × n` vertices over the unit square, two
    /// triangles per cell.
    fn height_grid(n: usize, h: impl Fn(f64, f64) -> f64) -> Mesh {
        let mut mesh = Mesh::default();
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
                mesh.vertices.push([x, y, h(x, y)]);
            }
        }
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = (j * n + i) as u32;
                let n = n as u32;
                mesh.triangles
                    .extend([[v, v + 1, v + n + 1], [v, v + n + 1, v + n]]);
            }
        }
        mesh
    }

    /// A hierarchy large enough to be built in two halves side by side
    /// ([`PARALLEL_BUILD`]) answers like a scan of every triangle: closest distances for 300
    /// pseudo-random points around a bumpy 190 × 190 grid (71,442 triangles), and every
    /// vertex's seed leaf holds one of its triangles.
    #[test]
    fn a_hierarchy_built_in_halves_finds_the_closest_triangles() {
        let mesh = height_grid(190, |x, y| 0.05 * (9.0 * x).sin() * (7.0 * y).cos());
        assert!(mesh.triangles.len() > PARALLEL_BUILD);
        let cp = ClosestPoints::new(&mesh).unwrap();
        let mut bits = xorshift(0x9e37_79b9_7f4a_7c15);
        let mut next = || (bits() % 100_000) as f64 / 100_000.0;
        for _ in 0..300 {
            let p = [1.2 * next() - 0.1, 1.2 * next() - 0.1, 0.4 * next() - 0.2];
            let brute = mesh
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
                    let q = closest_point_on_triangle(p, a, b, c);
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
                })
                .fold(f64::INFINITY, f64::min);
            assert_eq!(cp.query(p).distance, brute, "{p:?}");
        }
        for (v, &leaf) in cp.vertex_leaf.iter().enumerate() {
            let node = cp.nodes[leaf as usize];
            assert!(node.count > 0);
            let s = node.start as usize;
            assert!(cp.ids[s..s + node.count as usize]
                .iter()
                .any(|&t| mesh.triangles[t as usize].contains(&(v as u32))));
        }
    }

    /// A bumpy closed-off slab of two sheets, 24 × 24 vertices each: the bottom sheet
    /// faces down, the top one up, 0.05 above it and folding higher in bumps.
    fn two_sheets() -> Mesh {
        let n = 24;
        let mut mesh = Mesh::default();
        for sheet in 0..2 {
            for j in 0..n {
                for i in 0..n {
                    let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
                    let bump = 0.2 * (6.0 * x).sin() * (5.0 * y).cos();
                    let z = if sheet == 0 {
                        0.0
                    } else {
                        0.05 + bump.max(0.0)
                    };
                    mesh.vertices.push([x, y, z]);
                }
            }
        }
        let at = |s: usize, i: usize, j: usize| (s * n * n + j * n + i) as u32;
        for s in 0..2 {
            for j in 0..n - 1 {
                for i in 0..n - 1 {
                    let (a, b, c, d) = (
                        at(s, i, j),
                        at(s, i + 1, j),
                        at(s, i + 1, j + 1),
                        at(s, i, j + 1),
                    );
                    if s == 0 {
                        mesh.triangles.extend([[a, c, b], [a, d, c]]);
                    } else {
                        mesh.triangles.extend([[a, b, c], [a, c, d]]);
                    }
                }
            }
        }
        mesh
    }

    /// The facing test by a scan of every triangle (the definition of
    /// [`ClosestPoints::faces_against`]).
    fn faces_against_by_scan(mesh: &Mesh, tri: [[f64; 3]; 3], tie: f64) -> bool {
        let [a, b, c] = tri;
        let centroid: [f64; 3] = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
        let normal = crate::mesh::area_vector(a, b, c);
        let (mut along, mut against) = (f64::INFINITY, f64::INFINITY);
        for t in &mesh.triangles {
            let [p, q, r] = t.map(|i| mesh.vertices[i as usize]);
            let f = dot3(normal, crate::mesh::area_vector(p, q, r));
            let x = closest_point_on_triangle(centroid, p, q, r);
            let d = (0..3)
                .map(|k| (centroid[k] - x[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            if f > 0.0 {
                along = along.min(d);
            } else if f < 0.0 {
                against = against.min(d);
            }
        }
        against.is_finite() && against + tie < along
    }

    /// Every node's cone holds the unit normal of every triangle below it (the leaves' cones
    /// from their triangles, the inner ones merged from their children's), and every leaf's
    /// clearance is at most the distance from its box's centre to the nearest triangle whose
    /// normal lies more than 50° from the leaf's axis (by `acos`, independently of the
    /// squared test the search makes): on the two-sheet slab and on a 190 × 190 bumpy grid
    /// built in two halves.
    #[test]
    fn cones_hold_their_normals_and_clearances_are_lower_bounds() {
        let grid = height_grid(190, |x, y| 0.08 * (19.0 * x).sin() * (17.0 * y).cos());
        for (name, mesh, step) in [("two sheets", two_sheets(), 1), ("grid", grid, 97)] {
            let cp = ClosestPoints::new(&mesh).unwrap().with_clearances();
            // Each node's subtree is a contiguous run of leaves in depth-first order.
            fn run(cp: &ClosestPoints, at: usize) -> (usize, usize) {
                let node = cp.nodes[at];
                if node.count > 0 {
                    let s = node.start as usize;
                    return (s, s + node.count as usize);
                }
                (run(cp, at + 1).0, run(cp, node.start as usize).1)
            }
            for at in (0..cp.nodes.len()).step_by(step) {
                let (from, to) = run(&cp, at);
                let cone = cp.cones[at];
                for corners in &cp.corners[from..to] {
                    if let Some(u) = unit_normal(*corners) {
                        assert!(dot3(u, cone.axis) >= cone.cos - 1e-12, "{name}: node {at}");
                    }
                }
            }
            let (mut positive, mut checked) = (0, 0);
            for at in (0..cp.nodes.len()).step_by(step.min(7)) {
                let (node, r) = (cp.nodes[at], cp.clearance[at]);
                if node.count == 0 || r == 0.0 {
                    continue;
                }
                positive += 1;
                let axis = cp.cones[at].axis;
                let centre = node.centre();
                for t in &mesh.triangles {
                    let corners = t.map(|i| mesh.vertices[i as usize]);
                    let Some(u) = unit_normal(corners) else {
                        continue;
                    };
                    let degrees = dot3(u, axis).clamp(-1.0, 1.0).acos().to_degrees();
                    if degrees > 50.0 + 1e-9 {
                        let [a, b, c] = corners;
                        let x = closest_point_on_triangle(centre, a, b, c);
                        let d = (0..3)
                            .map(|k| (centre[k] - x[k]).powi(2))
                            .sum::<f64>()
                            .sqrt();
                        assert!(r <= d + 1e-12, "{name}: leaf {at}: {r} past {d}");
                        checked += 1;
                    }
                }
            }
            assert!(
                positive > 20 && checked > 1000,
                "{name}: {positive} leaves, {checked} triangles"
            );
        }
    }

    /// The facing test searched from any seed vertex's leaf gives the answer of the search
    /// from the root and of a scan of every triangle: on the two-sheet slab, for 2,000
    /// pseudo-random triangles (every fifth vertex as the seed) and 2,000 small triangles
    /// just above the top sheet tilted up to about 30° (each seeded at its nearest vertex),
    /// many of which the seed leaf's clearance settles without a search.
    #[test]
    fn facing_from_any_seed_agrees_with_the_search_from_the_root() {
        let mesh = two_sheets();
        let original = OriginalSurface::new(&mesh).unwrap();
        let mut next = xorshift(0x2545_f491_4f6c_dd1d);
        let (mut against, mut along) = (0, 0);
        for _ in 0..2000 {
            let tri: [[f64; 3]; 3] = std::array::from_fn(|_| {
                std::array::from_fn(|k| {
                    let r = (next() % 10_000) as f64 / 10_000.0;
                    if k == 2 {
                        0.3 * r - 0.05
                    } else {
                        r
                    }
                })
            });
            let [a, b, c] = tri;
            let centroid = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
            let normal = crate::mesh::area_vector(a, b, c);
            let root = original
                .closest
                .faces_against(centroid, normal, original.tie);
            let count = mesh.vertices.len() as u32;
            for seed in (0..count).step_by(5) {
                assert_eq!(
                    original.faces_against(tri, &[seed]),
                    root,
                    "{tri:?} from {seed}"
                );
                // Several seeds, on both sheets: the same answer.
                let seeds = [seed, (seed * 7 + 3) % count, (seed + count / 2) % count];
                assert_eq!(
                    original.faces_against(tri, &seeds),
                    root,
                    "{tri:?} from {seeds:?}"
                );
            }
            if root {
                against += 1;
            } else {
                along += 1;
            }
        }
        assert!(
            against > 100 && along > 100,
            "{against} against, {along} along"
        );
        let n = 24;
        let mut settled = 0;
        for _ in 0..2000 {
            let mut r = || (next() % 10_000) as f64 / 10_000.0;
            let (i, j) = (
                (r() * (n - 1) as f64) as usize,
                (r() * (n - 1) as f64) as usize,
            );
            let seed = (n * n + j * n + i) as u32;
            let p = mesh.vertices[seed as usize];
            let h = 0.004 * r();
            let (tx, ty) = (0.5 * (r() - 0.5), 0.5 * (r() - 0.5));
            let tri = [[0.0, 0.0], [0.02, 0.0], [0.0, 0.02]]
                .map(|[dx, dy]| [p[0] + dx, p[1] + dy, p[2] + h + tx * dx + ty * dy]);
            let expected = faces_against_by_scan(&mesh, tri, original.tie);
            assert_eq!(original.faces_against(tri, &[seed]), expected, "{tri:?}");
            assert_eq!(
                original.faces_against(tri, &[seed, seed + 1, seed + n as u32]),
                expected,
                "{tri:?}"
            );
            let [a, b, c] = tri;
            let centroid = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
            let normal = crate::mesh::area_vector(a, b, c);
            let unit = normal.map(|x| x / dot3(normal, normal).sqrt());
            let leaf = original.closest.vertex_leaf[seed as usize];
            let reach = {
                let mut seeded = Best::new(centroid);
                let cp = &original.closest;
                cp.scan_leaf(centroid, leaf, &mut seeded, &|j| {
                    let [a, b, c] = cp.corners[j];
                    dot3(normal, crate::mesh::area_vector(a, b, c)) > 0.0
                });
                seeded.best2.sqrt() - original.tie
            };
            if reach > 0.0 && original.closest.clear_within(leaf, centroid, unit, reach) {
                assert!(!expected);
                settled += 1;
            }
        }
        assert!(settled > 500, "{settled} settled by clearance");
    }

    #[test]
    fn surface_errors_on_a_vertical_square() {
        use crate::mesh::Scalars;
        // A 3×3 grid on the square [0,1]² of the xz plane (not a height field in xy), the
        // scalar x²; decimated to its four corners. Distances vanish; the scalar error peaks
        // at x = 1/2: |1/4 − 1/2|.
        let mut fine = Mesh::default();
        for k in 0..3 {
            for i in 0..3 {
                fine.vertices.push([i as f64 / 2.0, 0.0, k as f64 / 2.0]);
            }
        }
        fine.triangles = crate::decimate::data::grid_triangles(3, 3);
        let values = fine.vertices.iter().map(|p| p[0] * p[0]).collect();
        fine.scalars = Some(Scalars {
            name: "s".into(),
            values,
        });
        let coarse = Mesh {
            vertices: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
            ],
            triangles: crate::decimate::data::grid_triangles(2, 2),
            scalars: Some(Scalars {
                name: "s".into(),
                values: vec![0.0, 1.0, 0.0, 1.0],
            }),
            normals: None,
        };
        let e = surface_errors(&fine, &coarse);
        assert!(e.max_height < 1e-15, "{}", e.max_height);
        assert!(
            (e.max_scalar.unwrap() - 0.25).abs() < 1e-12,
            "{:?}",
            e.max_scalar
        );
        // Against itself: nothing.
        let same = surface_errors(&fine, &fine);
        assert!(same.max_scalar.unwrap() < 1e-15 && same.max_height < 1e-15);
    }
}
