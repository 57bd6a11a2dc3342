//! `cargo run -p make-meshes [-- OUT_DIR]`: writes the mesh assets (default
//! `assets/meshes/`), then reads each back with the simulator's loader and
//! prints its triangle count and enclosed volume.

use std::path::PathBuf;
use std::process::ExitCode;

use perifrac_sim::geometry::mesh::{Placement, TriMesh};

fn main() -> ExitCode {
    let dir = std::env::args_os().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/meshes"),
        PathBuf::from,
    );
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("{}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    for asset in make_meshes::assets() {
        let path = dir.join(asset.name);
        if let Err(e) = std::fs::write(&path, &asset.bytes) {
            eprintln!("{}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        match TriMesh::load(&path, &Placement::default()) {
            Ok(m) => {
                let (lo, hi) = m.bounds();
                println!(
                    "{}: {} triangles, {} vertices, volume {:.4e} m³, bounds {lo:.3?}–{hi:.3?}, {} bytes",
                    asset.name,
                    m.triangles.len(),
                    m.vertices.len(),
                    m.enclosed_volume(),
                    asset.bytes.len()
                );
            }
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}
