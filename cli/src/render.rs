//! `perifrac render`, and the previews at the end of `run` and `demo`.

use std::path::Path;
#[cfg(feature = "gl")]
use std::time::Duration;

#[cfg(feature = "gl")]
use indicatif::{ProgressBar, ProgressStyle};
#[cfg(feature = "gl")]
use perifrac_cache::Layout;

use crate::args::RenderConfig;
use crate::commands::Failure;
#[cfg(feature = "gl")]
use crate::commands::{EXIT_FAILED, EXIT_INPUT};

#[cfg(feature = "gl")]
fn progress_bar(quiet: bool, message: &str) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} image {pos}/{len} {msg} ETA {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(message.to_string());
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// Worker threads for previews: one GL context each.
#[cfg(feature = "gl")]
fn workers(threads: Option<usize>) -> usize {
    threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}

#[cfg(feature = "gl")]
fn color_by(arg: Option<crate::args::ColorByArg>) -> perifrac_render::cache::ColorBy {
    use crate::args::ColorByArg;
    use perifrac_render::cache::ColorBy;
    match arg {
        None | Some(ColorByArg::Material) => ColorBy::Material,
        Some(ColorByArg::Damage) => ColorBy::Damage,
        Some(ColorByArg::Fragment) => ColorBy::Fragment,
        Some(ColorByArg::Plastic) => ColorBy::Plastic,
        Some(ColorByArg::Temperature) => ColorBy::Temperature,
        Some(ColorByArg::Quantity) => ColorBy::Quantity,
    }
}

/// Renders previews of `out`, printing warnings and a summary; `Ok(seconds)`.
#[cfg(feature = "gl")]
pub fn previews(
    out: &Path,
    options: &perifrac_render::preview::PreviewOptions,
    quiet: bool,
) -> Result<f64, perifrac_render::RenderError> {
    let bar = progress_bar(quiet, "rendering previews");
    let report = perifrac_render::preview::render_cache(out, options, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let report = report?;
    // The manifest records the images, so `perifrac verify` checks them too.
    let layout = Layout::new(out);
    match options.frames {
        Some(range) => layout.record_frame_outputs(&[layout.preview_dir()], range)?,
        None => layout.record_outputs(&[layout.preview_dir()])?,
    }
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    if report.mp4_skipped && !quiet {
        eprintln!(
            "note: movie written as {} (animated PNG); no ffmpeg on the PATH, so no MP4",
            layout.movie().display()
        );
    }
    if !quiet {
        let n = report.images.max(1) as f64;
        let p = report.passes;
        eprintln!(
            "previews: {} images at {}×{} in {:.1} s with {} ({} worker{}); per image: upload {:.0} ms, shadow {:.0} ms, main {:.0} ms, resolve+readback {:.0} ms, PNG {:.0} ms; in {}",
            report.images,
            options.width,
            options.height,
            report.seconds,
            report
                .backend
                .map_or_else(|| "no backend".to_string(), |b| b.to_string()),
            options.workers,
            if options.workers == 1 { "" } else { "s" },
            1e3 * p.upload / n,
            1e3 * p.shadow / n,
            1e3 * p.main / n,
            1e3 * p.readback / n,
            1e3 * report.encode / n,
            layout.preview_dir().display()
        );
    }
    Ok(report.seconds)
}

/// `perifrac render --join`: the contact sheet (and movies) from the frames ranges
/// rendered, recorded in the manifest.
#[cfg(feature = "gl")]
fn join(out: &Path, movie: bool, quiet: bool) -> Result<(), perifrac_render::RenderError> {
    let report = perifrac_render::preview::join(out, movie)?;
    let layout = Layout::new(out);
    layout.record_outputs(&[layout.preview_dir()])?;
    if report.mp4_skipped && !quiet {
        eprintln!(
            "note: movie written as {} (animated PNG); no ffmpeg on the PATH, so no MP4",
            layout.movie().display()
        );
    }
    if !quiet {
        let files: Vec<String> = report
            .files
            .iter()
            .map(|f| f.display().to_string())
            .collect();
        eprintln!(
            "joined the frames in {:.1} s: {}",
            report.seconds,
            files.join(", ")
        );
    }
    Ok(())
}

/// `perifrac render`.
pub fn command(config: &RenderConfig, quiet: bool) -> Result<(), Failure> {
    #[cfg(feature = "gl")]
    {
        use perifrac_render::RenderError;
        use perifrac_render::preview::CameraMotion;
        let options = perifrac_render::preview::PreviewOptions {
            width: config.size.0,
            height: config.size.1,
            color_by: color_by(config.color_by),
            frame: config.frame,
            frames: crate::commands::frames_within(&config.out, config.frames)?,
            turntable: config.turntable,
            workers: workers(config.threads),
            azimuth: config.azimuth.map(f32::to_radians),
            movie: config.movie,
            overlay: config.overlay,
            camera: match config.camera {
                crate::args::CameraArg::Auto => CameraMotion::Auto,
                crate::args::CameraArg::Fixed => CameraMotion::Fixed,
                crate::args::CameraArg::Follow => CameraMotion::Follow,
                crate::args::CameraArg::Largest => CameraMotion::Largest,
            },
        };
        crate::verify::warn(&config.out)?;
        let result = if config.join {
            join(&config.out, config.movie, quiet)
        } else {
            previews(&config.out, &options, quiet).map(|_| ())
        };
        result.map_err(|e| {
            let code = match &e {
                RenderError::Input { .. } | RenderError::Size(_) => EXIT_INPUT,
                // A malformed scene.toml or particle frame is bad input (as in
                // `surface`); I/O is not.
                RenderError::Cache(c) if c.is_bad_input() => EXIT_INPUT,
                _ => EXIT_FAILED,
            };
            Failure {
                error: e.into(),
                code,
            }
        })?;
        Ok(())
    }
    #[cfg(not(feature = "gl"))]
    {
        let _ = (config, quiet);
        Err(Failure {
            error: anyhow::anyhow!(
                "this perifrac was built without the `gl` feature; rebuild with default features to render previews"
            ),
            code: 1,
        })
    }
}

/// The previews at the end of `run` and `demo` (`[output] preview = true`): a failure
/// (no GL library, for example) is a warning, the simulation's outputs stand.
/// Returns the seconds spent, if it rendered.
pub fn stage(out: &Path, threads: Option<usize>, quiet: bool) -> Option<f64> {
    #[cfg(feature = "gl")]
    {
        let options = perifrac_render::preview::PreviewOptions {
            workers: workers(threads),
            movie: true,
            ..Default::default()
        };
        match previews(out, &options, quiet) {
            Ok(seconds) => Some(seconds),
            Err(e) => {
                eprintln!(
                    "warning: previews skipped: {e}; the simulation's outputs are complete (render them later with `perifrac render {}`)",
                    out.display()
                );
                None
            }
        }
    }
    #[cfg(not(feature = "gl"))]
    {
        if !quiet {
            eprintln!(
                "note: no previews of {}: this perifrac was built without the `gl` feature",
                out.display()
            );
        }
        let _ = threads;
        None
    }
}
