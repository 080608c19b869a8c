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
/// cdylib before its integration tests, into `deps/` (where the test executable lives) and
/// the directory above it.
pub fn library() -> PathBuf {
    tbi_tests::cdylib("testmodel")
}
