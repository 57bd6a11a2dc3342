//! The `sheet` surface method, for membranes: a sheet's own triangulated particles
//! (`sheet/NNNN.ply`: the lattice triangles whose three bonds are intact) offset by
//! half its thickness to both sides along the vertex normals, with every open edge
//! closed by a wall — so the wrinkles and crack edges the particles carry survive,
//! which a particle-to-volume mesher smooths away (Han §7, Fig. 12). Walls along edges
//! that were open in the first frame (the sheet's outline, initial slits) belong to
//! the surface; walls along edges opened since are the crack faces.

use std::collections::HashSet;
use std::sync::atomic::{AtomicUsize, Ordering};

use perifrac_cache::Layout;
use perifrac_cache::collider::mesh_colliders;
use perifrac_cache::frames::FrameRange;
use perifrac_cache::manifest::Manifest;
use perifrac_cache::mesh::{SurfaceEncoder, SurfaceMesh};
use perifrac_cache::scene::Scene;
use perifrac_cache::sheet::SheetFrame;
use perifrac_math::{add, cross, normalize, scale, sub};
use rayon::prelude::*;

use crate::error::{Result, SurfaceError};
use crate::frame_range;
use crate::write_encoded as write;

/// Directed edges used by exactly one triangle: the open edges, each in the direction
/// its triangle runs it.
pub fn open_edges(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let directed: HashSet<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .collect();
    let mut open: Vec<(u32, u32)> = directed
        .iter()
        .copied()
        .filter(|&(a, b)| !directed.contains(&(b, a)))
        .collect();
    open.sort_unstable();
    open
}

/// The closed shell of `sheet` over the triangles `triangles` (its own, or another
/// frame's for an animation): vertex v at p_v ± (h_v/2) n_v (n_v the area-weighted
/// normal of its triangles; a vertex of no triangle, which no triangle draws, takes
/// the normal +y), the top
/// triangles, the bottom ones reversed, and a wall of two triangles along every open
/// edge, in `crack_indices` unless the edge is in `outline`. Both copies of a vertex
/// carry its damage and θ; `quantity_range` is the θ range of the colour map.
pub fn shell(
    sheet: &SheetFrame,
    triangles: &[[u32; 3]],
    outline: &HashSet<(u32, u32)>,
    quantity_range: [f32; 2],
) -> SurfaceMesh {
    let n = sheet.positions.len();
    let p: Vec<[f64; 3]> = sheet.positions.iter().map(|x| x.map(f64::from)).collect();
    let mut normal = vec![[0.0f64; 3]; n];
    for t in triangles {
        let [a, b, c] = t.map(|v| v as usize);
        let area_normal = cross(sub(p[b], p[a]), sub(p[c], p[a]));
        for v in [a, b, c] {
            normal[v] = add(normal[v], area_normal);
        }
    }
    let normal: Vec<[f64; 3]> = normal
        .into_iter()
        .map(|m| {
            if m == [0.0; 3] {
                [0.0, 1.0, 0.0]
            } else {
                normalize(m)
            }
        })
        .collect();
    let side = |sign: f64| -> Vec<[f32; 3]> {
        (0..n)
            .map(|v| {
                add(
                    p[v],
                    scale(normal[v], sign * 0.5 * f64::from(sheet.thickness[v])),
                )
            })
            .map(|x| x.map(|c| c as f32))
            .collect()
    };
    let f32n = |sign: f64| normal.iter().map(move |m| m.map(|c| (sign * c) as f32));
    let mut mesh = SurfaceMesh {
        positions: [side(1.0), side(-1.0)].concat(),
        normals: f32n(1.0).chain(f32n(-1.0)).collect(),
        damage: [sheet.damage.clone(), sheet.damage.clone()].concat(),
        quantity: [sheet.quantity.clone(), sheet.quantity.clone()].concat(),
        quantity_range,
        ..SurfaceMesh::default()
    };
    let n = n as u32;
    for t in triangles {
        mesh.surface_indices.extend_from_slice(t);
        mesh.surface_indices
            .extend_from_slice(&[t[0] + n, t[2] + n, t[1] + n]);
    }
    for (a, b) in open_edges(triangles) {
        let wall = [a, a + n, b + n, a, b + n, b];
        if outline.contains(&(a, b)) {
            mesh.surface_indices.extend_from_slice(&wall);
        } else {
            mesh.crack_indices.extend_from_slice(&wall);
        }
    }
    mesh
}

/// The smallest and largest finite θ over every frame's sheet, the fixed range of the
/// colour map (so a colour is the same θ in every frame and file); [θ, θ] when θ never
/// changes, [0, 0] when no θ is finite.
pub fn quantity_range(layout: &Layout, frames: usize) -> Result<[f32; 2]> {
    let per_frame: Vec<[f32; 2]> = (1..=frames)
        .into_par_iter()
        .map(|frame| {
            let sheet = SheetFrame::read(&layout.sheet(frame))?;
            Ok(sheet
                .quantity
                .iter()
                .filter(|q| q.is_finite())
                .fold([f32::INFINITY, f32::NEG_INFINITY], |[lo, hi], &q| {
                    [lo.min(q), hi.max(q)]
                }))
        })
        .collect::<Result<_>>()?;
    let [lo, hi] = per_frame
        .iter()
        .fold([f32::INFINITY, f32::NEG_INFINITY], |[lo, hi], r| {
            [lo.min(r[0]), hi.max(r[1])]
        });
    Ok(if lo <= hi { [lo, hi] } else { [0.0, 0.0] })
}

/// One frame of `animated.glb`: its vertex positions and θ in the last frame's topology.
type Morph = (Vec<[f32; 3]>, Vec<f32>);

/// Runs the `sheet` method over frames `range` of the cache at `layout` (every frame
/// with `None`), frames in parallel: reads `sheet/NNNN.ply`, writes `surface/NNNN.glb`
/// through `encoder`, θ's colour range the run's ([`quantity_range`], over every frame
/// whatever the range, so a range's files are the bytes a run over every frame
/// writes), and calls `progress(done, total)` after each frame. Over every frame it
/// also writes `surface/animated.glb` (the last frame's topology, one morph target a
/// frame, θ of every frame beside the positions) and records the time in the
/// manifest. Returns the frames surfaced.
pub fn stage(
    layout: &Layout,
    range: Option<FrameRange>,
    encoder: &dyn SurfaceEncoder,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<usize> {
    let manifest = Manifest::read(&layout.manifest())?;
    let frames = manifest.frame_times.len();
    if frames == 0 || !layout.sheet(1).is_file() {
        return Err(SurfaceError::Input(format!(
            "{} is missing: the sheet method reads the membranes' sheets; run a membrane \
             scene with [output] surface = \"sheet\"",
            layout.sheet(1).display()
        )));
    }
    let range = frame_range(layout, &manifest, range)?;
    let whole = range.is_all(frames);
    let dir = layout.surface_dir();
    std::fs::create_dir_all(&dir).map_err(|e| SurfaceError::io(&dir, e))?;
    let start = std::time::Instant::now();
    let first = SheetFrame::read(&layout.sheet(1))?;
    let outline: HashSet<(u32, u32)> = open_edges(&first.triangles).into_iter().collect();
    let last = SheetFrame::read(&layout.sheet(frames))?;
    let quantities = quantity_range(layout, frames)?;
    let done = AtomicUsize::new(0);
    let animated: Vec<Option<Morph>> = range
        .frames()
        .into_par_iter()
        .map(|frame| -> Result<_> {
            let sheet = if frame == frames {
                last.clone()
            } else {
                SheetFrame::read(&layout.sheet(frame))?
            };
            if sheet.positions.len() != last.positions.len() {
                return Err(SurfaceError::Input(format!(
                    "{}: {} vertices where the last frame has {}: the frames are not of one run",
                    layout.sheet(frame).display(),
                    sheet.positions.len(),
                    last.positions.len()
                )));
            }
            let mut mesh = shell(&sheet, &sheet.triangles, &outline, quantities);
            mesh.name = manifest.scene.clone();
            write(
                &layout.surface(frame),
                format!("frame {frame}"),
                encoder.fractured(&mesh),
            )?;
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, range.len());
            Ok(whole.then(|| {
                let animated = shell(&sheet, &last.triangles, &outline, quantities);
                (animated.positions, animated.quantity)
            }))
        })
        .collect::<Result<_>>()?;
    if whole {
        // The scene's mesh colliders, which animated.glb carries beside the surface.
        let scene = Scene::load_cached(&layout.scene())?;
        let colliders = mesh_colliders(layout, &scene, Some(&manifest))?;
        let (positions, quantity): (Vec<_>, Vec<_>) = animated.into_iter().flatten().unzip();
        let mut base = shell(&first, &last.triangles, &outline, quantities);
        base.name = manifest.scene.clone();
        let times: Vec<f32> = manifest.frame_times.iter().map(|&t| t as f32).collect();
        write(
            &layout.animated_surface(),
            "surface/animated.glb".into(),
            encoder.animated(&base, &times, &positions, &quantity, &colliders),
        )?;
        let seconds = start.elapsed().as_secs_f64();
        layout.update_manifest(|m| {
            m.timings.surface = seconds;
            Ok(())
        })?;
    }
    Ok(range.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles sharing the edge 1–2 in the z = 0 plane, 2 mm thick.
    fn square() -> SheetFrame {
        SheetFrame {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, 0.0],
            ],
            thickness: vec![0.002; 4],
            quantity: vec![0.0; 4],
            damage: vec![0.0; 4],
            triangles: vec![[0, 1, 2], [1, 3, 2]],
        }
    }

    #[test]
    fn a_sheet_becomes_a_closed_shell_of_its_thickness() {
        let s = square();
        let outline: HashSet<_> = open_edges(&s.triangles).into_iter().collect();
        assert_eq!(outline.len(), 4);
        let mesh = shell(&s, &s.triangles, &outline, [0.0, 0.0]);
        assert_eq!(mesh.positions.len(), 8);
        assert_eq!(mesh.positions[0], [0.0, 0.0, 0.001]);
        assert_eq!(mesh.positions[4], [0.0, 0.0, -0.001]);
        // 2 top + 2 bottom + 2 a wall for 4 outline edges; no crack.
        assert_eq!(mesh.surface_indices.len(), 3 * 12);
        assert!(mesh.crack_indices.is_empty());
        // Closed: every directed edge has its reverse.
        let all: Vec<[u32; 3]> = mesh
            .surface_indices
            .chunks(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        assert!(open_edges(&all).is_empty(), "the shell is watertight");
        // Outward: the signed volume is the sheet's, 1 m² × 2 mm.
        let p = |v: u32| mesh.positions[v as usize].map(f64::from);
        let volume: f64 = all
            .iter()
            .map(|t| perifrac_math::dot(p(t[0]), cross(p(t[1]), p(t[2]))) / 6.0)
            .sum();
        assert!((volume - 0.002).abs() < 1e-9, "volume {volume}");
    }

    #[test]
    fn a_torn_edge_gets_crack_walls() {
        let s = square();
        let outline: HashSet<_> = open_edges(&s.triangles).into_iter().collect();
        // The second triangle's bonds broke: the shared edge 1–2 opens.
        let torn = [s.triangles[0]];
        let mesh = shell(&s, &torn, &outline, [0.0, 0.0]);
        assert_eq!(mesh.crack_indices.len(), 6, "one wall along the new edge");
        assert_eq!(mesh.surface_indices.len(), 3 * (2 + 4));
    }
}
