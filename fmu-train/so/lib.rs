//! `libtrain.so`: the train FMU's C symbols. The model and its variable layout are the
//! `fmu-train` library, which the master links too (without these symbols).
fmi_export::export_fmi2!(fmu_train::TrainFmu, "train");
fmi_export::export_fmi3!(fmu_train::TrainFmu, "train");
