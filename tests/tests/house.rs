//! The house rules of the workspace's non-test code: every `<crate>/src/**/*.rs` of every
//! crate found by walking the workspace (a directory with a `Cargo.toml` and a `src/`),
//! without its `#[cfg(test)]` modules; `tests/`, `benches/`, `examples/` and `build.rs` are
//! not checked.
//!
//! * No import circles: within a crate, no files depend on each other round a loop through
//!   `crate::`, `super::` or `self::` paths (a parent naming its children is structure, not a
//!   dependency, and so is naming the crate root). Files in a circle can be neither read,
//!   tested nor moved one without the others: they are one module spread over several files.
//! * Files of at most 800 lines: a file is what one reads and reviews at a time; a longer
//!   one holds more than one idea.
//! * Functions of at most 150 lines, from `fn` to the closing brace: a function should fit
//!   in one's head; a longer one is a sequence of steps that want names.
//! * No crate over 22 % of the workspace's lines (the `tests` crate not counted): one crate
//!   doing most of the work is a monolith with satellites, slow to build and hard to own.
//!
//! Known violations are listed below, each with its reason. A violation missing from its
//! list fails, and so does a listed one that no longer violates: the lists only shrink.

use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const MAX_FILE_LINES: usize = 800;
const MAX_FN_LINES: usize = 150;
const MAX_CRATE_PERCENT: f64 = 22.0;

/// Known import circles, each the sorted files of one circle (from the workspace root).
const CIRCLES: &[&[&str]] = &[];

/// Known files over 800 non-test lines.
const LONG_FILES: &[&str] = &[];

/// Known functions over 150 lines, as `file::name`.
const LONG_FUNCTIONS: &[&str] = &[];

/// Known crates over 22 % of the workspace's non-test lines, by directory.
const BIG_CRATES: &[&str] = &[];

/// Directories never searched for crates (besides hidden ones and Python venvs).
const SKIP_DIRS: &[&str] = &["target", "node_modules", "__pycache__"];

/// One non-test source file.
struct SourceFile {
    /// Path from the workspace root, `/`-separated.
    path: String,
    /// Module path within the crate (empty for `src/lib.rs` and `src/main.rs`).
    module: Vec<String>,
    /// The text with comments, literals and `#[cfg(test)]` modules blanked: ASCII only,
    /// with the line breaks of the file.
    code: String,
    /// Lines without those of `#[cfg(test)]` modules.
    lines: usize,
}

/// One crate: its directory from the workspace root and its source files, sorted by path.
struct Crate {
    dir: String,
    files: Vec<SourceFile>,
}

/// Every crate of the workspace, read once.
fn workspace() -> &'static [Crate] {
    static CRATES: OnceLock<Vec<Crate>> = OnceLock::new();
    CRATES.get_or_init(|| {
        let root = workspace_root();
        let mut all = Vec::new();
        walk(&root, &mut all);
        all.sort();
        let crates: Vec<Crate> = all
            .iter()
            .filter(|p| p.ends_with("Cargo.toml") && p.with_file_name("src").is_dir())
            .filter_map(|manifest| Some(load_crate(&root, manifest.parent()?, &all)))
            .collect();
        let manifest = fs::read_to_string(root.join("Cargo.toml")).unwrap_or_default();
        let members = manifest
            .split("\nmembers")
            .nth(1)
            .and_then(|m| m.split(']').next());
        for member in members.unwrap_or("").split('"').skip(1).step_by(2) {
            let found = crates.iter().any(|c| c.dir == member);
            let has_src = root.join(member).join("src").is_dir();
            assert!(
                found || !has_src,
                "workspace member {member} not found by the walk"
            );
        }
        let files: usize = crates.iter().map(|c| c.files.len()).sum();
        let lines: usize = crates.iter().map(crate_lines).sum();
        eprintln!(
            "house: {} crates, {files} source files, {lines} non-test lines",
            crates.len()
        );
        crates
    })
}

/// The directory whose `Cargo.toml` has the `[workspace]` table.
fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .find(|dir| {
            fs::read_to_string(dir.join("Cargo.toml"))
                .is_ok_and(|text| text.lines().any(|line| line.trim() == "[workspace]"))
        })
        .expect("no workspace Cargo.toml above this crate")
        .to_path_buf()
}

/// `path` from `root`, `/`-separated.
fn relative(root: &Path, path: &Path) -> String {
    let path = path.strip_prefix(root).unwrap_or(path);
    path.to_string_lossy()
        .replace(std::path::MAIN_SEPARATOR, "/")
}

/// Every file under `dir`, except in hidden directories, Python venvs and [`SKIP_DIRS`].
fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).into_iter().flatten().flatten() {
        let (name, path) = (entry.file_name(), entry.path());
        let name = name.to_string_lossy();
        if !entry.file_type().is_ok_and(|t| t.is_dir()) {
            out.push(path);
        } else if !name.starts_with('.')
            && !SKIP_DIRS.contains(&name.as_ref())
            && !path.join("pyvenv.cfg").exists()
        {
            walk(&path, out);
        }
    }
}

/// The crate in `dir`, with its `.rs` files under `src/` among `all`.
fn load_crate(root: &Path, dir: &Path, all: &[PathBuf]) -> Crate {
    let src = dir.join("src");
    let mut files: Vec<SourceFile> = all
        .iter()
        .filter(|p| p.starts_with(&src) && p.extension().is_some_and(|e| e == "rs"))
        .map(|path| {
            let text = fs::read_to_string(path)
                .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
            let mut code = blank_literals(&text);
            let test_lines = blank_test_modules(&mut code);
            SourceFile {
                path: relative(root, path),
                module: module_path(&relative(dir, path)),
                code: String::from_utf8(code).expect("blanked code is ASCII"),
                lines: text.lines().count().saturating_sub(test_lines),
            }
        })
        .collect();
    files.sort_by(|a, b| a.path.cmp(&b.path));
    Crate {
        dir: relative(root, dir),
        files,
    }
}

/// The module of a file given by its path in the crate (`src/a/b.rs` is `a::b`).
fn module_path(local: &str) -> Vec<String> {
    let inner = local.strip_prefix("src/").unwrap_or(local);
    let inner = inner.trim_end_matches(".rs").trim_end_matches("/mod");
    if inner == "lib" || inner == "main" {
        return Vec::new();
    }
    inner.split('/').map(str::to_string).collect()
}

fn crate_lines(krate: &Crate) -> usize {
    krate.files.iter().map(|f| f.lines).sum()
}

/// `src` with comments and string, raw-string and char literals replaced by spaces (line
/// breaks kept), and any other non-ASCII char by `x`, so that bytes are chars.
fn blank_literals(src: &str) -> Vec<u8> {
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::with_capacity(chars.len());
    let mut i = 0;
    while i < chars.len() {
        if let Some(end) = literal_end(&chars, i) {
            let end = end.min(chars.len());
            out.extend(
                chars[i..end]
                    .iter()
                    .map(|&c| if c == '\n' { c } else { ' ' } as u8),
            );
            i = end;
        } else {
            out.push(
                u8::try_from(chars[i])
                    .ok()
                    .filter(u8::is_ascii)
                    .unwrap_or(b'x'),
            );
            i += 1;
        }
    }
    out
}

/// Where the comment or literal starting at `i` ends (exclusive), if one starts there.
fn literal_end(c: &[char], i: usize) -> Option<usize> {
    let at = |k: usize| c.get(k).copied().unwrap_or('\0');
    match (at(i), at(i + 1)) {
        ('/', '/') => Some((i..c.len()).find(|&k| c[k] == '\n').unwrap_or(c.len())),
        ('/', '*') => Some(block_comment_end(c, i)),
        ('"', _) => Some(quoted_end(c, i + 1, '"')),
        ('\'', '\\') => Some(quoted_end(c, i + 1, '\'')),
        ('\'', _) if at(i + 2) == '\'' => Some(i + 3),
        ('r', '"' | '#') if raw_prefix_at(c, i) => raw_string_end(c, i + 1),
        _ => None,
    }
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Whether the `r` at `i` starts a raw string prefix (`r`, `br` or `cr`, not inside a word).
fn raw_prefix_at(c: &[char], i: usize) -> bool {
    let ident_at = |k: Option<usize>| k.is_some_and(|k| is_ident_char(c[k]));
    !ident_at(i.checked_sub(1)) || (matches!(c[i - 1], 'b' | 'c') && !ident_at(i.checked_sub(2)))
}

fn block_comment_end(c: &[char], mut k: usize) -> usize {
    let mut depth = 0;
    while k + 1 < c.len() {
        let delta = match (c[k], c[k + 1]) {
            ('/', '*') => 1,
            ('*', '/') => -1,
            _ => 0,
        };
        depth += delta;
        k += if delta == 0 { 1 } else { 2 };
        if delta != 0 && depth == 0 {
            return k;
        }
    }
    c.len()
}

/// The end of a quoted literal whose text starts at `k`, backslash escapes skipped.
fn quoted_end(c: &[char], mut k: usize, quote: char) -> usize {
    while k < c.len() {
        match c[k] {
            '\\' => k += 2,
            q if q == quote => return k + 1,
            _ => k += 1,
        }
    }
    c.len()
}

/// The end of a raw string whose hashes (if any) start at `k`; None if none starts there.
fn raw_string_end(c: &[char], k: usize) -> Option<usize> {
    let hashes = c[k..].iter().take_while(|&&ch| ch == '#').count();
    if c.get(k + hashes) != Some(&'"') {
        return None;
    }
    let body = k + hashes + 1;
    (body..c.len())
        .find(|&e| c[e] == '"' && (1..=hashes).all(|h| c.get(e + h) == Some(&'#')))
        .map(|e| e + 1 + hashes)
        .or(Some(c.len()))
}

/// Blanks every `#[cfg(test)]` module (from its attribute's line to its closing brace) and
/// returns how many lines those took.
fn blank_test_modules(code: &mut [u8]) -> usize {
    const ATTRIBUTE: &[u8] = b"#[cfg(test)]";
    let mut removed = 0;
    let mut from = 0;
    while let Some(found) = code[from..]
        .windows(ATTRIBUTE.len())
        .position(|w| w == ATTRIBUTE)
        .map(|p| p + from)
    {
        from = found + 1;
        let line_start = code[..found]
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1);
        if !code[line_start..found].iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let Some(open) = test_module_body(code, found + ATTRIBUTE.len()) else {
            continue;
        };
        let Some(close) = matching(code, open) else {
            continue;
        };
        removed += code[found..close].iter().filter(|&&b| b == b'\n').count() + 1;
        for b in &mut code[found..=close] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
        from = close;
    }
    removed
}

/// The opening brace of the `mod name {` after an attribute ending at `i` (more attributes
/// may come between), if a module with a body follows.
fn test_module_body(code: &[u8], mut i: usize) -> Option<usize> {
    loop {
        while code.get(i).is_some_and(u8::is_ascii_whitespace) {
            i += 1;
        }
        if !code[i..].starts_with(b"#[") {
            break;
        }
        i = matching(code, i + 1)? + 1;
    }
    let end = i + code[i..].iter().position(|&b| b == b'{' || b == b';')?;
    let head = std::str::from_utf8(&code[i..end]).ok()?;
    (code[end] == b'{' && head.split_whitespace().rev().nth(1) == Some("mod")).then_some(end)
}

/// The bracket closing the one (`{`, `[` or `(`) at `open`, in blanked code.
fn matching(code: &[u8], open: usize) -> Option<usize> {
    let close = match code[open] {
        b'{' => b'}',
        b'[' => b']',
        _ => b')',
    };
    let mut depth = 0usize;
    code.iter().enumerate().skip(open).find_map(|(k, &b)| {
        depth += usize::from(b == code[open]);
        depth -= usize::from(b == close);
        (depth == 0).then_some(k)
    })
}

fn line_of(code: &str, pos: usize) -> usize {
    code[..pos].matches('\n').count() + 1
}

/// The tokens of blanked code with their offsets: words, `::` and single punctuation.
fn tokens(code: &str) -> Vec<(usize, &str)> {
    let bytes = code.as_bytes();
    let word = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let start = i;
        if word(bytes[i]) {
            while i < bytes.len() && word(bytes[i]) {
                i += 1;
            }
        } else if bytes[i..].starts_with(b"::") {
            i += 2;
        } else {
            i += 1;
            if bytes[start].is_ascii_whitespace() {
                continue;
            }
        }
        out.push((start, &code[start..i]));
    }
    out
}

fn is_word(token: &str) -> bool {
    token.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
}

/// The modules (as absolute paths in the crate, possibly naming items below them) that
/// `code` of module `module` names through `crate::`, `super::` or `self::`, with offsets.
fn mentioned_paths(code: &str, module: &[String]) -> Vec<(usize, Vec<String>)> {
    let toks = tokens(code);
    let words: Vec<&str> = toks.iter().map(|t| t.1).collect();
    let tok = |k: usize| words.get(k).copied().unwrap_or("");
    let mut out = Vec::new();
    for (k, &(pos, word)) in toks.iter().enumerate() {
        let after_path = k > 0 && tok(k - 1) == "::";
        let visibility = k > 1 && tok(k - 1) == "in" && tok(k - 2) == "(";
        if after_path
            || visibility
            || !matches!((word, tok(k + 1)), ("crate" | "super" | "self", "::"))
        {
            continue;
        }
        let mut base = module.to_vec();
        if word == "crate" {
            base.clear();
        }
        let mut next = k + 2;
        if word == "super" {
            base.pop();
            while tok(next) == "super" && tok(next + 1) == "::" {
                base.pop();
                next += 2;
            }
        }
        let mut paths = Vec::new();
        path_tail(&words, next, base, &mut paths);
        out.extend(paths.into_iter().map(|p| (pos, p)));
    }
    out
}

/// Reads the path after `prefix::` from token `k` (groups `{a, b::c}` give one path per
/// member) into `out`; returns the token after it.
fn path_tail(
    t: &[&str],
    mut k: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<Vec<String>>,
) -> usize {
    let tok = |i: usize| t.get(i).copied().unwrap_or("");
    while is_word(tok(k)) {
        prefix.push(tok(k).to_string());
        if tok(k + 1) != "::" {
            out.push(prefix);
            return k + 1;
        }
        k += 2;
    }
    if tok(k) != "{" {
        out.push(prefix);
        return k;
    }
    k += 1;
    while !matches!(tok(k), "}" | "") {
        k = path_tail(t, k, prefix.clone(), out);
        while !matches!(tok(k), "," | "}" | "") {
            k += 1;
        }
        if tok(k) == "," {
            k += 1;
        }
    }
    k + 1
}

/// The crate's import graph: for each file, the files it depends on, each with the first
/// mention (line, path) that makes it so.
fn import_graph(krate: &Crate) -> Vec<BTreeMap<usize, (usize, String)>> {
    let by_module: HashMap<String, usize> = krate
        .files
        .iter()
        .enumerate()
        .map(|(i, f)| (f.module.join("::"), i))
        .collect();
    let mut graph = vec![BTreeMap::new(); krate.files.len()];
    for (from, file) in krate.files.iter().enumerate() {
        for (pos, path) in mentioned_paths(&file.code, &file.module) {
            let Some(to) = (1..=path.len())
                .rev()
                .find_map(|n| by_module.get(&path[..n].join("::")).copied())
            else {
                continue;
            };
            let target = &krate.files[to].module;
            let descendant =
                target.len() >= file.module.len() && target[..file.module.len()] == file.module[..];
            if target.is_empty() || descendant {
                continue;
            }
            graph[from]
                .entry(to)
                .or_insert_with(|| (line_of(&file.code, pos), path.join("::")));
        }
    }
    graph
}

/// The files of each circle (strongly connected set of more than one file), ascending.
fn circles(graph: &[BTreeMap<usize, (usize, String)>]) -> Vec<Vec<usize>> {
    let n = graph.len();
    let reach: Vec<Vec<bool>> = (0..n)
        .map(|start| {
            let (mut seen, mut todo) = (vec![false; n], vec![start]);
            while let Some(v) = todo.pop() {
                todo.extend(
                    graph[v]
                        .keys()
                        .filter(|&&w| !std::mem::replace(&mut seen[w], true)),
                );
            }
            seen
        })
        .collect();
    (0..n)
        .map(|i| {
            (0..n)
                .filter(|&j| j == i || (reach[i][j] && reach[j][i]))
                .collect()
        })
        .enumerate()
        .filter(|(i, set): &(usize, Vec<usize>)| set.len() > 1 && set[0] == *i)
        .map(|(_, set)| set)
        .collect()
}

/// Every function with a body: name, line of `fn`, and lines from there to its closing brace.
fn functions(code: &str) -> Vec<(String, usize, usize)> {
    let toks = tokens(code);
    let mut out = Vec::new();
    for (k, &(pos, word)) in toks.iter().enumerate() {
        let name = toks.get(k + 1).map_or("", |t| t.1);
        if word != "fn" || !is_word(name) {
            continue;
        }
        let mut depth = 0i32;
        let body = toks[k + 2..].iter().find_map(|&(p, t)| {
            match t {
                "(" | "[" => depth += 1,
                ")" | "]" => depth -= 1,
                "{" | ";" if depth == 0 => return Some((t == "{").then_some(p)),
                _ => {}
            }
            None
        });
        let Some(close) = body
            .flatten()
            .and_then(|open| matching(code.as_bytes(), open))
        else {
            continue;
        };
        let first = line_of(code, pos);
        out.push((name.to_string(), first, line_of(code, close) - first + 1));
    }
    out
}

/// Fails on every finding of `rule` (key to description) not in the allowlist `list`, and on
/// every entry of the list no longer found (`now` gives its current measure, if any).
fn enforce(
    rule: &str,
    hint: &str,
    (list, allowed): (&str, &[&str]),
    found: &BTreeMap<String, String>,
    now: impl Fn(&str) -> Option<String>,
) {
    for detail in found.values() {
        eprintln!("house:   {detail}");
    }
    let mut problems: Vec<String> = found
        .iter()
        .filter(|(key, _)| !allowed.contains(&key.as_str()))
        .map(|(_, detail)| detail.clone())
        .collect();
    problems.extend(
        allowed
            .iter()
            .filter(|key| !found.contains_key(**key))
            .map(|key| {
                let now = now(key).map_or("no longer found".to_string(), |n| format!("now {n}"));
                format!("remove {key} from {list}: it is {now}")
            }),
    );
    assert!(
        problems.is_empty(),
        "house rule {rule}: {} problem(s); {hint} (known ones are listed in {list})\n\n  {}\n",
        problems.len(),
        problems.join("\n  ")
    );
}

#[test]
fn no_import_circles() {
    let mut found = BTreeMap::new();
    for krate in workspace() {
        let graph = import_graph(krate);
        for circle in circles(&graph) {
            let local = |i: usize| &krate.files[i].path[krate.dir.len() + 1..];
            let names: Vec<&str> = circle.iter().map(|&i| local(i)).collect();
            let mut detail = format!("circle in {}: {}", krate.dir, names.join(" ↔ "));
            for &from in &circle {
                for (to, (line, path)) in &graph[from] {
                    if circle.contains(to) {
                        let (f, t) = (local(from), local(*to));
                        detail += &format!("\n      {f} → {t} ({f}:{line} names {path})");
                    }
                }
            }
            let files: Vec<&str> = circle
                .iter()
                .map(|&i| krate.files[i].path.as_str())
                .collect();
            found.insert(files.join(" ↔ "), detail);
        }
    }
    eprintln!("house: {} import circle(s)", found.len());
    let allowed: Vec<String> = CIRCLES.iter().map(|files| files.join(" ↔ ")).collect();
    let allowed: Vec<&str> = allowed.iter().map(String::as_str).collect();
    let hint = "break a circle by moving what its files share into a module of its own";
    enforce(
        "no_import_circles",
        hint,
        ("CIRCLES", &allowed),
        &found,
        |_| None,
    );
}

#[test]
fn files_under_800_lines() {
    let lines: BTreeMap<&str, usize> = workspace()
        .iter()
        .flat_map(|c| &c.files)
        .map(|f| (f.path.as_str(), f.lines))
        .collect();
    let found: BTreeMap<String, String> = lines
        .iter()
        .filter(|(_, &n)| n > MAX_FILE_LINES)
        .map(|(path, n)| {
            let detail = format!("{path} has {n} non-test lines (limit {MAX_FILE_LINES})");
            (path.to_string(), detail)
        })
        .collect();
    eprintln!("house: {} file(s) over {MAX_FILE_LINES} lines", found.len());
    let hint = "split a long file into modules";
    enforce(
        "files_under_800_lines",
        hint,
        ("LONG_FILES", LONG_FILES),
        &found,
        |key| lines.get(key).map(|n| format!("{n} lines")),
    );
}

#[test]
fn functions_under_150_lines() {
    // Longest function of each `file::name` (a name may be defined by several impls).
    let mut longest: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for file in workspace().iter().flat_map(|c| &c.files) {
        for (name, line, length) in functions(&file.code) {
            let entry = longest
                .entry(format!("{}::{name}", file.path))
                .or_insert((line, length));
            if length > entry.1 {
                *entry = (line, length);
            }
        }
    }
    let found: BTreeMap<String, String> = longest
        .iter()
        .filter(|(_, &(_, length))| length > MAX_FN_LINES)
        .map(|(key, (line, length))| {
            let detail = format!("{key} is {length} lines from line {line} (limit {MAX_FN_LINES})");
            (key.clone(), detail)
        })
        .collect();
    eprintln!(
        "house: {} of {} functions over {MAX_FN_LINES} lines",
        found.len(),
        longest.len()
    );
    let (hint, list) = ("split a long function into named steps", LONG_FUNCTIONS);
    enforce(
        "functions_under_150_lines",
        hint,
        ("LONG_FUNCTIONS", list),
        &found,
        |key| {
            longest
                .get(key)
                .map(|(_, length)| format!("{length} lines"))
        },
    );
}

#[test]
fn no_crate_over_22_percent() {
    let own = relative(&workspace_root(), Path::new(env!("CARGO_MANIFEST_DIR")));
    let counted: Vec<(&str, usize)> = workspace()
        .iter()
        .filter(|c| c.dir != own)
        .map(|c| (c.dir.as_str(), crate_lines(c)))
        .collect();
    let total: usize = counted.iter().map(|c| c.1).sum();
    let share: BTreeMap<&str, f64> = counted
        .iter()
        .map(|&(dir, n)| (dir, 100.0 * n as f64 / total.max(1) as f64))
        .collect();
    for (dir, n) in &counted {
        eprintln!("house:   {dir}: {n} lines, {:.1} %", share[dir]);
    }
    let found: BTreeMap<String, String> = counted
        .iter()
        .filter(|(dir, _)| share[dir] > MAX_CRATE_PERCENT)
        .map(|&(dir, n)| {
            let detail = format!(
                "{dir} has {:.1} % of the workspace's non-test lines ({n} of {total}; limit {MAX_CRATE_PERCENT} %)",
                share[dir]
            );
            (dir.to_string(), detail)
        })
        .collect();
    eprintln!(
        "house: {} of {} crates over {MAX_CRATE_PERCENT} % of {total} lines",
        found.len(),
        counted.len()
    );
    let hint = "move a part of a big crate into a crate of its own";
    enforce(
        "no_crate_over_22_percent",
        hint,
        ("BIG_CRATES", BIG_CRATES),
        &found,
        |key| share.get(key).map(|p| format!("{p:.1} %")),
    );
}

#[test]
fn the_scanner_sees_code_only() {
    let src = "fn a<'x>(v: &'x str) {\n    let s = \"}\"; // }\n    let r = r#\"{\"#;\n    \
               let c = '{';\n    /* { /* } */ */\n}\nfn decl(x: [u8; 2]);\n#[cfg(test)]\n\
               #[allow(unused)]\nmod tests {\n    fn b() {}\n}\n";
    let mut code = blank_literals(src);
    assert_eq!(blank_test_modules(&mut code), 5);
    let code = String::from_utf8(code).unwrap();
    assert_eq!(functions(&code), [("a".to_string(), 1, 6)]);
    let module = ["x".to_string(), "y".to_string()];
    let text =
        "use crate::{a, b::{c, d as e}};\nuse super::super::f::G;\npub(in crate::h) fn i() {}";
    let paths: Vec<String> = mentioned_paths(text, &module)
        .into_iter()
        .map(|(_, path)| path.join("::"))
        .collect();
    assert_eq!(paths, ["a", "b::c", "b::d", "f::G"]);
}
