//! `[output]`: which files a run writes, and how its surfaces are made.

use serde::{Deserialize, Serialize};

use super::default_true;

/// `[output]`: which files the run writes.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Write `particles/NNNN.ply` each frame. Default true.
    #[serde(default = "default_true")]
    pub particles: bool,
    /// Write a checkpoint every this many frames (0: never). Default 10.
    #[serde(default = "default_checkpoint_every")]
    pub checkpoint_every: usize,
    /// The surface stage `perifrac run` runs after simulating: `"none"`, `"vdb"`
    /// (OpenVDB level sets and meshes, see `[output.vdb]`) or `"embedded"` (the
    /// boundary of the split tet mesh, Chen §5.2, see `[output.embedded]`). Default
    /// `"none"`.
    #[serde(default)]
    pub surface: SurfaceMethod,
    /// Write the split tet mesh `tets/NNNN.vtu` each frame (Chen §5.2). Default false,
    /// or true when `surface = "embedded"` (which reads it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tets: Option<bool>,
    /// Settings of the `vdb` surface method (`[output.vdb]`).
    #[serde(default)]
    pub vdb: VdbSpec,
    /// Render `preview/NNNN.png` and `preview/contact_sheet.png` after the run (the
    /// render stage, Mesa's software OpenGL). Default true.
    #[serde(default = "default_true")]
    pub preview: bool,
    /// Settings of the `embedded` surface method (`[output.embedded]`).
    #[serde(default)]
    pub embedded: EmbeddedSpec,
    /// The playback time base of every file that carries time (`cache.usd`,
    /// `surface/animated.glb`, `tets/tets.pvd`): cache frame k is on timeline frame
    /// k, (k − 1)/`playback_fps` seconds after frame 1 (`animated.glb` keys it at
    /// k/`playback_fps` s, as Blender counts glTF time). The simulation time of each
    /// frame stays in `manifest.json` (`frame_times`) and in each file's metadata.
    /// Default 24.
    #[serde(default = "default_playback_fps")]
    pub playback_fps: f64,
    /// Also write damage as the glTF vertex colour `COLOR_0` of the fractured surfaces.
    /// glTF viewers multiply the base colour by it, so it tints the surface red where
    /// damaged; by default damage is only the attribute `_DAMAGE`. Default false.
    #[serde(default)]
    pub gltf_damage_colour: bool,
    /// Write `cache.usd`, the whole cache as one USD stage, after the run (and after
    /// the surface stage); `perifrac export usd OUT` writes it for any cache.
    /// Default true.
    #[serde(default = "default_true")]
    pub usd: bool,
    /// A frame rate that changes along the shot: segments `{ until, fps }` in
    /// increasing `until` (s), each written at its own `fps`, then `[scene] fps` to
    /// the end (for example 7,500 frames a second through an impact, then 24). Each
    /// cache frame is still one timeline frame at `playback_fps`, so the shot plays
    /// slow motion into real time. Default: none, `[scene] fps` throughout.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub schedule: Vec<ScheduleSpec>,
}

/// One segment of `[output] schedule`: frames at `fps` up to `until` s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScheduleSpec {
    /// Where the segment ends (s); it starts where the one before it ends (or at 0).
    pub until: f64,
    /// Frames a second within it.
    pub fps: f64,
}

fn default_playback_fps() -> f64 {
    24.0
}

impl OutputSpec {
    /// Whether the run writes `tets/NNNN.vtu` (and so maintains the embedded mesh).
    pub fn writes_tets(&self) -> bool {
        self.tets.unwrap_or(self.surface == SurfaceMethod::Embedded)
    }

    /// Whether the run writes `sheet/NNNN.ply` (membranes, the `sheet` method).
    pub fn writes_sheets(&self) -> bool {
        self.surface == SurfaceMethod::Sheet
    }
}

/// `[output.embedded]`: the crack-surface smoothing of the `embedded` method (the
/// remedy Chen et al. §7 names for zig-zag cracks; see `perifrac_surface::embedded`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmbeddedSpec {
    /// Laplacian smoothing passes over the crack vertices (each moves a vertex half
    /// way to its neighbours' mean, guarded against inverting tets, then fragment
    /// volumes are restored); 0 turns smoothing off. Default 20 (a flat cut at
    /// λ = 0.02 m is within 0.2λ of its plane after 20).
    #[serde(default = "default_smoothing_passes")]
    pub smoothing_passes: usize,
}

impl Default for EmbeddedSpec {
    fn default() -> Self {
        EmbeddedSpec {
            smoothing_passes: default_smoothing_passes(),
        }
    }
}

fn default_smoothing_passes() -> usize {
    20
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            particles: true,
            checkpoint_every: default_checkpoint_every(),
            surface: SurfaceMethod::default(),
            tets: None,
            vdb: VdbSpec::default(),
            embedded: EmbeddedSpec::default(),
            preview: true,
            playback_fps: default_playback_fps(),
            gltf_damage_colour: false,
            usd: true,
            schedule: Vec::new(),
        }
    }
}

/// Which surface stage runs after the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SurfaceMethod {
    /// No surfaces: particles only.
    #[default]
    None,
    /// OpenVDB: particles → level sets per fragment → `vdb/NNNN.vdb` and
    /// `surface/NNNN.glb`.
    Vdb,
    /// The embedded tet mesh (Chen §5.2): `tets/NNNN.vtu` → boundary with smoothed
    /// crack faces → `surface/NNNN.glb` and `surface/animated.glb`.
    Embedded,
    /// Membranes only: each sheet's own triangulated particles (`sheet/NNNN.ply`, the
    /// lattice triangles whose bonds are intact) offset to its thickness with the crack
    /// edges closed → `surface/NNNN.glb` and `surface/animated.glb`.
    Sheet,
}

/// `[output.vdb]`: how particles become level sets and meshes (the `vdb` method).
///
/// Lengths are in particle spacings: a particle of a body with mean tet edge λ has
/// volume λ³/9.1 (the BCC mesher's tets per λ³) and spacing s = (λ³/9.1)^(1/3). The
/// defaults were calibrated together: spheres 2.25 times the particles'
/// volume-equivalent radius cover the gaps between particles (the widest, around each
/// vertex of the BCC lattice, is 0.62λ = 1.29 s from the nearest particle), two
/// mean-curvature passes remove the bumps, and an offset of −0.8 s takes the surface
/// back to the body's volume (within 0.2% on spheres 5 and 8 λ in radius).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VdbSpec {
    /// Voxel edge as a fraction of the particle spacing (of the finest body in the
    /// frame). Particles whose sphere radius is under 1.5 voxels would be dropped by
    /// the rasterizer, so `radius_scale × 0.62 / voxel_size` must be at least 1.5.
    /// Default 0.8 (spheres of 1.74 voxels in radius at the default `radius_scale`).
    #[serde(default = "default_vdb_voxel_size")]
    pub voxel_size: f64,
    /// Sphere radius as a multiple of the radius of a sphere with the particle's
    /// volume (0.62 spacings). Below about 2.1 the spheres do not reach the middle of
    /// the gap around each lattice vertex (1.29 spacings from its nearest particles)
    /// and leave a bubble there wherever a voxel centre falls in it: an inner surface
    /// in the mesh. Default 2.25.
    #[serde(default = "default_vdb_radius_scale")]
    pub radius_scale: f64,
    /// Smoothing filter: `"none"`, `"mean-curvature"`, `"gaussian"` or `"laplacian"`.
    /// Default `"mean-curvature"`.
    #[serde(default)]
    pub filter: VdbFilter,
    /// Passes of the filter. Default 2.
    #[serde(default = "default_vdb_iterations")]
    pub iterations: usize,
    /// Distance the surface is moved outward after filtering, in particle spacings
    /// (negative: inward), to take the enlarged spheres back to the body's volume.
    /// Default −0.8.
    #[serde(default = "default_vdb_offset")]
    pub offset: f64,
    /// Mesh adaptivity in [0, 1] (0: uniform polygons the size of a voxel).
    /// Default 0.
    #[serde(default)]
    pub adaptivity: f64,
    /// Fragments with fewer particles are not surfaced but written as debris points
    /// (`surface/NNNN_debris.ply`). Default 8.
    #[serde(default = "default_vdb_min_fragment_particles")]
    pub min_fragment_particles: usize,
    /// One level set per fragment, so that cracks stay open. With `false` all
    /// particles go into one level set and fragments closer than a sphere's diameter
    /// merge. Default true.
    #[serde(default = "default_true")]
    pub per_fragment: bool,
}

impl Default for VdbSpec {
    fn default() -> Self {
        VdbSpec {
            voxel_size: default_vdb_voxel_size(),
            radius_scale: default_vdb_radius_scale(),
            filter: VdbFilter::default(),
            iterations: default_vdb_iterations(),
            offset: default_vdb_offset(),
            adaptivity: 0.0,
            min_fragment_particles: default_vdb_min_fragment_particles(),
            per_fragment: true,
        }
    }
}

/// The smoothing filter of the `vdb` method (OpenVDB `tools::LevelSetFilter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum VdbFilter {
    /// No smoothing.
    None,
    /// Mean-curvature flow: smooths bumps, keeps flat faces flat.
    #[default]
    MeanCurvature,
    /// Gaussian convolution (width 1 voxel).
    Gaussian,
    /// Laplacian flow.
    Laplacian,
}

fn default_checkpoint_every() -> usize {
    10
}
fn default_vdb_voxel_size() -> f64 {
    0.8
}
fn default_vdb_radius_scale() -> f64 {
    2.25
}
fn default_vdb_iterations() -> usize {
    2
}
fn default_vdb_offset() -> f64 {
    -0.8
}
fn default_vdb_min_fragment_particles() -> usize {
    8
}
