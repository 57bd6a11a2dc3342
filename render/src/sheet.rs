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

/// Width in pixels of `text` drawn at `scale`.
pub fn text_width(text: &str, scale: u32) -> u32 {
    (text.chars().count() as u32 * 6).saturating_sub(1) * scale
}

/// Draws the digits of `text` (other characters leave a gap) with the top-left corner
/// at (`x`, `y`), each font pixel `scale`² image pixels; clipped to the image.
pub fn draw_text(image: &mut RgbImage, x: u32, y: u32, text: &str, scale: u32, color: [u8; 3]) {
    for (i, ch) in text.chars().enumerate() {
        let Some(glyph) = ch.to_digit(10).map(|d| DIGITS[d as usize]) else {
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
