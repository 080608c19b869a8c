//! `libbridge.so`: the bridge FMU's C symbols. The model and its variable layout are the
//! `fmu-bridge` library, which the master links too (without these symbols).
fmi_export::export_fmi2!(fmu_bridge::BridgeFmu, "bridge");
fmi_export::export_fmi3!(fmu_bridge::BridgeFmu, "bridge");
