//! Movies of rendered previews: an animated PNG (APNG, through the `png` crate, pure
//! Rust) and, when `ffmpeg` is on the `PATH`, an H.264 MP4 of the same frames. Frames
//! are read back from the PNG files the preview just wrote, one at a time, so memory
//! stays one frame's worth whatever the length.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use image::RgbImage;

use crate::RenderError;

/// The frame delay of `fps` frames a second as the APNG's fraction of seconds
/// (numerator, denominator), each at most 65,535: exactly 1/fps for a whole rate,
/// else to within 0.01 %.
pub fn frame_delay(fps: f64) -> (u16, u16) {
    if fps.fract() == 0.0 && (1.0..=65535.0).contains(&fps) {
        return (1, fps as u16);
    }
    let fps = fps.clamp(1e-3, 65535.0);
    // The largest numerator that keeps the denominator (numerator × fps) in range.
    let numerator = (65535.0 / fps).floor().clamp(1.0, 65535.0);
    (
        numerator as u16,
        (numerator * fps).round().clamp(1.0, 65535.0) as u16,
    )
}

fn read_frame(path: &Path) -> Result<RgbImage, RenderError> {
    Ok(image::open(path)
        .map_err(|e| RenderError::Input {
            path: path.to_path_buf(),
            message: format!("cannot read the rendered frame back for the movie: {e}"),
        })?
        .to_rgb8())
}

/// Writes the PNG images `frames` (all one size, in order) as an animated PNG at
/// `fps` frames a second, looping, to `out` (atomically).
pub fn write_apng(out: &Path, frames: &[PathBuf], fps: f64) -> Result<(), RenderError> {
    let Some(first) = frames.first() else {
        return Err(RenderError::Input {
            path: out.to_path_buf(),
            message: "no frames to make a movie of".into(),
        });
    };
    let first = read_frame(first)?;
    let (width, height) = first.dimensions();
    let failed = |e: png::EncodingError| RenderError::Input {
        path: out.to_path_buf(),
        message: format!("APNG encoding failed: {e}"),
    };
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        encoder
            .set_animated(frames.len() as u32, 0)
            .map_err(failed)?;
        let (numerator, denominator) = frame_delay(fps);
        encoder
            .set_frame_delay(numerator, denominator)
            .map_err(failed)?;
        let mut writer = encoder.write_header().map_err(failed)?;
        writer.write_image_data(first.as_raw()).map_err(failed)?;
        for path in &frames[1..] {
            let image = read_frame(path)?;
            if image.dimensions() != (width, height) {
                return Err(RenderError::Input {
                    path: path.clone(),
                    message: format!(
                        "{}×{} pixels where the movie's first frame has {width}×{height}",
                        image.width(),
                        image.height()
                    ),
                });
            }
            writer.write_image_data(image.as_raw()).map_err(failed)?;
        }
        writer.finish().map_err(failed)?;
    }
    Ok(perifrac_cache::write_atomic(out, &bytes)?)
}

/// Whether an `ffmpeg` runs from the `PATH`.
pub fn ffmpeg_available() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Writes the PNG images `frames` as an H.264 MP4 (yuv420p, padded to even sizes) at
/// `fps` to `out`, through `ffmpeg` reading raw frames on its standard input; written
/// to a temporary name and renamed into place.
pub fn write_mp4(out: &Path, frames: &[PathBuf], fps: f64) -> Result<(), RenderError> {
    let Some(first) = frames.first() else {
        return Err(RenderError::Input {
            path: out.to_path_buf(),
            message: "no frames to make a movie of".into(),
        });
    };
    let (width, height) = read_frame(first)?.dimensions();
    let partial = out.with_extension("partial.mp4");
    let mut child = Command::new("ffmpeg")
        .args([
            "-y",
            "-loglevel",
            "error",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgb24",
        ])
        .args(["-s", &format!("{width}x{height}"), "-r", &format!("{fps}")])
        .args(["-i", "-", "-c:v", "libx264", "-pix_fmt", "yuv420p"])
        .args([
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-movflags",
            "+faststart",
        ])
        .arg(&partial)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| RenderError::io(Path::new("ffmpeg"), e))?;
    let fed = (|| -> Result<(), RenderError> {
        let mut stdin = child.stdin.take().ok_or_else(|| RenderError::Io {
            path: PathBuf::from("ffmpeg"),
            error: std::io::Error::other("no standard input"),
        })?;
        for path in frames {
            let image = read_frame(path)?;
            if image.dimensions() != (width, height) {
                return Err(RenderError::Input {
                    path: path.clone(),
                    message: "frames of different sizes cannot make one movie".into(),
                });
            }
            stdin
                .write_all(image.as_raw())
                .map_err(|e| RenderError::io(Path::new("ffmpeg"), e))?;
        }
        Ok(())
    })();
    let output = child
        .wait_with_output()
        .map_err(|e| RenderError::io(Path::new("ffmpeg"), e))?;
    if let Err(e) = fed {
        let _ = std::fs::remove_file(&partial);
        return Err(e);
    }
    if !output.status.success() {
        let _ = std::fs::remove_file(&partial);
        return Err(RenderError::Input {
            path: out.to_path_buf(),
            message: format!(
                "ffmpeg failed ({}): {}",
                output.status,
                String::from_utf8_lossy(&output.stderr).trim()
            ),
        });
    }
    std::fs::rename(&partial, out).map_err(|e| RenderError::io(out, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_delays_are_exact_for_whole_rates_and_close_otherwise() {
        assert_eq!(frame_delay(24.0), (1, 24));
        assert_eq!(frame_delay(7500.0), (1, 7500));
        for fps in [29.97, 23.976, 0.5, 1e5] {
            let (n, d) = frame_delay(fps);
            let delay = n as f64 / d as f64;
            let want = 1.0 / fps.min(65535.0);
            assert!((delay / want - 1.0).abs() <= 1e-4, "{fps}: {n}/{d}");
        }
    }

    #[test]
    fn an_apng_decodes_back_frame_by_frame() {
        let dir = tempfile::tempdir().unwrap();
        let frames: Vec<PathBuf> = (0..3u8)
            .map(|k| {
                let path = dir.path().join(format!("{k}.png"));
                let image = RgbImage::from_pixel(5, 3, image::Rgb([k * 100, 7, 9]));
                crate::sheet::write_png(&path, &image).unwrap();
                path
            })
            .collect();
        let out = dir.path().join("movie.png");
        write_apng(&out, &frames, 30.0).unwrap();
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let control = reader.info().animation_control.expect("animated");
        assert_eq!((control.num_frames, control.num_plays), (3, 0));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        for k in 0..3u8 {
            let info = reader.next_frame(&mut buf).unwrap();
            assert_eq!((info.width, info.height), (5, 3));
            assert_eq!(&buf[..3], &[k * 100, 7, 9]);
            let fc = reader.info().frame_control.expect("a frame control");
            assert_eq!((fc.delay_num, fc.delay_den), (1, 30));
        }
        // A frame of another size is named.
        let odd = dir.path().join("odd.png");
        crate::sheet::write_png(&odd, &RgbImage::new(4, 4)).unwrap();
        let err = write_apng(&out, &[frames[0].clone(), odd], 30.0).unwrap_err();
        assert!(err.to_string().contains("odd.png"), "{err}");
    }
}
