//! The mesh assets of `assets/meshes/`, made from formulas so that they are
//! reproducible byte for byte:
//!
//! - `vase.obj`: a vase by surface of revolution of a wall profile with a
//!   rounded foot, a bulging body and a rim rounded as a torus (Chen Fig. 16);
//! - `jello.ply` (binary): a jello block, a box with edges and corners rounded
//!   as cylinders and spheres (Chen Fig. 8);
//! - `figure.glb`: a small figure (head, body, arms, legs) as the smooth union of
//!   an ellipsoid, a sphere and capsules, triangulated by marching tetrahedra,
//!   which gives a closed, manifold, non-self-intersecting surface (Chen Fig. 14).
//!
//! Every feature is rounded at a radius at least the resolution λ of the scene
//! that uses the asset, so that the tet mesh can follow it within λ/4.

#![warn(missing_docs)]

use std::collections::HashMap;

use gltf_json as json;
use json::validation::{Checked, USize64};
use perifrac_math::{dot, norm, scale, sub};
use perifrac_sim::geometry::mesh::TriMesh;

/// An asset: its file name in `assets/meshes/` and its bytes.
pub struct Asset {
    /// File name.
    pub name: &'static str,
    /// File contents.
    pub bytes: Vec<u8>,
}

/// Every asset, in a fixed order.
pub fn assets() -> Vec<Asset> {
    vec![
        Asset {
            name: "vase.obj",
            bytes: obj_bytes(
                &vase(),
                "vase: surface of revolution, made by tools/make-meshes",
            ),
        },
        Asset {
            name: "jello.ply",
            bytes: ply_bytes(
                &jello(),
                "jello block: rounded box, made by tools/make-meshes",
            ),
        },
        Asset {
            name: "figure.glb",
            bytes: glb_bytes(&figure(), "figure"),
        },
    ]
}

/// Vase wall thickness in m.
const VASE_WALL: f64 = 0.024;
/// Vase height of the wall's centreline in m.
const VASE_HEIGHT: f64 = 0.16;
/// Radius of the vase's body at the foot (centreline), in m.
const VASE_FOOT_RADIUS: f64 = 0.04;
/// How much the body bulges beyond the foot radius, in m.
const VASE_BULGE: f64 = 0.022;
/// Radius of the foot's rounded corner (centreline), in m: the inside corner is
/// rounded at this minus half the wall.
const VASE_CORNER: f64 = 0.024;
/// Segments around the axis.
const VASE_SEGMENTS: usize = 72;
/// Profile sample spacing in m.
const VASE_STEP: f64 = 0.006;

/// The vase: the wall's centreline in the (r, y) half-plane, offset by half the
/// wall on both sides, capped by a half circle at the rim, revolved about y.
pub fn vase() -> TriMesh {
    let half = VASE_WALL / 2.0;
    // Centreline: along the bottom, a quarter circle, then up the body.
    let mut centre: Vec<[f64; 2]> = Vec::new();
    let flat = VASE_FOOT_RADIUS - VASE_CORNER;
    let n = (flat / VASE_STEP).ceil() as usize;
    for i in 0..n {
        centre.push([flat * i as f64 / n as f64, half]);
    }
    let n = ((VASE_CORNER * std::f64::consts::FRAC_PI_2) / VASE_STEP).ceil() as usize;
    for i in 0..n {
        let a = -std::f64::consts::FRAC_PI_2 + std::f64::consts::FRAC_PI_2 * i as f64 / n as f64;
        centre.push([
            flat + VASE_CORNER * a.cos(),
            half + VASE_CORNER + VASE_CORNER * a.sin(),
        ]);
    }
    let y1 = half + VASE_CORNER;
    let n = ((VASE_HEIGHT - y1) / VASE_STEP).ceil() as usize;
    for i in 0..=n {
        let s = i as f64 / n as f64;
        let bulge = (std::f64::consts::PI * 0.9 * s).sin().powi(2);
        centre.push([
            VASE_FOOT_RADIUS + VASE_BULGE * bulge,
            y1 + (VASE_HEIGHT - y1) * s,
        ]);
    }
    let tangent = |i: usize| {
        let (a, b) = (
            centre[i.saturating_sub(1)],
            centre[(i + 1).min(centre.len() - 1)],
        );
        let d = [b[0] - a[0], b[1] - a[1]];
        let l = d[0].hypot(d[1]);
        [d[0] / l, d[1] / l]
    };
    let normal = |i: usize| {
        let t = tangent(i);
        [t[1], -t[0]]
    };
    let mut profile: Vec<[f64; 2]> = Vec::new();
    for (i, c) in centre.iter().enumerate() {
        let n = normal(i);
        profile.push([c[0] + half * n[0], c[1] + half * n[1]]);
    }
    let last = centre.len() - 1;
    let (end, t, nrm) = (centre[last], tangent(last), normal(last));
    let cap = 8;
    for i in 1..cap {
        let a = std::f64::consts::PI * i as f64 / cap as f64;
        profile.push([
            end[0] + half * (a.cos() * nrm[0] + a.sin() * t[0]),
            end[1] + half * (a.cos() * nrm[1] + a.sin() * t[1]),
        ]);
    }
    for (i, c) in centre.iter().enumerate().rev() {
        let n = normal(i);
        profile.push([c[0] - half * n[0], c[1] - half * n[1]]);
    }
    // The first and last points sit on the axis.
    profile[0][0] = 0.0;
    let k = profile.len() - 1;
    profile[k][0] = 0.0;
    revolve(&profile, VASE_SEGMENTS)
}

/// Revolves a profile in the (r, y) half-plane about y; profile points with
/// r = 0 become single poles. The result is wound outward.
fn revolve(profile: &[[f64; 2]], segments: usize) -> TriMesh {
    let mut vertices = Vec::new();
    let mut ring = Vec::new();
    for p in profile {
        if p[0] == 0.0 {
            vertices.push([0.0, p[1], 0.0]);
            ring.push(vec![(vertices.len() - 1) as u32; segments]);
        } else {
            let start = vertices.len() as u32;
            for j in 0..segments {
                let a = std::f64::consts::TAU * j as f64 / segments as f64;
                vertices.push([p[0] * a.cos(), p[1], -p[0] * a.sin()]);
            }
            ring.push((0..segments as u32).map(|j| start + j).collect());
        }
    }
    let mut triangles = Vec::new();
    for i in 0..profile.len() - 1 {
        for j in 0..segments {
            let k = (j + 1) % segments;
            let (a, b, c, d) = (ring[i][j], ring[i][k], ring[i + 1][j], ring[i + 1][k]);
            if a != b {
                triangles.push([a, c, b]);
            }
            if c != d {
                triangles.push([b, c, d]);
            }
        }
    }
    outward(TriMesh {
        vertices,
        triangles,
    })
}

fn outward(mut m: TriMesh) -> TriMesh {
    if m.enclosed_volume() < 0.0 {
        m.flip();
    }
    m
}

/// Jello block half extents in m (a 0.2 m cube, as in `jello-bullet.toml`).
const JELLO_HALF: [f64; 3] = [0.1, 0.1, 0.1];
/// Radius of the block's rounded edges and corners in m.
const JELLO_ROUND: f64 = 0.02;
/// Grid intervals across the flat part of a face.
const JELLO_FLAT_CELLS: usize = 14;
/// Grid intervals across each rounded band (a quarter circle spans two bands).
const JELLO_BAND_CELLS: usize = 4;

/// The jello block: a box's surface gridded densely near its edges, each point
/// `q` moved to `c + r (q − c)/|q − c|` with `c` its clamp to the box shrunk
/// by the rounding radius `r`.
pub fn jello() -> TriMesh {
    let r = JELLO_ROUND;
    let nodes = |h: f64| -> Vec<f64> {
        let inner = h - r;
        let mut band: Vec<f64> = (1..=JELLO_BAND_CELLS)
            .map(|i| {
                let a = std::f64::consts::FRAC_PI_4 * i as f64 / JELLO_BAND_CELLS as f64;
                inner + r * a.tan()
            })
            .collect();
        if let Some(last) = band.last_mut() {
            *last = h;
        }
        let mut out: Vec<f64> = band.iter().rev().map(|x| -x).collect();
        out.extend(
            (0..=JELLO_FLAT_CELLS)
                .map(|i| -inner + 2.0 * inner * i as f64 / JELLO_FLAT_CELLS as f64),
        );
        out.extend(band);
        out
    };
    let axis_nodes = JELLO_HALF.map(nodes);
    let mut mesh = TriMesh::default();
    for a in 0..3 {
        let (u, v) = ((a + 1) % 3, (a + 2) % 3);
        for s in [-1.0, 1.0] {
            let (nu, nv) = (&axis_nodes[u], &axis_nodes[v]);
            let start = mesh.vertices.len() as u32;
            for &y in nv {
                for &x in nu {
                    let mut q = [0.0; 3];
                    q[a] = s * JELLO_HALF[a];
                    q[u] = x;
                    q[v] = y;
                    mesh.vertices.push(q);
                }
            }
            let w = nu.len() as u32;
            for j in 0..nv.len() as u32 - 1 {
                for i in 0..w - 1 {
                    let (p00, p10) = (start + j * w + i, start + j * w + i + 1);
                    let (p01, p11) = (p00 + w, p10 + w);
                    // (u, v, a) is right-handed: u × v = a, so (p00, p10, p11)
                    // faces +a; flip on the −a face.
                    for t in [[p00, p10, p11], [p00, p11, p01]] {
                        mesh.triangles
                            .push(if s > 0.0 { t } else { [t[0], t[2], t[1]] });
                    }
                }
            }
        }
    }
    mesh.weld();
    for p in &mut mesh.vertices {
        let c = [0, 1, 2].map(|k| p[k].clamp(-(JELLO_HALF[k] - r), JELLO_HALF[k] - r));
        let d = sub(*p, c);
        let l = norm(d);
        *p = [0, 1, 2].map(|k| c[k] + r * d[k] / l);
    }
    outward(mesh)
}

/// Grid cell of the figure's marching tetrahedra, in m.
const FIGURE_CELL: f64 = 0.008;
/// Fillet size of the smooth union joining the figure's parts, in m.
const FIGURE_BLEND: f64 = 0.035;

fn capsule(p: [f64; 3], a: [f64; 3], b: [f64; 3], r: f64) -> f64 {
    let (pa, ba) = (sub(p, a), sub(b, a));
    let h = (dot(pa, ba) / dot(ba, ba)).clamp(0.0, 1.0);
    norm(sub(pa, scale(ba, h))) - r
}

/// Approximate ellipsoid distance (exact zero set): `k0 (k0 − 1) / k1`.
fn ellipsoid(p: [f64; 3], c: [f64; 3], r: [f64; 3]) -> f64 {
    let q = sub(p, c);
    let k0 = norm([0, 1, 2].map(|k| q[k] / r[k]));
    let k1 = norm([0, 1, 2].map(|k| q[k] / (r[k] * r[k])));
    k0 * (k0 - 1.0) / k1
}

/// Polynomial smooth minimum with blend width `k`.
fn smooth_min(a: f64, b: f64, k: f64) -> f64 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k / 4.0
}

/// The figure's implicit function (negative inside): standing on y = 0, arms
/// out along x.
pub fn figure_field(p: [f64; 3]) -> f64 {
    let parts = [
        ellipsoid(p, [0.0, 0.16, 0.0], [0.055, 0.07, 0.04]),
        norm([p[0], p[1] - 0.27, p[2]]) - 0.045,
        capsule(p, [0.03, 0.195, 0.0], [0.155, 0.2, 0.0], 0.027),
        capsule(p, [-0.03, 0.195, 0.0], [-0.155, 0.2, 0.0], 0.027),
        capsule(p, [0.03, 0.12, 0.0], [0.045, 0.029, 0.0], 0.028),
        capsule(p, [-0.03, 0.12, 0.0], [-0.045, 0.029, 0.0], 0.028),
    ];
    parts[1..]
        .iter()
        .fold(parts[0], |acc, &d| smooth_min(acc, d, FIGURE_BLEND))
}

/// The figure, by marching tetrahedra over [`figure_field`].
pub fn figure() -> TriMesh {
    let lo = [-0.21, -0.01, -0.07];
    let hi = [0.21, 0.33, 0.07];
    outward(marching_tetrahedra(figure_field, lo, hi, FIGURE_CELL))
}

/// The six tetrahedra of a cube around its diagonal from corner 0 to corner 7
/// (corner bits: x = 1, y = 2, z = 4); neighbouring cubes split their shared
/// faces the same way, so the surface is closed.
const KUHN: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

/// Zero set of `field` over the box `[lo, hi]` with cubes of side `cell`,
/// each split into six tetrahedra. Cut points are placed by linear
/// interpolation, kept 1% of an edge away from its ends (no zero-area
/// triangles); values of exactly zero count as outside.
pub fn marching_tetrahedra(
    field: impl Fn([f64; 3]) -> f64,
    lo: [f64; 3],
    hi: [f64; 3],
    cell: f64,
) -> TriMesh {
    let n = [0, 1, 2].map(|k| ((hi[k] - lo[k]) / cell).ceil() as usize);
    let id = |i: usize, j: usize, k: usize| (k * (n[1] + 1) + j) * (n[0] + 1) + i;
    let point = |i: usize, j: usize, k: usize| {
        [
            lo[0] + i as f64 * cell,
            lo[1] + j as f64 * cell,
            lo[2] + k as f64 * cell,
        ]
    };
    let mut values = vec![0.0; (n[0] + 1) * (n[1] + 1) * (n[2] + 1)];
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                values[id(i, j, k)] = field(point(i, j, k));
            }
        }
    }
    let mut mesh = TriMesh::default();
    let mut cuts: HashMap<(usize, usize), u32> = HashMap::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let corner = |c: usize| (i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                for tet in KUHN {
                    let ids = tet.map(|c| {
                        let (a, b, d) = corner(c);
                        id(a, b, d)
                    });
                    let pts = tet.map(|c| {
                        let (a, b, d) = corner(c);
                        point(a, b, d)
                    });
                    let f = ids.map(|v| values[v]);
                    let inside: Vec<usize> = (0..4).filter(|&v| f[v] < 0.0).collect();
                    let outside: Vec<usize> = (0..4).filter(|&v| f[v] >= 0.0).collect();
                    if inside.is_empty() || outside.is_empty() {
                        continue;
                    }
                    let mut cut = |a: usize, b: usize| -> u32 {
                        let key = (ids[a].min(ids[b]), ids[a].max(ids[b]));
                        *cuts.entry(key).or_insert_with(|| {
                            // From the inside corner a to the outside corner b.
                            let t = (f[a] / (f[a] - f[b])).clamp(0.01, 0.99);
                            mesh.vertices
                                .push([0, 1, 2].map(|x| pts[a][x] + t * (pts[b][x] - pts[a][x])));
                            (mesh.vertices.len() - 1) as u32
                        })
                    };
                    let polygon: Vec<u32> = match (inside.len(), outside.len()) {
                        (1, 3) => outside.iter().map(|&o| cut(inside[0], o)).collect(),
                        (3, 1) => inside.iter().map(|&v| cut(v, outside[0])).collect(),
                        _ => vec![
                            cut(inside[0], outside[0]),
                            cut(inside[0], outside[1]),
                            cut(inside[1], outside[1]),
                            cut(inside[1], outside[0]),
                        ],
                    };
                    // Orient each triangle from the inside corners towards the outside ones.
                    let mean = |s: &[usize]| {
                        [0, 1, 2]
                            .map(|x| s.iter().map(|&v| pts[v][x]).sum::<f64>() / s.len() as f64)
                    };
                    let (ci, co) = (mean(&inside), mean(&outside));
                    let out_dir = [0, 1, 2].map(|x| co[x] - ci[x]);
                    for t in 1..polygon.len() - 1 {
                        let tri = [polygon[0], polygon[t], polygon[t + 1]];
                        let [a, b, c] = tri.map(|v| mesh.vertices[v as usize]);
                        let e1 = [0, 1, 2].map(|x| b[x] - a[x]);
                        let e2 = [0, 1, 2].map(|x| c[x] - a[x]);
                        let nrm = [
                            e1[1] * e2[2] - e1[2] * e2[1],
                            e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0],
                        ];
                        let d = (0..3).map(|x| nrm[x] * out_dir[x]).sum::<f64>();
                        mesh.triangles.push(if d >= 0.0 {
                            tri
                        } else {
                            [tri[0], tri[2], tri[1]]
                        });
                    }
                }
            }
        }
    }
    mesh
}

/// Wavefront OBJ text: a comment, `v` lines (6 decimals), `f` lines.
pub fn obj_bytes(m: &TriMesh, comment: &str) -> Vec<u8> {
    let mut s = format!("# {comment}\n");
    for v in &m.vertices {
        s += &format!("v {:.6} {:.6} {:.6}\n", v[0], v[1], v[2]);
    }
    for t in &m.triangles {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s.into_bytes()
}

/// Binary little-endian PLY: float x, y, z; faces as uchar-counted int lists.
pub fn ply_bytes(m: &TriMesh, comment: &str) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment {comment}\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        m.vertices.len(),
        m.triangles.len()
    )
    .into_bytes();
    for v in &m.vertices {
        for x in v {
            out.extend_from_slice(&(*x as f32).to_le_bytes());
        }
    }
    for t in &m.triangles {
        out.push(3);
        for i in t {
            out.extend_from_slice(&(*i as i32).to_le_bytes());
        }
    }
    out
}

/// A GLB with one node, one mesh, one triangle primitive (float positions with
/// min/max, u32 indices; buffer views 4-byte aligned with their targets).
pub fn glb_bytes(m: &TriMesh, name: &str) -> Vec<u8> {
    let positions: Vec<[f32; 3]> = m.vertices.iter().map(|v| v.map(|x| x as f32)).collect();
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in &positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let mut bin = Vec::new();
    for p in &positions {
        for x in p {
            bin.extend_from_slice(&x.to_le_bytes());
        }
    }
    let index_offset = bin.len();
    for t in &m.triangles {
        for i in t {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    let mut root = json::Root::default();
    let buffer = root.push(json::Buffer {
        byte_length: USize64::from(bin.len()),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let view = |root: &mut json::Root, offset: usize, length: usize, target| {
        root.push(json::buffer::View {
            buffer,
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Checked::Valid(target)),
            extensions: None,
            extras: Default::default(),
        })
    };
    let position_view = view(
        &mut root,
        0,
        index_offset,
        json::buffer::Target::ArrayBuffer,
    );
    let index_view = view(
        &mut root,
        index_offset,
        bin.len() - index_offset,
        json::buffer::Target::ElementArrayBuffer,
    );
    let accessor = |view, count: usize, component, type_, bounds: Option<([f32; 3], [f32; 3])>| {
        json::Accessor {
            buffer_view: Some(view),
            byte_offset: Some(USize64(0)),
            count: USize64::from(count),
            component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Checked::Valid(type_),
            min: bounds.map(|(l, _)| json::Value::from(l.to_vec())),
            max: bounds.map(|(_, h)| json::Value::from(h.to_vec())),
            name: None,
            normalized: false,
            sparse: None,
        }
    };
    let position_accessor = root.push(accessor(
        position_view,
        positions.len(),
        json::accessor::ComponentType::F32,
        json::accessor::Type::Vec3,
        Some((lo, hi)),
    ));
    let index_accessor = root.push(accessor(
        index_view,
        3 * m.triangles.len(),
        json::accessor::ComponentType::U32,
        json::accessor::Type::Scalar,
        None,
    ));
    let mesh = root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some(name.to_string()),
        primitives: vec![json::mesh::Primitive {
            attributes: [(
                Checked::Valid(json::mesh::Semantic::Positions),
                position_accessor,
            )]
            .into_iter()
            .collect(),
            extensions: None,
            extras: Default::default(),
            indices: Some(index_accessor),
            material: None,
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets: None,
        }],
        weights: None,
    });
    let node = root.push(json::Node {
        mesh: Some(mesh),
        name: Some(name.to_string()),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);
    root.asset.generator = Some("perifrac tools/make-meshes".into());
    let mut text = root.to_vec().unwrap_or_default();
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed files are exactly what the generators write.
    #[test]
    fn reproduces_the_committed_assets() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/meshes");
        for asset in assets() {
            let committed = std::fs::read(dir.join(asset.name)).expect("committed asset");
            assert!(
                committed == asset.bytes,
                "{} differs from what make-meshes writes: run `cargo run -p make-meshes`",
                asset.name
            );
        }
    }
}
