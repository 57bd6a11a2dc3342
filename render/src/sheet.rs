//! Image files: PNG encoding (fast compression, written atomically), the contact sheet
//! (a grid of frames with their numbers) and the tiny built-in bitmap font that draws
//! the numbers.

use std::path::Path;

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{ImageEncoder, Rgb, RgbImage};

use crate::RenderError;

/// Encodes `image` as PNG (fast compression) and writes it atomically.
pub fn write_png(path: &Path, image: &RgbImage) -> Result<(), RenderError> {
    let mut bytes = Vec::with_capacity(image.as_raw().len() / 2);
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Fast, FilterType::Sub)
        .write_image(
            image.as_raw(),
            image.width(),
            image.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| RenderError::Input {
            path: path.to_path_buf(),
            message: format!("PNG encoding failed: {e}"),
        })?;
    Ok(perifrac_cache::write_atomic(path, &bytes)?)
}

/// The size of a frame's thumbnail on the contact sheet, for a frame of `width` ×
/// `height` pixels: a quarter of its width, at most 320 pixels, the same aspect.
pub fn thumbnail_size(width: u32, height: u32) -> (u32, u32) {
    let w = (width / 4).clamp(1, 320);
    (w, (height * w / width.max(1)).max(1))
}

/// Frame numbers as runs, `3..5, 9`, at most a dozen of them shown.
pub fn frame_list(frames: &[usize]) -> String {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for &k in frames {
        match runs.last_mut() {
            Some(run) if run.1 + 1 == k => run.1 = k,
            _ => runs.push((k, k)),
        }
    }
    let shown: Vec<String> = runs
        .iter()
        .take(12)
        .map(|&(a, b)| {
            if a == b {
                a.to_string()
            } else {
                format!("{a}..{b}")
            }
        })
        .collect();
    let more = if runs.len() > 12 { ", …" } else { "" };
    format!("{}{more}", shown.join(", "))
}

/// 5×7 glyphs of the digits 0–9, one byte a row, bit 4 leftmost.
const DIGITS: [[u8; 7]; 10] = [
    [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
    [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
    [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
    [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
    [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
    [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
    [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
    [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
    [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
    [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
];

/// 5×7 glyphs of the other characters the overlays need (the letters of `FRAME`,
/// `SIM`, `MS`, `PLAY`, and the decimal point).
const OTHERS: [(char, [u8; 7]); 11] = [
    ('A', [0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11]),
    ('E', [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F]),
    ('F', [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10]),
    ('I', [0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E]),
    ('L', [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F]),
    ('M', [0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11]),
    ('P', [0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10]),
    ('R', [0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11]),
    ('S', [0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E]),
    ('Y', [0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04]),
    ('.', [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C]),
];

/// The glyph of `ch`, if the font has it.
fn glyph(ch: char) -> Option<[u8; 7]> {
    match ch.to_digit(10) {
        Some(d) => Some(DIGITS[d as usize]),
        None => OTHERS.iter().find(|(c, _)| *c == ch).map(|(_, g)| *g),
    }
}

/// Width in pixels of `text` drawn at `scale`.
pub fn text_width(text: &str, scale: u32) -> u32 {
    (text.chars().count() as u32 * 6).saturating_sub(1) * scale
}

/// Draws the digits, the decimal points and the letters of `FRAME`, `SIM`, `MS` and
/// `PLAY` in `text` (other characters leave a gap) with the top-left corner
/// at (`x`, `y`), each font pixel `scale`² image pixels; clipped to the image.
pub fn draw_text(image: &mut RgbImage, x: u32, y: u32, text: &str, scale: u32, color: [u8; 3]) {
    for (i, ch) in text.chars().enumerate() {
        let Some(glyph) = glyph(ch) else {
            continue;
        };
        let left = x + i as u32 * 6 * scale;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..5u32 {
                if bits & (0x10 >> col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (px, py) = (left + col * scale + dx, y + row as u32 * scale + dy);
                        if px < image.width() && py < image.height() {
                            image.put_pixel(px, py, Rgb(color));
                        }
                    }
                }
            }
        }
    }
}

/// The review overlay of a frame (`--overlay`): its number, its simulation time and
/// its playback time, e.g. `FRAME 12  SIM 1.467 MS  PLAY 0.458 S`. Simulation times
/// under a second are in milliseconds.
pub fn overlay_text(frame: usize, sim_time: f64, playback_time: f64) -> String {
    let sim = if sim_time.abs() < 1.0 {
        format!("{:.3} MS", 1e3 * sim_time)
    } else {
        format!("{sim_time:.3} S")
    };
    format!("FRAME {frame}  SIM {sim}  PLAY {playback_time:.3} S")
}

/// Draws `text` in the image's bottom-left corner on a dark band, at a size that
/// reads at the image's height (a font pixel per 270 image rows, at least one).
pub fn draw_overlay(image: &mut RgbImage, text: &str) {
    let scale = (image.height() / 270).max(1);
    let (w, h) = (text_width(text, scale) + 4 * scale, 11 * scale);
    let y0 = image.height().saturating_sub(h);
    for y in y0..image.height() {
        for x in 0..w.min(image.width()) {
            image.put_pixel(x, y, Rgb([20, 20, 22]));
        }
    }
    draw_text(
        image,
        2 * scale,
        y0 + 2 * scale,
        text,
        scale,
        [255, 255, 255],
    );
}

/// A grid of `frames` (number, thumbnail), left to right and top to bottom, each
/// labelled with its number in the top-left corner. Thumbnails share the first one's
/// size.
pub fn contact_sheet(frames: &[(usize, RgbImage)]) -> RgbImage {
    let Some((_, first)) = frames.first() else {
        return RgbImage::new(1, 1);
    };
    let (tw, th) = first.dimensions();
    let n = frames.len() as u32;
    let columns = ((n as f64).sqrt().ceil() as u32).clamp(1, 8);
    let rows = n.div_ceil(columns);
    let gap = 4;
    let mut sheet = RgbImage::from_pixel(
        columns * (tw + gap) + gap,
        rows * (th + gap) + gap,
        Rgb([32, 33, 36]),
    );
    let scale = (th / 60).max(1);
    for (i, (number, thumb)) in frames.iter().enumerate() {
        let (c, r) = (i as u32 % columns, i as u32 / columns);
        let (x0, y0) = (gap + c * (tw + gap), gap + r * (th + gap));
        image::imageops::replace(&mut sheet, thumb, x0 as i64, y0 as i64);
        let label = format!("{number:04}");
        let (w, h) = (text_width(&label, scale) + 4 * scale, 11 * scale);
        for y in y0..(y0 + h).min(y0 + th) {
            for x in x0..(x0 + w).min(x0 + tw) {
                sheet.put_pixel(x, y, Rgb([20, 20, 22]));
            }
        }
        draw_text(
            &mut sheet,
            x0 + 2 * scale,
            y0 + 2 * scale,
            &label,
            scale,
            [255, 255, 255],
        );
    }
    sheet
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digits_are_drawn_and_distinct() {
        let mut seen = std::collections::BTreeSet::new();
        for d in 0..10 {
            let mut img = RgbImage::new(5, 7);
            draw_text(&mut img, 0, 0, &d.to_string(), 1, [255, 255, 255]);
            let lit: Vec<bool> = img.pixels().map(|p| p[0] > 0).collect();
            assert!(lit.iter().any(|&b| b));
            assert!(seen.insert(lit), "digit {d} looks like another");
        }
    }

    #[test]
    fn overlay_characters_are_drawn_and_distinct() {
        let text = overlay_text(12, 0.0014666, 0.4583);
        assert_eq!(text, "FRAME 12  SIM 1.467 MS  PLAY 0.458 S");
        assert_eq!(
            overlay_text(3, 2.5, 2.0),
            "FRAME 3  SIM 2.500 S  PLAY 2.000 S"
        );
        let mut seen = std::collections::BTreeSet::new();
        for ch in "0123456789AEFILMPRSY.".chars() {
            let mut img = RgbImage::new(5, 7);
            draw_text(&mut img, 0, 0, &ch.to_string(), 1, [255, 255, 255]);
            let lit: Vec<bool> = img.pixels().map(|p| p[0] > 0).collect();
            assert!(lit.iter().any(|&b| b), "{ch} draws nothing");
            assert!(seen.insert(lit), "{ch} looks like another");
        }
        // The band sits in the bottom-left corner and the top row is untouched.
        let mut img = RgbImage::from_pixel(400, 100, Rgb([200, 200, 200]));
        draw_overlay(&mut img, &text);
        assert_eq!(img.get_pixel(0, 99).0, [20, 20, 22]);
        assert_eq!(img.get_pixel(0, 0).0, [200, 200, 200]);
        assert!((89..100).any(|y| (0..200).any(|x| img.get_pixel(x, y).0 == [255; 3])));
    }

    #[test]
    fn sheet_has_a_cell_a_frame() {
        let thumbs: Vec<(usize, RgbImage)> = (1..=5)
            .map(|i| (i, RgbImage::from_pixel(40, 30, Rgb([200, 0, 0]))))
            .collect();
        let sheet = contact_sheet(&thumbs);
        assert_eq!(sheet.dimensions(), (3 * 44 + 4, 2 * 34 + 4));
        // The label's white digits sit in the first cell.
        assert!((4..15).any(|y| (4..30).any(|x| sheet.get_pixel(x, y).0 == [255, 255, 255])));
    }
}
