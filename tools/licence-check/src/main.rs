//! Checks the licences of every crate the default build links (normal and build
//! dependencies of the workspace's crates, with default features), from
//! `cargo metadata`. perifrac is MIT OR Apache-2.0: a copyleft licence (GPL, AGPL,
//! LGPL, MPL, EPL, …) in the default build fails the check. Opt-in features (such as
//! a TetGen mesher, AGPL-3.0) are not part of the default build and are not checked.

use std::collections::{BTreeMap, BTreeSet};
use std::process::{Command, ExitCode};

use serde_json::Value;

/// Licences a dependency may use (alone or as one side of an OR).
const ALLOWED: &[&str] = &[
    "MIT",
    "MIT-0",
    "Apache-2.0",
    "Apache-2.0 WITH LLVM-exception",
    "BSD-2-Clause",
    "BSD-3-Clause",
    "ISC",
    "Zlib",
    "Unicode-3.0",
    "Unicode-DFS-2016",
    "BSL-1.0",
    "CC0-1.0",
    "Unlicense",
];

/// Whether an SPDX expression is satisfiable with allowed licences only.
fn allowed(expression: &str) -> bool {
    let cleaned = expression.replace(['(', ')'], " ").replace('/', " OR ");
    cleaned.split(" OR ").any(|alternative| {
        alternative
            .split(" AND ")
            .map(str::trim)
            .all(|licence| ALLOWED.contains(&licence))
    })
}

fn main() -> ExitCode {
    let output = match Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(["metadata", "--format-version", "1", "--locked"])
        .output()
    {
        Ok(o) if o.status.success() => o.stdout,
        Ok(o) => {
            eprintln!(
                "licence-check: cargo metadata failed: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            return ExitCode::from(2);
        }
        Err(e) => {
            eprintln!("licence-check: could not run cargo metadata: {e}");
            return ExitCode::from(2);
        }
    };
    let meta: Value = match serde_json::from_slice(&output) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("licence-check: unreadable cargo metadata: {e}");
            return ExitCode::from(2);
        }
    };
    let empty = Vec::new();
    let packages: BTreeMap<&str, &Value> = meta["packages"]
        .as_array()
        .unwrap_or(&empty)
        .iter()
        .filter_map(|p| Some((p["id"].as_str()?, p)))
        .collect();
    let nodes: BTreeMap<&str, &Value> = meta["resolve"]["nodes"]
        .as_array()
        .unwrap_or(&empty)
        .iter()
        .filter_map(|n| Some((n["id"].as_str()?, n)))
        .collect();
    let mut stack: Vec<&str> = meta["workspace_members"]
        .as_array()
        .unwrap_or(&empty)
        .iter()
        .filter_map(Value::as_str)
        .collect();
    let mut seen = BTreeSet::new();
    let mut bad = Vec::new();
    while let Some(id) = stack.pop() {
        if !seen.insert(id) {
            continue;
        }
        if let Some(p) = packages.get(id)
            && p["source"].is_string()
        {
            let licence = p["license"].as_str().unwrap_or("(none)");
            if !allowed(licence) {
                bad.push(format!("{} {}: {licence}", p["name"], p["version"]));
            }
        }
        let Some(node) = nodes.get(id) else { continue };
        for dep in node["deps"].as_array().unwrap_or(&empty) {
            let linked = dep["dep_kinds"]
                .as_array()
                .unwrap_or(&empty)
                .iter()
                .any(|k| k["kind"].as_str() != Some("dev"));
            if linked && let Some(pkg) = dep["pkg"].as_str() {
                stack.push(pkg);
            }
        }
    }
    if bad.is_empty() {
        println!(
            "licence-check: {} crates in the default build, all permissively licensed",
            seen.len()
        );
        ExitCode::SUCCESS
    } else {
        eprintln!(
            "licence-check: not allowed in the default build (perifrac is MIT OR Apache-2.0):"
        );
        for b in &bad {
            eprintln!("  {b}");
        }
        ExitCode::FAILURE
    }
}

#[cfg(test)]
mod tests {
    use super::allowed;

    #[test]
    fn expressions() {
        assert!(allowed("MIT OR Apache-2.0"));
        assert!(allowed("(MIT OR Apache-2.0) AND Unicode-3.0"));
        assert!(allowed("MIT/Apache-2.0"));
        assert!(!allowed("AGPL-3.0-only"));
        assert!(!allowed("MPL-2.0"));
        assert!(allowed("MPL-2.0 OR MIT"));
        assert!(!allowed("GPL-2.0 AND MIT"));
    }
}
