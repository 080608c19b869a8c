//! The progress bar of long runs (standard error, only on a terminal).

/// A bar over `steps` steps on stderr; hidden when `enabled` is false or stderr is not a
/// terminal (so logs and tests see no control characters).
pub fn bar(steps: usize, enabled: bool) -> indicatif::ProgressBar {
    counted(steps, "steps", enabled)
}

/// A bar over `n` things named `what` (e.g. "cases"), as [`bar`].
pub fn counted(n: usize, what: &str, enabled: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !enabled || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let pb = indicatif::ProgressBar::new(n as u64);
    pb.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{{elapsed_precise}} [{{bar:40}}] {{pos}}/{{len}} {what} ({{per_sec}}, eta {{eta}})"
        ))
        .expect("valid template")
        .progress_chars("=> "),
    );
    pb
}
