//! One FMU instance: the object behind `fmi2Component`, and the body of every FMI
//! function once the C arguments have been checked and converted (see [`crate::api`]).
//!
//! Methods return `Ok(status)` for fmi2OK/fmi2Warning/fmi2Discard (having logged a
//! reason for anything but OK) and `Err(reason)` for fmi2Error; the caller logs the
//! reason and moves the instance to [`State::Error`].

// The fmi2StatusKind constants keep the standard's spelling, also in patterns.
#![allow(non_upper_case_globals)]

use std::ffi::CString;
use std::path::PathBuf;

use crate::logging::{self, Logger, LOG_EVENTS};
use crate::model::{FmuModel, Phase, StepOutcome};
use crate::snapshot::{self, Frame, Identity, Snapshot};
use crate::state::State;
use crate::types::{
    fmi2DoStepStatus, fmi2LastSuccessfulTime, fmi2PendingStatus, fmi2StatusKind, fmi2Terminated,
    Status,
};

pub(crate) const INSTANCE_MAGIC: u64 = 0x4543_4e41_5453_4e49; // "INSTANCE"

/// Relative tolerance for matching `currentCommunicationPoint` with the internal time and
/// for the stop time: `1e-12 · max(1, |t|)`.
pub const TIME_TOLERANCE: f64 = 1e-12;

fn time_tolerance(t: f64) -> f64 {
    TIME_TOLERANCE * t.abs().max(1.0)
}

/// A tag that differs between model types (guards snapshot and component pointers): the
/// type's `TypeId` folded to 64 bits, a constant the compiler works out (every call of the
/// C API checks it).
pub(crate) fn type_tag<M: 'static>() -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = crate::guid::Fnv1a64::default();
    std::any::TypeId::of::<M>().hash(&mut h);
    h.finish()
}

/// The object an `fmi2Component` points to.
///
/// `#[repr(C)]` so that `magic` and `type_tag` are the first two words: a component
/// pointer is checked against them before it is used (best effort, see
/// [`crate::api`]).
#[repr(C)]
pub struct Instance<M> {
    pub(crate) magic: u64,
    pub(crate) type_tag: u64,
    model_identifier: &'static str,
    name: String,
    guid: String,
    resources: PathBuf,
    pub(crate) logger: Logger,
    pub(crate) frame: Frame,
    model: M,
    /// Strings returned by the last `fmi2GetString`, kept alive until the next call.
    string_buffer: Vec<CString>,
    /// `"fmi2"` or `"fmi3"`: the prefix of the function names in messages.
    pub(crate) prefix: &'static str,
}

impl<M: FmuModel> Instance<M> {
    pub(crate) fn new(
        model_identifier: &'static str,
        name: String,
        guid: String,
        resources: PathBuf,
        logger: Logger,
        model: M,
    ) -> Self {
        Instance {
            magic: INSTANCE_MAGIC,
            type_tag: type_tag::<M>(),
            model_identifier,
            name,
            guid,
            resources,
            logger,
            frame: Frame::instantiated(),
            model,
            string_buffer: Vec::new(),
            prefix: "fmi2",
        }
    }

    /// The instance name given to `fmi2Instantiate`.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The decoded resources folder.
    pub fn resources(&self) -> &std::path::Path {
        &self.resources
    }

    /// Current machine state.
    pub fn state(&self) -> State {
        self.frame.state
    }

    /// Internal time (end of the last successful step).
    pub fn time(&self) -> f64 {
        self.frame.time
    }

    /// Read access to the model.
    pub fn model(&self) -> &M {
        &self.model
    }

    fn event(&self, message: &str) {
        self.logger.log(Status::Ok, LOG_EVENTS, message);
    }

    /// [`Instance::event`] with the message formatted only when it will be delivered (the
    /// state is saved and restored at every iteration of an implicit master).
    fn event_with(&self, message: impl FnOnce() -> String) {
        if self.logger.filter.delivers(Status::Ok, LOG_EVENTS) {
            self.event(&message());
        }
    }

    fn identity(&self) -> Identity {
        Identity::new(self.model_identifier, &self.guid)
    }

    fn phase(&self) -> Result<Phase, String> {
        match self.frame.state {
            State::Instantiated => Ok(Phase::Instantiated),
            State::InitializationMode => Ok(Phase::Initialization),
            State::StepComplete => Ok(Phase::Stepping),
            s => Err(format!("variables cannot be set in state {s}")),
        }
    }

    pub(crate) fn set_debug_logging(&mut self, logging_on: bool, categories: &[&str]) -> Status {
        let mut known: Vec<&str> = logging::LOG_CATEGORIES.iter().map(|(n, _)| *n).collect();
        known.extend(M::LOG_CATEGORIES.iter().map(|(n, _)| *n));
        let unknown = self
            .logger
            .filter
            .set(logging_on, categories.iter().copied(), &known);
        if unknown.is_empty() {
            Status::Ok
        } else {
            self.logger.log_status(
                Status::Warning,
                &format!(
                    "{}SetDebugLogging: unknown log categories {unknown:?} (applied anyway); known categories: {}",
                    self.prefix,
                    known.join(", ")
                ),
            );
            Status::Warning
        }
    }

    pub(crate) fn setup_experiment(
        &mut self,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<Status, String> {
        if !start_time.is_finite() {
            return Err(format!("startTime {start_time} is not finite"));
        }
        if let Some(stop) = stop_time {
            if !stop.is_finite() || stop < start_time {
                return Err(format!(
                    "stopTime {stop} must be finite and not before startTime {start_time}"
                ));
            }
        }
        self.model.setup_experiment(start_time, stop_time)?;
        self.frame.time = start_time;
        self.frame.start_time = start_time;
        self.frame.stop_time = stop_time;
        Ok(Status::Ok)
    }

    pub(crate) fn enter_initialization_mode(&mut self) -> Result<Status, String> {
        self.model.enter_initialization()?;
        self.frame.state = State::InitializationMode;
        self.event("entered initialization mode");
        Ok(Status::Ok)
    }

    pub(crate) fn exit_initialization_mode(&mut self) -> Result<Status, String> {
        self.model.exit_initialization()?;
        self.frame.state = State::StepComplete;
        self.event(&format!(
            "initialized at t = {}; step mode",
            self.frame.time
        ));
        Ok(Status::Ok)
    }

    pub(crate) fn terminate(&mut self) -> Result<Status, String> {
        self.frame.state = State::Terminated;
        self.event(&format!("terminated at t = {}", self.frame.time));
        Ok(Status::Ok)
    }

    pub(crate) fn reset(&mut self) -> Result<Status, String> {
        self.model.reset()?;
        self.frame = Frame::instantiated();
        self.string_buffer.clear();
        self.event("reset to the instantiated state");
        Ok(Status::Ok)
    }

    pub(crate) fn get_real(&mut self, vr: &[u32], values: &mut [f64]) -> Result<Status, String> {
        self.model.get_reals(vr, values)?;
        if let Some(i) = fmi2::first_non_finite(&values[..vr.len().min(values.len())]) {
            return Err(format!(
                "Real value reference {} has the non-finite value {}",
                vr[i], values[i]
            ));
        }
        Ok(Status::Ok)
    }

    pub(crate) fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<Status, String> {
        if let Some((r, v)) = knowns.iter().zip(seed).find(|(_, v)| !v.is_finite()) {
            return Err(format!(
                "the seed of Real value reference {r} is the non-finite value {v}"
            ));
        }
        self.model
            .directional_derivative(unknowns, knowns, seed, out)?;
        if let Some((r, v)) = unknowns
            .iter()
            .zip(out.iter())
            .find(|(_, v)| !v.is_finite())
        {
            return Err(format!(
                "the derivative of Real value reference {r} is the non-finite value {v}"
            ));
        }
        Ok(Status::Ok)
    }

    pub(crate) fn set_real(&mut self, vr: &[u32], values: &[f64]) -> Result<Status, String> {
        if let Some(i) = fmi2::first_non_finite(&values[..vr.len().min(values.len())]) {
            return Err(format!(
                "Real value reference {} cannot be set to the non-finite value {}",
                vr[i], values[i]
            ));
        }
        let phase = self.phase()?;
        self.model.set_reals(vr, values, phase)?;
        Ok(Status::Ok)
    }

    pub(crate) fn get_integer(&mut self, vr: &[u32], values: &mut [i32]) -> Result<Status, String> {
        for (r, out) in vr.iter().zip(values.iter_mut()) {
            *out = self.model.get_integer(*r)?;
        }
        Ok(Status::Ok)
    }

    pub(crate) fn set_integer(&mut self, vr: &[u32], values: &[i32]) -> Result<Status, String> {
        let phase = self.phase()?;
        for (r, v) in vr.iter().zip(values) {
            self.model.set_integer(*r, *v, phase)?;
        }
        Ok(Status::Ok)
    }

    pub(crate) fn get_boolean(&mut self, vr: &[u32], values: &mut [i32]) -> Result<Status, String> {
        for (r, out) in vr.iter().zip(values.iter_mut()) {
            *out = i32::from(self.model.get_boolean(*r)?);
        }
        Ok(Status::Ok)
    }

    pub(crate) fn set_boolean(&mut self, vr: &[u32], values: &[bool]) -> Result<Status, String> {
        let phase = self.phase()?;
        for (r, v) in vr.iter().zip(values) {
            self.model.set_boolean(*r, *v, phase)?;
        }
        Ok(Status::Ok)
    }

    /// Fetch strings into the instance's buffer; the returned C strings stay valid until
    /// the next `fmi2GetString` or `fmi2FreeInstance`.
    pub(crate) fn get_string(&mut self, vr: &[u32]) -> Result<&[CString], String> {
        let mut fetched = Vec::with_capacity(vr.len());
        for r in vr {
            let s = self.model.get_string(*r)?;
            fetched.push(
                CString::new(s)
                    .map_err(|_| format!("String value reference {r} contains a NUL byte"))?,
            );
        }
        self.string_buffer = fetched;
        Ok(&self.string_buffer)
    }

    pub(crate) fn set_string(&mut self, vr: &[u32], values: &[&str]) -> Result<Status, String> {
        let phase = self.phase()?;
        for (r, v) in vr.iter().zip(values) {
            self.model.set_string(*r, v, phase)?;
        }
        Ok(Status::Ok)
    }

    pub(crate) fn do_step(&mut self, t: f64, h: f64) -> Result<Status, String> {
        if !t.is_finite() {
            return Err(format!("currentCommunicationPoint {t} is not finite"));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(format!(
                "communicationStepSize {h} must be finite and positive"
            ));
        }
        let now = self.frame.time;
        if (t - now).abs() > time_tolerance(now) {
            return Err(format!(
                "currentCommunicationPoint {t} differs from the FMU's time {now}"
            ));
        }
        if let Some(stop) = self.frame.stop_time {
            if t + h > stop + time_tolerance(stop) {
                return Err(format!(
                    "the step from {t} by {h} to {} passes the stop time {stop}",
                    t + h
                ));
            }
        }
        match self.model.do_step(t, h) {
            Ok(StepOutcome::Ok) => {
                self.frame.time = t + h;
                Ok(Status::Ok)
            }
            Ok(StepOutcome::Discard(reason)) => {
                self.frame.state = State::StepFailed;
                self.frame.terminate_requested = true;
                self.logger.log_status(
                    Status::Discard,
                    &format!(
                        "{}DoStep: step from t = {t} by h = {h} discarded: {reason}",
                        self.prefix
                    ),
                );
                Ok(Status::Discard)
            }
            Err(reason) => Err(format!("step from t = {t} by h = {h} failed: {reason}")),
        }
    }

    fn discard(&self, function: &str, message: &str) -> Status {
        self.logger
            .log_status(Status::Discard, &format!("{function}: {message}"));
        Status::Discard
    }

    pub(crate) fn get_status(&self, kind: fmi2StatusKind) -> Status {
        match kind {
            fmi2DoStepStatus | fmi2PendingStatus => self.discard(
                "fmi2GetStatus",
                "no asynchronous step exists (canRunAsynchronuously=false)",
            ),
            k => self.discard(
                "fmi2GetStatus",
                &format!("status kind {k} is not defined for fmi2Status values"),
            ),
        }
    }

    pub(crate) fn get_real_status(&self, kind: fmi2StatusKind) -> Result<f64, Status> {
        match kind {
            fmi2LastSuccessfulTime => Ok(self.frame.time),
            k => Err(self.discard(
                "fmi2GetRealStatus",
                &format!("status kind {k} has no Real value (only fmi2LastSuccessfulTime)"),
            )),
        }
    }

    pub(crate) fn get_integer_status(&self, kind: fmi2StatusKind) -> Status {
        self.discard(
            "fmi2GetIntegerStatus",
            &format!("status kind {kind} has no Integer value"),
        )
    }

    pub(crate) fn get_boolean_status(&self, kind: fmi2StatusKind) -> Result<bool, Status> {
        match kind {
            fmi2Terminated => Ok(self.frame.terminate_requested),
            k => Err(self.discard(
                "fmi2GetBooleanStatus",
                &format!("status kind {k} has no Boolean value (only fmi2Terminated)"),
            )),
        }
    }

    pub(crate) fn get_string_status(&self, kind: fmi2StatusKind) -> Status {
        match kind {
            fmi2PendingStatus => self.discard(
                "fmi2GetStringStatus",
                "no asynchronous step is pending (canRunAsynchronuously=false)",
            ),
            k => self.discard(
                "fmi2GetStringStatus",
                &format!("status kind {k} has no String value"),
            ),
        }
    }

    /// A new snapshot of the complete dynamic state.
    pub(crate) fn snapshot(&self) -> Snapshot<M> {
        Snapshot::new(self.type_tag, self.frame, self.model.clone())
    }

    /// Overwrite `snap` with the current state (reuses the model's allocations).
    pub(crate) fn snapshot_into(&self, snap: &mut Snapshot<M>) {
        snap.frame = self.frame;
        snap.model.clone_from(&self.model);
        self.event_with(|| format!("FMU state saved at t = {}", self.frame.time));
    }

    pub(crate) fn restore(&mut self, snap: &Snapshot<M>) {
        self.frame = snap.frame;
        self.model.clone_from(&snap.model);
        self.event_with(|| {
            format!(
                "FMU state restored: t = {}, state {}",
                self.frame.time, self.frame.state
            )
        });
    }

    pub(crate) fn serialize(&self, snap: &Snapshot<M>) -> Vec<u8> {
        snapshot::encode(self.identity(), &snap.frame, &snap.model.serialize_state())
    }

    /// Rebuild a snapshot from serialized bytes (the model part is a clone of this
    /// instance's model with the payload restored into it).
    pub(crate) fn deserialize(&self, bytes: &[u8]) -> Result<(Frame, M), String> {
        let (frame, payload) = snapshot::decode(bytes, self.identity())?;
        let mut model = self.model.clone();
        model.deserialize_state(payload)?;
        Ok((frame, model))
    }
}

#[cfg(test)]
mod tests {
    use super::type_tag;

    /// Component and state pointers of one model type are told from another's by the tag: it
    /// differs between types and is the same on every call.
    #[test]
    fn the_type_tag_differs_between_types_and_is_stable() {
        struct A;
        struct B;
        assert_ne!(type_tag::<A>(), type_tag::<B>());
        assert_ne!(type_tag::<A>(), type_tag::<u64>());
        assert_eq!(type_tag::<A>(), type_tag::<A>());
        assert_ne!(type_tag::<A>(), 0);
    }
}
