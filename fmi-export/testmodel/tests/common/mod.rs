//! Locating the testmodel shared object and its resources from an integration test.

#![allow(dead_code)] // each test binary uses a different subset

use std::path::{Path, PathBuf};

/// The `resources` folder of the test model (in the source tree).
pub fn resources() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("resources")
}

/// The GUID of the shipped resources.
pub fn guid() -> String {
    let bytes = std::fs::read(resources().join(testmodel::CONFIG_FILE)).expect("config.txt");
    testmodel::guid_for(&bytes)
}

/// `libtestmodel.so` as built by cargo for this test run: cargo builds the package's
/// cdylib before its integration tests, into the directory above `deps/` (where the test
/// executable lives) and into `deps/` itself.
pub fn library() -> PathBuf {
    let name = format!(
        "{}testmodel{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    let exe = std::env::current_exe().expect("test executable path");
    let mut candidates = Vec::new();
    for dir in exe.ancestors().skip(1).take(2) {
        candidates.push(dir.join(&name));
    }
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .unwrap_or_else(|| panic!("{name} not found; looked at {candidates:?}"))
}
