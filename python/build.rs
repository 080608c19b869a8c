//! Builds the FMU libraries the wheel ships (`libbridge.so`, `libtrain.so`, `libwind.so`, the
//! cdylibs of `fmu-bridge-so`, `fmu-train-so`, `fmu-wind-so`) and leaves them in
//! `$OUT_DIR`, from where maturin packs them as `tbi/_lib/` (pyproject.toml,
//! `include = [{ from = "out-dir", … }]`). The installed package finds them beside itself.
//!
//! The libraries are built by a cargo of their own, in a target folder of their own
//! (`target/wheel-fmu-libs` of the workspace): the cargo building this crate holds the lock
//! of its target folder, and a second cargo on it would wait for ever.

use std::path::{Path, PathBuf};
use std::process::Command;

const PACKAGES: [(&str, &str); 3] = [
    ("fmu-bridge-so", "libbridge.so"),
    ("fmu-train-so", "libtrain.so"),
    ("fmu-wind-so", "libwind.so"),
];

/// The workspace crates the libraries are built from: a change in one builds them again.
const SOURCES: [&str; 11] = [
    "fmu-bridge",
    "fmu-train",
    "fmu-wind",
    "dynamics",
    "fmi-export",
    "fmi2",
    "track",
    "wind",
    "modes",
    "modelDescription",
    "Cargo.lock",
];

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let workspace = manifest
        .parent()
        .expect("python/ is in the workspace")
        .to_path_buf();
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("set by cargo"));
    let target = workspace.join("target").join("wheel-fmu-libs");
    for s in SOURCES {
        println!("cargo:rerun-if-changed={}", workspace.join(s).display());
    }
    println!("cargo:rerun-if-changed=build.rs");
    println!(
        "cargo:warning=building the FMU libraries (libbridge.so, libtrain.so, libwind.so) into {}",
        target.display()
    );
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.arg("build")
        .arg("--release")
        .arg("--manifest-path")
        .arg(workspace.join("Cargo.toml"))
        .arg("--target-dir")
        .arg(&target);
    for (package, _) in PACKAGES {
        cmd.args(["-p", package]);
    }
    // the libraries as `cargo build --release` of the workspace builds them: none of the
    // extension module's flags or target settings
    for var in [
        "CARGO_TARGET_DIR",
        "CARGO_BUILD_TARGET_DIR",
        "CARGO_BUILD_BUILD_DIR",
        "CARGO_ENCODED_RUSTFLAGS",
        "RUSTFLAGS",
        "CARGO_BUILD_TARGET",
        "PYO3_CONFIG_FILE",
    ] {
        cmd.env_remove(var);
    }
    let status = cmd.status().expect("cargo runs");
    assert!(status.success(), "cargo build of the FMU libraries failed");
    std::fs::create_dir_all(&out).expect("OUT_DIR");
    for (_, lib) in PACKAGES {
        copy(&target.join("release").join(lib), &out.join(lib));
    }
}

fn copy(from: &Path, to: &Path) {
    std::fs::copy(from, to)
        .unwrap_or_else(|e| panic!("{} → {}: {e}", from.display(), to.display()));
}
