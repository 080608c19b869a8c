//! An output folder owned by one run at a time.
//!
//! `tbi run` (and each case of `tbi sweep`) claims its folder by creating the lock file
//! `.tbi-lock` (with the process id) before it writes anything there, and removes it when
//! done. A second run on the same folder is refused with a message naming the folder and
//! the process holding it; a lock left by a process that no longer exists is taken over.
//! Final files (`summary.json`) are written under a temporary name and renamed, so a reader
//! never sees half of one.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of the lock file inside an output folder.
pub const LOCK_FILE: &str = ".tbi-lock";

/// A claimed output folder; the claim ends when this value drops.
#[derive(Debug)]
pub struct OutputDir {
    path: PathBuf,
    lock: PathBuf,
}

impl OutputDir {
    /// Create `path` if needed and claim it.
    pub fn claim(path: &Path) -> Result<OutputDir, String> {
        std::fs::create_dir_all(path)
            .map_err(|e| format!("{}: cannot create output folder: {e}", path.display()))?;
        let lock = path.join(LOCK_FILE);
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&lock)
            {
                Ok(mut f) => {
                    let _ = writeln!(f, "{}", std::process::id());
                    return Ok(OutputDir {
                        path: path.to_path_buf(),
                        lock,
                    });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let holder = std::fs::read_to_string(&lock)
                        .ok()
                        .and_then(|s| s.trim().parse::<u32>().ok());
                    match holder {
                        Some(pid) if process_alive(pid) => {
                            return Err(format!(
                                "{}: output folder is in use by another tbi run (process {pid}; lock file {}); choose another folder with --out or wait for it to finish",
                                path.display(),
                                lock.display()
                            ))
                        }
                        // stale: the process is gone (or the file is not ours); take over
                        _ => {
                            let _ = std::fs::remove_file(&lock);
                        }
                    }
                }
                Err(e) => return Err(format!("{}: {e}", lock.display())),
            }
        }
        Err(format!(
            "{}: cannot take the lock file {}",
            path.display(),
            lock.display()
        ))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.lock);
    }
}

/// Whether a process with this id exists (on Linux; elsewhere every holder counts as alive).
pub fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        true
    }
}

/// Write `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), String> {
    replace_atomically(path, |tmp| std::fs::write(tmp, bytes))
}

/// Write `path` through a temporary file in the same folder, which `write` fills, and a
/// rename: on failure the temporary file is removed and `path` is left as it was.
pub fn replace_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> std::io::Result<()>,
) -> Result<(), String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let result = write(&tmp)
        .and_then(|_| std::fs::rename(&tmp, path))
        .map_err(|e| format!("{}: {e}", path.display()));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// A buffered file whose write errors name it ("history.csv: No space left on device").
pub struct NamedFile {
    path: PathBuf,
    inner: std::io::BufWriter<std::fs::File>,
}

impl NamedFile {
    pub fn create(path: &Path) -> Result<NamedFile, String> {
        let f = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(NamedFile {
            path: path.to_path_buf(),
            inner: std::io::BufWriter::new(f),
        })
    }

    fn named(&self, e: std::io::Error) -> std::io::Error {
        std::io::Error::new(e.kind(), format!("{}: {e}", self.path.display()))
    }
}

impl Write for NamedFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.inner.write(buf).map_err(|e| self.named(e))
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush().map_err(|e| self.named(e))
    }
}

/// A temporary folder under `$TMPDIR` (`<prefix>-<pid>-<n>`), removed with its content when
/// this value drops; those of the same prefix left by a killed process are removed first.
#[derive(Debug)]
pub struct TempDir {
    path: PathBuf,
}

impl TempDir {
    pub fn new(prefix: &str) -> Result<TempDir, String> {
        static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        fmi_import::archive::UnpackedDir::remove_stale(prefix);
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!("{prefix}-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(TempDir { path })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}

/// `path` with `suffix` appended to its file name (`out.csv` + `.partial`).
pub fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(suffix);
    PathBuf::from(name)
}

/// The file `path` names, resolved: the canonical path where it exists, else its folder's
/// canonical path joined with its name.
fn resolved(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    match (std::fs::canonicalize(parent), path.file_name()) {
        (Ok(dir), Some(name)) => dir.join(name),
        _ => path.to_path_buf(),
    }
}

/// Refuse to write any of `outputs` when it is one of `inputs` (`(path, what it is)`):
/// an output never replaces the system, an FMU or a data file it was made from.
pub fn refuse_inputs(outputs: &[PathBuf], inputs: &[(PathBuf, String)]) -> Result<(), String> {
    for out in outputs {
        let o = resolved(out);
        if let Some((path, what)) = inputs.iter().find(|(p, _)| resolved(p) == o) {
            return Err(format!(
                "{}: this output would replace {what} {}; choose another --output",
                out.display(),
                path.display()
            ));
        }
    }
    Ok(())
}
