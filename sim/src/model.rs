//! The interface every solver implements, so that one integrator ([`crate::world`])
//! steps them all: peridynamics (`pd`), the FEM references (`fem`), and the models
//! that come next (membranes, MPM).
//!
//! A model owns a set of *points* (particles or mesh vertices) with positions,
//! velocities, reference positions and masses. The integrator moves them by velocity
//! Verlet with accelerations the model computes from the current state; anchors,
//! colliders, the blow-up detector, checkpoints and the cache are the world's, written
//! once over this trait. A model that advances itself (an MPM sub-step through its
//! grid) says so with [`Stepping::Own`] and gets [`Model::advance`] called instead.

use std::any::Any;
use std::fmt::Debug;
use std::sync::Arc;

use crate::cache::checkpoint::{Decoder, Encoder};
use crate::cache::sheet::SheetFrame;
use crate::cache::vtu::TetFrame;
use crate::contact::{Anchor, Collider};
use crate::error::Result;
use crate::family::Bonds;
use crate::ranks::Ranks;

/// A model's points, read-only.
#[derive(Debug, Clone, Copy)]
pub struct Points<'a> {
    /// Current positions (m).
    pub position: &'a [[f64; 3]],
    /// Velocities (m/s).
    pub velocity: &'a [[f64; 3]],
    /// Reference (rest) positions (m): anchors move points relative to these.
    pub reference: &'a [[f64; 3]],
    /// Masses (kg).
    pub mass: &'a [f64],
}

/// A model's points, with positions and velocities writable.
#[derive(Debug)]
pub struct PointsMut<'a> {
    /// Current positions (m).
    pub position: &'a mut [[f64; 3]],
    /// Velocities (m/s).
    pub velocity: &'a mut [[f64; 3]],
    /// Reference (rest) positions (m).
    pub reference: &'a [[f64; 3]],
    /// Masses (kg).
    pub mass: &'a [f64],
}

/// The columns a model gives the particle cache (`particles/NNNN.ply`), one entry a
/// particle. Particles need not be the integrator's points: the FEM writes its tet
/// barycentres.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParticleColumns {
    /// Positions.
    pub position: Vec<[f32; 3]>,
    /// Velocities.
    pub velocity: Vec<[f32; 3]>,
    /// Damage φ in [0, 1].
    pub damage: Vec<f32>,
    /// Plastic strain measure.
    pub plastic: Vec<f32>,
    /// Scene body index.
    pub body: Vec<u32>,
    /// Fragment id, numbered from 0 within the model.
    pub fragment: Vec<u32>,
    /// Further columns the model adds (name, one value a particle), written after the
    /// standard ones. Every model that has particles adds
    /// [`crate::cache::ply::VOLUME`], each particle's volume (m³), first.
    pub extra: Vec<(String, Vec<f32>)>,
}

/// What particle contact ([`crate::particle_contact`]) needs of a model's points.
#[derive(Debug, Clone, Copy)]
pub struct ContactPoints<'a> {
    /// Volume of each point (m³); its particle spacing is V^{1/3}.
    pub volume: &'a [f64],
    /// The model's bonds: two points joined by an intact bond do not touch.
    pub bonds: Option<&'a Bonds>,
    /// Whether points of one body that no intact bond joins touch (fragments, crack
    /// faces); without, only points of different bodies do.
    pub self_contact: bool,
}

/// A fragment's surface in the reference configuration ([`Model::reference_surface`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PieceSurface {
    /// Vertex positions X (m).
    pub vertices: Vec<[f64; 3]>,
    /// Triangles over `vertices`, wound outward.
    pub triangles: Vec<[u32; 3]>,
    /// How far the surface reaches beyond the points (m): the largest distance from a
    /// point to a vertex of a surface face it owns.
    pub reach: f64,
}

/// What the rigid phase ([`crate::rigid`]) reads of a model whose fragments may go
/// rigid: one entry a point.
#[derive(Debug, Clone, PartialEq)]
pub struct Fragments {
    /// The fragment of each point: connected components of intact bonds, numbered by
    /// their smallest point in increasing order.
    pub fragment: Vec<u32>,
    /// How near each point's bonds are to breaking: the largest, over its intact
    /// bonds, of what would break the bond in units of its threshold (1 breaks); −1
    /// for a point of a body that cannot break (its fragments stay in the model).
    pub breaking: Vec<f64>,
    /// Whether each point has lost a bond: only a fragment that broke off (one of its
    /// points damaged) or a small free piece goes rigid, so an intact body at rest
    /// waits for what breaks it.
    pub damaged: Vec<bool>,
    /// The P-wave speed c_p of each body's material (indexed as
    /// [`Model::point_bodies`]): how fast a piece of it rings.
    pub wave_speed: Vec<f64>,
    /// The closing speed of a hit whose stress wave strains each body's material to
    /// its critical stretch, s_c c_p (∞ for a material that does not break in
    /// tension): what a rigid piece's hit is measured against before it goes back to
    /// its model (docs/rigid.md, "Going back").
    pub hit_speed: Vec<f64>,
}

/// How a model's points are advanced in time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stepping {
    /// The world's velocity Verlet with [`Model::accelerations`].
    Verlet,
    /// The model's own [`Model::advance`] (for example an MPM grid sub-step).
    Own,
}

/// What [`Model::advance`] may use of the world.
#[derive(Debug)]
pub struct Environment<'a> {
    /// Gravity (m/s²).
    pub gravity: [f64; 3],
    /// The rigid colliders, at their positions at the start of the step.
    pub colliders: &'a [Collider],
    /// The model's anchors.
    pub anchors: &'a [Anchor],
    /// Time at the end of the step (s).
    pub time: f64,
}

/// A solver behind the one integrator. Everything the time loop, the frame loop,
/// anchors, colliders, the blow-up detector, checkpoints and the cache need of it.
pub trait Model: Any + Debug + Send + Sync {
    /// The model's name, for messages and the manifest (`"peridynamics"`).
    fn name(&self) -> &'static str;

    /// What the integrator's points are, for messages (`"particle"`, `"mesh vertex"`).
    fn point_kind(&self) -> &'static str {
        "particle"
    }

    /// The points.
    fn points(&self) -> Points<'_>;

    /// The points, positions and velocities writable.
    fn points_mut(&mut self) -> PointsMut<'_>;

    /// The scene body of each point.
    fn point_bodies(&self) -> &[u32];

    /// How the points are advanced.
    fn stepping(&self) -> Stepping {
        Stepping::Verlet
    }

    /// Computes the internal forces at the current positions (and whatever the model
    /// updates with them: plasticity, fracture); returns how many bonds broke.
    fn internal_forces(&mut self) -> usize;

    /// Writes each point's acceleration, internal force over mass plus `gravity`,
    /// into `out` (after [`Model::internal_forces`]).
    fn accelerations(&self, gravity: [f64; 3], out: &mut [[f64; 3]]);

    /// Damps the velocities over one step `dt` (air drag, smoothing), leaving points
    /// that are `anchored` alone.
    fn damp(&mut self, dt: f64, anchored: &[bool]);

    /// Advances the model by `dt` on its own ([`Stepping::Own`]); returns how many
    /// bonds broke. Verlet models are never asked.
    fn advance(&mut self, dt: f64, environment: &Environment<'_>) -> Result<usize> {
        let _ = (dt, environment);
        Err(crate::error::SimError::Refused(format!(
            "the {} model is stepped by the world's integrator, not by itself",
            self.name()
        )))
    }

    /// The largest stable time step (s) and the point that limits it.
    fn stable_time_step(&self) -> (f64, usize);

    /// Kinetic energy (J), summed in an order independent of the thread count.
    fn kinetic_energy(&self) -> f64;

    /// Strain energy (J) at the last computed forces.
    fn strain_energy(&self) -> f64;

    /// The cache particle that stands for point `point` (for messages).
    fn particle_of_point(&self, point: usize) -> usize {
        point
    }

    /// The particles for the cache.
    fn particles(&self) -> ParticleColumns;

    /// The cache particles' positions in full precision (for measurements); the
    /// points' positions unless the particles are not the points.
    fn particle_positions(&self) -> Vec<[f64; 3]> {
        self.points().position.to_vec()
    }

    /// The points' data for particle contact, or `None` when they take no part in it
    /// (the default).
    fn contact_points(&self) -> Option<ContactPoints<'_>> {
        None
    }

    /// The points' fragments and how near their bonds are to breaking, for a model
    /// whose fragments may leave it for the rigid phase; `None` (the default) for a
    /// model that keeps its points.
    fn fragments(&self) -> Option<Fragments> {
        None
    }

    /// Hands `points` (a fragment that [`Model::fragments`] named) to the rigid phase:
    /// from now on the model computes no force on them and their bonds neither stretch
    /// nor break; the world moves them with their rigid body. Models that return no
    /// fragments are never asked.
    fn freeze(&mut self, points: &[u32]) {
        let _ = points;
    }

    /// Gives `points` (a rigid piece, at the pose and velocity its body left them) back
    /// to the model: its forces and bonds act on them again from the next step, from
    /// the bonds' state at the hand-off (a rigid motion leaves every bond's stretch as
    /// it was). Models that return no fragments are never asked.
    fn thaw(&mut self, points: &[u32]) {
        let _ = points;
    }

    /// How rigid piece `points` has turned from the reference configuration (its
    /// body's rotation times its collider's turn at the switch), given before each
    /// frame's tets are placed: a point whose intact bonds no longer span 3-D (a chip
    /// of one to a few points) places its tet by this rotation, so that the tet turns
    /// with the body and stays on its collider. Models without a tet mesh ignore it.
    fn orient(&mut self, points: &[u32], rotation: [[f64; 3]; 3]) {
        let _ = (points, rotation);
    }

    /// The surface of `points` (a fragment going rigid) in the reference
    /// configuration, for its rigid body's collider; `None` (the default) for a model without a tet mesh, whose pieces
    /// collide as their particles (docs/rigid.md, "Colliders and contact").
    fn reference_surface(&self, points: &[u32]) -> Option<PieceSurface> {
        let _ = points;
        None
    }

    /// Which points are in the rigid phase, `None` while none is.
    fn frozen(&self) -> Option<&[bool]> {
        None
    }

    /// Bonds the model holds (directed), for the manifest.
    fn bonds(&self) -> usize {
        0
    }

    /// Directed bonds whose broken bit is set (cut before the first step or broken
    /// since); a resume checks the checkpoint's count of broken bonds against it.
    fn broken_bonds(&self) -> u64 {
        0
    }

    /// Writes the model's saved state (not scratch) into a checkpoint.
    fn save(&self, out: &mut Encoder);

    /// Restores the saved state written by [`Model::save`] for the same scene,
    /// checking everything before the model uses it (lengths against the scene,
    /// indices in range, values finite where they must be): a checkpoint that passes
    /// its checksum but is wrong is refused through [`Decoder::error`], never panics.
    fn restore(&mut self, input: &mut Decoder<'_>) -> Result<()>;

    /// Wall time of each of the model's stages so far (s), by name.
    fn stage_times(&self) -> Vec<(&'static str, f64)>;

    /// Splits the model's work over the ranks of a distributed run
    /// ([`crate::ranks`]); every rank must end each step holding the same state as a
    /// single process would. By default a model does all its work on every rank (the
    /// same bytes, no speed-up).
    fn share(&mut self, ranks: Arc<dyn Ranks>) {
        let _ = ranks;
    }

    /// Sets the stage times back to zero (benchmarks).
    fn reset_stage_times(&mut self);

    /// The sheet of the current state (its particles and intact triangles), for
    /// models that write `sheet/` (membranes).
    fn sheet_frame(&self) -> Option<SheetFrame> {
        None
    }

    /// The split tet mesh of the current state, for models that write `tets/`.
    fn tet_frame(&mut self) -> Option<TetFrame> {
        None
    }

    /// Restores the split tet mesh's topology from the last frame written before a
    /// checkpoint, so that resumed frames keep its vertex numbering.
    fn restore_tet_frame(&mut self, last: TetFrame) -> Result<()> {
        let _ = last;
        Ok(())
    }
}
