//! The modules of each folder depend on one another without cycles (the data flow of the
//! pipeline holds inside a stage too): a test over the source tree.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The text of a module: its file, or every file under its folder; without `//` comments (doc
/// links are not dependencies).
fn module_text(folder: &Path, module: &str) -> String {
    let mut files = Vec::new();
    let file = folder.join(format!("{module}.rs"));
    if file.exists() {
        files.push(file);
    }
    let mut stack = vec![folder.join(module)];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    let mut text = String::new();
    for f in files {
        for line in fs::read_to_string(&f).unwrap().lines() {
            text.push_str(line.split("//").next().unwrap_or(""));
            text.push('\n');
        }
    }
    text
}

/// Whether `text` names `name` as a whole word right after `prefix` (`super::name`,
/// `crate::sim::name`) or inside a `prefix{…}` group.
fn refers(text: &str, prefix: &str, name: &str) -> bool {
    let word = |rest: &str| {
        rest.strip_prefix(name)
            .is_some_and(|after| !after.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
    };
    text.match_indices(prefix).any(|(i, _)| {
        let rest = &text[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group = &group[..group.find('}').unwrap_or(group.len())];
            group
                .split([',', ' ', '\n'])
                .any(|item| item.trim() == name || item.trim().starts_with(&format!("{name}::")))
        } else {
            word(rest)
        }
    })
}

/// The dependency graph of the modules directly in `folder` (`path`: its module path).
fn graph(folder: &Path, path: &str) -> BTreeMap<String, BTreeSet<String>> {
    let mut modules = BTreeSet::new();
    for entry in fs::read_dir(folder).unwrap().flatten() {
        let p = entry.path();
        let name = p.file_stem().unwrap().to_string_lossy().to_string();
        if p.is_dir() || (p.extension().is_some_and(|e| e == "rs") && name != "mod") {
            modules.insert(name);
        }
    }
    let mut g = BTreeMap::new();
    for m in &modules {
        let text = module_text(folder, m);
        let uses = (modules.iter())
            .filter(|o| *o != m)
            .filter(|o| {
                refers(&text, "super::", o) || refers(&text, &format!("crate::{path}::"), o)
            })
            .cloned()
            .collect();
        g.insert(m.clone(), uses);
    }
    g
}

/// The strongly connected components with more than one module (Tarjan).
fn cycles(g: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        g: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        for w in &s.g[v] {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.stack.contains(&w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                component.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.found.push(component);
            }
        }
    }
    let mut s = State {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for v in g.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.found
}

#[test]
fn no_folder_has_modules_that_import_each_other_in_a_cycle() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut folders = vec![root.clone()];
    let mut found = Vec::new();
    let mut checked = 0;
    while let Some(folder) = folders.pop() {
        for entry in fs::read_dir(&folder).unwrap().flatten() {
            if entry.path().is_dir() {
                folders.push(entry.path());
            }
        }
        if folder == root {
            continue;
        }
        let rel = folder.strip_prefix(&root).unwrap();
        let path = rel.to_string_lossy().replace('/', "::");
        for c in cycles(&graph(&folder, &path)) {
            found.push(format!("src/{}: {}", rel.display(), c.join(" ↔ ")));
        }
        checked += 1;
    }
    assert!(checked > 10, "only {checked} folders found under src/");
    assert!(
        found.is_empty(),
        "file-level import cycles:\n{}",
        found.join("\n")
    );
}

/// The detection itself finds a cycle when there is one (and none in a chain).
#[test]
fn a_cycle_is_found_and_a_chain_is_not() {
    let g = |edges: &[(&str, &str)]| {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for &(a, b) in edges {
            g.entry(a.into()).or_default().insert(b.into());
            g.entry(b.into()).or_default();
        }
        g
    };
    assert_eq!(
        cycles(&g(&[("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")])),
        vec![vec!["a".to_string(), "b".into(), "c".into()]]
    );
    assert!(cycles(&g(&[("a", "b"), ("b", "c"), ("a", "c")])).is_empty());
    assert!(refers(
        "use super::{check::Checker, x};",
        "super::",
        "check"
    ));
    assert!(refers("super::validate::parse", "super::", "validate"));
    assert!(!refers("super::validate_top::f", "super::", "validate"));
}
