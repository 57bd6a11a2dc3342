#[cfg(feature = "dim3")]
mod ball_to_trimesh;
#[cfg(feature = "dim3")]
mod capsule_to_trimesh;
#[cfg(feature = "dim3")]
mod cone_to_trimesh;
#[cfg(feature = "dim3")]
mod convex_polyhedron_to_trimesh;
mod cuboid_to_trimesh;
#[cfg(feature = "dim3")]
mod cylinder_to_trimesh;
#[cfg(feature = "dim3")]
mod heightfield_to_trimesh;
#[cfg(feature = "dim3")]
mod voxels_to_trimesh;
