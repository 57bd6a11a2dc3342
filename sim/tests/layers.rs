//! The models share through the layers below them (`family`, `embed`, `perifrac-math`,
//! the cache), never by importing each other (ARCHITECTURE; issue 32, item 5): no file
//! of a model's module names another model's module.

use std::path::Path;

/// The model modules of `sim/src`.
const MODELS: [&str; 3] = ["pd", "mpm", "membrane"];

/// Every `.rs` file under `dir`, with its text.
fn sources(dir: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("reads the model's folder")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).expect("reads the source");
            out.push((path.display().to_string(), text));
        }
    }
}

#[test]
fn no_model_imports_another_model() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut found = Vec::new();
    for model in MODELS {
        let mut files = Vec::new();
        sources(&src.join(model), &mut files);
        assert!(!files.is_empty(), "sim/src/{model} holds the model");
        for (path, text) in files {
            for other in MODELS.iter().filter(|&&o| o != model) {
                for (n, line) in text.lines().enumerate() {
                    if line.contains(&format!("crate::{other}::"))
                        || line.contains(&format!("crate::{other}}}"))
                        || line.contains(&format!("crate::{other};"))
                        || line.contains(&format!("crate::{other}::{{"))
                    {
                        found.push(format!("{path}:{}: {}", n + 1, line.trim()));
                    }
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "a model imports another model:\n{}",
        found.join("\n")
    );
}
