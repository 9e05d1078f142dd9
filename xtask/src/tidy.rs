//! `cargo xtask tidy`: no module imports another that imports it back, inside any crate (GUIDE §2,
//! issue 32).
//!
//! For every crate root (`src/lib.rs`, `src/main.rs`, `src/bin/*.rs`) of every crate under
//! `crates/`, of `benches` and of `xtask`, the check builds the graph of the crate's modules and
//! reports each strongly connected component of more than one module (Tarjan's algorithm): a
//! circle, with the names each module takes from the others.
//!
//! - **Nodes.** Modules found by following `mod name;` declarations from the root: `src/a.rs` or
//!   `src/a/mod.rs` is `a`, `src/a/b.rs` is `a::b`; an inline `mod name { .. }` is a node too. A
//!   module and its submodules are distinct nodes.
//! - **Edges.** A path in code that names a module of the crate: `use` declarations (with their
//!   `{..}` trees, `self`, globs and aliases, `pub use` re-exports included) and paths in
//!   expressions, types and patterns, written from `crate::` (or `$crate::`), `self::`,
//!   `super::`, a child module's name, or a name a `use` brought into scope. The edge goes to the
//!   deepest module the path names (`crate::sampler::abit::Abit` is `sampler::abit`,
//!   `crate::svg::Layer` is `svg`); a name a module only re-exports (`pub use dem::HeightGrid` in
//!   `lib.rs`, then `crate::HeightGrid` elsewhere) is followed to the module that defines it, so a
//!   crate root's re-exports do not tie every module to the root. A path to an item of another
//!   crate is no edge.
//! - **Not edges.** A parent's `mod child;` declaration (a parent owns its children; only its
//!   `use`s and paths count). Comments (doc comments and their intra-doc links included), string,
//!   byte-string, raw-string and character literals are blanked before scanning.
//! - **Ignored.** Every item under `#[cfg(test)]`: inline test modules, test-only `use`s and whole
//!   files declared `#[cfg(test)] mod tests_x;` (such files are no nodes): tests may import
//!   anything, and they are no part of the layering a reader or a build depends on. Integration
//!   tests (`tests/`), examples and bench targets are other crates and are not scanned.
//!
//! The scanner is lexical, not a compiler: it does not expand macros (other than seeing the paths
//! written in their bodies) and does not follow `#[path]` attributes (the workspace has none; a
//! declared module whose file is missing is an error, not a silent gap).

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `cargo xtask tidy`: prints every circle, exit 1 if there is any.
pub fn run() -> Result<ExitCode, String> {
    let root = crate::regress::case::workspace_root();
    let reports = check_workspace(&root, &[])?;
    let mut circles = 0;
    for report in &reports {
        for circle in &report.circles {
            circles += 1;
            println!("{}: {circle}", report.name);
        }
    }
    let checked: Vec<&str> = reports.iter().map(|r| r.name.as_str()).collect();
    println!(
        "tidy: {} crate roots checked ({})",
        checked.len(),
        checked.join(", ")
    );
    if circles > 0 {
        println!("tidy: {circles} module import circle(s)");
        return Ok(ExitCode::from(1));
    }
    println!("tidy: no module import circles");
    Ok(ExitCode::SUCCESS)
}

/// The circles of one crate root (`crates/terrain (lib)`).
#[derive(Debug)]
pub struct CrateReport {
    /// The crate's directory relative to the workspace root and the root's kind.
    pub name: String,
    /// Its circles, in module order.
    pub circles: Vec<Circle>,
}

/// Checks every crate of the workspace at `root` except the directories in `skip`.
pub fn check_workspace(root: &Path, skip: &[&str]) -> Result<Vec<CrateReport>, String> {
    let mut dirs = Vec::new();
    let crates = root.join("crates");
    let entries = std::fs::read_dir(&crates).map_err(|e| format!("{}: {e}", crates.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("{}: {e}", crates.display()))?;
        dirs.push(format!("crates/{}", entry.file_name().to_string_lossy()));
    }
    dirs.push("benches".into());
    dirs.push("xtask".into());
    dirs.sort();
    let mut reports = Vec::new();
    for dir in dirs {
        if skip.contains(&dir.as_str()) || !root.join(&dir).join("src").is_dir() {
            continue;
        }
        let files = read_sources(&root.join(&dir).join("src"))?;
        for (kind, root_file) in crate_roots(&files) {
            let circles = circles(&files, &root_file).map_err(|e| format!("{dir}: {e}"))?;
            reports.push(CrateReport {
                name: format!("{dir} ({kind})"),
                circles,
            });
        }
    }
    Ok(reports)
}

/// Every `.rs` file under `src`, by its path relative to `src` with `/` separators.
fn read_sources(src: &Path) -> Result<BTreeMap<String, String>, String> {
    fn walk(dir: &Path, rel: &str, out: &mut BTreeMap<String, String>) -> Result<(), String> {
        let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        for entry in entries {
            let entry = entry.map_err(|e| format!("{}: {e}", dir.display()))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let path: PathBuf = entry.path();
            let rel_name = if rel.is_empty() {
                name.clone()
            } else {
                format!("{rel}/{name}")
            };
            if path.is_dir() {
                walk(&path, &rel_name, out)?;
            } else if name.ends_with(".rs") {
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                out.insert(rel_name, text);
            }
        }
        Ok(())
    }
    let mut out = BTreeMap::new();
    walk(src, "", &mut out)?;
    Ok(out)
}

/// The crate roots among `files`: `lib.rs`, `main.rs` and `bin/*.rs`, with their kind.
fn crate_roots(files: &BTreeMap<String, String>) -> Vec<(String, String)> {
    let mut roots = Vec::new();
    for (kind, file) in [("lib", "lib.rs"), ("bin", "main.rs")] {
        if files.contains_key(file) {
            roots.push((kind.to_string(), file.to_string()));
        }
    }
    for file in files.keys() {
        if let Some(name) = file.strip_prefix("bin/")
            && !name.contains('/')
        {
            roots.push((
                format!("bin {}", name.trim_end_matches(".rs")),
                file.clone(),
            ));
        }
    }
    roots
}

/// A module import circle: modules that reach each other through their imports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Circle {
    /// The modules of the circle (`crate` for the root) with their files, in module order.
    pub modules: Vec<(String, String)>,
    /// The names each module of the circle takes from another ([`Take`]).
    pub takes: Vec<Take>,
}

/// `(from, to, names)`: the names module `from` takes from module `to`, each with the line of its
/// first use in `from`'s file.
pub type Take = (String, String, Vec<(String, usize)>);

impl fmt::Display for Circle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.modules.iter().map(|(m, _)| m.as_str()).collect();
        write!(f, "module import circle: {}", names.join(", "))?;
        let file_of: BTreeMap<&str, &str> = self
            .modules
            .iter()
            .map(|(m, file)| (m.as_str(), file.as_str()))
            .collect();
        for (from, to, names) in &self.takes {
            let names: Vec<String> = names
                .iter()
                .map(|(n, l)| format!("{n} (line {l})"))
                .collect();
            write!(
                f,
                "\n  {from} (src/{}) takes from {to}: {}",
                file_of[from.as_str()],
                names.join(", ")
            )?;
        }
        Ok(())
    }
}

/// The circles of the crate whose root is `root` among `files` (paths relative to `src/`).
pub fn circles(files: &BTreeMap<String, String>, root: &str) -> Result<Vec<Circle>, String> {
    let graph = Crate::load(files, root)?;
    let edges = graph.edges();
    let names: Vec<&String> = graph.modules.keys().collect();
    let index: BTreeMap<&str, usize> = names
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), i))
        .collect();
    let mut adjacency = vec![Vec::new(); names.len()];
    for (from, to) in edges.keys() {
        adjacency[index[from.as_str()]].push(index[to.as_str()]);
    }
    let mut out = Vec::new();
    for component in strongly_connected(&adjacency) {
        if component.len() < 2 {
            continue;
        }
        let members: BTreeSet<&str> = component.iter().map(|&i| names[i].as_str()).collect();
        let modules = members
            .iter()
            .map(|m| (display(m), graph.modules[*m].file.clone()))
            .collect();
        let takes = edges
            .iter()
            .filter(|((from, to), _)| {
                members.contains(from.as_str()) && members.contains(to.as_str())
            })
            .map(|((from, to), names)| {
                let names = names.iter().map(|(n, l)| (n.clone(), *l)).collect();
                (display(from), display(to), names)
            })
            .collect();
        out.push(Circle { modules, takes });
    }
    out.sort_by(|a, b| a.modules.cmp(&b.modules));
    Ok(out)
}

/// `crate` for the root module, else its path.
fn display(module: &str) -> String {
    if module.is_empty() {
        "crate".into()
    } else {
        module.into()
    }
}

/// Tarjan's strongly connected components of a graph given by adjacency lists.
fn strongly_connected(adjacency: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct State<'a> {
        adjacency: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(s: &mut State<'_>, v: usize) {
        s.index[v] = Some(s.next);
        s.low[v] = s.next;
        s.next += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for &w in &s.adjacency[v] {
            match s.index[w] {
                None => {
                    visit(s, w);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            s.out.push(component);
        }
    }
    let n = adjacency.len();
    let mut s = State {
        adjacency,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(&mut s, v);
        }
    }
    s.out
}

/// Replaces comments and string, byte-string, raw-string and character literals by spaces
/// (newlines kept, so line numbers stay right).
pub fn blank_comments_and_literals(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let blank = |out: &mut String, from: &[char]| {
        for &ch in from {
            out.push(if ch == '\n' { '\n' } else { ' ' });
        }
    };
    let ident_char = |ch: char| ch.is_alphanumeric() || ch == '_';
    let mut i = 0;
    while i < c.len() {
        let prev_ident = i > 0 && ident_char(c[i - 1]);
        if c[i] == '/' && c.get(i + 1) == Some(&'/') {
            let end = (i..c.len()).find(|&j| c[j] == '\n').unwrap_or(c.len());
            blank(&mut out, &c[i..end]);
            i = end;
        } else if c[i] == '/' && c.get(i + 1) == Some(&'*') {
            let mut depth = 0;
            let mut j = i;
            while j < c.len() {
                if c[j] == '/' && c.get(j + 1) == Some(&'*') {
                    depth += 1;
                    j += 2;
                } else if c[j] == '*' && c.get(j + 1) == Some(&'/') {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            let end = j.min(c.len());
            blank(&mut out, &c[i..end]);
            i = end;
        } else if let Some(start) = raw_string_start(&c, i, prev_ident) {
            // r"..", r#".."#, br#".."#, cr".."; `start` is the index of the opening quote.
            let hashes = start - i - c[i..start].iter().take_while(|&&ch| ch != '#').count();
            let mut j = start + 1;
            while j < c.len() {
                if c[j] == '"'
                    && c[j + 1..]
                        .iter()
                        .take(hashes)
                        .filter(|&&h| h == '#')
                        .count()
                        == hashes
                {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            let end = j.min(c.len());
            blank(&mut out, &c[i..end]);
            i = end;
        } else if c[i] == '"' {
            let mut j = i + 1;
            while j < c.len() && c[j] != '"' {
                j += if c[j] == '\\' { 2 } else { 1 };
            }
            let end = (j + 1).min(c.len());
            blank(&mut out, &c[i..end]);
            i = end;
        } else if c[i] == '\'' {
            // A character literal ('x', '\n', '\u{..}', '\''), else a lifetime or label.
            let end = if c.get(i + 1) == Some(&'\\') {
                let mut j = i + 3;
                while j < c.len() && c[j] != '\'' {
                    j += 1;
                }
                Some(j + 1)
            } else if c.get(i + 2) == Some(&'\'') {
                Some(i + 3)
            } else {
                None
            };
            match end {
                Some(end) => {
                    let end = end.min(c.len());
                    blank(&mut out, &c[i..end]);
                    i = end;
                }
                None => {
                    out.push('\'');
                    i += 1;
                }
            }
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// The index of the opening quote when a raw string literal starts at `i`.
fn raw_string_start(c: &[char], i: usize, prev_ident: bool) -> Option<usize> {
    if prev_ident {
        return None;
    }
    let mut j = i;
    if matches!(c[j], 'b' | 'c') && c.get(j + 1) == Some(&'r') {
        j += 1;
    }
    if c[j] != 'r' {
        return None;
    }
    j += 1;
    while c.get(j) == Some(&'#') {
        j += 1;
    }
    (c.get(j) == Some(&'"')).then_some(j)
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum Tok {
    Ident(String),
    PathSep,
    Punct(char),
}

/// Tokens with their 1-based lines, from blanked source.
fn tokenize(src: &str) -> Vec<(Tok, usize)> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch.is_alphanumeric() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            let mut word: String = c[start..i].iter().collect();
            // A raw identifier r#name is the identifier name.
            if word == "r"
                && c.get(i) == Some(&'#')
                && c.get(i + 1).is_some_and(|n| n.is_alphabetic() || *n == '_')
            {
                let s = i + 1;
                i = s;
                while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                    i += 1;
                }
                word = c[s..i].iter().collect();
            }
            out.push((Tok::Ident(word), line));
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            out.push((Tok::PathSep, line));
            i += 2;
        } else {
            out.push((Tok::Punct(ch), line));
            i += 1;
        }
    }
    out
}

/// One module of a crate, as scanned.
#[derive(Debug, Default)]
struct Module {
    /// Its file, relative to `src/`.
    file: String,
    /// The directory its `mod child;` files live in, relative to `src/`.
    child_dir: String,
    /// Its (non-test) child modules.
    children: BTreeSet<String>,
    /// Names a module-level `use` binds, with the path it binds them to.
    imports: BTreeMap<String, Vec<String>>,
    /// Paths of module-level glob imports.
    globs: Vec<Vec<String>>,
    /// Names of items defined at module level.
    defined: BTreeSet<String>,
    /// Every path it mentions (module-level and local `use`s, paths in code), with its line and
    /// whether it is a re-export (`pub use`, `pub(crate) use`) binding the given name.
    paths: Vec<(Vec<String>, usize, Option<String>)>,
    /// Identifiers its code mentions outside `use` declarations.
    idents: BTreeSet<String>,
}

/// The modules of one crate root, keyed by path (`""` for the root, `a::b`).
struct Crate {
    modules: BTreeMap<String, Module>,
}

fn join(parent: &str, child: &str) -> String {
    if parent.is_empty() {
        child.into()
    } else {
        format!("{parent}::{child}")
    }
}

fn parent_of(module: &str) -> Option<&str> {
    if module.is_empty() {
        None
    } else {
        Some(module.rsplit_once("::").map_or("", |(p, _)| p))
    }
}

fn is_item_keyword(word: &str) -> bool {
    matches!(
        word,
        "fn" | "struct" | "enum" | "trait" | "type" | "const" | "static" | "union" | "mod"
    )
}

impl Crate {
    fn load(files: &BTreeMap<String, String>, root: &str) -> Result<Crate, String> {
        let mut krate = Crate {
            modules: BTreeMap::new(),
        };
        let root_dir = root.rsplit_once('/').map_or("", |(d, _)| d).to_string();
        // (module path, file, directory of its children's files)
        let mut pending = vec![(String::new(), root.to_string(), root_dir)];
        while let Some((path, file, child_dir)) = pending.pop() {
            let text = files
                .get(&file)
                .ok_or_else(|| format!("module `{}`: no file src/{file}", display(&path)))?;
            let declared = krate.scan(&path, &file, &child_dir, text);
            for (module, child) in declared {
                let dir = &krate.modules[&module].child_dir;
                let prefix = if dir.is_empty() {
                    String::new()
                } else {
                    format!("{dir}/")
                };
                let flat = format!("{prefix}{child}.rs");
                let nested = format!("{prefix}{child}/mod.rs");
                let (child_file, grandchild_dir) = if files.contains_key(&flat) {
                    (flat, format!("{prefix}{child}"))
                } else if files.contains_key(&nested) {
                    (nested, format!("{prefix}{child}"))
                } else {
                    return Err(format!(
                        "module `{}` declared in src/{file}: neither src/{flat} nor src/{nested}",
                        join(&module, &child)
                    ));
                };
                pending.push((join(&module, &child), child_file, grandchild_dir));
            }
        }
        Ok(krate)
    }

    /// Scans one file (module `path`), adding it and its inline modules; returns the
    /// `(module, child)` pairs of its non-test `mod child;` declarations.
    fn scan(
        &mut self,
        path: &str,
        file: &str,
        child_dir: &str,
        text: &str,
    ) -> Vec<(String, String)> {
        let toks = tokenize(&blank_comments_and_literals(text));
        let ident = |i: usize| match toks.get(i) {
            Some((Tok::Ident(w), _)) => Some(w.as_str()),
            _ => None,
        };
        let punct = |i: usize, p: char| matches!(toks.get(i), Some((Tok::Punct(q), _)) if *q == p);
        let sep = |i: usize| matches!(toks.get(i), Some((Tok::PathSep, _)));
        self.modules.insert(
            path.to_string(),
            Module {
                file: file.to_string(),
                child_dir: child_dir.to_string(),
                ..Module::default()
            },
        );
        let mut declared = Vec::new();
        // (module, brace depth inside its body)
        let mut scopes: Vec<(String, usize)> = vec![(path.to_string(), 0)];
        let mut depth = 0;
        let mut i = 0;
        while i < toks.len() {
            let (scope, scope_depth) = scopes.last().cloned().expect("the file's scope");
            let at_module_level = depth == scope_depth;
            let line = toks[i].1;
            if let Some(word) = ident(i) {
                let module = self.modules.get_mut(&scope).expect("scope exists");
                module.idents.insert(word.to_string());
            }
            if punct(i, '#') {
                let inner = punct(i + 1, '!');
                let open = if inner { i + 2 } else { i + 1 };
                if punct(open, '[') {
                    let close = matching(&toks, open);
                    if is_cfg_test(&toks[open + 1..close]) {
                        if inner {
                            // The whole file (or inline module) is test-only.
                            if scopes.len() == 1 {
                                let module = self.modules.get_mut(path).expect("inserted");
                                module.paths.clear();
                                return Vec::new();
                            }
                            i = close + 1;
                            continue;
                        }
                        i = item_end(&toks, close + 1);
                        continue;
                    }
                    i = close + 1;
                    continue;
                }
            }
            match &toks[i].0 {
                Tok::Punct('{') => {
                    depth += 1;
                    i += 1;
                }
                Tok::Punct('}') => {
                    depth = depth.saturating_sub(1);
                    if scopes.len() > 1 && depth < scope_depth {
                        scopes.pop();
                    }
                    i += 1;
                }
                Tok::Ident(word) if word == "use" && !sep(i.wrapping_sub(1)) => {
                    let public = ident(i.wrapping_sub(1)) == Some("pub")
                        || (punct(i.wrapping_sub(1), ')')
                            && (2..6).any(|k| ident(i.wrapping_sub(k)) == Some("pub")));
                    let mut entries = Vec::new();
                    let end = use_tree(&toks, i + 1, &[], &mut entries);
                    let module = self.modules.get_mut(&scope).expect("scope exists");
                    for entry in entries {
                        let reexport = match &entry.binding {
                            Binding::Name(name) if public => Some(name.clone()),
                            _ => None,
                        };
                        module.paths.push((entry.path.clone(), line, reexport));
                        if !at_module_level {
                            continue;
                        }
                        match entry.binding {
                            Binding::Name(name) => {
                                module.imports.insert(name, entry.path);
                            }
                            Binding::Glob => module.globs.push(entry.path),
                            Binding::None => {}
                        }
                    }
                    i = end;
                }
                Tok::Ident(word) if word == "mod" && ident(i + 1).is_some() => {
                    let name = ident(i + 1).expect("checked").to_string();
                    if punct(i + 2, ';') {
                        self.modules
                            .get_mut(&scope)
                            .expect("scope exists")
                            .children
                            .insert(name.clone());
                        declared.push((scope.clone(), name));
                        i += 3;
                    } else if punct(i + 2, '{') {
                        let parent = &self.modules[&scope];
                        let inline = Module {
                            file: file.to_string(),
                            child_dir: format!("{}/{name}", parent.child_dir)
                                .trim_start_matches('/')
                                .to_string(),
                            ..Module::default()
                        };
                        let inline_path = join(&scope, &name);
                        self.modules
                            .get_mut(&scope)
                            .expect("scope exists")
                            .children
                            .insert(name);
                        self.modules.insert(inline_path.clone(), inline);
                        depth += 1;
                        scopes.push((inline_path, depth));
                        i += 3;
                    } else {
                        i += 1;
                    }
                }
                Tok::Ident(word) if at_module_level && is_item_keyword(word) => {
                    if let Some(name) = ident(i + 1) {
                        self.modules
                            .get_mut(&scope)
                            .expect("scope exists")
                            .defined
                            .insert(name.to_string());
                    }
                    i += 1;
                }
                Tok::Ident(word)
                    if at_module_level && word == "macro_rules" && punct(i + 1, '!') =>
                {
                    if let Some(name) = ident(i + 2) {
                        self.modules
                            .get_mut(&scope)
                            .expect("scope exists")
                            .defined
                            .insert(name.to_string());
                    }
                    i += 2;
                }
                Tok::Ident(first) if sep(i + 1) && !sep(i.wrapping_sub(1)) => {
                    let dollar = punct(i.wrapping_sub(1), '$');
                    let mut segments = vec![if dollar && first == "crate" {
                        "crate".to_string()
                    } else {
                        first.clone()
                    }];
                    let mut j = i + 1;
                    while sep(j) {
                        match ident(j + 1) {
                            Some(w) => segments.push(w.to_string()),
                            None => break,
                        }
                        j += 2;
                    }
                    self.modules
                        .get_mut(&scope)
                        .expect("scope exists")
                        .paths
                        .push((segments, line, None));
                    i = j;
                }
                Tok::PathSep => {
                    // `::std::..`: a path into another crate; skip it.
                    let mut j = i;
                    while sep(j) && ident(j + 1).is_some() {
                        j += 2;
                    }
                    i = j.max(i + 1);
                }
                _ => i += 1,
            }
        }
        declared
    }

    /// Every edge `(from, to)` with the names `from` takes from `to` and each one's first line.
    fn edges(&self) -> BTreeMap<(String, String), BTreeMap<String, usize>> {
        let mut edges: BTreeMap<(String, String), BTreeMap<String, usize>> = BTreeMap::new();
        for (from, module) in &self.modules {
            for (path, line, reexport) in &module.paths {
                if let Some((to, name)) = self.resolve(from, path, 0)
                    && &to != from
                    && !publishes_own_child(from, &to, module, reexport.as_deref())
                {
                    let names = edges.entry((from.clone(), to)).or_default();
                    let first = names.entry(name).or_insert(*line);
                    *first = (*first).min(*line);
                }
            }
        }
        edges
    }

    /// The module a path written in module `at` names and the name it takes there; `None` for a
    /// path into another crate or to something local (a variable, `Self`, a generic).
    fn resolve(&self, at: &str, path: &[String], depth: usize) -> Option<(String, String)> {
        if depth > 32 || path.is_empty() {
            return None;
        }
        let module = self.modules.get(at)?;
        let first = path[0].as_str();
        let (start, rest) = match first {
            "crate" => (String::new(), &path[1..]),
            "self" => (at.to_string(), &path[1..]),
            "super" => {
                let mut cur = at;
                let mut k = 0;
                while path.get(k).map(String::as_str) == Some("super") {
                    cur = parent_of(cur)?;
                    k += 1;
                }
                (cur.to_string(), &path[k..])
            }
            _ if module.children.contains(first) => (at.to_string(), path),
            _ if module.imports.contains_key(first) => {
                let mut full = module.imports[first].clone();
                full.extend_from_slice(&path[1..]);
                return self.resolve(at, &full, depth + 1);
            }
            _ => return None,
        };
        self.walk(start, rest, depth)
    }

    /// Walks `rest` down from module `cur` to the deepest module it names, following names that
    /// `cur` itself imports (re-exports) to where they are defined.
    fn walk(&self, mut cur: String, rest: &[String], depth: usize) -> Option<(String, String)> {
        for (k, segment) in rest.iter().enumerate() {
            let module = self.modules.get(&cur)?;
            if module.children.contains(segment) && self.modules.contains_key(&join(&cur, segment))
            {
                cur = join(&cur, segment);
                continue;
            }
            if module.defined.contains(segment) {
                return Some((cur, segment.clone()));
            }
            if let Some(target) = module.imports.get(segment) {
                let mut full = target.clone();
                full.extend_from_slice(&rest[k + 1..]);
                return self.resolve(&cur, &full, depth + 1);
            }
            for glob in &module.globs {
                if let Some((g, _)) = self.resolve(&cur, glob, depth + 1)
                    && let Some(gm) = self.modules.get(&g)
                    && (gm.defined.contains(segment)
                        || gm.imports.contains_key(segment)
                        || gm.children.contains(segment))
                {
                    return self.walk(g, &rest[k..], depth + 1);
                }
            }
            return Some((cur, segment.clone()));
        }
        let name = cur.rsplit("::").next().unwrap_or("").to_string();
        let name = if name.is_empty() {
            "crate".into()
        } else {
            name
        };
        Some((cur, name))
    }
}

/// Whether a path is a module re-exporting an item of its own descendant `to` (`pub use
/// child::Item` in a parent) without its code using the name: that publishes the child's item
/// (as `mod child;` publishes the child) and is no dependency of the parent's code. Paths that
/// reach the item through the re-export are followed to the child, so no circle hides behind it.
fn publishes_own_child(from: &str, to: &str, module: &Module, reexport: Option<&str>) -> bool {
    let Some(name) = reexport else {
        return false;
    };
    let below = from.is_empty() || to.starts_with(&format!("{from}::"));
    below && !module.idents.contains(name)
}

/// The index of the bracket closing the one at `open`.
fn matching(toks: &[(Tok, usize)], open: usize) -> usize {
    let mut depth = 0usize;
    for (j, (tok, _)) in toks.iter().enumerate().skip(open) {
        match tok {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => {
                depth -= 1;
                if depth == 0 {
                    return j;
                }
            }
            _ => {}
        }
    }
    toks.len().saturating_sub(1)
}

/// Whether an attribute's tokens are `cfg(test)` (or a `cfg(all(test, ..))`).
fn is_cfg_test(attr: &[(Tok, usize)]) -> bool {
    let words: Vec<&str> = attr
        .iter()
        .filter_map(|(t, _)| match t {
            Tok::Ident(w) => Some(w.as_str()),
            _ => None,
        })
        .collect();
    matches!(
        words.as_slice(),
        ["cfg", "test"] | ["cfg", "all", "test", ..]
    )
}

/// The index just past the item starting at `i` (its attributes included): its `;` or the `}`
/// closing its body.
fn item_end(toks: &[(Tok, usize)], mut i: usize) -> usize {
    while i < toks.len() {
        match toks[i].0 {
            Tok::Punct(';') => return i + 1,
            Tok::Punct('{' | '(' | '[') => {
                let close = matching(toks, i);
                if toks[i].0 == Tok::Punct('{') {
                    return close + 1;
                }
                i = close + 1;
            }
            _ => i += 1,
        }
    }
    i
}

#[derive(Debug)]
enum Binding {
    Name(String),
    Glob,
    None,
}

#[derive(Debug)]
struct UseEntry {
    path: Vec<String>,
    binding: Binding,
}

/// Parses a use tree at `i` under `prefix`; returns the index past it (past the `;` at the top).
fn use_tree(
    toks: &[(Tok, usize)],
    mut i: usize,
    prefix: &[String],
    out: &mut Vec<UseEntry>,
) -> usize {
    let mut path = prefix.to_vec();
    if matches!(toks.get(i), Some((Tok::PathSep, _))) {
        // `use ::other_crate::..`
        path.push("::".into());
        i += 1;
    }
    loop {
        match toks.get(i).map(|t| &t.0) {
            Some(Tok::Ident(w)) if w != "as" => {
                path.push(w.clone());
                i += 1;
                if matches!(toks.get(i), Some((Tok::PathSep, _))) {
                    i += 1;
                    continue;
                }
                let mut binding = Binding::Name(w.clone());
                if matches!(toks.get(i), Some((Tok::Ident(a), _)) if a == "as") {
                    binding = match toks.get(i + 1) {
                        Some((Tok::Ident(alias), _)) if alias != "_" => {
                            Binding::Name(alias.clone())
                        }
                        _ => Binding::None,
                    };
                    i += 2;
                }
                if w == "self" {
                    path.pop();
                    if let Binding::Name(n) = &binding
                        && n == "self"
                    {
                        binding = path
                            .last()
                            .map_or(Binding::None, |l| Binding::Name(l.clone()));
                    }
                }
                out.push(UseEntry { path, binding });
                break;
            }
            Some(Tok::Punct('*')) => {
                out.push(UseEntry {
                    path,
                    binding: Binding::Glob,
                });
                i += 1;
                break;
            }
            Some(Tok::Punct('{')) => {
                i += 1;
                loop {
                    match toks.get(i).map(|t| &t.0) {
                        Some(Tok::Punct('}')) => {
                            i += 1;
                            break;
                        }
                        Some(Tok::Punct(',')) => i += 1,
                        None => return i,
                        _ => i = use_tree(toks, i, &path, out),
                    }
                }
                break;
            }
            _ => break,
        }
    }
    if prefix.is_empty() && matches!(toks.get(i), Some((Tok::Punct(';'), _))) {
        i += 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    fn krate(files: &[(&str, &str)]) -> BTreeMap<String, String> {
        files
            .iter()
            .map(|(p, t)| (p.to_string(), t.to_string()))
            .collect()
    }

    fn modules_of(circles: &[Circle]) -> Vec<Vec<String>> {
        circles
            .iter()
            .map(|c| c.modules.iter().map(|(m, _)| m.clone()).collect())
            .collect()
    }

    #[test]
    fn a_circle_is_found_with_the_names_each_side_takes() {
        let files = krate(&[
            ("lib.rs", "pub mod a;\npub mod b;\npub mod c;\n"),
            ("a.rs", "use crate::b::{Bee, make_bee};\npub struct Ay;\n"),
            (
                "b.rs",
                "pub struct Bee;\npub fn make_bee() -> crate::a::Ay { todo!() }\n",
            ),
            ("c.rs", "use crate::a::Ay;\n"),
        ]);
        let found = circles(&files, "lib.rs").unwrap();
        assert_eq!(
            modules_of(&found),
            vec![vec!["a".to_string(), "b".to_string()]]
        );
        let c = &found[0];
        assert_eq!(
            c.takes,
            vec![
                (
                    "a".into(),
                    "b".into(),
                    vec![("Bee".into(), 1), ("make_bee".into(), 1)]
                ),
                ("b".into(), "a".into(), vec![("Ay".into(), 2)]),
            ]
        );
        let text = c.to_string();
        assert!(
            text.contains("a (src/a.rs) takes from b: Bee (line 1), make_bee (line 1)"),
            "{text}"
        );
        assert!(
            text.contains("b (src/b.rs) takes from a: Ay (line 2)"),
            "{text}"
        );
    }

    #[test]
    fn a_dag_passes_and_a_parent_declaring_its_children_is_no_edge() {
        let files = krate(&[
            (
                "lib.rs",
                "pub mod grid;\npub mod dem;\npub mod io;\npub use dem::read;\n",
            ),
            ("grid.rs", "pub struct Grid;\n"),
            (
                "dem.rs",
                "use crate::grid::Grid;\npub fn read() -> Grid { crate::io::parse() }\n",
            ),
            ("io/mod.rs", "mod ascii;\npub use self::ascii::parse;\n"),
            (
                "io/ascii.rs",
                "use crate::grid::Grid;\npub fn parse() -> Grid { Grid }\n",
            ),
        ]);
        assert_eq!(circles(&files, "lib.rs").unwrap(), Vec::<Circle>::new());
    }

    #[test]
    fn comments_strings_and_doc_links_are_no_imports() {
        let files = krate(&[
            ("lib.rs", "pub mod a;\npub mod b;\n"),
            ("a.rs", "use crate::b::Bee;\npub struct Ay;\n"),
            (
                "b.rs",
                concat!(
                    "//! See [`crate::a::Ay`].\n",
                    "/// Made from [`crate::a::Ay`]; /* crate::a::Ay */\n",
                    "pub struct Bee;\n",
                    "/* nested /* crate::a::Ay */ still a comment crate::a::Ay */\n",
                    "pub const S: &str = \"crate::a::Ay\";\n",
                    "pub const R: &str = r#\"use crate::a::Ay; \"quoted\"\"#;\n",
                    "pub const C: char = '\"'; pub fn f<'x>(s: &'x str) -> &'x str { s }\n",
                    "#[doc = \"crate::a::Ay\"] pub fn g() {}\n",
                ),
            ),
        ]);
        assert_eq!(circles(&files, "lib.rs").unwrap(), Vec::<Circle>::new());
        // The same file with a real path after the literals closes the circle.
        let mut files = files;
        files
            .get_mut("b.rs")
            .unwrap()
            .push_str("pub type T = crate::a::Ay;\n");
        assert_eq!(
            modules_of(&circles(&files, "lib.rs").unwrap()),
            vec![vec!["a".to_string(), "b".to_string()]]
        );
    }

    #[test]
    fn super_paths_resolve_to_the_module_they_name() {
        let files = krate(&[
            ("lib.rs", "pub mod sampler;\n"),
            (
                "sampler/mod.rs",
                "pub mod abit;\npub mod termination;\npub use abit::Stop;\n",
            ),
            (
                "sampler/abit.rs",
                "use super::termination::Termination;\npub enum Stop { A }\n",
            ),
            // `super::Stop` is re-exported by the parent: it is abit's.
            (
                "sampler/termination.rs",
                "pub struct Termination;\nfn f(s: super::Stop) { let _ = super::super::sampler::abit::Stop::A; }\n",
            ),
        ]);
        let found = circles(&files, "lib.rs").unwrap();
        assert_eq!(
            modules_of(&found),
            vec![vec![
                "sampler::abit".to_string(),
                "sampler::termination".to_string()
            ]]
        );
        assert_eq!(found[0].takes[1].2, vec![("Stop".to_string(), 2)]);
        // A child using a name its parent defines (not re-exports) is an edge to the parent, and
        // the parent's `use` of the child closes a circle.
        let files = krate(&[
            ("lib.rs", "pub mod s;\n"),
            (
                "s/mod.rs",
                "mod k;\npub struct Shared;\nfn f() { k::go() }\n",
            ),
            ("s/k.rs", "use super::Shared;\npub fn go() {}\n"),
        ]);
        assert_eq!(
            modules_of(&circles(&files, "lib.rs").unwrap()),
            vec![vec!["s".to_string(), "s::k".to_string()]]
        );
    }

    #[test]
    fn a_parent_publishing_its_child_is_no_edge_unless_its_code_uses_the_name() {
        let files = |parent: &str| {
            krate(&[
                ("lib.rs", "pub mod s;\n"),
                ("s/mod.rs", parent),
                ("s/k.rs", "use super::Shared;\npub struct Kid;\n"),
            ])
        };
        let publishes = "mod k;\npub use k::Kid;\npub struct Shared;\n";
        assert_eq!(
            circles(&files(publishes), "lib.rs").unwrap(),
            Vec::<Circle>::new()
        );
        let uses = "mod k;\npub use k::Kid;\npub struct Shared;\npub fn f(_: Kid) {}\n";
        assert_eq!(
            modules_of(&circles(&files(uses), "lib.rs").unwrap()),
            vec![vec!["s".to_string(), "s::k".to_string()]]
        );
    }

    #[test]
    fn test_only_modules_and_items_are_ignored() {
        let files = krate(&[
            (
                "lib.rs",
                "pub mod a;\npub mod b;\n#[cfg(test)]\nmod tests_b;\n",
            ),
            (
                "a.rs",
                "use crate::b::Bee;\npub struct Ay;\n#[cfg(test)]\nmod tests {\n    use crate::b::*;\n    fn t() { let _ = crate::b::Bee; }\n}\n",
            ),
            (
                "b.rs",
                "pub struct Bee;\n#[cfg(test)]\nuse crate::a::Ay;\n#[cfg(test)]\n#[allow(dead_code)]\nfn t() -> crate::a::Ay { Ay }\n",
            ),
            ("tests_b.rs", "use crate::a::Ay;\nuse crate::b::Bee;\n"),
        ]);
        assert_eq!(circles(&files, "lib.rs").unwrap(), Vec::<Circle>::new());
    }

    #[test]
    fn paths_through_imported_modules_and_aliases_reach_the_deepest_module() {
        let files = krate(&[
            ("lib.rs", "pub mod x;\npub mod y;\n"),
            ("x/mod.rs", "pub mod deep;\n"),
            (
                "x/deep.rs",
                "pub struct D;\nfn f() -> crate::y::Why { todo!() }\n",
            ),
            (
                "y.rs",
                "use crate::x as ex;\npub struct Why;\nfn g() { let _ = ex::deep::D; }\n",
            ),
        ]);
        assert_eq!(
            modules_of(&circles(&files, "lib.rs").unwrap()),
            vec![vec!["x::deep".to_string(), "y".to_string()]]
        );
    }

    #[test]
    fn a_declared_module_without_a_file_is_an_error() {
        let files = krate(&[("lib.rs", "mod gone;\n")]);
        let err = circles(&files, "lib.rs").unwrap_err();
        assert!(err.contains("src/gone.rs"), "{err}");
    }

    /// The workspace's crates have no circles, the facade and the binary included.
    #[test]
    fn the_workspace_has_no_module_import_circles() {
        let root = crate::regress::case::workspace_root();
        let reports = check_workspace(&root, &[]).unwrap();
        assert!(reports.iter().any(|r| r.name.starts_with("crates/rappel")));
        let circles: Vec<String> = reports
            .iter()
            .flat_map(|r| r.circles.iter().map(move |c| format!("{}: {c}", r.name)))
            .collect();
        assert!(circles.is_empty(), "{}", circles.join("\n"));
    }
}
