#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! No import circles between the modules of a crate (ARCHITECTURE.md,
//! "Module map"): a circle means no file of it can be read or changed
//! alone. Read from the source text as `../shared/tools/module-cycles.py`
//! does: module A depends on B when A names `crate::B…` (a path or a `use`
//! group) or a sibling `super::B`; comments and `#[cfg(test)]` blocks are
//! left out (tests may import anything).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Module path (`a::b`) to its file, for one crate's `src`.
fn module_files(src: &Path) -> BTreeMap<String, PathBuf> {
    let mut mods = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("a readable source folder") {
            let path = entry.expect("a folder entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let rel = path.strip_prefix(src).unwrap().with_extension("");
            let mut parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if parts.last().is_some_and(|p| p == "mod") {
                parts.pop();
            }
            if parts == ["lib"] || parts == ["main"] || parts.first().is_some_and(|p| p == "bin") {
                continue;
            }
            mods.insert(parts.join("::"), path);
        }
    }
    mods
}

/// The text without line comments, cut at the first `#[cfg(test)]`.
fn strip(text: &str) -> String {
    let code: String = text
        .lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n");
    match code.find("#[cfg(test)]") {
        Some(i) => code[..i].to_owned(),
        None => code,
    }
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The `a::b::C` path that starts at `text`, and its length.
fn path_at(text: &str) -> (String, usize) {
    let mut end = 0;
    let bytes = text.as_bytes();
    loop {
        let start = end;
        while end < text.len() && is_ident(bytes[end] as char) {
            end += 1;
        }
        if end == start {
            // `crate::{` or `crate::*`: the path stops before its `::`.
            end = start.saturating_sub(2);
            break;
        }
        if text[end..].starts_with("::") && text[end + 2..].starts_with(|c: char| is_ident(c)) {
            end += 2;
        } else {
            break;
        }
    }
    (text[..end].to_owned(), end)
}

/// Expands a `use` group's inside (`a::{B, C}, d`) into full paths.
fn expand_group(prefix: &str, inside: &str, out: &mut BTreeSet<String>) {
    let mut depth = 0;
    let mut item = String::new();
    let mut items = Vec::new();
    for c in inside.chars() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(std::mem::take(&mut item));
                continue;
            }
            _ => {}
        }
        item.push(c);
    }
    items.push(item);
    for item in items {
        let item: String = item.split_whitespace().collect::<Vec<_>>().join(" ");
        let item = item.split(" as ").next().unwrap_or("").trim().to_owned();
        if item.is_empty() {
            continue;
        }
        let join = |rest: &str| {
            if prefix.is_empty() {
                rest.to_owned()
            } else {
                format!("{prefix}::{rest}")
            }
        };
        match item.find('{') {
            Some(open) => {
                let head = item[..open].trim_end_matches("::");
                let close = item.rfind('}').unwrap_or(item.len());
                expand_group(&join(head), &item[open + 1..close], out);
            }
            None => {
                out.insert(join(&item));
            }
        }
    }
}

/// The paths a module's text names: `crate::…`, `use crate::{…}` groups,
/// and `super::x` (as the sibling `parent::x`).
fn references(text: &str, module: &str) -> BTreeSet<String> {
    let mut refs = BTreeSet::new();
    for (i, _) in text.match_indices("crate::") {
        if i > 0 && is_ident(text[..i].chars().next_back().unwrap()) {
            continue; // `lucerna_crate::` and the like
        }
        let rest = &text[i + "crate::".len()..];
        if rest.starts_with('{') {
            let mut depth = 0;
            let mut end = rest.len();
            for (k, c) in rest.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            end = k;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            expand_group("", &rest[1..end], &mut refs);
        } else {
            let (path, _) = path_at(rest);
            // `crate::a::{B, C}`: the group below `a`.
            let after = &rest[path.len()..];
            if let Some(group) = after.strip_prefix("::{") {
                let close = group.find("};").or_else(|| group.find('}'));
                expand_group(&path, &group[..close.unwrap_or(group.len())], &mut refs);
            }
            if !path.is_empty() {
                refs.insert(path);
            }
        }
    }
    let parent = module.rsplit_once("::").map_or("", |(p, _)| p);
    for (i, _) in text.match_indices("super::") {
        if i > 0 && is_ident(text[..i].chars().next_back().unwrap()) {
            continue;
        }
        let (path, _) = path_at(&text[i + "super::".len()..]);
        if let Some(first) = path.split("::").next().filter(|s| !s.is_empty()) {
            refs.insert(if parent.is_empty() {
                first.to_owned()
            } else {
                format!("{parent}::{first}")
            });
        }
    }
    refs
}

/// The longest module prefix of `path`.
fn resolve<'a>(path: &str, mods: &'a BTreeMap<String, PathBuf>) -> Option<&'a str> {
    let segments: Vec<&str> = path.split("::").collect();
    (1..=segments.len())
        .rev()
        .find_map(|n| mods.get_key_value(&segments[..n].join("::")))
        .map(|(k, _)| k.as_str())
}

/// Strongly connected sets of two or more modules (Tarjan).
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    struct Tarjan<'g> {
        graph: &'g BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        on_stack: BTreeSet<&'g str>,
        out: Vec<BTreeSet<String>>,
    }
    impl<'g> Tarjan<'g> {
        fn visit(&mut self, v: &'g str) {
            let i = self.index.len();
            self.index.insert(v, i);
            self.low.insert(v, i);
            self.stack.push(v);
            self.on_stack.insert(v);
            for w in self.graph.get(v).into_iter().flatten() {
                let w = w.as_str();
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.low[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(lw);
                } else if self.on_stack.contains(w) {
                    let iw = self.index[w];
                    let lv = self.low.get_mut(v).unwrap();
                    *lv = (*lv).min(iw);
                }
            }
            if self.low[v] == self.index[v] {
                let mut component = BTreeSet::new();
                loop {
                    let w = self.stack.pop().unwrap();
                    self.on_stack.remove(w);
                    component.insert(w.to_owned());
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    self.out.push(component);
                }
            }
        }
    }
    let mut t = Tarjan {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !t.index.contains_key(v.as_str()) {
            t.visit(v);
        }
    }
    t.out
}

/// Each crate's import circles, with the names that tie each arrow.
fn crate_circles(crate_dir: &Path) -> Vec<String> {
    let mods = module_files(&crate_dir.join("src"));
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut why: BTreeMap<(String, String), BTreeSet<String>> = BTreeMap::new();
    for (module, file) in &mods {
        let text = strip(&std::fs::read_to_string(file).expect("a readable source file"));
        for r in references(&text, module) {
            let Some(target) = resolve(&r, &mods) else {
                continue;
            };
            if target == module || module.starts_with(&format!("{target}::")) {
                continue;
            }
            graph
                .entry(module.clone())
                .or_default()
                .insert(target.to_owned());
            why.entry((module.clone(), target.to_owned()))
                .or_default()
                .insert(r.rsplit("::").next().unwrap_or(&r).to_owned());
        }
    }
    circles(&graph)
        .into_iter()
        .map(|component| {
            let mut text = component.iter().cloned().collect::<Vec<_>>().join(", ");
            for a in &component {
                for b in graph.get(a).into_iter().flatten() {
                    if component.contains(b) {
                        let names: Vec<_> = why[&(a.clone(), b.clone())].iter().cloned().collect();
                        text.push_str(&format!("\n    {a} -> {b}: {}", names.join(", ")));
                    }
                }
            }
            text
        })
        .collect()
}

#[test]
fn no_crate_has_an_import_circle_between_its_modules() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut found = Vec::new();
    let mut dirs: Vec<_> = std::fs::read_dir(&crates)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("src").is_dir())
        .collect();
    dirs.sort();
    assert!(dirs.len() >= 12, "the crates are found: {dirs:?}");
    for dir in dirs {
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        for circle in crate_circles(&dir) {
            found.push(format!("{name}: {circle}"));
        }
    }
    assert!(
        found.is_empty(),
        "{} import circle(s) between modules (move the type both sides use \
         into a module of its own):\n{}",
        found.len(),
        found.join("\n")
    );
}

#[test]
fn the_reader_sees_use_groups_paths_and_super() {
    let text = strip(
        "use crate::{a::{B, c::D}, e as f};\nuse crate::g::{H, I};\n\
         fn x() { crate::j::k(); super::l::m(); } // crate::n\n\
         #[cfg(test)] mod tests { use crate::o; }",
    );
    let refs = references(&text, "p::q");
    let expected: BTreeSet<String> = ["a::B", "a::c::D", "e", "g", "g::H", "g::I", "j::k", "p::l"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(refs, expected);
    // A circle is found, a chain is not.
    let graph = |edges: &[(&str, &str)]| {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (a, b) in edges {
            g.entry(a.to_string()).or_default().insert(b.to_string());
        }
        g
    };
    assert_eq!(circles(&graph(&[("a", "b"), ("b", "c")])).len(), 0);
    assert_eq!(
        circles(&graph(&[("a", "b"), ("b", "c"), ("c", "a")])).len(),
        1
    );
}
