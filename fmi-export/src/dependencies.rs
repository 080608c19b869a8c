//! The `dependencies` of `<ModelStructure>`, found by probing a model in-process.
//!
//! For a model in a prepared state (its inputs at a generic operating point, in the phase
//! the dependencies are for: initialisation mode for `<InitialUnknowns>`, step mode at a
//! communication point for `<Outputs>`), each known (input or parameter) `uⱼ` is moved by
//! `δⱼ` from that state and every output `yᵢ` read again:
//!
//! ```text
//! yᵢ depends on uⱼ  ⇔  yᵢ(u + δⱼ eⱼ) ≠ yᵢ(u)   (compared bit for bit)
//! ```
//!
//! The state is restored between probes from a clone of the model taken before the first
//! (`clone_from`, as `fmi2SetFMUstate` restores a saved state). An output that does not
//! depend on a known is computed without it and stays bit-identical; one that does changes
//! unless the operating point is special (an output exactly insensitive there), which the
//! caller avoids by choosing generic values.

use crate::model::{FmuModel, Phase};

/// What `<ModelStructure>` declares of an FMU's outputs: for each output value reference,
/// the value references it depends on at a communication point (`<Outputs>`) and in
/// initialisation mode (`<InitialUnknowns>`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Declared {
    pub outputs: Vec<(u32, Vec<u32>)>,
    pub initial: Vec<(u32, Vec<u32>)>,
}

/// For each of `outputs` (same order), the `knowns` it depends on (in `knowns` order).
/// `delta(vr, value)` is the perturbation of a known at its current value, added, or
/// subtracted where the model refuses the sum (a known at the top of its range). The model is
/// left in the state it was given in.
pub fn probe<M: FmuModel>(
    model: &mut M,
    knowns: &[u32],
    outputs: &[u32],
    phase: Phase,
    delta: impl Fn(u32, f64) -> f64,
) -> Result<Vec<Vec<u32>>, String> {
    let snapshot = model.clone();
    let read = |m: &mut M| -> Result<Vec<u64>, String> {
        outputs
            .iter()
            .map(|&vr| m.get_real(vr).map(f64::to_bits).map_err(String::from))
            .collect()
    };
    let base = read(model)?;
    let mut deps = vec![Vec::new(); outputs.len()];
    for &k in knowns {
        model.clone_from(&snapshot);
        let v = model.get_real(k)?;
        let d = delta(k, v);
        // a known at the top of its range (a train at its highest speed, say) is moved down
        if model.set_real(k, v + d, phase).is_err() {
            model.clone_from(&snapshot);
            model.set_real(k, v - d, phase).map_err(|e| {
                format!("value reference {k} = {v} can be moved neither up nor down by {d}: {e}")
            })?;
        }
        for (d, (now, was)) in deps.iter_mut().zip(read(model)?.iter().zip(&base)) {
            if now != was {
                d.push(k);
            }
        }
    }
    model.clone_from(&snapshot);
    Ok(deps)
}
