//! Global names of lattice points (Section 3.2): a lattice point on an element's node, edge
//! or face is named by the global node numbers of that entity and its position in a frame
//! fixed by those numbers, so every element that shares the entity names the point alike.
//! Entities whose nodes repeat a number (collapsed elements) and element interiors get names
//! local to the element; such points are joined later only if they coincide in world space.

use super::FeError;
use std::collections::HashMap;

/// The global name of a lattice point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum PointKey {
    Node(u32),
    /// On the element edge between nodes `ends[0] < ends[1]`, `at` steps from `ends[0]`.
    Edge {
        ends: [u32; 2],
        at: u32,
    },
    /// On the face with corners `corners` in canonical cyclic order (smallest first, then its
    /// smaller neighbour); `at` steps along `corners[0] → corners[1]` and
    /// `corners[0] → corners[3]`.
    Face {
        corners: [u32; 4],
        at: [u32; 2],
    },
    /// Inside the element, or on an entity with a repeated node.
    Local {
        element: u32,
        at: [u32; 3],
    },
}

/// A cut edge's name: its two lattice points, ordered.
pub(crate) type EdgeKey = (PointKey, PointKey);

/// The edge key of the lattice edge from `p` along `axis`, and whether its lower point comes
/// first in the key.
pub(crate) fn edge_key(
    element: usize,
    nodes: &[u32; 8],
    n: [usize; 3],
    p: [usize; 3],
    axis: usize,
) -> (EdgeKey, bool) {
    let mut q = p;
    q[axis] += 1;
    let (a, b) = (
        point_key(element, nodes, n, p),
        point_key(element, nodes, n, q),
    );
    if a <= b {
        ((a, b), true)
    } else {
        ((b, a), false)
    }
}

pub(super) fn node_at(nodes: &[u32; 8], side: [usize; 3]) -> u32 {
    nodes[side[0] + 2 * side[1] + 4 * side[2]]
}

/// The global name of lattice point `p` (`0 ≤ p[d] ≤ n[d]`) of element `element`.
pub(crate) fn point_key(
    element: usize,
    nodes: &[u32; 8],
    n: [usize; 3],
    p: [usize; 3],
) -> PointKey {
    let local = PointKey::Local {
        element: element as u32,
        at: p.map(|x| x as u32),
    };
    let on: [bool; 3] = std::array::from_fn(|d| p[d] == 0 || p[d] == n[d]);
    let side = |d: usize| usize::from(p[d] == n[d]);
    match on.iter().filter(|&&b| b).count() {
        3 => PointKey::Node(node_at(nodes, [side(0), side(1), side(2)])),
        2 => {
            let d = (0..3).find(|&d| !on[d]).expect("one free direction");
            let mut s = [side(0), side(1), side(2)];
            s[d] = 0;
            let a = node_at(nodes, s);
            s[d] = 1;
            let b = node_at(nodes, s);
            match a.cmp(&b) {
                std::cmp::Ordering::Less => PointKey::Edge {
                    ends: [a, b],
                    at: p[d] as u32,
                },
                std::cmp::Ordering::Greater => PointKey::Edge {
                    ends: [b, a],
                    at: (n[d] - p[d]) as u32,
                },
                std::cmp::Ordering::Equal => local,
            }
        }
        1 => {
            let d = (0..3).find(|&d| on[d]).expect("one fixed direction");
            let (u, v) = free_axes(d);
            let ids = face_corners(nodes, d, side(d));
            match canonical_face(ids) {
                None => local,
                Some((corners, start, forward)) => {
                    let at = face_position([p[u], p[v]], [n[u], n[v]], start, forward);
                    PointKey::Face {
                        corners,
                        at: at.map(|x| x as u32),
                    }
                }
            }
        }
        _ => local,
    }
}

/// The two directions spanning the face normal to `d`, in increasing order.
pub(super) fn free_axes(d: usize) -> (usize, usize) {
    match d {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The corners of the face normal to `d` at `side`, cyclic: `(0,0), (1,0), (1,1), (0,1)` in
/// the face's `(u, v)`.
pub(super) fn face_corners(nodes: &[u32; 8], d: usize, side: usize) -> [u32; 4] {
    let (u, v) = free_axes(d);
    [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(a, b)| {
        let mut s = [0; 3];
        s[d] = side;
        s[u] = a;
        s[v] = b;
        node_at(nodes, s)
    })
}

/// The canonical cyclic order of four distinct corner ids: start at the smallest, go towards
/// its smaller neighbour. `None` when an id repeats.
pub(super) fn canonical_face(ids: [u32; 4]) -> Option<([u32; 4], usize, bool)> {
    for i in 0..4 {
        for j in i + 1..4 {
            if ids[i] == ids[j] {
                return None;
            }
        }
    }
    let start = (0..4).min_by_key(|&i| ids[i]).expect("four corners");
    let forward = ids[(start + 1) % 4] < ids[(start + 3) % 4];
    let step = |k: usize| {
        if forward {
            (start + k) % 4
        } else {
            (start + 4 - k) % 4
        }
    };
    Some(([0, 1, 2, 3].map(|k| ids[step(k)]), start, forward))
}

/// The position `(i, j)` of a face lattice point (face counts `(nu, nv)`) in the frame that
/// starts at cyclic corner `start` and runs towards its next (`forward`) or previous corner.
pub(super) fn face_position(
    at: [usize; 2],
    n: [usize; 2],
    start: usize,
    forward: bool,
) -> [usize; 2] {
    let corner = |c: usize| match c % 4 {
        0 => [0, 0],
        1 => [n[0], 0],
        2 => [n[0], n[1]],
        _ => [0, n[1]],
    };
    let q0 = corner(start);
    let q1 = corner(if forward { start + 1 } else { start + 3 });
    let du = [at[0].abs_diff(q0[0]), at[1].abs_diff(q0[1])];
    if q1[0] != q0[0] {
        du
    } else {
        [du[1], du[0]]
    }
}

/// The cell counts a face's canonical frame sees along its two axes.
pub(super) fn face_counts(n: [usize; 2], start: usize, forward: bool) -> [usize; 2] {
    let along_u_first = if forward {
        start.is_multiple_of(2)
    } else {
        start % 2 == 1
    };
    if along_u_first {
        n
    } else {
        [n[1], n[0]]
    }
}

/// Errors when two elements share an edge or face but would subdivide it differently (the
/// shared lattice points would not match: a crack).
pub(crate) fn check_conforming(elements: &[[u32; 8]], n: [usize; 3]) -> Result<(), FeError> {
    if n[0] == n[1] && n[1] == n[2] {
        return Ok(());
    }
    let mut seen: HashMap<Vec<u32>, (usize, Vec<usize>)> = HashMap::new();
    let mut claim = |element: usize, key: Vec<u32>, counts: Vec<usize>| -> Result<(), FeError> {
        match seen.get(&key) {
            Some((other, theirs)) if *theirs != counts => Err(FeError::NonConforming {
                element,
                other: *other,
                entity: format!("the nodes {key:?}"),
                mine: counts,
                theirs: theirs.clone(),
            }),
            Some(_) => Ok(()),
            None => {
                seen.insert(key, (element, counts));
                Ok(())
            }
        }
    };
    for (e, nodes) in elements.iter().enumerate() {
        for d in 0..3 {
            // The four element edges along d.
            for (a, b) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (u, v) = free_axes(d);
                let mut s = [0; 3];
                s[u] = a;
                s[v] = b;
                let x = node_at(nodes, s);
                s[d] = 1;
                let y = node_at(nodes, s);
                if x != y {
                    claim(e, vec![x.min(y), x.max(y)], vec![n[d]])?;
                }
            }
            for side in 0..2 {
                let (u, v) = free_axes(d);
                if let Some((corners, start, forward)) =
                    canonical_face(face_corners(nodes, d, side))
                {
                    claim(
                        e,
                        corners.to_vec(),
                        face_counts([n[u], n[v]], start, forward).to_vec(),
                    )?;
                }
            }
        }
    }
    Ok(())
}

/// Test elements: two unit hexahedra glued along x = 1 (nodes of a 2×1×1 block, id =
/// i + 3j + 6k), the second rotated a quarter turn about x (local (a, b, c) ↦ global
/// (1 + a, c, 1 − b)); and the first with its x = 1, y = 1 edge collapsed onto x = 1, y = 0
/// (a wedge).
#[cfg(test)]
pub(crate) fn glued_pair_and_wedge() -> [[u32; 8]; 3] {
    let id = |i: u32, j: u32, k: u32| i + 3 * j + 6 * k;
    let e0 = [0, 1, 2, 3, 4, 5, 6, 7].map(|l: u32| id(l & 1, l >> 1 & 1, l >> 2 & 1));
    let e1 = [0, 1, 2, 3, 4, 5, 6, 7].map(|l: u32| {
        let (a, b, c) = (l & 1, l >> 1 & 1, l >> 2 & 1);
        id(1 + a, c, 1 - b)
    });
    let wedge = [0, 1, 2, 3, 4, 5, 6, 7].map(|l: u32| id(l & 1, l >> 1 & 1 & !l, l >> 2 & 1));
    [e0, e1, wedge]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit hexahedra glued along x = 1, the second rotated a quarter turn about x.
    #[test]
    fn shared_face_points_get_one_name() {
        let [e0, e1, _] = glued_pair_and_wedge();
        let n = [4, 4, 4];
        for j in 0..=4 {
            for k in 0..=4 {
                // Global point (1, j/4, k/4): element 0 at (4, j, k), element 1 at (0, 4 − k, j).
                let a = point_key(0, &e0, n, [4, j, k]);
                let b = point_key(1, &e1, n, [0, 4 - k, j]);
                assert_eq!(a, b, "point (1, {j}, {k})");
            }
        }
        // Interior points are local.
        assert_ne!(
            point_key(0, &e0, n, [2, 2, 2]),
            point_key(1, &e1, n, [2, 2, 2])
        );
        assert!(check_conforming(&[e0, e1], n).is_ok());
        // Different counts across the rotated face do not conform.
        assert!(matches!(
            check_conforming(&[e0, e1], [4, 2, 3]),
            Err(FeError::NonConforming { .. })
        ));
    }
}
