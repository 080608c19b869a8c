//! `libwind.so`: the wind FMU's C symbols. The model and its variable layout are the
//! `fmu-wind` library, which the master links too (without these symbols).
fmi_export::export_fmi2!(fmu_wind::WindFmu, "wind");
fmi_export::export_fmi3!(fmu_wind::WindFmu, "wind");
