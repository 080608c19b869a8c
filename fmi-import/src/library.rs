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
        let library = open(path).map_err(|e| LoadError::Open(e.to_string()))?;
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
