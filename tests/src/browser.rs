//! Headless Chromium for the report tests: installed once by `tests/browser/setup.sh`,
//! started with the flags this machine's closed network needs and a fresh profile.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The browser `tests/browser/setup.sh` installs (or finds).
pub fn path() -> PathBuf {
    let out = crate::run(Command::new("bash").arg(crate::repo_path("tests/browser/setup.sh")));
    assert!(
        out.status.success(),
        "tests/browser/setup.sh: {}",
        crate::text(&out.stderr)
    );
    PathBuf::from(
        crate::text(&out.stdout)
            .lines()
            .last()
            .expect("a path")
            .trim(),
    )
}

/// Open `page` headless with a fresh profile in `profile` and these `extra` arguments
/// (`--dump-dom`, `--screenshot=…`); the browser's output, its log on stderr.
pub fn open(page: &Path, profile: &Path, extra: &[String]) -> Output {
    crate::run(
        Command::new(path())
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--enable-logging=stderr",
                "--v=0",
            ])
            .arg(format!("--user-data-dir={}", profile.display()))
            .args(extra)
            .arg(format!("file://{}", page.display())),
    )
}

/// A report page is one self-contained file: nothing loaded from elsewhere, no scripts.
pub fn assert_self_contained(html: &str) {
    for needle in ["src=\"http", "href=\"http", "<script", "<link", "<img"] {
        assert!(!html.contains(needle), "the page has {needle}");
    }
}
