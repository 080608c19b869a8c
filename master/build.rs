//! Builds the C shim that gives FMUs a variadic `fmi2CallbackLogger` (see
//! `src/fmi/logger_shim.c` and the `fmi::logger` module).
fn main() {
    println!("cargo:rerun-if-changed=src/fmi/logger_shim.c");
    cc::Build::new()
        .file("src/fmi/logger_shim.c")
        .warnings(true)
        .extra_warnings(true)
        .compile("tbi_fmi2_logger_shim");
}
