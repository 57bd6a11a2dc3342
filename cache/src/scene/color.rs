//! `color` of a `[materials.NAME]` table: how previews draw the material's bodies
//! (meshes, VDB fragment meshes, sheets and particles), as `"#RRGGBB"` or an sRGB
//! triple `[r, g, b]` in [0, 1]. Materials without one take [`PALETTE`] colours in
//! the order of the materials table (sorted by name).

use serde::{Deserialize, Serialize};

/// A material's display colour, as written in the scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ColorSpec {
    /// `"#RRGGBB"`, hexadecimal sRGB.
    Hex(String),
    /// `[r, g, b]`, sRGB components in [0, 1].
    Rgb([f64; 3]),
}

impl ColorSpec {
    /// The sRGB components in [0, 1], or what is wrong with the value.
    pub fn srgb(&self) -> Result<[f32; 3], String> {
        match self {
            ColorSpec::Hex(text) => {
                let digits = text
                    .strip_prefix('#')
                    .filter(|d| d.len() == 6 && d.chars().all(|c| c.is_ascii_hexdigit()))
                    .ok_or_else(|| {
                        format!(
                            "'{text}' is not a colour: write \"#RRGGBB\" (six hexadecimal digits, \
                             e.g. \"#C8553D\") or an sRGB triple [r, g, b] in [0, 1]"
                        )
                    })?;
                Ok(std::array::from_fn(|k| {
                    let byte = u8::from_str_radix(&digits[2 * k..2 * k + 2], 16).unwrap_or(0);
                    byte as f32 / 255.0
                }))
            }
            ColorSpec::Rgb(rgb) => {
                if rgb.iter().all(|c| c.is_finite() && (0.0..=1.0).contains(c)) {
                    Ok(rgb.map(|c| c as f32))
                } else {
                    Err(format!(
                        "the sRGB components must be in [0, 1], got {rgb:?} (for 0–255 values \
                         divide by 255, or write \"#RRGGBB\")"
                    ))
                }
            }
        }
    }
}

/// The default colours (sRGB) of materials without `color`, in the order of the
/// materials table: muted, well apart in hue, none near the crack faces' ochre or the
/// colliders' steel.
pub const PALETTE: [[f32; 3]; 8] = [
    [0.78, 0.79, 0.81], // light grey (the one material of most scenes, as before)
    [0.30, 0.55, 0.80], // blue
    [0.45, 0.70, 0.35], // green
    [0.80, 0.35, 0.40], // red
    [0.60, 0.45, 0.75], // violet
    [0.35, 0.70, 0.70], // teal
    [0.85, 0.80, 0.45], // straw
    [0.55, 0.40, 0.30], // brown
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_and_triples_parse_and_bad_ones_say_how_to_write_them() {
        let hex = ColorSpec::Hex("#FF8000".into()).srgb().unwrap();
        assert_eq!(hex, [1.0, 128.0 / 255.0, 0.0]);
        assert_eq!(
            ColorSpec::Rgb([0.25, 0.5, 1.0]).srgb().unwrap(),
            [0.25, 0.5, 1.0]
        );
        for bad in ["FF8000", "#FF80", "#GG8000", "#FF80000"] {
            let err = ColorSpec::Hex(bad.into()).srgb().unwrap_err();
            assert!(err.contains("#RRGGBB"), "{err}");
        }
        let err = ColorSpec::Rgb([200.0, 0.0, 0.0]).srgb().unwrap_err();
        assert!(err.contains("[0, 1]") && err.contains("255"), "{err}");
    }
}
