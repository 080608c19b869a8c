//! README.md and docs/*.md as a tested guide: every fenced block marked ```` ```sh test ````
//! runs as written, in order per file, in one fresh folder outside the checkout, with the
//! built `tbi` first on `PATH`, and exits 0.

mod common;

use std::path::{Path, PathBuf};

/// The blocks of `markdown` whose info string is `sh test`, with their first line numbers.
fn tested_blocks(markdown: &str) -> Vec<(usize, String)> {
    let mut blocks = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (i, line) in markdown.lines().enumerate() {
        match &mut current {
            None if line.trim_start().starts_with("```") => {
                let info: Vec<&str> = line.trim_start()[3..].split_whitespace().collect();
                if info.first() == Some(&"sh") && info.contains(&"test") {
                    current = Some((i + 2, String::new()));
                } else {
                    // another block: skipped to its end
                    current = Some((0, String::new()));
                }
            }
            Some((start, body)) if line.trim() == "```" => {
                if *start > 0 {
                    blocks.push((*start, std::mem::take(body)));
                }
                current = None;
            }
            Some((_, body)) => {
                body.push_str(line);
                body.push('\n');
            }
            None => {}
        }
    }
    blocks
}

fn guides() -> Vec<PathBuf> {
    let root = common::repo_root();
    let mut files = vec![root.join("README.md")];
    if let Ok(dir) = std::fs::read_dir(root.join("docs")) {
        let mut docs: Vec<PathBuf> = dir
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "md"))
            .collect();
        docs.sort();
        files.extend(docs);
    }
    files
}

fn run_guide(file: &Path) -> usize {
    let text = std::fs::read_to_string(file).unwrap();
    let blocks = tested_blocks(&text);
    let name = file.file_stem().unwrap().to_string_lossy().to_string();
    let dir = std::env::temp_dir().join(format!("tbi-guide-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let bin = common::tbi().parent().unwrap().to_path_buf();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for (line, block) in &blocks {
        let out = std::process::Command::new("bash")
            .args(["-euo", "pipefail", "-c", block])
            .current_dir(&dir)
            .env("PATH", &path)
            .output()
            .unwrap();
        let (stdout, stderr) = (
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
        );
        println!("{}:{line}:\n{block}--- stdout\n{stdout}", file.display());
        assert!(
            out.status.success(),
            "{}:{line}: the block exited {}\n{block}--- stdout\n{stdout}--- stderr\n{stderr}",
            file.display(),
            out.status
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
    blocks.len()
}

#[test]
fn every_tested_block_runs_as_written() {
    let mut total = 0;
    for f in guides() {
        total += run_guide(&f);
    }
    assert!(total >= 4, "{total} tested blocks");
}

/// README.md is a guide, not a journal: at most 20 KB, and no commit hashes.
#[test]
fn the_readme_is_a_short_guide() {
    let text = std::fs::read_to_string(common::repo_root().join("README.md")).unwrap();
    assert!(text.len() <= 20 * 1024, "README.md is {} bytes", text.len());
    for word in text.split(|c: char| !c.is_ascii_alphanumeric()) {
        let hex = word.len() >= 7 && word.chars().all(|c| c.is_ascii_hexdigit());
        let has_letter = word.chars().any(|c| c.is_ascii_alphabetic());
        let has_digit = word.chars().any(|c| c.is_ascii_digit());
        assert!(
            !(hex && has_letter && has_digit),
            "README.md names {word}, like a commit"
        );
    }
}

/// The extraction: only `sh test` blocks, other blocks skipped whole.
#[test]
fn only_blocks_marked_for_testing_are_taken() {
    let md = "text\n```sh test\necho a\n```\n```toml\n```sh test\n```\n```sh\necho b\n```\n```\nplain\n```\n```sh test\necho c\necho d\n```\n";
    let b = tested_blocks(md);
    assert_eq!(
        b,
        [
            (3, "echo a\n".to_string()),
            (15, "echo c\necho d\n".to_string())
        ]
    );
}
