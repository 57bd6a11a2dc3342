//! Plain meshes as one glTF (the `vdb` method's surfaces): a primitive a mesh, no
//! materials, damage as `_DAMAGE` where the mesh has it.

use gltf_json as json;
use json::validation::Checked;
use perifrac_cache::mesh::SurfaceMesh;

use super::{Triangles, accessor, check, finish, invalid, new_root, push_scalars, push_view};
use crate::RenderError;

/// Encodes meshes as a .glb file (an asset with no scene when `meshes` is empty):
/// one primitive a mesh, of its original-surface then its crack triangles, without
/// materials; a mesh's damage, when it has any, as the float attribute `_DAMAGE`.
pub fn to_glb(meshes: &[SurfaceMesh]) -> Result<Vec<u8>, RenderError> {
    use json::accessor::{ComponentType, Type};
    use json::buffer::Target;

    let mut root = new_root();
    let mut bin: Vec<u8> = Vec::new();
    let mut nodes = Vec::with_capacity(meshes.len());
    for surface in meshes {
        let all: Vec<u32>;
        let indices = if surface.crack_indices.is_empty() {
            &surface.surface_indices
        } else {
            all = [surface.surface_indices.as_slice(), &surface.crack_indices].concat();
            &all
        };
        let mesh = Triangles {
            name: &surface.name,
            positions: &surface.positions,
            normals: &surface.normals,
            indices,
        };
        check(&mesh)?;
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in mesh.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let floats = |v: &'_ [[f32; 3]]| {
            v.iter()
                .flat_map(|p| p.iter().map(|x| x.to_le_bytes()).collect::<Vec<_>>())
                .collect::<Vec<_>>()
        };
        let count = mesh.positions.len();
        let view = push_view(
            &mut root,
            &mut bin,
            floats(mesh.positions).into_iter(),
            Target::ArrayBuffer,
        );
        let positions = root.push(accessor(
            view,
            count,
            ComponentType::F32,
            Type::Vec3,
            Some((lo, hi)),
        ));
        let view = push_view(
            &mut root,
            &mut bin,
            floats(mesh.normals).into_iter(),
            Target::ArrayBuffer,
        );
        let normals = root.push(accessor(view, count, ComponentType::F32, Type::Vec3, None));
        let view = push_view(
            &mut root,
            &mut bin,
            mesh.indices.iter().map(|i| i.to_le_bytes()),
            Target::ElementArrayBuffer,
        );
        let indices = root.push(accessor(
            view,
            mesh.indices.len(),
            ComponentType::U32,
            Type::Scalar,
            None,
        ));
        let damage = if surface.damage.is_empty() {
            None
        } else if surface.damage.len() == count {
            Some(push_scalars(&mut root, &mut bin, &surface.damage))
        } else {
            return Err(invalid(format!(
                "mesh '{}' has {count} positions but {} damage values",
                surface.name,
                surface.damage.len()
            )));
        };
        let primitive = json::mesh::Primitive {
            attributes: [
                (
                    Checked::Valid(json::mesh::Semantic::Positions),
                    Some(positions),
                ),
                (Checked::Valid(json::mesh::Semantic::Normals), Some(normals)),
                (
                    Checked::Valid(json::mesh::Semantic::Extras("DAMAGE".into())),
                    damage,
                ),
            ]
            .into_iter()
            .filter_map(|(semantic, accessor)| Some((semantic, accessor?)))
            .collect(),
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: None,
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets: None,
        };
        let gltf_mesh = root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(mesh.name.to_string()),
            primitives: vec![primitive],
            weights: None,
        });
        nodes.push(root.push(json::Node {
            mesh: Some(gltf_mesh),
            name: Some(mesh.name.to_string()),
            ..Default::default()
        }));
    }
    if !nodes.is_empty() {
        let scene = root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes,
        });
        root.scene = Some(scene);
    }
    finish(root, bin, &[])
}
