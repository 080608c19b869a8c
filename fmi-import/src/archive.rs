//! Unpacking an FMU archive safely, and the `file:` URI of a directory.
//!
//! An FMU is a zip file from an arbitrary source. [`unpack`] extracts it into a fresh,
//! private (mode 0700) temporary directory that it alone writes to, and refuses — naming
//! the FMU and the entry — anything that could write outside that directory or exhaust
//! the machine:
//!
//! - entry names that are absolute (`/x`, `C:x`), contain a backslash, a NUL, or a `..`
//!   component, or that occur twice;
//! - symbolic links and other non-regular entries (devices, FIFOs);
//! - encrypted entries;
//! - more than [`UnpackLimits::max_entries`] entries, an entry larger than
//!   [`UnpackLimits::max_entry_size`], or more than [`UnpackLimits::max_total_size`] in
//!   all. Sizes are enforced on the bytes actually inflated, not on the sizes the archive
//!   declares, so a forged header cannot bypass them.
//!
//! Files are created with `create_new`, so an existing path is never overwritten or
//! followed. The directory is removed when the returned [`UnpackedDir`] is dropped.

use super::error::FmiError;
use std::collections::HashSet;
use std::fs;
use std::io::{self, Read, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Bounds on what an archive may expand to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnpackLimits {
    /// Maximum number of entries (files and directories). Default 10 000.
    pub max_entries: usize,
    /// Maximum inflated size of one entry in bytes. Default 256 MiB.
    pub max_entry_size: u64,
    /// Maximum inflated size of all entries together in bytes. Default 512 MiB (the
    /// project's largest FMU, the Tsing Ma bridge, unpacks to about 3 MB).
    pub max_total_size: u64,
}

impl Default for UnpackLimits {
    fn default() -> Self {
        Self {
            max_entries: 10_000,
            max_entry_size: 256 << 20,
            max_total_size: 512 << 20,
        }
    }
}

/// A temporary directory that is deleted (recursively) on drop.
#[derive(Debug)]
pub struct UnpackedDir {
    path: PathBuf,
}

impl UnpackedDir {
    /// Create a new empty private directory under the system temporary directory.
    pub fn create(prefix: &str) -> io::Result<Self> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let base = std::env::temp_dir();
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        for _ in 0..100 {
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let path = base.join(format!("{prefix}-{}-{nanos:08x}-{n}", std::process::id()));
            let mut builder = fs::DirBuilder::new();
            #[cfg(unix)]
            {
                use std::os::unix::fs::DirBuilderExt;
                builder.mode(0o700);
            }
            match builder.create(&path) {
                Ok(()) => {
                    // canonical, so that URIs and library paths are absolute and free of
                    // symbolic links in the temp dir's own path
                    let path = fs::canonicalize(&path)?;
                    return Ok(Self { path });
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            }
        }
        Err(io::Error::new(
            io::ErrorKind::AlreadyExists,
            "could not find an unused temporary directory name",
        ))
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Remove the directories `{prefix}-{pid}-…` of the process `pid` (a worker that was
    /// ended or died) in the temporary directory.
    pub fn remove_of_process(prefix: &str, pid: u32) {
        remove_dirs(prefix, |p| p == pid);
    }

    /// Remove the directories `{prefix}-{pid}-…` in the temporary directory whose process
    /// no longer exists (left by a run that was killed). Linux only; elsewhere nothing.
    pub fn remove_stale(prefix: &str) {
        if !cfg!(target_os = "linux") {
            return;
        }
        remove_dirs(prefix, |pid| {
            pid != std::process::id() && !Path::new("/proc").join(pid.to_string()).exists()
        });
    }
}

/// Remove the directories `{prefix}-{pid}-…` in the temporary directory whose `pid` is
/// `chosen`.
fn remove_dirs(prefix: &str, chosen: impl Fn(u32) -> bool) {
    let Ok(entries) = fs::read_dir(std::env::temp_dir()) else {
        return;
    };
    let head = format!("{prefix}-");
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let pid = name
            .strip_prefix(&head)
            .and_then(|rest| rest.split('-').next())
            .and_then(|p| p.parse::<u32>().ok());
        if pid.is_some_and(&chosen) {
            let _ = fs::remove_dir_all(entry.path());
        }
    }
}

impl Drop for UnpackedDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.path);
    }
}

/// The display name used for an FMU in messages: its file name.
pub fn fmu_display_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// Check an entry name and turn it into a relative path with only normal components.
fn safe_relative_path(name: &str) -> Result<PathBuf, String> {
    if name.is_empty() {
        return Err("empty entry name".into());
    }
    if name.contains('\0') {
        return Err("the name contains a NUL character".into());
    }
    if name.contains('\\') {
        return Err("the name contains a backslash (FMU paths use forward slashes)".into());
    }
    if name.starts_with('/') {
        return Err("absolute path".into());
    }
    if name.contains(':') {
        return Err("the name contains a drive or device separator ':'".into());
    }
    let mut path = PathBuf::new();
    for component in Path::new(name).components() {
        match component {
            Component::Normal(c) => path.push(c),
            Component::CurDir => {}
            Component::ParentDir => return Err("the path contains a '..' component".into()),
            Component::RootDir | Component::Prefix(_) => return Err("absolute path".into()),
        }
    }
    if path.as_os_str().is_empty() {
        return Err("the name has no file or directory component".into());
    }
    Ok(path)
}

/// Extract the FMU at `fmu` into a new temporary directory (see the module docs).
pub fn unpack(fmu: &Path, limits: &UnpackLimits) -> Result<UnpackedDir, FmiError> {
    let fmu_name = fmu_display_name(fmu);
    let archive_error = |entry: Option<&str>, message: String| FmiError::Archive {
        fmu: fmu_name.clone(),
        entry: entry.map(str::to_owned),
        message,
    };
    let file = fs::File::open(fmu)
        .map_err(|e| archive_error(None, format!("cannot open {}: {e}", fmu.display())))?;
    let mut archive = zip::ZipArchive::new(io::BufReader::new(file))
        .map_err(|e| archive_error(None, format!("not a valid zip archive ({e})")))?;
    // The zip reader indexes entries by name and keeps one of two equal names; refuse
    // archives whose central directory repeats a name (which of the two would be used?).
    if let Some(name) = repeated_name(fmu) {
        return Err(archive_error(
            Some(&name),
            "the archive holds this path twice".into(),
        ));
    }
    if archive.len() > limits.max_entries {
        return Err(archive_error(
            None,
            format!(
                "the archive has {} entries, more than the limit of {}",
                archive.len(),
                limits.max_entries
            ),
        ));
    }
    UnpackedDir::remove_stale("tbi-fmu");
    let dir = UnpackedDir::create("tbi-fmu")
        .map_err(|e| archive_error(None, format!("cannot create a temporary directory: {e}")))?;

    let mut seen = HashSet::new();
    let mut total: u64 = 0;
    for i in 0..archive.len() {
        let mut entry = archive
            .by_index(i)
            .map_err(|e| archive_error(None, format!("cannot read entry {}: {e}", i + 1)))?;
        let name = entry
            .name()
            .map_err(|e| {
                archive_error(None, format!("entry {} has an unreadable name: {e}", i + 1))
            })?
            .into_owned();
        let relative = safe_relative_path(&name).map_err(|m| archive_error(Some(&name), m))?;
        if !seen.insert(relative.clone()) {
            return Err(archive_error(
                Some(&name),
                "the archive holds this path twice".into(),
            ));
        }
        if entry.is_symlink() {
            return Err(archive_error(
                Some(&name),
                "symbolic links are not allowed in an FMU".into(),
            ));
        }
        if let Some(mode) = entry.unix_mode() {
            let kind = mode & 0o170000;
            if kind != 0 && kind != 0o100000 && kind != 0o040000 {
                return Err(archive_error(
                    Some(&name),
                    format!("special file (mode {mode:o}) is not allowed in an FMU"),
                ));
            }
        }
        if entry.encrypted() {
            return Err(archive_error(
                Some(&name),
                "encrypted entries are not supported".into(),
            ));
        }
        let target = dir.path().join(&relative);
        if entry.is_dir() {
            fs::create_dir_all(&target).map_err(|e| {
                archive_error(Some(&name), format!("cannot create the directory: {e}"))
            })?;
            continue;
        }
        if entry.size() > limits.max_entry_size {
            return Err(archive_error(
                Some(&name),
                format!(
                    "declared size {} bytes exceeds the limit of {} bytes per entry",
                    entry.size(),
                    limits.max_entry_size
                ),
            ));
        }
        if let Some(parent) = target.parent() {
            fs::create_dir_all(parent).map_err(|e| {
                archive_error(
                    Some(&name),
                    format!("cannot create the parent directory: {e}"),
                )
            })?;
        }
        let mut out = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&target)
            .map_err(|e| archive_error(Some(&name), format!("cannot create the file: {e}")))?;
        let allowed = limits
            .max_entry_size
            .min(limits.max_total_size.saturating_sub(total));
        let mut limited = (&mut entry).take(allowed.saturating_add(1));
        let written = copy(&mut limited, &mut out)
            .map_err(|e| archive_error(Some(&name), format!("cannot extract: {e}")))?;
        if written > allowed {
            let message = if written > limits.max_entry_size {
                format!(
                    "inflates to more than the limit of {} bytes per entry",
                    limits.max_entry_size
                )
            } else {
                format!(
                    "the archive inflates to more than the limit of {} bytes in total",
                    limits.max_total_size
                )
            };
            return Err(archive_error(Some(&name), message));
        }
        total += written;
    }
    Ok(dir)
}

/// The first name the central directory of the zip file lists twice, read directly from
/// the file (the end-of-central-directory record and the file headers; archives too large
/// for the classic format are left to the reader). Only the file's tail, where the record
/// is, and the part from the central directory on are read, not the entries' data.
fn repeated_name(path: &Path) -> Option<String> {
    use std::io::{Seek, SeekFrom};
    let mut file = fs::File::open(path).ok()?;
    let len = usize::try_from(file.metadata().ok()?.len()).ok()?;
    // the file from byte `start` to its end
    let mut read_from = |start: usize| -> Option<Vec<u8>> {
        file.seek(SeekFrom::Start(start as u64)).ok()?;
        let mut buf = Vec::with_capacity(len.saturating_sub(start));
        file.read_to_end(&mut buf).ok()?;
        Some(buf)
    };
    let le = |bytes: &[u8], o: usize, width: usize| -> Option<usize> {
        let b = bytes.get(o..o + width)?;
        Some(b.iter().rev().fold(0, |v, &x| (v << 8) | usize::from(x)))
    };
    let tail_start = len.saturating_sub(22 + 65_535);
    let tail = read_from(tail_start)?;
    let eocd = (0..tail.len().saturating_sub(21))
        .rev()
        .find(|&i| tail[i..i + 4] == [0x50, 0x4b, 0x05, 0x06])?;
    let (count, directory) = (le(&tail, eocd + 10, 2)?, le(&tail, eocd + 16, 4)?);
    // the bytes from the central directory on, and the file offset of their first
    let (bytes, base) = if directory >= tail_start {
        (tail, tail_start)
    } else {
        (read_from(directory)?, directory)
    };
    let mut at = directory - base;
    let mut seen = HashSet::new();
    for _ in 0..count {
        if bytes.get(at..at + 4)? != [0x50, 0x4b, 0x01, 0x02] {
            return None;
        }
        let (n, extra, comment) = (
            le(&bytes, at + 28, 2)?,
            le(&bytes, at + 30, 2)?,
            le(&bytes, at + 32, 2)?,
        );
        let name = String::from_utf8_lossy(bytes.get(at + 46..at + 46 + n)?).into_owned();
        if !seen.insert(name.clone()) {
            return Some(name);
        }
        at += 46 + n + extra + comment;
    }
    None
}

fn copy(from: &mut impl Read, to: &mut impl Write) -> io::Result<u64> {
    let mut buffer = vec![0u8; 64 * 1024];
    let mut total = 0u64;
    loop {
        let n = match from.read(&mut buffer) {
            Ok(0) => return Ok(total),
            Ok(n) => n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        to.write_all(&buffer[..n])?;
        total += n as u64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;
    use zip::write::SimpleFileOptions;

    /// A zip at a fresh path with the given (name, bytes) entries.
    fn make_zip(entries: &[(&str, &[u8])]) -> (UnpackedDir, PathBuf) {
        let dir = UnpackedDir::create("tbi-archive-test").unwrap();
        let path = dir.path().join("test.fmu");
        let mut zip = zip::ZipWriter::new(fs::File::create(&path).unwrap());
        for (name, bytes) in entries {
            zip.start_file(*name, SimpleFileOptions::default()).unwrap();
            zip.write_all(bytes).unwrap();
        }
        zip.finish().unwrap();
        (dir, path)
    }

    fn unpack_err(entries: &[(&str, &[u8])]) -> String {
        let (_dir, path) = make_zip(entries);
        unpack(&path, &UnpackLimits::default())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn unpacks_nested_files() {
        let (_dir, path) = make_zip(&[
            ("modelDescription.xml", b"<x/>"),
            ("resources/data/table.csv", b"1,2\n"),
            ("./documentation/index.html", b"<p/>"),
        ]);
        let out = unpack(&path, &UnpackLimits::default()).unwrap();
        assert_eq!(
            fs::read(out.path().join("resources/data/table.csv")).unwrap(),
            b"1,2\n"
        );
        assert_eq!(
            fs::read(out.path().join("documentation/index.html")).unwrap(),
            b"<p/>"
        );
        let kept = out.path().to_path_buf();
        drop(out);
        assert!(!kept.exists(), "the directory is removed on drop");
    }

    #[test]
    fn refuses_parent_components() {
        let e = unpack_err(&[
            ("modelDescription.xml", b""),
            ("resources/../../evil.so", b"x"),
        ]);
        assert_eq!(
            e,
            "test.fmu: entry \"resources/../../evil.so\": the path contains a '..' component"
        );
    }

    #[test]
    fn refuses_absolute_and_windows_paths() {
        assert!(
            unpack_err(&[("/etc/passwd", b"")]).contains("entry \"/etc/passwd\": absolute path")
        );
        assert!(unpack_err(&[("C:/x", b"")]).contains("drive or device separator"));
        assert!(unpack_err(&[("a\\b", b"")]).contains("backslash"));
    }

    #[test]
    fn refuses_symlinks() {
        let dir = UnpackedDir::create("tbi-archive-test").unwrap();
        let path = dir.path().join("link.fmu");
        let mut zip = zip::ZipWriter::new(fs::File::create(&path).unwrap());
        zip.add_symlink(
            "resources/link",
            "/etc/passwd",
            SimpleFileOptions::default(),
        )
        .unwrap();
        zip.finish().unwrap();
        let e = unpack(&path, &UnpackLimits::default())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "link.fmu: entry \"resources/link\": symbolic links are not allowed in an FMU"
        );
    }

    #[test]
    fn refuses_duplicates() {
        let e = unpack_err(&[("a.txt", b"1"), ("./a.txt", b"2")]);
        assert!(
            e.contains("entry \"./a.txt\": the archive holds this path twice"),
            "{e}"
        );
    }

    #[test]
    fn refuses_a_name_the_zip_reader_would_keep_once() {
        // two entries, then the second renamed to the first's name in the local and
        // central headers (the zip writer itself refuses equal names); also with a central
        // directory that starts more than 64 KiB before the end of the file (1500 more
        // entries), which is read apart from the file's tail
        let names: Vec<String> = (0..1500)
            .map(|i| format!("resources/a-file-with-a-long-name-{i:05}.txt"))
            .collect();
        for extra in [0, names.len()] {
            let mut entries: Vec<(&str, &[u8])> = vec![
                ("modelDescription.xml", b"<a/>"),
                ("modelDescriptioX.xml", b"<b/>"),
            ];
            entries.extend(names[..extra].iter().map(|n| (n.as_str(), &b"x"[..])));
            let (dir, path) = make_zip(&entries);
            let mut bytes = fs::read(&path).unwrap();
            let (from, to) = (b"modelDescriptioX.xml", b"modelDescription.xml");
            let mut i = 0;
            while let Some(p) = bytes[i..].windows(from.len()).position(|w| w == from) {
                bytes[i + p..i + p + from.len()].copy_from_slice(to);
                i += p + from.len();
            }
            let twice = dir.path().join("twice.fmu");
            fs::write(&twice, bytes).unwrap();
            let e = unpack(&twice, &UnpackLimits::default())
                .unwrap_err()
                .to_string();
            assert_eq!(
                e, "twice.fmu: entry \"modelDescription.xml\": the archive holds this path twice",
                "{extra} more entries"
            );
        }
    }

    #[test]
    fn enforces_limits() {
        let (_dir, path) = make_zip(&[("a", b"1"), ("b", b"2"), ("c", b"3")]);
        let few = UnpackLimits {
            max_entries: 2,
            ..UnpackLimits::default()
        };
        let e = unpack(&path, &few).unwrap_err().to_string();
        assert!(
            e.contains("the archive has 3 entries, more than the limit of 2"),
            "{e}"
        );

        let zeros = vec![0u8; 100_000];
        let (_dir, path) = make_zip(&[("big", &zeros)]);
        let small = UnpackLimits {
            max_entry_size: 1000,
            ..UnpackLimits::default()
        };
        let e = unpack(&path, &small).unwrap_err().to_string();
        assert!(
            e.contains("entry \"big\": declared size 100000 bytes exceeds the limit of 1000"),
            "{e}"
        );

        let (_dir, path) = make_zip(&[("a", &zeros), ("b", &zeros)]);
        let total = UnpackLimits {
            max_total_size: 150_000,
            ..UnpackLimits::default()
        };
        let e = unpack(&path, &total).unwrap_err().to_string();
        assert!(
            e.contains(
                "entry \"b\": the archive inflates to more than the limit of 150000 bytes in total"
            ),
            "{e}"
        );
    }

    #[test]
    fn forged_sizes_are_caught_while_inflating() {
        // Patch the declared uncompressed size (local header and central directory) of a
        // 100 kB entry down to 10 bytes: the limit must still hold on the real bytes.
        let zeros = vec![0u8; 100_000];
        let (_dir, path) = make_zip(&[("bomb", &zeros)]);
        let mut bytes = fs::read(&path).unwrap();
        let real = 100_000u32.to_le_bytes();
        let mut patched = 0;
        for i in 0..bytes.len() - 4 {
            if bytes[i..i + 4] == real {
                bytes[i..i + 4].copy_from_slice(&10u32.to_le_bytes());
                patched += 1;
            }
        }
        assert_eq!(patched, 2);
        fs::write(&path, &bytes).unwrap();
        let limits = UnpackLimits {
            max_entry_size: 1000,
            ..UnpackLimits::default()
        };
        let e = unpack(&path, &limits).unwrap_err().to_string();
        assert!(e.starts_with("test.fmu: entry \"bomb\": "), "{e}");
    }

    #[test]
    fn corrupt_archive_is_named() {
        let dir = UnpackedDir::create("tbi-archive-test").unwrap();
        let path = dir.path().join("corrupt.fmu");
        fs::write(&path, b"PK\x03\x04 this is not really a zip file").unwrap();
        let e = unpack(&path, &UnpackLimits::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("corrupt.fmu: not a valid zip archive"), "{e}");
        let e = unpack(&dir.path().join("missing.fmu"), &UnpackLimits::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("missing.fmu: cannot open"), "{e}");
    }
}
