//! A loaded FMU shared object with its 34 functions resolved: the one loader used by
//! [`Fmu::load`](crate::Fmu::load) and the misuse harness.

use fmi2::Functions;
use std::path::{Path, PathBuf};

/// Why a shared object could not be used.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LoadError {
    /// `dlopen` failed; the loader's own message.
    Open(String),
    /// The library does not export these FMI 2.0 functions.
    MissingSymbols(Vec<&'static str>),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Open(message) => f.write_str(message),
            LoadError::MissingSymbols(names) => write!(f, "does not export {}", names.join(", ")),
        }
    }
}

/// An FMU binary, loaded with `RTLD_NOW | RTLD_LOCAL` (unresolved dependencies fail at
/// load, not in the middle of a simulation), and the table of its functions.
///
/// Dereferences to [`Functions`], so a call reads `(library.do_step)(c, t, h, flag)`.
/// The pointers are only reachable through `&self`: they cannot outlive the library.
pub struct Library {
    path: PathBuf,
    functions: Functions,
    // Last field: unloaded after the table is gone.
    _library: libloading::Library,
}

impl std::fmt::Debug for Library {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Library")
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

impl Library {
    /// Load `path` and resolve all 34 functions, naming every missing one.
    ///
    /// Loading runs the library's initialisers and the resolved pointers are trusted to
    /// have the fmi2 signatures: the library must be an FMU binary, as for any importer.
    pub fn load(path: &Path) -> Result<Library, LoadError> {
        Self::load_for(path, false)
    }

    /// [`Library::load`] for an FMU whose description says `needsExecutionTool`: see
    /// [`open_fmu_library`].
    pub fn load_for(path: &Path, needs_execution_tool: bool) -> Result<Library, LoadError> {
        let library = open_fmu_library(path, needs_execution_tool).map_err(LoadError::Open)?;
        // SAFETY: an FMU binary; FMI 2.0 fixes the exported signatures.
        let functions = unsafe { Functions::load(&library) }.map_err(LoadError::MissingSymbols)?;
        Ok(Library {
            path: path.to_owned(),
            functions,
            _library: library,
        })
    }

    /// The path the library was loaded from.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl std::ops::Deref for Library {
    type Target = Functions;

    fn deref(&self) -> &Functions {
        &self.functions
    }
}

/// Check an ELF shared object before `dlopen` sees it: a truncated or foreign file can
/// crash the loader (SIGBUS on a mapping past the end of the file) instead of failing.
/// Verified: the ELF magic, 64-bit little-endian, a shared object (`ET_DYN`) for this
/// machine's architecture, and that the program headers and every loadable segment lie
/// inside the file. Other platforms' binaries are left to the loader.
pub fn check_binary(path: &Path) -> Result<(), String> {
    if !cfg!(all(
        target_os = "linux",
        target_endian = "little",
        target_pointer_width = "64"
    )) {
        return Ok(());
    }
    use std::io::{Read, Seek, SeekFrom};
    let cannot = |e: std::io::Error| format!("cannot read {}: {e}", path.display());
    // the header and the program headers are read, not the whole file
    let mut file = std::fs::File::open(path).map_err(cannot)?;
    let len = file.metadata().map_err(cannot)?.len();
    let mut bytes = Vec::with_capacity(64);
    (&mut file)
        .take(64)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    let what = |why: String| format!("{} is not a loadable shared object: {why}", path.display());
    if bytes.len() < 64 || &bytes[..4] != b"\x7fELF" {
        let head: Vec<String> = bytes.iter().take(4).map(|b| format!("{b:02x}")).collect();
        return Err(what(format!(
            "no ELF header (the file is {len} bytes and starts with {})",
            if head.is_empty() {
                "nothing".to_owned()
            } else {
                head.join(" ")
            }
        )));
    }
    let u16_at = |o: usize| u16::from_le_bytes([bytes[o], bytes[o + 1]]);
    let u64_of = |b: &[u8], o: usize| -> u64 {
        b.get(o..o + 8).map_or(u64::MAX, |b| {
            u64::from_le_bytes(b.try_into().expect("8 bytes"))
        })
    };
    let u64_at = |o: usize| u64_of(&bytes, o);
    if bytes[4] != 2 || bytes[5] != 1 {
        return Err(what("not a 64-bit little-endian ELF file".into()));
    }
    if u16_at(16) != 3 {
        return Err(what(format!(
            "ELF type {} is not a shared object (ET_DYN = 3)",
            u16_at(16)
        )));
    }
    let machine = u16_at(18);
    let expected = if cfg!(target_arch = "x86_64") {
        Some(62)
    } else if cfg!(target_arch = "aarch64") {
        Some(183)
    } else {
        None
    };
    if let Some(m) = expected {
        if machine != m {
            return Err(what(format!(
                "built for ELF machine {machine}, this is machine {m} ({})",
                std::env::consts::ARCH
            )));
        }
    }
    let (phoff, phentsize, phnum) = (u64_at(32), u16_at(54) as u64, u16_at(56) as u64);
    if phentsize < 56 || phoff.saturating_add(phentsize.saturating_mul(phnum)) > len {
        return Err(what(format!(
            "truncated: its program headers end past the file's {len} bytes"
        )));
    }
    // inside the file (just checked): at most 65 535 entries of at most 65 535 bytes
    let mut ph = vec![0; (phentsize * phnum) as usize];
    file.seek(SeekFrom::Start(phoff)).map_err(cannot)?;
    file.read_exact(&mut ph).map_err(cannot)?;
    for i in 0..phnum {
        let h = (i * phentsize) as usize;
        let kind = u32::from_le_bytes(ph[h..h + 4].try_into().expect("4 bytes"));
        let (offset, filesz) = (u64_of(&ph, h + 8), u64_of(&ph, h + 32));
        if kind == 1 && offset.saturating_add(filesz) > len {
            return Err(what(format!(
                "truncated: loadable segment {i} ends at byte {}, the file has {len}",
                offset.saturating_add(filesz)
            )));
        }
    }
    let (shoff, shentsize, shnum) = (u64_at(40), u16_at(58) as u64, u16_at(60) as u64);
    if shoff.saturating_add(shentsize.saturating_mul(shnum)) > len {
        return Err(what(format!(
            "truncated: its section headers end past the file's {len} bytes"
        )));
    }
    Ok(())
}

/// Check and open an FMU's shared library. When it cannot be opened and the FMU needs an
/// execution tool, the tool may be Python: the libraries of pythonfmu and pythonfmu3 FMUs
/// leave the Python C API to the process that loads them (FMPy, being Python, has it).
/// Then the Python library is loaded into this process with its symbols global
/// ([`load_python`]) and the FMU's library opened again.
pub fn open_fmu_library(
    path: &Path,
    needs_execution_tool: bool,
) -> Result<libloading::Library, String> {
    check_binary(path)?;
    match open(path) {
        Ok(library) => Ok(library),
        Err(first) if needs_execution_tool => {
            let first = describe(&first);
            load_python().map_err(|why| {
                format!(
                    "{first} (the FMU needs an execution tool; Python could not be loaded: {why})"
                )
            })?;
            open(path).map_err(|e| describe(&e))
        }
        Err(e) => Err(describe(&e)),
    }
}

/// A loading error with its cause (`dlerror`'s text).
fn describe(e: &libloading::Error) -> String {
    match std::error::Error::source(e) {
        Some(cause) => format!("{e}: {cause}"),
        None => e.to_string(),
    }
}

/// Loads the shared Python library into this process, its symbols global, once: that of
/// the interpreter `$TBI_PYTHON`, else `python3` on the PATH (asked for its `LIBDIR` and
/// `INSTSONAME`).
pub fn load_python() -> Result<(), String> {
    static LOADED: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    LOADED
        .get_or_init(|| {
            let python = std::env::var("TBI_PYTHON").unwrap_or_else(|_| "python3".into());
            let out = std::process::Command::new(&python)
                .args([
                    "-c",
                    "import os, sysconfig as s; print(os.path.join(s.get_config_var('LIBDIR'), s.get_config_var('INSTSONAME')))",
                ])
                .output()
                .map_err(|e| format!("cannot run {python}: {e}"))?;
            let lib = String::from_utf8_lossy(&out.stdout).trim().to_owned();
            if !out.status.success() || lib.is_empty() {
                return Err(format!("{python} did not name its shared library"));
            }
            #[cfg(unix)]
            {
                use libloading::os::unix::{Library, RTLD_GLOBAL, RTLD_NOW};
                // SAFETY: the Python library's initialisers; it stays loaded for the process.
                let library = unsafe { Library::open(Some(&lib), RTLD_NOW | RTLD_GLOBAL) }
                    .map_err(|e| format!("{lib}: {}", describe(&e)))?;
                std::mem::forget(library);
                Ok(())
            }
            #[cfg(not(unix))]
            Err(format!("{lib}: Python is loaded for FMUs on Unix only"))
        })
        .clone()
}

fn open(path: &Path) -> Result<libloading::Library, libloading::Error> {
    #[cfg(unix)]
    {
        use libloading::os::unix::{Library, RTLD_LOCAL, RTLD_NOW};
        // SAFETY: loading runs the library's initialisers; an FMU is trusted code.
        unsafe { Library::open(Some(path), RTLD_NOW | RTLD_LOCAL) }.map(Into::into)
    }
    #[cfg(not(unix))]
    {
        // SAFETY: as above.
        unsafe { libloading::Library::new(path) }
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    #[test]
    fn truncated_and_foreign_files_are_refused_before_dlopen() {
        let exe = std::env::current_exe().unwrap();
        let dir = std::env::temp_dir().join(format!("tbi-elf-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // a real shared object of this machine: the C library
        let libc = [
            "/lib/x86_64-linux-gnu/libc.so.6",
            "/lib64/libc.so.6",
            "/usr/lib/libc.so.6",
        ]
        .into_iter()
        .map(Path::new)
        .find(|p| p.is_file());
        if let Some(libc) = libc {
            check_binary(libc).unwrap();
            let bytes = std::fs::read(libc).unwrap();
            let cut = dir.join("cut.so");
            std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
            let e = check_binary(&cut).unwrap_err();
            assert!(e.contains("truncated"), "{e}");
            assert!(
                matches!(Library::load(&cut), Err(LoadError::Open(m)) if m.contains("truncated"))
            );
        }
        let text = dir.join("text.so");
        std::fs::write(&text, b"hello, world").unwrap();
        assert!(check_binary(&text).unwrap_err().contains("no ELF header"));
        // an executable is not a shared object (unless built as PIE, which is ET_DYN too)
        let _ = check_binary(&exe);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
