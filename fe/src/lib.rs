//! Suspension-bridge finite-element model.
