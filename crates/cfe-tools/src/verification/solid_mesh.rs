//! Solid meshes the 3D verification cases build in code: a box on a tensor
//! grid of given coordinates (graded towards a contact), a box of mixed TET4
//! and HEX8 cells, and plane quadrangle meshes — a quarter annulus (polar
//! grid) and a quarter disc (an O-grid: a square core and two mapped blocks, so
//! no cell has a flat 180° corner on the circle) — extruded along z into HEX8
//! layers whose heights may vary over the plane (a sphere's cap).
//!
//! ```text
//!   quarter disc (O-grid)        quarter annulus (polar)
//!   y                            y
//!   |‾‾‾-._                      |‾‾-._
//!   |  B   `.                    |     `.
//!   |______  \                   |__    \
//!   | core | A|                     `.   |
//!   |______|__|__ x                   |__|__ x
//! ```
//!
//! Every mesh names its boundaries as `Mesh::<D3>::block` does where a side is
//! plane (`left` x = 0, `front` y = 0, `bottom`, `top`), and `outer` (or
//! `inner`) for the curved sides.

use cfe::dim::D3;
use cfe::mesh::{BoundaryFace, Mesh, SolidElement, SolidKind};
use std::collections::{BTreeMap, HashMap};

/// A box on the tensor grid of the coordinates `xs`, `ys`, `zs` (each
/// increasing), cells of `kind`, its sides named as [`Mesh::<D3>::block`] names
/// them (the same node and element numbering).
pub fn grid(xs: &[f64], ys: &[f64], zs: &[f64], kind: SolidKind) -> Mesh<D3> {
    let n = [xs.len() - 1, ys.len() - 1, zs.len() - 1];
    let mut m = Mesh::<D3>::block(
        [0.0, n[0] as f64],
        [0.0, n[1] as f64],
        [0.0, n[2] as f64],
        n,
        kind,
    );
    for x in &mut m.nodes {
        *x = [
            xs[x[0].round() as usize],
            ys[x[1].round() as usize],
            zs[x[2].round() as usize],
        ];
    }
    m
}

/// Coordinates from `start`: cells of size `h` up to `start + inner` (rounded
/// to whole cells), then the fewest cells growing by a constant ratio (at most
/// `ratio`) that end at `start + outer` exactly.
pub fn graded(start: f64, inner: f64, h: f64, outer: f64, ratio: f64) -> Vec<f64> {
    let n = (inner / h).round().max(1.0) as usize;
    let h = inner / n as f64;
    let mut xs: Vec<f64> = (0..=n).map(|i| start + h * i as f64).collect();
    let rest = outer - inner;
    // Σ_{i=1..k} h r^i for k cells growing by r.
    let sum = |r: f64, k: usize| (1..=k).map(|i| h * r.powi(i as i32)).sum::<f64>();
    let mut k = 1;
    while sum(ratio, k) < rest {
        k += 1;
    }
    // The ratio in [1/2, ratio] whose k cells end at `outer` (bisection).
    let (mut lo, mut hi) = (0.5, ratio);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if sum(mid, k) < rest {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let r = 0.5 * (lo + hi);
    let mut x = start + inner;
    for i in 1..=k {
        x += h * r.powi(i as i32);
        xs.push(x);
    }
    if let Some(last) = xs.last_mut() {
        *last = start + outer;
    }
    xs
}

/// `n` equal cells over `[a, b]`: n + 1 coordinates.
pub fn uniform(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect()
}

/// The box of [`Mesh::<D3>::block`] with TET4 cells where x is below the
/// middle (cell index i < nx/2) and HEX8 cells elsewhere: the same nodes, so
/// its faces carry triangles and quadrangles; sides named as the block's.
pub fn mixed_block(x: [f64; 2], y: [f64; 2], z: [f64; 2], cells: [usize; 3]) -> Mesh<D3> {
    let tet = Mesh::<D3>::block(x, y, z, cells, SolidKind::Tet4);
    let hex = Mesh::<D3>::block(x, y, z, cells, SolidKind::Hex8);
    let nx = cells[0];
    let mut elements = Vec::new();
    for c in 0..hex.elements.len() {
        if c % nx < nx / 2 {
            elements.extend_from_slice(&tet.elements[6 * c..6 * c + 6]);
        } else {
            elements.push(hex.elements[c]);
        }
    }
    let mut mesh = Mesh::<D3> {
        nodes: hex.nodes,
        elements,
        boundaries: BTreeMap::new(),
        node_sets: Default::default(),
    };
    let sides: [(&str, usize, f64); 6] = [
        ("left", 0, x[0]),
        ("right", 0, x[1]),
        ("front", 1, y[0]),
        ("back", 1, y[1]),
        ("bottom", 2, z[0]),
        ("top", 2, z[1]),
    ];
    name_faces(&mut mesh, |f, nodes| {
        sides
            .iter()
            .find(|(_, axis, at)| f.iter().all(|&n| nodes[n][*axis] == *at))
            .map(|s| s.0)
    });
    mesh
}

/// Names every boundary face of `mesh` by `side(face nodes, node coordinates)`
/// (`None`: unnamed), replacing its boundaries.
fn name_faces(mesh: &mut Mesh<D3>, side: impl Fn(&[usize], &[[f64; 3]]) -> Option<&'static str>) {
    let mut named: BTreeMap<String, Vec<BoundaryFace>> = BTreeMap::new();
    for face in mesh.boundary_faces() {
        if let Some(s) = side(face.nodes.as_slice(), &mesh.nodes) {
            named.entry(s.to_string()).or_default().push(face);
        }
    }
    mesh.boundaries = named;
}

/// A plane mesh of quadrangles: its points and its cells (corners
/// counter-clockwise).
#[derive(Debug, Clone, Default)]
pub struct Quads {
    /// Points (x, y).
    pub points: Vec<[f64; 2]>,
    /// Cells, four point indices each, counter-clockwise.
    pub cells: Vec<[usize; 4]>,
}

impl Quads {
    /// The index of the point at `p`, added if no point is within 1e-9 × `scale`
    /// of it (the blocks of an O-grid share their seams).
    fn point(&mut self, p: [f64; 2], seen: &mut HashMap<[i64; 2], usize>, scale: f64) -> usize {
        let key = p.map(|c| (c / scale * 1e9).round() as i64);
        *seen.entry(key).or_insert_with(|| {
            self.points.push(p);
            self.points.len() - 1
        })
    }

    /// Adds the structured block whose point (i, j) (i < = ni, j ≤ nj) is
    /// `at(i, j)`, its cells turned counter-clockwise.
    fn add_block(
        &mut self,
        ni: usize,
        nj: usize,
        at: impl Fn(usize, usize) -> [f64; 2],
        seen: &mut HashMap<[i64; 2], usize>,
        scale: f64,
    ) {
        let mut id = vec![vec![0; nj + 1]; ni + 1];
        for (i, row) in id.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = self.point(at(i, j), seen, scale);
            }
        }
        for i in 0..ni {
            for j in 0..nj {
                let mut c = [id[i][j], id[i + 1][j], id[i + 1][j + 1], id[i][j + 1]];
                let p = c.map(|k| self.points[k]);
                let area2: f64 = (0..4)
                    .map(|k| {
                        let (a, b) = (p[k], p[(k + 1) % 4]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum();
                if area2 < 0.0 {
                    c.swap(1, 3);
                }
                self.cells.push(c);
            }
        }
    }
}

/// The quarter annulus r₀ ≤ r ≤ r₁, 0 ≤ θ ≤ 90°: `nr` × `nt` cells of a polar
/// grid.
pub fn quarter_annulus(r: [f64; 2], nr: usize, nt: usize) -> Quads {
    let mut q = Quads::default();
    let mut seen = HashMap::new();
    q.add_block(
        nr,
        nt,
        |i, j| {
            let rr = r[0] + (r[1] - r[0]) * i as f64 / nr as f64;
            let t = std::f64::consts::FRAC_PI_2 * j as f64 / nt as f64;
            [rr * t.cos(), rr * t.sin()]
        },
        &mut seen,
        r[1],
    );
    q
}

/// The quarter disc r ≤ `radius` as an O-grid: a square core [0, s]² (s =
/// `core` × radius) of n × n cells, and two blocks of n (along the core's side)
/// × `m` (outwards) cells between the core's sides x = s and y = s and the arcs
/// 0–45° and 45–90°, their points on straight lines from the core to the arc.
pub fn quarter_disc(radius: f64, core: f64, n: usize, m: usize) -> Quads {
    let s = core * radius;
    let mut q = Quads::default();
    let mut seen = HashMap::new();
    q.add_block(
        n,
        n,
        |i, j| [s * i as f64 / n as f64, s * j as f64 / n as f64],
        &mut seen,
        radius,
    );
    let ray = |inner: [f64; 2], theta: f64, k: usize| {
        let f = k as f64 / m as f64;
        let outer = [radius * theta.cos(), radius * theta.sin()];
        [
            inner[0] + f * (outer[0] - inner[0]),
            inner[1] + f * (outer[1] - inner[1]),
        ]
    };
    let quarter = std::f64::consts::FRAC_PI_4;
    // Block A: from the side x = s (y = s j / n) to the arc θ = 45° j / n.
    q.add_block(
        m,
        n,
        |k, j| {
            ray(
                [s, s * j as f64 / n as f64],
                quarter * j as f64 / n as f64,
                k,
            )
        },
        &mut seen,
        radius,
    );
    // Block B: from the side y = s (x = s j / n) to the arc θ = 90° − 45° j / n.
    q.add_block(
        m,
        n,
        |k, j| {
            let theta = 2.0 * quarter - quarter * j as f64 / n as f64;
            ray([s * j as f64 / n as f64, s], theta, k)
        },
        &mut seen,
        radius,
    );
    q
}

/// The quadrangles `q` extruded into `layers` HEX8 layers: point p of layer k
/// (0 ≤ k ≤ layers) at height `z(p, k)` (increasing with k). Boundaries:
/// `bottom` (layer 0), `top` (layer `layers`), and on the sides `left` (x = 0),
/// `front` (y = 0), and `outer` / `inner` (the other sides: farther from or
/// nearer to the z axis than `split` — `outer` for all with `split` 0).
pub fn extrude(
    q: &Quads,
    layers: usize,
    z: impl Fn([f64; 2], usize) -> f64,
    split: f64,
) -> Mesh<D3> {
    let np = q.points.len();
    let mut nodes = Vec::with_capacity(np * (layers + 1));
    for k in 0..=layers {
        for p in &q.points {
            nodes.push([p[0], p[1], z(*p, k)]);
        }
    }
    let mut elements = Vec::with_capacity(q.cells.len() * layers);
    for k in 0..layers {
        for c in &q.cells {
            let lo = c.map(|i| k * np + i);
            let hi = c.map(|i| (k + 1) * np + i);
            elements.push(SolidElement::Hex8([
                lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3],
            ]));
        }
    }
    let mut mesh = Mesh::<D3> {
        nodes,
        elements,
        boundaries: BTreeMap::new(),
        node_sets: Default::default(),
    };
    let tol = 1e-9
        * q.points
            .iter()
            .fold(0.0f64, |a, p| a.max(p[0].abs()).max(p[1].abs()));
    name_faces(&mut mesh, |f, x| {
        let layer = |n: usize| n / np;
        if f.iter().all(|&n| layer(n) == 0) {
            Some("bottom")
        } else if f.iter().all(|&n| layer(n) == layers) {
            Some("top")
        } else if f.iter().all(|&n| x[n][0].abs() <= tol) {
            Some("left")
        } else if f.iter().all(|&n| x[n][1].abs() <= tol) {
            Some("front")
        } else if f.iter().all(|&n| x[n][0].hypot(x[n][1]) >= split) {
            Some("outer")
        } else {
            Some("inner")
        }
    });
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The O-grid quarter disc extruded is a valid mesh whose volume is the
    /// quarter cylinder's to the polygon's error (its outer points on the
    /// circle), with every side named; the polar quarter annulus likewise.
    #[test]
    fn quarter_disc_and_annulus_are_valid_and_fill_their_shapes() {
        let (r, h) = (2.0, 0.5);
        let d = extrude(
            &quarter_disc(r, 0.55, 6, 4),
            2,
            |_, k| h * k as f64 / 2.0,
            0.0,
        );
        d.validate("disc").unwrap();
        let v: f64 = (0..d.elements.len()).map(|e| d.element_volume(e)).sum();
        let exact = std::f64::consts::PI * r * r / 4.0 * h;
        // 12 chords on the quarter arc: the polygon's area deficit ≈ 0.3 %.
        assert!(v < exact && v > 0.99 * exact, "{v} {exact}");
        for side in ["bottom", "top", "left", "front", "outer"] {
            assert!(!d.boundaries[side].is_empty(), "{side}");
        }
        let outer = d.boundary_nodes("outer").unwrap();
        assert!(
            outer
                .iter()
                .all(|&n| (d.nodes[n][0].hypot(d.nodes[n][1]) - r).abs() < 1e-12)
        );
        let a = extrude(&quarter_annulus([1.0, 2.0], 3, 8), 1, |_, k| k as f64, 1.5);
        a.validate("ring").unwrap();
        assert_eq!(a.elements.len(), 24);
        assert_eq!(a.boundaries["inner"].len(), 8);
        assert_eq!(a.boundaries["outer"].len(), 8);
    }

    /// The graded coordinates start at h steps, end at the given length, and
    /// grow; the grid box keeps the block's side names.
    #[test]
    fn graded_grid_is_a_valid_box() {
        let xs = graded(0.0, 1.0, 0.25, 5.0, 1.4);
        assert_eq!(&xs[..5], &[0.0, 0.25, 0.5, 0.75, 1.0]);
        assert_eq!(*xs.last().unwrap(), 5.0);
        assert!(xs.windows(3).all(|w| w[2] - w[1] >= w[1] - w[0] - 1e-12));
        let m = grid(
            &xs,
            &uniform(0.0, 1.0, 2),
            &uniform(-1.0, 0.0, 3),
            SolidKind::Hex8,
        );
        m.validate("grid").unwrap();
        let top = m.boundary_nodes("top").unwrap();
        assert!(top.iter().all(|&n| m.nodes[n][2] == 0.0));
        let mixed = mixed_block([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [4, 2, 2]);
        mixed.validate("mixed").unwrap();
        assert_eq!(mixed.counts(), (6 * 8, 8));
    }
}
