//! Sheets of one particle layer (Han §6: "a single layer of uniformly distributed
//! particles"), sampled on a regular triangular lattice, or resampled from a triangle
//! mesh (open or closed) to the spacing by isotropic remeshing
//! ([`crate::geometry::mesh::remesh`]), whose vertices are the particles and whose
//! triangles the sheet's.
//!
//! The lattice is triangular rather than square because a triangular lattice of
//! central pair forces is elastically isotropic (the same stiffness in every in-plane
//! direction, Poisson ratio exactly 1/3), while a square lattice has the cubic
//! anisotropy of its two bond lengths; it is also the densest packing, so every
//! particle carries the same area A = (√3/2) h² for spacing h. Rows run along the
//! sheet's first in-plane axis u, `√3/2 h` apart along v, every other row shifted by
//! h/2.

use std::path::Path;

use crate::geometry::mesh::TriMesh;
use crate::geometry::mesh::remesh::remesh;
use crate::geometry::shape;
use crate::scene::{BodySpec, ShapeSpec};

/// A sampled sheet: particle positions and what every particle carries.
#[derive(Debug, Clone, PartialEq)]
pub struct Sheet {
    /// Particle positions (m), row by row.
    pub position: Vec<[f64; 3]>,
    /// Area A_i of each particle (m²): (√3/2) h² on a lattice, a third of its
    /// triangles' area on a mesh.
    pub area: Vec<f64>,
    /// Thickness of the sheet (m).
    pub thickness: f64,
    /// The sheet's triangles (indices into `position`) for a mesh sheet; empty for a
    /// lattice, whose triangles are found from its bonds
    /// ([`crate::membrane::MembraneModel::lattice_triangles`]).
    pub triangles: Vec<[u32; 3]>,
}

/// The outline of a sheet in its plane.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Outline {
    /// A rectangle of full sides `[a, b]` along u and v.
    Rectangle([f64; 2]),
    /// A disc of this radius.
    Disc(f64),
}

/// A sheet's placement: centre, normal axis, the in-plane axes u and v (the other two
/// in increasing order), outline and thickness.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Placement {
    center: [f64; 3],
    normal: usize,
    outline: Outline,
    thickness: f64,
}

fn in_plane(normal: usize) -> [usize; 2] {
    match normal {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

/// The sheet a membrane body's shape stands for: a `box` or `slab` is a rectangle in
/// the plane of its two larger sides with its smallest side as the thickness (the
/// first smallest on ties); a `cylinder` is a disc across its axis with its height as
/// the thickness. Other shapes are an error saying so.
fn placement(shape: &ShapeSpec) -> Result<Placement, String> {
    match shape {
        ShapeSpec::Box { center, size } | ShapeSpec::Slab { center, size } => {
            let normal = (0..3).fold(0, |n, a| if size[a] < size[n] { a } else { n });
            let [u, v] = in_plane(normal);
            Ok(Placement {
                center: *center,
                normal,
                outline: Outline::Rectangle([size[u], size[v]]),
                thickness: size[normal],
            })
        }
        ShapeSpec::Cylinder {
            center,
            radius,
            height,
            axis,
        } => Ok(Placement {
            center: *center,
            normal: axis.index(),
            outline: Outline::Disc(*radius),
            thickness: *height,
        }),
        _ => Err(
            "a membrane is a rectangle (type = \"box\" or \"slab\": the smallest side is the thickness), \
             a disc (type = \"cylinder\": the height is the thickness) or a triangle mesh \
             (type = \"mesh\")"
                .into(),
        ),
    }
}

/// The surface of a mesh sheet, read (relative to `base_dir`), placed and checked;
/// `None` for the other shapes.
fn mesh_surface(body: &BodySpec, base_dir: &Path) -> Result<Option<TriMesh>, String> {
    match (&body.shape, shape::placement(&body.shape)) {
        (ShapeSpec::Mesh { path, .. }, Some(placement)) => {
            TriMesh::load_surface(&base_dir.join(path), &placement)
                .map(Some)
                .map_err(|e| e.to_string())
        }
        _ => Ok(None),
    }
}

/// The thickness of a mesh sheet (`[body.membrane] thickness`, which the scene's
/// validation requires of a mesh membrane).
fn mesh_thickness(body: &BodySpec) -> Result<f64, String> {
    body.membrane
        .as_ref()
        .and_then(|m| m.thickness)
        .ok_or_else(|| "a membrane given by a mesh needs [body.membrane] thickness (m)".into())
}

/// The thickness of a membrane body's sheet (m): its shape's smallest side or height,
/// or `[body.membrane] thickness` for a mesh.
pub fn thickness(body: &BodySpec) -> Result<f64, String> {
    match body.shape {
        ShapeSpec::Mesh { .. } => mesh_thickness(body),
        ref shape => Ok(placement(shape)?.thickness),
    }
}

/// The number of particles [`sample`] places, computed without placing them (for
/// the memory estimate before a run): a mesh sheet's area over the lattice's area
/// per particle, which the remeshed sheet matches on average.
pub fn particle_count(body: &BodySpec, base_dir: &Path) -> Result<f64, String> {
    let h = body.resolution;
    let row = h * 3f64.sqrt() / 2.0;
    if let Some(mesh) = mesh_surface(body, base_dir)? {
        return Ok((mesh.area() / (h * row)).max(1.0));
    }
    let p = placement(&body.shape)?;
    Ok(match p.outline {
        Outline::Rectangle([a, b]) => (a / h).round().max(1.0) * (b / row).round().max(1.0),
        Outline::Disc(radius) => std::f64::consts::PI * radius * radius / (h * row),
    })
}

/// Samples the sheet of a membrane body at its `resolution` (the spacing h); a mesh
/// file is read relative to `base_dir`.
pub fn sample(body: &BodySpec, base_dir: &Path) -> Result<Sheet, String> {
    let h = body.resolution;
    if let Some(mesh) = mesh_surface(body, base_dir)? {
        let r = remesh(&mesh, h);
        if r.vertices.len() < 2 {
            return Err(format!(
                "the sheet holds {} particle at spacing {h} m (its mesh's area is {:.3e} m²): \
                 make it larger or the resolution finer",
                r.vertices.len(),
                mesh.area()
            ));
        }
        return Ok(Sheet {
            position: r.vertices,
            area: r.area,
            thickness: mesh_thickness(body)?,
            triangles: r.triangles,
        });
    }
    let p = placement(&body.shape)?;
    let row = h * 3f64.sqrt() / 2.0;
    let [u, v] = in_plane(p.normal);
    let mut position = Vec::new();
    let mut put = |a: f64, b: f64| {
        let mut x = p.center;
        x[u] += a;
        x[v] += b;
        position.push(x);
    };
    match p.outline {
        Outline::Rectangle([a, b]) => {
            // Cell-centred: each particle owns an h × (√3/2)h cell of the rectangle.
            let columns = (a / h).round().max(1.0) as usize;
            let rows = (b / row).round().max(1.0) as usize;
            for j in 0..rows {
                let shift = if j % 2 == 0 { -0.25 * h } else { 0.25 * h };
                let y = (j as f64 - (rows - 1) as f64 / 2.0) * row;
                for i in 0..columns {
                    let x = (i as f64 - (columns - 1) as f64 / 2.0) * h;
                    put(if columns > 1 { x + shift } else { x }, y);
                }
            }
        }
        Outline::Disc(radius) => {
            let reach = (radius / row).floor() as i64;
            for j in -reach..=reach {
                let y = j as f64 * row;
                let shift = if j.rem_euclid(2) == 1 { 0.5 * h } else { 0.0 };
                let span = ((radius / h).ceil() as i64) + 1;
                for i in -span..=span {
                    let x = i as f64 * h + shift;
                    if x * x + y * y <= radius * radius {
                        put(x, y);
                    }
                }
            }
        }
    }
    if position.len() < 2 {
        return Err(format!(
            "the sheet holds {} particle at spacing {h} m: make it larger or the resolution finer",
            position.len()
        ));
    }
    Ok(Sheet {
        area: vec![h * row; position.len()],
        position,
        thickness: p.thickness,
        triangles: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Axis;

    fn body(shape: ShapeSpec, h: f64) -> BodySpec {
        let text = format!(
            "material = \"m\"\nresolution = {h}\nshape = {{ type = \"box\", center = [0, 0, 0], size = [1, 1, 1] }}\n"
        );
        let mut b: BodySpec = toml::from_str(&text).expect("body");
        b.shape = shape;
        b
    }

    #[test]
    fn rectangle_and_disc_cover_their_area() {
        let rect = body(
            ShapeSpec::Slab {
                center: [0.0, 1.0, 0.0],
                size: [0.4, 0.001, 0.2],
            },
            0.01,
        );
        let s = sample(&rect, Path::new(".")).expect("sheet");
        assert_eq!(s.thickness, 0.001);
        let area: f64 = s.area.iter().sum();
        assert!((area - 0.08).abs() / 0.08 < 0.03, "area {area}");
        assert!(s.position.iter().all(|x| x[1] == 1.0));
        let disc = body(
            ShapeSpec::Cylinder {
                center: [0.0; 3],
                radius: 0.1,
                height: 0.002,
                axis: Axis::Z,
            },
            0.005,
        );
        let d = sample(&disc, Path::new(".")).expect("disc");
        let area: f64 = d.area.iter().sum();
        let exact = std::f64::consts::PI * 0.01;
        assert!((area - exact).abs() / exact < 0.03, "area {area}");
        assert!(d.position.iter().all(|x| x[2] == 0.0));
    }

    #[test]
    fn a_sphere_is_no_sheet() {
        let b = body(
            ShapeSpec::Sphere {
                center: [0.0; 3],
                radius: 1.0,
            },
            0.1,
        );
        assert!(sample(&b, Path::new(".")).unwrap_err().contains("cylinder"));
    }
}
