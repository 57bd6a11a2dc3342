//! `perifrac bench render`: warm per-pass render timings of a 200k-triangle mesh and of
//! 3×10^5 particles at 1280×720, and the demo's preview time against its simulation.

use std::path::Path;

use crate::commands::Failure;

/// Runs the render benchmark and writes `OUT/render.md`.
#[cfg(feature = "gl")]
pub fn run(
    size: (u32, u32),
    triangles: usize,
    particles: usize,
    frames: usize,
    demo: bool,
    out: &Path,
    quiet: bool,
) -> Result<(), Failure> {
    use std::fmt::Write as _;
    use std::time::Instant;

    use perifrac_render::camera::{AZIMUTH, Camera};
    use perifrac_render::gl::{PassTimes, Renderer, View};

    let t = Instant::now();
    let mut renderer = Renderer::new(size.0, size.1).map_err(anyhow::Error::from)?;
    let setup = t.elapsed().as_secs_f64();
    let mut table = String::new();
    let _ = writeln!(
        table,
        "| scene | primitives | upload | shadow | main (MSAA 4×) | resolve + readback | frame (warm) | PNG encode |"
    );
    let _ = writeln!(table, "|---|---|---|---|---|---|---|---|");
    for (name, geometry, primitives) in [
        (
            "mesh",
            bumpy_sphere(triangles),
            format!("{triangles} triangles"),
        ),
        (
            "particles",
            particle_block(particles),
            format!("{particles} particles"),
        ),
    ] {
        let bounds = geometry.bounds();
        let view = View {
            camera: Camera::framing(&bounds, size.0 as f32 / size.1 as f32, AZIMUTH),
            bounds,
            ground: 0.0,
            key_strength: 1.0,
        };
        renderer
            .render(&geometry, &view)
            .map_err(anyhow::Error::from)?;
        let mut sum = PassTimes::default();
        let mut encode = 0.0;
        let tmp = out.join(format!("render-{name}.png"));
        std::fs::create_dir_all(out)
            .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", out.display())))?;
        for _ in 0..frames {
            let r = renderer
                .render(&geometry, &view)
                .map_err(anyhow::Error::from)?;
            sum.upload += r.times.upload;
            sum.shadow += r.times.shadow;
            sum.main += r.times.main;
            sum.readback += r.times.readback;
            let t = Instant::now();
            perifrac_render::sheet::write_png(&tmp, &r.image).map_err(anyhow::Error::from)?;
            encode += t.elapsed().as_secs_f64();
        }
        let n = frames as f64;
        let ms = |s: f64| format!("{:.0} ms", 1e3 * s / n);
        let _ = writeln!(
            table,
            "| {name} | {primitives} | {} | {} | {} | {} | **{}** | {} |",
            ms(sum.upload),
            ms(sum.shadow),
            ms(sum.main),
            ms(sum.readback),
            ms(sum.total()),
            ms(encode)
        );
        if !quiet {
            eprintln!(
                "{name}: {:.3} s a frame (warm), PNG {:.3} s",
                sum.total() / n,
                encode / n
            );
        }
    }
    let mut report = format!(
        "# Render\n\n{}×{}, {} on `{}`, {frames} timed frames after one warm-up (context creation \
         and shader compilation excluded: {setup:.2} s once a thread). Each pass ends with glFinish.\n\n{table}",
        size.0,
        size.1,
        renderer.backend(),
        renderer.gl_renderer()
    );
    drop(renderer);
    if demo {
        let scene = perifrac_cache::scene::Scene::parse(
            crate::commands::DEMO_SCENE,
            Path::new("demo.toml (built in)"),
            Path::new("."),
        )?;
        let dir = out.join("demo");
        let lifecycle = crate::commands::Lifecycle {
            force: true,
            resume_command: format!("perifrac bench render --demo -o {}", out.display()),
        };
        let timing = crate::commands::simulate(
            &scene,
            &dir,
            &perifrac_sim::run::RunOptions::default(),
            &lifecycle,
            &crate::ranks::Launch::single(),
            None,
            quiet,
        )?;
        let preview = timing.preview.ok_or_else(|| {
            Failure::from(anyhow::anyhow!(
                "the demo's previews failed (see the warning above)"
            ))
        })?;
        let _ = write!(
            report,
            "\nDemo (`perifrac demo`, 960×540 previews of every frame + contact sheet): simulation \
             {:.1} s, previews {preview:.1} s = {:.1} % of the simulation.\n",
            timing.simulation,
            100.0 * preview / timing.simulation
        );
    }
    let path = out.join("render.md");
    std::fs::write(&path, &report)
        .map_err(|e| Failure::from(anyhow::anyhow!("{}: {e}", path.display())))?;
    println!("{report}");
    Ok(())
}

/// Without the `gl` feature there is nothing to time.
#[cfg(not(feature = "gl"))]
pub fn run(
    _size: (u32, u32),
    _triangles: usize,
    _particles: usize,
    _frames: usize,
    _demo: bool,
    _out: &Path,
    _quiet: bool,
) -> Result<(), Failure> {
    Err(Failure::from(anyhow::anyhow!(
        "this perifrac was built without the `gl` feature: nothing to benchmark"
    )))
}

/// A latitude–longitude sphere of radius 0.5 m with bumps, resting on the ground, with
/// about `triangles` triangles.
#[cfg(feature = "gl")]
fn bumpy_sphere(triangles: usize) -> perifrac_render::geometry::FrameGeometry {
    use perifrac_render::geometry::{FrameGeometry, Shading, surface_color};
    let rings = ((triangles as f64 / 4.0).sqrt().round() as u32).max(2);
    let segments = 2 * rings;
    let mut positions = Vec::new();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let bump = 1.0 + 0.04 * (7.0 * theta).sin() * (9.0 * phi).sin();
            let radius = 0.5 * bump;
            positions.push([
                radius * theta.sin() * phi.cos(),
                0.52 + radius * theta.cos(),
                radius * theta.sin() * phi.sin(),
            ]);
        }
    }
    let mut indices = Vec::new();
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b) = (r * row + s, (r + 1) * row + s);
            indices.extend_from_slice(&[a, a + 1, b, b, a + 1, b + 1]);
        }
    }
    let mut g = FrameGeometry {
        ground: Some(0.0),
        ..FrameGeometry::default()
    };
    let color = surface_color();
    g.push_mesh(&positions, None, &|_| color, &indices, Shading::Surface);
    g
}

/// A block of about `count` particles on a cubic lattice (1 m wide), coloured by a
/// damage ramp.
#[cfg(feature = "gl")]
fn particle_block(count: usize) -> perifrac_render::geometry::FrameGeometry {
    use perifrac_render::geometry::{FrameGeometry, damage_color};
    let n = (count as f64).cbrt().ceil() as usize;
    let h = 1.0 / n as f32;
    let mut g = FrameGeometry {
        ground: Some(0.0),
        ..FrameGeometry::default()
    };
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                if g.point_count() == count {
                    return g;
                }
                let p = [
                    -0.5 + (i as f32 + 0.5) * h,
                    (j as f32 + 0.5) * h,
                    -0.5 + (k as f32 + 0.5) * h,
                ];
                g.push_point(p, 0.5 * h, damage_color(p[1]));
            }
        }
    }
    g
}
