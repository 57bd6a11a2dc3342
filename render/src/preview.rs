//! Preview images of an output directory: `preview/NNNN.png` for every frame (one fixed
//! camera framed on the whole shot, or one that follows it where the action spreads
//! far beyond its start: [`CameraMotion`]; a frame rendered alone goes to
//! `preview/frame_NNNN.png`, never over the sequence's), `preview/turntable_NNN.png` (N views of
//! one frame around the vertical axis), `preview/contact_sheet.png` and, when asked,
//! the movies (`preview/movie.png`, `movie.mp4`, `turntable.png`; [`crate::movie`]).
//! Frames render in parallel, each worker thread with its own GL context reused for
//! all its frames.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use image::RgbImage;

use perifrac_cache::frames::FrameRange;

use crate::RenderError;
use crate::cache::{Cache, ColorBy, Framing, Ranges};
use crate::camera::{Bounds, Camera, Subject};
pub use crate::follow::{FOLLOW_GROWTH, follow_cameras, largest_piece_view, spreads};
use crate::gl::{Backend, PassTimes, Renderer, View};
use crate::{movie, sheet};

/// What to render.
#[derive(Debug, Clone, PartialEq)]
pub struct PreviewOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Colouring.
    pub color_by: ColorBy,
    /// Only this frame, into `preview/frame_NNNN.png` (else every frame).
    pub frame: Option<usize>,
    /// Only these frames of the sequence, into `preview/NNNN.png` through the cameras
    /// of the whole sequence (a farm's array job; [`join`] makes the contact sheet and
    /// the movies once every range is there).
    pub frames: Option<FrameRange>,
    /// Turntable views (0: none) of `frame`, or of the last frame.
    pub turntable: usize,
    /// Worker threads (each with its own GL context).
    pub workers: usize,
    /// Camera azimuth (radians about +y; 0 looks from +z), of the frames and of the
    /// first turntable view; `None`: [`Cache::view_azimuth`] (from the side the
    /// projectile comes from).
    pub azimuth: Option<f32>,
    /// Also write the sequence (and the turntable) as movies at the playback rate:
    /// `preview/movie.png` (animated PNG), `preview/movie.mp4` when ffmpeg is on the
    /// `PATH`, `preview/turntable.png`.
    pub movie: bool,
    /// Draw the frame number, the simulation time and the playback time in the
    /// bottom-left corner of the sequence's frames (for reviews).
    pub overlay: bool,
    /// Whether the sequence's camera stays put or follows the shot.
    pub camera: CameraMotion,
}

/// How the camera of a sequence moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CameraMotion {
    /// `Follow` when the action ends up spreading over more than [`FOLLOW_GROWTH`]
    /// times the size of the first frame's (a shot whose debris flies metres from a
    /// wall a few decimetres wide), else `Fixed`.
    #[default]
    Auto,
    /// One camera framed on the whole shot ([`Camera::fit`] on the robust subject of
    /// every frame).
    Fixed,
    /// Frame k's camera framed on the shot so far (frames 1 to k): close on the impact,
    /// pulling back as the debris spreads ([`follow_cameras`]).
    Follow,
    /// Frame k's camera framed on frame k's largest piece and the particles around it
    /// ([`largest_piece_view`]): for a still of the end of a shot whose pieces lie
    /// metres apart.
    Largest,
}

impl Default for PreviewOptions {
    fn default() -> Self {
        PreviewOptions {
            width: 960,
            height: 540,
            color_by: ColorBy::Material,
            frame: None,
            frames: None,
            turntable: 0,
            workers: 1,
            azimuth: None,
            movie: false,
            overlay: false,
            camera: CameraMotion::Auto,
        }
    }
}

/// What was rendered.
#[derive(Debug, Clone, Default)]
pub struct PreviewReport {
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Frame images rendered (turntable views included).
    pub images: usize,
    /// The GL backend used.
    pub backend: Option<Backend>,
    /// Sum of the pass timings over all images.
    pub passes: PassTimes,
    /// Seconds spent encoding and writing PNGs (in the workers).
    pub encode: f64,
    /// Wall-clock seconds of the whole preview.
    pub seconds: f64,
    /// Things the user should know (empty frames).
    pub warnings: Vec<String>,
    /// A movie was asked for but no MP4 written: no ffmpeg on the `PATH`.
    pub mp4_skipped: bool,
}

/// One image to make: which frame, from where, into which file.
struct Job {
    frame: usize,
    camera: Camera,
    /// What the shadow map and the clip planes cover.
    bounds: Bounds,
    path: PathBuf,
    thumbnail: bool,
    /// The review overlay's text, if asked for.
    overlay: Option<String>,
}

/// Renders the previews of the output directory `out`; `progress(done, total)` is
/// called after each image.
pub fn render_cache(
    out: &Path,
    options: &PreviewOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<PreviewReport, RenderError> {
    let start = Instant::now();
    let cache = Cache::open(out)?;
    if let Some(k) = options.frame
        && !cache.frames.contains(&k)
    {
        return Err(RenderError::Input {
            path: out.to_path_buf(),
            message: format!(
                "frame {k} is not in the cache (frames {}–{})",
                cache.frames[0],
                cache.frames[cache.frames.len() - 1]
            ),
        });
    }
    let framing = cache.sequence_framing(options.color_by)?;
    let view = fixed_view(&cache, &framing, options);
    let (bounds, ground) = (view.bounds, view.ground);
    let aspect = options.width as f32 / options.height as f32;
    let azimuth = options.azimuth.unwrap_or_else(|| cache.view_azimuth());
    let follow = match options.camera {
        CameraMotion::Fixed | CameraMotion::Largest => None,
        CameraMotion::Follow => Some(follow_cameras(&framing, aspect, azimuth)),
        CameraMotion::Auto => spreads(&framing).then(|| follow_cameras(&framing, aspect, azimuth)),
    };
    let layout = &cache.layout;
    let dir = layout.preview_dir();
    std::fs::create_dir_all(&dir).map_err(|e| RenderError::io(&dir, e))?;
    if let Some(range) = options.frames {
        range
            .check(cache.frames.len())
            .map_err(|message| RenderError::Input {
                path: out.to_path_buf(),
                message,
            })?;
    }
    let frames: Vec<usize> = match (options.frame, options.frames) {
        (Some(k), _) => vec![k],
        (None, Some(range)) => range.frames().collect(),
        (None, None) => cache.frames.clone(),
    };
    // Frame k's camera and bounds (cache.frames and the framing's frames agree), or
    // `None` for the fixed camera's.
    let moving = |frame: usize| -> Option<(Camera, Bounds)> {
        let i = cache.frames.iter().position(|&f| f == frame)?;
        match &follow {
            Some(cameras) => cameras.get(i).copied(),
            None if options.camera == CameraMotion::Largest => {
                let piece = &framing.frames.get(i)?.largest;
                largest_piece_view(piece, framing.subject.pad, aspect, azimuth)
            }
            None => None,
        }
    };
    let view_of = |frame: usize| moving(frame).unwrap_or((view.camera, bounds));
    // Every frame of the sequence: it makes the contact sheet (and the movie).
    let sequence = options.frame.is_none() && options.frames.is_none();
    let mut jobs: Vec<Job> = frames
        .iter()
        .map(|&frame| {
            let (camera, bounds) = view_of(frame);
            Job {
                frame,
                camera,
                bounds,
                path: match options.frame {
                    Some(_) => layout.single_preview(frame),
                    None => layout.preview(frame),
                },
                thumbnail: sequence,
                overlay: options.overlay.then(|| {
                    sheet::overlay_text(
                        frame,
                        cache.frame_time(frame),
                        frame.saturating_sub(1) as f64 / cache.playback_fps(),
                    )
                }),
            }
        })
        .collect();
    let turntable_frame = options
        .frame
        .unwrap_or(cache.frames[cache.frames.len() - 1]);
    let subject = &framing.subject;
    for (i, camera) in Camera::turntable(subject, &bounds, aspect, azimuth, options.turntable)
        .into_iter()
        .enumerate()
    {
        jobs.push(Job {
            frame: turntable_frame,
            camera,
            bounds,
            path: layout.turntable(i + 1),
            thumbnail: false,
            overlay: None,
        });
    }
    let mut report = run_jobs(&cache, &jobs, options, &framing.ranges, ground, progress)?;
    if options.camera == CameraMotion::Largest {
        let fixed: Vec<String> = frames
            .iter()
            .filter(|&&f| moving(f).is_none())
            .map(usize::to_string)
            .collect();
        if !fixed.is_empty() {
            report.preview.warnings.push(format!(
                "--camera largest: frames {} have no particles to find a piece in; framed on the whole shot",
                fixed.join(", ")
            ));
        }
    }
    if sequence && report.thumbnails.len() > 1 {
        report.thumbnails.sort_by_key(|(frame, _)| *frame);
        let path = layout.contact_sheet();
        sheet::write_png(&path, &sheet::contact_sheet(&report.thumbnails))?;
        report.preview.files.push(path);
    }
    if options.movie {
        write_movies(&cache, options, &jobs, &mut report.preview)?;
    } else {
        // Frames rendered again without a movie: a movie of the frames they replaced
        // would no longer match them.
        let mut stale = Vec::new();
        if options.frame.is_none() {
            stale.extend([layout.movie(), layout.movie_mp4()]);
        }
        if options.frames.is_some() {
            // So is the contact sheet; `join` makes both again.
            stale.push(layout.contact_sheet());
        }
        if options.turntable > 0 {
            stale.push(layout.turntable_movie());
        }
        for path in stale {
            match std::fs::remove_file(&path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(RenderError::io(&path, e));
                }
                _ => {}
            }
        }
    }
    report.preview.seconds = start.elapsed().as_secs_f64();
    Ok(report.preview)
}

/// Makes `preview/contact_sheet.png` (and with `movie` the sequence's movies,
/// `preview/movie.png` and `movie.mp4` when ffmpeg is there) from the frames
/// `preview/NNNN.png` already rendered, by `--frames` ranges on a farm: the files a
/// render of every frame writes, as it makes them from the same images. Every frame of
/// the cache must be there; the missing ones are named.
pub fn join(out: &Path, movie: bool) -> Result<PreviewReport, RenderError> {
    let start = Instant::now();
    let cache = Cache::open(out)?;
    let layout = &cache.layout;
    let paths: Vec<PathBuf> = cache.frames.iter().map(|&k| layout.preview(k)).collect();
    let missing: Vec<usize> = cache
        .frames
        .iter()
        .zip(&paths)
        .filter(|(_, p)| !p.is_file())
        .map(|(&k, _)| k)
        .collect();
    if !missing.is_empty() {
        return Err(RenderError::Input {
            path: layout.preview_dir(),
            message: format!(
                "{} of the {} frames not rendered yet ({}); render them with `perifrac render \
                 {} --frames FIRST..LAST` before joining",
                missing.len(),
                cache.frames.len(),
                sheet::frame_list(&missing),
                out.display()
            ),
        });
    }
    let mut report = PreviewReport::default();
    let mut thumbnails = Vec::with_capacity(paths.len());
    for (&k, path) in cache.frames.iter().zip(&paths) {
        let image = image::open(path)
            .map_err(|e| RenderError::Input {
                path: path.clone(),
                message: format!("not a readable PNG ({e}); render frame {k} again"),
            })?
            .into_rgb8();
        let (w, h) = sheet::thumbnail_size(image.width(), image.height());
        thumbnails.push((k, image::imageops::thumbnail(&image, w, h)));
    }
    if thumbnails.len() > 1 {
        let path = layout.contact_sheet();
        sheet::write_png(&path, &sheet::contact_sheet(&thumbnails))?;
        report.files.push(path);
    }
    if movie {
        let fps = cache.playback_fps();
        movie::write_apng(&layout.movie(), &paths, fps)?;
        report.files.push(layout.movie());
        if movie::ffmpeg_available() {
            movie::write_mp4(&layout.movie_mp4(), &paths, fps)?;
            report.files.push(layout.movie_mp4());
        } else {
            report.mp4_skipped = true;
        }
    }
    report.seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

/// The movies of the rendered `jobs`: the sequence's frames (unless one frame was
/// asked for) and the turntable's views, each as an animated PNG at the playback rate;
/// the sequence also as an MP4 when ffmpeg is there.
fn write_movies(
    cache: &Cache,
    options: &PreviewOptions,
    jobs: &[Job],
    report: &mut PreviewReport,
) -> Result<(), RenderError> {
    let fps = cache.playback_fps();
    let layout = &cache.layout;
    let (sequence, turntable) = jobs.split_at(jobs.len() - options.turntable);
    if options.frame.is_none() && options.frames.is_none() && !sequence.is_empty() {
        let frames: Vec<PathBuf> = sequence.iter().map(|j| j.path.clone()).collect();
        movie::write_apng(&layout.movie(), &frames, fps)?;
        report.files.push(layout.movie());
        if movie::ffmpeg_available() {
            movie::write_mp4(&layout.movie_mp4(), &frames, fps)?;
            report.files.push(layout.movie_mp4());
        } else {
            report.mp4_skipped = true;
        }
    }
    if !turntable.is_empty() {
        let views: Vec<PathBuf> = turntable.iter().map(|j| j.path.clone()).collect();
        movie::write_apng(&layout.turntable_movie(), &views, fps)?;
        report.files.push(layout.turntable_movie());
    }
    Ok(())
}

/// The one view of a sequence's frames ([`Camera::fit`] on the robust subject of
/// [`Cache::sequence_framing`], from `options.azimuth` or [`Cache::view_azimuth`]), the
/// subject it frames, and the sequence's value ranges for `options.color_by`.
pub fn sequence_view(
    cache: &Cache,
    options: &PreviewOptions,
) -> Result<(View, Subject, Ranges), RenderError> {
    let framing = cache.sequence_framing(options.color_by)?;
    let view = fixed_view(cache, &framing, options);
    Ok((view, framing.subject, framing.ranges))
}

/// The fixed camera's view of `framing` (see [`sequence_view`]).
fn fixed_view(cache: &Cache, framing: &Framing, options: &PreviewOptions) -> View {
    let bounds = framing.bounds;
    let aspect = options.width as f32 / options.height as f32;
    let azimuth = options.azimuth.unwrap_or_else(|| cache.view_azimuth());
    let ground = cache.ground().unwrap_or(if bounds.is_empty() {
        0.0
    } else {
        bounds.min[1]
    });
    View {
        camera: Camera::fit(&framing.subject, &bounds, aspect, azimuth),
        bounds,
        ground,
        key_strength: 1.0,
    }
}

struct Collected {
    preview: PreviewReport,
    thumbnails: Vec<(usize, RgbImage)>,
}

fn run_jobs(
    cache: &Cache,
    jobs: &[Job],
    options: &PreviewOptions,
    ranges: &Ranges,
    ground: f32,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Collected, RenderError> {
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let collected = Mutex::new(Collected {
        preview: PreviewReport::default(),
        thumbnails: Vec::new(),
    });
    let workers = options.workers.clamp(1, jobs.len().max(1));
    let (thumb_width, thumb_height) = sheet::thumbnail_size(options.width, options.height);
    // A failing worker returns the index of the job that failed, so that the error
    // reported is the first failing job in order, whichever thread met it first.
    let worker = || -> Result<(), (usize, RenderError)> {
        let mut renderer = Renderer::new(options.width, options.height).map_err(|e| (0, e))?;
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(job) = jobs.get(i) else {
                return Ok(());
            };
            let geometry = cache
                .geometry(job.frame, options.color_by, ranges)
                .map_err(|e| (i, e))?;
            let view = View {
                camera: job.camera,
                bounds: job.bounds,
                ground,
                key_strength: 1.0,
            };
            let mut rendered = renderer.render(&geometry, &view).map_err(|e| (i, e))?;
            if let Some(text) = &job.overlay {
                sheet::draw_overlay(&mut rendered.image, text);
            }
            let t = Instant::now();
            sheet::write_png(&job.path, &rendered.image).map_err(|e| (i, e))?;
            let encode = t.elapsed().as_secs_f64();
            let thumbnail = job
                .thumbnail
                .then(|| image::imageops::thumbnail(&rendered.image, thumb_width, thumb_height));
            {
                let mut c = collected.lock().unwrap_or_else(|e| e.into_inner());
                let p = &mut c.preview;
                p.backend = Some(renderer.backend());
                p.images += 1;
                p.encode += encode;
                let t = rendered.times;
                p.passes.upload += t.upload;
                p.passes.shadow += t.shadow;
                p.passes.main += t.main;
                p.passes.readback += t.readback;
                p.files.push(job.path.clone());
                if rendered.in_view == 0 {
                    p.warnings.push(format!(
                        "{}: frame {} has nothing in view (everything fell out of the camera's view, or the frame is empty); rendered the ground only",
                        job.path.display(),
                        job.frame
                    ));
                }
                if let Some(thumb) = thumbnail {
                    c.thumbnails.push((job.frame, thumb));
                }
            }
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, jobs.len());
        }
    };
    let results: Vec<Result<(), (usize, RenderError)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers).map(|_| s.spawn(worker)).collect();
        handles
            .into_iter()
            .map(|h| {
                h.join().unwrap_or_else(|_| {
                    Err((
                        0,
                        RenderError::Gl("a preview worker thread panicked".into()),
                    ))
                })
            })
            .collect()
    });
    if let Some((_, e)) = results
        .into_iter()
        .filter_map(Result::err)
        .min_by_key(|(i, _)| *i)
    {
        return Err(e);
    }
    let mut c = collected.into_inner().unwrap_or_else(|e| e.into_inner());
    c.preview.files.sort();
    c.preview.warnings.sort();
    Ok(c)
}
