//! The argument parsing and validation of `args`.

use super::*;

fn parse(args: &[&str]) -> Result<RunConfig, String> {
    let cli = Cli::try_parse_from(args).map_err(|e| e.to_string())?;
    match cli.command {
        Command::Run(r) => RunConfig::try_from(r),
        other => Err(format!("not run: {other:?}")),
    }
}

#[test]
fn run_flags() {
    let c = parse(&[
        "perifrac",
        "run",
        "a.toml",
        "-o",
        "x",
        "--frames",
        "3",
        "--threads",
        "2",
        "--resume",
    ])
    .unwrap();
    assert_eq!(c.frames, Some(3));
    assert_eq!(c.threads, Some(2));
    assert_eq!(c.out, Some(PathBuf::from("x")));
    assert!(c.resume && !c.force);
    assert!(
        parse(&["perifrac", "run", "a.toml", "--force"])
            .unwrap()
            .force
    );
    assert!(
        parse(&["perifrac", "run", "a.toml", "--force", "--resume"])
            .unwrap_err()
            .contains("cannot be used with")
    );
}

#[test]
fn bad_numbers_are_refused() {
    assert!(
        parse(&["perifrac", "run", "a.toml", "--frames", "0"])
            .unwrap_err()
            .contains("--frames")
    );
    assert!(
        parse(&["perifrac", "run", "a.toml", "--threads", "two"])
            .unwrap_err()
            .contains("--threads")
    );
    assert!(parse(&["perifrac", "run"]).is_err());
}

#[test]
fn surface_flags() {
    let parse = |args: &[&str]| -> Result<SurfaceConfig, String> {
        let cli = Cli::try_parse_from(args).map_err(|e| e.to_string())?;
        match cli.command {
            Command::Surface(s) => SurfaceConfig::try_from(s),
            other => Err(format!("not surface: {other:?}")),
        }
    };
    let c = parse(&[
        "perifrac",
        "surface",
        "out/x",
        "--method",
        "vdb",
        "--threads",
        "2",
    ])
    .unwrap();
    assert_eq!(c.out, PathBuf::from("out/x"));
    assert_eq!(c.method, SurfaceMethodArg::Vdb);
    assert_eq!(c.threads, Some(2));
    assert_eq!(
        parse(&["perifrac", "surface", "o"]).unwrap().method,
        SurfaceMethodArg::Vdb
    );
    assert!(parse(&["perifrac", "surface", "o", "--method", "marching"]).is_err());
    assert!(
        parse(&["perifrac", "surface", "o", "--threads", "0"])
            .unwrap_err()
            .contains("--threads")
    );
}

#[test]
fn render_flags() {
    let parse = |args: &[&str]| -> Result<RenderConfig, String> {
        let cli = Cli::try_parse_from(args).map_err(|e| e.to_string())?;
        match cli.command {
            Command::Render(r) => RenderConfig::try_from(r),
            other => Err(format!("not render: {other:?}")),
        }
    };
    let c = parse(&[
        "perifrac",
        "render",
        "out/x",
        "--turntable",
        "12",
        "--frame",
        "7",
        "--size",
        "320x200",
        "--color-by",
        "fragment",
    ])
    .unwrap();
    assert_eq!(c.turntable, 12);
    assert_eq!(c.frame, Some(7));
    assert_eq!(c.size, (320, 200));
    assert_eq!(c.color_by, Some(ColorByArg::Fragment));
    let q = parse(&["perifrac", "render", "o", "--color-by", "quantity"]).unwrap();
    assert_eq!(q.color_by, Some(ColorByArg::Quantity));
    let d = parse(&["perifrac", "render", "o"]).unwrap();
    assert_eq!(
        (d.turntable, d.frame, d.size, d.color_by, d.movie),
        (0, None, (960, 540), None, false)
    );
    let m = parse(&[
        "perifrac",
        "render",
        "o",
        "--movie",
        "--color-by",
        "material",
    ])
    .unwrap();
    assert_eq!((m.movie, m.color_by), (true, Some(ColorByArg::Material)));
    assert!(
        !m.overlay
            && parse(&["perifrac", "render", "o", "--overlay"])
                .unwrap()
                .overlay
    );
    for bad in ["0x10", "10", "axb", "9000x10"] {
        assert!(
            parse(&["perifrac", "render", "o", "--size", bad])
                .unwrap_err()
                .contains("--size"),
            "{bad}"
        );
    }
    assert!(
        parse(&["perifrac", "render", "o", "--frame", "0"])
            .unwrap_err()
            .contains("--frame")
    );
    assert!(parse(&["perifrac", "render", "o", "--color-by", "heat"]).is_err());
    assert_eq!(
        parse(&["perifrac", "render", "o", "--azimuth", "-90"])
            .unwrap()
            .azimuth,
        Some(-90.0)
    );
    assert_eq!(
        d.azimuth, None,
        "the azimuth follows the projectile unless given"
    );
    assert!(
        parse(&["perifrac", "render", "o", "--azimuth", "left"])
            .unwrap_err()
            .contains("--azimuth")
    );
}

#[test]
fn quiet_is_global() {
    let cli = Cli::try_parse_from(["perifrac", "check", "a.toml", "--quiet"]).unwrap();
    assert!(cli.quiet);
}
