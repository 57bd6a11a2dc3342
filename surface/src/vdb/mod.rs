//! The `vdb` surface method: one frame of particles → narrow-band level sets →
//! `vdb/NNNN.vdb` (grids `surface` and `v`) and triangle meshes, through the system
//! OpenVDB (`openvdb-sys`).
//!
//! For each fragment (connected component of intact bonds, from the cache) with at
//! least `min_fragment_particles` particles:
//! 1. `tools::ParticlesToLevelSet` rasterizes a sphere per particle, of radius
//!    `radius_scale` × the particle's volume-equivalent radius (0.62 spacings), at a
//!    voxel size of `voxel_size` spacings of the finest body in the frame, and
//!    `tools::LevelSetTracker` renormalizes the union and trims it to a narrow band
//!    of signed distance;
//! 2. `tools::LevelSetFilter` smooths it (`filter`, `iterations`) and offsets it
//!    (`offset`);
//! 3. `tools::volumeToMesh` meshes it (`adaptivity`); quads become triangles here.
//!
//! The fragments' level sets are unioned (`tools::csgUnion`) into the frame's
//! `surface` grid; the velocity grid `v` holds, over the band the particles were
//! rasterized into, the velocity of the particle nearest each voxel. Each fragment is
//! surfaced on its own, so cracks stay open; smaller fragments are written as debris
//! points. A body whose particles form a single layer at rest (the first frame) is
//! refused.

mod grid;
mod stage;

use std::path::Path;
use std::time::Instant;

use perifrac_cache::manifest::{BodyInfo, Manifest};
use perifrac_cache::mesh::SurfaceMesh;
use perifrac_cache::ply::ParticleFrame;
use perifrac_cache::scene::{VdbFilter, VdbSpec};
use perifrac_cache::{Layout, temporary_file};

pub use grid::{Frame, LevelSet, RasterCount, initialize};
pub use stage::stage;

use crate::debris::Debris;
use crate::error::{Result, SurfaceError};
use crate::mesh::TriangleMesh;
use crate::particles::{self, SPHERE_RADIUS_PER_SPACING};

/// Half width of the narrow band, in voxels (OpenVDB's `LEVEL_SET_HALF_WIDTH`).
pub const HALF_WIDTH: f64 = 3.0;

/// The surface of one fragment.
#[derive(Debug, Clone, PartialEq)]
pub struct FragmentMesh {
    /// Fragment id (from the cache); 0 with `per_fragment = false`.
    pub fragment: u32,
    /// Particles it was made from.
    pub particles: usize,
    /// Its triangles.
    pub mesh: TriangleMesh,
    /// Each vertex's damage: its nearest particle's ([`particles::nearest_damage`]).
    pub damage: Vec<f32>,
}

impl FragmentMesh {
    /// The mesh as the cache's surface type, named `fragment N`, with area-weighted
    /// vertex normals.
    pub fn surface_mesh(&self) -> SurfaceMesh {
        SurfaceMesh {
            name: format!("fragment {}", self.fragment),
            positions: self.mesh.positions.clone(),
            normals: self.mesh.vertex_normals(),
            damage: self.damage.clone(),
            surface_indices: self.mesh.indices.clone(),
            ..SurfaceMesh::default()
        }
    }
}

/// Wall-clock seconds spent in each step of a frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepSeconds {
    /// Reading the particles, grouping, checks.
    pub prepare: f64,
    /// Rasterizing spheres and renormalizing the narrow band.
    pub level_set: f64,
    /// Smoothing and offsetting.
    pub filter: f64,
    /// Meshing.
    pub mesh: f64,
    /// Unioning into the frame's grids and writing `.vdb` and debris files.
    pub write: f64,
}

/// What a frame's surfacing did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameStats {
    /// Particles in the frame.
    pub particles: usize,
    /// Fragments surfaced (level sets made).
    pub fragments: usize,
    /// Fragments written as debris points.
    pub debris_fragments: usize,
    /// Particles written as debris points.
    pub debris_particles: usize,
    /// Particles the rasterizer dropped (radius under 1.5 voxels or huge).
    pub dropped_particles: usize,
    /// Voxel edge (m).
    pub voxel_size: f64,
    /// Active voxels of the frame's `surface` grid.
    pub active_voxels: usize,
    /// Triangles over all meshes.
    pub triangles: usize,
    /// Time in each step.
    pub seconds: StepSeconds,
}

/// A surfaced frame: one mesh per surfaced fragment, and what it took.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameSurface {
    /// Frame number (from 1).
    pub frame: usize,
    /// Meshes, in increasing fragment id.
    pub meshes: Vec<FragmentMesh>,
    /// Counts and timings.
    pub stats: FrameStats,
}

/// Surfaces frame `frame` of the cache at `layout`: reads `particles/NNNN.ply`,
/// writes `vdb/NNNN.vdb` and `surface/NNNN_debris.ply`, and returns the meshes.
pub fn surface_frame(
    layout: &Layout,
    manifest: &Manifest,
    frame: usize,
    spec: &VdbSpec,
) -> Result<FrameSurface> {
    let start = Instant::now();
    let particles = ParticleFrame::read(&layout.particles(frame))?;
    let read = start.elapsed().as_secs_f64();
    let vdb = layout.vdb(frame);
    let debris = layout.debris(frame);
    for path in [&vdb, &debris] {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| SurfaceError::io(dir, e))?;
        }
    }
    let mut surface = surface_particles(frame, &particles, &manifest.bodies, spec, &vdb, &debris)?;
    surface.stats.seconds.prepare += read;
    Ok(surface)
}

/// Surfaces one frame of particles (bodies as in the manifest) and writes the .vdb
/// file to `vdb_path` and the debris points to `debris_path`.
pub fn surface_particles(
    frame: usize,
    particles: &ParticleFrame,
    bodies: &[BodyInfo],
    spec: &VdbSpec,
    vdb_path: &Path,
    debris_path: &Path,
) -> Result<FrameSurface> {
    let mut seconds = StepSeconds::default();
    let t = Instant::now();
    particles::check_finite(frame, particles)?;
    let body = particles::body_indices(frame, particles, bodies)?;
    // At rest only: a body torn to dust or shreds later is surfaced as what it is,
    // not refused after its whole simulation has run.
    if frame <= 1 {
        particles::check_volumetric(frame, particles, &body, bodies)?;
    }
    let spacing: Vec<f64> = bodies.iter().map(particles::body_spacing).collect();
    let finest = body
        .iter()
        .map(|&b| spacing[b as usize])
        .fold(f64::INFINITY, f64::min);
    if !(finest.is_finite() && finest > 0.0) {
        return Err(SurfaceError::Frame {
            frame,
            message: "the manifest gives no body a positive particle spacing (mean_edge or particle_spacing); rerun the scene with this perifrac".into(),
        });
    }
    let voxel_size = spec.voxel_size * finest;
    let radius: Vec<f32> = body
        .iter()
        .map(|&b| (spec.radius_scale * SPHERE_RADIUS_PER_SPACING * spacing[b as usize]) as f32)
        .collect();
    let groups = if spec.per_fragment {
        particles::fragments(frame, particles)?
    } else {
        vec![(0, (0..particles.len() as u32).collect())]
    };
    seconds.prepare = t.elapsed().as_secs_f64();

    let mut stats = FrameStats {
        particles: particles.len(),
        voxel_size,
        ..FrameStats::default()
    };
    let mut debris = Debris::default();
    let mut grids = Frame::new(frame, voxel_size, HALF_WIDTH)?;
    let mut meshes = Vec::new();
    let (mut position, mut velocity, mut radii) = (Vec::new(), Vec::new(), Vec::new());
    for (fragment, members) in groups {
        if members.len() < spec.min_fragment_particles {
            stats.debris_fragments += 1;
            stats.debris_particles += members.len();
            for &i in &members {
                let i = i as usize;
                debris.position.push(particles.position[i]);
                debris.velocity.push(particles.velocity[i]);
                debris.radius.push(radius[i]);
                debris.fragment.push(particles.fragment[i]);
                debris.material.push(particles.material[i]);
            }
            continue;
        }
        position.clear();
        velocity.clear();
        radii.clear();
        for &i in &members {
            position.push(particles.position[i as usize]);
            velocity.push(particles.velocity[i as usize]);
            radii.push(radius[i as usize]);
        }
        let t = Instant::now();
        let (mut level_set, dropped) =
            LevelSet::from_spheres(frame, &position, &radii, voxel_size, HALF_WIDTH)?;
        stats.dropped_particles += dropped.too_small + dropped.too_large;
        seconds.level_set += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let kind = match spec.filter {
            VdbFilter::None => None,
            VdbFilter::MeanCurvature => Some(openvdb_sys::FILTER_MEAN_CURVATURE),
            VdbFilter::Gaussian => Some(openvdb_sys::FILTER_GAUSSIAN),
            VdbFilter::Laplacian => Some(openvdb_sys::FILTER_LAPLACIAN),
        };
        if let Some(kind) = kind {
            level_set.filter(kind, spec.iterations)?;
        }
        level_set.offset(spec.offset * finest)?;
        seconds.filter += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let mesh = level_set.mesh(spec.adaptivity)?;
        seconds.mesh += t.elapsed().as_secs_f64();
        let t = Instant::now();
        grids.add(level_set, &velocity)?;
        seconds.write += t.elapsed().as_secs_f64();
        if !mesh.is_empty() {
            stats.triangles += mesh.triangle_count();
            let reach = 2.0 * f64::from(radii.iter().copied().fold(0.0f32, f32::max));
            let damage = particles::nearest_damage(
                &mesh.positions,
                &particles.position,
                &particles.damage,
                &members,
                reach,
            );
            meshes.push(FragmentMesh {
                fragment,
                particles: members.len(),
                mesh,
                damage,
            });
        }
        stats.fragments += 1;
    }
    let t = Instant::now();
    stats.active_voxels = grids.active_voxels();
    let tmp = temporary_file(vdb_path);
    let written = grids.write(&tmp.path).and_then(|()| {
        std::fs::rename(&tmp.path, vdb_path).map_err(|e| SurfaceError::io(vdb_path, e))
    });
    if let Err(e) = written {
        // A partial file would keep a full disk full.
        let _ = std::fs::remove_file(&tmp.path);
        return Err(e);
    }
    debris.write(debris_path, frame)?;
    seconds.write += t.elapsed().as_secs_f64();
    stats.seconds = seconds;
    Ok(FrameSurface {
        frame,
        meshes,
        stats,
    })
}
