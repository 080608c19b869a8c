//! The train model as an FMI 2.0 Co-Simulation FMU.
