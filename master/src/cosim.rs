//! Co-simulation of the bridge and train FMUs through the FMI 2.0 C ABI.
use crate::model::Model;
use crate::scenario::Scenario;
use tbi_dynamics::response::Recorder;

pub fn run_cosim<W: std::io::Write>(
    _scenario: &Scenario,
    _model: &Model,
    _rec: &mut Recorder<W>,
    _show_progress: bool,
) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    Err("co-simulation is being wired; use --solver monolithic".into())
}
