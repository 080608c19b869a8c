//! Built-in suspension-bridge presets: the finite-element model of `tbi-fe`, solved for its
//! lowest modes once per process and preset.

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};
use tbi_dynamics::bridge::ModeSet;
use tbi_fe::{FeModel, SuspensionBridgeParams};

/// Known preset names.
pub const PRESETS: &[&str] = &["tsing-ma"];

/// Parameters of a preset.
pub fn preset_params(name: &str) -> Result<SuspensionBridgeParams, String> {
    match name {
        "tsing-ma" => Ok(SuspensionBridgeParams::tsing_ma()),
        other => Err(format!(
            "unknown suspension preset \"{other}\"; available: {PRESETS:?}"
        )),
    }
}

type Cache = Mutex<HashMap<(String, usize), ModeSet>>;

/// The lowest `modes` modes of a preset (cached for the life of the process).
pub fn preset_modes(name: &str, modes: usize) -> Result<ModeSet, String> {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    let key = (name.to_string(), modes);
    // Held during the computation so that parallel runs (tbi sweep) compute it once.
    let mut guard = cache.lock().expect("cache lock");
    if let Some(set) = guard.get(&key) {
        return Ok(set.clone());
    }
    let params = preset_params(name)?;
    let fe = FeModel::build(&params).map_err(|e| format!("building the {name} model: {e}"))?;
    // The lowest `modes` modes of the whole structure, as the paper's "first 20 modes up to
    // 0.38 Hz"; cable- and tower-only modes (labels `C-k`) have no deck motion and simply
    // stay uncoupled.
    let result = fe.modes(modes).map_err(|e| format!("modal analysis of the {name} model: {e}"))?;
    let set = result.to_mode_set();
    guard.insert(key, set.clone());
    Ok(set)
}
