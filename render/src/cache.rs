//! Reading an output directory for previews: which frames exist, the colliders and the
//! ground from the resolved `scene.toml`, mesh colliders' geometry from
//! `colliders/mesh_N.ply`, per-frame collider positions and rotations from
//! `manifest.json`, particles from `particles/NNNN.ply`, surfaces from
//! `surface/NNNN.glb` (embedded or VDB meshes, with crack faces and `_DAMAGE`), turned
//! into [`FrameGeometry`].
//!
//! Framing a whole shot (the camera's subject and bounds, the value ranges of the
//! colours) is [`Cache::sequence_framing`], in the `framing` submodule.

mod framing;

#[cfg(test)]
pub(crate) use framing::pieces;
pub use framing::{
    FRAMING_TAIL, FramePoints, Framing, GRAIN_PARTICLES, SAMPLES_PER_FRAME, percentile_bounds,
};

use std::path::Path;

use perifrac_cache::CacheError;
use perifrac_cache::Layout;
use perifrac_cache::collider::{MovingCollider, mesh_colliders};
use perifrac_cache::manifest::Manifest;
use perifrac_cache::ply::{FloatPly, ParticleFrame};
use perifrac_cache::scene::{ColliderSpec, Scene};

use crate::RenderError;
use crate::camera::AZIMUTH;
use crate::geometry::{self, FrameGeometry};
use crate::gltf::read_glb;
use crate::paint;

/// What the particles (and, for damage, the meshes) are coloured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorBy {
    /// Each body in its material's colour (the scene's `color`, or the default
    /// palette), on meshes and particles alike; crack faces apart (ochre).
    #[default]
    Material,
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
pub(crate) const NO_RANGE: [f32; 2] = [f32::INFINITY, f32::NEG_INFINITY];

/// `range` widened by the finite values of `values`.
pub(crate) fn widen(range: [f32; 2], values: &[f32]) -> [f32; 2] {
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
    /// Frames a second of playback (`[output] playback_fps`).
    playback_fps: f64,
    /// Particle radius of each body (half its resolution λ), for caches without the
    /// volume column.
    radii: Vec<f32>,
    /// The camera's azimuth when none is asked for (radians).
    azimuth: f32,
    /// Display colour of each body (linear).
    colors: Vec<[f32; 3]>,
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
            colors: scene
                .body_colors()
                .into_iter()
                .map(geometry::linear)
                .collect(),
            azimuth: view_azimuth(&scene),
            colliders: scene.colliders,
            meshes,
            ground,
            fps: scene.scene.fps,
            playback_fps: scene.output.playback_fps,
        })
    }

    /// Whether frame `frame` is drawn from its surface mesh (rather than particles).
    pub fn uses_surface(&self, frame: usize, color_by: ColorBy) -> bool {
        matches!(
            color_by,
            ColorBy::Material | ColorBy::Damage | ColorBy::Quantity
        ) && self.layout.surface(frame).is_file()
    }

    /// The camera's azimuth when none is asked for (radians): [`crate::camera::AZIMUTH`]
    /// off the path of the projectile, on the side it comes from, so its impact face
    /// and the projectile itself are in view; [`crate::camera::AZIMUTH`] when nothing
    /// moves horizontally.
    pub fn view_azimuth(&self) -> f32 {
        self.azimuth
    }

    /// The simulation time of `frame` (s): the manifest's, else (frame − 1)/fps.
    pub fn frame_time(&self, frame: usize) -> f64 {
        self.manifest
            .as_ref()
            .and_then(|m| m.frame_times.get(frame.wrapping_sub(1)).copied())
            .unwrap_or(frame.saturating_sub(1) as f64 / self.fps)
    }

    /// Frames a second of playback (`[output] playback_fps`), the movies' rate.
    pub fn playback_fps(&self) -> f64 {
        self.playback_fps
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
        let time = self.frame_time(frame);
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

    /// The display colour (linear) of body `material` (the PLY's column), the first
    /// body's for a value that names none.
    fn body_color(&self, material: f32) -> [f32; 3] {
        let first = self
            .colors
            .first()
            .copied()
            .unwrap_or_else(geometry::surface_color);
        if material.is_finite() && material >= 0.0 {
            self.colors.get(material as usize).copied().unwrap_or(first)
        } else {
            first
        }
    }

    /// Paints the original surface of the meshes in `g` by material: one colour when
    /// every body has the same, else each vertex in the colour of the body of the
    /// nearest particle of `frame` (read from its PLY, when there is one).
    fn paint_by_material(&self, frame: usize, g: &mut FrameGeometry) -> Result<(), RenderError> {
        let alike = self.colors.windows(2).all(|w| w[0] == w[1]);
        let path = self.layout.particles(frame);
        if alike || !path.is_file() {
            paint::paint_surfaces(&mut g.mesh_vertices, &self.colors, None);
            return Ok(());
        }
        let p = ParticleFrame::read(&path)?;
        let spacing = 2.0 * self.radii.iter().copied().fold(0.0, f32::max);
        let nearest = paint::NearestBody::new(&p.position, &p.material, spacing);
        paint::paint_surfaces(&mut g.mesh_vertices, &self.colors, Some(&nearest));
        Ok(())
    }

    /// The vdb method's debris of `frame` (`surface/NNNN_debris.ply`: the fragments
    /// too small to surface, loose particles), as particles of their body's size and
    /// colour (the file's `radius` is the level set's sphere, about twice a
    /// particle's). Without them a piece that comes apart into particles vanishes from
    /// the previews.
    fn push_debris(&self, frame: usize, g: &mut FrameGeometry) -> Result<(), RenderError> {
        let path = self.layout.debris(frame);
        if !path.is_file() {
            return Ok(());
        }
        let bytes = std::fs::read(&path).map_err(|e| CacheError::io(&path, e))?;
        let ply = FloatPly::from_bytes(&bytes).map_err(|m| CacheError::format(&path, m))?;
        let column = |name: &str| {
            ply.column(name).ok_or_else(|| {
                CacheError::format(
                    &path,
                    format!(
                        "the debris points have no '{name}' property; run perifrac surface again"
                    ),
                )
            })
        };
        let [x, y, z, material] = ["x", "y", "z", "material"].map(column);
        let (x, y, z, material) = (x?, y?, z?, material?);
        g.points.reserve(ply.count * geometry::POINT_STRIDE);
        for i in 0..ply.count {
            let (radius, color) = (self.radius(material[i]), self.body_color(material[i]));
            g.push_point([x[i], y[i], z[i]], radius, color);
        }
        Ok(())
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
            if color_by == ColorBy::Material {
                self.paint_by_material(frame, &mut g)?;
            }
            self.push_debris(frame, &mut g)?;
        } else if self.layout.particles(frame).is_file() {
            let path = self.layout.particles(frame);
            let p = ParticleFrame::read(&path)?;
            let colors: Vec<[f32; 3]> = match color_by {
                ColorBy::Material => p.material.iter().map(|&m| self.body_color(m)).collect(),
                ColorBy::Damage => p
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
            // Each particle at its own size (half the cube root of its volume); half λ
            // for caches written before the volume column.
            let sizes = p.sizes(|i| 2.0 * self.radius(p.material[i]));
            g.points.reserve(p.len() * geometry::POINT_STRIDE);
            for ((&position, size), color) in p.position.iter().zip(sizes).zip(colors) {
                g.push_point(position, 0.5 * size, color);
            }
        }
        self.push_colliders(frame, &mut g);
        Ok(g)
    }
}

/// See [`Cache::view_azimuth`]: the projectile is the sphere or box collider or the body
/// with the fastest horizontal start velocity.
fn view_azimuth(scene: &Scene) -> f32 {
    let colliders = scene.colliders.iter().filter_map(|c| match c {
        ColliderSpec::Sphere { velocity, .. } | ColliderSpec::Box { velocity, .. } => {
            Some(*velocity)
        }
        ColliderSpec::Ground { .. } | ColliderSpec::Mesh { .. } => None,
    });
    let bodies = scene.bodies.iter().map(|b| b.velocity);
    let fastest = colliders
        .chain(bodies)
        .map(|v| [v[0], v[2]])
        .filter(|h| h.iter().all(|x| x.is_finite()))
        .fold(None, |best: Option<[f64; 2]>, h| {
            let speed = h[0].hypot(h[1]);
            match best {
                Some(b) if b[0].hypot(b[1]) >= speed => Some(b),
                _ if speed > 0.0 => Some(h),
                _ => best,
            }
        });
    match fastest {
        // The eye on the side the projectile comes from: towards −v.
        Some([vx, vz]) => (-vx).atan2(-vz) as f32 + AZIMUTH,
        None => AZIMUTH,
    }
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

#[cfg(test)]
#[path = "cache_tests.rs"]
mod tests;
