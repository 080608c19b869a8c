//! Helpers of the cross-crate tests that only they use: ELF dependencies, the independent
//! references, the scenarios. The shared support (binaries, scratch folders, processes,
//! tables, FMPy, export and unpacking) is the library of this package, `tbi_tests`; a few of
//! its names are re-exported here for golden.rs, which reaches them through `common`.
//!
//! The tests build nothing themselves. They use the `tbi` executable and the FMU shared
//! objects `libbridge.so` / `libtrain.so` that `cargo build --release --workspace` puts next
//! to the test executable's `deps/` folder (`./tests/run.sh` does that build first).

#![allow(dead_code)] // each test binary uses a different subset

pub mod elf;
pub mod reference;
pub mod scenarios;

// the shared helpers golden.rs reaches through `common`
#[allow(unused_imports)]
pub use tbi_tests::{repo_root, run_ok, scratch};

use std::path::PathBuf;
use tbi_tests::release_dir;

/// The release `tbi` executable, after checking that `libbridge.so` and `libtrain.so` (the
/// FMUs it exports) are next to it.
pub fn tbi() -> PathBuf {
    release_dir().join("tbi")
}
