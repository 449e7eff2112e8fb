//! No import circle between the library's top-level modules, and none new inside its folders.
//!
//! The graph has one node per top-level module of `src/lib.rs` (geometry, narrow_phase,
//! contact_law, dynamics, run, scene, output, analysis, …) and an edge A → B wherever code in A
//! names B by a path: `crate::B…`, `crate::{B…, …}` or a `super::` chain that climbs out of A to
//! the crate's root. Comments (doc links included: they compile to nothing) and string literals
//! are left out. The test fails on a cycle and names the files and lines of each of its edges.
//! Inside a folder the same reading gives one graph per folder (its files, and `mod` for its
//! `mod.rs`: `import_circles_inside_folders`): the circles there are counted and may not grow
//! past today's, and no file of `narrow_phase` or `contact_law` names its folder's `mod.rs`
//! (their records are files of their own). `src/bin` is a crate of its own, over the library
//! only, and is not read.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The import circles inside the library's folders today (`import_circles_inside_folders`
/// lists them: dynamics — the world, its stepper and their parts — and output's run reader with
/// the walls' and cell's writers): a new one fails the test.
const CIRCLES_INSIDE_FOLDERS: usize = 2;

/// Where an edge was seen: `file:line`.
type Graph = BTreeMap<String, BTreeMap<String, Vec<String>>>;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The source with comments and the insides of string and character literals blanked (kept as
/// spaces, newlines kept, so that offsets give the same lines).
fn code_only(src: &str) -> String {
    let b: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                out.push(' ');
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(b[i]));
                    i += 1;
                }
            }
        } else if c == 'r'
            && (next == Some('"') || next == Some('#'))
            && (i == 0 || !(b[i - 1].is_alphanumeric() || b[i - 1] == '_'))
        {
            // A raw string r"…" or r#"…"#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|h| b.get(j + 1 + h) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.extend(b[i..j.min(b.len())].iter().map(|&c| blank(c)));
            i = j;
        } else if c == '"' {
            out.push(' ');
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    out.push(' ');
                    i += 1;
                }
                if i < b.len() {
                    out.push(blank(b[i]));
                    i += 1;
                }
            }
            out.push(' ');
            i += 1;
        } else if c == '\'' {
            // A character literal ('x', '\n', '\u{..}'), or else a lifetime (left as it is).
            let end = if next == Some('\\') {
                (i + 2..b.len().min(i + 12)).find(|&j| b[j] == '\'')
            } else if b.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match end {
                Some(e) => {
                    out.extend(std::iter::repeat_n(' ', e + 1 - i));
                    i = e + 1;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The first identifier of each comma-separated item of the group that opens at `b[i] == '{'`.
fn group_heads(b: &[char], mut i: usize) -> Vec<String> {
    let mut heads = Vec::new();
    let mut depth = 0;
    let mut expect_head = true;
    while i < b.len() {
        let c = b[i];
        match c {
            '{' => {
                depth += 1;
                if depth == 1 {
                    expect_head = true;
                }
            }
            '}' => {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            ',' if depth == 1 => expect_head = true,
            c if depth == 1 && expect_head && is_ident(c) => {
                let s: String = b[i..].iter().take_while(|&&c| is_ident(c)).collect();
                i += s.len();
                heads.push(s);
                expect_head = false;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    heads
}

/// The top-level modules that the code of one file, at module path `path` (`["dynamics",
/// "world"]` for src/dynamics/world.rs), names: each with the line it is named on (the first
/// segment of each path it names, its unit tests' included).
fn named_modules(code: &str, path: &[String]) -> Vec<(String, usize)> {
    resolved_paths(code, path, &[], false)
        .into_iter()
        .filter_map(|(p, line)| p.first().map(|h| (h.clone(), line)))
        .collect()
}

/// The top-level modules that `src/lib.rs` declares.
fn top_modules(lib: &str) -> BTreeSet<String> {
    code_only(lib)
        .lines()
        .filter_map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub ").unwrap_or(l);
            let name = l.strip_prefix("mod ")?.strip_suffix(';')?;
            Some(name.trim().to_string())
        })
        .collect()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module graph of the library in `src`.
fn graph(src: &Path) -> Graph {
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    let tops = top_modules(&lib);
    assert!(!tops.is_empty(), "no module declared in src/lib.rs");
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let mut g = Graph::new();
    for f in files {
        let rel = f.strip_prefix(src).unwrap();
        let mut path: Vec<String> = rel
            .with_extension("")
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        if path.last().is_some_and(|l| l == "mod") {
            path.pop();
        }
        let Some(top) = path.first().cloned() else {
            continue;
        };
        if !tops.contains(&top) {
            continue; // lib.rs itself, src/bin
        }
        let code = code_only(&std::fs::read_to_string(&f).unwrap());
        let node = g.entry(top.clone()).or_default();
        for (m, line) in named_modules(&code, &path) {
            if m != top && tops.contains(&m) {
                let at = format!("src/{}:{line}", rel.display());
                node.entry(m).or_default().push(at);
            }
        }
    }
    g
}

/// A cycle of the graph, if there is one: the modules in order, the first again at the end.
fn cycle(g: &Graph) -> Option<Vec<String>> {
    // Depth-first search; 1 on the path, 2 done.
    fn visit(
        g: &Graph,
        n: &str,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        path.push(n.to_string());
        for m in g.get(n).into_iter().flat_map(|e| e.keys()) {
            match state.get(m.as_str()) {
                Some(1) => {
                    let from = path.iter().position(|p| p == m).unwrap();
                    let mut c = path[from..].to_vec();
                    c.push(m.clone());
                    return Some(c);
                }
                Some(_) => {}
                None => {
                    if let Some(c) = visit(g, m, state, path) {
                        return Some(c);
                    }
                }
            }
        }
        path.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in g.keys() {
        if !state.contains_key(n.as_str())
            && let Some(c) = visit(g, n, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

fn describe(g: &Graph, c: &[String]) -> String {
    c.windows(2)
        .map(|w| {
            let at = &g[&w[0]][&w[1]];
            format!("{} -> {} ({})", w[0], w[1], at.join(", "))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn no_import_cycle_between_top_level_modules() {
    let g = graph(&root().join("src"));
    for (a, edges) in &g {
        let to: Vec<&str> = edges.keys().map(String::as_str).collect();
        println!("{a} -> {}", to.join(", "));
    }
    // The layers the design names are all present (a reader that saw nothing would pass).
    for (a, b) in [
        ("narrow_phase", "geometry"),
        ("dynamics", "narrow_phase"),
        ("run", "dynamics"),
        ("output", "run"),
    ] {
        assert!(
            g.get(a).is_some_and(|e| e.contains_key(b)),
            "expected {a} -> {b}; the reader of paths is broken"
        );
    }
    if let Some(c) = cycle(&g) {
        panic!(
            "import cycle between top-level modules: {}\n{}",
            c.join(" -> "),
            describe(&g, &c)
        );
    }
}

/// The reader and the search on a small tree with a cycle through a `super::` chain, a grouped
/// import and an inline module, and with paths that must not count (comments, strings).
#[test]
fn the_check_finds_a_planted_cycle() {
    let dir = std::env::temp_dir().join(format!("dem2d-module-graph-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("a")).unwrap();
    std::fs::create_dir_all(dir.join("b")).unwrap();
    let write = |p: &str, s: &str| std::fs::write(dir.join(p), s).unwrap();
    write("lib.rs", "pub mod a;\npub mod b;\npub mod c;\n");
    write("a/mod.rs", "pub mod x;\nuse crate::{b::Thing, std_like};\n");
    write(
        "a/x.rs",
        "// crate::c in a comment\nfn f() { let s = \"crate::c\"; let c = 'c'; }\n",
    );
    write(
        "b/mod.rs",
        "mod tests {\n    use super::super::c::Y;\n}\nfn g<'a>(x: &'a str) {}\n",
    );
    write(
        "c.rs",
        "pub struct Y;\n/* crate::b /* nested */ crate::b */\n",
    );
    let g = graph(&dir);
    // Only a → b and b → c (through `super::super` from an inline module): no cycle yet.
    let edges: Vec<(String, String)> = g
        .iter()
        .flat_map(|(a, e)| e.keys().map(move |b| (a.clone(), b.clone())))
        .collect();
    assert_eq!(
        edges,
        vec![("a".into(), "b".into()), ("b".into(), "c".into())]
    );
    assert_eq!(cycle(&g), None);
    // c names a through a `super::` from its own file (src/c.rs: super is the crate's root).
    write("c.rs", "pub struct Y;\nuse super::a::x;\n");
    let g = graph(&dir);
    let c = cycle(&g).expect("the planted cycle");
    assert_eq!(c.len(), 4, "{c:?}");
    assert!(
        describe(&g, &c).contains("src/c.rs:2"),
        "{}",
        describe(&g, &c)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The paths that the code of one file, at module path `path`, names through `crate::` or a
/// `super::` chain (resolved to a path from the crate's root: `crate::a::{b, c::d}` gives
/// `[a, b]` and `[a, c, d]`, up to the group's heads), and through the name of one of its own
/// child modules (`children`, as a `mod.rs` names its files: `cache::PairCache`); with
/// `skip_tests`, not in a `mod tests`.
fn resolved_paths(
    code: &str,
    path: &[String],
    children: &[String],
    skip_tests: bool,
) -> Vec<(Vec<String>, usize)> {
    let b: Vec<char> = code.chars().collect();
    let mut found = Vec::new();
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut line = 1;
    let mut i = 0;
    let word_at = |i: usize, w: &str| {
        let n = w.chars().count();
        b.len() >= i + n
            && b[i..i + n].iter().copied().eq(w.chars())
            && (i == 0 || !is_ident(b[i - 1]) || b[i - 1] == '$')
            && !b.get(i + n).is_some_and(|&c| is_ident(c))
    };
    let colons = |j: usize| b.get(j) == Some(&':') && b.get(j + 1) == Some(&':');
    let skip_ws = |mut j: usize| {
        while j < b.len() && b[j].is_whitespace() {
            j += 1;
        }
        j
    };
    // The identifiers of a path from `j` on (`a::b::{…}` or `a::b`): the chain, and the group's
    // heads if it ends in one.
    let chain = |mut j: usize| {
        let mut segs = Vec::new();
        loop {
            let s: String = b[j..].iter().take_while(|&&c| is_ident(c)).collect();
            if s.is_empty() {
                let heads = if b.get(j) == Some(&'{') {
                    group_heads(&b, j)
                } else {
                    Vec::new()
                };
                return (segs, heads, j);
            }
            j += s.len();
            segs.push(s);
            if colons(j) {
                j = skip_ws(j + 2);
            } else {
                return (segs, Vec::new(), j);
            }
        }
    };
    while i < b.len() {
        let c = b[i];
        if c == '\n' {
            line += 1;
        } else if c == '{' {
            depth += 1;
        } else if c == '}' {
            depth = depth.saturating_sub(1);
            if inline.last().is_some_and(|m| m.1 == depth) {
                inline.pop();
            }
        } else if word_at(i, "mod") {
            let j = skip_ws(i + 3);
            let name: String = b[j..].iter().take_while(|&&c| is_ident(c)).collect();
            let k = skip_ws(j + name.len());
            if !name.is_empty() && b.get(k) == Some(&'{') {
                inline.push((name, depth));
            }
        } else if skip_tests && inline.iter().any(|m| m.0 == "tests") {
            // A file's unit tests may reach its folder's API: not an import of the code.
        } else if (word_at(i, "crate") || word_at(i, "super")) && colons(i + 5) {
            let mut here: Vec<String> = path.to_vec();
            here.extend(inline.iter().map(|m| m.0.clone()));
            let mut j = i;
            loop {
                if word_at(j, "crate") && colons(j + 5) {
                    here.clear();
                    j = skip_ws(j + 7);
                } else if word_at(j, "super") && colons(j + 5) {
                    here.pop();
                    j = skip_ws(j + 7);
                } else {
                    break;
                }
            }
            let (segs, heads, end) = chain(j);
            let mut base = here;
            base.extend(segs);
            if heads.is_empty() {
                found.push((base.clone(), line));
            }
            for h in heads {
                let mut p = base.clone();
                p.push(h);
                found.push((p, line));
            }
            i = end.max(i + 1);
            continue;
        } else if inline.is_empty() && (i < 2 || b[i - 1] != ':') && is_ident(c) {
            let s: String = b[i..].iter().take_while(|&&c| is_ident(c)).collect();
            if (i == 0 || !is_ident(b[i - 1])) && colons(i + s.len()) && children.contains(&s) {
                let mut p = path.to_vec();
                p.push(s.clone());
                found.push((p, line));
            }
            i += s.len().max(1);
            continue;
        }
        i += 1;
    }
    found
}

/// One graph per folder of the crate rooted at `root_dir` (`src/bin` left out): its nodes the
/// folder's files (`mod` for its `mod.rs`), an edge x → y where x's code names y (or, for
/// `mod`, an item of the folder's `mod.rs`). Keyed by the folder's module path.
fn folder_graphs(root_dir: &Path) -> BTreeMap<String, Graph> {
    let mut files = Vec::new();
    rust_files(root_dir, &mut files);
    files.sort();
    let children_of = |dir: &Path| -> Vec<String> {
        let mut c: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| {
                let p = e.unwrap().path();
                let name = p.file_stem()?.to_string_lossy().into_owned();
                (p.is_dir() || (p.extension().is_some_and(|x| x == "rs") && name != "mod"))
                    .then_some(name)
            })
            .collect();
        c.sort();
        c
    };
    let mut graphs: BTreeMap<String, Graph> = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(root_dir).unwrap();
        if rel.components().count() < 2 || rel.starts_with("bin") {
            continue; // the crate's root files; another crate
        }
        let mut path: Vec<String> = rel
            .with_extension("")
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        let is_mod = path.last().is_some_and(|l| l == "mod");
        if is_mod {
            path.pop();
        }
        let (folder, node) = if is_mod {
            (path.clone(), "mod".to_string())
        } else {
            (
                path[..path.len() - 1].to_vec(),
                path.last().unwrap().clone(),
            )
        };
        let folder_dir = root_dir.join(folder.join("/"));
        let children = children_of(&folder_dir);
        let own_children = if is_mod { children.clone() } else { Vec::new() };
        let code = code_only(&std::fs::read_to_string(&f).unwrap());
        let g = graphs.entry(folder.join("::")).or_default();
        g.entry(node.clone()).or_default();
        for (p, line) in resolved_paths(&code, &path, &own_children, true) {
            if p.len() <= folder.len() || p[..folder.len()] != folder[..] {
                continue;
            }
            let next = &p[folder.len()];
            let target = if children.contains(next) {
                next.clone()
            } else {
                "mod".to_string()
            };
            if target != node {
                let at = format!("{}:{line}", rel.display());
                g.entry(node.clone())
                    .or_default()
                    .entry(target)
                    .or_default()
                    .push(at);
            }
        }
    }
    graphs
}

/// Tarjan's bookkeeping: the next index, each node's (index, low link), the stack and its set.
type Tarjan = (
    usize,
    BTreeMap<String, (usize, usize)>,
    Vec<String>,
    BTreeSet<String>,
);

/// The strongly connected components of more than one node (Tarjan's algorithm, iterative
/// enough for a folder's few files).
fn circles(g: &Graph) -> Vec<Vec<String>> {
    fn strong(g: &Graph, v: &str, t: &mut Tarjan, out: &mut Vec<Vec<String>>) {
        let k = t.0;
        t.0 += 1;
        t.1.insert(v.to_string(), (k, k));
        t.2.push(v.to_string());
        t.3.insert(v.to_string());
        for w in g.get(v).into_iter().flat_map(|e| e.keys()) {
            if !t.1.contains_key(w) {
                strong(g, w, t, out);
                let low = t.1[v].1.min(t.1[w].1);
                t.1.get_mut(v).unwrap().1 = low;
            } else if t.3.contains(w) {
                let low = t.1[v].1.min(t.1[w].0);
                t.1.get_mut(v).unwrap().1 = low;
            }
        }
        if t.1[v].0 == t.1[v].1 {
            let mut comp = Vec::new();
            loop {
                let w = t.2.pop().unwrap();
                t.3.remove(&w);
                let done = w == v;
                comp.push(w);
                if done {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                out.push(comp);
            }
        }
    }
    let mut t = (0, BTreeMap::new(), Vec::new(), BTreeSet::new());
    let mut out = Vec::new();
    for v in g.keys() {
        if !t.1.contains_key(v) {
            strong(g, v, &mut t, &mut out);
        }
    }
    out
}

#[test]
fn import_circles_inside_folders() {
    let mut all = Vec::new();
    for (folder, g) in folder_graphs(&root().join("src")) {
        for c in circles(&g) {
            let edges: Vec<String> = c
                .iter()
                .flat_map(|a| {
                    g[a].iter()
                        .filter(|(b, _)| c.contains(b))
                        .map(move |(b, at)| format!("  {a} -> {b} ({})", at.join(", ")))
                })
                .collect();
            println!("circle in {folder}: {}\n{}", c.join(", "), edges.join("\n"));
            all.push(format!("{folder}: {}", c.join(", ")));
        }
    }
    println!("{} circles inside folders", all.len());
    // The records of the narrow phase and of the contact laws are files of their own: no file
    // there names its folder's mod.rs.
    for folder in ["narrow_phase", "contact_law"] {
        let g = &folder_graphs(&root().join("src"))[folder];
        let back: Vec<String> = g
            .iter()
            .filter(|(a, _)| *a != "mod")
            .filter_map(|(a, e)| e.get("mod").map(|at| format!("{a} ({})", at.join(", "))))
            .collect();
        assert!(
            back.is_empty(),
            "{folder}: files that import its mod.rs: {back:?}"
        );
    }
    assert!(all.len() <= CIRCLES_INSIDE_FOLDERS, "{all:#?}");
}

/// The folder reader on a small tree: a circle between two files through `super::`, a file that
/// names its folder's `mod.rs`, a `mod.rs` that names a child by its bare name, a group import,
/// and a unit-test module that does not count.
#[test]
fn the_folder_check_finds_a_planted_circle() {
    let dir = std::env::temp_dir().join(format!("dem2d-folder-graph-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("a")).unwrap();
    let write = |p: &str, s: &str| std::fs::write(dir.join(p), s).unwrap();
    write("lib.rs", "pub mod a;\n");
    write(
        "a/mod.rs",
        "mod x;\nmod y;\nmod z;\npub struct Item;\nfn f() { x::go(); }\n",
    );
    write("a/x.rs", "use super::y::T;\npub fn go() {}\n");
    write(
        "a/y.rs",
        "pub struct T;\nuse crate::a::{z::W, x::go};\n#[cfg(test)]\nmod tests {\n    use super::super::Item;\n}\n",
    );
    write("a/z.rs", "pub struct W;\n// super::Item in a comment\n");
    let g = &folder_graphs(&dir)["a"];
    let edges: Vec<(String, String)> = g
        .iter()
        .flat_map(|(a, e)| e.keys().map(move |b| (a.clone(), b.clone())))
        .collect();
    let want: Vec<(String, String)> = [("mod", "x"), ("x", "y"), ("y", "x"), ("y", "z")]
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    assert_eq!(edges, want);
    assert_eq!(circles(g), vec![vec!["x".to_string(), "y".to_string()]]);
    // z names its folder's mod.rs: an edge to `mod`.
    write("a/z.rs", "pub struct W;\nuse super::Item;\n");
    let g = &folder_graphs(&dir)["a"];
    assert!(g["z"].contains_key("mod"), "{g:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
