//! `bench/accuracy.png`: error against wall time on log axes, one panel per scene,
//! one curve per method (plotters' bitmap backend; text in the bundled DejaVu Sans).

use std::path::Path;

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use crate::accuracy::Point;

/// DejaVu Sans (Bitstream Vera licence, `assets/fonts/DejaVuSans-LICENSE.txt`).
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// Draws the plot of `points` into a PNG at `path`.
pub fn accuracy_png(points: &[Point], path: &Path) -> anyhow::Result<()> {
    register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| anyhow::anyhow!("the bundled font does not load"))?;
    let mut scenes: Vec<&str> = points.iter().map(|p| p.scene.as_str()).collect();
    scenes.dedup();
    let mut methods: Vec<&str> = points.iter().map(|p| p.method.as_str()).collect();
    methods.sort();
    methods.dedup();
    let cols = scenes.len().clamp(1, 2);
    let rows = scenes.len().div_ceil(cols).max(1);
    let (w, h) = (560 * cols as u32, 420 * rows as u32);
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(draw)?;
        let panels = root.split_evenly((rows, cols));
        for (panel, scene) in panels.iter().zip(&scenes) {
            let mine: Vec<&Point> = points.iter().filter(|p| p.scene == *scene).collect();
            let positive = |v: f64| v.is_finite() && v > 0.0;
            let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
            for p in mine.iter().filter(|p| positive(p.wall) && positive(p.mean)) {
                t0 = t0.min(p.wall);
                t1 = t1.max(p.wall);
                e0 = e0.min(p.mean);
                e1 = e1.max(p.mean);
            }
            if t1 <= 0.0 {
                continue;
            }
            let mut chart = ChartBuilder::on(panel)
                .caption(*scene, ("sans-serif", 20))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d(
                    (t0 / 1.5..t1 * 1.5).log_scale(),
                    (e0 / 2.0..e1 * 2.0).log_scale(),
                )
                .map_err(draw)?;
            chart
                .configure_mesh()
                .x_desc("wall time (s)")
                .y_desc("error (mean, / bbox diagonal)")
                .x_label_formatter(&|v| format!("{v:.2}"))
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(draw)?;
            for (m, method) in methods.iter().enumerate() {
                let colour = COLOURS[m % COLOURS.len()];
                let mut series: Vec<(f64, f64)> = mine
                    .iter()
                    .filter(|p| p.method == *method && positive(p.wall) && positive(p.mean))
                    .map(|p| (p.wall, p.mean))
                    .collect();
                if series.is_empty() {
                    continue;
                }
                series.sort_by(|a, b| a.0.total_cmp(&b.0));
                chart
                    .draw_series(LineSeries::new(series.clone(), colour.stroke_width(2)))
                    .map_err(draw)?
                    .label(*method)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                    });
                chart
                    .draw_series(
                        series
                            .iter()
                            .map(|&(x, y)| Circle::new((x, y), 4, colour.filled())),
                    )
                    .map_err(draw)?;
            }
            chart
                .configure_series_labels()
                .label_font(("sans-serif", 13))
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(draw)?;
        }
        root.present().map_err(draw)?;
    }
    let file =
        std::fs::File::create(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder
        .write_header()
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    writer
        .write_image_data(&buffer)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(())
}

fn draw<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("drawing the accuracy plot: {e:?}")
}
