//! Reading an output directory for previews: which frames exist, the colliders and the
//! ground from the resolved `scene.toml`, mesh colliders' geometry from
//! `colliders/mesh_N.ply`, per-frame collider positions and rotations from
//! `manifest.json`, particles from `particles/NNNN.ply`, surfaces from
//! `surface/NNNN.glb` (embedded or VDB meshes, with crack faces and `_DAMAGE`), turned
//! into [`FrameGeometry`].

use std::path::Path;

use perifrac_cache::Layout;
use perifrac_cache::collider::{MovingCollider, mesh_colliders};
use perifrac_cache::manifest::Manifest;
use perifrac_cache::mesh::SurfaceMesh;
use perifrac_cache::ply::ParticleFrame;
use perifrac_cache::scene::{ColliderSpec, Scene};
use rayon::prelude::*;

use crate::RenderError;
use crate::camera::Bounds;
use crate::geometry::{self, FrameGeometry, Shading};

/// What the particles (and, for damage, the meshes) are coloured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorBy {
    /// Meshes by material (surface and crack faces apart), particles by damage.
    #[default]
    Auto,
    /// Damage φ, blue intact → red broken (Chen et al. 2018, Fig. 6).
    Damage,
    /// Fragment id (particles).
    Fragment,
    /// Plastic strain (particles), scaled by the sequence's largest value.
    Plastic,
    /// Temperature (particles; the PLY must have a `temperature` property).
    Temperature,
    /// A membrane's diffused quantity θ (Han Eq. 25): its sheet surfaces' `_QUANTITY`
    /// attribute, or the particles' `quantity` property; the viridis-like map over the
    /// sequence's range.
    Quantity,
}

/// Value ranges over a whole sequence, so colours mean the same in every frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ranges {
    /// Largest plastic strain.
    pub plastic_max: f32,
    /// Smallest and largest temperature.
    pub temperature: (f32, f32),
    /// Smallest and largest diffused quantity θ.
    pub quantity: [f32; 2],
}

/// The empty range (−∞ < +∞ fails), which every value widens.
const NO_RANGE: [f32; 2] = [f32::INFINITY, f32::NEG_INFINITY];

/// `range` widened by the finite values of `values`.
fn widen(range: [f32; 2], values: &[f32]) -> [f32; 2] {
    values
        .iter()
        .filter(|v| v.is_finite())
        .fold(range, |[lo, hi], &v| [lo.min(v), hi.max(v)])
}

/// An output directory opened for rendering.
#[derive(Debug, Clone)]
pub struct Cache {
    /// The directory's paths.
    pub layout: Layout,
    /// Frame numbers with particles or a surface, ascending.
    pub frames: Vec<usize>,
    manifest: Option<Manifest>,
    colliders: Vec<ColliderSpec>,
    /// The mesh colliders' geometry and poses, in scene order.
    meshes: Vec<MovingCollider>,
    ground: Option<f32>,
    /// Particle radius of each body (half its resolution λ).
    radii: Vec<f32>,
    fps: f64,
}

impl Cache {
    /// Opens `root`: it needs `scene.toml`, at least one particle or surface frame and,
    /// for each mesh collider, its `colliders/mesh_N.ply`.
    pub fn open(root: &Path) -> Result<Cache, RenderError> {
        let layout = Layout::new(root);
        if !layout.scene().is_file() {
            return Err(RenderError::Input {
                path: layout.scene(),
                message: "not found; is this the output directory of a `perifrac run`?".into(),
            });
        }
        let scene = Scene::load_cached(&layout.scene())?;
        let manifest = Manifest::read(&layout.manifest()).ok();
        let mut frames = layout.particle_frames();
        frames.extend(layout.surface_frames());
        frames.sort_unstable();
        frames.dedup();
        if frames.is_empty() {
            return Err(RenderError::Input {
                path: root.to_path_buf(),
                message: "no frames to render: neither particles/NNNN.ply nor surface/NNNN.glb"
                    .into(),
            });
        }
        let meshes = mesh_colliders(&layout, &scene, manifest.as_ref())?;
        let ground = scene.colliders.iter().find_map(|c| match c {
            ColliderSpec::Ground { height, .. } => Some(*height as f32),
            _ => None,
        });
        Ok(Cache {
            layout,
            frames,
            manifest,
            radii: scene
                .bodies
                .iter()
                .map(|b| 0.5 * b.resolution as f32)
                .collect(),
            colliders: scene.colliders,
            meshes,
            ground,
            fps: scene.scene.fps,
        })
    }

    /// Whether frame `frame` is drawn from its surface mesh (rather than particles).
    pub fn uses_surface(&self, frame: usize, color_by: ColorBy) -> bool {
        matches!(
            color_by,
            ColorBy::Auto | ColorBy::Damage | ColorBy::Quantity
        ) && self.layout.surface(frame).is_file()
    }

    /// The ground height, if the scene has a ground collider.
    pub fn ground(&self) -> Option<f32> {
        self.ground
    }

    /// Collider centres at `frame`: from the manifest where the run recorded them,
    /// else from the scene (start position moved at its start velocity).
    fn collider_centers(&self, frame: usize) -> Vec<[f32; 3]> {
        let recorded = self
            .manifest
            .as_ref()
            .and_then(|m| m.collider_centers.get(frame - 1));
        let time = self
            .manifest
            .as_ref()
            .and_then(|m| m.frame_times.get(frame - 1).copied())
            .unwrap_or((frame - 1) as f64 / self.fps);
        self.colliders
            .iter()
            .enumerate()
            .map(|(i, c)| {
                if let Some(p) = recorded.and_then(|r| r.get(i)) {
                    return p.map(|v| v as f32);
                }
                match c {
                    ColliderSpec::Sphere {
                        center, velocity, ..
                    }
                    | ColliderSpec::Box {
                        center, velocity, ..
                    } => std::array::from_fn(|k| (center[k] + velocity[k] * time) as f32),
                    ColliderSpec::Ground { height, .. } => [0.0, *height as f32, 0.0],
                    ColliderSpec::Mesh { translation, .. } => translation.map(|v| v as f32),
                }
            })
            .collect()
    }

    fn push_colliders(&self, frame: usize, g: &mut FrameGeometry) {
        let color = geometry::collider_color();
        for (c, center) in self.colliders.iter().zip(self.collider_centers(frame)) {
            match c {
                ColliderSpec::Sphere { radius, .. } => g.push_sphere(center, *radius as f32, color),
                ColliderSpec::Box { size, .. } => g.push_box(center, size.map(|v| v as f32), color),
                // The ground is the renderer's floor; mesh colliders below.
                ColliderSpec::Ground { .. } | ColliderSpec::Mesh { .. } => {}
            }
        }
        for collider in &self.meshes {
            let (center, rotation) = collider.pose(frame);
            let positions = geometry::posed(&collider.mesh.positions, center, rotation);
            g.push_flat_mesh(&positions, &collider.mesh.triangles, color);
        }
    }

    fn radius(&self, material: f32) -> f32 {
        let fallback = self.radii.first().copied().unwrap_or(0.005);
        if material.is_finite() && material >= 0.0 {
            self.radii
                .get(material as usize)
                .copied()
                .unwrap_or(fallback)
        } else {
            fallback
        }
    }

    /// The geometry of `frame`: its surface or its particles, and the colliders.
    pub fn geometry(
        &self,
        frame: usize,
        color_by: ColorBy,
        ranges: &Ranges,
    ) -> Result<FrameGeometry, RenderError> {
        let mut g = FrameGeometry {
            ground: self.ground,
            ..FrameGeometry::default()
        };
        if self.uses_surface(frame, color_by) {
            read_glb(&self.layout.surface(frame), color_by, ranges, &mut g)?;
        } else if self.layout.particles(frame).is_file() {
            let path = self.layout.particles(frame);
            let p = ParticleFrame::read(&path)?;
            let colors: Vec<[f32; 3]> = match color_by {
                ColorBy::Auto | ColorBy::Damage => p
                    .damage
                    .iter()
                    .map(|&d| geometry::damage_color(d))
                    .collect(),
                ColorBy::Fragment => p
                    .fragment
                    .iter()
                    .map(|&f| geometry::fragment_color(f))
                    .collect(),
                ColorBy::Plastic => {
                    let max = ranges.plastic_max.max(f32::MIN_POSITIVE);
                    p.plastic
                        .iter()
                        .map(|&e| geometry::plastic_color(e / max))
                        .collect()
                }
                ColorBy::Temperature => {
                    let t = temperature(&p, &path)?;
                    let (lo, hi) = ranges.temperature;
                    let span = (hi - lo).max(f32::MIN_POSITIVE);
                    t.iter()
                        .map(|&v| geometry::temperature_color((v - lo) / span))
                        .collect()
                }
                ColorBy::Quantity => quantity(&p, &path)?
                    .iter()
                    .map(|&v| geometry::quantity_color(v, ranges.quantity))
                    .collect(),
            };
            g.points.reserve(p.len() * geometry::POINT_STRIDE);
            for ((&position, &material), color) in p.position.iter().zip(&p.material).zip(colors) {
                g.push_point(position, self.radius(material), color);
            }
        }
        self.push_colliders(frame, &mut g);
        Ok(g)
    }

    /// Bounds of every frame (particles trimmed of the farthest 0.2 % on each side of
    /// each axis, so a few far-flung fragments do not shrink the subject), colliders
    /// included, and the sequence's value ranges for `color_by`.
    pub fn sequence_bounds(&self, color_by: ColorBy) -> Result<(Bounds, Ranges), RenderError> {
        // Every frame's result is kept and the first error in frame order reported, so
        // the message does not depend on which thread failed first.
        let per_frame: Vec<Result<(Bounds, Ranges), RenderError>> = self
            .frames
            .par_iter()
            .map(|&frame| -> Result<(Bounds, Ranges), RenderError> {
                let mut ranges = Ranges {
                    plastic_max: 0.0,
                    temperature: (f32::INFINITY, f32::NEG_INFINITY),
                    quantity: NO_RANGE,
                };
                let mut g = FrameGeometry::default();
                self.push_colliders(frame, &mut g);
                let mut bounds = g.bounds();
                if self.uses_surface(frame, color_by) {
                    let mut s = FrameGeometry::default();
                    ranges.quantity =
                        read_glb(&self.layout.surface(frame), color_by, &ranges, &mut s)?;
                    bounds = bounds.union(&s.bounds());
                } else if self.layout.particles(frame).is_file() {
                    let path = self.layout.particles(frame);
                    let p = ParticleFrame::read(&path)?;
                    bounds = bounds.union(&trimmed_bounds(&p.position, self.radius(0.0)));
                    ranges.plastic_max = p
                        .plastic
                        .iter()
                        .copied()
                        .filter(|v| v.is_finite())
                        .fold(0.0, f32::max);
                    if color_by == ColorBy::Temperature {
                        for &v in temperature(&p, &path)? {
                            if v.is_finite() {
                                ranges.temperature.0 = ranges.temperature.0.min(v);
                                ranges.temperature.1 = ranges.temperature.1.max(v);
                            }
                        }
                    }
                    if color_by == ColorBy::Quantity {
                        ranges.quantity = widen(NO_RANGE, quantity(&p, &path)?);
                    }
                }
                Ok((bounds, ranges))
            })
            .collect();
        let per_frame: Vec<(Bounds, Ranges)> = per_frame.into_iter().collect::<Result<_, _>>()?;
        let mut bounds = Bounds::EMPTY;
        let mut ranges = Ranges {
            plastic_max: 0.0,
            temperature: (f32::INFINITY, f32::NEG_INFINITY),
            quantity: NO_RANGE,
        };
        for (b, r) in per_frame {
            bounds = bounds.union(&b);
            ranges.plastic_max = ranges.plastic_max.max(r.plastic_max);
            ranges.temperature.0 = ranges.temperature.0.min(r.temperature.0);
            ranges.temperature.1 = ranges.temperature.1.max(r.temperature.1);
            ranges.quantity = widen(ranges.quantity, &r.quantity);
        }
        if !ranges.temperature.0.is_finite() {
            ranges.temperature = (0.0, 1.0);
        }
        if ranges.quantity[0] > ranges.quantity[1] {
            ranges.quantity = [0.0, 0.0];
        }
        Ok((bounds, ranges))
    }
}

/// Bounds of `points` without the 0.2 % farthest on each side of each axis, grown by
/// `radius`.
pub fn trimmed_bounds(points: &[[f32; 3]], radius: f32) -> Bounds {
    let finite: Vec<[f32; 3]> = points
        .iter()
        .copied()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .collect();
    if finite.is_empty() {
        return Bounds::EMPTY;
    }
    let cut = finite.len() / 500;
    let mut b = Bounds::EMPTY;
    for k in 0..3 {
        let mut values: Vec<f32> = finite.iter().map(|p| p[k]).collect();
        let hi = values.len() - 1 - cut;
        let (_, &mut lo_v, _) = values.select_nth_unstable_by(cut, f32::total_cmp);
        let (_, &mut hi_v, _) = values.select_nth_unstable_by(hi, f32::total_cmp);
        b.min[k] = lo_v - radius;
        b.max[k] = hi_v + radius;
    }
    b
}

/// The `temperature` column of a particle frame (read from `path`).
fn temperature<'a>(p: &'a ParticleFrame, path: &Path) -> Result<&'a [f32], RenderError> {
    p.extra("temperature").ok_or_else(|| RenderError::Input {
        path: path.to_path_buf(),
        message: "the particles have no 'temperature' property (only scenes with heat \
                  diffusion or a thermal Johnson–Cook MPM material write it); use \
                  --color-by damage, fragment or plastic"
            .into(),
    })
}

/// The `quantity` column of a membrane's particle frame (read from `path`).
fn quantity<'a>(p: &'a ParticleFrame, path: &Path) -> Result<&'a [f32], RenderError> {
    p.extra("quantity").ok_or_else(|| RenderError::Input {
        path: path.to_path_buf(),
        message: "the particles have no 'quantity' property (only membrane scenes write                   it); use --color-by damage, fragment or plastic"
            .into(),
    })
}

/// Appends the triangle meshes of a .glb file: primitives of the material named
/// "crack" are crack faces; with `ColorBy::Damage` a `_DAMAGE` vertex attribute colours
/// the vertices, with `ColorBy::Quantity` a `_QUANTITY` one (θ, on the map over
/// `ranges.quantity`; a primitive without it is an error). Points and lines (debris)
/// are skipped. Returns the range of the `_QUANTITY` values read (empty, +∞ > −∞,
/// unless `color_by` is `Quantity`).
pub fn read_glb(
    path: &Path,
    color_by: ColorBy,
    ranges: &Ranges,
    g: &mut FrameGeometry,
) -> Result<[f32; 2], RenderError> {
    let bad = |message: String| RenderError::Input {
        path: path.to_path_buf(),
        message,
    };
    let bytes = std::fs::read(path).map_err(|e| RenderError::io(path, e))?;
    let gltf =
        gltf::Gltf::from_slice(&bytes).map_err(|e| bad(format!("not a glTF binary: {e}")))?;
    let blob = gltf.blob.as_deref();
    let buffer = |b: gltf::Buffer<'_>| match b.source() {
        gltf::buffer::Source::Bin => blob,
        gltf::buffer::Source::Uri(_) => None,
    };
    let damage_semantic = gltf::Semantic::Extras("DAMAGE".into());
    let quantity_semantic = gltf::Semantic::Extras("QUANTITY".into());
    let mut range = NO_RANGE;
    for mesh in gltf.meshes() {
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let reader = primitive.reader(buffer);
            let Some(positions) = reader.read_positions() else {
                return Err(bad(format!(
                    "mesh '{}' has a primitive without positions (or external buffers)",
                    mesh.name().unwrap_or("?")
                )));
            };
            let positions: Vec<[f32; 3]> = positions.collect();
            let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            let crack = primitive.material().name() == Some("crack");
            let shading = if crack {
                Shading::Crack
            } else {
                Shading::Surface
            };
            let base = if crack {
                geometry::crack_color()
            } else {
                geometry::surface_color()
            };
            let values = |semantic: &gltf::Semantic| -> Option<Vec<f32>> {
                primitive
                    .get(semantic)
                    .and_then(|a| gltf::accessor::Iter::<f32>::new(a, buffer))
                    .map(|it| it.collect())
            };
            let damage = (color_by == ColorBy::Damage)
                .then(|| values(&damage_semantic))
                .flatten();
            let quantity = match color_by {
                ColorBy::Quantity => Some(values(&quantity_semantic).ok_or_else(|| {
                    bad(format!(
                        "mesh '{}' has no _QUANTITY attribute (only membranes' sheet surfaces                          carry θ); use --color-by damage, or run `perifrac surface OUT --method                          sheet` on a membrane cache",
                        mesh.name().unwrap_or("?")
                    ))
                })?),
                _ => None,
            };
            if let Some(q) = &quantity {
                range = widen(range, q);
            }
            let colors = |i: usize| match (&damage, &quantity) {
                (Some(d), _) => geometry::damage_color(d.get(i).copied().unwrap_or(0.0)),
                (_, Some(q)) => {
                    geometry::quantity_color(q.get(i).copied().unwrap_or(0.0), ranges.quantity)
                }
                _ => base,
            };
            g.push_mesh(&positions, normals.as_deref(), &colors, &indices, shading);
        }
    }
    Ok(range)
}

/// Reads the meshes of a .glb file the surface stage wrote (`surface/NNNN.glb`) back
/// into the cache's surface type, one [`SurfaceMesh`] a glTF mesh, named like it:
/// primitives of the material named "crack" give the crack triangles, the others the
/// original surface's; primitives that share their position accessor share vertices;
/// `_DAMAGE` is read when every primitive carries it. Points and lines are skipped.
pub fn read_surfaces(path: &Path) -> Result<Vec<SurfaceMesh>, RenderError> {
    let bad = |message: String| RenderError::Input {
        path: path.to_path_buf(),
        message,
    };
    let bytes = std::fs::read(path).map_err(|e| RenderError::io(path, e))?;
    let gltf =
        gltf::Gltf::from_slice(&bytes).map_err(|e| bad(format!("not a glTF binary: {e}")))?;
    let blob = gltf.blob.as_deref();
    let buffer = |b: gltf::Buffer<'_>| match b.source() {
        gltf::buffer::Source::Bin => blob,
        gltf::buffer::Source::Uri(_) => None,
    };
    let damage_semantic = gltf::Semantic::Extras("DAMAGE".into());
    let mut meshes = Vec::new();
    for mesh in gltf.meshes() {
        let name = mesh.name().unwrap_or("").to_string();
        let mut out = SurfaceMesh {
            name: name.clone(),
            ..SurfaceMesh::default()
        };
        let mut with_damage = true;
        // (position accessor, first vertex) of the primitives read so far.
        let mut shared: Vec<(usize, u32)> = Vec::new();
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let Some(accessor) = primitive.get(&gltf::Semantic::Positions) else {
                return Err(bad(format!(
                    "mesh '{name}' has a primitive without positions"
                )));
            };
            let reader = primitive.reader(buffer);
            let base = match shared.iter().find(|(a, _)| *a == accessor.index()) {
                Some(&(_, base)) => base,
                None => {
                    let base = out.positions.len() as u32;
                    let positions: Vec<[f32; 3]> = reader
                        .read_positions()
                        .ok_or_else(|| {
                            bad(format!("mesh '{name}': positions in an external buffer"))
                        })?
                        .collect();
                    let normals: Vec<[f32; 3]> = match reader.read_normals() {
                        Some(n) => n.collect(),
                        None => vec![[0.0; 3]; positions.len()],
                    };
                    let damage = primitive
                        .get(&damage_semantic)
                        .and_then(|a| gltf::accessor::Iter::<f32>::new(a, buffer));
                    match damage {
                        Some(d) if with_damage => out.damage.extend(d),
                        _ => with_damage = false,
                    }
                    out.positions.extend(positions);
                    out.normals.extend(normals);
                    shared.push((accessor.index(), base));
                    base
                }
            };
            let count = accessor.count() as u32;
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..count).collect(),
            };
            if let Some(&i) = indices.iter().find(|&&i| i >= count) {
                return Err(bad(format!(
                    "mesh '{name}': index {i} past its {count} vertices"
                )));
            }
            let list = if primitive.material().name() == Some("crack") {
                &mut out.crack_indices
            } else {
                &mut out.surface_indices
            };
            list.extend(indices.iter().map(|i| i + base));
        }
        if !with_damage || out.damage.len() != out.positions.len() {
            out.damage.clear();
        }
        meshes.push(out);
    }
    Ok(meshes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trimmed_bounds_ignore_a_few_outliers() {
        let mut pts: Vec<[f32; 3]> = (0..1000).map(|i| [i as f32 / 1000.0, 0.0, 0.0]).collect();
        pts.push([1e6, 0.0, 0.0]);
        pts.push([f32::NAN, 0.0, 0.0]);
        let b = trimmed_bounds(&pts, 0.0);
        assert!(b.max[0] < 1.0 && b.min[0] >= 0.0, "{b:?}");
    }

    #[test]
    fn missing_temperature_is_named() {
        let mut f = ParticleFrame {
            frame: 1,
            position: vec![[0.0; 3]],
            velocity: vec![[0.0; 3]],
            damage: vec![0.0],
            plastic: vec![0.0],
            material: vec![0.0],
            fragment: vec![0.0],
            ..ParticleFrame::default()
        };
        let err = temperature(&f, Path::new("p/0001.ply")).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("p/0001.ply") && text.contains("temperature"),
            "{text}"
        );
        f.extra = vec![("temperature".into(), vec![300.0])];
        assert_eq!(temperature(&f, Path::new("p")).unwrap(), [300.0]);
    }

    #[test]
    fn a_mesh_collider_is_drawn_at_the_frames_pose() {
        use perifrac_cache::collider::ColliderMesh;
        let dir = tempfile::tempdir().unwrap();
        let layout = Layout::new(dir.path());
        layout.create().unwrap();
        let table = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/meshes/table.obj");
        let scene = format!(
            "[scene]\nname = \"t\"\n\n[materials.m]\ndensity = 1000.0\nbulk_modulus = 1e5\n\
             shear_modulus = 1e5\n\n[[body]]\nmaterial = \"m\"\nresolution = 0.02\nshape = \
             {{ type = \"box\", center = [0, 0.4, 0], size = [0.1, 0.1, 0.1] }}\n\n\
             [[collider]]\ntype = \"mesh\"\npath = {:?}\n",
            table.to_str().unwrap()
        );
        std::fs::write(layout.scene(), scene).unwrap();
        // A quarter turn about y at frame 1: x ↦ −z.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        Manifest {
            frame_times: vec![0.0],
            collider_centers: vec![vec![[1.0, 2.0, 3.0]]],
            collider_rotations: vec![vec![[0.0, h, 0.0, h]]],
            ..Manifest::default()
        }
        .write(&layout.manifest())
        .unwrap();
        ParticleFrame {
            frame: 1,
            position: vec![[0.0, 0.4, 0.0]],
            velocity: vec![[0.0; 3]],
            damage: vec![0.0],
            plastic: vec![0.0],
            material: vec![0.0],
            fragment: vec![0.0],
            ..ParticleFrame::default()
        }
        .write(&layout.particles(1))
        .unwrap();
        let err = Cache::open(dir.path()).unwrap_err();
        let text = err.to_string();
        assert!(
            matches!(&err, RenderError::Cache(c) if c.is_bad_input())
                && text.contains("colliders/mesh_0.ply")
                && text.contains("--force"),
            "{text}"
        );
        std::fs::create_dir_all(layout.colliders_dir()).unwrap();
        let mesh = ColliderMesh {
            positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
            pivot: [0.0, 0.15, 0.0],
        };
        mesh.write(&layout.collider_mesh(0)).unwrap();
        let cache = Cache::open(dir.path()).unwrap();
        let g = cache
            .geometry(1, ColorBy::Auto, &Ranges::default())
            .unwrap();
        let corners: Vec<[f32; 3]> = g
            .mesh_vertices
            .chunks_exact(geometry::MESH_STRIDE)
            .filter(|v| v[9] == Shading::Collider as u32 as f32)
            .map(|v| [v[0], v[1], v[2]])
            .collect();
        // Four flat triangles; the file's vertex 1, (1, 0, 0), at (1, 2, 2).
        assert_eq!(corners.len(), 12);
        assert_eq!(corners[0], [1.0, 2.0, 3.0]);
        let moved = corners[2];
        assert!(
            (0..3).all(|k| (moved[k] - [1.0, 2.0, 2.0][k]).abs() < 1e-6),
            "{moved:?}"
        );
    }

    #[test]
    fn surfaces_read_back_as_written() {
        let mesh = SurfaceMesh {
            name: "block".into(),
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            normals: vec![[0.0, 0.0, 1.0]; 4],
            damage: vec![0.0, 0.25, 0.5, 1.0],
            surface_indices: vec![0, 2, 1, 0, 1, 3],
            crack_indices: vec![1, 2, 3],
            ..SurfaceMesh::default()
        };
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("0001.glb");
        let options = crate::gltf::Glb::default();
        std::fs::write(&file, crate::gltf::crack_glb(&mesh, &options).unwrap()).unwrap();
        assert_eq!(read_surfaces(&file).unwrap(), vec![mesh.clone()]);
        let plain = SurfaceMesh {
            damage: Vec::new(),
            crack_indices: Vec::new(),
            ..mesh
        };
        std::fs::write(
            &file,
            crate::gltf::to_glb(&[plain.clone(), plain.clone()]).unwrap(),
        )
        .unwrap();
        assert_eq!(read_surfaces(&file).unwrap(), vec![plain.clone(), plain]);
    }
}
