//! Compiles the variadic logger shim of the `logger` feature.
//!
//! Stable Rust cannot define a C-variadic function, but an FMU calls the importer's
//! logger as `logger(env, instanceName, status, category, format, ...)`. The shim in
//! `csrc/logger_shim.c` formats the message with `vsnprintf` and forwards it to a
//! non-variadic Rust callback. Without the feature nothing is compiled.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=csrc/logger_shim.c");
    #[cfg(feature = "logger")]
    {
        cc::Build::new()
            .file("csrc/logger_shim.c")
            .warnings(true)
            .extra_warnings(true)
            .compile("fmi2_logger_shim");
    }
}
