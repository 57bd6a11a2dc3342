//! A cache checked against its manifest (`perifrac verify`): every frame the manifest
//! lists is on disk, every file it recorded has the size and CRC-32 it had when it was
//! written, particle positions are finite, the checkpoint reads, and no frame from
//! another run sits beside them. `perifrac render` and `perifrac surface` run the same
//! checks first and warn on what they find.

use std::path::{Path, PathBuf};

use crate::checkpoint::Checkpoint;
use crate::layout::Layout;
use crate::manifest::{FileRecord, Manifest, Status, frame_of};
use crate::ply::ParticleFrame;
use crate::scene::Scene;

/// Something wrong with a cache.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// `manifest.json` is missing or cannot be read.
    Manifest {
        /// Why.
        message: String,
    },
    /// A file the manifest lists (or a frame it counts) is not there.
    Missing {
        /// The file.
        path: PathBuf,
    },
    /// A file is not as it was written: another length or another checksum.
    Damaged {
        /// The file.
        path: PathBuf,
        /// What differs.
        message: String,
    },
    /// A file could not be read or decoded.
    Unreadable {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A particle frame holds a non-finite position.
    NonFinite {
        /// The frame file.
        path: PathBuf,
        /// The first such particle.
        particle: usize,
    },
    /// A frame file the manifest does not list (left by another run).
    Stray {
        /// The file.
        path: PathBuf,
    },
    /// The manifest contradicts itself or the frames: collider centres or rotations
    /// for another number of frames or colliders, a particle count the frames do not
    /// have. The stages would draw or write the wrong thing, so `render` and `surface`
    /// refuse such a cache (exit code 2) where they only warn about damaged frames.
    Inconsistent {
        /// The manifest, or the frame file that disagrees with it.
        path: PathBuf,
        /// What disagrees.
        message: String,
    },
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::Manifest { message } => write!(f, "{message}"),
            Problem::Missing { path } => {
                write!(f, "{}: missing (the manifest lists it)", path.display())
            }
            Problem::Damaged { path, message } => write!(f, "{}: {message}", path.display()),
            Problem::Unreadable { path, message } => write!(f, "{}: {message}", path.display()),
            Problem::NonFinite { path, particle } => write!(
                f,
                "{}: particle {particle} has a non-finite position",
                path.display()
            ),
            Problem::Stray { path } => write!(
                f,
                "{}: a frame the manifest does not list (from another run?)",
                path.display()
            ),
            Problem::Inconsistent { path, message } => write!(
                f,
                "{}: {message}: the manifest does not describe this cache (edited, or from \
                 another run); run the scene again with --force",
                path.display()
            ),
        }
    }
}

/// What [`verify`] found.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// The manifest, if it reads.
    pub manifest: Option<Manifest>,
    /// Files checked against a recorded size and checksum.
    pub checked: usize,
    /// Everything wrong, in file order.
    pub problems: Vec<Problem>,
}

impl Report {
    /// Whether the manifest contradicts itself or the frames
    /// ([`Problem::Inconsistent`]).
    pub fn is_inconsistent(&self) -> bool {
        self.problems
            .iter()
            .any(|p| matches!(p, Problem::Inconsistent { .. }))
    }

    /// Whether nothing is damaged or missing.
    pub fn is_clean(&self) -> bool {
        self.problems.is_empty()
    }

    /// How the run stands, if the manifest reads.
    pub fn status(&self) -> Option<Status> {
        self.manifest.as_ref().map(|m| m.status)
    }
}

/// Checks the cache in `layout` against its manifest.
pub fn verify(layout: &Layout) -> Report {
    let mut report = Report::default();
    let manifest = match Manifest::read(&layout.manifest()) {
        Ok(m) => m,
        Err(e) => {
            let message = match layout.manifest().exists() {
                true => format!("{e}"),
                false => format!(
                    "{}: missing: frame times, counts and checksums are unknown",
                    layout.manifest().display()
                ),
            };
            report.problems.push(Problem::Manifest { message });
            // Without a manifest, still look at the frames that are there.
            for frame in layout.particle_frames() {
                check_particles(&layout.particles(frame), None, None, &mut report);
            }
            return report;
        }
    };
    let frames = manifest.frames();
    check_colliders(layout, &manifest, &mut report);
    let count = Some(manifest.particles);
    for (name, record) in &manifest.files {
        let path = layout.root.join(name);
        if name.starts_with("particles/") {
            check_particles(&path, Some(record), count, &mut report);
        } else if let Some(bytes) = read(&path, &mut report) {
            check_record(&path, &bytes, record, &mut report);
        }
    }
    // Frames the manifest counts but did not record (a manifest from before
    // checksums): they must at least be there.
    let recorded_particles = manifest.files.keys().any(|k| k.starts_with("particles/"));
    if !recorded_particles {
        for frame in 1..=frames {
            let path = layout.particles(frame);
            if path.exists() {
                check_particles(&path, None, count, &mut report);
            }
        }
    } else {
        for frame in 1..=frames {
            let name = format!("particles/{frame:04}.ply");
            if !manifest.files.contains_key(&name) {
                report.problems.push(Problem::Missing {
                    path: layout.root.join(name),
                });
            }
        }
    }
    for dir in [layout.particles_dir(), layout.tets_dir()] {
        for path in files_in(&dir) {
            let name = relative(&layout.root, &path);
            if frame_of(&name).is_some_and(|k| k > frames) {
                report.problems.push(Problem::Stray { path });
            }
        }
    }
    if layout.checkpoint().exists()
        && let Err(e) = Checkpoint::read(&layout.checkpoint())
    {
        report.problems.push(Problem::Unreadable {
            path: layout.checkpoint(),
            message: strip_path(&e.to_string(), &layout.checkpoint()),
        });
    }
    report.manifest = Some(manifest);
    report
}

/// The message of an error that starts with the path, without the path.
fn strip_path(message: &str, path: &Path) -> String {
    let prefix = format!("{}: ", path.display());
    message.strip_prefix(&prefix).unwrap_or(message).to_string()
}

fn relative(root: &Path, path: &Path) -> String {
    path.strip_prefix(root)
        .unwrap_or(path)
        .to_string_lossy()
        .replace('\\', "/")
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    files.sort();
    files
}

fn read(path: &Path, report: &mut Report) -> Option<Vec<u8>> {
    match std::fs::read(path) {
        Ok(bytes) => Some(bytes),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            report.problems.push(Problem::Missing {
                path: path.to_path_buf(),
            });
            None
        }
        Err(e) => {
            report.problems.push(Problem::Unreadable {
                path: path.to_path_buf(),
                message: e.to_string(),
            });
            None
        }
    }
}

/// Compares `bytes` with what was recorded; true when they match.
fn check_record(path: &Path, bytes: &[u8], record: &FileRecord, report: &mut Report) -> bool {
    report.checked += 1;
    let actual = FileRecord::of(bytes);
    let message = if actual.bytes != record.bytes {
        format!(
            "{} bytes, {} when written (truncated or overwritten)",
            actual.bytes, record.bytes
        )
    } else if actual.crc32 != record.crc32 {
        format!(
            "checksum {:#010x}, {:#010x} when written: the contents changed",
            actual.crc32, record.crc32
        )
    } else {
        return true;
    };
    report.problems.push(Problem::Damaged {
        path: path.to_path_buf(),
        message,
    });
    false
}

/// The manifest's collider poses against its frames and the scene's colliders: a row
/// of `collider_centers` (and of `collider_rotations`, when there are any) a frame, an
/// entry a collider; its body counts against its particle count.
fn check_colliders(layout: &Layout, manifest: &Manifest, report: &mut Report) {
    let path = layout.manifest();
    let frames = manifest.frames();
    let colliders = Scene::load_cached(&layout.scene())
        .ok()
        .map(|scene| scene.colliders.len());
    let mut inconsistent = |message: String| {
        report.problems.push(Problem::Inconsistent {
            path: path.clone(),
            message,
        })
    };
    let tables = [
        (
            "collider_centers",
            manifest
                .collider_centers
                .iter()
                .map(Vec::len)
                .collect::<Vec<_>>(),
        ),
        (
            "collider_rotations",
            manifest.collider_rotations.iter().map(Vec::len).collect(),
        ),
    ];
    for (name, rows) in tables {
        let expected = colliders.unwrap_or(0) > 0 && name == "collider_centers";
        if rows.len() != frames && (expected || !rows.is_empty()) {
            inconsistent(format!(
                "{name} has {} rows for its {frames} frames",
                rows.len()
            ));
        } else if let Some(colliders) = colliders
            && let Some(k) = rows.iter().position(|&n| n != colliders)
        {
            inconsistent(format!(
                "{name} has {} entries at frame {} for the scene's {colliders} colliders",
                rows[k],
                k + 1
            ));
        }
    }
    let in_bodies: usize = manifest.bodies.iter().map(|b| b.particles).sum();
    if !manifest.bodies.is_empty() && in_bodies != manifest.particles {
        inconsistent(format!(
            "particles = {} but its bodies hold {in_bodies}",
            manifest.particles
        ));
    }
}

/// A particle frame: against its record if there is one, then decoded for
/// non-finite positions and, with `count`, its particle count.
fn check_particles(
    path: &Path,
    record: Option<&FileRecord>,
    count: Option<usize>,
    report: &mut Report,
) {
    let Some(bytes) = read(path, report) else {
        return;
    };
    if let Some(record) = record
        && !check_record(path, &bytes, record, report)
    {
        return;
    }
    match ParticleFrame::from_bytes(&bytes) {
        Ok(frame) => {
            if let Some(count) = count.filter(|&n| n != frame.position.len()) {
                report.problems.push(Problem::Inconsistent {
                    path: path.to_path_buf(),
                    message: format!(
                        "{} particles, where manifest.json says particles = {count}",
                        frame.position.len()
                    ),
                });
            }
            if let Some(particle) = frame
                .position
                .iter()
                .position(|p| !p.iter().all(|x| x.is_finite()))
            {
                report.problems.push(Problem::NonFinite {
                    path: path.to_path_buf(),
                    particle,
                });
            }
        }
        Err(message) => report.problems.push(Problem::Unreadable {
            path: path.to_path_buf(),
            message,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::write_atomic;

    fn frame(k: usize, x: f32) -> ParticleFrame {
        ParticleFrame {
            frame: k,
            time: k as f64,
            position: vec![[x, 0.0, 0.0]],
            velocity: vec![[0.0; 3]],
            damage: vec![0.0],
            plastic: vec![0.0],
            material: vec![0.0],
            fragment: vec![0.0],
            extra: Vec::new(),
        }
    }

    #[test]
    fn damage_missing_frames_strays_and_nan_are_named() {
        let dir = tempfile::tempdir().expect("tempdir");
        let layout = Layout::new(dir.path());
        layout.create().expect("create");
        let mut manifest = Manifest {
            status: Status::Complete,
            particles: 1,
            ..Manifest::default()
        };
        for k in 1..=3 {
            let path = layout.particles(k);
            let record = frame(k, k as f32).write(&path).expect("write");
            manifest
                .files
                .insert(format!("particles/{k:04}.ply"), record);
            manifest.frame_times.push(k as f64);
        }
        manifest.write(&layout.manifest()).expect("manifest");
        let clean = verify(&layout);
        assert!(clean.is_clean(), "{:?}", clean.problems);
        assert_eq!(clean.checked, 3);

        // A flipped byte, a deleted frame, a stray frame, NaN in an unrecorded one.
        let mut bytes = std::fs::read(layout.particles(2)).expect("read");
        let last = bytes.len() - 1;
        bytes[last] ^= 0x10;
        std::fs::write(layout.particles(2), bytes).expect("write");
        std::fs::remove_file(layout.particles(3)).expect("remove");
        frame(4, f32::NAN)
            .write(&layout.particles(4))
            .expect("write");
        let report = verify(&layout);
        let text: Vec<String> = report.problems.iter().map(|p| p.to_string()).collect();
        assert_eq!(report.problems.len(), 3, "{text:?}");
        assert!(text[0].contains("0002.ply: checksum"), "{text:?}");
        assert!(text[1].contains("0003.ply: missing"), "{text:?}");
        assert!(
            text[2].contains("0004.ply: a frame the manifest does not list"),
            "{text:?}"
        );

        write_atomic(&layout.manifest(), b"{ not json").expect("write");
        let report = verify(&layout);
        assert!(matches!(report.problems[0], Problem::Manifest { .. }));
        assert!(
            report
                .problems
                .iter()
                .any(|p| matches!(p, Problem::NonFinite { particle: 0, .. })),
            "{:?}",
            report.problems
        );
    }
}
