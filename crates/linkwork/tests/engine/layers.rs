//! The engine's layers run one way and no file imports itself back. Reads src/ as text:
//! every `crate::` and `super::` path (in `use` lines and inline, braces expanded,
//! `#[cfg(test)]` modules left out), each resolved to the file that defines its longest
//! module prefix, through `pub use` re-exports. Fails on an edge from a lower layer to a
//! higher one and on any cycle between files.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Lowest first; a file may use its own layer and those before it.
const LAYERS: [&str; 9] =
    ["error", "math", "input", "constraints", "model", "solve", "compile", "sweep", "analysis"];
/// Layers beside another (same rank): each may use what that one may, neither the other.
const BESIDE: [(&str, &str); 1] = [("dynamics", "sweep")];
/// Side layers that may use only these (and themselves).
const SIDE: [(&str, &[&str]); 2] =
    [("screw", &["error", "math", "input"]), ("synthesis", &["error", "math", "input"])];

type Module = Vec<String>;

struct Crate {
    /// module path -> file (relative to src/)
    files: BTreeMap<Module, String>,
    /// module path -> its code, tests and comments removed
    code: BTreeMap<Module, String>,
}

fn read_crate(src: &Path) -> Crate {
    let mut files = BTreeMap::new();
    let mut code = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix(src).unwrap().with_extension("");
                let mut m: Module =
                    rel.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
                if matches!(m.last().map(String::as_str), Some("mod" | "lib")) {
                    m.pop();
                }
                let text = std::fs::read_to_string(&p).unwrap();
                code.insert(m.clone(), strip(&text));
                files.insert(m, p.strip_prefix(src).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    Crate { files, code }
}

/// The text without `//` comments and without `#[cfg(test)] mod name { ... }` blocks.
fn strip(text: &str) -> String {
    let no_comments: String =
        text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n");
    let mut out = String::new();
    let mut rest = no_comments.as_str();
    while let Some(i) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..i]);
        let after = &rest[i + "#[cfg(test)]".len()..];
        let trimmed = after.trim_start();
        let is_mod = trimmed.starts_with("mod ") || trimmed.starts_with("pub mod ");
        match (is_mod, after.find('{')) {
            (true, Some(open)) if !after[..open].contains(';') => {
                let mut depth = 0usize;
                let mut end = after.len();
                for (k, ch) in after[open..].char_indices() {
                    match ch {
                        '{' => depth += 1,
                        '}' => {
                            depth -= 1;
                            if depth == 0 {
                                end = open + k + 1;
                                break;
                            }
                        }
                        _ => {}
                    }
                }
                rest = &after[end..];
            }
            _ => rest = after,
        }
    }
    out.push_str(rest);
    out
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Every path starting at `crate` or `super` (or, with `relative`, any `pub use` path),
/// braces expanded: each as its segments.
fn paths_at(code: &str, start: usize, prefix: Vec<String>, out: &mut Vec<Vec<String>>) -> usize {
    // reads `seg::seg::{a, b::{c}}` from `start`; returns the end
    let b = code.as_bytes();
    let mut i = start;
    let mut segs = prefix;
    loop {
        let s = i;
        while i < b.len() && is_ident(b[i] as char) {
            i += 1;
        }
        if i > s {
            segs.push(code[s..i].to_string());
        }
        if code[i..].starts_with("::{") {
            i += 3;
            loop {
                while i < b.len() && (b[i] as char).is_whitespace() {
                    i += 1;
                }
                if i >= b.len() || b[i] == b'}' {
                    break;
                }
                i = paths_at(code, i, segs.clone(), out);
                while i < b.len() && b[i] != b',' && b[i] != b'}' {
                    i += 1; // skips ` as name`
                }
                if i < b.len() && b[i] == b',' {
                    i += 1;
                }
            }
            out.push(segs);
            return i + 1;
        } else if code[i..].starts_with("::") && code[i + 2..].starts_with(|c: char| is_ident(c)) {
            i += 2;
        } else {
            if segs.last().is_some_and(|s| s != "self" && s != "*") {
                out.push(segs);
            } else if segs.last().is_some_and(|s| s == "self") {
                segs.pop();
                out.push(segs);
            }
            return i;
        }
    }
}

fn crate_paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for key in ["crate::", "super::"] {
        let mut from = 0;
        while let Some(k) = code[from..].find(key) {
            let at = from + k;
            from = at + key.len();
            if at > 0 && (is_ident(code[..at].chars().last().unwrap()) || code[..at].ends_with('$')) {
                continue;
            }
            paths_at(code, at, Vec::new(), &mut out);
        }
    }
    out
}

/// An absolute module path for `path` written in module `here`.
fn absolute(here: &Module, path: &[String]) -> Vec<String> {
    let mut base: Vec<String> = here.clone();
    let mut k = usize::from(path.first().map(String::as_str) == Some("self"));
    if path.first().map(String::as_str) == Some("crate") {
        base.clear();
        k = 1;
    } else {
        while path.get(k).map(String::as_str) == Some("super") {
            base.pop();
            k += 1;
        }
    }
    base.extend(path[k..].iter().cloned());
    base
}

/// `pub use` re-exports: (module, name) -> the absolute path it stands for.
fn reexports(c: &Crate) -> BTreeMap<(Module, String), Vec<String>> {
    let mut map = BTreeMap::new();
    for (m, code) in &c.code {
        let mut from = 0;
        while let Some(k) = code[from..].find("pub use ") {
            let at = from + k + "pub use ".len();
            from = at;
            let mut paths = Vec::new();
            let end = paths_at(code, at, Vec::new(), &mut paths);
            let stmt = &code[at..code[end..].find(';').map_or(end, |e| end + e)];
            for p in paths {
                if p.is_empty() {
                    continue;
                }
                let name = p.last().unwrap().clone();
                let alias = stmt
                    .split(&format!("{name} as "))
                    .nth(1)
                    .map(|s| s.chars().take_while(|&ch| is_ident(ch)).collect::<String>());
                map.insert((m.clone(), alias.unwrap_or(name)), absolute(m, &p));
            }
        }
    }
    map
}

/// The file a path lands in: the longest prefix that is a module, re-exports followed.
fn resolve(
    c: &Crate,
    re: &BTreeMap<(Module, String), Vec<String>>,
    mut target: Vec<String>,
) -> Option<Module> {
    for _ in 0..8 {
        let n = (0..=target.len()).rev().find(|&n| c.files.contains_key(&target[..n]))?;
        let module = target[..n].to_vec();
        match target.get(n).and_then(|name| re.get(&(module.clone(), name.clone()))) {
            Some(to) => target = [to.clone(), target[n + 1..].to_vec()].concat(),
            None => return Some(module),
        }
    }
    None
}

fn edges(c: &Crate) -> BTreeMap<Module, BTreeSet<Module>> {
    let re = reexports(c);
    let mut out: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (m, code) in &c.code {
        let set = out.entry(m.clone()).or_default();
        for p in crate_paths(code) {
            let abs = absolute(m, &p);
            if let Some(to) = resolve(c, &re, abs) {
                if &to != m && !to.is_empty() {
                    set.insert(to);
                }
            }
        }
    }
    out
}

/// Rank of a file's layer (error, math, ...), or its side layer's name; None for lib.rs.
fn layer(m: &Module) -> Option<Result<usize, &'static str>> {
    let top = m.first()?;
    if let Some(i) = LAYERS.iter().position(|l| l == top) {
        return Some(Ok(i));
    }
    if let Some((_, of)) = BESIDE.iter().find(|(b, _)| b == top) {
        return Some(Ok(LAYERS.iter().position(|l| l == of).expect("a layer")));
    }
    if let Some((s, _)) = SIDE.iter().find(|(s, _)| s == top) {
        return Some(Err(s));
    }
    panic!("src/{} is in no layer: put it in one of {LAYERS:?} or {SIDE:?}", m.join("/"));
}

fn upward(e: &BTreeMap<Module, BTreeSet<Module>>, files: &BTreeMap<Module, String>) -> Vec<String> {
    let mut bad = Vec::new();
    for (from, tos) in e {
        let Some(lf) = layer(from) else { continue };
        for to in tos {
            let Some(lt) = layer(to) else { continue };
            // two layers of one rank side by side do not use each other
            let siblings = from[0] != to[0]
                && BESIDE
                    .iter()
                    .any(|(x, y)| (from[0] == *x && to[0] == *y) || (from[0] == *y && to[0] == *x));
            let ok = match (lf, lt) {
                (Ok(_), Ok(_)) if siblings => false,
                (Ok(a), Ok(b)) => b <= a,
                (Err(a), Err(b)) => a == b,
                (Err(s), Ok(b)) => SIDE.iter().find(|(n, _)| *n == s).unwrap().1.contains(&LAYERS[b]),
                (Ok(_), Err(_)) => false,
            };
            if !ok {
                bad.push(format!("{} -> {}", files[from], files[to]));
            }
        }
    }
    bad
}

/// Strongly connected components with more than one file (Tarjan).
fn cycles(e: &BTreeMap<Module, BTreeSet<Module>>, files: &BTreeMap<Module, String>) -> Vec<Vec<String>> {
    struct T<'a> {
        e: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        on: BTreeSet<&'a Module>,
        out: Vec<Vec<&'a Module>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a Module) {
        let i = t.index.len();
        t.index.insert(v, i);
        t.low.insert(v, i);
        t.stack.push(v);
        t.on.insert(v);
        if let Some(ws) = t.e.get(v) {
            for w in ws {
                if !t.index.contains_key(w) {
                    visit(t, w);
                    let lw = t.low[w];
                    let lv = t.low.get_mut(v).unwrap();
                    *lv = (*lv).min(lw);
                } else if t.on.contains(w) {
                    let iw = t.index[w];
                    let lv = t.low.get_mut(v).unwrap();
                    *lv = (*lv).min(iw);
                }
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = t.stack.pop() {
                t.on.remove(w);
                comp.push(w);
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                t.out.push(comp);
            }
        }
    }
    let mut t = T {
        e,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in e.keys() {
        if !t.index.contains_key(v) {
            visit(&mut t, v);
        }
    }
    t.out.into_iter().map(|c| c.into_iter().map(|m| files[m].clone()).collect()).collect()
}

fn src() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn layers_run_one_way() {
    let c = read_crate(&src());
    let bad = upward(&edges(&c), &c.files);
    assert!(bad.is_empty(), "{} edges against the layer order {LAYERS:?}:\n{}", bad.len(), bad.join("\n"));
}

#[test]
fn no_file_imports_itself_back() {
    let c = read_crate(&src());
    let cyc = cycles(&edges(&c), &c.files);
    assert!(cyc.is_empty(), "{} cycles:\n{:#?}", cyc.len(), cyc);
}

/// The reader itself: an upward `use`, an inline path, a path through a re-export and a
/// cycle are each found.
#[test]
fn the_reader_sees_what_it_must() {
    let mut c = read_crate(&src());
    let add = |c: &mut Crate, m: &[&str], code: &str| {
        let m: Module = m.iter().map(|s| s.to_string()).collect();
        c.code.get_mut(&m).expect("module exists").push_str(code);
    };
    add(&mut c, &["math", "small_lu"], "\nuse crate::sweep::time_loop::Request;\n");
    add(&mut c, &["input", "units"], "\nfn f() { let _ = crate::model::Model::default(); }\n");
    add(&mut c, &["constraints", "loads"], "\nuse crate::Data;\n");
    add(&mut c, &["dynamics", "mass"], "\nuse crate::sweep::time_loop::check_times;\n");
    let bad = upward(&edges(&c), &c.files);
    for want in [
        "dynamics/mass.rs -> sweep/time_loop.rs",
        "math/small_lu.rs -> sweep/time_loop.rs",
        "input/units.rs -> model/mod.rs",
        "constraints/loads.rs -> model/data.rs",
    ] {
        assert!(bad.iter().any(|b| b == want), "{want} not found in {bad:?}");
    }
    let mut c = read_crate(&src());
    add(&mut c, &["solve", "velocity"], "\nuse crate::solve::{position::{solve_position}};\n");
    add(&mut c, &["solve", "position"], "\n#[cfg(test)]\nmod tests { use crate::solve::acceleration; }\nuse super::velocity::solve_velocity;\n");
    let cyc = cycles(&edges(&c), &c.files);
    assert!(
        cyc.iter()
            .any(|k| k.contains(&"solve/position.rs".to_string())
                && k.contains(&"solve/velocity.rs".to_string())),
        "the cycle position <-> velocity not found in {cyc:?}"
    );
}
