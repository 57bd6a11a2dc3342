//! What a scene will cost in memory, estimated before any bond is built. Whether to
//! refuse a scene is the caller's policy (the CLI compares it with what the machine
//! has); the estimate is the simulator's.

use rayon::prelude::*;

use crate::error::{Result, SimError};
use crate::family;
use crate::geometry::discretize::Discretization;
use crate::geometry::mesh::{MeshSdf, TriMesh};
use crate::geometry::sdf::Sdf;
use crate::geometry::shape::{placement, to_sdf};
use crate::geometry::stuffing::lattice_size;
use crate::scene::{ModelKind, Scene, ShapeSpec};

/// Bytes per particle of state and scratch (positions, velocities, reference data,
/// θ, forces, accelerations, masses, flags); an MPM particle's are
/// [`MPM_PEAK_BYTES_PER_PARTICLE`].
pub const BYTES_PER_PARTICLE: usize = 8 * 3 * 5 + 8 * 5 + 4 * 3 + 2;

/// Bytes a run holds whatever its scene: the program and its libraries, the worker
/// threads' stacks, the allocator's arenas. Measured: 39 MiB, the intercept of an
/// MPM block's peak resident memory less its grid against its particles
/// (docs/memory.md).
pub const PROCESS_BYTES: f64 = 39.0 * (1u64 << 20) as f64;

/// Bytes an MPM particle takes at the run's peak besides the grid, `perifrac
/// check`'s figure: its state (x, v and X, m and V, its body, F and C, ε^p, the stress
/// stage's A_p, the grid's sort entries: 332), the step's other buffers and a frame's
/// columns. Measured: the slope of an elastic block's peak resident memory less its
/// grid against its particles, 262,144 to 2.4 million (docs/memory.md).
pub const MPM_PEAK_BYTES_PER_PARTICLE: usize = 489;

/// The grid's bytes a particle of a body that fills its blocks (a block of 10⁶
/// particles, [`crate::mpm::grid::SparseGrid::estimate_bytes`]): the estimate before seeding.
pub const MPM_COMPACT_GRID_BYTES_PER_PARTICLE: usize = 37;

/// What a scene will cost in memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryEstimate {
    /// Particles.
    pub particles: usize,
    /// Directed bonds expected from each body's particle density and horizon.
    pub bonds: f64,
    /// Bytes a bond takes (more with plasticity).
    pub bytes_per_bond: usize,
    /// Points of the mesher's lattices (0 once the scene is meshed).
    pub lattice_points: f64,
    /// Bytes at the run's peak (set-up, or the mesher's lattice if larger), the
    /// process's own [`PROCESS_BYTES`] included.
    pub bytes: f64,
    /// Of them, the MPM grid's: as for a body that fills its grid blocks until the
    /// particles are seeded ([`MemoryEstimate::with_grid`]).
    pub grid: f64,
    /// Of them, what the ranks of a distributed run split among themselves: the
    /// peridynamic bonds' constants and their set-up ([`SPLIT_PEAK_BYTES_PER_BOND`]).
    pub split: f64,
    /// The mesher's peak, which every rank reaches alone.
    pub mesh: f64,
}

/// Samples a grid of this many points a side over a body's bounds to measure the
/// fraction of its bounding box that is inside (the shape's volume) before meshing.
const VOLUME_SAMPLES: usize = 40;

/// Bytes the mesher holds a lattice point at its peak: the SDF value (f64), the
/// point's vertex (u32), the warped flag and the cut table around the surface.
pub const BYTES_PER_LATTICE_POINT: f64 = 8.0 + 4.0 + 1.0;

/// Estimates, before any body is meshed or sampled, what the run will need at its
/// peak: each body's particles from its shape's volume (an SDF sampled on a
/// coarse grid, the mesh file read for mesh bodies) and the lattice spacing (an
/// interior BCC cube of side h holds 12 tets), its lattice points, its bonds per
/// particle from the horizon. Cheap (no lattice, no particles), so a scene too
/// large for the machine is refused before the mesher allocates.
pub fn estimate_before_meshing(scene: &Scene) -> Result<MemoryEstimate> {
    let mut particles = 0.0;
    let mut bonds = 0.0;
    let mut lattice = 0.0;
    let smallest = scene
        .bodies
        .iter()
        .map(|b| b.resolution)
        .fold(f64::INFINITY, f64::min);
    for b in &scene.bodies {
        let error = |message: String| SimError::Mesh {
            body: b.name.clone(),
            message,
        };
        if b.model == ModelKind::Membrane {
            let n = crate::membrane::sheet::particle_count(b, &scene.base_dir).map_err(error)?;
            let h = b.resolution;
            let cutoff = b.membrane.as_ref().map_or(1.5, |m| m.cutoff) * h;
            let density = 1.0 / (h * h * 3f64.sqrt() / 2.0);
            particles += n;
            bonds += n * (std::f64::consts::PI * cutoff * cutoff * density - 1.0).max(0.0);
            continue;
        }
        let sdf: Box<dyn Sdf> = match (&b.shape, placement(&b.shape)) {
            (ShapeSpec::Mesh { path, .. }, Some(placement)) => {
                let surface = TriMesh::load(&scene.base_dir.join(path), &placement)
                    .map_err(|e| error(e.to_string()))?;
                Box::new(MeshSdf::new(&surface))
            }
            (shape, _) => to_sdf(shape, &scene.base_dir).map_err(error)?,
        };
        let (h, points) = lattice_size(sdf.as_ref(), b.resolution);
        lattice += points;
        let volume = inside_volume(sdf.as_ref());
        if b.model == ModelKind::Mpm {
            // Eight particles a cell of the grid spacing (the smallest resolution).
            let seeded = 8.0 * volume / smallest.powi(3);
            particles += seeded;
            let material = scene.materials.get(&b.material);
            if material.is_some_and(|m| m.mpm.as_ref().is_some_and(|m| m.bonds.is_some())) {
                // The integral-based MPM's families, within δ = 1.5 Δx of every
                // particle from the start (SPB-MPM's come as particles join).
                bonds += seeded * crate::mpm::patches::interior_family();
            }
            continue;
        }
        let tets = TETS_PER_CUBE * volume / h.powi(3);
        particles += tets;
        if !b.model.is_fem() && tets > 0.0 {
            let family = crate::pd::family_volume(b.delta()) / (volume / tets);
            bonds += tets * (family - 1.0).max(0.0);
        }
    }
    Ok(MemoryEstimate::new(scene, particles, bonds, lattice))
}

/// Tets an interior BCC lattice cube holds, plus what the boundary stencils add
/// (measured over the shapes of `estimates_before_meshing_match_the_mesh`).
const TETS_PER_CUBE: f64 = 12.0;

/// The volume inside `sdf`: its bounding box times the fraction of a
/// [`VOLUME_SAMPLES`]³ grid of cell centres that is inside.
fn inside_volume(sdf: &dyn Sdf) -> f64 {
    let (min, max) = sdf.bounds();
    let n = VOLUME_SAMPLES;
    let step = [0, 1, 2].map(|k| (max[k] - min[k]) / n as f64);
    let inside: usize = (0..n * n)
        .into_par_iter()
        .map(|ij| {
            let (i, j) = (ij / n, ij % n);
            (0..n)
                .filter(|&k| {
                    let p = [
                        min[0] + (i as f64 + 0.5) * step[0],
                        min[1] + (j as f64 + 0.5) * step[1],
                        min[2] + (k as f64 + 0.5) * step[2],
                    ];
                    sdf.distance(p) < 0.0
                })
                .count()
        })
        .sum();
    let box_volume = step.iter().product::<f64>() * (n * n * n) as f64;
    box_volume * inside as f64 / (n * n * n) as f64
}

/// Estimates the memory of a discretized scene from its meshes (the particles and
/// volumes known): a particle's family holds about V_H / (mean particle volume) − 1
/// bonds (fewer near surfaces).
pub fn estimate_memory(scene: &Scene, disc: &Discretization) -> MemoryEstimate {
    let bonds: f64 = scene
        .bodies
        .iter()
        .enumerate()
        .filter(|(_, spec)| !spec.model.is_fem() && spec.model != ModelKind::Mpm)
        .map(|(b, spec)| {
            let mesh = &disc.meshes[b];
            let count = mesh.tets.len() as f64;
            if count == 0.0 {
                return 0.0;
            }
            let mean_volume = mesh.total_volume() / count;
            let family = crate::pd::family_volume(spec.delta()) / mean_volume;
            count * (family - 1.0).max(0.0)
        })
        .sum();
    MemoryEstimate::new(scene, disc.position.len() as f64, bonds, 0.0)
}

/// Bytes a directed bond takes at the peak of a peridynamic set-up on every rank of a
/// distributed run, whatever their number: its neighbour word (with the broken
/// bit), and the families as found before they are joined into rows. Calibrated with
/// [`SPLIT_PEAK_BYTES_PER_BOND`] against the peak resident memory of one process and
/// of each of 2 and 4 ranks (docs/memory.md).
pub const WHOLE_PEAK_BYTES_PER_BOND: usize = 7;

/// Bytes a directed bond takes at the peak of set-up that the ranks split among
/// themselves ([`crate::pd::Coefficients`]: each rank builds and keeps the constants of
/// its own rows): the rest length and the four coefficients (24 kept), and the
/// correction weights while they are folded in.
pub const SPLIT_PEAK_BYTES_PER_BOND: usize = 30;

/// Bytes a bond takes at the peak of set-up in one process on top of what it keeps
/// for the run ([`family::BYTES_PER_BOND`]).
pub const SETUP_BYTES_PER_BOND: usize =
    WHOLE_PEAK_BYTES_PER_BOND + SPLIT_PEAK_BYTES_PER_BOND - family::BYTES_PER_BOND;

/// Bytes each rank of a distributed run holds besides its share of the model:
/// OpenMPI's shared-memory transport and buffers. Measured: 10–17 MiB over the
/// estimate without it on 2 and 4 ranks (docs/memory.md).
pub const RANK_BYTES: f64 = 15.0 * (1u64 << 20) as f64;

impl MemoryEstimate {
    /// The estimate of `particles` and `bonds` (directed) of `scene`'s models, with
    /// `lattice` mesher points (0 once meshed).
    pub fn new(scene: &Scene, particles: f64, bonds: f64, lattice: f64) -> MemoryEstimate {
        let plastic = scene.materials.values().any(|m| {
            (m.yield_psi0.is_some() || m.yield_stretch.is_some()) && m.plastic_limit > 0.0
        });
        // e^p and the reverse index of a yielding material; e^c of a crushing one.
        let crushing = scene
            .materials
            .values()
            .any(|m| m.critical_compression.is_some());
        // Every body of an MPM scene is MPM: its particles' and Ω^PD's bonds' bytes
        // instead (what building the bonds holds for a moment is not counted).
        let mpm = scene.bodies.iter().any(|b| b.model == ModelKind::Mpm);
        let (per_particle, bytes_per_bond, peak_per_bond, split_per_bond) = if mpm {
            // The plastic extensions a bond keeps.
            let flows = scene
                .materials
                .values()
                .filter_map(|m| m.mpm.as_ref().and_then(|m| m.bonds.as_ref()))
                .map(|b| crate::mpm::patches::flows_per_bond(b.viscosity, b.yield_stress))
                .max()
                .unwrap_or(0);
            let extension = flows * crate::mpm::patches::PLASTIC_BYTES_PER_BOND;
            let bytes = crate::mpm::patches::BYTES_PER_BOND + extension;
            (
                MPM_PEAK_BYTES_PER_PARTICLE + MPM_COMPACT_GRID_BYTES_PER_PARTICLE,
                bytes,
                bytes,
                0,
            )
        } else {
            // e^p on every rank, the reverse index with the rank's rows; e^c.
            let (whole, split) = (
                if plastic { 8 } else { 0 } + if crushing { 4 } else { 0 },
                if plastic { 4 } else { 0 },
            );
            // Only peridynamics splits its bonds over ranks; membranes (and the FEM,
            // which has none) run whole on every rank.
            let peridynamic = scene
                .bodies
                .iter()
                .all(|b| b.model == ModelKind::Peridynamics);
            (
                BYTES_PER_PARTICLE,
                family::BYTES_PER_BOND + whole + split,
                WHOLE_PEAK_BYTES_PER_BOND + SPLIT_PEAK_BYTES_PER_BOND + whole + split,
                if peridynamic {
                    SPLIT_PEAK_BYTES_PER_BOND + split
                } else {
                    0
                },
            )
        };
        let (per_particle, peak_per_bond) = (per_particle as f64, peak_per_bond as f64);
        let run = PROCESS_BYTES + bonds * peak_per_bond + particles * per_particle;
        let mesh = PROCESS_BYTES + lattice * BYTES_PER_LATTICE_POINT + particles * per_particle;
        MemoryEstimate {
            particles: particles.round() as usize,
            bonds,
            bytes_per_bond,
            lattice_points: lattice,
            bytes: run.max(mesh),
            split: if run > mesh {
                bonds * split_per_bond as f64
            } else {
                0.0
            },
            mesh,
            grid: if mpm {
                particles * MPM_COMPACT_GRID_BYTES_PER_PARTICLE as f64
            } else {
                0.0
            },
        }
    }

    /// The estimate with the MPM grid's `bytes` counted from the seeded particles
    /// ([`crate::mpm::grid::SparseGrid::estimate_bytes`]) in place of a body that
    /// fills its blocks: thin walls, nets and sheets hold a few particles a block.
    pub fn with_grid(mut self, bytes: f64) -> MemoryEstimate {
        self.bytes += bytes - self.grid;
        self.grid = bytes;
        self
    }

    /// The peak of each of `ranks` ranks of `mpirun -np N perifrac run` (docs/ranks.md):
    /// every rank holds the particles and the bonds' neighbours, and builds and keeps
    /// the peridynamic bonds' constants of its own rows alone; MPM, membranes and the
    /// FEM run whole on every rank.
    pub fn per_rank(&self, ranks: usize) -> f64 {
        if ranks <= 1 {
            return self.bytes;
        }
        let run = self.bytes - self.split * (1.0 - 1.0 / ranks as f64);
        run.max(self.mesh) + RANK_BYTES
    }
}

/// A ceiling on the memory a run may use and where it comes from: the machine's
/// available memory, the process's address-space limit, its cgroup's limit (the
/// caller finds them; the CLI takes the lowest).
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryLimit {
    /// Bytes.
    pub bytes: u64,
    /// What the bytes are, completing "… but N GiB …" (`are available (MemAvailable
    /// in /proc/meminfo)`, `is this process's limit (ulimit -v)`).
    pub source: String,
}

impl MemoryEstimate {
    /// Refuses a run that needs more than `limit` (the caller's policy: the CLI passes
    /// the lowest of the memory the machine has available and the process's limits).
    pub fn refuse_above(&self, limit: &MemoryLimit) -> Result<()> {
        if self.bytes > limit.bytes as f64 {
            let gib = |b: f64| b / (1u64 << 30) as f64;
            return Err(SimError::Refused(format!(
                "the run needs about {:.1} GiB ({} particles, {:.3e} bonds of {} bytes) but {:.1} GiB \
                 {}: use a coarser resolution or a smaller horizon",
                gib(self.bytes),
                self.particles,
                self.bonds,
                self.bytes_per_bond,
                gib(limit.bytes as f64),
                limit.source
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::geometry::discretize::discretize;

    /// The estimate from the shapes alone against the meshed scene: particles and
    /// bonds within 20% and 35% for a box, a sphere, a cylinder and a CSG difference.
    #[test]
    fn estimates_before_meshing_match_the_mesh() {
        for shape in [
            r#"{ type = "box", center = [0, 0, 0], size = [0.3, 0.2, 0.05] }"#,
            r#"{ type = "sphere", center = [0, 0, 0], radius = 0.1 }"#,
            r#"{ type = "cylinder", center = [0, 0, 0], radius = 0.08, height = 0.1, axis = "y" }"#,
            r#"{ type = "difference", base = { type = "box", center = [0, 0, 0], size = [0.2, 0.2, 0.1] }, minus = { type = "sphere", center = [0, 0.1, 0], radius = 0.08 } }"#,
        ] {
            let text = format!(
                "[scene]\nduration = 0.01\nfps = 100\n\
                 [materials.m]\ndensity = 1000.0\nyoungs_modulus = 1e6\npoisson_ratio = 0.3\n\
                 [[body]]\nmaterial = \"m\"\nresolution = 0.012\nshape = {shape}\n"
            );
            let scene = Scene::parse(&text, Path::new("m.toml"), Path::new(".")).expect("scene");
            let before = estimate_before_meshing(&scene).expect("estimate");
            let after = estimate_memory(&scene, &discretize(&scene).expect("meshes"));
            let particles = before.particles as f64 / after.particles as f64;
            let bonds = before.bonds / after.bonds;
            // Particles within 20%; bonds within 35%: the estimate counts interior
            // families, and a body four particles thick (the box) has more bonds a
            // particle than that near its faces' snapped vertices. The run checks again
            // from the meshes, with exact counts, before any bond is built.
            assert!(
                (particles - 1.0).abs() < 0.2 && (bonds - 1.0).abs() < 0.35,
                "{shape}: particles {} estimated, {} meshed; bonds {:.3e} / {:.3e}",
                before.particles,
                after.particles,
                before.bonds,
                after.bonds
            );
            assert!(before.lattice_points > after.particles as f64 / 12.0);
        }
    }
}
