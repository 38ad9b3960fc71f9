//! The core's module graph points one way (issue 26): a module's `crate::…`
//! uses, read from the source, may not lead back to it. The fast backend's
//! two files (`chain`, `lanes`) count as one module; an item re-exported at
//! the crate root (`crate::Robot`) counts as a use of the module it comes from.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The top-level module a source file belongs to (`ik/geo/srs.rs` → `ik`).
fn module_of(relative: &Path) -> String {
    let first = relative.components().next().unwrap().as_os_str().to_string_lossy().into_owned();
    let name = first.trim_end_matches(".rs").to_string();
    match name.as_str() {
        "chain" | "lanes" => "backend".into(),
        _ => name,
    }
}

/// The source without comments and without its `#[cfg(test)]` tail (tests
/// may use anything).
fn code(text: &str) -> String {
    let body = text.split("#[cfg(test)]").next().unwrap_or("");
    body.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// Every `crate::name` in `text`.
fn crate_uses(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = text;
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        if !name.is_empty() {
            out.insert(name);
        }
    }
    out
}

/// The modules of the items `lib.rs` re-exports (`pub use robot::Robot;` → Robot: robot).
fn root_items(lib: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for statement in code(lib).split(';') {
        let Some(path) = statement.trim().strip_prefix("pub use ") else { continue };
        let Some((module, items)) = path.split_once("::") else { continue };
        for item in items.split(|c: char| !(c.is_alphanumeric() || c == '_')).filter(|w| !w.is_empty()) {
            out.insert(item.to_string(), module.to_string());
        }
    }
    out
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let items = root_items(&std::fs::read_to_string(src.join("lib.rs")).unwrap());
    let mut files = Vec::new();
    let mut stack = vec![src.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") && !path.ends_with("tests.rs") {
                // A `tests.rs` is a unit-test module in a file of its own: tests may use anything.
                files.push(path);
            }
        }
    }
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for path in &files {
        let module = module_of(path.strip_prefix(&src).unwrap());
        if module == "lib" {
            continue;
        }
        graph.entry(module.clone()).or_default();
        let text = std::fs::read_to_string(path).unwrap();
        for used in crate_uses(&code(&text)) {
            let used = items.get(&used).cloned().unwrap_or(used);
            let used = if used == "chain" || used == "lanes" { "backend".to_string() } else { used };
            if used != module {
                graph.entry(module.clone()).or_default().insert(used);
            }
        }
    }
    // Keep only edges to modules (not to items such as `crate::nalgebra`).
    let modules: BTreeSet<String> = graph.keys().cloned().collect();
    for deps in graph.values_mut() {
        deps.retain(|d| modules.contains(d));
    }
    graph
}

/// The modules reachable from `from`.
fn reachable(graph: &BTreeMap<String, BTreeSet<String>>, from: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut stack = vec![from.to_string()];
    while let Some(m) = stack.pop() {
        for d in graph.get(&m).into_iter().flatten() {
            if seen.insert(d.clone()) {
                stack.push(d.clone());
            }
        }
    }
    seen
}

#[test]
fn the_module_graph_has_no_cycle() {
    let graph = graph();
    for (module, deps) in &graph {
        println!("{module} -> {}", deps.iter().cloned().collect::<Vec<_>>().join(", "));
    }
    // The layers the issue asks for, bottom up.
    for (lower, upper) in [("math", "model"), ("model", "robot"), ("robot", "ik"), ("robot", "traj"), ("error", "ik")] {
        assert!(!reachable(&graph, lower).contains(upper), "{lower} depends on {upper}");
    }
    let cycles: Vec<String> = graph
        .iter()
        .flat_map(|(m, deps)| {
            let graph = &graph;
            deps.iter().filter(move |d| reachable(graph, d).contains(m)).map(move |d| format!("{m} -> {d}"))
        })
        .collect();
    assert!(cycles.is_empty(), "edges on a cycle of the module graph: {cycles:?}");
}

#[test]
fn the_reader_finds_uses_and_skips_comments_and_tests() {
    let text =
        "use crate::math::Pose;\n// crate::ik in a comment\nfn f() { crate::model::X }\n#[cfg(test)]\nuse crate::traj;";
    let uses = crate_uses(&code(text));
    assert_eq!(uses.into_iter().collect::<Vec<_>>(), vec!["math".to_string(), "model".to_string()]);
    let items = root_items("pub use robot::Robot;\npub use model::{\n    Joint, Model,\n};\nmod x;");
    assert_eq!(items["Robot"], "robot");
    assert_eq!((items["Joint"].as_str(), items["Model"].as_str()), ("model", "model"));
}
