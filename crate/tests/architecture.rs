//! Dependencies point one way (issue 14): the lower layers — `linalg` and
//! `kinematics` — name nothing from the layers built on them (`skeleton`,
//! `control_point`, `avoidance`, `world`, …). The source files are read with
//! `include_str!`, so the test runs natively and under `wasm-pack test --node`;
//! natively it also checks that the list below covers every file.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

/// Every source file of the lower layers, by path under `crate/src`.
const LOWER: &[(&str, &str)] = &[
    ("linalg.rs", include_str!("../src/linalg.rs")),
    (
        "kinematics/mod.rs",
        include_str!("../src/kinematics/mod.rs"),
    ),
    (
        "kinematics/frames.rs",
        include_str!("../src/kinematics/frames.rs"),
    ),
    ("kinematics/ik.rs", include_str!("../src/kinematics/ik.rs")),
    (
        "kinematics/inertia.rs",
        include_str!("../src/kinematics/inertia.rs"),
    ),
    (
        "kinematics/preset_inertials.rs",
        include_str!("../src/kinematics/preset_inertials.rs"),
    ),
    (
        "kinematics/presets.rs",
        include_str!("../src/kinematics/presets.rs"),
    ),
    (
        "kinematics/spec.rs",
        include_str!("../src/kinematics/spec.rs"),
    ),
    (
        "kinematics/dh_from_axes.rs",
        include_str!("../src/kinematics/dh_from_axes.rs"),
    ),
];

/// Modules built on top of the lower layers.
const HIGHER: &[&str] = &[
    "skeleton",
    "control_point",
    "transition",
    "avoidance",
    "dependability",
    "scenario",
    "world",
    "distance",
    "fitting",
    "dynamics",
    "parsers",
];

/// Re-exports kept only so that old paths still compile; the code of the
/// module does not use them. Remove an entry when its users import from the
/// new place (none left: `kinematics::ik` no longer re-exports `linalg` or
/// `control_point::clik`).
const COMPATIBILITY_REEXPORTS: &[(&str, &str)] = &[];

#[test]
fn lower_layers_name_no_higher_module() {
    let mut found = Vec::new();
    for (file, text) in LOWER {
        for (n, line) in text.lines().enumerate() {
            let code = line.trim_start();
            if code.starts_with("//") {
                continue;
            }
            if COMPATIBILITY_REEXPORTS.contains(&(file, code)) {
                continue;
            }
            for module in HIGHER {
                if code.contains(&format!("crate::{module}")) {
                    found.push(format!("{file}:{}: {code}", n + 1));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "lower layers name higher modules:\n{}",
        found.join("\n")
    );
}

#[test]
fn compatibility_reexports_are_still_present() {
    // An entry whose line has gone should leave the list too.
    for (file, line) in COMPATIBILITY_REEXPORTS {
        let text = LOWER.iter().find(|(f, _)| f == file).unwrap().1;
        assert!(
            text.lines().any(|l| l.trim_start() == *line),
            "{file}: {line}"
        );
    }
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn the_list_covers_every_lower_file() {
    use std::path::Path;
    fn walk(dir: &Path, root: &Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, root, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(root).unwrap();
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec!["linalg.rs".to_owned()];
    walk(&src.join("kinematics"), &src, &mut files);
    files.sort();
    let mut listed: Vec<String> = LOWER.iter().map(|(f, _)| (*f).to_owned()).collect();
    listed.sort();
    assert_eq!(files, listed);
}

const LIB: &str = include_str!("../src/lib.rs");
const README: &str = include_str!("../../README.md");

/// The modules `lib.rs` declares (`pub mod x;` or `mod x;`).
fn declared_modules() -> Vec<String> {
    LIB.lines()
        .filter_map(|l| {
            let l = l.trim();
            let rest = l
                .strip_prefix("pub mod ")
                .or_else(|| l.strip_prefix("mod "))?;
            Some(rest.trim_end_matches(';').to_owned())
        })
        .collect()
}

/// README's section "Architecture".
fn architecture_section() -> &'static str {
    README
        .split("\n## Architecture")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("README has an Architecture section")
}

/// The modules README's architecture table names (`` | `x.rs` | `` or
/// `` | `x/` | ``), in the section "Architecture".
fn readme_modules() -> Vec<String> {
    let section = architecture_section();
    section
        .lines()
        .filter_map(|l| {
            let cell = l.strip_prefix("| `")?.split('`').next()?;
            let name = cell
                .strip_suffix(".rs")
                .or_else(|| cell.strip_suffix('/'))?;
            Some(name.to_owned())
        })
        .collect()
}

/// `described` names exactly the modules `lib.rs` declares.
fn assert_names_every_module(mut described: Vec<String>, table: &str) {
    let mut declared = declared_modules();
    declared.sort();
    described.sort();
    assert_eq!(declared, described, "lib.rs modules vs {table}");
}

#[test]
fn readme_architecture_table_matches_lib_modules() {
    assert_names_every_module(readme_modules(), "README's architecture table");
}

/// The modules `lib.rs`'s own table names (`` //! | [`x`] | `` or
/// `` //! | `x` (…) | ``).
fn lib_table_modules() -> Vec<String> {
    LIB.lines()
        .filter_map(|l| {
            let cell = l.strip_prefix("//! | ")?.split(" |").next()?;
            let name = cell
                .trim_start_matches('[')
                .strip_prefix('`')?
                .split('`')
                .next()?;
            Some(name.to_owned())
        })
        .collect()
}

#[test]
fn lib_table_names_every_module() {
    assert_names_every_module(lib_table_modules(), "its own table");
}

/// Natively: every file and folder directly inside a module's folder
/// (`crate/src/<module>/`) is named in that module's row of README's
/// architecture table (`step.rs`, `rows/`), so the map shows every part.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn readme_rows_name_every_file_of_their_module() {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let section = architecture_section();
    let mut missing = Vec::new();
    for line in section.lines() {
        let Some(name) = line
            .strip_prefix("| `")
            .and_then(|l| l.split('`').next())
            .and_then(|c| c.strip_suffix('/'))
        else {
            continue;
        };
        let row = line.split_once(" | ").map_or("", |(_, rest)| rest);
        let mut entries: Vec<_> = std::fs::read_dir(src.join(name))
            .expect("the module's folder")
            .map(|e| e.expect("an entry"))
            .collect();
        entries.sort_by_key(std::fs::DirEntry::file_name);
        for entry in entries {
            let file = entry.file_name().to_string_lossy().into_owned();
            let shown = if entry.path().is_dir() {
                format!("{file}/")
            } else {
                file.clone()
            };
            if file == "mod.rs" || file == "tests.rs" || file == "tests" {
                continue;
            }
            if !row.contains(&format!("`{shown}")) && !row.contains(&format!("{shown}`")) {
                missing.push(format!("{name}/{shown}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "README's architecture rows do not name: {missing:?}"
    );
}
